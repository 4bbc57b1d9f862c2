//! The user's tool library: a TOML file (`tools.toml` in the data folder) holding the tools a new
//! project starts with. The default library (`assets/tools/default.toml`) is compiled in, so a
//! fresh machine has it; the workstation writes the file (atomically) after each change of the
//! project's tools, merged with what another workstation sharing the file saved since
//! (`ToolLibrary::save_merged`: a tool added there is kept, a conflicting edit refused).

use std::path::{Path, PathBuf};

pub use crate::project::tool_library::{TOOL_LIBRARY_VERSION, ToolLibrary};

/// The default library, compiled into the binary.
pub const DEFAULT_LIBRARY_TOML: &str = include_str!("../../assets/tools/default.toml");

/// The name of the library file in the data folder.
pub const LIBRARY_FILE_NAME: &str = "tools.toml";

/// The workstation's side of the library: the compiled-in default and the start-up load (the
/// format, the checks and the merged save are the engine's, [`crate::project::tool_library`]).
impl ToolLibrary {
    /// The compiled-in default library.
    #[must_use]
    pub fn builtin() -> Self {
        // The embedded file is checked by a unit test; an empty library is the fallback.
        Self::from_toml(DEFAULT_LIBRARY_TOML, Path::new("assets/tools/default.toml")).unwrap_or(
            Self {
                version: TOOL_LIBRARY_VERSION,
                default_tool: None,
                tools: Vec::new(),
            },
        )
    }

    /// The library at `path`; the built-in one when the file does not exist. A file that exists
    /// but cannot be read or parsed gives the built-in library and the error message.
    #[must_use]
    pub fn load_or_builtin(path: &Path) -> (Self, Option<String>) {
        match std::fs::read_to_string(path) {
            Ok(text) => match Self::from_toml(&text, path) {
                Ok(lib) => (lib, None),
                Err(e) => (Self::builtin(), Some(e)),
            },
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => (Self::builtin(), None),
            Err(e) => (Self::builtin(), Some(format!("{}: {e}", path.display()))),
        }
    }
}

/// The library file in `data_dir`.
#[must_use]
pub fn library_path(data_dir: &Path) -> PathBuf {
    data_dir.join(LIBRARY_FILE_NAME)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::CutterKind;

    #[test]
    fn the_builtin_library_parses_and_selects_a_ball_end_mill() {
        let lib = ToolLibrary::from_toml(DEFAULT_LIBRARY_TOML, Path::new("default.toml"))
            .expect("default library is valid");
        assert!(lib.tools.len() >= 4);
        let kinds: Vec<_> = lib.tools.iter().map(|t| t.cutter.kind).collect();
        assert!(kinds.contains(&CutterKind::Flat));
        assert!(
            kinds
                .iter()
                .any(|k| matches!(k, CutterKind::BullNose { .. }))
        );
        assert!(kinds.iter().any(|k| matches!(k, CutterKind::Cone { .. })));
        let sel = lib.default_selection().expect("a default tool");
        assert_eq!(lib.tools[sel].cutter.kind, CutterKind::Ball);
        assert!((lib.tools[sel].cutter.diameter - 6.0).abs() < 1e-12);
    }

    #[test]
    fn a_saved_library_reads_back_equal_and_bad_files_name_the_place() {
        let dir = std::env::temp_dir().join(format!("talas-toollib-{}", std::process::id()));
        let path = library_path(&dir);
        let lib = ToolLibrary::builtin();
        lib.save(&path).expect("saved");
        let (back, err) = ToolLibrary::load_or_builtin(&path);
        assert_eq!(err, None);
        assert_eq!(back, lib);
        let _ = std::fs::write(&path, "version = 1\n[[tools]]\nname = 3\n");
        let (fallback, err) = ToolLibrary::load_or_builtin(&path);
        assert_eq!(fallback, lib);
        assert!(err.is_some_and(|e| e.contains("tools.toml:3")));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
