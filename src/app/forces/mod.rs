//! The cutting-forces window: for the active operation's computed path, a background job
//! (progress, Cancel) runs [`crate::project::forces::operation_forces`] on the project's stock
//! as the earlier operations leave it, at the project's spindle speed and — when the posted
//! program is current — on the run's planned clock. The result is plotted against time
//! ([`plot`]): F_x, F_y, F_z and the resultant (N), the torque (N·m) or the cutting power (W),
//! peak or mean per revolution, with the tool's and the spindle's limits as dashed lines and a
//! cursor at the pose the tool stands at; clicking the plot picks the pose cut then. The
//! coefficient library (TOML in the data folder, the built-in Al7075-T651 calibration until
//! edited) is edited in [`library_editor`]. With "Colour the path" the viewport draws the path
//! coloured by the plotted quantity per move, with a legend in its unit and the limit marked
//! ([`colour`]); for the pose the tool stands at, the tool's deflection and the wall error
//! along the depth are plotted ([`deflection_panel`]); "Schedule feeds" rewrites the feeds for
//! a target peak force and can apply the scheduled path to the operation ([`schedule_panel`]).
//! The window is a workstation [`crate::app::feature::Feature`] ([`feature`]): Machining →
//! "Cutting forces…" opens it, and its jobs show in the status bar.

pub mod colour;
pub mod deflection_panel;
pub mod feature;
pub mod library_editor;
pub mod plot;
pub mod schedule_panel;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::command::Command;
use super::feature::FeatureView;
use super::job::{Job, JobSlot};
use crate::force::library::Library;
use crate::force::path::Limits;
use crate::machine::Machine;
use crate::project::Operation;
use crate::project::forces::{ForceRunError, ForceRunInput, ForceTimeline, operation_forces};

use crate::toolpath::Toolpath;
use crate::tools::Cutter;

/// The built-in coefficient library (Al7075-T651, calibrated on the thesis's Table 8.4).
pub const DEFAULT_COEFFICIENTS_TOML: &str = include_str!("../../../assets/force/coefficients.toml");

/// The coefficient library's file name in the data folder.
pub const COEFFICIENTS_FILE_NAME: &str = "force-coefficients.toml";

/// Most Z rays of the force stock by default (sets its resolution).
pub const DEFAULT_MAX_RAYS: f64 = 300_000.0;

/// The coefficient library file in `data_dir`.
#[must_use]
pub fn coefficients_path(data_dir: &Path) -> PathBuf {
    data_dir.join(COEFFICIENTS_FILE_NAME)
}

/// The library text in `data_dir` (the built-in one when there is no file).
///
/// # Errors
/// The read error, naming the file.
pub fn library_text(data_dir: &Path) -> Result<String, String> {
    let path = coefficients_path(data_dir);
    match std::fs::read_to_string(&path) {
        Ok(t) => Ok(t),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            Ok(DEFAULT_COEFFICIENTS_TOML.to_string())
        }
        Err(e) => Err(format!("{}: {e}", path.display())),
    }
}

/// What a force result was computed for (it is current while these are unchanged).
#[derive(Clone, Debug, PartialEq)]
struct ForceKey {
    index: usize,
    operation: Operation,
    cutter: Cutter,
    planned: bool,
}

/// A computed force result with what it was computed from.
pub struct Outcome {
    /// The forces and their timeline.
    pub timeline: ForceTimeline,
    /// The path they were computed along.
    pub toolpath: Arc<Toolpath>,
    /// The tool.
    pub cutter: Cutter,
    /// The coefficients used.
    pub coefficients: crate::force::path::ModeCoefficients,
}

type ForceJob = JobSlot<Result<Outcome, ForceRunError>, ForceKey>;

/// The profile of the tool's deflection at a pose: (result serial, pose) and the profile.
type DeflectionCache = (
    (u64, usize),
    Result<Option<crate::project::forces::PoseDeflection>, String>,
);

/// What the plot shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Shown {
    /// F_x, F_y, F_z and the resultant, N.
    #[default]
    Force,
    /// Cutting torque, N·m.
    Torque,
    /// Cutting power, W.
    Power,
}

/// The cutting-forces window.
#[derive(Default)]
pub struct ForcesWindow {
    /// Whether the window is shown.
    pub open: bool,
    job: ForceJob,
    result: Option<(ForceKey, Arc<Outcome>)>,
    /// Serial number of the current result (bumped per result).
    serial: u64,
    /// Is the result computed for the operation, tool and clock as they are now?
    current: bool,
    /// Draw the path coloured by the plotted quantity.
    pub colour_path: bool,
    /// The coloured path as last built.
    coloured: Option<colour::ColouredPath>,
    /// The deflection profile at the tool's pose.
    deflection: Option<DeflectionCache>,
    /// Show the deflection profile.
    pub show_deflection: bool,
    /// Feed scheduling.
    pub schedule: schedule_panel::SchedulePanel,
    /// The last problem (shown in the window).
    pub message: Option<String>,
    /// What the plot shows.
    pub shown: Shown,
    /// Plot the mean per revolution instead of the peak.
    pub mean: bool,
    /// The coefficient library editor.
    pub editor: library_editor::LibraryEditor,
    /// The plot's screen transform as last drawn (time ↔ screen x).
    pub plot_transform: Option<egui_plot::PlotTransform>,
    /// Most Z rays of the stock the forces read (`None`: [`DEFAULT_MAX_RAYS`]); fewer is
    /// coarser and faster.
    pub max_rays: Option<f64>,
}

fn key_of(view: &FeatureView<'_>, index: usize) -> Option<ForceKey> {
    let project = view.project;
    let operation = project.operations.get(index)?.clone();
    let cutter = project.tools.get(operation.tool())?.cutter.clone();
    Some(ForceKey {
        index,
        operation,
        cutter,
        planned: view.results.planned_clock(index).is_some(),
    })
}

impl ForcesWindow {
    /// The finished result, when there is one.
    #[must_use]
    pub fn result(&self) -> Option<&ForceTimeline> {
        self.result.as_ref().map(|(_, r)| &r.timeline)
    }

    /// The finished result with the path, tool and coefficients it was computed from.
    #[must_use]
    pub fn outcome(&self) -> Option<&Arc<Outcome>> {
        self.result.as_ref().map(|(_, r)| r)
    }

    /// The coloured path as last built (while "Colour the path" is on).
    #[must_use]
    pub fn coloured_path(&self) -> Option<&colour::ColouredPath> {
        self.coloured
            .as_ref()
            .filter(|_| self.colour_path && self.current)
    }

    /// The deflection profile last computed: the pose and the profile.
    #[must_use]
    pub fn deflection(
        &self,
    ) -> Option<(
        usize,
        &Result<Option<crate::project::forces::PoseDeflection>, String>,
    )> {
        self.deflection.as_ref().map(|((_, p), d)| (*p, d))
    }

    /// Is a force job running?
    #[must_use]
    pub fn is_running(&self) -> bool {
        self.job.is_running()
    }

    /// Stop the running job; its label when there was one.
    pub fn cancel(&mut self) -> Option<String> {
        if let Some(label) = self.schedule.cancel() {
            return Some(label);
        }
        let label = self.job.cancel()?;
        self.message = Some("Cancelled".into());
        Some(label)
    }

    /// Start computing the forces of the active operation.
    pub fn start(&mut self, view: &FeatureView<'_>, ctx: &egui::Context) {
        match prepare(view, self.max_rays.unwrap_or(DEFAULT_MAX_RAYS)) {
            Ok((key, input)) => {
                self.cancel();
                self.message = None;
                let label = format!("Cutting forces of {}", key.operation.name());
                self.job
                    .start(key, Job::start(label, ctx, move |p| input.run(p)));
            }
            Err(m) => self.message = Some(m),
        }
    }

    /// Collect a finished job.
    fn poll(&mut self, ctx: &egui::Context) {
        self.schedule.poll();
        if self.job.is_running() || self.schedule.is_running() {
            ctx.request_repaint_after(std::time::Duration::from_millis(100));
        }
        let Some(done) = self.job.poll() else { return };
        let outcome = done.result.unwrap_or_else(|| {
            Err(ForceRunError::Stock(
                "the worker stopped unexpectedly".into(),
            ))
        });
        match outcome {
            Ok(r) => {
                self.serial += 1;
                self.result = Some((done.key, Arc::new(r)));
                self.coloured = None;
                self.deflection = None;
            }
            Err(ForceRunError::Cancelled) => self.message = Some("Cancelled".into()),
            Err(e) => self.message = Some(format!("Forces not computed: {e}")),
        }
    }

    /// Keep the coloured path and the deflection profile up to date, then, when open, draw
    /// the window.
    fn window(&mut self, ctx: &egui::Context, view: &FeatureView<'_>, commands: &mut Vec<Command>) {
        let now = view.active_operation.and_then(|i| key_of(view, i));
        self.current = self
            .result
            .as_ref()
            .is_some_and(|(k, _)| now.as_ref() == Some(k));
        self.update_colouring(view);
        if !self.open {
            return;
        }
        let mut open = self.open;
        egui::Window::new("Cutting forces")
            .id(egui::Id::unique("talas cutting forces"))
            .open(&mut open)
            .default_pos([80.0, 90.0])
            .default_size([900.0, 640.0])
            .resizable(true)
            .vscroll(true)
            .show(ctx, |ui| self.ui(ui, view, commands));
        self.open = open;
    }

    /// Rebuild the coloured path when the result or the plotted quantity changed.
    fn update_colouring(&mut self, view: &FeatureView<'_>) {
        let Some((_, o)) = &self.result else {
            self.coloured = None;
            return;
        };
        if !self.colour_path {
            return;
        }
        let key = colour::ColourKey {
            result: self.serial,
            shown: self.shown,
            mean: self.mean,
        };
        if self.coloured.as_ref().is_some_and(|c| c.key == key) {
            return;
        }
        self.coloured = Some(colour::coloured_path(
            &o.toolpath,
            &o.timeline,
            key,
            view.next_id(),
        ));
    }

    /// The window's contents.
    pub fn ui(&mut self, ui: &mut egui::Ui, view: &FeatureView<'_>, commands: &mut Vec<Command>) {
        let current = view.active_operation.and_then(|i| key_of(view, i));
        ui.horizontal(|ui| {
            let name = current
                .as_ref()
                .map_or("no operation", |k| k.operation.name());
            ui.label(egui::RichText::new(name).strong());
            if let Some(job) = self.job.job() {
                ui.add(
                    egui::ProgressBar::new(job.progress.fraction() as f32)
                        .desired_width(160.0)
                        .show_percentage(),
                );
                if ui.button("Cancel").clicked() {
                    self.cancel();
                }
            } else if ui
                .add_enabled(current.is_some(), egui::Button::new("Compute forces"))
                .on_hover_text(
                    "Forces along the computed path, on the stock the earlier operations leave",
                )
                .clicked()
            {
                self.start(view, ui.ctx());
            }
            ui.separator();
            ui.toggle_value(&mut self.editor.open, "Coefficients…");
            ui.separator();
            ui.checkbox(&mut self.colour_path, "Colour the path")
                .on_hover_text("Colour each cutting move of the path in the viewport by the plotted quantity (its largest value over the move), with the limit marked on the legend");
            ui.checkbox(&mut self.show_deflection, "Deflection at the pose");
        });
        if let Some(m) = &self.message {
            ui.colored_label(ui.visuals().warn_fg_color, m);
        }
        if self.editor.open {
            self.editor.ui(ui, view.data_dir);
            ui.separator();
        }
        let Some((key, outcome)) = &self.result else {
            ui.label("Compute the forces of the active operation (its tool needs flutes, e.g. flat:d=10,flutes=3).");
            return;
        };
        let outcome = Arc::clone(outcome);
        let index = key.index;
        if current.as_ref() != Some(key) {
            ui.colored_label(
                ui.visuals().warn_fg_color,
                "The operation, its tool or its posted program changed since: compute again.",
            );
        }
        let result = &outcome.timeline;
        let cursor = view
            .tool_pose
            .and_then(|p| result.pose_time_s.get(p).copied());
        let plot_height = if self.show_deflection { 220.0 } else { 300.0 };
        let (transform, pose) = ui
            .allocate_ui(egui::vec2(ui.available_width(), plot_height + 60.0), |ui| {
                plot::ui(ui, result, (&mut self.shown, &mut self.mean), cursor)
            })
            .inner;
        self.plot_transform = Some(transform);
        if let Some(pose) = pose {
            commands.push(Command::PickPose(Some(pose)));
        }
        ui.separator();
        ui.label(egui::RichText::new("Feed schedule").strong());
        let machine = view.project.machine.clone();
        self.schedule
            .ui(ui, &outcome, (index, self.serial), &machine, commands);
        if self.show_deflection {
            self.deflection_ui(ui, view, &outcome);
        }
    }

    /// The deflection profile of the pose the tool stands at (computed once per pose).
    fn deflection_ui(&mut self, ui: &mut egui::Ui, view: &FeatureView<'_>, outcome: &Outcome) {
        ui.separator();
        ui.label(egui::RichText::new("Deflection and wall error at the tool's pose").strong());
        if let Some(p) = view.tool_pose {
            let k = (self.serial, p);
            if self.deflection.as_ref().is_none_or(|(c, _)| *c != k) {
                let d = deflection_panel::compute(
                    &outcome.timeline,
                    p,
                    &outcome.cutter,
                    &outcome.coefficients,
                );
                self.deflection = Some((k, d));
            }
        }
        let shown = self
            .deflection
            .as_ref()
            .filter(|((_, p), _)| Some(*p) == view.tool_pose)
            .map(|(_, d)| d);
        deflection_panel::ui(ui, view.tool_pose, shown);
    }
}

/// Everything the worker needs, owned.
struct Prepared {
    stock: crate::project::Stock,
    bounds: crate::geometry::Aabb,
    earlier: Vec<(Toolpath, Cutter)>,
    toolpath: Toolpath,
    cutter: Cutter,
    coefficients: crate::force::path::ModeCoefficients,
    rpm: f64,
    clock: Option<Vec<f64>>,
    limits: Limits,
    resolution: f64,
}

impl Prepared {
    fn run(&self, progress: &crate::diagnostics::Progress) -> Result<Outcome, ForceRunError> {
        let timeline = operation_forces(
            &ForceRunInput {
                stock: &self.stock,
                part_bounds: self.bounds,
                earlier: self.earlier.iter().map(|(t, c)| (t, c)).collect(),
                toolpath: &self.toolpath,
                cutter: &self.cutter,
                coefficients: &self.coefficients,
                spindle_rpm: self.rpm,
                pose_time_s: self.clock.as_deref(),
                limits: self.limits,
                resolution_mm: self.resolution,
            },
            progress,
        )?;
        Ok(Outcome {
            timeline,
            toolpath: Arc::new(self.toolpath.clone()),
            cutter: self.cutter.clone(),
            coefficients: self.coefficients.clone(),
        })
    }
}

/// The tool's limits, the power limit lowered to the machine's spindle power.
#[must_use]
pub fn limits_of(cutter: &Cutter, machine: Option<&Machine>) -> Limits {
    let l = cutter.limits;
    let spindle = machine.and_then(|m| m.spindle_power_w);
    let power = match (l.max_power_w, spindle) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
    Limits {
        max_force_n: l.max_force_n,
        max_torque_nm: l.max_torque_nm,
        max_power_w: power,
    }
}

fn prepare(view: &FeatureView<'_>, max_rays: f64) -> Result<(ForceKey, Prepared), String> {
    let index = view
        .active_operation
        .ok_or("Add and calculate an operation first")?;
    let key = key_of(view, index).ok_or("The operation has no tool")?;
    let project = view.project;
    let doc = view.document.ok_or("Open a part first")?;
    let (result, fresh) = view
        .results
        .operation_result(index)
        .ok_or("Calculate the operation first")?;
    if !fresh {
        return Err("The path is stale: calculate the operation again".into());
    }
    crate::force::EndMill::from_cutter(&key.cutter).map_err(|e| {
        format!("{e} (give the tool its flutes in the tool library, e.g. flutes=3,helix=30)")
    })?;
    let mut earlier = Vec::new();
    for j in 0..index {
        if let Some((r, true)) = view.results.operation_result(j) {
            earlier.push((r.toolpath().clone(), r.cutter.clone()));
        }
    }
    let text = library_text(view.data_dir)?;
    let library = Library::parse(&text).map_err(|m| format!("coefficient library: {m}"))?;
    let (coefficients, _) = library
        .mode_coefficients(None)
        .map_err(|m| format!("coefficient library: {m}"))?;
    let machine = Machine::resolve(&project.machine).ok();
    let stock = project.stock;
    let b = crate::simulation::StockShape::of(&stock, &doc.bounds).bounds();
    let area = ((b.max.x - b.min.x) * (b.max.y - b.min.y)).max(1e-6);
    let resolution = (area / max_rays.max(1.0)).sqrt().clamp(0.05, 2.0);
    let resolution = (resolution * 100.0).ceil() / 100.0;
    let prepared = Prepared {
        stock,
        bounds: doc.bounds,
        earlier,
        toolpath: result.toolpath().clone(),
        cutter: key.cutter.clone(),
        coefficients,
        rpm: project.post.spindle_rpm,
        clock: view.results.planned_clock(index).map(<[f64]>::to_vec),
        limits: limits_of(&key.cutter, machine.as_ref()),
        resolution,
    };
    Ok((key, prepared))
}
