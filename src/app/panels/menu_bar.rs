//! The menu bar: File (new, open, save, save as, recent, quit), Edit (undo, redo), View (fit,
//! standard views, projection, edges, grid, colour by a scalar field) and Machining. The entries
//! that issue a command, with their keys, come from the one table in [`super::super::actions`];
//! the check boxes, radio buttons and the recent-files list are laid out here.

use super::super::actions::{Action, ActionState, Menu, Toggle, section_ui};
use super::super::command::Command;
use super::super::recent_files::RecentFiles;
use super::super::scalar_field::ScalarField;
use super::super::toolpaths::PathColouring;
use crate::render::Projection;

/// What the View menu shows as checked.
#[derive(Clone, Copy, Debug)]
pub struct ViewFlags {
    /// Current projection.
    pub projection: Projection,
    /// Edges shown.
    pub edges: bool,
    /// Grid shown.
    pub grid: bool,
    /// The view orbits in the active setup's frame (the part as it lies on that setup's table).
    pub orient_to_setup: bool,
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
}

/// What the Edit menu shows: descriptions of the steps undo and redo would take.
#[derive(Clone, Copy, Debug, Default)]
pub struct UndoLabels {
    /// The step undo would undo.
    pub undo: Option<&'static str>,
    /// The step redo would redo.
    pub redo: Option<&'static str>,
}

/// The menu bar: the table's entries (`actions`) in their menus and sections, and the view
/// toggles (the features' `toggles` at the end of View → Tool Paths).
pub fn menu_bar_ui(
    ui: &mut egui::Ui,
    actions: &[Action],
    recent: &RecentFiles,
    view: ViewFlags,
    toggles: &[Toggle],
    undo: UndoLabels,
    commands: &mut Vec<Command>,
) {
    let state = ActionState {
        undo: undo.undo,
        redo: undo.redo,
        has_faces: view.has_faces,
    };
    let section = |ui: &mut egui::Ui, place: (Menu, u8), commands: &mut Vec<Command>| {
        section_ui(ui, actions, &state, place, commands);
    };
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            section(ui, (Menu::File, 0), commands);
            ui.separator();
            section(ui, (Menu::File, 1), commands);
            recent_ui(ui, recent, commands);
            ui.separator();
            section(ui, (Menu::File, 2), commands);
        });
        ui.menu_button("Edit", |ui| section(ui, (Menu::Edit, 0), commands));
        ui.menu_button("View", |ui| {
            section(ui, (Menu::View, 0), commands);
            ui.separator();
            section(ui, (Menu::View, 1), commands);
            ui.separator();
            view_toggles_ui(ui, view, toggles, commands);
        });
        ui.menu_button("Machining", |ui| {
            section(ui, (Menu::Machining, 0), commands);
            ui.separator();
            section(ui, (Menu::Machining, 1), commands);
            ui.separator();
            section(ui, (Menu::Machining, 2), commands);
        });
    });
}

/// File → Open Recent.
fn recent_ui(ui: &mut egui::Ui, recent: &RecentFiles, commands: &mut Vec<Command>) {
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
}

/// View: projection, edges, grid, colour by, tool paths (state shown and changed in place).
fn view_toggles_ui(
    ui: &mut egui::Ui,
    view: ViewFlags,
    toggles: &[Toggle],
    commands: &mut Vec<Command>,
) {
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
    let mut orient = view.orient_to_setup;
    if ui
        .checkbox(&mut orient, "Part as it lies in the setup")
        .on_hover_text(
            "The view turns with the active setup: Top looks down its spindle, and the view \
             cube names its sides. Off, the part keeps its own CAD orientation.",
        )
        .changed()
    {
        commands.push(Command::SetOrientToSetup(orient));
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
        for t in toggles {
            let mut on = t.on;
            if ui
                .add_enabled(t.enabled, egui::Checkbox::new(&mut on, t.label))
                .changed()
            {
                commands.push((t.set)(on));
            }
        }
    });
}
