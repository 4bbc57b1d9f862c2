//! The user's tool library: a TOML file (`tools.toml` in the data folder) holding the tools a new
//! project starts with. The default library (`assets/tools/default.toml`) is compiled in, so a
//! fresh machine has it; the tool library panel writes the file (atomically) after each change.

use std::path::{Path, PathBuf};

use crate::project::ToolEntry;
use crate::tools::CutterKind;

/// The library format version written by this build.
pub const TOOL_LIBRARY_VERSION: u32 = 1;

/// The default library, compiled into the binary.
pub const DEFAULT_LIBRARY_TOML: &str = include_str!("../../assets/tools/default.toml");

/// The name of the library file in the data folder.
pub const LIBRARY_FILE_NAME: &str = "tools.toml";

/// A tool library.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ToolLibrary {
    /// Format version (1 when missing).
    #[serde(default = "first_version")]
    pub version: u32,
    /// Index of the tool a new project selects (`None`: the first ball end mill, if any).
    #[serde(default)]
    pub default_tool: Option<usize>,
    /// The tools.
    #[serde(default)]
    pub tools: Vec<ToolEntry>,
}

fn first_version() -> u32 {
    1
}

impl ToolLibrary {
    /// Parse library TOML; `source` names the file in errors.
    ///
    /// # Errors
    /// A one-line message naming `source`: TOML syntax (with line), a newer version, an invalid
    /// tool size.
    pub fn from_toml(text: &str, source: &Path) -> Result<Self, String> {
        let lib: Self = toml::from_str(text).map_err(|e| {
            let line = e.span().map_or(1, |s| {
                text.get(..s.start).unwrap_or("").matches('\n').count() + 1
            });
            format!("{}:{line}: {}", source.display(), e.message().trim())
        })?;
        if lib.version > TOOL_LIBRARY_VERSION {
            return Err(format!(
                "{}: tool library version {} is newer than this Talas understands ({TOOL_LIBRARY_VERSION})",
                source.display(),
                lib.version
            ));
        }
        for (i, t) in lib.tools.iter().enumerate() {
            t.cutter
                .validate()
                .map_err(|e| format!("{}: tool {} ('{}'): {e}", source.display(), i + 1, t.name))?;
        }
        Ok(lib)
    }

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

    /// Write the library to `path` atomically (creating the folder).
    ///
    /// # Errors
    /// The I/O or encoding error, naming the file.
    pub fn save(&self, path: &Path) -> Result<(), String> {
        let text = toml::to_string_pretty(self).map_err(|e| format!("{}: {e}", path.display()))?;
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let header = "# Talas tool library (lengths in mm, cone half_angle in rad)\n\n";
        crate::storage::write_atomic(path, format!("{header}{text}").as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The tool a new project selects: `default_tool` when valid, else the first ball end mill,
    /// else the first tool.
    #[must_use]
    pub fn default_selection(&self) -> Option<usize> {
        self.default_tool
            .filter(|&i| i < self.tools.len())
            .or_else(|| {
                self.tools
                    .iter()
                    .position(|t| t.cutter.kind == CutterKind::Ball)
            })
            .or(if self.tools.is_empty() { None } else { Some(0) })
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
