//! L1 importers: STEP (ISO 10303-21) to a [`crate::geometry::brep::Part`], STL to a
//! [`crate::geometry::mesh::TriMesh`], and the one reader of parts, [`open`], which decides a
//! file's kind and gives a [`Workpiece`] (B-rep, mesh, exact faces, one shared BVH). Every error
//! names the file and the place in it.

pub mod step;
pub mod stl;
pub mod workpiece;

pub use workpiece::{FileFormat, OpenOptions, Workpiece, open, open_step_bytes};

use std::path::{Path, PathBuf};

/// An import failure: which file, where in it, and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}{}: {message}", file.display(), place.as_ref().map(|p| format!(": {p}")).unwrap_or_default())]
pub struct ImportError {
    /// The file being read.
    pub file: PathBuf,
    /// The place: `line 12`, `#345`, `line 12, #345`, `byte 84`, `facet 3`, ...
    pub place: Option<String>,
    /// What is wrong, one sentence.
    pub message: String,
}

impl ImportError {
    /// An error in `file` at `place`.
    pub fn new(file: &Path, place: impl Into<Option<String>>, message: impl Into<String>) -> Self {
        Self {
            file: file.to_path_buf(),
            place: place.into(),
            message: message.into(),
        }
    }
}
