//! The ONE adapter between the workstation and the engine's importers: every file the workstation
//! opens goes through [`load_part`], on a worker thread. The rest of the app sees only
//! [`LoadedPart`] and [`LoadError`].
//!
//! REPLACE WHEN THE ENGINE LANDS (one place):
//! - STEP: in [`load_step`], call `talas::import::step::read_step(path)` and
//!   `talas::geometry::tessellate::tessellate_part(&part, &TessellationOptions::default())`,
//!   then return `Ok(LoadedPart::from_part(path, &part, part_mesh.mesh, part_mesh.face_of_triangle))`.
//! - STL: replace [`interim_stl`] with the engine's STL reader (`talas::import::stl`).

use std::path::{Path, PathBuf};

use crate::diagnostics::{Diagnostic, Progress};
use crate::geometry::brep::Part;
use crate::geometry::mesh::TriMesh;
use crate::import::ImportError;

/// One face of a loaded part, as the project tree and properties panel show it.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceSummary {
    /// Surface kind (`bspline`, `plane`, ...).
    pub kind: String,
    /// Source entity id in the file (STEP `#id`), 0 when none.
    pub source_id: u64,
}

/// A part read from a file, tessellated and ready to show.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedPart {
    /// The file it came from.
    pub path: PathBuf,
    /// Name from the file, else the file stem.
    pub name: String,
    /// The triangles (mm), with per-vertex normals.
    pub mesh: TriMesh,
    /// For each triangle of `mesh`, the index into `faces` it belongs to.
    pub face_of_triangle: Vec<u32>,
    /// The B-rep faces (empty for a mesh file: the whole mesh is the part).
    pub faces: Vec<FaceSummary>,
    /// What the importer skipped or repaired.
    pub diagnostics: Vec<Diagnostic>,
    /// What kind of file this was (`STEP`, `STL`).
    pub format: &'static str,
}

impl LoadedPart {
    /// Summarise an imported B-rep part and its tessellation.
    #[must_use]
    pub fn from_part(path: &Path, part: &Part, mesh: TriMesh, face_of_triangle: Vec<u32>) -> Self {
        let faces = part
            .faces
            .iter()
            .map(|f| FaceSummary {
                kind: f.surface.kind().to_string(),
                source_id: f.source_id,
            })
            .collect();
        Self {
            path: path.to_path_buf(),
            name: if part.name.trim().is_empty() {
                file_stem(path)
            } else {
                part.name.clone()
            },
            mesh,
            face_of_triangle,
            faces,
            diagnostics: part.diagnostics.clone(),
            format: "STEP",
        }
    }
}

/// Why a file could not be opened.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LoadError {
    /// The importer rejected the file (names the file and the place).
    #[error(transparent)]
    Import(#[from] ImportError),
    /// The user cancelled.
    #[error("cancelled")]
    Cancelled,
}

/// Read the part at `path` (STEP or STL, by extension) and tessellate it. Runs on a worker
/// thread; reports progress and stops early when `progress` is cancelled.
///
/// # Errors
/// [`LoadError::Import`] for unreadable or malformed files, [`LoadError::Cancelled`] on cancel.
pub fn load_part(path: &Path, progress: &Progress) -> Result<LoadedPart, LoadError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("stp" | "step") => load_step(path, progress),
        Some("stl") => {
            let mesh = interim_stl::read(path, progress)?;
            let triangles = mesh.triangles.len();
            Ok(LoadedPart {
                path: path.to_path_buf(),
                name: file_stem(path),
                mesh,
                face_of_triangle: vec![0; triangles],
                faces: Vec::new(),
                diagnostics: Vec::new(),
                format: "STL",
            })
        }
        _ => Err(ImportError::new(
            path,
            None,
            "unknown file type: Talas opens .stp, .step and .stl files",
        )
        .into()),
    }
}

/// STEP: waits for the engine's reader and tessellator (see the module docs for the two calls).
fn load_step(path: &Path, progress: &Progress) -> Result<LoadedPart, LoadError> {
    progress.check().map_err(|_| LoadError::Cancelled)?;
    if !path.is_file() {
        return Err(ImportError::new(path, None, "file not found").into());
    }
    Err(ImportError::new(
        path,
        None,
        "STEP import is not wired into this build yet (document_loader::load_step)",
    )
    .into())
}

fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "part".to_string(), |s| s.to_string_lossy().into_owned())
}

/// INTERIM, FOR REPLACEMENT by the engine's STL reader: a minimal binary STL reader so the
/// workstation can be exercised before the importers land. Welds identical vertices and gives
/// smooth normals that keep creases sharper than 35°.
mod interim_stl {
    use std::collections::HashMap;
    use std::path::Path;

    use glam::DVec3;

    use crate::diagnostics::Progress;
    use crate::geometry::mesh::TriMesh;
    use crate::import::ImportError;

    use super::LoadError;

    const HEADER_BYTES: usize = 84;
    const FACET_BYTES: usize = 50;

    /// Read a binary STL file.
    pub fn read(path: &Path, progress: &Progress) -> Result<TriMesh, LoadError> {
        let bytes = std::fs::read(path).map_err(|e| ImportError::new(path, None, e.to_string()))?;
        if bytes.starts_with(b"solid") && bytes.windows(5).take(1024).any(|w| w == b"facet") {
            return Err(ImportError::new(
                path,
                None,
                "ASCII STL is not read by the interim reader; save as binary STL",
            )
            .into());
        }
        let count_bytes: [u8; 4] = bytes
            .get(80..84)
            .and_then(|b| b.try_into().ok())
            .ok_or_else(|| {
                ImportError::new(
                    path,
                    Some("byte 80".into()),
                    "file too short for a binary STL header",
                )
            })?;
        let count = u32::from_le_bytes(count_bytes) as usize;
        let expected = count
            .checked_mul(FACET_BYTES)
            .and_then(|n| n.checked_add(HEADER_BYTES));
        if expected != Some(bytes.len()) {
            return Err(ImportError::new(
                path,
                Some("byte 80".into()),
                format!(
                    "header says {count} facets but the file has {} bytes",
                    bytes.len()
                ),
            )
            .into());
        }
        let mut welded: HashMap<[u32; 3], u32> = HashMap::new();
        let mut points: Vec<DVec3> = Vec::new();
        let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(count);
        for (i, facet) in bytes[HEADER_BYTES..].chunks_exact(FACET_BYTES).enumerate() {
            if i % 65_536 == 0 {
                progress.check().map_err(|_| LoadError::Cancelled)?;
                progress.set(0.8 * i as f64 / count.max(1) as f64);
            }
            let mut corner = [0_u32; 3];
            for (k, c) in corner.iter_mut().enumerate() {
                let at = 12 + 12 * k;
                let f = |j: usize| {
                    let b = [
                        facet[at + 4 * j],
                        facet[at + 4 * j + 1],
                        facet[at + 4 * j + 2],
                        facet[at + 4 * j + 3],
                    ];
                    f32::from_le_bytes(b)
                };
                let p = [f(0), f(1), f(2)];
                if p.iter().any(|v| !v.is_finite()) {
                    return Err(ImportError::new(
                        path,
                        Some(format!("facet {i}")),
                        "non-finite vertex coordinate",
                    )
                    .into());
                }
                let key = p.map(|v| (v + 0.0).to_bits());
                let next = u32::try_from(points.len()).unwrap_or(u32::MAX);
                *c = *welded.entry(key).or_insert_with(|| {
                    points.push(DVec3::new(
                        f64::from(p[0]),
                        f64::from(p[1]),
                        f64::from(p[2]),
                    ));
                    next
                });
            }
            if corner[0] != corner[1] && corner[1] != corner[2] && corner[0] != corner[2] {
                triangles.push(corner);
            }
        }
        progress.set(0.85);
        Ok(crease_normals(&points, &triangles))
    }

    /// Split vertices where the surface folds by more than 35° and give each copy the
    /// area-weighted normal of the triangles on its side.
    fn crease_normals(points: &[DVec3], triangles: &[[u32; 3]]) -> TriMesh {
        let cos_crease = 35.0_f64.to_radians().cos();
        let face_normal: Vec<DVec3> = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| points[i as usize]);
                (b - a).cross(c - a)
            })
            .collect();
        let mut incident: Vec<Vec<u32>> = vec![Vec::new(); points.len()];
        for (t, tri) in triangles.iter().enumerate() {
            for &v in tri {
                incident[v as usize].push(u32::try_from(t).unwrap_or(u32::MAX));
            }
        }
        let mut mesh = TriMesh::default();
        let mut copies: HashMap<(u32, [u64; 3]), u32> = HashMap::new();
        for (t, tri) in triangles.iter().enumerate() {
            let own = face_normal[t].normalize_or_zero();
            let mut out = [0_u32; 3];
            for (k, &v) in tri.iter().enumerate() {
                let n = incident[v as usize]
                    .iter()
                    .map(|&o| face_normal[o as usize])
                    .filter(|n| n.normalize_or_zero().dot(own) >= cos_crease)
                    .sum::<DVec3>()
                    .normalize_or(own);
                let key = (v, n.to_array().map(|x| ((x * 1e4).round() as i64) as u64));
                let next = u32::try_from(mesh.positions.len()).unwrap_or(u32::MAX);
                out[k] = *copies.entry(key).or_insert_with(|| {
                    mesh.positions.push(points[v as usize]);
                    mesh.normals.push(n);
                    next
                });
            }
            mesh.triangles.push(out);
        }
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write_stl(name: &str, triangles: &[[[f32; 3]; 3]], claimed: u32) -> PathBuf {
        let mut bytes = vec![0_u8; 80];
        bytes.extend_from_slice(&claimed.to_le_bytes());
        for t in triangles {
            bytes.extend_from_slice(&[0; 12]);
            for p in t {
                for v in p {
                    bytes.extend_from_slice(&v.to_le_bytes());
                }
            }
            bytes.extend_from_slice(&[0; 2]);
        }
        let path =
            std::env::temp_dir().join(format!("talas-loader-{}-{name}.stl", std::process::id()));
        let _ = std::fs::write(&path, bytes);
        path
    }

    #[test]
    fn a_cube_corner_keeps_its_crease() {
        // Two triangles of the z = 0 square and two of the x = 0 wall, meeting at 90°.
        let tris = [
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 1.0]],
            [[0.0, 0.0, 0.0], [0.0, 1.0, 1.0], [0.0, 0.0, 1.0]],
        ];
        let path = write_stl("corner", &tris, 4);
        let part = load_part(&path, &Progress::new());
        let _ = std::fs::remove_file(&path);
        let part = part.expect("valid STL");
        assert_eq!(part.mesh.triangles.len(), 4);
        // 6 distinct points; the 2 on the crease are split: 8 vertices.
        assert_eq!(part.mesh.positions.len(), 8);
        for (t, tri) in part.mesh.triangles.iter().enumerate() {
            let expected = if t < 2 {
                glam::DVec3::Z
            } else {
                glam::DVec3::X
            };
            for &v in tri {
                assert!((part.mesh.normals[v as usize].abs() - expected).length() < 1e-9);
            }
        }
    }

    #[test]
    fn a_truncated_file_is_an_error_naming_the_place() {
        let path = write_stl("short", &[[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]], 3);
        let err = load_part(&path, &Progress::new());
        let _ = std::fs::remove_file(&path);
        match err {
            Err(LoadError::Import(e)) => {
                assert_eq!(e.place.as_deref(), Some("byte 80"));
                assert!(e.message.contains("3 facets"));
            }
            other => panic!("expected an import error, got {other:?}"),
        }
    }

    #[test]
    fn unknown_extensions_and_missing_files_are_errors() {
        assert!(matches!(
            load_part(Path::new("/nonexistent/x.obj"), &Progress::new()),
            Err(LoadError::Import(_))
        ));
        assert!(matches!(
            load_part(Path::new("/nonexistent/x.stl"), &Progress::new()),
            Err(LoadError::Import(_))
        ));
        assert!(matches!(
            load_part(Path::new("/nonexistent/x.stp"), &Progress::new()),
            Err(LoadError::Import(_))
        ));
    }

    #[test]
    fn cancelling_stops_the_load() {
        let path = write_stl("cancel", &[[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]], 1);
        let progress = Progress::new();
        progress.cancel();
        let r = load_part(&path, &progress);
        let _ = std::fs::remove_file(&path);
        assert_eq!(r.err(), Some(LoadError::Cancelled));
    }
}
