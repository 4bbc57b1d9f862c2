//! One batch of steps applied to one ray family: the hot path of the removal.
//!
//! - Each step's bodies are prepared once per batch (no allocation per step: the batch's
//!   buffers are reused): clipped to the part of the tool that can reach the stock's box
//!   (the rest of a long tool only meets air), their boxes, and for a vertical tool over Z
//!   rays the footprint's row spans (the stadium of the tool radius around the tip's path).
//! - For each ray family, a tilted body's sweep is prepared for the family's rays once (the
//!   sweep bounds and exact-interval constants of `sweep::Prepared`, the shadow's row spans),
//!   `SWEEP_STEPS` steps at a time (their buffers allocated once per part), and shared by
//!   every task; the sweep bounds are taken along each row of rays once, when its first ray
//!   needs them.
//! - The grid is cut into square tasks of `TASK` rays; rayon runs the tasks in parallel, each
//!   applying every step of the batch, in order, to its own rays (disjoint slices, no locks).
//!   A ray's result depends only on the steps in order, never on the thread count.
//! - Every `CULL` × `CULL` tile keeps the extent of its material along the ray (an outer
//!   bound, tightened after each batch): a body whose extent along the ray misses it skips
//!   the whole tile (holders and shanks above the stock, rapids through air).
//! - Per ray, the material already below the body's lowest point (or, for a ball end mill
//!   on Z rays, a top that the swept sphere would lower by less than `REJECT_MM`, by a test
//!   without square roots) is passed over before any interval is computed.

use std::ops::Range;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::ballrow::{BallStep, LANES, cut_below};
use super::dexel::{Dexel, DexelFamily};
use super::engine::{CollisionKind, Hit};
use super::exact::{StadiumEdge, disc_span, stadium_span};
use super::motion::{MovePlan, Step};
use super::sweep::{Body, Prepared, PreparedRow, SweepStep, general_interval, vertical_interval};
use crate::geometry::Aabb;

/// Rays per side of a culling tile (the tiles a family's volume is summed by).
const CULL: usize = super::dexel::VOLUME_TILE;
/// Rays per side of a parallel task (a multiple of `CULL`).
const TASK: usize = 32;
/// Culling tiles per task side.
const CPT: usize = TASK / CULL;
/// Work items (tasks × steps, bodies, shadow rows) up to which a batch runs on the calling
/// thread instead of the pool.
const SMALL_WORK: usize = 32;
/// Steps whose bodies' sweeps are prepared at a time (and held: a few kB each).
const SWEEP_STEPS: usize = 256;
/// A ball end mill's step that would take less than this off a Z ray's top passes the ray
/// over (the quick test of `ray`; it spares the exact interval on the rays the previous
/// step already cut to the same surface), mm.
const REJECT_MM: f64 = 1e-4;

/// A body of one step, ready for the rays.
#[derive(Clone, Copy, Debug)]
struct PBody {
    body: Body,
    /// Collision kind checked (None: the cutting end on a feed move).
    kind: Option<CollisionKind>,
    /// Whether it removes material.
    cuts: bool,
    bbox: Aabb,
    /// Ball end mill whose top is out of the stock's box (nothing above it to cut): the
    /// segment of sphere centres and the radius, for the quick tests.
    ball: Option<(DVec3, DVec3, f64)>,
    /// Ball end mill on a vertical feed step: the row kernel's constants (Z rays).
    fast: Option<BallStep>,
}

/// A step of the batch.
#[derive(Clone, Debug)]
struct PStep {
    step: SweepStep,
    vertical: bool,
    /// The step before it, in this run, ended at this step's start with the same axis (so a
    /// ball's rear half-disc was cut to the sphere at the start: see `rear_chord`).
    chained: bool,
    move_index: usize,
    bodies: Range<usize>,
}

/// The steps of one batch and their bodies (buffers reused from batch to batch).
pub(super) struct Batch {
    steps: Vec<PStep>,
    bodies: Vec<PBody>,
    bbox: Aabb,
}

impl Default for Batch {
    fn default() -> Self {
        Self {
            steps: Vec::new(),
            bodies: Vec::new(),
            bbox: Aabb::EMPTY,
        }
    }
}

/// Axial heights `[lo, hi]` at which a body of radius `r` on the step can touch the box `b`
/// (a conservative range: outside it the body is in air); `None` when it never can.
fn heights_in_box(step: &SweepStep, r: f64, b: &Aabb) -> Option<(f64, f64)> {
    let (a, p0, p1) = (step.axis.to_array(), step.p0.to_array(), step.p1.to_array());
    let (lo_b, hi_b) = (b.min.to_array(), b.max.to_array());
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        let ak = a[k];
        let ext = r * (1.0 - ak * ak).max(0.0).sqrt() + 1e-3;
        let (t_min, t_max) = (p0[k].min(p1[k]), p0[k].max(p1[k]));
        // Some tip puts the section's centre within [lo_b − ext, hi_b + ext]:
        // t_min + h·a ≤ hi_b + ext and t_max + h·a ≥ lo_b − ext.
        let (up, down) = (hi_b[k] + ext - t_min, lo_b[k] - ext - t_max);
        if ak.abs() < 1e-12 {
            if up < 0.0 || down > 0.0 {
                return None;
            }
        } else if ak > 0.0 {
            hi = hi.min(up / ak);
            lo = lo.max(down / ak);
        } else {
            lo = lo.max(up / ak);
            hi = hi.min(down / ak);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

impl Batch {
    /// Prepare `chunk`'s steps: bodies clipped to the stock's box `bounds`, their boxes.
    pub(super) fn fill(
        &mut self,
        chunk: &[Step],
        before: Option<&Step>,
        plan: &MovePlan,
        cutting: &Body,
        guards: &[(Body, CollisionKind)],
        bounds: &Aabb,
    ) {
        self.steps.clear();
        self.bodies.clear();
        self.bbox = Aabb::EMPTY;
        let mut prev = before;
        for s in chunk {
            let chained = prev.is_some_and(|q| q.to == s.from && q.axis == s.axis);
            prev = Some(s);
            let step = SweepStep {
                p0: s.from,
                p1: s.to,
                axis: s.axis,
            };
            let rapid = plan.moves.get(s.move_index).is_some_and(|m| m.rapid);
            let first = self.bodies.len();
            let all = std::iter::once((*cutting, rapid.then_some(CollisionKind::Rapid)))
                .chain(guards.iter().map(|(g, k)| (*g, Some(*k))));
            for (body, kind) in all {
                let Some((lo, hi)) = heights_in_box(&step, body.radius(), bounds) else {
                    continue;
                };
                if hi < body.bottom() || lo > body.top() {
                    continue;
                }
                let Some(body) = body.clipped(lo, hi) else {
                    continue;
                };
                let bbox = step.bbox(&body);
                self.bbox.union(&bbox);
                // Only when the tool's top is out of the box (no material above it).
                let ball = match body {
                    Body::Cutting {
                        radius,
                        flat,
                        corner,
                        cone_tan,
                        ..
                    } if flat == 0.0 && cone_tan == 0.0 && corner == radius => {
                        let lift = step.axis * radius;
                        Some((step.p0 + lift, step.p1 + lift, radius))
                    }
                    _ => None,
                }
                .filter(|_| body.top() < cutting.top());
                let fast = match body {
                    Body::Cutting {
                        radius,
                        flat,
                        corner,
                        cone_tan,
                        top,
                    } if flat == 0.0
                        && cone_tan == 0.0
                        && corner == radius
                        && kind.is_none()
                        && step.is_vertical() =>
                    {
                        Some(BallStep::new(step.p0, step.p1, radius, top))
                    }
                    _ => None,
                };
                self.bodies.push(PBody {
                    body,
                    kind,
                    cuts: kind.is_none() || kind == Some(CollisionKind::Rapid),
                    bbox,
                    ball,
                    fast,
                });
            }
            if self.bodies.len() > first {
                self.steps.push(PStep {
                    vertical: step.is_vertical(),
                    chained,
                    step,
                    move_index: s.move_index,
                    bodies: first..self.bodies.len(),
                });
            }
        }
    }
}

/// Per culling tile of a family: the material's extent along the ray, `[lo, hi]` (an outer
/// bound; `[∞, −∞]` when the tile holds nothing), and the summed length of its rays' material
/// (mm, summed in ray order), both brought up to date for every tile a batch changes: a
/// `Cull` kept between runs on the same stock is the one [`Cull::new`] would make again, and
/// the stock's volume follows from the tiles without visiting every ray.
#[derive(Clone, Debug)]
pub(super) struct Cull {
    /// Tiles along u.
    nu: usize,
    ranges: Vec<[f32; 2]>,
    lengths: Vec<f64>,
}

/// The extent along the ray of the material of `rays`, and its summed length (in order).
fn tile_extent<'a>(rays: impl Iterator<Item = &'a Dexel>) -> ([f32; 2], f64) {
    let mut e = [f32::INFINITY, f32::NEG_INFINITY];
    let mut length = 0.0;
    for d in rays {
        if let (Some([a, _]), Some([_, b])) = (d.intervals().first(), d.intervals().last()) {
            e = [e[0].min(*a), e[1].max(*b)];
            length += d.length();
        }
    }
    (e, length)
}

impl Cull {
    /// The tiles of `fam` as it is now.
    pub(super) fn new(fam: &DexelFamily) -> Self {
        let (nu, nv) = (fam.nu.div_ceil(CULL), fam.nv.div_ceil(CULL));
        let tiles: Vec<([f32; 2], f64)> = (0..nu * nv)
            .into_par_iter()
            .map(|k| {
                let (ci, cj) = (k % nu, k / nu);
                let (i0, i1) = (ci * CULL, ((ci + 1) * CULL).min(fam.nu));
                let rows = cj * CULL..((cj + 1) * CULL).min(fam.nv);
                tile_extent(rows.flat_map(|j| {
                    fam.dexels
                        .get(j * fam.nu + i0..j * fam.nu + i1)
                        .unwrap_or(&[])
                        .iter()
                }))
            })
            .collect();
        let (ranges, lengths) = tiles.into_iter().unzip();
        Self {
            nu,
            ranges,
            lengths,
        }
    }

    /// The summed material length of the family's rays, mm, tile by tile in tile order (times
    /// the cell area: [`DexelFamily::volume`] to the bit).
    pub(super) fn material_length(&self) -> f64 {
        let mut total = 0.0;
        for l in &self.lengths {
            total += l;
        }
        total
    }

    /// Whether this was made for a family of `fam`'s grid.
    pub(super) fn fits(&self, fam: &DexelFamily) -> bool {
        self.nu == fam.nu.div_ceil(CULL) && self.ranges.len() == self.nu * fam.nv.div_ceil(CULL)
    }
}

/// The family's grid, copied for the tasks.
#[derive(Clone, Copy)]
struct Grid {
    o: [f64; 3],
    spacing: f64,
    nu: usize,
    nv: usize,
    uvw: (usize, usize, usize),
    dir: DVec3,
    z_family: bool,
    family: usize,
    tol: f64,
}

impl Grid {
    fn ray_origin(&self, i: usize, j: usize) -> DVec3 {
        let (u, v, _) = self.uvw;
        let mut p = self.o;
        #[allow(clippy::cast_precision_loss)]
        let (fi, fj) = (i as f64 + 0.5, j as f64 + 0.5);
        if let Some(x) = p.get_mut(u) {
            *x += fi * self.spacing;
        }
        if let Some(x) = p.get_mut(v) {
            *x += fj * self.spacing;
        }
        DVec3::from_array(p)
    }
}

/// A square of the grid owned by one parallel task: its rows, each a slice of `i0..i1`.
struct Task<'a> {
    i0: usize,
    j0: usize,
    rows: Vec<&'a mut [Dexel]>,
}

/// What a task gives back: collision hits and the new extents of the tiles it changed.
type TaskOut = (Vec<Hit>, Vec<(usize, ([f32; 2], f64))>);

/// Apply a batch to one family (index `f`); returns the collision hits (deepest per move and
/// kind within each task, by the same rule as the final merge).
pub(super) fn apply_batch(
    fam: &mut DexelFamily,
    f: usize,
    batch: &Batch,
    cull: &mut Cull,
    tol: f64,
) -> Vec<Hit> {
    let (nu, nv) = (fam.nu, fam.nv);
    if nu == 0 || nv == 0 || batch.steps.is_empty() {
        return Vec::new();
    }
    let (u, v, w) = fam.axis.axes();
    let grid = Grid {
        o: fam.origin.to_array(),
        spacing: fam.spacing,
        nu,
        nv,
        uvw: (u, v, w),
        dir: fam.axis.direction(),
        z_family: fam.axis == super::dexel::RayAxis::Z,
        family: f,
        tol,
    };
    let (lo, hi) = (batch.bbox.min.to_array(), batch.bbox.max.to_array());
    let (ja, jb) = DexelFamily::cell_range(grid.o[v], grid.spacing, nv, lo[v], hi[v]);
    let (ia, ib) = DexelFamily::cell_range(grid.o[u], grid.spacing, nu, lo[u], hi[u]);
    if ja >= jb || ia >= ib {
        return Vec::new();
    }
    let (tja, tjb) = (ja / TASK, jb.div_ceil(TASK));
    let (tia, tib) = (ia / TASK, ib.div_ceil(TASK));
    let ncols = tib - tia;
    let mut tasks: Vec<Task> = (tja..tjb)
        .flat_map(|tj| {
            (tia..tib).map(move |ti| Task {
                i0: ti * TASK,
                j0: tj * TASK,
                rows: Vec::with_capacity(TASK),
            })
        })
        .collect();
    let (c0, c1) = (tia * TASK, (tib * TASK).min(nu));
    for (r, row) in fam
        .dexels
        .chunks_mut(nu)
        .enumerate()
        .skip(tja * TASK)
        .take((tjb - tja) * TASK)
    {
        let Some(part) = row.get_mut(c0..c1) else {
            continue;
        };
        let base = (r / TASK - tja) * ncols;
        for (c, piece) in part.chunks_mut(TASK).enumerate() {
            if let Some(t) = tasks.get_mut(base + c) {
                t.rows.push(piece);
            }
        }
    }
    // The tasks run the batch's steps a part at a time, each part's sweeps prepared once.
    let mut hits = Vec::new();
    for steps in batch.steps.chunks(SWEEP_STEPS) {
        let sweeps = prepare_sweeps(batch, steps, &grid);
        let base = steps.first().map_or(0, |p| p.bodies.start);
        let ranges = &cull.ranges;
        let cnu = cull.nu;
        let run = |t: &mut Task| run_task(t, (batch, steps), (&sweeps, base), &grid, (ranges, cnu));
        // A few steps over a few tasks (the control's live cutting) are run on this thread:
        // handing them to the pool costs more than they do. The result is the same.
        let outs: Vec<TaskOut> = if tasks.len().saturating_mul(steps.len()) <= SMALL_WORK {
            tasks.iter_mut().map(run).collect()
        } else {
            tasks.par_iter_mut().map(run).collect()
        };
        for (h, updates) in outs {
            hits.extend(h);
            for (k, (e, length)) in updates {
                if let (Some(slot), Some(l)) = (cull.ranges.get_mut(k), cull.lengths.get_mut(k)) {
                    *slot = e;
                    *l = length;
                }
            }
        }
    }
    hits
}

/// A body of the batch as the family's rays see it, shared by every task: the rays its box
/// covers and, for a tilted body, its sweep along the step prepared once per batch and
/// family.
struct Sweep {
    /// Rays `i0..i1` × `j0..j1` of the grid within the body's box (empty: none).
    cells: [usize; 4],
    tilted: Option<Tilted>,
}

/// A tilted body's sweep (or any body over X or Y rays) for the family's rays.
struct Tilted {
    prepared: Prepared,
    /// Where [`Sweeps::rows`] holds the body's rows `j0..j1` of [`Sweep::cells`].
    rows: Range<usize>,
}

/// The sweeps of some steps' bodies, and the row spans of the tilted ones: per row, the rays
/// `a..c` within the body's shadow ([`Shadow`]; `a ≥ c` where the row misses it).
struct Sweeps {
    list: Vec<Sweep>,
    rows: Vec<(usize, usize)>,
}

impl Sweeps {
    /// The rays of row `j` within `ia..ib` in the shadow of the tilted body `t` (rows from
    /// `j0`).
    fn row(
        &self,
        t: &Tilted,
        j: usize,
        j0: usize,
        (ia, ib): (usize, usize),
    ) -> Option<(usize, usize)> {
        let rows = self.rows.get(t.rows.clone())?;
        let (a, c) = rows.get(j.checked_sub(j0)?).copied()?;
        let (a, c) = (a.max(ia), c.min(ib));
        (a < c).then_some((a, c))
    }
}

/// The row spans `j0..` of a body's shadow into `out` (one per row).
fn shadow_rows(p: &PStep, b: &PBody, g: &Grid, j0: usize, out: &mut [(usize, usize)]) {
    let (u, v, _) = g.uvw;
    let shadow = Shadow::new(&p.step, &b.body, g);
    for (k, slot) in out.iter_mut().enumerate() {
        #[allow(clippy::cast_precision_loss)]
        let y = g.o[v] + ((j0 + k) as f64 + 0.5) * g.spacing;
        *slot = match shadow.span(y) {
            Some((x0, x1)) if x0 <= x1 => DexelFamily::cell_range(g.o[u], g.spacing, g.nu, x0, x1),
            _ => (0, 0),
        };
    }
}

/// The sweeps of the bodies of `steps` (some of the batch's) for the family's rays, in the
/// order of `batch.bodies`; vertical tools over Z rays (closed forms) and bodies whose box
/// misses the grid get no prepared sweep.
fn prepare_sweeps(batch: &Batch, steps: &[PStep], g: &Grid) -> Sweeps {
    let (u, v, _) = g.uvw;
    let owners: Vec<(usize, usize)> = steps
        .iter()
        .enumerate()
        .flat_map(|(s, p)| p.bodies.clone().map(move |k| (s, k)))
        .collect();
    let make = |&(s, k): &(usize, usize)| {
        let none = Sweep {
            cells: [0; 4],
            tilted: None,
        };
        let (Some(p), Some(b)) = (steps.get(s), batch.bodies.get(k)) else {
            return none;
        };
        let (lo, hi) = (b.bbox.min.to_array(), b.bbox.max.to_array());
        let (i0, i1) = DexelFamily::cell_range(g.o[u], g.spacing, g.nu, lo[u], hi[u]);
        let (j0, j1) = DexelFamily::cell_range(g.o[v], g.spacing, g.nv, lo[v], hi[v]);
        if i0 >= i1 || j0 >= j1 {
            return none;
        }
        Sweep {
            cells: [i0, i1, j0, j1],
            tilted: (!(g.z_family && p.vertical)).then(|| Tilted {
                prepared: b.body.prepare(&p.step, g.dir),
                rows: 0..0,
            }),
        }
    };
    let mut list: Vec<Sweep> = if owners.len() <= SMALL_WORK {
        owners.iter().map(make).collect()
    } else {
        owners.par_iter().map(make).collect()
    };
    let mut total = 0;
    for sw in &mut list {
        if let Some(t) = &mut sw.tilted {
            let n = sw.cells[3] - sw.cells[2];
            t.rows = total..total + n;
            total += n;
        }
    }
    let mut rows = vec![(0, 0); total];
    let mut jobs = Vec::with_capacity(list.len());
    let mut rest: &mut [(usize, usize)] = &mut rows;
    for (sw, &(s, k)) in list.iter().zip(&owners) {
        let Some(t) = &sw.tilted else {
            continue;
        };
        let Some((head, tail)) = std::mem::take(&mut rest).split_at_mut_checked(t.rows.len())
        else {
            break;
        };
        jobs.push((head, s, k, sw.cells[2]));
        rest = tail;
    }
    let shade = |(out, s, k, j0): (&mut [(usize, usize)], usize, usize, usize)| {
        if let (Some(p), Some(b)) = (steps.get(s), batch.bodies.get(k)) {
            shadow_rows(p, b, g, j0, out);
        }
    };
    if jobs.len() <= SMALL_WORK {
        jobs.into_iter().for_each(shade);
    } else {
        jobs.into_par_iter().for_each(shade);
    }
    Sweeps { list, rows }
}

/// Apply `steps` (some of the batch's, in order) to the task's rays; `sweeps` from
/// [`prepare_sweeps`] for them, the first for the batch's body `base`.
fn run_task(
    t: &mut Task,
    (batch, steps): (&Batch, &[PStep]),
    (sweeps, base): (&Sweeps, usize),
    g: &Grid,
    (ranges, cnu): (&[[f32; 2]], usize),
) -> TaskOut {
    let mut hits = Vec::new();
    let mut dirty = [false; CPT * CPT];
    // The row bounds' buffer, reused by every row.
    let mut made = RowCache::default();
    let (_, _, w) = g.uvw;
    let i1 = t.i0 + t.rows.first().map_or(0, |r| r.len());
    let j1 = t.j0 + t.rows.len();
    for p in steps {
        for k in p.bodies.clone() {
            let (Some(b), Some(sweep)) =
                (batch.bodies.get(k), sweeps.list.get(k.wrapping_sub(base)))
            else {
                continue;
            };
            let [ia, ib, ja, jb] = sweep.cells;
            let (ja, jb) = (ja.max(t.j0), jb.min(j1));
            let (ia, ib) = (ia.max(t.i0), ib.min(i1));
            if ja >= jb || ia >= ib {
                continue;
            }
            let vertical = g.z_family && p.vertical;
            if !vertical && sweep.tilted.is_none() {
                continue;
            }
            let (lo, hi) = (b.bbox.min.to_array(), b.bbox.max.to_array());
            let ctx = BodyCtx {
                p,
                b,
                w_lo: lo[w] - g.o[w],
                w_hi: hi[w] - g.o[w],
                vertical,
                prepared: sweep.tilted.as_ref().map(|s| &s.prepared),
            };
            let j0 = sweep.cells[2];
            for j in ja..jb {
                let span = match &sweep.tilted {
                    Some(tilted) => sweeps.row(tilted, j, j0, (ia, ib)),
                    None => row_span(&ctx, g, j, (ia, ib)),
                };
                let Some((sa, sb)) = span else {
                    continue;
                };
                let Some(row) = t.rows.get_mut(j - t.j0) else {
                    continue;
                };
                // The sweep's bounds along the row, made for the row's first ray that needs
                // them.
                made.made = false;
                let bounded = ctx.prepared.is_some_and(Prepared::has_bounds);
                let mut i = sa;
                while i < sb {
                    let (ci, cj) = (i / CULL, j / CULL);
                    let end = ((ci + 1) * CULL).min(sb);
                    let e = ranges.get(cj * cnu + ci).copied().unwrap_or([0.0, 0.0]);
                    if f64::from(e[1]) > ctx.w_lo && f64::from(e[0]) < ctx.w_hi {
                        let changed = match b.fast.filter(|_| ctx.vertical) {
                            Some(fb) => ball_run(row, (i, end, j), &fb, &ctx, (t.i0, g), &mut hits),
                            None => (i..end).fold(false, |changed, k| {
                                row.get_mut(k - t.i0).is_some_and(|d| {
                                    let row = bounded.then_some(&mut made);
                                    ray(d, (k, j), &ctx, (g, row), &mut hits)
                                }) | changed
                            }),
                        };
                        if changed
                            && let Some(slot) =
                                dirty.get_mut((cj - t.j0 / CULL) * CPT + (ci - t.i0 / CULL))
                        {
                            *slot = true;
                        }
                    }
                    i = end;
                }
            }
        }
    }
    let mut updates = Vec::new();
    for (k, _) in dirty.iter().enumerate().filter(|(_, d)| **d) {
        let (ci, cj) = (t.i0 / CULL + k % CPT, t.j0 / CULL + k / CPT);
        let (a, c) = (ci * CULL - t.i0, (ci * CULL - t.i0 + CULL).min(i1 - t.i0));
        let rows = (cj * CULL - t.j0)..((cj * CULL - t.j0 + CULL).min(j1 - t.j0));
        let e = tile_extent(
            t.rows
                .get(rows)
                .unwrap_or(&[])
                .iter()
                .flat_map(|r| r.get(a..c).unwrap_or(&[]).iter()),
        );
        updates.push((cj * cnu + ci, e));
    }
    (hits, updates)
}

/// The rays `sa..sb` of row `j` (within `ia..ib`) that a vertical tool over Z rays can
/// change: the footprint's stadium less the rear half-disc already cut (tilted bodies:
/// [`Sweeps::row`]); `None` when the row misses it.
fn row_span(ctx: &BodyCtx, g: &Grid, j: usize, (ia, ib): (usize, usize)) -> Option<(usize, usize)> {
    let (u, v, _) = g.uvw;
    #[allow(clippy::cast_precision_loss)]
    let y = g.o[v] + (j as f64 + 0.5) * g.spacing;
    let (p, b) = (ctx.p, ctx.b);
    let (x0, x1) = if ctx.vertical {
        let (x0, x1) = stadium_span(
            p.step.p0.truncate(),
            p.step.p1.truncate(),
            b.body.radius(),
            y,
        )?;
        match (b.ball.is_some() && p.chained)
            .then(|| rear_chord(&p.step, b.body.radius(), y))
            .flatten()
        {
            // The rear half-disc touches one end of the span: the rest remains.
            Some((r0, r1)) if r0 <= x0 => (x0.max(r1), x1),
            Some((r0, r1)) if r1 >= x1 => (x0, x1.min(r0)),
            _ => (x0, x1),
        }
    } else {
        return Some((ia, ib));
    };
    if x0 > x1 {
        return None;
    }
    let (a, c) = DexelFamily::cell_range(g.o[u], g.spacing, g.nu, x0, x1);
    let (a, c) = (a.max(ia), c.min(ib));
    (a < c).then_some((a, c))
}

/// A body's shadow on the grid plane of a family: every point of the body swept along the
/// step lies within `r` of the parallelogram swept by its axis segment, so a ray meets the
/// sweep only where its grid point lies within `r` of the parallelogram's projection.
struct Shadow {
    /// The projected corners, in order around the parallelogram (u, v), mm.
    corners: [DVec2; 4],
    /// The radius, grown by a rounding margin, mm.
    r: f64,
    /// The edges' rectangles (from corner k to k + 1), taken once for every row.
    edges: [Option<StadiumEdge>; 4],
}

impl Shadow {
    fn new(step: &SweepStep, body: &Body, g: &Grid) -> Self {
        let (u, v, _) = g.uvw;
        let (h0, h1) = body.axis_span();
        let (a, b) = (step.p0 + step.axis * h0, step.p0 + step.axis * h1);
        let d = step.p1 - step.p0;
        let uv = |p: DVec3| {
            let q = p.to_array();
            DVec2::new(
                q.get(u).copied().unwrap_or(0.0),
                q.get(v).copied().unwrap_or(0.0),
            )
        };
        let r = body.radius();
        let corners = [uv(a), uv(b), uv(b + d), uv(a + d)];
        Self {
            corners,
            r: r + 1e-9 * (1.0 + r) + 1e-9 * (a.abs().max_element() + d.abs().max_element()),
            edges: std::array::from_fn(|k| {
                let (p, q) = (corners.get(k)?, corners.get((k + 1) % 4)?);
                StadiumEdge::new(*p, *q)
            }),
        }
    }

    /// The u-interval of the shadow on the row at `y`: the hull of the edges' stadiums (the
    /// shadow is convex, and a row through its inside crosses two edges).
    ///
    /// The same values, in the same order, as [`stadium_span`] of each edge: the corners'
    /// discs are taken once per row and the edges' directions once per shadow.
    fn span(&self, y: f64) -> Option<(f64, f64)> {
        let discs = self.corners.map(|c| disc_span(c, self.r, y));
        let mut out = None;
        for (k, edge) in self.edges.iter().enumerate() {
            if let (Some(a), Some(b)) = (discs.get(k), discs.get((k + 1) % 4)) {
                let ends = super::exact::hull(*a, *b);
                let stadium = match edge {
                    Some(e) => super::exact::hull(ends, e.span(self.r, y)),
                    None => ends,
                };
                out = super::exact::hull(out, stadium);
            }
        }
        out
    }

    /// [`Shadow::span`] as first written (a stadium per edge), for the tests.
    #[cfg(test)]
    fn span_reference(&self, y: f64) -> Option<(f64, f64)> {
        let c = &self.corners;
        let mut out = None;
        for k in 0..4 {
            if let (Some(a), Some(b)) = (c.get(k), c.get((k + 1) % 4)) {
                out = super::exact::hull(out, stadium_span(*a, *b, self.r, y));
            }
        }
        out
    }
}

/// A body of a step as the rays of a task see it.
struct BodyCtx<'a> {
    p: &'a PStep,
    b: &'a PBody,
    /// The body's extent along the ray (offsets), from its box.
    w_lo: f64,
    w_hi: f64,
    /// Vertical tool over Z rays: the closed forms of `vertical_interval`.
    vertical: bool,
    /// The body's sweep along the step prepared for the family's rays (tilted bodies).
    prepared: Option<&'a Prepared>,
}

/// Apply a vertical ball's step to the rays `i..end` (at most `LANES`) of row `j` by the row
/// kernel, the general path for the rays it leaves; returns whether any material changed.
fn ball_run(
    row: &mut [Dexel],
    (i, end, j): (usize, usize, usize),
    fb: &BallStep,
    ctx: &BodyCtx,
    (i0, g): (usize, &Grid),
    hits: &mut Vec<Hit>,
) -> bool {
    let (u, v, w) = g.uvw;
    let n = (end - i).min(LANES);
    let mut lo = [0.0; LANES];
    #[allow(clippy::cast_precision_loss)]
    let y = g.o[v] + (j as f64 + 0.5) * g.spacing;
    fb.entries((g.o[u], g.spacing, i), n, y, &mut lo);
    let ow = g.o[w];
    let limit = fb.limit_offset(ow);
    let mut changed = false;
    for (k, z) in lo.iter().take(n).enumerate() {
        let Some(d) = row.get_mut(i + k - i0) else {
            continue;
        };
        changed |= match cut_below(d, z - ow, limit) {
            Some(c) => c,
            None => ray(d, (i + k, j), ctx, (g, None), hits),
        };
    }
    changed
}

/// A body's sweep bounds along one row of rays, made for the row's first ray that needs them
/// (in place: the row's buffer is reused).
#[derive(Default)]
struct RowCache {
    made: bool,
    row: PreparedRow,
}

/// Apply one body to ray (i, j); returns whether its material changed.
/// `row`: where the body's sweep bounds along the ray's row are kept (see
/// [`Prepared::along_into`]; made here when first needed).
fn ray(
    dexel: &mut Dexel,
    (i, j): (usize, usize),
    c: &BodyCtx,
    (g, row): (&Grid, Option<&mut RowCache>),
    hits: &mut Vec<Hit>,
) -> bool {
    let (first, top) = match dexel {
        Dexel::Empty => return false,
        Dexel::One([a, b]) => (*a, *b),
        Dexel::Many(v) => match (v.first(), v.last()) {
            (Some([a, _]), Some([_, b])) => (*a, *b),
            _ => return false,
        },
    };
    if f64::from(top) <= c.w_lo || f64::from(first) >= c.w_hi {
        return false;
    }
    let o = g.ray_origin(i, j);
    let (_, _, w) = g.uvw;
    let ow = g.o[w];
    let step = &c.p.step;
    let interval = if c.vertical {
        if let Some((c0, c1, r)) = c.b.ball {
            // REJECT_MM below the top is below every sphere centre and outside the swept
            // sphere: the sweep starts above it (it would take less than REJECT_MM off).
            let q = DVec3::new(o.x, o.y, f64::from(top) + ow - REJECT_MM);
            if q.z < c0.z.min(c1.z) && dist2_segment(q, c0, c1) > r * r {
                return false;
            }
        }
        vertical_interval(&c.b.body, step.p0, step.p1, DVec2::new(o.x, o.y))
            .map(|(a, b)| (a - ow, b - ow))
    } else if c.b.body.has_closed_form() {
        let Some(prep) = c.prepared else {
            return false;
        };
        #[allow(clippy::cast_precision_loss)]
        let row = row.map(|r| {
            if !r.made {
                prep.along_into(g.ray_origin(0, j), g.uvw.0, &mut r.row);
                r.made = true;
            }
            let r = &r.row;
            (r, i as f64 * g.spacing)
        });
        if c.b.kind.is_some() && !c.b.cuts && guard_beaten(dexel, c, (o, prep, row), g.tol, hits) {
            return false;
        }
        c.b.body
            .interval_prepared(step, (o, g.dir), dexel.intervals(), (prep, row))
    } else {
        general_interval(&c.b.body, step, o, g.dir, c.w_lo - 1.0, c.w_hi + 1.0)
    };
    let Some((a, b)) = interval else {
        return false;
    };

    #[allow(clippy::cast_possible_truncation)]
    let (a, b) = (a as f32, b as f32);
    if let Some(kind) = c.b.kind {
        let depth = dexel.overlap(a, b);
        if depth > g.tol
            && let Some([x, y]) = dexel.first_overlap(a, b)
        {
            let s = 0.5 * (f64::from(x) + f64::from(y));
            record(
                hits,
                Hit {
                    move_index: c.p.move_index,
                    kind,
                    depth,
                    key: (g.family, j * g.nu + i),
                    position: o + g.dir * s,
                },
            );
        }
    }
    c.b.cuts && dexel.subtract(a, b)
}

/// Whether a collision body's sweep (closed form) can give the ray no hit that would count:
/// the material within the outer bounds of its interval is at most the contact tolerance, or
/// less than the depth of a hit this task already recorded for the same move and kind (then
/// `record` would keep that one, and so would the final merge).
fn guard_beaten(
    dexel: &Dexel,
    c: &BodyCtx,
    (o, prep, row): (DVec3, &Prepared, Option<(&PreparedRow, f64)>),
    tol: f64,
    hits: &[Hit],
) -> bool {
    let Some((lo, hi)) = prep.cylinder_at(o, row) else {
        return false;
    };
    let Some(kind) = c.b.kind else {
        return false;
    };
    // Beyond the rounding of the interval's ends to f32.
    let (lo, hi) = (lo - 2e-7 * lo.abs(), hi + 2e-7 * hi.abs());
    let most: f64 = dexel
        .intervals()
        .iter()
        .map(|[a, b]| (f64::from(*b).min(hi) - f64::from(*a).max(lo)).max(0.0))
        .sum();
    if most <= tol {
        return true;
    }
    hits.iter()
        .rev()
        .take(4)
        .any(|h| h.move_index == c.p.move_index && h.kind == kind && most < h.depth)
}

/// The chord of row `y` through the half-disc of radius `r` at the start of a vertical step
/// that lies behind it (`(q − p₀)·d ≤ 0` in XY), when the step does not descend. There the
/// swept ball's lowest point is the start sphere's (the distance to the centre and the
/// centre's height both grow with t), which the step before already cut: nothing changes.
fn rear_chord(step: &SweepStep, r: f64, y: f64) -> Option<(f64, f64)> {
    let d = step.p1 - step.p0;
    if d.z < 0.0 {
        return None;
    }
    let dy = y - step.p0.y;
    let h2 = r * r - dy * dy;
    if h2 < 0.0 {
        return None;
    }
    let h = h2.sqrt();
    let (mut lo, mut hi) = (step.p0.x - h, step.p0.x + h);
    // d.x·(x − x₀) + d.y·(y − y₀) ≤ 0
    let k = -d.y * dy;
    if d.x > 0.0 {
        hi = hi.min(step.p0.x + k / d.x);
    } else if d.x < 0.0 {
        lo = lo.max(step.p0.x + k / d.x);
    } else if k < 0.0 {
        return None;
    }
    (lo <= hi).then_some((lo, hi))
}

/// Squared distance from `q` to the segment [a, b].
fn dist2_segment(q: DVec3, a: DVec3, b: DVec3) -> f64 {
    let d = b - a;
    let dd = d.length_squared();
    let t = if dd > 0.0 {
        ((q - a).dot(d) / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (q - a - d * t).length_squared()
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A shadow's row spans with the corners' discs and the edges' directions taken once are
    /// those of a stadium per edge, to the bit (random tilted steps, every family's axes).
    #[test]
    fn shadow_span_is_the_stadiums_to_the_bit() {
        let mut rnd = crate::test_uniform(23);
        let mut spans = 0;
        for k in 0..2000 {
            let axis = DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() + 0.1)
                .try_normalize()
                .unwrap_or(DVec3::Z);
            let p0 = DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 20.0;
            let scale = [0.0, 1e-13, 0.02, 0.3, 5.0][k % 5];
            let d = DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * scale;
            let step = SweepStep {
                p0,
                p1: p0 + d,
                axis,
            };
            let body = if k % 2 == 0 {
                Body::Cutting {
                    radius: 3.0,
                    flat: 0.0,
                    corner: 3.0,
                    cone_tan: 0.0,
                    top: 3.0 + 20.0 * rnd(),
                }
            } else {
                Body::Cylinder {
                    radius: 0.5 + 4.0 * rnd(),
                    z0: 10.0 * rnd(),
                    z1: 12.0 + 20.0 * rnd(),
                }
            };
            let uvw = [(0, 1, 2), (1, 2, 0), (2, 0, 1)][k % 3];
            let g = Grid {
                o: [-30.0; 3],
                spacing: 0.29,
                nu: 200,
                nv: 200,
                uvw,
                dir: DVec3::Z,
                z_family: uvw.2 == 2,
                family: 0,
                tol: 0.0,
            };
            let shadow = Shadow::new(&step, &body, &g);
            for m in 0..200 {
                let y = -30.0 + 0.3 * f64::from(m);
                let (got, want) = (shadow.span(y), shadow.span_reference(y));
                assert_eq!(
                    got.map(|(a, b)| (a.to_bits(), b.to_bits())),
                    want.map(|(a, b)| (a.to_bits(), b.to_bits())),
                    "{k} {y}"
                );
                spans += usize::from(got.is_some());
            }
        }
        assert!(spans > 20_000, "{spans}");
    }
}
