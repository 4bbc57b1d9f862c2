//! The workstation (egui/eframe): the only module that sees both the engine and the GUI crates.

use std::path::PathBuf;

/// Open the workstation window on `file` (or on the embedded default part).
///
/// # Errors
/// When the window cannot be created (no display, no graphics adapter).
pub fn run(file: Option<PathBuf>) -> Result<(), String> {
    let _ = file;
    todo!("gui helper")
}
