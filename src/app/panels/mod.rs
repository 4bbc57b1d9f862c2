//! The panels around the viewport. Each reads the state it shows and returns [`super::command::Command`]s;
//! none changes the document itself. The state types they show live in [`super::state`], the
//! small widgets and formatters they share in [`super::widgets`].

pub mod log_panel;
pub mod machine_panel;
pub mod menu_bar;
pub mod operation_editor;
pub mod playback;
pub mod project_dialogs;
pub mod project_tree;
pub mod properties;
pub mod setup_editor;
pub mod status_bar;
pub mod tool_library;

pub use super::widgets::grouped;
