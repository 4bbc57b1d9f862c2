//! "Stock here" without re-cutting the whole path: while the whole simulation of a set of paths
//! runs, copies of the stock (keyframes) are kept at move boundaries of the last path, spaced
//! evenly in steps and bounded in memory. The stock at a pose is then the nearest keyframe at
//! or before it, cut by the moves from there to the pose only.
//!
//! The pieces run as one whole run does (the first step of a piece continues the step before
//! it, collisions are merged per move), so the stock, volumes and collisions at a pose are bit
//! for bit those of simulating the path cut at that pose from the start
//! ([`super::simulate::simulate_toolpaths`]).

use super::Stock;
use super::simulate::{Simulated, SimulationSettings, cut_path, measured, stock_grid};
use crate::diagnostics::Progress;
use crate::geometry::Aabb;
use crate::geometry::mesh::TriMesh;
use crate::simulation::{
    Continued, DexelStock, MovePlan, SimError, SimOptions, SimReport, StepOptions, plan_toolpath,
    run_moves,
};
use crate::toolpath::Toolpath;
use crate::tools::Cutter;

/// Memory the keyframes may take by default, bytes (256 MiB).
pub const DEFAULT_KEYFRAME_BYTES: u64 = 256 << 20;

/// Most keyframes kept (the pieces re-cut are then at most 1/64 of the last path's steps).
pub const MAX_KEYFRAMES: usize = 64;

/// What a set of keyframes was cut from.
#[derive(Clone, Debug, PartialEq)]
struct Inputs {
    stock: Stock,
    part_box: Aabb,
    paths: Vec<(Toolpath, Cutter)>,
    settings: SimulationSettings,
}

/// The stock just before one move of the last path.
#[derive(Clone, Debug)]
struct Keyframe {
    /// Moves of the last path cut into `stock`.
    moves: usize,
    stock: DexelStock,
    /// The last path's report over those moves.
    report: SimReport,
}

/// Keyframes of one simulation (see the module documentation).
#[derive(Clone, Debug)]
pub struct StockKeyframes {
    inputs: Inputs,
    /// The last path's moves.
    plan: MovePlan,
    /// Reports of the paths before the last.
    earlier: Vec<SimReport>,
    frames: Vec<Keyframe>,
}

impl StockKeyframes {
    /// Were these keyframes cut from these inputs?
    #[must_use]
    pub fn matches(
        &self,
        stock: &Stock,
        part: &TriMesh,
        paths: &[(&Toolpath, &Cutter)],
        settings: &SimulationSettings,
    ) -> bool {
        let i = &self.inputs;
        i.stock == *stock
            && i.part_box == part.bbox()
            && i.settings == *settings
            && i.paths.len() == paths.len()
            && i.paths
                .iter()
                .zip(paths)
                .all(|((t, c), (t2, c2))| t == *t2 && c == *c2)
    }

    /// Number of keyframes.
    #[must_use]
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// No keyframe kept?
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Bytes the keyframes' stocks hold.
    #[must_use]
    pub fn memory_bytes(&self) -> u64 {
        self.frames.iter().map(|f| f.stock.memory_bytes()).sum()
    }

    /// Most steps re-cut by [`stock_here`] (the longest stretch between keyframes).
    #[must_use]
    pub fn max_gap_steps(&self) -> usize {
        let first = |m: usize| {
            self.plan
                .moves
                .get(m)
                .map_or(self.plan.steps.len(), |mv| mv.first_step)
        };
        let mut ends: Vec<usize> = self.frames.iter().map(|f| first(f.moves)).collect();
        ends.push(self.plan.steps.len());
        ends.windows(2)
            .map(|w| w[1].saturating_sub(w[0]))
            .max()
            .unwrap_or(0)
    }
}

/// [`super::simulate::simulate_toolpaths`], keeping keyframes of the last path within
/// `budget_bytes` (at most [`MAX_KEYFRAMES`]; the first, the stock before the last path, is
/// always kept) for [`stock_here`].
///
/// # Errors
/// As [`super::simulate::simulate_toolpaths`].
pub fn simulate_with_keyframes(
    stock: &Stock,
    part: &TriMesh,
    paths: &[(&Toolpath, &Cutter)],
    settings: &SimulationSettings,
    budget_bytes: u64,
    progress: &Progress,
) -> Result<(Simulated, StockKeyframes), SimError> {
    let Some(((last_path, last_cutter), before)) = paths.split_last() else {
        return Err(SimError::Options("no tool path to simulate".into()));
    };
    let (mut dexels, resolution) = stock_grid(stock, part, settings)?;
    let mut earlier = Vec::with_capacity(before.len());
    for (toolpath, cutter) in before {
        earlier.push(cut_path(
            &mut dexels,
            resolution,
            toolpath,
            cutter,
            progress,
        )?);
    }
    let step = StepOptions::for_resolution(resolution, last_cutter.flute_length);
    let plan = plan_toolpath(last_path, &step)?;
    let count = frame_count(&dexels, budget_bytes);
    let starts = frame_moves(&plan, count);
    let mut frames = Vec::with_capacity(starts.len());
    let mut report = empty_report(&dexels);
    let mut used = 0u64;
    let total = plan.moves.len();
    let mut cut = 0;
    for &m in starts.iter().chain(std::iter::once(&total)) {
        if m > cut {
            let share = fraction(cut, total)..fraction(m, total);
            let piece = cut_piece(&mut dexels, last_cutter, &plan, cut..m, share, progress)?;
            report = joined(&report, &piece, &plan, m);
            cut = m;
        }
        if m < total {
            let bytes = dexels.memory_bytes();
            while frames.len() > 1 && used + bytes > budget_bytes {
                used -= thin(&mut frames, &plan, m);
            }
            if frames.is_empty() || used + bytes <= budget_bytes {
                used += bytes;
                frames.push(Keyframe {
                    moves: m,
                    stock: dexels.clone(),
                    report: report.clone(),
                });
            }
        }
    }
    let mut reports = earlier.clone();
    reports.push(report);
    let simulated = measured(&dexels, part, reports, progress)?;
    let inputs = Inputs {
        stock: *stock,
        part_box: part.bbox(),
        paths: paths
            .iter()
            .map(|(t, c)| ((*t).clone(), (*c).clone()))
            .collect(),
        settings: *settings,
    };
    let keyframes = StockKeyframes {
        inputs,
        plan,
        earlier,
        frames,
    };
    Ok((simulated, keyframes))
}

/// The stock after the last path is cut up to pose `pose` (its moves ending at poses ≤ `pose`),
/// measured against `part`: the same result as [`super::simulate::simulate_toolpaths`] on the
/// last path cut at that pose, from the nearest keyframe.
///
/// # Errors
/// [`SimError::Options`] when no keyframe lies at or before the pose, [`SimError::Cancelled`],
/// and the deviation's errors.
pub fn stock_here(
    keyframes: &StockKeyframes,
    part: &TriMesh,
    pose: usize,
    progress: &Progress,
) -> Result<Simulated, SimError> {
    let plan = &keyframes.plan;
    let end = plan.moves.partition_point(|m| m.block <= pose);
    let frame = keyframes
        .frames
        .iter()
        .rev()
        .find(|f| f.moves <= end)
        .ok_or_else(|| SimError::Options(format!("no stock keyframe at or before pose {pose}")))?;
    let Some((_, cutter)) = keyframes.inputs.paths.last() else {
        return Err(SimError::Options("no tool path to simulate".into()));
    };
    let mut dexels = frame.stock.clone();
    let piece = cut_piece(
        &mut dexels,
        cutter,
        plan,
        frame.moves..end,
        0.0..1.0,
        progress,
    )?;
    let mut reports = keyframes.earlier.clone();
    reports.push(joined(&frame.report, &piece, plan, end));
    measured(&dexels, part, reports, progress)
}

/// Cut moves `range` of `plan`, continuing the moves before it.
fn cut_piece(
    dexels: &mut DexelStock,
    cutter: &Cutter,
    plan: &MovePlan,
    range: std::ops::Range<usize>,
    share: std::ops::Range<f64>,
    progress: &Progress,
) -> Result<SimReport, SimError> {
    let continued = Continued {
        after_earlier_moves: range.start > 0,
        progress: share,
    };
    run_moves(
        dexels,
        cutter,
        plan,
        range,
        &SimOptions::default(),
        progress,
        &continued,
    )
}

/// Drop the keyframe (never the first) whose neighbours are closest in steps, with a keyframe
/// about to be kept before move `next`; returns the bytes freed.
fn thin(frames: &mut Vec<Keyframe>, plan: &MovePlan, next: usize) -> u64 {
    let step = |m: usize| {
        plan.moves
            .get(m)
            .map_or(plan.steps.len(), |mv| mv.first_step)
    };
    let after = |i: usize| frames.get(i + 1).map_or(next, |f| f.moves);
    let drop = (1..frames.len()).min_by_key(|&i| {
        step(after(i)).saturating_sub(frames.get(i - 1).map_or(0, |f| step(f.moves)))
    });
    drop.map_or(0, |i| frames.remove(i).stock.memory_bytes())
}

/// How many keyframes fit `budget_bytes` at the stock's present size.
fn frame_count(dexels: &DexelStock, budget_bytes: u64) -> usize {
    let each = dexels.memory_bytes().max(1);
    usize::try_from(budget_bytes / each).map_or(MAX_KEYFRAMES, |n| n.clamp(1, MAX_KEYFRAMES))
}

/// The moves before which `count` keyframes are kept: the first move, then the move starting
/// nearest after every 1/`count` of the steps.
fn frame_moves(plan: &MovePlan, count: usize) -> Vec<usize> {
    let steps = plan.steps.len();
    let mut out: Vec<usize> = Vec::with_capacity(count);
    for k in 0..count {
        let target = steps * k / count.max(1);
        let m = plan.moves.partition_point(|mv| mv.first_step < target);
        if m < plan.moves.len() && out.last().is_none_or(|&l| l < m) {
            out.push(m);
        }
    }
    out
}

#[allow(clippy::cast_precision_loss)]
fn fraction(m: usize, total: usize) -> f64 {
    m as f64 / total.max(1) as f64
}

/// A report of no moves on `dexels`.
fn empty_report(dexels: &DexelStock) -> SimReport {
    let v = dexels.volume_mm3();
    SimReport {
        initial_volume_mm3: v,
        final_volume_mm3: v,
        removed_volume_mm3: 0.0,
        collisions: Vec::new(),
        moves: 0,
        steps: 0,
        time_s: 0.0,
        memory_bytes: dexels.memory_bytes(),
    }
}

/// The report of moves `0..end` from that of the moves before `piece` and `piece`'s, summed as
/// one run over `0..end` sums them.
fn joined(head: &SimReport, piece: &SimReport, plan: &MovePlan, end: usize) -> SimReport {
    let mut collisions = head.collisions.clone();
    collisions.extend(piece.collisions.iter().copied());
    SimReport {
        initial_volume_mm3: head.initial_volume_mm3,
        final_volume_mm3: piece.final_volume_mm3,
        removed_volume_mm3: head.initial_volume_mm3 - piece.final_volume_mm3,
        collisions,
        moves: head.moves + piece.moves,
        steps: head.steps + piece.steps,
        time_s: plan
            .moves
            .get(..end)
            .map_or(0.0, |m| m.iter().map(|m| m.duration_s).sum()),
        memory_bytes: piece.memory_bytes,
    }
}
