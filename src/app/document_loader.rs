//! The ONE adapter between the workstation and the engine's reader: every file the workstation
//! opens goes through [`load_part`], on a worker thread, which calls [`crate::import::open`] (the
//! reader the command line uses too) and keeps its [`Workpiece`] for planning. The rest of the
//! app sees only [`LoadedPart`] and [`LoadError`].
//!
//! For display, an STL mesh's creases are split ([`super::crease`]); the workpiece keeps the
//! mesh as read.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::crease::split_creases;
use crate::diagnostics::{Diagnostic, Progress};
use crate::geometry::mesh::TriMesh;
use crate::geometry::surface::SurfaceGeom;
use crate::import::{FileFormat, ImportError, OpenOptions, Workpiece, open, open_step_bytes};

/// Folds sharper than this are drawn as creases in meshes from STL files, rad (35°).
const STL_CREASE_ANGLE_RAD: f64 = 0.610_865_238_198_015_2;

/// One face of a loaded part, as the project tree and properties panel show it.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceSummary {
    /// Surface kind (`bspline`, `plane`, ...).
    pub kind: String,
    /// Source entity id in the file (STEP `#id`), 0 when none.
    pub source_id: u64,
    /// The carrier surface (for picking and curvature), when the part came from a B-rep.
    pub surface: Option<Arc<SurfaceGeom>>,
    /// Whether the face normal agrees with the surface's `S_u × S_v`.
    pub same_sense: bool,
}

/// A part read from a file, tessellated and ready to show.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedPart {
    /// The file it came from.
    pub path: PathBuf,
    /// Display name: the file's stem.
    pub name: String,
    /// Product name written in the file (STEP), may be empty.
    pub product_name: String,
    /// The mesh drawn when it is not the workpiece's own (an STL mesh with its creases split:
    /// the same triangles, more vertices); `None`: the workpiece's mesh is drawn, not copied.
    pub display_mesh: Option<TriMesh>,
    /// The B-rep faces (empty for a mesh file: the whole mesh is the part).
    pub faces: Vec<FaceSummary>,
    /// What the importer skipped or repaired.
    pub diagnostics: Vec<Diagnostic>,
    /// What kind of file this was (`STEP`, `STL`).
    pub format: &'static str,
    /// The engine's workpiece (the mesh as read, exact faces, one shared BVH): what operations
    /// are planned on.
    pub workpiece: Arc<Workpiece>,
    /// The machining features recognised on the B-rep (regions from +Z, holes), one line
    /// each ([`crate::features::summaries`]); empty for a mesh, and for a part of more than
    /// [`FEATURE_FACE_LIMIT`] faces (recognised on demand by `talas features`).
    pub features: Vec<crate::features::FeatureSummary>,
}

/// Parts with more faces than this are not searched for features while loading (the search
/// tessellates the part again and would add seconds to opening a large assembly).
pub const FEATURE_FACE_LIMIT: usize = 600;

impl LoadedPart {
    /// The triangles shown (mm), with per-vertex normals: [`Self::display_mesh`] or the
    /// workpiece's mesh.
    #[must_use]
    pub fn mesh(&self) -> &TriMesh {
        self.display_mesh.as_ref().unwrap_or(&self.workpiece.mesh)
    }

    /// For each triangle of [`Self::mesh`], the index into `faces` it belongs to (all 0 for a
    /// mesh file; the display mesh keeps the workpiece's triangles in order).
    #[must_use]
    pub fn face_of_triangle(&self) -> &[u32] {
        &self.workpiece.face_of_triangle
    }

    /// Summarise a workpiece for display (an STL mesh has its creases split).
    #[must_use]
    pub fn from_workpiece(workpiece: Workpiece) -> Self {
        let path = workpiece.source.clone();
        let (display_mesh, faces, product_name) = match &workpiece.part {
            Some(part) => (
                None,
                part.faces
                    .iter()
                    .zip(&workpiece.surfaces)
                    .map(|(f, surface)| FaceSummary {
                        kind: f.surface.kind().to_string(),
                        source_id: f.source_id,
                        surface: surface.clone(),
                        same_sense: f.same_sense,
                    })
                    .collect(),
                // Product names are often the exporter's ("Open CASCADE STEP translator"):
                // the file's name reads better; the product name is kept beside it.
                part.name.trim().to_string(),
            ),
            None => (
                Some(split_creases(&workpiece.mesh, STL_CREASE_ANGLE_RAD)),
                Vec::new(),
                String::new(),
            ),
        };
        let features = workpiece
            .part
            .as_deref()
            .filter(|p| p.faces.len() <= FEATURE_FACE_LIMIT)
            .map(crate::features::summaries)
            .unwrap_or_default();
        Self {
            name: file_stem(&path),
            path,
            product_name,
            display_mesh,
            faces,
            diagnostics: workpiece.diagnostics.clone(),
            format: workpiece.format.name(),
            workpiece: Arc::new(workpiece),
            features,
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
    let cancelled = |_| LoadError::Cancelled;
    progress.check().map_err(cancelled)?;
    FileFormat::of(path)?;
    progress.set(0.05);
    let workpiece = open(path, &OpenOptions::default(), progress).map_err(|e| {
        if progress.is_cancelled() {
            LoadError::Cancelled
        } else {
            LoadError::Import(e)
        }
    })?;
    progress.check().map_err(cancelled)?;
    progress.set(0.9);
    let part = LoadedPart::from_workpiece(workpiece);
    progress.set(1.0);
    Ok(part)
}

/// Where the embedded default part says it comes from (in messages and the properties panel).
pub const DEFAULT_PART_PATH: &str = "assets/bicubic-hills.stp";
/// The default part, compiled into the binary so the workstation opens on it anywhere.
const DEFAULT_PART_STEP: &[u8] = include_bytes!("../../assets/bicubic-hills.stp");

/// Read and tessellate the embedded default part (on a worker thread, like [`load_part`]).
///
/// # Errors
/// As [`load_part`] (only [`LoadError::Cancelled`] in practice: the file is tested).
pub fn load_default_part(progress: &Progress) -> Result<LoadedPart, LoadError> {
    let cancelled = |_| LoadError::Cancelled;
    progress.check().map_err(cancelled)?;
    progress.set(0.05);
    let workpiece = open_step_bytes(
        Path::new(DEFAULT_PART_PATH),
        DEFAULT_PART_STEP,
        &OpenOptions::default(),
    )?;
    progress.check().map_err(cancelled)?;
    progress.set(1.0);
    Ok(LoadedPart::from_workpiece(workpiece))
}

fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "part".to_string(), |s| s.to_string_lossy().into_owned())
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
        assert_eq!(part.mesh().triangles.len(), 4);
        // 6 distinct points; the 2 on the crease are split: 8 vertices.
        assert_eq!(part.mesh().positions.len(), 8);
        for (t, tri) in part.mesh().triangles.iter().enumerate() {
            let expected = if t < 2 {
                glam::DVec3::Z
            } else {
                glam::DVec3::X
            };
            for &v in tri {
                assert!((part.mesh().normals[v as usize].abs() - expected).length() < 1e-9);
            }
        }
    }

    #[test]
    fn a_truncated_file_is_an_error_naming_the_place() {
        let path = write_stl("short", &[[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]], 3);
        let err = load_part(&path, &Progress::new());
        let _ = std::fs::remove_file(&path);
        match err {
            Err(LoadError::Import(e)) => assert!(e.place.is_some(), "{e}"),
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
