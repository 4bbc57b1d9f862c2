//! The job's setups in the workstation, a feature: the workholding of the setup in focus drawn
//! around the part (in part coordinates, where it holds the part), the setup's stock box
//! outlined, the view turned so the part lies as on that setup's table (the camera orbits in the
//! setup's frame, its work offset marked by the setup's axes), and "Post job…" (Machining menu): every operation of every setup planned in its
//! setup's frame and one program per setup written next to the chosen file
//! (`STEM-NN-SETUP.EXT`), on a worker thread with progress and Cancel
//! ([`crate::project::job::post_job`], as `talas job --post` does), and "Simulate job": the
//! setups cut one after the other, the stock after the setup in focus drawn in its place
//! ([`simulation`]).

pub mod simulation;

use std::any::Any;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DMat4, DVec3, Mat3, Mat4};

use crate::app::actions::{Action, Menu};
use crate::app::command::{Command, FeatureCommand};
use crate::app::feature::{
    Feature, FeatureContext, FeatureSave, FeatureView, InsteadOfPart, RenderIds, SceneParts,
    chosen_file,
};
use crate::app::job::{Job, JobSlot, JobStatus};
use crate::app::viewport::ViewportState;
use crate::diagnostics::Severity;
use crate::import::Workpiece;
use crate::project::Project;
use crate::project::job::post_job;
use crate::project::setups::{self, Placement};
use crate::render::{LineData, LineInstance, MeshData, MeshInstance, Rgba8};

/// Colour of the workholding: machined steel.
const WORKHOLDING_COLOUR: Rgba8 = [150, 160, 172, 255];
/// Colour of the setup's stock outline.
const STOCK_OUTLINE_COLOUR: Rgba8 = [230, 180, 60, 255];

/// The job's save dialog: the chosen name's stem prefixes every setup's program.
const JOB_FILE: FeatureSave = FeatureSave {
    feature: JobSetups::ID,
    title: "Post job: one program per setup",
    types: &[
        (
            "G-code (.ngc, .nc, .mpf, .h, .i, .gcode)",
            &["ngc", "nc", "mpf", "h", "i", "gcode"],
        ),
        ("All files", &[]),
    ],
};

/// What a finished post of the job wrote: each file and its line count.
type Written = Result<Vec<(PathBuf, usize)>, String>;

/// The drawn workholding and stock of one setup, with what it was made from.
struct Drawn {
    key: String,
    meshes: Vec<MeshInstance>,
    lines: Vec<LineInstance>,
    /// World (part) from the setup's frame, when the setup could be placed.
    world_from_setup: Option<Mat4>,
    error: Option<String>,
}

/// The job feature: the drawn setup and the running post of the whole job.
#[derive(Default)]
pub struct JobSetups {
    drawn: Option<Drawn>,
    job: JobSlot<Written, ()>,
    /// The whole job's simulation.
    pub simulation: simulation::JobSimulation,
    /// The stock after the setup in view, when the job was simulated on this project.
    stock_shown: Option<InsteadOfPart>,
}

impl JobSetups {
    /// The feature's id.
    pub const ID: &'static str = "job";

    /// Is the job being posted?
    #[must_use]
    pub fn is_posting(&self) -> bool {
        self.job.is_running()
    }

    /// The workholding meshes drawn for the setup in view (one per item).
    #[must_use]
    pub fn drawn_workholding(&self) -> usize {
        self.drawn.as_ref().map_or(0, |d| d.meshes.len())
    }

    /// Why the setup in view's workholding is not drawn, if it is not.
    #[must_use]
    pub fn drawing_error(&self) -> Option<&str> {
        self.drawn.as_ref().and_then(|d| d.error.as_deref())
    }

    /// Rebuild the drawn workholding when the setup in view or what places it changed.
    fn refresh(&mut self, cx: &mut FeatureContext<'_>) {
        let view = cx.view;
        let Some(doc) = view.document else {
            self.drawn = None;
            return;
        };
        let project = view.project;
        let s = view
            .active_setup
            .min(project.setups.len().saturating_sub(1));
        let key = format!(
            "{s}|{}|{:?}|{:?}|{:?}",
            doc.part.path.display(),
            project.stock,
            project.setups,
            view.project_path
        );
        if self.drawn.as_ref().is_some_and(|d| d.key == key) {
            return;
        }
        let base = view
            .project_path
            .and_then(Path::parent)
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        let drawn = match scene_of(project, s, &doc.part.workpiece, &base, cx) {
            Ok((meshes, lines, world)) => Drawn {
                key,
                meshes,
                lines,
                world_from_setup: Some(world),
                error: None,
            },
            Err(e) => {
                if self.drawn.as_ref().and_then(|d| d.error.as_ref()) != Some(&e) {
                    cx.log(Severity::Warning, format!("Workholding not drawn: {e}"));
                }
                Drawn {
                    key,
                    meshes: Vec::new(),
                    lines: Vec::new(),
                    world_from_setup: None,
                    error: Some(e),
                }
            }
        };
        self.drawn = Some(drawn);
    }

    /// Post the whole job in the background, writing next to `path`.
    fn start(&mut self, path: &Path, cx: &mut FeatureContext<'_>) {
        let view = cx.view;
        let Some(doc) = view.document else {
            cx.notify(Severity::Warning, "Open a part before posting the job");
            return;
        };
        let project = view.project.clone();
        let part = Arc::clone(&doc.part.workpiece);
        let dir = path
            .parent()
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        let stem = path.file_stem().map_or_else(
            || project.name.clone(),
            |s| s.to_string_lossy().into_owned(),
        );
        let ext = path
            .extension()
            .map_or_else(|| "ngc".to_string(), |e| e.to_string_lossy().into_owned());
        let label = format!("Posting the job ({} setups)", project.setups.len());
        cx.log(Severity::Info, format!("{label} into {}", dir.display()));
        let job = Job::start(label, cx.egui, move |progress| {
            let programs = post_job(&project, &part, progress)?;
            let mut written = Vec::new();
            for p in programs {
                let file = dir.join(format!("{stem}-{}.{ext}", p.stem));
                crate::storage::write_atomic(&file, p.program.text.as_bytes())
                    .map_err(|e| format!("{}: cannot write: {e}", file.display()))?;
                written.push((file, p.program.text.lines().count()));
            }
            Ok(written)
        });
        self.job.start((), job);
    }

    fn poll_job(&mut self, cx: &mut FeatureContext<'_>) {
        let Some(done) = self.job.poll() else {
            return;
        };
        match done.result {
            Some(Ok(files)) => {
                for (file, lines) in &files {
                    cx.log(
                        Severity::Info,
                        format!("Wrote {} ({lines} lines)", file.display()),
                    );
                }
                cx.notify(
                    Severity::Info,
                    format!(
                        "Posted the job: {} programs in {:.1} s",
                        files.len(),
                        done.elapsed_s
                    ),
                );
            }
            Some(Err(e)) => cx.notify(Severity::Error, format!("Job not posted: {e}")),
            None => cx.notify(
                Severity::Error,
                "Posting the job failed: the worker stopped unexpectedly",
            ),
        }
    }
}

/// The world-from-setup transform of a placement: the part point `p` sits at
/// `rotation·(p − origin)` in the setup frame, so the setup point `s` is at
/// `rotationᵀ·s + origin` in part (world) coordinates.
fn world_from_setup(place: &Placement) -> Mat4 {
    let r = place.rotation.transpose();
    let m = DMat4::from_cols(
        r.x_axis.extend(0.0),
        r.y_axis.extend(0.0),
        r.z_axis.extend(0.0),
        place.origin.extend(1.0),
    );
    m.as_mat4()
}

/// The setup's workholding meshes, its stock box's edges and world-from-setup, in part
/// coordinates.
fn scene_of(
    project: &Project,
    s: usize,
    part: &Workpiece,
    base: &Path,
    cx: &mut FeatureContext<'_>,
) -> Result<(Vec<MeshInstance>, Vec<LineInstance>, Mat4), String> {
    let placements = setups::placements(project, Some(part))?;
    let bounds = part.mesh.bbox();
    let place = placements
        .get(s)
        .ok_or_else(|| format!("no setup {}", s + 1))?;
    let world = world_from_setup(place);
    let meshes = setups::workholding_meshes(project, s, &placements, &bounds, base)?
        .iter()
        .map(|m| MeshInstance {
            id: cx.next_id(),
            data: Arc::new(MeshData::flat(&m.positions, &m.triangles)),
            world_from_mesh: world,
            colour: WORKHOLDING_COLOUR,
            scalar_map: None,
        })
        .collect();
    let solid = setups::stock_solid(project, s, &placements, &bounds)?;
    let b = solid.bbox();
    let lines = if b.is_empty() {
        Vec::new()
    } else {
        vec![LineInstance {
            id: cx.next_id(),
            data: Arc::new(box_edges(b.min, b.max)),
            world_from_lines: world,
            draw_segments: None,
        }]
    };
    Ok((meshes, lines, world))
}

/// The 12 edges of a box as line segments.
fn box_edges(min: DVec3, max: DVec3) -> LineData {
    let colour = STOCK_OUTLINE_COLOUR;
    let c = |i: u32| {
        DVec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
        .as_vec3()
        .to_array()
    };
    let mut out = LineData::default();
    for a in 0..8u32 {
        for bit in [1u32, 2, 4] {
            if a & bit == 0 {
                out.push_polyline(&[c(a), c(a | bit)], colour);
            }
        }
    }
    out
}

impl Feature for JobSetups {
    fn id(&self) -> &'static str {
        Self::ID
    }

    fn actions(&self) -> Vec<Action> {
        let post = FeatureCommand {
            feature: Self::ID,
            action: "post",
        };
        let simulate = FeatureCommand {
            feature: Self::ID,
            action: "simulate",
        };
        vec![
            Action::new(
                Command::Feature(post),
                "Post job…",
                Some((Menu::Machining, 1)),
            )
            .hint("Plan every operation in its setup and write one program per setup"),
            Action::new(
                Command::Feature(simulate),
                "Simulate job",
                Some((Menu::Machining, 1)),
            )
            .hint(
                "Cut every setup in order, each from the stock the one before it left; pick a \
                 setup to see the stock after it",
            ),
        ]
    }

    fn apply(&mut self, command: Command, cx: &mut FeatureContext<'_>) -> Option<Command> {
        if let Some(path) = chosen_file(&command, Self::ID) {
            self.start(path, cx);
            return None;
        }
        match command {
            Command::Feature(FeatureCommand {
                feature: Self::ID,
                action: "simulate",
            }) => {
                self.simulation.start(cx);
                None
            }
            Command::Feature(FeatureCommand {
                feature: Self::ID,
                action: "post",
            }) => {
                let project = cx.view.project;
                let dir = cx
                    .view
                    .project_path
                    .and_then(|p| p.parent().map(Path::to_path_buf))
                    .or_else(|| std::env::current_dir().ok())
                    .unwrap_or_default();
                let ext = match project.post.dialect.as_str() {
                    "siemens" => "mpf",
                    "heidenhain" => "i",
                    "linuxcnc" => "ngc",
                    _ => "nc",
                };
                let stem = crate::project::job::program_stem(&project.name);
                cx.ask_save_path(JOB_FILE, dir.join(format!("{stem}.{ext}")));
                None
            }
            other => Some(other),
        }
    }

    fn poll(&mut self, cx: &mut FeatureContext<'_>) {
        self.refresh(cx);
        self.poll_job(cx);
        self.simulation.poll(cx);
        let view = cx.view;
        let in_view = view
            .active_setup
            .min(view.project.setups.len().saturating_sub(1));
        self.stock_shown = self
            .drawn
            .as_ref()
            .and_then(|d| d.world_from_setup)
            .and_then(|world| self.simulation.stock_after(&view, in_view, world));
    }

    fn job_status(&self) -> Option<JobStatus> {
        self.job.status().or_else(|| self.simulation.status())
    }

    fn cancel(&mut self) -> Option<String> {
        self.job.cancel().or_else(|| self.simulation.cancel())
    }

    fn reset(&mut self) {
        *self = Self::default();
    }

    fn ui(&mut self, ctx: &egui::Context, view: &FeatureView<'_>, _commands: &mut Vec<Command>) {
        self.simulation.window_ui(ctx, view);
    }

    /// The work offset marked with the setup's axes, and the camera orbiting in its frame
    /// (when the view follows the setup): a part turned over for setup 2 is seen turned over.
    fn steer_view(&mut self, viewport: &mut ViewportState, _ids: &RenderIds) -> Vec<MeshInstance> {
        if viewport.machine_shown {
            return Vec::new();
        }
        if let Some(world) = self.drawn.as_ref().and_then(|d| d.world_from_setup) {
            viewport.work_offset = Some(world);
            let frame = if viewport.orient_to_setup {
                Mat3::from_mat4(world)
            } else {
                Mat3::IDENTITY
            };
            if viewport.camera.frame != frame {
                viewport.camera.frame = frame;
            }
        } else {
            viewport.camera.frame = Mat3::IDENTITY;
        }
        Vec::new()
    }

    fn scene(&self) -> SceneParts {
        let Some(d) = &self.drawn else {
            return SceneParts::default();
        };
        let stock = self.stock_shown.as_ref().map(|s| InsteadOfPart {
            mesh: s.mesh.clone(),
            legend: s.legend.clone(),
            mapping: s.mapping,
        });
        SceneParts {
            meshes: d.meshes.clone(),
            lines: d.lines.clone(),
            hide_paths: stock.is_some(),
            instead_of_part: stock,
            ..SceneParts::default()
        }
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_setup_frame_maps_back_onto_the_part() {
        // Turned over about X and the origin at the part's top centre: a setup point goes back
        // to the part point it came from.
        let rotation = glam::DMat3::from_rotation_x(std::f64::consts::PI);
        let origin = DVec3::new(10.0, 20.0, 30.0);
        let place = Placement {
            rotation,
            origin,
            work_plane: glam::DMat3::IDENTITY,
        };
        let part_point = DVec3::new(12.0, 25.0, 27.0);
        let in_setup = rotation * (part_point - origin);
        let back = world_from_setup(&place).transform_point3(in_setup.as_vec3());
        assert!((back.as_dvec3() - part_point).length() < 1e-5, "{back}");
    }

    #[test]
    fn a_box_has_twelve_edges() {
        let l = box_edges(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0));
        assert_eq!(l.segment_count(), 12);
    }
}
