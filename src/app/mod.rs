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
//!   the workstation (state, commands, jobs, windows, scene, files); [`features`] lists the
//!   registered ones, each its own module (folder). A feature is registered by one line of the
//!   `features!` list in this file, which declares its module and adds it to [`features`].
//! - [`posted`]: the posted program as the features share it (made by the program feature,
//!   read by the playback, the forces, the operator panel and the path colouring).

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
pub mod job;
pub mod message_log;
pub mod number_field;
pub mod offscreen_render;
pub mod panels;
pub mod posted;
pub mod project_session;
pub mod recent_files;
pub mod scalar_field;
pub mod state;
pub mod theme;
pub mod tool_library;
pub mod toolpaths;
pub mod viewport;
pub mod widgets;
pub mod workstation;

use std::path::PathBuf;

pub use workstation::{Workstation, WorkstationConfig};

/// Declares each feature's module and builds [`features`] from the same list, so that a new
/// feature is its own folder plus one line in the list. (`cargo fmt` does not reach modules
/// declared inside a macro: CI formats them with `rustfmt src/app/*/mod.rs`.)
macro_rules! features {
    ($($module:ident :: $feature:ident),+ $(,)?) => {
        $(pub mod $module;)+

        /// The registered workstation features (see [`feature`]), in the order their commands
        /// are offered and their windows drawn:
        ///
        $(#[doc = concat!("- [`", stringify!($module), "::", stringify!($feature), "`]")])+
        #[must_use]
        pub fn features() -> Vec<Box<dyn feature::Feature>> {
            vec![$(boxed::<$module::$feature>()),+]
        }
    };
}

/// A fresh `F`, boxed as a feature.
fn boxed<F: feature::Feature + Default>() -> Box<dyn feature::Feature> {
    Box::new(F::default())
}

// The data reduction's surface wins over the simulated stock (first `instead_of_part`).
features! {
    program::PostedProgram,
    reduction::DataReduction,
    stock_simulation::StockSimulation,
    profile_editor::ProfileEditor,
    operator_panel::OperatorPanel,
    forces::ForcesWindow,
    job_setups::JobSetups,
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
