//! Material removal: every step's swept cutting body is subtracted from every ray it meets;
//! the shank and holder sweeps, and the cutting body on rapids, are checked against the
//! material left and reported as collisions.
//!
//! Parallel and deterministic: steps are taken in batches; within a batch each thread owns a
//! band of rows of a ray family and applies every step of the batch, in order, to its rays.
//! A ray's result depends only on the steps in order, never on the thread; collision records
//! are merged by (move, kind) keeping the deepest, ties to the lowest (family, ray) index.

use std::collections::BTreeMap;
use std::ops::Range;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::SimError;
use super::dexel::{DexelFamily, RayAxis};
use super::motion::{MovePlan, Step};
use super::stock::DexelStock;
use super::sweep::{Body, SweepStep, general_interval, vertical_interval};
use crate::diagnostics::Progress;
use crate::geometry::Aabb;
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
            batch_steps: 256,
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

/// A step prepared for a batch: its bodies, their boxes, the move it belongs to.
struct Prepared {
    step: SweepStep,
    vertical: bool,
    rapid: bool,
    move_index: usize,
    bodies: Vec<(Body, Aabb, Option<CollisionKind>)>,
}

#[derive(Clone, Copy, Debug)]
struct Hit {
    move_index: usize,
    kind: CollisionKind,
    depth: f64,
    key: (usize, usize),
    position: DVec3,
}

impl Hit {
    fn better_than(&self, other: &Self) -> bool {
        self.depth > other.depth || (self.depth == other.depth && self.key < other.key)
    }
}

fn collision_bodies(c: &Cutter) -> Vec<(Body, CollisionKind)> {
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
    let initial = stock.volume_mm3();
    let cutting = Body::cutting(cutter);
    let guards = if opts.check_holder {
        collision_bodies(cutter)
    } else {
        Vec::new()
    };
    let mut merged: BTreeMap<(usize, CollisionKind), Hit> = BTreeMap::new();
    let batch = opts.batch_steps.max(1);
    let total = steps.len().max(1);
    for (b, chunk) in steps.chunks(batch).enumerate() {
        progress.check().map_err(|_| SimError::Cancelled)?;
        let prepared: Vec<Prepared> = chunk
            .iter()
            .map(|s| prepare(s, plan, &cutting, &guards))
            .collect();
        for (f, fam) in stock.families.iter_mut().enumerate() {
            for hit in apply_batch(fam, f, &prepared, opts.contact_tolerance_mm) {
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
        progress.set(((b + 1) * batch).min(total) as f64 / total as f64);
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
    let final_volume = stock.volume_mm3();
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
        memory_bytes: stock.memory_bytes(),
    })
}

fn prepare(
    s: &Step,
    plan: &MovePlan,
    cutting: &Body,
    guards: &[(Body, CollisionKind)],
) -> Prepared {
    let step = SweepStep {
        p0: s.from,
        p1: s.to,
        axis: s.axis,
    };
    let rapid = plan.moves.get(s.move_index).is_some_and(|m| m.rapid);
    let mut bodies = vec![(
        *cutting,
        step.bbox(cutting),
        rapid.then_some(CollisionKind::Rapid),
    )];
    for (g, k) in guards {
        bodies.push((*g, step.bbox(g), Some(*k)));
    }
    Prepared {
        vertical: step.is_vertical(),
        step,
        rapid,
        move_index: s.move_index,
        bodies,
    }
}

/// Apply a batch to one family; returns the collision hits (deepest per move and kind within
/// each band, by the same rule as the final merge).
fn apply_batch(fam: &mut DexelFamily, f: usize, batch: &[Prepared], tol: f64) -> Vec<Hit> {
    let nu = fam.nu;
    let nv = fam.nv;
    if nu == 0 || nv == 0 {
        return Vec::new();
    }
    let threads = rayon::current_num_threads().max(1);
    let rows = (nv / (threads * 4)).max(1);
    let (u, v, w) = fam.axis.axes();
    let origin = fam.origin;
    let spacing = fam.spacing;
    let geometry = fam.clone_header();
    let o = origin.to_array();
    let dir = fam.axis.direction();
    let z_family = fam.axis == RayAxis::Z;
    let hits: Vec<Vec<Hit>> = fam
        .dexels
        .par_chunks_mut(rows * nu)
        .enumerate()
        .map(|(c, band)| {
            let j0 = c * rows;
            let j1 = j0 + band.len() / nu;
            let mut hits: Vec<Hit> = Vec::new();
            for p in batch {
                for (body, bbox, kind) in &p.bodies {
                    let (lo, hi) = (bbox.min.to_array(), bbox.max.to_array());
                    let (ja, jb) = DexelFamily::cell_range(o[v], spacing, nv, lo[v], hi[v]);
                    let (ja, jb) = (ja.max(j0), jb.min(j1));
                    if ja >= jb {
                        continue;
                    }
                    let (ia, ib) = DexelFamily::cell_range(o[u], spacing, nu, lo[u], hi[u]);
                    let (s_lo, s_hi) = (lo[w] - o[w] - 1.0, hi[w] - o[w] + 1.0);
                    for j in ja..jb {
                        for i in ia..ib {
                            let Some(dexel) = band.get_mut((j - j0) * nu + i) else {
                                continue;
                            };
                            if matches!(dexel, super::dexel::Dexel::Empty) {
                                continue;
                            }
                            let ray = geometry.ray_origin(i, j);
                            let interval = if z_family && p.vertical {
                                vertical_interval(
                                    body,
                                    p.step.p0,
                                    p.step.p1,
                                    DVec2::new(ray.x, ray.y),
                                )
                                .map(|(a, b)| (a - o[w], b - o[w]))
                            } else {
                                general_interval(body, &p.step, ray, dir, s_lo, s_hi)
                            };
                            let Some((a, b)) = interval else {
                                continue;
                            };
                            #[allow(clippy::cast_possible_truncation)]
                            let (a, b) = (a as f32, b as f32);
                            if let Some(kind) = kind {
                                let depth = dexel.overlap(a, b);
                                if depth > tol
                                    && let Some([x, y]) = dexel.first_overlap(a, b)
                                {
                                    let s = 0.5 * (f64::from(x) + f64::from(y));
                                    let hit = Hit {
                                        move_index: p.move_index,
                                        kind: *kind,
                                        depth,
                                        key: (f, j * nu + i),
                                        position: ray + dir * s,
                                    };
                                    record(&mut hits, hit);
                                }
                            }
                            let cuts = match kind {
                                None => true,
                                Some(k) => *k == CollisionKind::Rapid && p.rapid,
                            };
                            if cuts {
                                dexel.subtract(a, b);
                            }
                        }
                    }
                }
            }
            hits
        })
        .collect();
    hits.into_iter().flatten().collect()
}

/// Keep the better of `hit` and the last record when they share move and kind.
fn record(hits: &mut Vec<Hit>, hit: Hit) {
    if let Some(last) = hits.last_mut()
        && last.move_index == hit.move_index
        && last.kind == hit.kind
    {
        if hit.better_than(last) {
            *last = hit;
        }
        return;
    }
    hits.push(hit);
}

impl DexelFamily {
    /// The grid description without the rays.
    fn clone_header(&self) -> Self {
        Self {
            axis: self.axis,
            origin: self.origin,
            spacing: self.spacing,
            nu: self.nu,
            nv: self.nv,
            dexels: Vec::new(),
        }
    }
}
