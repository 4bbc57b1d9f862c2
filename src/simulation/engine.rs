//! Material removal: every step's swept cutting body is subtracted from every ray it meets;
//! the shank and holder sweeps, and the cutting body on rapids, are checked against the
//! material left and reported as collisions.
//!
//! Parallel and deterministic: steps are taken in batches; within a batch each parallel task
//! owns a square of rays of a ray family and applies every step of the batch, in order, to
//! its rays (see `batch`). A ray's result depends only on the steps in order, never on the
//! thread; collision records are merged by (move, kind) keeping the deepest, ties to the
//! lowest (family, ray) index.

use std::collections::BTreeMap;
use std::ops::Range;

use glam::DVec3;

use super::SimError;
use super::batch::{Batch, Cull, apply_batch};
use super::motion::MovePlan;
use super::stock::DexelStock;
use super::sweep::Body;
use crate::diagnostics::Progress;
use crate::tools::Cutter;

/// What hit the material.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CollisionKind {
    /// The cutting end moved through material on a rapid (G0) move.
    Rapid,
    /// The shank (above the flutes) met material.
    Shank,
    /// A holder section met material.
    Holder,
}

/// One collision: the deepest contact of one kind during one move.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Collision {
    /// What hit.
    pub kind: CollisionKind,
    /// Index of the move in the plan.
    pub move_index: usize,
    /// The move's block (G-code line or tool-path pose index).
    pub block: usize,
    /// A point of the material hit (middle of the deepest ray's overlap), mm.
    pub position: DVec3,
    /// Length of material inside the body along that ray, mm.
    pub depth_mm: f64,
}

/// Settings of the removal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimOptions {
    /// Overlaps shorter than this along a ray are contact, not collision, mm.
    pub contact_tolerance_mm: f64,
    /// Check shank and holder against the material.
    pub check_holder: bool,
    /// Steps per parallel batch.
    pub batch_steps: usize,
}

impl Default for SimOptions {
    fn default() -> Self {
        Self {
            contact_tolerance_mm: 1e-3,
            check_holder: true,
            batch_steps: 1024,
        }
    }
}

/// What a simulation run did.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SimReport {
    /// Stock volume before, mm³.
    pub initial_volume_mm3: f64,
    /// Stock volume after, mm³.
    pub final_volume_mm3: f64,
    /// Removed volume, mm³.
    pub removed_volume_mm3: f64,
    /// Collisions, by move then kind.
    pub collisions: Vec<Collision>,
    /// Moves simulated.
    pub moves: usize,
    /// Steps simulated.
    pub steps: usize,
    /// Time of the moves at their programmed feeds, s.
    pub time_s: f64,
    /// Memory held by the stock afterwards, bytes.
    pub memory_bytes: u64,
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Hit {
    pub(super) move_index: usize,
    pub(super) kind: CollisionKind,
    pub(super) depth: f64,
    pub(super) key: (usize, usize),
    pub(super) position: DVec3,
}

impl Hit {
    pub(super) fn better_than(&self, other: &Self) -> bool {
        self.depth > other.depth || (self.depth == other.depth && self.key < other.key)
    }
}

pub(super) fn collision_bodies(c: &Cutter) -> Vec<(Body, CollisionKind)> {
    let mut out = Vec::new();
    if c.overall_length > c.flute_length {
        out.push((
            Body::Cylinder {
                radius: 0.5 * c.shank_diameter,
                z0: c.flute_length,
                z1: c.overall_length,
            },
            CollisionKind::Shank,
        ));
    }
    let mut z = c.overall_length;
    for h in &c.holder {
        out.push((
            Body::Cylinder {
                radius: 0.5 * h.diameter,
                z0: z,
                z1: z + h.length,
            },
            CollisionKind::Holder,
        ));
        z += h.length;
    }
    out
}

/// Simulate every move of `plan` on `stock`.
///
/// # Errors
/// As [`simulate_moves`].
pub fn simulate(
    stock: &mut DexelStock,
    cutter: &Cutter,
    plan: &MovePlan,
    opts: &SimOptions,
    progress: &Progress,
) -> Result<SimReport, SimError> {
    simulate_moves(stock, cutter, plan, 0..plan.moves.len(), opts, progress)
}

/// Simulate the moves `range` of `plan` on `stock` (call again with the next range to play
/// back in pieces). Progress goes from 0 to 1 over the range; a cancel stops between batches
/// with the stock partly cut.
///
/// # Errors
/// [`SimError::Tool`] for an invalid cutter, [`SimError::Options`] for a move range outside
/// the plan or bad options, [`SimError::Cancelled`] when cancelled.
pub fn simulate_moves(
    stock: &mut DexelStock,
    cutter: &Cutter,
    plan: &MovePlan,
    range: Range<usize>,
    opts: &SimOptions,
    progress: &Progress,
) -> Result<SimReport, SimError> {
    run_moves(
        stock,
        cutter,
        plan,
        range,
        opts,
        progress,
        &Continued::default(),
    )
}

/// How a run of moves continues an earlier one on the same stock.
#[derive(Clone, Debug)]
pub(crate) struct Continued {
    /// The moves before the range were cut on this stock, in order, by the same cutter (the
    /// first step may continue the step before it, as in one whole run).
    pub(crate) after_earlier_moves: bool,
    /// The share of the progress bar this run fills.
    pub(crate) progress: Range<f64>,
}

impl Default for Continued {
    fn default() -> Self {
        Self {
            after_earlier_moves: false,
            progress: 0.0..1.0,
        }
    }
}

/// What a stock keeps between runs of moves cut into it one after the other (the virtual
/// control's live cutting: thousands of runs of a step or two): per ray family the culling
/// tiles, each with the extent and the summed length of its material, brought up to date by
/// every run for the tiles it changes. A run then costs what its steps touch instead of a
/// pass over the whole stock to make the tiles (and two more for its volume before and
/// after), and the stock's volume is read off the tiles. The tiles are the ones a fresh run
/// would make, so the stock and the collisions are the same bit for bit; the volume is
/// summed tile by tile (deterministic, within rounding of [`DexelStock::volume_mm3`]).
///
/// Valid while only [`run_moves_cached`] changes the stock (it is made again when the grid
/// no longer fits).
#[derive(Clone, Debug)]
pub(crate) struct StockCache {
    culls: Vec<Cull>,
}

impl StockCache {
    /// The tiles of `stock` as it is now (one pass over every ray).
    pub(crate) fn new(stock: &DexelStock) -> Self {
        Self {
            culls: stock.families.iter().map(Cull::new).collect(),
        }
    }

    fn fits(&self, stock: &DexelStock) -> bool {
        self.culls.len() == stock.families.len()
            && self
                .culls
                .iter()
                .zip(&stock.families)
                .all(|(c, f)| c.fits(f))
    }

    /// The stock's material volume from the tiles, mm³ (a tri-dexel stock: the mean of its
    /// three families, as [`DexelStock::volume_mm3`]).
    pub(crate) fn volume_mm3(&self, stock: &DexelStock) -> f64 {
        #[allow(clippy::cast_precision_loss)]
        let n = stock.families.len().max(1) as f64;
        self.culls
            .iter()
            .zip(&stock.families)
            .map(|(c, f)| c.material_length() * f.spacing * f.spacing)
            .sum::<f64>()
            / n
    }
}

/// [`simulate_moves`] as a piece of a longer run: the stock and collisions are those of the
/// whole run, bit for bit, when the pieces are run in order.
pub(crate) fn run_moves(
    stock: &mut DexelStock,
    cutter: &Cutter,
    plan: &MovePlan,
    range: Range<usize>,
    opts: &SimOptions,
    progress: &Progress,
    continued: &Continued,
) -> Result<SimReport, SimError> {
    let initial = stock.volume_mm3();
    let mut cache = StockCache::new(stock);
    let mut report = run_moves_cached(
        stock, cutter, plan, range, opts, progress, continued, &mut cache,
    )?;
    let final_volume = stock.volume_mm3();
    report.initial_volume_mm3 = initial;
    report.final_volume_mm3 = final_volume;
    report.removed_volume_mm3 = initial - final_volume;
    report.memory_bytes = stock.memory_bytes();
    Ok(report)
}

/// [`run_moves`] on a stock whose tiles `cache` keeps between runs (made again when it no
/// longer fits the stock's grid). The report's volumes are the cache's
/// ([`StockCache::volume_mm3`]) and its `memory_bytes` is 0 (counting it visits every ray).
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_moves_cached(
    stock: &mut DexelStock,
    cutter: &Cutter,
    plan: &MovePlan,
    range: Range<usize>,
    opts: &SimOptions,
    progress: &Progress,
    continued: &Continued,
    cache: &mut StockCache,
) -> Result<SimReport, SimError> {
    cutter
        .validate()
        .map_err(|e| SimError::Tool(e.to_string()))?;
    if range.start > range.end || range.end > plan.moves.len() {
        return Err(SimError::Options(format!(
            "move range {range:?} outside the plan's {} moves",
            plan.moves.len()
        )));
    }
    if !(opts.contact_tolerance_mm >= 0.0) {
        return Err(SimError::Options("contact tolerance must be ≥ 0".into()));
    }
    let step_range = {
        let first = |m: usize| {
            plan.moves
                .get(m)
                .map_or(plan.steps.len(), |mv| mv.first_step)
        };
        first(range.start)..first(range.end)
    };
    let steps = plan.steps.get(step_range.clone()).unwrap_or(&[]);
    if !cache.fits(stock) {
        *cache = StockCache::new(stock);
    }
    let initial = cache.volume_mm3(stock);
    let cutting = Body::cutting(cutter);
    let guards = if opts.check_holder {
        collision_bodies(cutter)
    } else {
        Vec::new()
    };
    let mut merged: BTreeMap<(usize, CollisionKind), Hit> = BTreeMap::new();
    let batch = opts.batch_steps.max(1);
    let total = steps.len().max(1);
    let mut prepared = Batch::default();
    let bounds = stock.bounds;
    for (b, chunk) in steps.chunks(batch).enumerate() {
        progress.check().map_err(|_| SimError::Cancelled)?;
        let before = match (b * batch).checked_sub(1) {
            Some(k) => steps.get(k),
            None if continued.after_earlier_moves => step_range
                .start
                .checked_sub(1)
                .and_then(|k| plan.steps.get(k)),
            None => None,
        };
        prepared.fill(chunk, before, plan, &cutting, &guards, &bounds);
        for (f, (fam, cull)) in stock.families.iter_mut().zip(&mut cache.culls).enumerate() {
            for hit in apply_batch(fam, f, &prepared, cull, opts.contact_tolerance_mm) {
                let key = (hit.move_index, hit.kind);
                match merged.get(&key) {
                    Some(old) if !hit.better_than(old) => {}
                    _ => {
                        merged.insert(key, hit);
                    }
                }
            }
        }
        #[allow(clippy::cast_precision_loss)]
        let done = ((b + 1) * batch).min(total) as f64 / total as f64;
        let share = &continued.progress;
        progress.set(share.start + done * (share.end - share.start));
    }
    let collisions = merged
        .into_values()
        .map(|h| Collision {
            kind: h.kind,
            move_index: h.move_index,
            block: plan.moves.get(h.move_index).map_or(0, |m| m.block),
            position: h.position,
            depth_mm: h.depth,
        })
        .collect();
    let final_volume = cache.volume_mm3(stock);
    Ok(SimReport {
        initial_volume_mm3: initial,
        final_volume_mm3: final_volume,
        removed_volume_mm3: initial - final_volume,
        collisions,
        moves: range.len(),
        steps: steps.len(),
        time_s: plan
            .moves
            .get(range)
            .map_or(0.0, |m| m.iter().map(|m| m.duration_s).sum()),
        memory_bytes: 0,
    })
}
