//! "Simulate job" (Machining menu): every setup's operations planned in its frame, linked over
//! the stock, and cut setup after setup, each setup starting from what the one before it left
//! ([`crate::project::job_sim::simulate_whole_job`], as `talas job --simulate` runs it), on a
//! worker thread with progress and Cancel. The stock after the setup in focus is drawn in place
//! of the part, in that setup's place on the part and coloured by its deviation from the part;
//! picking another setup in the tree shows the stock after it, so the job plays setup after
//! setup. A window lists each setup's removed volume, gouge, stock collisions and workholding
//! contacts. The result is shown while the project it was run on is unchanged.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Mat4;

use crate::app::feature::{FeatureContext, FeatureView, InsteadOfPart};
use crate::app::job::{Job, JobSlot, JobStatus};
use crate::app::scalar_field::band_mapping;
use crate::diagnostics::Severity;
use crate::project::Project;
use crate::project::job_sim::{SetupSimulation, simulate_whole_job};
use crate::project::simulate::SimulationSettings;
use crate::render::{DataId, MeshData, MeshInstance};

/// Colour of the simulated stock (sRGB), as the operation's simulation draws it.
const STOCK_COLOUR: [u8; 4] = [196, 170, 120, 255];
/// Half-width of the deviation band the job's stock is coloured against, mm.
pub const JOB_BAND_MM: f64 = 0.1;

/// One setup's result as drawn.
pub struct ShownSetup {
    /// The engine's record of the setup's simulation.
    pub result: SetupSimulation,
    /// The setup's name.
    pub name: String,
    /// Its operations' names, in order (for the workholding contacts).
    pub operations: Vec<String>,
    /// The stock's top with its deviation as render data (setup frame), with its id.
    mesh: Option<(DataId, Arc<MeshData>)>,
}

/// A finished simulation of the whole job.
pub struct ShownJob {
    /// What it was run on (it is shown while the project matches).
    key: String,
    /// Each setup, in order.
    pub setups: Vec<ShownSetup>,
    /// Wall time, s.
    pub elapsed_s: f64,
}

/// The job simulation's state in the job feature.
#[derive(Default)]
pub struct JobSimulation {
    job: JobSlot<Result<Vec<SetupSimulation>, String>, String>,
    shown: Option<ShownJob>,
    /// The report window is open.
    pub window_open: bool,
}

/// What a simulation depends on: the project's machining content and the part.
fn key_of(project: &Project, part: &Path) -> String {
    format!(
        "{}|{:?}|{:?}|{:?}|{:?}|{:?}",
        part.display(),
        project.stock,
        project.setups,
        project.operations,
        project.tools,
        project.machine
    )
}

fn mesh_of(s: &SetupSimulation) -> Option<MeshData> {
    let m = s.measured.as_ref()?;
    let mesh = &m.stock_mesh;
    let f = |v: glam::DVec3| [v.x as f32, v.y as f32, v.z as f32];
    let normals = if mesh.normals.len() == mesh.positions.len() {
        mesh.normals.iter().map(|&n| f(n)).collect()
    } else {
        vec![[0.0, 0.0, 1.0]; mesh.positions.len()]
    };
    Some(MeshData {
        positions: mesh.positions.iter().map(|&p| f(p)).collect(),
        normals,
        scalars: m.deviation_mm.iter().map(|&d| d as f32).collect(),
        indices: mesh.triangles.iter().flatten().copied().collect(),
    })
}

impl JobSimulation {
    /// Is the job being simulated?
    #[must_use]
    pub fn is_running(&self) -> bool {
        self.job.is_running()
    }

    /// The finished simulation, when the project is still the one it was run on.
    #[must_use]
    pub fn shown(&self, view: &FeatureView<'_>) -> Option<&ShownJob> {
        let doc = view.document?;
        let key = key_of(view.project, &doc.part.path);
        self.shown.as_ref().filter(|s| s.key == key)
    }

    /// Start simulating the whole job.
    pub fn start(&mut self, cx: &mut FeatureContext<'_>) {
        let view = cx.view;
        let Some(doc) = view.document else {
            cx.notify(Severity::Warning, "Open a part before simulating the job");
            return;
        };
        if view.project.operations.is_empty() {
            cx.notify(Severity::Warning, "The job has no operation to simulate");
            return;
        }
        let project = view.project.clone();
        let part = Arc::clone(&doc.part.workpiece);
        let key = key_of(&project, &doc.part.path);
        let base = view
            .project_path
            .and_then(Path::parent)
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        let label = format!("Simulating the job ({} setups)", project.setups.len());
        cx.log(Severity::Info, label.clone());
        let job = Job::start(label, cx.egui, move |progress| {
            simulate_whole_job(
                &project,
                &part,
                &base,
                &SimulationSettings::default(),
                progress,
            )
        });
        self.job.start(key, job);
    }

    /// Take a finished run.
    pub fn poll(&mut self, cx: &mut FeatureContext<'_>) {
        let Some(done) = self.job.poll() else {
            return;
        };
        match done.result {
            Some(Ok(results)) => {
                let project = cx.view.project;
                let setups: Vec<ShownSetup> = results
                    .into_iter()
                    .map(|r| {
                        let setup = project.setups.get(r.setup);
                        let mesh = mesh_of(&r).map(|m| (cx.next_id(), Arc::new(m)));
                        ShownSetup {
                            name: setup.map_or_else(String::new, |s| s.name.clone()),
                            operations: setup.map_or_else(Vec::new, |s| {
                                s.operations
                                    .iter()
                                    .filter_map(|&i| project.operations.get(i))
                                    .map(|o| o.name().to_string())
                                    .collect()
                            }),
                            result: r,
                            mesh,
                        }
                    })
                    .collect();
                let removed: f64 = setups.iter().map(|s| s.result.removed_volume_mm3).sum();
                let contacts = setups
                    .iter()
                    .flat_map(|s| &s.result.workholding)
                    .filter(|h| h.is_some())
                    .count();
                cx.notify(
                    if contacts > 0 {
                        Severity::Warning
                    } else {
                        Severity::Info
                    },
                    format!(
                        "Simulated the job: {} setups, {:.1} cm³ removed, {contacts} operations \
                         touching the workholding, in {:.1} s",
                        setups.len(),
                        removed / 1000.0,
                        done.elapsed_s
                    ),
                );
                self.shown = Some(ShownJob {
                    key: done.key,
                    setups,
                    elapsed_s: done.elapsed_s,
                });
                self.window_open = true;
            }
            Some(Err(e)) => cx.notify(Severity::Error, format!("Job not simulated: {e}")),
            None => cx.notify(
                Severity::Error,
                "Simulating the job failed: the worker stopped unexpectedly",
            ),
        }
    }

    /// The running job's status.
    #[must_use]
    pub fn status(&self) -> Option<JobStatus> {
        self.job.status()
    }

    /// Cancel the running job.
    pub fn cancel(&mut self) -> Option<String> {
        self.job.cancel()
    }

    /// The stock after setup `s`, drawn in place of the part in that setup's place
    /// (`world_from_setup`), coloured by its deviation from the part.
    #[must_use]
    pub fn stock_after(
        &self,
        view: &FeatureView<'_>,
        s: usize,
        world_from_setup: Mat4,
    ) -> Option<InsteadOfPart> {
        let shown = self.shown(view)?;
        let (id, data) = shown.setups.get(s)?.mesh.as_ref()?;
        let mapping = band_mapping(JOB_BAND_MM);
        Some(InsteadOfPart {
            mesh: MeshInstance {
                id: *id,
                data: Arc::clone(data),
                world_from_mesh: world_from_setup,
                colour: STOCK_COLOUR,
                scalar_map: Some(mapping),
            },
            legend: format!("Stock after setup {} · deviation (mm)", s + 1),
            mapping,
        })
    }

    /// The report window: one block per setup.
    pub fn window_ui(&mut self, ctx: &egui::Context, view: &FeatureView<'_>) {
        if !self.window_open {
            return;
        }
        let Some(shown) = self.shown(view) else {
            return;
        };
        let mut open = self.window_open;
        egui::Window::new("Job simulation")
            .open(&mut open)
            .default_width(420.0)
            .show(ctx, |ui| {
                ui.weak(format!(
                    "Every setup cut in order, each from what the one before it left ({:.1} s). \
                     Pick a setup in the tree to see the stock after it.",
                    shown.elapsed_s
                ));
                for (s, setup) in shown.setups.iter().enumerate() {
                    let r = &setup.result;
                    ui.separator();
                    ui.strong(format!("{}. {}", s + 1, setup.name));
                    crate::app::widgets::grid(
                        ui,
                        &format!("job setup {s}"),
                        &[
                            (
                                "Start",
                                if r.carried {
                                    format!(
                                        "{:.2} cm³, from setup {}",
                                        r.start_volume_mm3 / 1000.0,
                                        s
                                    )
                                } else {
                                    format!("{:.2} cm³", r.start_volume_mm3 / 1000.0)
                                },
                            ),
                            (
                                "Removed",
                                format!("{:.2} cm³", r.removed_volume_mm3 / 1000.0),
                            ),
                            ("Left", format!("{:.2} cm³", r.end_volume_mm3 / 1000.0)),
                            ("Deepest gouge", format!("{:.3} mm", r.max_gouge_mm)),
                            (
                                "Shank or holder in the stock",
                                format!("{} contacts", r.stock_collisions),
                            ),
                            ("Grid", format!("{:.3} mm", r.resolution_mm)),
                        ],
                    );
                    for (k, hit) in r.workholding.iter().enumerate() {
                        if let Some(h) = hit {
                            let name = setup.operations.get(k).map_or("?", String::as_str);
                            ui.colored_label(
                                crate::app::theme::WARNING,
                                format!(
                                    "⚠ {name}: the tool touches the workholding at pose {}",
                                    h.block
                                ),
                            );
                        }
                    }
                }
            });
        self.window_open = open;
    }
}
