//! Data reduction, a workstation [`Feature`](super::feature::Feature): the window's settings,
//! the background job ([`crate::reduce::reduce_part`] with progress and Cancel), the reduced
//! surface drawn in the viewport instead of the part, coloured by its signed error at the
//! Z-map's nodes (blue: below the part, white: on it, red: above), and the STL export of the
//! reduced grid.
//!
//! - [`settings`]: what a reduction is run with and what it produced;
//! - [`window`]: the window (settings, singular values, report);
//! - `feature`: its menu entry and commands, jobs, scene.

mod feature;
pub mod settings;
pub mod window;

use std::path::PathBuf;
use std::sync::Arc;

use glam::{DVec2, Mat4};

use super::command::{Command, FeatureCommand};
use super::feature::{FeatureContext, FeatureView, InsteadOfPart};
use super::job::{Job, JobSlot};
use crate::diagnostics::Severity;
use crate::import::stl::{StlFormat, save_stl};
use crate::reduce::{ExactFaces, ReduceError, reduce_part, reduce_part_xy};
use crate::render::{ColourMap, DataId, MeshData, MeshInstance, ScalarMapping};
pub use settings::{RankChoice, ReductionResult, ReductionSettings, ZmapSource};
use window::{ReductionView, reduction_window};

/// Colour of the reduced surface where no error is mapped (sRGB).
const SURFACE_COLOUR: [u8; 4] = [170, 190, 210, 255];

/// A finished reduction with its render data.
struct ShownReduction {
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

/// The data-reduction feature: its window, job and reduced surface.
#[derive(Default)]
pub struct DataReduction {
    /// The window is open.
    open: bool,
    /// The window's settings (None until the window first opens on a part).
    settings: Option<ReductionSettings>,
    job: ReductionJob,
    shown: Option<ShownReduction>,
    /// Draw the reduced surface instead of the part.
    visible: bool,
    /// The loaded part's render id (a reduction of another part is not drawn over it).
    part_id: Option<DataId>,
}

impl DataReduction {
    /// Its id in [`FeatureCommand`]s.
    pub const ID: &'static str = "reduction";

    /// Its command `action`: `"open"` (the window), `"reduce"` (with the window's settings),
    /// `"show"` / `"hide"` (the reduced surface instead of the part), `"export"` (ask where to
    /// save the STL; the path comes back as [`Command::FeatureFile`] with this id).
    #[must_use]
    pub fn command(action: &'static str) -> Command {
        Command::Feature(FeatureCommand {
            feature: Self::ID,
            action,
        })
    }

    /// Is a reduction running?
    #[must_use]
    pub fn is_running(&self) -> bool {
        self.job.is_running()
    }

    /// The latest reduction, if any.
    #[must_use]
    pub fn result(&self) -> Option<&ReductionResult> {
        self.shown.as_ref().map(|s| &s.result)
    }

    /// Is the reduced surface drawn in the viewport?
    #[must_use]
    pub fn is_visible(&self) -> bool {
        self.visible
    }

    /// Forget the reduced surface and drop a running job without a word (the window and its
    /// settings stay).
    fn forget(&mut self) {
        self.job = ReductionJob::default();
        self.shown = None;
        self.visible = false;
    }

    /// Show the reduced surface instead of the part (when there is one), or not.
    fn set_visible(&mut self, on: bool, cx: &mut FeatureContext<'_>) {
        self.visible = on && self.shown.is_some();
        if self.visible {
            cx.switch(super::feature::ViewSwitch::HideStock);
        }
    }

    fn start(&mut self, cx: &mut FeatureContext<'_>) {
        let Some(settings) = self.settings else {
            return;
        };
        let Some(doc) = cx.view.document else { return };
        let Some(bvh) = doc.bvh.clone() else {
            cx.notify(Severity::Warning, "The part has no triangles to sample");
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
        let opts = settings.options();
        let what = match settings.source {
            ZmapSource::Regular => "Z-map",
            ZmapSource::XyDependent => "XY-dependent Z-map",
        };
        let mesh = doc.part.mesh().clone();
        cx.log(
            Severity::Info,
            format!(
                "Reducing the {what} of {} at {} mm, tolerance {} mm",
                doc.part.name, settings.step_mm, settings.tolerance_mm
            ),
        );
        let job = Job::start(
            format!("Reducing the {what}"),
            cx.egui,
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
        self.job.start((part_id, settings), job);
    }

    /// Collect a finished reduction.
    fn poll_job(&mut self, cx: &mut FeatureContext<'_>) {
        self.part_id = cx.view.document.map(|d| d.ids[0]);
        let Some(done) = self.job.poll() else {
            return;
        };
        let ((part_id, settings), elapsed_s) = (done.key, done.elapsed_s);
        match done.result {
            Some(Ok(result)) => {
                cx.log(Severity::Info, finished_text(&result, elapsed_s));
                let (mesh, mapping) = error_mesh(&result, settings.tolerance_mm);
                let id = cx.next_id();
                self.shown = Some(ShownReduction {
                    part_id,
                    settings,
                    result,
                    elapsed_s,
                    id,
                    mesh: Arc::new(mesh),
                    mapping,
                });
                self.visible = true;
                cx.switch(super::feature::ViewSwitch::HideStock);
            }
            Some(Err(ReduceError::Cancelled)) => {}
            Some(Err(e)) => cx.notify(Severity::Error, format!("Reduction failed: {e}")),
            None => cx.notify(
                Severity::Error,
                "Reduction failed: the worker stopped unexpectedly",
            ),
        }
    }

    /// The reduced surface to draw instead of the part, with its legend, when visible.
    fn instead_of_part(&self) -> Option<InsteadOfPart> {
        // A reduction of another part (one opened since) is not drawn over this one.
        let s = self
            .shown
            .as_ref()
            .filter(|s| self.visible && Some(s.part_id) == self.part_id)?;
        Some(InsteadOfPart {
            mesh: MeshInstance {
                id: s.id,
                data: Arc::clone(&s.mesh),
                world_from_mesh: Mat4::IDENTITY,
                colour: SURFACE_COLOUR,
                scalar_map: Some(s.mapping),
            },
            legend: "Reduction error, model − part (mm)".to_string(),
            mapping: s.mapping,
        })
    }

    /// A file name for the reduced surface: next to the project, named after the part.
    fn export_suggestion(view: &FeatureView<'_>) -> PathBuf {
        let dir = view
            .project_path
            .and_then(|p| p.parent().map(std::path::Path::to_path_buf))
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_default();
        let name = view.document.map_or("part", |d| d.part.name.as_str());
        dir.join(format!("{name}-reduced.stl"))
    }

    fn export(&self, path: &std::path::Path, cx: &mut FeatureContext<'_>) {
        let Some(s) = &self.shown else {
            cx.notify(Severity::Warning, "Reduce the Z-map before exporting it");
            return;
        };
        let mesh = match &s.result {
            ReductionResult::Regular(r) => r.reduced_mesh(),
            ReductionResult::Xy(r) => r.reduced_mesh(),
        };
        match save_stl(path, &mesh, StlFormat::Binary) {
            Ok(()) => cx.log(
                Severity::Info,
                format!(
                    "Exported the reduced surface ({} triangles) to {}",
                    mesh.triangles.len(),
                    path.display()
                ),
            ),
            Err(e) => cx.notify(Severity::Error, format!("Not exported: {e}")),
        }
    }

    /// The data-reduction window.
    fn window(&mut self, ctx: &egui::Context, view: &FeatureView<'_>, commands: &mut Vec<Command>) {
        if !self.open {
            return;
        }
        let Some(doc) = view.document else {
            return;
        };
        let size = DVec2::new(
            doc.bounds.max.x - doc.bounds.min.x,
            doc.bounds.max.y - doc.bounds.min.y,
        );
        let part_id = doc.ids[0];
        let mut settings = self.settings.unwrap_or_else(|| {
            let ball = view
                .project
                .selected_tool()
                .filter(|t| matches!(t.cutter.kind, crate::tools::CutterKind::Ball))
                .map(|t| t.cutter.radius());
            ReductionSettings::for_part(size, ball)
        });
        let shown = ReductionView {
            part_size_mm: Some(size),
            result: self
                .shown
                .as_ref()
                .map(|s| (&s.result, &s.settings, s.elapsed_s)),
            stale: self
                .shown
                .as_ref()
                .is_some_and(|s| s.part_id != part_id || s.settings != settings),
            running: self.job.job().map(|j| j.progress.fraction()),
            visible: self.visible,
        };
        let mut open = true;
        reduction_window(ctx, &mut open, &mut settings, &shown, commands);
        self.settings = Some(settings);
        self.open = open;
    }
}

/// The log line of a finished reduction: grid, ranks, stored numbers, errors, time.
fn finished_text(result: &ReductionResult, elapsed_s: f64) -> String {
    let (kind, cols, rows, ranks) = match result {
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
    let mean = match result {
        ReductionResult::Regular(r) => r.reduction.mean_error,
        ReductionResult::Xy(r) => r.reduction.mean_error,
    };
    format!(
        "Reduced a {cols}×{rows} (X×Y) {kind}Z-map to rank {ranks} ({} numbers): max error {:.4} mm, mean {mean:.4} mm, in {elapsed_s:.2} s",
        result.stored_numbers(),
        result.max_error(),
    )
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
