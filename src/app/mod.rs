//! The workstation (egui/eframe): the only module that sees both the engine and the GUI crates.
//!
//! - [`workstation`]: the [`eframe::App`]; lays out the panels and applies [`command::Command`]s
//!   in one place.
//! - [`actions`]: the one table of menu entries and keyboard shortcuts.
//! - [`job`]: the one background-job type (progress, cancel, poll; dropped = cancelled).
//! - [`state`]: the state types the panels show (focus, dock tab);
//!   [`widgets`]: the small widgets and formatters the panels share.
//! - [`panels`]: menu bar, project tree, properties, log, status bar (they return commands).
//! - [`viewport`]: the 3D view; [`viewport::bridge`] joins egui to [`crate::render`].
//! - [`number_field`]: the one widget every numeric property is typed in.
//! - [`document_loader`]: the one adapter to the engine's importers (runs on a [`job::Job`]).
//! - [`feature`]: the [`feature::Feature`] trait a tool window or panel implements to plug into
//!   the workstation (state, commands, jobs, windows, scene); [`features`] registers them:
//!   - [`program`]: the posted program of the active operation (post, G-code and motion-plot
//!     tabs of the bottom dock, export, line ↔ pose ↔ playback ↔ plot-time links);
//!   - [`reduction`]: data reduction (the part's Z-map reduced by SVD, its error map, STL);
//!   - [`stock_simulation`]: the stock cut by the active path, coloured by its deviation;
//!   - [`operator_panel`]: the virtual control's operator panel (jog, MPG, MDI, AUTO) and the
//!     machine drawn in the viewport;
//!   - [`profile_editor`]: 2D section profiles and their ball-electrode (EDM) paths.

pub mod actions;
pub mod command;
pub mod crease;
pub mod document;
pub mod document_loader;
pub mod face_group;
pub mod feature;
pub mod file_chooser;
pub mod file_dialog;
pub mod findings_list;
pub mod forces;
pub mod job;
pub mod message_log;
pub mod number_field;
pub mod offscreen_render;
pub mod operator_panel;
pub mod panels;
pub mod profile_editor;
pub mod program;
pub mod project_session;
pub mod recent_files;
pub mod reduction;
pub mod scalar_field;
pub mod state;
pub mod stock_simulation;
pub mod theme;
pub mod tool_library;
pub mod toolpaths;
pub mod viewport;
pub mod widgets;
pub mod workstation;

use std::path::PathBuf;

pub use workstation::{Workstation, WorkstationConfig};

/// The registered workstation features (see [`feature`]), in the order their windows are drawn.
/// A new feature is its own folder, its `mod` line above and one line here.
#[must_use]
pub fn features() -> Vec<Box<dyn feature::Feature>> {
    vec![
        Box::new(program::PostedProgram::default()) as Box<dyn feature::Feature>,
        Box::new(reduction::DataReduction::default()),
        Box::new(stock_simulation::StockSimulation::default()),
        Box::new(profile_editor::ProfileEditor::new()),
        Box::new(operator_panel::OperatorPanel::new()),
        Box::new(forces::ForcesWindow::default()),
    ]
}

/// Open the workstation window on `file` (or on the embedded default part).
///
/// # Errors
/// When the window cannot be created (no display, no graphics adapter).
pub fn run(file: Option<PathBuf>) -> Result<(), String> {
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("Talas")
            .with_inner_size([1600.0, 1000.0])
            .with_min_inner_size([800.0, 500.0])
            .with_drag_and_drop(true),
        renderer: eframe::Renderer::Wgpu,
        // The viewport composites into egui's pass with one sample and no depth (see
        // viewport::bridge::install); the 3D scene has its own MSAA and depth.
        multisampling: 1,
        depth_buffer: 0,
        ..Default::default()
    };
    eframe::run_native(
        "Talas",
        options,
        Box::new(move |cc| {
            Ok(Box::new(Workstation::new(
                &cc.egui_ctx,
                cc.wgpu_render_state.as_ref(),
                WorkstationConfig::user(file),
            )))
        }),
    )
    .map_err(|e| e.to_string())
}
