//! Stock simulation of the active operation's path, a workstation feature ([`feature`]): a
//! background job (progress, Cancel) through [`crate::project::simulate::simulate_toolpath`],
//! the cut stock drawn instead of the part coloured by its signed deviation from the part
//! against a tolerance band (graded blue → white → orange within the band; violet for gouges
//! and red for material left beyond it), its legend, red crosses at the collisions, and the
//! report in the operation editor ([`editor`]). "Stock here" cuts up to the playback pose from
//! the keyframes a whole run kept (`stock_here`).

pub mod editor;
pub mod feature;
mod stock_here;

use std::sync::Arc;

use glam::Mat4;

use super::feature::{FeatureContext, FeatureView, InsteadOfPart};
use super::job::{Job, JobSlot};
use crate::diagnostics::Severity;
use crate::project::Operation;
use crate::project::simulate::{Simulated, SimulationSettings};
use crate::render::{DataId, LineData, LineInstance, MeshData, MeshInstance, ScalarMapping};
use crate::simulation::SimError;
use crate::tools::Cutter;

/// Colour of the stock when no deviation is shown (sRGB).
const STOCK_COLOUR: [u8; 4] = [196, 170, 120, 255];

/// What a simulation was run on (it is shown while these are unchanged).
#[derive(Clone, Debug, PartialEq)]
struct SimKey {
    /// The operations simulated, in order (the last is the one asked for), with their tools.
    operations: Vec<(Operation, Cutter)>,
    part_id: DataId,
    stock: crate::project::Stock,
    /// The last operation's path cut only up to this pose (playback), or whole.
    upto: Option<usize>,
    /// The index of the operation asked for.
    index: usize,
}

impl SimKey {
    fn name(&self) -> &str {
        self.operations.last().map_or("", |(o, _)| o.name())
    }

    /// The same operations, tools, part and stock (cut whole or up to any pose).
    fn same_run(&self, other: &Self) -> bool {
        (&self.operations, self.part_id, &self.stock)
            == (&other.operations, other.part_id, &other.stock)
    }
}

impl ShownSimulation {
    /// The last operation's path was cut up to this pose ("Stock here"), or whole (`None`).
    #[must_use]
    pub fn up_to_pose(&self) -> Option<usize> {
        self.key.upto
    }
}

/// A finished simulation with its render data.
pub struct ShownSimulation {
    key: SimKey,
    /// The simulation's result.
    pub simulated: Simulated,
    /// Wall time, s.
    pub elapsed_s: f64,
    id: DataId,
    mesh: Arc<MeshData>,
    /// Red crosses at the collisions, with their render id.
    markers: (DataId, Arc<LineData>),
    /// Half-width of the tolerance band the deviation is coloured against, mm (by default the
    /// operation's scallop height, or its stock to leave for roughing).
    pub band_mm: f64,
}

impl ShownSimulation {
    /// Colour mapping of the deviation: the tolerance band ±`band_mm` graded, out-of-band
    /// colours beyond it.
    #[must_use]
    pub fn mapping(&self) -> ScalarMapping {
        band_mapping(self.band_mm)
    }
}

pub use crate::app::scalar_field::{MIN_BAND_MM, band_mapping};

/// The default tolerance band of `operation`'s stock: its scallop height (finishing, raster, waterline, steep-and-shallow) or
/// its stock to leave (roughing), at least [`MIN_BAND_MM`].
#[must_use]
pub fn default_band_mm(operation: &Operation) -> f64 {
    let band = match operation {
        Operation::Finish { options, .. } => options.scallop,
        Operation::Raster { scallop_mm, .. }
        | Operation::Waterline { scallop_mm, .. }
        | Operation::SteepShallow { scallop_mm, .. }
        | Operation::Rest { scallop_mm, .. } => *scallop_mm,
        // A pencil pass leaves what its chord tolerance allows along the corner.
        Operation::Pencil { tolerance_mm, .. } => *tolerance_mm,
        Operation::Rough {
            stock_to_leave_mm, ..
        } => *stock_to_leave_mm,
        Operation::Face(_) | Operation::Pocket(_) | Operation::Contour(_) | Operation::Holes(_) => {
            operation.common().map_or(0.0, |c| {
                c.stock_to_leave_walls_mm.max(c.stock_to_leave_floors_mm)
            })
        }
    };
    band.max(MIN_BAND_MM)
}

/// The stock-simulation feature's state.
#[derive(Default)]
pub struct StockSimulation {
    job: JobSlot<Result<Simulated, SimError>, SimKey>,
    /// The latest simulation.
    shown: Option<ShownSimulation>,
    /// Draw the simulated stock.
    visible: bool,
    /// Keyframes of the latest whole simulation, for "Stock here".
    keyframes: stock_here::KeyframeSlot,
    /// The active operation when last polled: another operation's path becoming active (a
    /// new calculation, a pick) hides the simulated stock, which would hide that path.
    last_active: Option<usize>,
}

/// What simulating operation `index` runs: every operation before it that has a fresh path
/// (in order: the stock after each one is the next one's stock), then operation `index`.
fn sim_key(view: &FeatureView<'_>, index: usize) -> Option<SimKey> {
    let project = view.project;
    let mut operations = Vec::new();
    for i in 0..=index {
        let operation = project.operations.get(i)?.clone();
        let cutter = project.tools.get(operation.tool())?.cutter.clone();
        let fresh = matches!(view.results.operation_result(i), Some((_, true)));
        if fresh || i == index {
            operations.push((operation, cutter));
        }
    }
    Some(SimKey {
        operations,
        part_id: view.document?.ids[0],
        stock: project.stock,
        upto: None,
        index,
    })
}

impl StockSimulation {
    /// The feature's id.
    pub const ID: &'static str = "stock_simulation";

    /// Simulate operation `index`'s computed path (it must be fresh), after the earlier
    /// calculated operations, up to pose `upto` (the playback position) or whole.
    fn start(&mut self, index: usize, upto: Option<usize>, cx: &mut FeatureContext<'_>) {
        let view = cx.view;
        let Some(mut key) = sim_key(&view, index) else {
            return;
        };
        key.upto = upto;
        let Some((_, true)) = view.results.operation_result(index) else {
            cx.notify(
                Severity::Warning,
                "Calculate the operation before simulating it",
            );
            return;
        };
        let Some(doc) = view.document else { return };
        // The fresh paths of the operations in the key, in order.
        let mut paths = Vec::new();
        for i in 0..=index {
            if let Some((r, true)) = view.results.operation_result(i) {
                paths.push((r.toolpath().clone(), r.cutter.clone()));
            }
        }
        let part = doc.part.mesh().clone();
        let stock = view.project.stock;
        let settings = SimulationSettings {
            max_rays: 250_000,
            ..SimulationSettings::default()
        };
        let label = match upto {
            Some(p) => format!("Simulating {} up to pose {}", key.name(), p + 1),
            None => format!("Simulating {}", key.name()),
        };
        let before = key.operations.len().saturating_sub(1);
        cx.log(
            Severity::Info,
            if before > 0 {
                format!(
                    "{label} after {before} earlier operation(s) on the same stock (Z dexels, at most 250 000 rays)"
                )
            } else {
                format!("{label} (Z dexels, at most 250 000 rays)")
            },
        );
        let inputs = stock_here::SimInputs {
            stock,
            part,
            paths,
            upto,
            settings,
        };
        let slot = Arc::clone(&self.keyframes);
        let job = Job::start(label, cx.egui, move |progress| {
            stock_here::run_simulation(&inputs, &slot, progress)
        });
        self.job.start(key, job);
    }

    /// Is a simulation running?
    #[must_use]
    pub fn is_running(&self) -> bool {
        self.job.is_running()
    }

    /// The simulation shown for operation `index` (whole, or up to a playback pose), when it
    /// matches the operation, tool, part and stock as they are in `view`.
    #[must_use]
    pub fn simulation_of(&self, index: usize, view: &FeatureView<'_>) -> Option<&ShownSimulation> {
        let key = sim_key(view, index)?;
        self.shown.as_ref().filter(|s| s.key.same_run(&key))
    }

    /// The simulation on display (whole or up to a playback pose), if any.
    #[must_use]
    pub fn shown(&self) -> Option<&ShownSimulation> {
        self.shown.as_ref()
    }

    /// Is the simulated stock drawn (when there is one)?
    #[must_use]
    pub fn is_visible(&self) -> bool {
        self.visible
    }

    /// Hide the simulated stock when another operation's path becomes the active one (it
    /// would hide that path; the "Simulated stock" toggle shows it again).
    fn follow_active(&mut self, cx: &mut FeatureContext<'_>) {
        let active = cx.view.active_operation;
        if active == self.last_active {
            return;
        }
        self.last_active = active;
        if let Some(s) = &self.shown
            && self.visible
            && active != Some(s.key.index)
        {
            self.visible = false;
            cx.log(
                Severity::Info,
                format!(
                    "The simulated stock of '{}' is hidden while another path is active \
                     (View > Tool Paths > Simulated stock shows it)",
                    s.key.name()
                ),
            );
        }
    }

    /// Collect a finished simulation.
    fn poll_job(&mut self, cx: &mut FeatureContext<'_>) {
        let Some(done) = self.job.poll() else {
            return;
        };
        let (key, elapsed_s) = (done.key, done.elapsed_s);
        match done.result {
            Some(Ok(simulated)) => {
                let r = &simulated.report;
                cx.log(
                    Severity::Info,
                    format!(
                        "Simulated '{}': {:.0} mm³ removed, {} collisions, deepest gouge {:.1} µm, 99 % of the surface within {:.1} µm, {:.2} mm dexels, in {elapsed_s:.1} s",
                        key.name(),
                        r.removed_volume_mm3,
                        r.collisions.len(),
                        simulated.max_gouge_mm * 1000.0,
                        simulated.remaining_p99_mm * 1000.0,
                        simulated.resolution_mm
                    ),
                );
                if !r.collisions.is_empty() {
                    cx.notify(
                        Severity::Warning,
                        format!(
                            "'{}': {} collisions of the shank, holder or a rapid with the stock",
                            key.name(),
                            r.collisions.len()
                        ),
                    );
                }
                cx.next_id();
                let mesh = deviation_mesh(&simulated);
                let band_mm = key
                    .operations
                    .last()
                    .map_or(MIN_BAND_MM, |(o, _)| default_band_mm(o));
                let id = cx.next_id();
                let size = cx
                    .view
                    .document
                    .map_or(2.0, |d| 0.015 * (d.bounds.max - d.bounds.min).max_element())
                    .max(0.5);
                let markers = (
                    cx.next_id(),
                    Arc::new(collision_markers(&simulated, size as f32)),
                );
                self.shown = Some(ShownSimulation {
                    key,
                    simulated,
                    elapsed_s,
                    id,
                    mesh: Arc::new(mesh),
                    markers,
                    band_mm,
                });
                self.visible = true;
            }
            Some(Err(SimError::Cancelled)) => {}
            Some(Err(e)) => cx.notify(Severity::Error, format!("Simulation failed: {e}")),
            None => cx.notify(
                Severity::Error,
                "Simulation failed: the worker stopped unexpectedly",
            ),
        }
    }

    /// Red crosses at the collisions of the shown simulation, when visible.
    fn collision_instance(&self) -> Option<LineInstance> {
        let s = self.shown.as_ref().filter(|_| self.visible)?;
        (s.markers.1.segment_count() > 0).then(|| LineInstance {
            id: s.markers.0,
            data: Arc::clone(&s.markers.1),
            world_from_lines: Mat4::IDENTITY,
            draw_segments: None,
        })
    }

    /// The stock mesh drawn instead of the part, with its legend, when visible.
    fn stock_instance(&self) -> Option<InsteadOfPart> {
        let s = self.shown.as_ref().filter(|_| self.visible)?;
        let mapping = s.mapping();
        Some(InsteadOfPart {
            mesh: MeshInstance {
                id: s.id,
                data: Arc::clone(&s.mesh),
                world_from_mesh: Mat4::IDENTITY,
                colour: STOCK_COLOUR,
                scalar_map: Some(mapping),
            },
            legend: "Stock deviation (mm)".to_string(),
            mapping,
        })
    }

    /// Colour the shown stock's deviation against a tolerance band of ±`band_mm`.
    fn set_deviation_band(&mut self, band_mm: f64) {
        if let Some(s) = &mut self.shown
            && band_mm.is_finite()
            && band_mm >= MIN_BAND_MM
        {
            s.band_mm = band_mm;
        }
    }

    /// Drop the stock keyframes (the paths they were cut from changed).
    fn drop_keyframes(&self) {
        if let Ok(mut k) = self.keyframes.lock() {
            *k = None;
        }
    }
}

/// The stock mesh with the signed deviation from the part as its scalar (mm).
fn deviation_mesh(s: &Simulated) -> MeshData {
    let m = &s.stock_mesh;
    let f = |v: glam::DVec3| [v.x as f32, v.y as f32, v.z as f32];
    let normals = if m.normals.len() == m.positions.len() {
        m.normals.iter().map(|&n| f(n)).collect()
    } else {
        vec![[0.0, 0.0, 1.0]; m.positions.len()]
    };
    MeshData {
        positions: m.positions.iter().map(|&p| f(p)).collect(),
        normals,
        scalars: s.deviation_mm.iter().map(|&d| d as f32).collect(),
        indices: m.triangles.iter().flatten().copied().collect(),
    }
}

/// Colour of the collision markers (sRGB).
const COLLISION_COLOUR: [u8; 4] = [255, 40, 40, 255];

/// A three-axis cross of half-size `size` mm at every collision of `s`.
fn collision_markers(s: &Simulated, size: f32) -> LineData {
    let mut out = LineData::default();
    for c in &s.report.collisions {
        let p = c.position.as_vec3();
        for d in [glam::Vec3::X, glam::Vec3::Y, glam::Vec3::Z] {
            out.push_polyline(
                &[(p - d * size).to_array(), (p + d * size).to_array()],
                COLLISION_COLOUR,
            );
        }
    }
    out
}
