//! The one table of the workstation's actions: every menu entry that issues a [`Command`] and
//! every keyboard shortcut, each with its label, menu place, keys and the rule that enables it.
//! The menu bar ([`super::panels::menu_bar`]) draws its entries from [`actions`] and
//! [`shortcuts`] turns key presses into the same commands, so a menu entry and its key cannot
//! disagree. (The menus' check boxes and radio buttons, which show state rather than issue one
//! command, are laid out by the menu bar itself; a feature's check boxes are [`Toggle`]s.)
//!
//! Adding an entry or a key is one [`Action`] in [`actions`].

use egui::{Key, KeyboardShortcut, Modifiers};

use super::command::{Command, PlaybackCommand};
use crate::project::OperationKind;
use crate::render::StandardView;

/// Ctrl+O: open a part or a project.
pub const OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
/// Ctrl+N: new project.
pub const NEW: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::N);
/// Ctrl+S: save the project.
pub const SAVE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
/// Ctrl+Shift+S: save the project under another name.
pub const SAVE_AS: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::S);
/// Ctrl+Z: undo.
pub const UNDO: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Z);
/// Ctrl+Shift+Z: redo.
pub const REDO: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::Z);
/// Ctrl+Y: redo.
pub const REDO_ALT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Y);
/// Ctrl+Q: quit.
pub const QUIT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Q);

/// The standard views and their keys.
pub const VIEW_KEYS: [(StandardView, Key); 7] = [
    (StandardView::Top, Key::Num1),
    (StandardView::Front, Key::Num2),
    (StandardView::Right, Key::Num3),
    (StandardView::Back, Key::Num4),
    (StandardView::Left, Key::Num5),
    (StandardView::Bottom, Key::Num6),
    (StandardView::Iso, Key::Num0),
];

/// A key without modifiers.
const fn plain(key: Key) -> KeyboardShortcut {
    KeyboardShortcut::new(Modifiers::NONE, key)
}

/// The menus of the menu bar.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Menu {
    /// New, open, save, quit.
    File,
    /// Undo, redo.
    Edit,
    /// Fit, standard views (and the view toggles the menu bar draws itself).
    View,
    /// Operations, calculate, simulate, post and the tool windows.
    Machining,
}

/// A check box a feature adds at the end of View → Tool Paths: it shows `on` and, when
/// clicked, issues `set` with the new value.
#[derive(Clone, Copy, Debug)]
pub struct Toggle {
    /// The label.
    pub label: &'static str,
    /// Checked.
    pub on: bool,
    /// Can be clicked (greyed out otherwise).
    pub enabled: bool,
    /// The command that sets it.
    pub set: fn(bool) -> Command,
}

/// When an action can be taken: the menu greys it out otherwise (its key still asks, and the
/// workstation answers, e.g. "Nothing to undo").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Enabled {
    /// Always.
    Always,
    /// There is a step to undo.
    CanUndo,
    /// There is a step to redo.
    CanRedo,
    /// The part has exact faces (operations on a face).
    HasFaces,
}

/// What the enabling rules and the changing labels look at.
#[derive(Clone, Copy, Debug, Default)]
pub struct ActionState {
    /// The step undo would undo.
    pub undo: Option<&'static str>,
    /// The step redo would redo.
    pub redo: Option<&'static str>,
    /// Does the part have exact faces?
    pub has_faces: bool,
}

/// One menu entry and/or keyboard shortcut.
#[derive(Clone, Debug)]
pub struct Action {
    /// What it asks the workstation to do.
    pub command: Command,
    /// The label in the menu (Undo and Redo add the step they would take).
    pub label: String,
    /// Where it sits: menu and section (sections are separated by a line; entries keep the
    /// table's order). `None`: a key only.
    pub menu: Option<(Menu, u8)>,
    /// Tooltip in the menu.
    pub hint: Option<&'static str>,
    /// Its keys (the first is shown in the menu).
    pub keys: Vec<KeyboardShortcut>,
    /// Do its keys work while a text field has focus? (Ctrl+Z belongs to the text field.)
    pub in_text: bool,
    /// When it can be taken.
    pub enabled: Enabled,
}

impl Action {
    /// An entry labelled `label` at `menu` (`None`: a key only) issuing `command`, always
    /// enabled, without keys.
    #[must_use]
    pub fn new(command: Command, label: impl Into<String>, menu: Option<(Menu, u8)>) -> Self {
        Self {
            command,
            label: label.into(),
            menu,
            hint: None,
            keys: Vec::new(),
            in_text: false,
            enabled: Enabled::Always,
        }
    }

    /// With these keys (the first is shown in the menu).
    #[must_use]
    pub fn keys(mut self, keys: &[KeyboardShortcut]) -> Self {
        self.keys = keys.to_vec();
        self
    }

    /// Its keys work inside text fields too.
    #[must_use]
    pub fn global(mut self) -> Self {
        self.in_text = true;
        self
    }

    /// With a tooltip.
    #[must_use]
    pub fn hint(mut self, hint: &'static str) -> Self {
        self.hint = Some(hint);
        self
    }

    /// Enabled only when `enabled` holds.
    #[must_use]
    pub fn when(mut self, enabled: Enabled) -> Self {
        self.enabled = enabled;
        self
    }

    /// Can it be taken now?
    #[must_use]
    pub fn is_enabled(&self, state: &ActionState) -> bool {
        match self.enabled {
            Enabled::Always => true,
            Enabled::CanUndo => state.undo.is_some(),
            Enabled::CanRedo => state.redo.is_some(),
            Enabled::HasFaces => state.has_faces,
        }
    }

    /// The menu label now (Undo and Redo name their step).
    #[must_use]
    pub fn label_in(&self, state: &ActionState) -> String {
        let step = match self.enabled {
            Enabled::CanUndo => state.undo,
            Enabled::CanRedo => state.redo,
            _ => None,
        };
        step.map_or_else(|| self.label.clone(), |s| format!("{} {s}", self.label))
    }
}

/// Every action of the workstation itself, in menu order (the features add theirs, see
/// [`super::feature::Feature::actions`]; the tool windows go to the Machining menu's section 2).
#[must_use]
pub fn actions() -> Vec<Action> {
    use Menu::{Edit, File, Machining, View};
    let mut out = vec![
        Action::new(Command::NewProject, "New Project", Some((File, 0)))
            .keys(&[NEW])
            .global(),
        Action::new(Command::OpenDialog, "Open…", Some((File, 0)))
            .keys(&[OPEN])
            .global(),
        Action::new(Command::OpenProjectDialog, "Open Project…", Some((File, 0))),
        Action::new(Command::SaveProject, "Save Project", Some((File, 0)))
            .keys(&[SAVE])
            .global(),
        Action::new(
            Command::SaveProjectAsDialog,
            "Save Project As…",
            Some((File, 0)),
        )
        .keys(&[SAVE_AS])
        .global(),
        Action::new(
            Command::OpenDefaultPart,
            "Open Default Part",
            Some((File, 1)),
        ),
        Action::new(Command::Quit, "Quit", Some((File, 2)))
            .keys(&[QUIT])
            .global(),
        Action::new(Command::Undo, "Undo", Some((Edit, 0)))
            .keys(&[UNDO])
            .when(Enabled::CanUndo),
        Action::new(Command::Redo, "Redo", Some((Edit, 0)))
            .keys(&[REDO, REDO_ALT])
            .when(Enabled::CanRedo),
        Action::new(Command::FitAll, "Fit All", Some((View, 0))).keys(&[plain(Key::F)]),
    ];
    out.extend(VIEW_KEYS.map(|(v, key)| {
        Action::new(Command::StandardView(v), v.name(), Some((View, 1))).keys(&[plain(key)])
    }));
    out.extend(OperationKind::ALL.map(|kind| {
        let add = Action::new(
            Command::AddOperation(kind),
            format!("Add {}", kind.label()),
            Some((Machining, 0)),
        );
        if kind.needs_face() {
            add.when(Enabled::HasFaces)
        } else {
            add
        }
    }));
    out.extend([
        Action::new(Command::CalculateActive, "Calculate", Some((Machining, 1)))
            .keys(&[plain(Key::F5)]),
        Action::new(Command::SimulateActive, "Simulate", Some((Machining, 1)))
            .keys(&[plain(Key::F6)]),
        Action::new(Command::PostActive, "Post G-code", Some((Machining, 1)))
            .keys(&[plain(Key::F7)]),
        Action::new(
            Command::CompareOperations,
            "Compare operations…",
            Some((Machining, 1)),
        ),
        Action::new(
            Command::ExportProgramDialog,
            "Export G-code…",
            Some((Machining, 1)),
        ),
        Action::new(
            Command::Playback(PlaybackCommand::Toggle),
            "Play / Pause",
            Some((Machining, 1)),
        )
        .keys(&[plain(Key::Space)]),
        Action::new(
            Command::Playback(PlaybackCommand::Step(-1)),
            "Step back",
            None,
        )
        .keys(&[plain(Key::Comma)]),
        Action::new(
            Command::Playback(PlaybackCommand::Step(1)),
            "Step forward",
            None,
        )
        .keys(&[plain(Key::Period)]),
    ]);
    out
}

/// Draw the entries of `menu`'s section `section` as buttons; a clicked one's command goes to
/// `commands` (and closes the menu).
pub fn section_ui(
    ui: &mut egui::Ui,
    table: &[Action],
    state: &ActionState,
    (menu, section): (Menu, u8),
    commands: &mut Vec<Command>,
) {
    for a in table.iter().filter(|a| a.menu == Some((menu, section))) {
        let mut button = egui::Button::new(a.label_in(state));
        if let Some(key) = a.keys.first() {
            button = button.shortcut_text(ui.ctx().format_shortcut(key));
        }
        let mut response = ui.add_enabled(a.is_enabled(state), button);
        if let Some(hint) = a.hint {
            response = response.on_hover_text(hint);
        }
        if response.clicked() {
            commands.push(a.command.clone());
            ui.close();
        }
    }
}

/// Turn this frame's key presses into the commands of `table` (keys other than the global ones
/// only while no text field has focus; a clicked button or tree row keeps focus too, and must
/// not swallow F5 or Space).
pub fn shortcuts(ctx: &egui::Context, table: &[Action], commands: &mut Vec<Command>) {
    let in_text = ctx.text_edit_focused();
    let mut keyed: Vec<(&KeyboardShortcut, &Action)> = table
        .iter()
        .filter(|a| a.in_text || !in_text)
        .flat_map(|a| a.keys.iter().map(move |k| (k, a)))
        .collect();
    // The longer shortcuts first: Ctrl+Shift+S must not be taken as Ctrl+S.
    keyed.sort_by_key(|(k, _)| std::cmp::Reverse(modifier_count(k.modifiers)));
    ctx.input_mut(|i| {
        for (key, action) in keyed {
            if i.consume_shortcut(key) {
                commands.push(action.command.clone());
            }
        }
    });
}

fn modifier_count(m: Modifiers) -> usize {
    [m.alt, m.ctrl || m.command || m.mac_cmd, m.shift]
        .into_iter()
        .filter(|&b| b)
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_two_actions_share_a_key_and_every_entry_has_a_place_or_a_key() {
        let table = actions();
        let mut keys: Vec<KeyboardShortcut> = table.iter().flat_map(|a| a.keys.clone()).collect();
        let n = keys.len();
        keys.sort_by_key(|k| format!("{k:?}"));
        keys.dedup();
        assert_eq!(keys.len(), n, "a key is bound twice");
        assert!(table.iter().all(|a| a.menu.is_some() || !a.keys.is_empty()));
    }

    #[test]
    fn undo_is_greyed_without_a_step_and_names_it_otherwise() {
        let table = actions();
        let Some(undo) = table.iter().find(|a| a.command == Command::Undo) else {
            unreachable!("the table has Undo")
        };
        let none = ActionState::default();
        assert!(!undo.is_enabled(&none));
        let some = ActionState {
            undo: Some("Add operation"),
            ..none
        };
        assert!(undo.is_enabled(&some));
        assert_eq!(undo.label_in(&some), "Undo Add operation");
    }
}
