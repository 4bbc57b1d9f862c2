//! STL reader (ASCII and binary, reliably told apart) and writer.
//!
//! Telling the two apart: a file is binary when its length is exactly `84 + 50 · count`, where
//! `count` is the little-endian `u32` at byte 80, even when its 80-byte header starts with
//! `solid` (many exporters write that). Otherwise a file starting with `solid` is read as ASCII;
//! anything else is read as binary, and a length that does not match the header's count is an
//! error naming the facet and byte where the data ends or the extra data begins.
//!
//! Reading never allocates more than the file's own size justifies, never panics, and names the
//! place of every error: `facet K, byte N` for binary files, `line N` for ASCII.

mod ascii;
mod binary;
mod writer;

use std::path::Path;

pub use writer::{save_stl, write_stl_ascii, write_stl_binary};

use super::ImportError;
use crate::diagnostics::Diagnostic;
use crate::geometry::DVec3;
use crate::geometry::mesh::TriMesh;

/// How to turn an STL file into a mesh.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StlOptions {
    /// Millimetres per file unit (1.0 for files in mm, 25.4 for inches). Must be finite and > 0.
    pub unit_scale: f64,
    /// Vertices closer than this (absolute, mm, after scaling) are merged into one, so that the
    /// facet soup becomes a connected mesh. Default 1e-5 mm (10 nm): far below any machining
    /// tolerance, yet it still joins corners that two exporter code paths rounded slightly
    /// differently. 0 merges only bit-identical corners. Must be finite and ≥ 0.
    pub weld_tol_mm: f64,
}

impl Default for StlOptions {
    fn default() -> Self {
        Self {
            unit_scale: 1.0,
            weld_tol_mm: 1e-5,
        }
    }
}

/// The two STL encodings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum StlFormat {
    /// Text: `solid … facet normal … outer loop … vertex … endsolid`.
    Ascii,
    /// 80-byte header, `u32` facet count, 50 bytes a facet.
    Binary,
}

/// An STL file read into a welded mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct StlMesh {
    /// The welded mesh (mm), with angle-weighted vertex normals; triangles wound as in the file.
    pub mesh: TriMesh,
    /// Which encoding the file used.
    pub format: StlFormat,
    /// Number of facets in the file (before welding drops collapsed ones).
    pub facet_count: usize,
    /// The solid's name (ASCII) or the header's printable text (binary), trimmed.
    pub name: String,
    /// File facet indices (0-based) of facets with zero area.
    pub degenerate_facets: Vec<usize>,
    /// Warnings and notes about the file (trailing bytes, flipped normals, open edges, ...).
    pub diagnostics: Vec<Diagnostic>,
}

/// Facets as read from the file, before scaling and welding.
#[derive(Clone, Debug, Default)]
struct RawFacets {
    /// Three corners per facet, in file units.
    corners: Vec<[DVec3; 3]>,
    /// The normal stored with each facet (zero when absent or not finite).
    normals: Vec<DVec3>,
    /// Solid name or header text.
    name: String,
    /// Notes from the parser.
    diagnostics: Vec<Diagnostic>,
}

/// Read an STL file (ASCII or binary) into a welded mesh.
///
/// # Errors
/// [`ImportError`] naming the file (and the place, when it is in the data) when the file cannot
/// be read, is neither valid ASCII nor valid binary STL, holds a non-finite coordinate, or the
/// options are invalid.
pub fn read_stl(path: &Path, opts: &StlOptions) -> Result<StlMesh, ImportError> {
    let bytes = std::fs::read(path)
        .map_err(|e| ImportError::new(path, None, format!("cannot read file: {e}")))?;
    parse_stl(&bytes, path, opts)
}

/// Parse STL bytes (ASCII or binary) into a welded mesh; `name_for_errors` is the file name the
/// errors carry.
///
/// # Errors
/// As [`read_stl`], without the file-system part.
pub fn parse_stl(
    bytes: &[u8],
    name_for_errors: &Path,
    opts: &StlOptions,
) -> Result<StlMesh, ImportError> {
    let file = name_for_errors;
    if !(opts.unit_scale.is_finite() && opts.unit_scale > 0.0) {
        return Err(ImportError::new(
            file,
            None,
            format!("unit scale must be finite and > 0, got {}", opts.unit_scale),
        ));
    }
    if !(opts.weld_tol_mm.is_finite() && opts.weld_tol_mm >= 0.0) {
        return Err(ImportError::new(
            file,
            None,
            format!(
                "weld tolerance must be finite and >= 0 mm, got {}",
                opts.weld_tol_mm
            ),
        ));
    }
    let (raw, format) = decode(bytes, file)?;
    build_mesh(raw, format, file, opts)
}

/// Does the text start with the `solid` keyword (after an optional UTF-8 byte-order mark and
/// white space, any case)?
fn starts_with_solid(bytes: &[u8]) -> bool {
    let b = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let start = b
        .iter()
        .position(|c| !c.is_ascii_whitespace())
        .unwrap_or(b.len());
    b.get(start..start + 5)
        .is_some_and(|w| w.eq_ignore_ascii_case(b"solid"))
}

/// Pick the encoding and parse.
fn decode(bytes: &[u8], file: &Path) -> Result<(RawFacets, StlFormat), ImportError> {
    if bytes.is_empty() {
        return Err(ImportError::new(
            file,
            Some("byte 0".to_string()),
            "empty file",
        ));
    }
    if binary::expected_len(bytes) == Some(bytes.len() as u64) {
        return match binary::parse(bytes, file) {
            Ok(raw) => Ok((raw, StlFormat::Binary)),
            // An ASCII file whose length happens to fit its "count" (a huge one): try the text.
            Err(binary_err) if starts_with_solid(bytes) => match ascii::parse(bytes, file) {
                Ok(raw) => Ok((raw, StlFormat::Ascii)),
                Err(_) => Err(binary_err),
            },
            Err(binary_err) => Err(binary_err),
        };
    }
    if starts_with_solid(bytes) {
        return match ascii::parse(bytes, file) {
            Ok(raw) => Ok((raw, StlFormat::Ascii)),
            Err(ascii_err) => match binary::parse(bytes, file) {
                // A binary file whose header starts with "solid" and that has a few stray
                // bytes after its last facet.
                Ok(raw) => Ok((raw, StlFormat::Binary)),
                Err(_) => Err(with_binary_note(ascii_err, bytes)),
            },
        };
    }
    Ok((binary::parse(bytes, file)?, StlFormat::Binary))
}

/// Add to an ASCII error why the file is not binary either.
fn with_binary_note(mut err: ImportError, bytes: &[u8]) -> ImportError {
    if let (Some(expected), Some(count)) = (binary::expected_len(bytes), binary::count(bytes)) {
        err.message = format!(
            "{} (not a binary STL either: its header claims {count} facets, {expected} bytes, \
             but the file has {} bytes)",
            err.message,
            bytes.len()
        );
    }
    err
}

/// Scale, record degenerate facets, weld, compute normals, and note what is worth knowing.
fn build_mesh(
    raw: RawFacets,
    format: StlFormat,
    file: &Path,
    opts: &StlOptions,
) -> Result<StlMesh, ImportError> {
    let RawFacets {
        corners,
        normals,
        name,
        mut diagnostics,
    } = raw;
    let facet_count = corners.len();
    let Some(n) = u32::try_from(facet_count)
        .ok()
        .filter(|n| *n <= u32::MAX / 3)
    else {
        return Err(ImportError::new(
            file,
            None,
            format!("too many facets ({facet_count}) for one mesh"),
        ));
    };
    let mut positions = Vec::with_capacity(facet_count * 3);
    for (k, c) in corners.iter().enumerate() {
        for p in c {
            let q = *p * opts.unit_scale;
            if !q.is_finite() {
                return Err(ImportError::new(
                    file,
                    Some(format!("facet {k}")),
                    format!(
                        "coordinate overflows after the unit scale {}",
                        opts.unit_scale
                    ),
                ));
            }
            positions.push(q);
        }
    }
    let triangles = (0..n).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
    let mut mesh = TriMesh::new(positions, triangles);
    let degenerate_facets = mesh.degenerate_triangles(0.0);
    if facet_count > 0 && degenerate_facets.len() == facet_count {
        return Err(ImportError::new(
            file,
            Some("facet 0".into()),
            format!("all {facet_count} facets have zero area: the file holds no surface"),
        ));
    }
    if !degenerate_facets.is_empty() {
        let first: Vec<String> = degenerate_facets
            .iter()
            .take(5)
            .map(ToString::to_string)
            .collect();
        diagnostics.push(Diagnostic::warning(
            Some(format!("facet {}", first.join(", "))),
            format!("{} facets have zero area", degenerate_facets.len()),
        ));
    }
    let flipped = count_flipped_normals(&mesh, &normals);
    if flipped > 0 {
        diagnostics.push(Diagnostic::warning(
            None,
            format!("{flipped} facets store a normal opposite to their vertex winding; the winding is used"),
        ));
    }
    let before = mesh.triangles.len();
    mesh.weld(opts.weld_tol_mm);
    let dropped = before - mesh.triangles.len();
    if dropped > 0 {
        diagnostics.push(Diagnostic::info(
            None,
            format!(
                "{dropped} facets collapsed when welding vertices within {} mm and were dropped",
                opts.weld_tol_mm
            ),
        ));
    }
    let open = mesh.boundary_edges().len();
    if open > 0 {
        diagnostics.push(Diagnostic::info(
            None,
            format!("mesh is open: {open} boundary edges"),
        ));
    }
    if facet_count == 0 {
        diagnostics.push(Diagnostic::warning(None, "file holds no facets"));
    }
    mesh.compute_normals();
    Ok(StlMesh {
        mesh,
        format,
        facet_count,
        name,
        degenerate_facets,
        diagnostics,
    })
}

/// Facets whose stored (non-zero) normal points against the normal of their winding.
fn count_flipped_normals(mesh: &TriMesh, stored: &[DVec3]) -> usize {
    stored
        .iter()
        .enumerate()
        .filter(|(k, n)| {
            mesh.triangle_corners(*k)
                .is_some_and(|[a, b, c]| (b - a).cross(c - a).dot(**n) < 0.0)
        })
        .count()
}

/// A token shortened for an error message (at most 40 characters).
fn shown(token: &str) -> String {
    let mut s: String = token.chars().take(40).collect();
    if s.len() < token.len() {
        s.push('…');
    }
    s
}
