//! Calculated paths saved beside their project (`NAME.talas.paths`), so reopening a project
//! does not recalculate what its inputs have not changed: each path is kept with the digest of
//! every input its computation read ([`super::pipeline::digests`]), and a path is taken back
//! only for an operation whose digest is the same now (same operation, tool, part, stock,
//! setups, machine, earlier operations). The file is JSON, written atomically and strictly
//! (sorted by operation, byte-identical for the same paths); reading is bounded in size and a
//! file that does not parse is reported, never fatal: the project opens without its paths.

use std::path::{Path, PathBuf};

use super::pipeline::Computed;
use super::results::Digest;

/// The format line of the file.
pub const FORMAT: &str = "talas-paths 1";

/// The largest paths file read, bytes (paths of a large job can be long; a file past this is
/// reported and left alone).
pub const LIMIT_BYTES: u64 = 1 << 30;

/// One saved path: the operation's index, the digest of its inputs, and its result.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SavedPath {
    /// Index of the operation in the project.
    pub operation: usize,
    /// The digest of the inputs it was computed from, 16 hex digits.
    pub digest: String,
    /// The result (the path as shown, posted and simulated).
    pub computed: Computed,
}

#[derive(serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    format: String,
    paths: Vec<SavedPath>,
}

/// The paths file of the project file `project`: `project` + `.paths`.
#[must_use]
pub fn paths_file(project: &Path) -> PathBuf {
    let mut name = project.as_os_str().to_owned();
    name.push(".paths");
    PathBuf::from(name)
}

/// Write `paths` (operation index, input digest, result) to `file`, atomically; with no path,
/// remove an old file instead (a stale file would never match, but need not stay).
///
/// # Errors
/// The file that could not be written and why.
pub fn save(file: &Path, paths: &[(usize, Digest, &Computed)]) -> Result<(), String> {
    if paths.is_empty() {
        return match std::fs::remove_file(file) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                Err(format!("{}: cannot remove: {e}", file.display()))
            }
            _ => Ok(()),
        };
    }
    let mut paths: Vec<SavedPath> = paths
        .iter()
        .map(|(operation, digest, computed)| SavedPath {
            operation: *operation,
            digest: digest.to_string(),
            computed: (*computed).clone(),
        })
        .collect();
    paths.sort_by_key(|p| p.operation);
    let text = serde_json::to_vec(&File {
        format: FORMAT.into(),
        paths,
    })
    .map_err(|e| format!("{}: cannot encode the paths: {e}", file.display()))?;
    crate::storage::write_atomic(file, &text)
        .map_err(|e| format!("{}: cannot write: {e}", file.display()))
}

/// The paths saved in `file` (none when there is no file).
///
/// # Errors
/// The file and why it cannot be read: too large, not this format, not valid JSON (with the
/// line and column).
pub fn load(file: &Path) -> Result<Vec<SavedPath>, String> {
    let bytes = match crate::storage::read_bounded(file, LIMIT_BYTES) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(format!("{}: {e}", file.display())),
    };
    let f: File = serde_json::from_slice(&bytes).map_err(|e| {
        format!(
            "{}: line {}, column {}: {e}",
            file.display(),
            e.line(),
            e.column()
        )
    })?;
    if f.format != FORMAT {
        return Err(format!(
            "{}: format '{}', expected '{FORMAT}'",
            file.display(),
            f.format
        ));
    }
    Ok(f.paths)
}

/// The saved path of operation `index` when it was computed from inputs with digest `digest`.
#[must_use]
pub fn matching(saved: &[SavedPath], index: usize, digest: Digest) -> Option<&SavedPath> {
    let want = digest.to_string();
    saved
        .iter()
        .find(|p| p.operation == index && p.digest == want)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};

    fn computed() -> Computed {
        let cutter = crate::tools::Cutter::new(crate::tools::CutterKind::Ball, 6.0).unwrap();
        let pose =
            |x: f64, kind| Pose::new(kind, glam::DVec3::new(x, 1.0, 2.0), glam::DVec3::Z, 600.0);
        Computed {
            toolpath: Toolpath::new(
                ToolRecord {
                    spec: "ball:d=6".into(),
                    cutter,
                },
                vec![pose(0.0, MoveKind::Rapid), pose(1.5, MoveKind::Cut)],
            ),
            passes: 1,
            diagnostics: vec![crate::diagnostics::Diagnostic::warning(None, "a note")],
            lead_rad: Some(0.1),
            clearance_mm: None,
            part_hits: Vec::new(),
            left_out: Vec::new(),
        }
    }

    #[test]
    fn paths_round_trip_and_match_only_their_digest() {
        let dir = std::env::temp_dir().join(format!("talas-saved-paths-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = paths_file(&dir.join("job.talas"));
        assert!(file.ends_with("job.talas.paths"));
        assert_eq!(load(&file).unwrap(), Vec::new(), "no file: no paths");
        let c = computed();
        save(&file, &[(2, Digest(0xabc), &c), (0, Digest(7), &c)]).unwrap();
        let first = std::fs::read(&file).unwrap();
        save(&file, &[(0, Digest(7), &c), (2, Digest(0xabc), &c)]).unwrap();
        assert_eq!(std::fs::read(&file).unwrap(), first, "byte-identical");
        let back = load(&file).unwrap();
        assert_eq!(back.len(), 2);
        assert_eq!(back[0].operation, 0);
        assert_eq!(back[1].computed, c);
        assert!(matching(&back, 2, Digest(0xabc)).is_some());
        assert!(
            matching(&back, 2, Digest(0xabd)).is_none(),
            "changed inputs"
        );
        assert!(
            matching(&back, 1, Digest(0xabc)).is_none(),
            "another operation"
        );
        // A broken file is an error naming it and the place, never a panic.
        std::fs::write(&file, b"{\"format\": \"talas-paths 1\", \"paths\": [1,").unwrap();
        let e = load(&file).unwrap_err();
        assert!(e.contains("job.talas.paths") && e.contains("line 1"), "{e}");
        std::fs::write(&file, b"{\"format\": \"other 9\", \"paths\": []}").unwrap();
        assert!(
            load(&file)
                .unwrap_err()
                .contains("expected 'talas-paths 1'")
        );
        save(&file, &[]).unwrap();
        assert!(!file.exists(), "no path: the file goes");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
