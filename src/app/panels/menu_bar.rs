//! The menu bar: File (new, open, save, save as, recent, quit), Edit (undo, redo) and View (fit,
//! standard views, projection, edges, grid, colour by a scalar field), with the keyboard
//! shortcuts shown beside the entries.

use egui::{Key, KeyboardShortcut, Modifiers};

use super::super::command::{Command, PlaybackCommand};
use super::super::recent_files::RecentFiles;
use super::super::scalar_field::ScalarField;
use super::super::toolpaths::PathColouring;
use crate::project::OperationKind;
use crate::render::{Projection, StandardView};

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

/// What the View menu shows as checked.
#[derive(Clone, Copy, Debug)]
pub struct ViewFlags {
    /// Current projection.
    pub projection: Projection,
    /// Edges shown.
    pub edges: bool,
    /// Grid shown.
    pub grid: bool,
    /// Scalar field the part is coloured by.
    pub scalar_field: Option<ScalarField>,
    /// Can the part be coloured by curvature (it has exact surfaces)?
    pub fields_available: bool,
    /// How tool paths are coloured.
    pub path_colouring: PathColouring,
    /// Every operation's path drawn (not only the active one's).
    pub all_paths: bool,
    /// Tool-axis vectors drawn at the active path's cutting poses.
    pub axis_vectors: bool,
    /// Does the part have exact faces (finishing operations possible)?
    pub has_faces: bool,
    /// The simulated stock is drawn.
    pub stock: bool,
    /// There is a simulated stock to draw.
    pub stock_available: bool,
}

/// What the Edit menu shows: descriptions of the steps undo and redo would take.
#[derive(Clone, Copy, Debug, Default)]
pub struct UndoLabels {
    /// The step undo would undo.
    pub undo: Option<&'static str>,
    /// The step redo would redo.
    pub redo: Option<&'static str>,
}

fn shortcut_button(ui: &mut egui::Ui, text: &str, shortcut: &KeyboardShortcut) -> bool {
    ui.add(egui::Button::new(text).shortcut_text(ui.ctx().format_shortcut(shortcut)))
        .clicked()
}

/// The menu bar.
pub fn menu_bar_ui(
    ui: &mut egui::Ui,
    recent: &RecentFiles,
    view: ViewFlags,
    undo: UndoLabels,
    commands: &mut Vec<Command>,
) {
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            if shortcut_button(ui, "New Project", &NEW) {
                commands.push(Command::NewProject);
            }
            if shortcut_button(ui, "Open…", &OPEN) {
                commands.push(Command::OpenDialog);
            }
            if ui.button("Open Project…").clicked() {
                commands.push(Command::OpenProjectDialog);
            }
            if shortcut_button(ui, "Save Project", &SAVE) {
                commands.push(Command::SaveProject);
            }
            if shortcut_button(ui, "Save Project As…", &SAVE_AS) {
                commands.push(Command::SaveProjectAsDialog);
            }
            ui.separator();
            if ui.button("Open Default Part").clicked() {
                commands.push(Command::OpenDefaultPart);
            }
            ui.add_enabled_ui(!recent.paths.is_empty(), |ui| {
                ui.menu_button("Open Recent", |ui| {
                    for path in &recent.paths {
                        let name = path.file_name().map_or_else(
                            || path.display().to_string(),
                            |n| n.to_string_lossy().into_owned(),
                        );
                        if ui
                            .button(name)
                            .on_hover_text(path.display().to_string())
                            .clicked()
                        {
                            commands.push(Command::Open(path.clone()));
                        }
                    }
                });
            });
            ui.separator();
            if ui
                .add(egui::Button::new("Quit").shortcut_text(ui.ctx().format_shortcut(&QUIT)))
                .clicked()
            {
                commands.push(Command::Quit);
            }
        });
        ui.menu_button("Edit", |ui| {
            let text = undo
                .undo
                .map_or_else(|| "Undo".to_string(), |l| format!("Undo {l}"));
            if ui
                .add_enabled(
                    undo.undo.is_some(),
                    egui::Button::new(text).shortcut_text(ui.ctx().format_shortcut(&UNDO)),
                )
                .clicked()
            {
                commands.push(Command::Undo);
            }
            let text = undo
                .redo
                .map_or_else(|| "Redo".to_string(), |l| format!("Redo {l}"));
            if ui
                .add_enabled(
                    undo.redo.is_some(),
                    egui::Button::new(text).shortcut_text(ui.ctx().format_shortcut(&REDO)),
                )
                .clicked()
            {
                commands.push(Command::Redo);
            }
        });
        ui.menu_button("View", |ui| {
            if ui
                .add(egui::Button::new("Fit All").shortcut_text("F"))
                .clicked()
            {
                commands.push(Command::FitAll);
            }
            ui.separator();
            for (v, key) in VIEW_KEYS {
                if ui
                    .add(egui::Button::new(v.name()).shortcut_text(key.symbol_or_name()))
                    .clicked()
                {
                    commands.push(Command::StandardView(v));
                }
            }
            ui.separator();
            let mut projection = view.projection;
            ui.radio_value(&mut projection, Projection::Perspective, "Perspective");
            ui.radio_value(&mut projection, Projection::Orthographic, "Orthographic");
            if projection != view.projection {
                commands.push(Command::SetProjection(projection));
            }
            ui.separator();
            let mut edges = view.edges;
            if ui.checkbox(&mut edges, "Edges").changed() {
                commands.push(Command::SetEdges(edges));
            }
            let mut grid = view.grid;
            if ui.checkbox(&mut grid, "Grid").changed() {
                commands.push(Command::SetGrid(grid));
            }
            ui.separator();
            ui.add_enabled_ui(view.fields_available, |ui| {
                ui.menu_button("Colour By", |ui| {
                    let mut field = view.scalar_field;
                    ui.radio_value(&mut field, None, "Plain");
                    for f in ScalarField::ALL {
                        ui.radio_value(&mut field, Some(f), f.name());
                    }
                    if field != view.scalar_field {
                        commands.push(Command::SetScalarField(field));
                    }
                });
            });
            ui.menu_button("Tool Paths", |ui| {
                let mut c = view.path_colouring;
                for option in PathColouring::ALL {
                    ui.radio_value(&mut c, option, option.name());
                }
                if c != view.path_colouring {
                    commands.push(Command::SetPathColouring(c));
                }
                ui.separator();
                let mut all = view.all_paths;
                if ui.checkbox(&mut all, "All operations").changed() {
                    commands.push(Command::SetShowAllPaths(all));
                }
                let mut axes = view.axis_vectors;
                if ui.checkbox(&mut axes, "Tool-axis vectors").changed() {
                    commands.push(Command::SetShowAxisVectors(axes));
                }
                let mut stock = view.stock;
                if ui
                    .add_enabled(
                        view.stock_available,
                        egui::Checkbox::new(&mut stock, "Simulated stock"),
                    )
                    .changed()
                {
                    commands.push(Command::SetStockVisible(stock));
                }
            });
        });
        ui.menu_button("Machining", |ui| {
            for kind in OperationKind::ALL {
                let enabled = view.has_faces || !kind.needs_face();
                if ui
                    .add_enabled(enabled, egui::Button::new(format!("Add {}", kind.label())))
                    .clicked()
                {
                    commands.push(Command::AddOperation(kind));
                    ui.close();
                }
            }
            ui.separator();
            if ui
                .add(egui::Button::new("Calculate").shortcut_text("F5"))
                .clicked()
            {
                commands.push(Command::CalculateActive);
                ui.close();
            }
            if ui
                .add(egui::Button::new("Simulate").shortcut_text("F6"))
                .clicked()
            {
                commands.push(Command::SimulateActive);
                ui.close();
            }
            if ui
                .add(egui::Button::new("Post G-code").shortcut_text("F7"))
                .clicked()
            {
                commands.push(Command::PostActive);
                ui.close();
            }
            if ui.button("Compare operations…").clicked() {
                commands.push(Command::CompareOperations);
                ui.close();
            }
            if ui.button("Export G-code…").clicked() {
                commands.push(Command::ExportProgramDialog);
                ui.close();
            }
            ui.separator();
            if ui
                .button("Data reduction (Z-map SVD)…")
                .on_hover_text(
                    "Sample the part's Z-map and reduce it by singular value decomposition",
                )
                .clicked()
            {
                commands.push(Command::OpenReductionView);
                ui.close();
            }
            if ui
                .button("2D profile / EDM electrode…")
                .on_hover_text("Profile editor: the path of a ball electrode along a 2D section")
                .clicked()
            {
                commands.push(Command::OpenProfileEditor);
                ui.close();
            }
            if ui
                .button("Operator panel…")
                .on_hover_text("Jog, MDI and AUTO on the virtual control of the project's machine")
                .clicked()
            {
                commands.push(Command::OpenOperatorPanel);
                ui.close();
            }
            if ui
                .button("Cutting forces…")
                .on_hover_text("Forces, torque and power along the active operation's path; the coefficient library")
                .clicked()
            {
                commands.push(Command::OpenForces);
                ui.close();
            }
            if ui
                .add(egui::Button::new("Play / Pause").shortcut_text("Space"))
                .clicked()
            {
                commands.push(Command::Playback(PlaybackCommand::Toggle));
                ui.close();
            }
        });
    });
}

/// Keyboard shortcuts of the workstation (not while a text field has focus).
pub fn shortcuts(ctx: &egui::Context, commands: &mut Vec<Command>) {
    ctx.input_mut(|i| {
        if i.consume_shortcut(&OPEN) {
            commands.push(Command::OpenDialog);
        }
        if i.consume_shortcut(&QUIT) {
            commands.push(Command::Quit);
        }
        if i.consume_shortcut(&NEW) {
            commands.push(Command::NewProject);
        }
        // The longer shortcuts first: Ctrl+Shift+S must not be taken as Ctrl+S.
        if i.consume_shortcut(&SAVE_AS) {
            commands.push(Command::SaveProjectAsDialog);
        }
        if i.consume_shortcut(&SAVE) {
            commands.push(Command::SaveProject);
        }
    });
    // Only a focused text field takes the keys (a clicked button or tree row keeps focus too,
    // and must not swallow F5 or Space).
    if ctx.text_edit_focused() {
        // A text field has focus: Ctrl+Z belongs to it.
        return;
    }
    ctx.input_mut(|i| {
        if i.consume_shortcut(&REDO) || i.consume_shortcut(&REDO_ALT) {
            commands.push(Command::Redo);
        }
        if i.consume_shortcut(&UNDO) {
            commands.push(Command::Undo);
        }
    });
    ctx.input_mut(|i| {
        if i.consume_key(Modifiers::NONE, Key::F) {
            commands.push(Command::FitAll);
        }
        if i.consume_key(Modifiers::NONE, Key::F5) {
            commands.push(Command::CalculateActive);
        }
        if i.consume_key(Modifiers::NONE, Key::F6) {
            commands.push(Command::SimulateActive);
        }
        if i.consume_key(Modifiers::NONE, Key::F7) {
            commands.push(Command::PostActive);
        }
        if i.consume_key(Modifiers::NONE, Key::Space) {
            commands.push(Command::Playback(PlaybackCommand::Toggle));
        }
        if i.consume_key(Modifiers::NONE, Key::Comma) {
            commands.push(Command::Playback(PlaybackCommand::Step(-1)));
        }
        if i.consume_key(Modifiers::NONE, Key::Period) {
            commands.push(Command::Playback(PlaybackCommand::Step(1)));
        }
        for (v, key) in VIEW_KEYS {
            if i.consume_key(Modifiers::NONE, key) {
                commands.push(Command::StandardView(v));
            }
        }
    });
}
