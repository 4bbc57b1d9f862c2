//! STEP entities → boundary representation ([`Part`]), as Open CASCADE transfers them.
//!
//! - `assembly`: roots (product definitions no assembly uses), component placements, cycle and
//!   size guards.
//! - `representation`: shape representations, their items (solids, shells, faces, mapped
//!   items, geometric sets) and relationships.
//! - [`units`]: length and plane angle units of each representation context (all lengths are
//!   scaled to mm, cone angles to rad).
//! - `topology`: shells, faces, loops, oriented edges, edges and vertices (shared by entity id);
//!   `chains`: loops listed out of order or with a reversed edge are repaired into chains.
//! - `curves`, `surfaces`, `splines`, `points`: geometry entities.
//! - [`placement`]: rigid motions applied to every geometry kind.
//!
//! A face that cannot be built (unsupported surface, dangling reference, bad parameters) is
//! skipped with a warning naming its `#id`, as Open CASCADE does; a file yielding no face at all
//! is an error.

mod assembly;
mod chains;
mod curves;
mod entities;
pub mod placement;
mod points;
mod representation;
mod splines;
mod surfaces;
mod topology;
pub mod units;

use super::part21::Exchange;
use crate::diagnostics::Diagnostic;
use crate::geometry::brep::Part;

/// What kind of problem a [`BrepError`] reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// A reference to an entity the file does not have.
    Dangling,
    /// A reference to an entity of the wrong type (a point where a direction is expected).
    WrongType,
    /// A missing or mistyped parameter, or an empty list where one is required.
    BadParameter,
    /// Geometry that cannot be built (zero direction, bad radius, knot/pole/weight mismatch).
    InvalidGeometry,
    /// An entity type Talas does not read.
    Unsupported,
    /// A reference cycle or nesting too deep.
    Cycle,
    /// Nothing in the file made a face.
    NoFaces,
}

/// A B-rep building failure, naming the entity and its line where there is one.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}{message}", self.place().map(|p| format!("{p}: ")).unwrap_or_default())]
pub struct BrepError {
    /// The entity at fault.
    pub id: Option<u64>,
    /// Its 1-based line in the file.
    pub line: Option<usize>,
    /// What kind of problem.
    pub kind: ErrorKind,
    /// What is wrong, one sentence.
    pub message: String,
}

impl BrepError {
    /// `line N, #id` (or whichever of the two is known).
    #[must_use]
    pub fn place(&self) -> Option<String> {
        match (self.line, self.id) {
            (Some(l), Some(i)) => Some(format!("line {l}, #{i}")),
            (None, Some(i)) => Some(format!("#{i}")),
            (Some(l), None) => Some(format!("line {l}")),
            (None, None) => None,
        }
    }
}

/// "no faces found", naming what the file holds instead (the most frequent entity types).
fn no_faces_message(ex: &Exchange) -> String {
    let mut counts: std::collections::BTreeMap<&str, usize> = std::collections::BTreeMap::new();
    for inst in ex.instances.values() {
        for r in &inst.records {
            *counts.entry(r.name.as_str()).or_default() += 1;
        }
    }
    if counts.is_empty() {
        return "no faces found: the data section holds no entities".into();
    }
    let mut by_count: Vec<(&str, usize)> = counts.into_iter().collect();
    by_count.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    let shown: Vec<String> = by_count
        .iter()
        .take(6)
        .map(|(name, n)| format!("{n} {name}"))
        .collect();
    let more = by_count.len().saturating_sub(6);
    format!(
        "no faces found: the file holds {} entities ({}{}), none of them a face of a shape \
         representation",
        ex.instances.len(),
        shown.join(", "),
        if more > 0 {
            format!(", {more} more types")
        } else {
            String::new()
        }
    )
}

/// Build the part a parsed STEP file describes: every face reachable from the root products (or,
/// in a file without products, from its shape representations), in mm. Warnings (faces skipped,
/// units assumed, cycles cut) go to [`Part::diagnostics`] with `place: Some("#id")`, after the
/// parser's own diagnostics.
///
/// # Errors
/// When no face could be built: the first face's error if faces were found but all failed,
/// else [`ErrorKind::NoFaces`].
pub fn build_part(ex: &Exchange) -> Result<Part, BrepError> {
    let model = entities::Model::new(ex);
    let mut transfer = assembly::Transfer::new(&model);
    transfer.run();
    let builder = transfer.b;
    let mut part = builder.part;
    if part.faces.is_empty() {
        return Err(builder.first_error.unwrap_or_else(|| BrepError {
            id: None,
            line: None,
            kind: ErrorKind::NoFaces,
            message: no_faces_message(ex),
        }));
    }
    if builder.faces_skipped > 0 {
        part.diagnostics.push(Diagnostic::warning(
            None,
            format!(
                "{} of {} faces skipped",
                builder.faces_skipped,
                builder.faces_skipped + part.faces.len()
            ),
        ));
    }
    let mut diagnostics = ex.diagnostics.clone();
    diagnostics.append(&mut part.diagnostics);
    part.diagnostics = diagnostics;
    Ok(part)
}
