//! Cutting forces of a computed operation, as the workstation shows them: the project's stock
//! (cut first by the earlier operations' paths), the operation's path read move by move by
//! [`crate::force::path::path_forces`], and a timeline of the per-piece forces against time —
//! the planned time of the posted run when it is given (each pose's time from the run's clock,
//! which also gives each move its actual mean feed and so its feed per tooth), else the time at
//! the programmed feeds.

use super::Stock;

use crate::diagnostics::Progress;
use crate::force::path::{
    Limits, ModeCoefficients, PathForces, PathMove, PathOptions, Workpiece, path_forces,
};
use crate::force::stock::{Material, SampleOptions, SimulatedStock, path_moves};
use crate::force::{EndMill, ForceError};
use crate::geometry::Aabb;
use crate::simulation::{DexelMode, DexelStock, SimOptions, StepOptions, plan_toolpath, simulate};
use crate::toolpath::Toolpath;
use crate::tools::Cutter;

/// What the forces of an operation are computed from.
pub struct ForceRunInput<'a> {
    /// The project's stock (the default one around the part when none is set).
    pub stock: &'a Stock,
    /// The part's bounds (for the default stock).
    pub part_bounds: Aabb,
    /// Paths cut before this one, in order, with their cutters.
    pub earlier: Vec<(&'a Toolpath, &'a Cutter)>,
    /// The operation's path (part coordinates).
    pub toolpath: &'a Toolpath,
    /// Its cutter (with flutes).
    pub cutter: &'a Cutter,
    /// Coefficients per milling mode.
    pub coefficients: &'a ModeCoefficients,
    /// Spindle speed, rev/min.
    pub spindle_rpm: f64,
    /// Planned time at which each pose is reached, s (the posted run's clock), if any.
    pub pose_time_s: Option<&'a [f64]>,
    /// Limits to flag.
    pub limits: Limits,
    /// Dexel spacing of the stock, mm.
    pub resolution_mm: f64,
}

/// One point of the force timeline: a piece of a cutting move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceSample {
    /// Start and end time of the piece, s.
    pub t_s: [f64; 2],
    /// The pose the piece's move goes to.
    pub pose: usize,
    /// Signed peak F_x, F_y, F_z over a revolution, machine frame, N.
    pub peak: [f64; 3],
    /// Mean F_x, F_y, F_z over a revolution, machine frame, N.
    pub mean: [f64; 3],
    /// Largest resultant, N.
    pub peak_resultant_n: f64,
    /// Largest and mean torque, N·m.
    pub torque_nm: [f64; 2],
    /// Largest and mean cutting power, W.
    pub power_w: [f64; 2],
}

/// The forces of an operation and their timeline.
#[derive(Clone, Debug)]
pub struct ForceTimeline {
    /// Per move and per piece, with totals.
    pub forces: PathForces,
    /// One sample per piece in material (air pieces are left out), in time order.
    pub samples: Vec<ForceSample>,
    /// Time at which each pose is reached, s.
    pub pose_time_s: Vec<f64>,
    /// True when the time is the posted run's planned time, false at the programmed feeds.
    pub planned_time: bool,
    /// The limits flagged.
    pub limits: Limits,
    /// The path's moves at the programmed feeds (what feed scheduling rewrites).
    pub moves: Vec<PathMove>,
}

impl ForceTimeline {
    /// The sample at time `t_s` (the piece running then, else the nearest in time).
    #[must_use]
    pub fn sample_at(&self, t_s: f64) -> Option<&ForceSample> {
        let k = self.samples.partition_point(|s| s.t_s[1] < t_s);
        let after = self.samples.get(k);
        let before = k.checked_sub(1).and_then(|i| self.samples.get(i));
        match (before, after) {
            (Some(_), Some(a)) if a.t_s[0] <= t_s => Some(a),
            (Some(b), Some(a)) => Some(if t_s - b.t_s[1] <= a.t_s[0] - t_s {
                b
            } else {
                a
            }),
            (b, a) => a.or(b),
        }
    }
}

/// The material with a progress check at every move (cancel stops the run).
struct Watched<'a, 'p> {
    inner: SimulatedStock<'a>,
    progress: &'p Progress,
    moves: usize,
}

impl Material for Watched<'_, '_> {
    fn material_at(&self, p: glam::DVec3) -> bool {
        self.inner.material_at(p)
    }
}

impl Workpiece for Watched<'_, '_> {
    fn cut_move(&mut self, index: usize) -> Result<(), ForceError> {
        if self.progress.is_cancelled() {
            return Err(ForceError::Input("cancelled".into()));
        }
        #[allow(clippy::cast_precision_loss)]
        self.progress
            .set(0.2 + 0.8 * index as f64 / self.moves.max(1) as f64);
        self.inner.cut_move(index)
    }
}

/// Why the forces of an operation were not computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ForceRunError {
    /// The user cancelled.
    #[error("cancelled")]
    Cancelled,
    /// The stock or a path could not be simulated.
    #[error("stock: {0}")]
    Stock(String),
    /// The force model refused (the message names the pose).
    #[error("{0}")]
    Force(#[from] ForceError),
}

/// Forces of `input.toolpath` on the stock left by the earlier paths (their tool paths, cut
/// into `input.stock` at `input.resolution_mm`).
///
/// # Errors
/// [`ForceRunError`]: a cancel, a stock that cannot be built or cut, a tool without flutes, a
/// move without a spindle speed.
pub fn operation_forces(
    input: &ForceRunInput<'_>,
    progress: &Progress,
) -> Result<ForceTimeline, ForceRunError> {
    let shape = crate::simulation::StockShape::of(input.stock, &input.part_bounds);
    let stock_err = |e: crate::simulation::SimError| ForceRunError::Stock(e.to_string());
    let mut dexels = DexelStock::new(
        vec![shape],
        input.resolution_mm,
        DexelMode::Z,
        crate::simulation::DEFAULT_MEMORY_LIMIT_BYTES,
    )
    .map_err(stock_err)?;
    for (tp, cutter) in &input.earlier {
        let step = StepOptions::for_resolution(input.resolution_mm, cutter.flute_length);
        let plan = plan_toolpath(tp, &step).map_err(stock_err)?;
        let quiet = Progress::new();
        simulate(&mut dexels, cutter, &plan, &SimOptions::default(), &quiet).map_err(stock_err)?;
        if progress.is_cancelled() {
            return Err(ForceRunError::Cancelled);
        }
    }
    operation_forces_on(dexels, input, progress)
}

/// Forces of `input.toolpath` on `stock`, the stock as it is before the operation (the result
/// store's in-process stock, [`super::Results::stock_before`]), on its own grid: `input`'s
/// stock, earlier paths and resolution are not read.
///
/// # Errors
/// As [`operation_forces`].
pub fn operation_forces_on(
    stock: DexelStock,
    input: &ForceRunInput<'_>,
    progress: &Progress,
) -> Result<ForceTimeline, ForceRunError> {
    let mill = EndMill::from_cutter(input.cutter)?;
    let stock_err = |e: crate::simulation::SimError| ForceRunError::Stock(e.to_string());
    let dexels = stock;
    progress.set(0.2);
    let step = StepOptions::for_resolution(dexels.resolution_mm, input.cutter.flute_length);
    let mut plan = plan_toolpath(input.toolpath, &step).map_err(stock_err)?;
    let programmed_moves = path_moves(&plan, |_| input.spindle_rpm);
    let clock = input
        .pose_time_s
        .filter(|c| c.len() == input.toolpath.poses.len());
    if let Some(c) = clock {
        for m in &mut plan.moves {
            if let (Some(t1), Some(t0)) = (
                c.get(m.block),
                m.block.checked_sub(1).and_then(|k| c.get(k)),
            ) && t1 > t0
            {
                m.duration_s = t1 - t0;
            }
        }
    }
    let pose_time_s = match clock {
        Some(c) => c.to_vec(),
        None => programmed_clock(&plan, input.toolpath.poses.len()),
    };
    let moves = path_moves(&plan, |_| input.spindle_rpm);
    let options = PathOptions {
        flute_length_mm: input.cutter.flute_length,
        sample: SampleOptions::default(),
        limits: input.limits,
        ..PathOptions::default()
    };
    let mut work = Watched {
        inner: SimulatedStock::new(dexels, input.cutter, &plan),
        progress,
        moves: moves.len(),
    };
    let forces = match path_forces(&mut work, &mill, input.coefficients, &moves, &options) {
        Err(_) if progress.is_cancelled() => return Err(ForceRunError::Cancelled),
        r => r?,
    };
    let samples = samples(&forces, &moves, &pose_time_s);
    Ok(ForceTimeline {
        forces,
        samples,
        pose_time_s,
        planned_time: clock.is_some(),
        limits: input.limits,
        moves: programmed_moves,
    })
}

/// The time each pose is reached at the plan's move durations (programmed feeds).
fn programmed_clock(plan: &crate::simulation::MovePlan, poses: usize) -> Vec<f64> {
    let mut t = vec![0.0; poses];
    let mut now = 0.0;
    for m in &plan.moves {
        now += m.duration_s;
        if let Some(slot) = t.get_mut(m.block) {
            *slot = now;
        }
    }
    // Poses no move reaches keep the time of the pose before them.
    for k in 1..t.len() {
        if t[k] < t[k - 1] {
            t[k] = t[k - 1];
        }
    }
    t
}

/// One sample per engaged piece, timed by its share of its move's length.
fn samples(
    forces: &PathForces,
    moves: &[crate::force::path::PathMove],
    clock: &[f64],
) -> Vec<ForceSample> {
    let mut out = Vec::new();
    let mut along = 0.0;
    let mut last_move = usize::MAX;
    for p in &forces.pieces {
        if p.move_index != last_move {
            along = 0.0;
            last_move = p.move_index;
        }
        let len = p.length_mm();
        let (a, b) = (along, along + len);
        along = b;
        if p.mode.is_none() {
            continue;
        }
        let Some(m) = moves.get(p.move_index) else {
            continue;
        };
        let pose = m.block;
        let t1 = clock.get(pose).copied().unwrap_or(0.0);
        let t0 = pose
            .checked_sub(1)
            .and_then(|k| clock.get(k))
            .copied()
            .unwrap_or(t1);
        let total = m.length_mm().max(1e-12);
        let at = |s: f64| t0 + (t1 - t0) * (s / total).clamp(0.0, 1.0);
        let omega = p.spindle_rpm * std::f64::consts::TAU / 60.0;
        out.push(ForceSample {
            t_s: [at(a), at(b)],
            pose,
            peak: [p.peak.fx, p.peak.fy, p.peak.fz],
            mean: [p.mean.fx, p.mean.fy, p.mean.fz],
            peak_resultant_n: p.peak_resultant_n,
            torque_nm: [p.peak_torque_nm, p.mean_torque_nm],
            power_w: [p.peak_torque_nm * omega, p.mean_torque_nm * omega],
        });
    }
    out
}

/// How the tool bends at one pose, and the wall it leaves.
#[derive(Clone, Debug, PartialEq)]
pub struct PoseDeflection {
    /// The pose.
    pub pose: usize,
    /// Index of the piece shown (the heaviest of the move into the pose) in
    /// [`PathForces::pieces`].
    pub piece: usize,
    /// Its milling mode.
    pub mode: crate::force::Mode,
    /// Rotation angle of the largest resultant, rad.
    pub phi_rad: f64,
    /// Top of the cut above the tip, mm.
    pub depth_mm: f64,
    /// The tool's deflection along the depth at that angle (x: feed, y: normal to it).
    pub deflection: Vec<crate::force::deflection::DeflectionPoint>,
    /// The wall (form) error along the depth, µm (negative: overcut).
    pub wall: Vec<crate::force::deflection::WallPoint>,
    /// The beam.
    pub beam: crate::force::deflection::BeamSpec,
}

/// The deflection profile and wall error of the heaviest engaged piece of the move into `pose`
/// (`None` when that move cuts no material), with the tool as the cantilever `beam` and
/// `points` heights from the tip to the top of the cut.
///
/// # Errors
/// [`ForceError`] for a tool without flutes, a beam out of range or a point count outside
/// 2..=10 000.
pub fn pose_deflection(
    timeline: &ForceTimeline,
    pose: usize,
    cutter: &Cutter,
    coefficients: &ModeCoefficients,
    beam: &crate::force::deflection::BeamSpec,
    points: usize,
) -> Result<Option<PoseDeflection>, ForceError> {
    use crate::force::deflection::{Cantilever, deflection_profile, peak_disk_loads, wall_profile};
    let forces = &timeline.forces;
    let block_of = |move_index: usize| {
        forces
            .moves
            .iter()
            .find(|m| m.move_index == move_index)
            .map(|m| m.block)
    };
    let heaviest = forces
        .pieces
        .iter()
        .enumerate()
        .filter(|(_, p)| p.mode.is_some() && block_of(p.move_index) == Some(pose))
        .max_by(|a, b| a.1.peak_resultant_n.total_cmp(&b.1.peak_resultant_n));
    let Some((index, piece)) = heaviest else {
        return Ok(None);
    };
    let Some(mode) = piece.mode else {
        return Ok(None);
    };
    let mill = EndMill::from_cutter(cutter)?;
    let k = coefficients.get(mode);
    let cantilever = Cantilever::end_mill(beam)?;
    let depth = piece.engagement.disks.last().map_or(0.0, |d| d.z1);
    let (phi, loads) = peak_disk_loads(&mill, k, &piece.engagement, 360);
    let deflection = deflection_profile(&cantilever, &loads, depth.min(beam.overhang), points)?;
    let wall = wall_profile(&mill, k, &piece.engagement, &cantilever, mode, points)?;
    Ok(Some(PoseDeflection {
        pose,
        piece: index,
        mode,
        phi_rad: phi,
        depth_mm: depth,
        deflection,
        wall,
        beam: *beam,
    }))
}
