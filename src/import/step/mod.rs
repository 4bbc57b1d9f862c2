//! STEP (ISO 10303-21, AP203/AP214/AP242) import: a tolerant Part 21 reader ([`part21`]) and the
//! B-rep builder that maps entities to Talas geometry ([`brep`]).
//!
//! Entry points: [`read_step`] (a file to a [`Part`]) and [`brep::build_part`] (a parsed
//! [`part21::Exchange`] to a [`Part`]).

pub mod brep;
pub mod part21;

use std::path::Path;

pub use brep::{BrepError, ErrorKind, build_part};

use super::ImportError;
use crate::geometry::brep::Part;

/// Read a STEP file into a [`Part`] (mm): parse it, then build the B-rep of every face its root
/// products reach. Warnings travel in [`Part::diagnostics`].
///
/// # Errors
/// An [`ImportError`] naming the file and the place (`line N, #id`) when the file cannot be read
/// or parsed, or yields no face.
pub fn read_step(path: &Path) -> Result<Part, ImportError> {
    let bytes = std::fs::read(path)
        .map_err(|e| ImportError::new(path, None, format!("cannot read the file: {e}")))?;
    read_step_bytes(path, &bytes)
}

/// Like [`read_step`] for bytes already in memory; `path` only names the source in errors.
///
/// # Errors
/// As [`read_step`].
pub fn read_step_bytes(path: &Path, bytes: &[u8]) -> Result<Part, ImportError> {
    let ex = part21::parse(bytes).map_err(|e| {
        let place = match e.id {
            Some(id) => format!("line {}, #{id}", e.line),
            None => format!("line {}", e.line),
        };
        ImportError::new(path, Some(place), e.message.clone())
    })?;
    build_part(&ex).map_err(|e| ImportError::new(path, e.place(), e.message.clone()))
}
