//! The menu bar: File (Open, Recent, Quit) and View (fit, standard views, projection, edges,
//! grid), with the keyboard shortcuts shown beside the entries.

use egui::{Key, KeyboardShortcut, Modifiers};

use super::super::command::Command;
use super::super::recent_files::RecentFiles;
use crate::render::{Projection, StandardView};

/// Ctrl+O: open a part.
pub const OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
/// Ctrl+Q: quit.
pub const QUIT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Q);

/// The standard views and their keys.
pub const VIEW_KEYS: [(StandardView, Key); 4] = [
    (StandardView::Top, Key::Num1),
    (StandardView::Front, Key::Num2),
    (StandardView::Right, Key::Num3),
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
}

/// The menu bar.
pub fn menu_bar_ui(
    ui: &mut egui::Ui,
    recent: &RecentFiles,
    view: ViewFlags,
    commands: &mut Vec<Command>,
) {
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            if ui
                .add(egui::Button::new("Open…").shortcut_text(ui.ctx().format_shortcut(&OPEN)))
                .clicked()
            {
                commands.push(Command::OpenDialog);
            }
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
    });
    if ctx.egui_wants_keyboard_input() {
        return;
    }
    ctx.input_mut(|i| {
        if i.consume_key(Modifiers::NONE, Key::F) {
            commands.push(Command::FitAll);
        }
        for (v, key) in VIEW_KEYS {
            if i.consume_key(Modifiers::NONE, key) {
                commands.push(Command::StandardView(v));
            }
        }
    });
}
