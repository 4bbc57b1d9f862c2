//! The data-reduction view's state: the window's settings, the background job
//! ([`crate::reduce::reduce_part`] with progress and Cancel), the reduced surface drawn in the
//! viewport coloured by its signed error at the Z-map's nodes (blue: below the part, white:
//! on it, red: above), and the STL export of the reduced grid.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{DVec2, Mat4};

use super::super::command::Command;
use super::super::job::{Job, JobSlot};
use super::super::panels::reduction_view::{ReductionView, reduction_window};
use super::super::state::{ReductionResult, ReductionSettings, ZmapSource};
use super::Workstation;
use crate::diagnostics::Severity;
use crate::import::stl::{StlFormat, save_stl};
use crate::reduce::{ExactFaces, ReduceError, reduce_part, reduce_part_xy};
use crate::render::{ColourMap, DataId, MeshData, MeshInstance, ScalarMapping};

/// Colour of the reduced surface where no error is mapped (sRGB).
const SURFACE_COLOUR: [u8; 4] = [170, 190, 210, 255];

/// A finished reduction with its render data.
pub(super) struct ShownReduction {
    /// The part it was made from.
    part_id: DataId,
    settings: ReductionSettings,
    result: ReductionResult,
    elapsed_s: f64,
    id: DataId,
    mesh: Arc<MeshData>,
    mapping: ScalarMapping,
}

/// A running reduction, keyed by the part and settings it was started with.
type ReductionJob = JobSlot<Result<ReductionResult, ReduceError>, (DataId, ReductionSettings)>;

/// The data-reduction state of the workstation.
#[derive(Default)]
pub(super) struct Reductions {
    /// The window is open.
    pub open: bool,
    /// The window's settings (None until the window first opens on a part).
    settings: Option<ReductionSettings>,
    pub(super) job: ReductionJob,
    shown: Option<ShownReduction>,
    /// Draw the reduced surface instead of the part.
    pub visible: bool,
}

impl Reductions {
    /// Forget the reduced surface (the window and its settings stay).
    pub fn forget_result(&mut self) {
        self.shown = None;
        self.visible = false;
    }
}

impl Workstation {
    /// Act on a data-reduction command.
    pub(super) fn apply_reduction(&mut self, command: Command) {
        match command {
            Command::OpenReductionView => self.reductions.open = true,
            Command::Reduce(settings) => self.start_reduction(settings),
            Command::SetReductionVisible(on) => {
                self.reductions.visible = on && self.reductions.shown.is_some();
                if self.reductions.visible {
                    self.sims.visible = false;
                }
            }
            Command::ExportReductionDialog => {
                self.save_dialog_for(super::super::file_dialog::SavePurpose::ReducedStl);
            }
            Command::ExportReductionTo(path) => self.export_reduction(path),
            _ => {}
        }
    }

    fn start_reduction(&mut self, settings: ReductionSettings) {
        let Some(doc) = &self.document else { return };
        let Some(bvh) = doc.bvh.clone() else {
            let t = self.now_s();
            self.log
                .notify(t, Severity::Warning, "The part has no triangles to sample");
            return;
        };
        let part_id = doc.ids[0];
        let exact = doc
            .part
            .faces
            .iter()
            .any(|f| f.surface.is_some())
            .then(|| ExactFaces {
                face_of_triangle: doc.part.face_of_triangle().to_vec(),
                surfaces: doc.part.faces.iter().map(|f| f.surface.clone()).collect(),
            });
        self.reductions.settings = Some(settings);
        let opts = settings.options();
        let what = match settings.source {
            ZmapSource::Regular => "Z-map",
            ZmapSource::XyDependent => "XY-dependent Z-map",
        };
        let mesh = doc.part.mesh().clone();
        let message = format!(
            "Reducing the {what} of {} at {} mm, tolerance {} mm",
            doc.part.name, settings.step_mm, settings.tolerance_mm
        );
        self.log_info(message);
        let job = Job::start(
            format!("Reducing the {what}"),
            &self.run.ctx,
            move |progress| match settings.source {
                ZmapSource::Regular => {
                    reduce_part(&bvh, exact.as_ref(), settings.step_mm, &opts, progress)
                        .map(|r| ReductionResult::Regular(Box::new(r)))
                }
                ZmapSource::XyDependent => {
                    reduce_part_xy(&mesh, &bvh, settings.step_mm, &opts, progress)
                        .map(|r| ReductionResult::Xy(Box::new(r)))
                }
            },
        );
        self.reductions.job.start((part_id, settings), job);
    }

    /// Is a reduction running?
    #[must_use]
    pub fn is_reducing(&self) -> bool {
        self.reductions.job.is_running()
    }

    /// The latest reduction, if any.
    #[must_use]
    pub fn reduction(&self) -> Option<&ReductionResult> {
        self.reductions.shown.as_ref().map(|s| &s.result)
    }

    /// Is the reduced surface drawn in the viewport?
    #[must_use]
    pub fn reduction_visible(&self) -> bool {
        self.reductions.visible
    }

    /// Collect a finished reduction.
    pub(super) fn poll_reduction_job(&mut self) {
        let Some(done) = self.reductions.job.poll() else {
            return;
        };
        let ((part_id, settings), elapsed_s) = (done.key, done.elapsed_s);
        let t = self.now_s();
        match done.result {
            Some(Ok(result)) => {
                let (kind, cols, rows, ranks) = match &result {
                    ReductionResult::Regular(r) => (
                        "",
                        r.zmap.grid.cols(),
                        r.zmap.grid.rows(),
                        r.reduction.rank.to_string(),
                    ),
                    ReductionResult::Xy(r) => (
                        "XY-dependent ",
                        r.map.z.cols(),
                        r.map.z.rows(),
                        format!(
                            "X {} Y {} Z {}",
                            r.reduction.x.rank, r.reduction.y.rank, r.reduction.z.rank
                        ),
                    ),
                };
                let mean = match &result {
                    ReductionResult::Regular(r) => r.reduction.mean_error,
                    ReductionResult::Xy(r) => r.reduction.mean_error,
                };
                self.log.push(
                    t,
                    Severity::Info,
                    format!(
                        "Reduced a {cols}×{rows} (X×Y) {kind}Z-map to rank {ranks} ({} numbers): max error {:.4} mm, mean {mean:.4} mm, in {elapsed_s:.2} s",
                        result.stored_numbers(),
                        result.max_error(),
                    ),
                );
                let (mesh, mapping) = error_mesh(&result, settings.tolerance_mm);
                self.ops.next_id += 1;
                let id = self.ops.next_id;
                self.reductions.shown = Some(ShownReduction {
                    part_id,
                    settings,
                    result,
                    elapsed_s,
                    id,
                    mesh: Arc::new(mesh),
                    mapping,
                });
                self.reductions.visible = true;
                self.sims.visible = false;
            }
            Some(Err(ReduceError::Cancelled)) => {}
            Some(Err(e)) => self
                .log
                .notify(t, Severity::Error, format!("Reduction failed: {e}")),
            None => self.log.notify(
                t,
                Severity::Error,
                "Reduction failed: the worker stopped unexpectedly",
            ),
        }
    }

    /// The reduced surface to draw instead of the part, and its legend, when visible.
    pub(super) fn reduction_instance(&self) -> Option<(MeshInstance, ScalarMapping)> {
        let part_id = self.document.as_ref()?.ids[0];
        // A reduction of another part (one opened since) is not drawn over this one.
        let s = self
            .reductions
            .shown
            .as_ref()
            .filter(|s| self.reductions.visible && s.part_id == part_id)?;
        Some((
            MeshInstance {
                id: s.id,
                data: Arc::clone(&s.mesh),
                world_from_mesh: Mat4::IDENTITY,
                colour: SURFACE_COLOUR,
                scalar_map: Some(s.mapping),
            },
            s.mapping,
        ))
    }

    /// A file name for the reduced surface: next to the project, named after the part.
    pub(super) fn reduction_suggestion(&self) -> PathBuf {
        let dir = self
            .saved
            .session
            .path
            .as_ref()
            .and_then(|p| p.parent().map(std::path::Path::to_path_buf))
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_default();
        let name = self
            .document
            .as_ref()
            .map_or("part", |d| d.part.name.as_str());
        dir.join(format!("{name}-reduced.stl"))
    }

    fn export_reduction(&mut self, path: PathBuf) {
        let t = self.now_s();
        let Some(s) = &self.reductions.shown else {
            self.log
                .notify(t, Severity::Warning, "Reduce the Z-map before exporting it");
            return;
        };
        let mesh = match &s.result {
            ReductionResult::Regular(r) => r.reduced_mesh(),
            ReductionResult::Xy(r) => r.reduced_mesh(),
        };
        match save_stl(&path, &mesh, StlFormat::Binary) {
            Ok(()) => self.log.push(
                t,
                Severity::Info,
                format!(
                    "Exported the reduced surface ({} triangles) to {}",
                    mesh.triangles.len(),
                    path.display()
                ),
            ),
            Err(e) => self
                .log
                .notify(t, Severity::Error, format!("Not exported: {e}")),
        }
    }

    /// The data-reduction window.
    pub(super) fn reduction_ui(&mut self, ctx: &egui::Context, commands: &mut Vec<Command>) {
        if !self.reductions.open {
            return;
        }
        let Some(doc) = &self.document else {
            return;
        };
        let size = DVec2::new(
            doc.bounds.max.x - doc.bounds.min.x,
            doc.bounds.max.y - doc.bounds.min.y,
        );
        let part_id = doc.ids[0];
        let mut settings = self.reductions.settings.unwrap_or_else(|| {
            let ball = self
                .saved
                .session
                .project
                .selected_tool()
                .filter(|t| matches!(t.cutter.kind, crate::tools::CutterKind::Ball))
                .map(|t| t.cutter.radius());
            ReductionSettings::for_part(size, ball)
        });
        let view = ReductionView {
            part_size_mm: Some(size),
            result: self
                .reductions
                .shown
                .as_ref()
                .map(|s| (&s.result, &s.settings, s.elapsed_s)),
            stale: self
                .reductions
                .shown
                .as_ref()
                .is_some_and(|s| s.part_id != part_id || s.settings != settings),
            running: self.reductions.job.job().map(|j| j.progress.fraction()),
            visible: self.reductions.visible,
        };
        let mut open = true;
        reduction_window(ctx, &mut open, &mut settings, &view, commands);
        self.reductions.settings = Some(settings);
        self.reductions.open = open;
    }
}

/// The reduced surface at the Z-map's nodes with its signed error as the scalar (a regular
/// Z-map), or the original XY-dependent Z-map with the reduced surface's vertical distance above
/// each node (nodes outside it: 0), mapped symmetrically about zero over ± the tolerance: white
/// is on the part, full blue or red is at or beyond the tolerance (below or above the part).
fn error_mesh(r: &ReductionResult, tolerance_mm: f64) -> (MeshData, ScalarMapping) {
    let (mut mesh, scalars): (_, Vec<f32>) = match r {
        ReductionResult::Regular(r) => (
            r.approximation_mesh(),
            r.signed_error.values().iter().map(|&d| d as f32).collect(),
        ),
        ReductionResult::Xy(r) => (
            r.original_mesh(),
            r.signed_error
                .iter()
                .map(|d| d.unwrap_or(0.0) as f32)
                .collect(),
        ),
    };
    let f = |v: glam::DVec3| [v.x as f32, v.y as f32, v.z as f32];
    mesh.compute_normals();
    let range = tolerance_mm.max(1e-6) as f32;
    (
        MeshData {
            positions: mesh.positions.iter().map(|&p| f(p)).collect(),
            normals: mesh.normals.iter().map(|&n| f(n)).collect(),
            scalars,
            indices: mesh.triangles.iter().flatten().copied().collect(),
        },
        ScalarMapping {
            map: ColourMap::CoolWarm,
            min: -range,
            max: range,
        },
    )
}
