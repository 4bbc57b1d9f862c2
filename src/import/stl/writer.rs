//! STL writers (binary and ASCII) and an atomic save to a file.
//!
//! Facet normals are computed from the vertex winding (zero for a zero-area triangle). Binary
//! files store `f32`, so a mesh read from a binary STL is written back bit-exactly; ASCII files
//! print each `f64` in the shortest form that reads back to the same value.

use std::io::{self, BufWriter, Write};
use std::path::Path;

use super::StlFormat;
use super::binary::HEADER_LEN;
use crate::geometry::DVec3;
use crate::geometry::mesh::TriMesh;
use crate::import::ImportError;

/// The binary header Talas writes (it must not start with `solid`).
const HEADER_TEXT: &[u8] = b"binary STL written by Talas (units: mm)";

/// Check the mesh can be written: valid indices, finite positions.
fn check(mesh: &TriMesh) -> io::Result<()> {
    mesh.validate()
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e.to_string()))
}

/// Corners and unit normal (zero when degenerate) of every triangle; `check` has run.
fn facets(mesh: &TriMesh) -> impl Iterator<Item = (DVec3, [DVec3; 3])> + '_ {
    (0..mesh.triangles.len()).filter_map(|t| {
        let c = mesh.triangle_corners(t)?;
        let n = (c[1] - c[0])
            .cross(c[2] - c[0])
            .try_normalize()
            .unwrap_or(DVec3::ZERO);
        Some((n, c))
    })
}

/// Write `mesh` as binary STL.
///
/// # Errors
/// [`io::ErrorKind::InvalidData`] for an index out of range, a non-finite position, a coordinate
/// beyond the `f32` range or more than 2³² − 1 triangles; any error of the writer.
#[allow(clippy::cast_possible_truncation)]
pub fn write_stl_binary<W: Write>(mesh: &TriMesh, w: W) -> io::Result<()> {
    check(mesh)?;
    if mesh
        .positions
        .iter()
        .any(|p| p.abs().max_element() > f64::from(f32::MAX))
    {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            "coordinate beyond the f32 range of binary STL",
        ));
    }
    let count = u32::try_from(mesh.triangles.len())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidData, "more than 2^32 - 1 triangles"))?;
    let mut w = BufWriter::new(w);
    let mut header = [b' '; HEADER_LEN];
    for (h, c) in header.iter_mut().zip(HEADER_TEXT) {
        *h = *c;
    }
    w.write_all(&header)?;
    w.write_all(&count.to_le_bytes())?;
    for (n, c) in facets(mesh) {
        let mut rec = [0_u8; 50];
        let values = [n, c[0], c[1], c[2]]
            .into_iter()
            .flat_map(|v| [v.x, v.y, v.z]);
        for (slot, x) in rec.chunks_exact_mut(4).zip(values) {
            // Positions read from binary STL are f32 values, so this cast is exact for them.
            slot.copy_from_slice(&(x as f32).to_le_bytes());
        }
        w.write_all(&rec)?;
    }
    w.flush()
}

/// `name` made safe for the `solid` line: control characters become spaces, trimmed.
fn solid_name(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect::<String>()
        .trim()
        .to_string()
}

/// Write `mesh` as ASCII STL with the solid name `name`.
///
/// # Errors
/// [`io::ErrorKind::InvalidData`] for an index out of range or a non-finite position; any error
/// of the writer.
pub fn write_stl_ascii<W: Write>(mesh: &TriMesh, name: &str, w: W) -> io::Result<()> {
    check(mesh)?;
    let name = solid_name(name);
    let mut w = BufWriter::new(w);
    writeln!(w, "solid {name}")?;
    for (n, c) in facets(mesh) {
        writeln!(w, "  facet normal {:e} {:e} {:e}", n.x, n.y, n.z)?;
        writeln!(w, "    outer loop")?;
        for p in c {
            writeln!(w, "      vertex {:e} {:e} {:e}", p.x, p.y, p.z)?;
        }
        writeln!(w, "    endloop")?;
        writeln!(w, "  endfacet")?;
    }
    writeln!(w, "endsolid {name}")?;
    w.flush()
}

/// Save `mesh` to `path` atomically: write a temporary file in the same directory, flush it to
/// disk, then rename it over `path`, so that a reader never sees a half-written file. The ASCII
/// solid name is the file stem.
///
/// # Errors
/// [`ImportError`] naming `path` when the mesh cannot be written (see [`write_stl_binary`]) or
/// the file system refuses; the temporary file is removed.
pub fn save_stl(path: &Path, mesh: &TriMesh, format: StlFormat) -> Result<(), ImportError> {
    let mut bytes = Vec::new();
    match format {
        StlFormat::Binary => write_stl_binary(mesh, &mut bytes),
        StlFormat::Ascii => {
            let stem = path
                .file_stem()
                .map(|s| s.to_string_lossy())
                .unwrap_or_default();
            write_stl_ascii(mesh, &stem, &mut bytes)
        }
    }
    .and_then(|()| crate::storage::write_atomic(path, &bytes))
    .map_err(|e| ImportError::new(path, None, format!("cannot save STL: {e}")))
}
