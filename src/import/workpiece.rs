//! The one reader of parts: [`open`] decides a file's kind (by its extension), reads it, and
//! tessellates a B-rep with one tolerance policy, giving a [`Workpiece`]: the B-rep when there
//! is one, the mesh, which face each triangle belongs to, each face's exact surface, and one
//! triangle hierarchy built on first use and shared by every caller (planning, simulation,
//! data reduction, picking). The workstation, the project pipeline and every subcommand read
//! parts here.

use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use super::ImportError;
use super::step::{read_step, read_step_bytes};
use super::stl::{StlOptions, read_stl};
use crate::diagnostics::{Diagnostic, Progress};
use crate::geometry::brep::Part;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::geometry::surface::SurfaceGeom;
use crate::geometry::tessellate::{TessellationOptions, tessellate_part};

/// The kinds of file [`open`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileFormat {
    /// ISO 10303-21 (`.stp`, `.step`): a B-rep, tessellated.
    Step,
    /// STL (`.stl`, ASCII or binary): a mesh.
    Stl,
}

impl FileFormat {
    /// The kind of `path` by its extension (case-insensitive).
    ///
    /// # Errors
    /// An [`ImportError`] naming the file when the extension is none of these.
    pub fn of(path: &Path) -> Result<Self, ImportError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("stp" | "step") => Ok(Self::Step),
            Some("stl") => Ok(Self::Stl),
            _ => Err(ImportError::new(
                path,
                None,
                "unknown file type: Talas opens .stp, .step and .stl files",
            )),
        }
    }

    /// The name shown to users (`STEP`, `STL`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Step => "STEP",
            Self::Stl => "STL",
        }
    }
}

/// How to read a part.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OpenOptions {
    /// Chord tolerance of the tessellation, mm (`None`: 1e-4 of the part's diagonal, at most
    /// 0.01 mm; see [`TessellationOptions::for_size`]).
    pub chord_tol_mm: Option<f64>,
}

/// A part read from a file: what every stage after import works on.
#[derive(Clone, Debug)]
pub struct Workpiece {
    /// The file it came from (or the name an embedded part is known by).
    pub source: PathBuf,
    /// The kind of file.
    pub format: FileFormat,
    /// The B-rep (STEP), `None` for a mesh file.
    pub part: Option<Arc<Part>>,
    /// The triangles of the whole part, mm.
    pub mesh: TriMesh,
    /// For each triangle of `mesh`, the index of the face it belongs to (all 0 for a mesh file).
    pub face_of_triangle: Vec<u32>,
    /// The exact surface of each face, in the part's face order (empty for a mesh file).
    pub surfaces: Vec<Option<Arc<SurfaceGeom>>>,
    /// What the reader and the tessellator skipped or repaired.
    pub diagnostics: Vec<Diagnostic>,
    bvh: OnceLock<Result<Arc<MeshBvh>, String>>,
}

impl PartialEq for Workpiece {
    fn eq(&self, other: &Self) -> bool {
        self.source == other.source
            && self.format == other.format
            && self.mesh == other.mesh
            && self.face_of_triangle == other.face_of_triangle
    }
}

impl Workpiece {
    /// A workpiece of a mesh alone (no faces, no exact surfaces).
    #[must_use]
    pub fn from_mesh(source: &Path, mesh: TriMesh, diagnostics: Vec<Diagnostic>) -> Self {
        Self {
            source: source.to_path_buf(),
            format: FileFormat::Stl,
            part: None,
            face_of_triangle: vec![0; mesh.triangles.len()],
            mesh,
            surfaces: Vec::new(),
            diagnostics,
            bvh: OnceLock::new(),
        }
    }

    /// A workpiece of a B-rep tessellated with `options`.
    #[must_use]
    pub fn from_part(source: &Path, part: Part, options: &OpenOptions) -> Self {
        let tessellation = tessellate_part(&part, &tessellation_options(&part, options));
        let mut diagnostics = part.diagnostics.clone();
        diagnostics.extend(tessellation.diagnostics);
        Self {
            source: source.to_path_buf(),
            format: FileFormat::Step,
            surfaces: part
                .faces
                .iter()
                .map(|f| Some(Arc::new(f.surface.clone())))
                .collect(),
            part: Some(Arc::new(part)),
            mesh: tessellation.mesh,
            face_of_triangle: tessellation.face_of_triangle,
            diagnostics,
            bvh: OnceLock::new(),
        }
    }

    /// The triangle hierarchy of [`Workpiece::mesh`], built on the first call and shared.
    ///
    /// # Errors
    /// Why none can be built (no triangle of non-zero area), naming the file.
    pub fn bvh(&self) -> Result<Arc<MeshBvh>, String> {
        self.bvh
            .get_or_init(|| {
                // Every planner on the mesh sizes its grids and passes by the part's box: a
                // part reaching beyond ±10 m (one vertex of a cube at 10¹⁵ mm) is refused
                // here, before a pass count or an allocation follows from it (issue 36).
                let far = crate::units::MAX_COORDINATE_MM;
                let b = self.mesh.bbox();
                if !self.mesh.positions.is_empty()
                    && (b.min.abs().max_element() > far || b.max.abs().max_element() > far)
                {
                    return Err(format!(
                        "{}: the part reaches beyond ±{far} mm (its box {:?} to {:?} mm); \
                         machining plans only parts within that",
                        self.source.display(),
                        b.min.to_array().map(crate::units::short),
                        b.max.to_array().map(crate::units::short),
                    ));
                }
                MeshBvh::new(&self.mesh)
                    .map(Arc::new)
                    .map_err(|e| format!("{}: {e}", self.source.display()))
            })
            .clone()
    }

    /// The exact surface of face `index`, when it has one.
    #[must_use]
    pub fn surface(&self, index: usize) -> Option<&Arc<SurfaceGeom>> {
        self.surfaces.get(index)?.as_ref()
    }
}

fn tessellation_options(part: &Part, options: &OpenOptions) -> TessellationOptions {
    match options.chord_tol_mm {
        Some(t) if t.is_finite() && t > 0.0 => TessellationOptions::with_chord_tol(t),
        _ => TessellationOptions::for_size(part.rough_bbox().diagonal()),
    }
}

/// Read the part in `path` (STEP or STL, by extension) and tessellate a B-rep. Stops early
/// (with an error saying so) when `progress` is cancelled.
///
/// # Errors
/// An [`ImportError`] naming the file and the place for an unknown kind, an unreadable or
/// malformed file, or a cancel.
pub fn open(
    path: &Path,
    options: &OpenOptions,
    progress: &Progress,
) -> Result<Workpiece, ImportError> {
    let cancelled = |_| ImportError::new(path, None, "cancelled");
    progress.check().map_err(cancelled)?;
    match FileFormat::of(path)? {
        FileFormat::Step => {
            let part = read_step(path)?;
            progress.check().map_err(cancelled)?;
            progress.set(0.5);
            Ok(Workpiece::from_part(path, part, options))
        }
        FileFormat::Stl => {
            let stl = read_stl(path, &StlOptions::default())?;
            Ok(Workpiece::from_mesh(path, stl.mesh, stl.diagnostics))
        }
    }
}

/// Read a STEP part from `bytes` (an embedded part; `name` only names it in messages).
///
/// # Errors
/// As [`open`].
pub fn open_step_bytes(
    name: &Path,
    bytes: &[u8],
    options: &OpenOptions,
) -> Result<Workpiece, ImportError> {
    Ok(Workpiece::from_part(
        name,
        read_step_bytes(name, bytes)?,
        options,
    ))
}
