//! Adaptive clearing (2D, constant engagement): the material at a level is kept as a fine grid
//! of cells (cleared or not); from a helix entry at the widest spot of the tool-centre region,
//! the tool walks in short steps, each step's direction found by bisection on its turn angle so
//! that the tool circle's front half holds at most the target engagement angle of uncut
//! material, with the material on the right of the feed (climb milling with a clockwise
//! spindle). A walk ends in air or where no direction keeps the engagement; the next one starts
//! from the point of the path so far nearest to the nearest material left, linked staying down
//! when the tool crosses only cleared area, else by a retract. Where a plain offset would bury
//! the tool the walk turns back on itself (trochoidal loops). A last lap along every boundary
//! of the tool-centre region (exact lines and arcs) leaves the walls at the allowance.
//!
//! The same 2D path is cut at every level, from the top down to the floor plus the floor
//! allowance in steps of at most the step-down; each level enters by its own helix.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::{DVec2, DVec3};

use super::PlanarError;
use crate::geometry::planar::{Element, Region};
use crate::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};

/// Options of [`adaptive`].
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveOptions {
    /// Height of the top of the material, mm.
    pub top_z_mm: f64,
    /// Height of the floor, mm.
    pub floor_z_mm: f64,
    /// Largest depth of one level, mm.
    pub step_down_mm: f64,
    /// Largest radial engagement angle, rad, in [5°, 180°].
    pub engagement_rad: f64,
    /// Stock left on the walls, mm.
    pub wall_allowance_mm: f64,
    /// Stock left on the floor, mm.
    pub floor_allowance_mm: f64,
    /// Safe height above the top for rapids, mm above `top_z_mm`.
    pub clearance_mm: f64,
    /// Largest ramp angle of the helix entry, rad.
    pub ramp_angle_rad: f64,
    /// Cutting feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Chord tolerance of the sampled view of arcs, mm.
    pub chord_tol_mm: f64,
    /// Cell size of the material grid the planner steers on, mm.
    pub resolution_mm: f64,
}

impl Default for AdaptiveOptions {
    fn default() -> Self {
        Self {
            top_z_mm: 0.0,
            floor_z_mm: -5.0,
            step_down_mm: 5.0,
            engagement_rad: 60f64.to_radians(),
            wall_allowance_mm: 0.2,
            floor_allowance_mm: 0.2,
            clearance_mm: 5.0,
            ramp_angle_rad: 3f64.to_radians(),
            feed_mm_per_min: 1000.0,
            chord_tol_mm: 0.005,
            resolution_mm: 0.05,
        }
    }
}

/// The margin the planner keeps below the target angle (grid quantisation), rad.
const MARGIN_RAD: f64 = 1.0 * PI / 180.0;
/// Below this engagement a step is in air, rad.
const AIR_RAD: f64 = 2.0 * PI / 180.0;
/// Samples of the front half circle.
const HALF_SAMPLES: usize = 180;
/// Most grid cells (memory bound).
const MAX_CELLS: usize = 40_000_000;

/// Cells of material (true) or cleared, row by row.
struct Grid {
    origin: DVec2,
    h: f64,
    nx: usize,
    ny: usize,
    cells: Vec<bool>,
    /// (sin φ, cos φ) of the front half's sample angles.
    half: Vec<(f64, f64)>,
    /// Unit vectors of the whole circle's sample angles.
    full: Vec<DVec2>,
}

impl Grid {
    fn new(lo: DVec2, hi: DVec2, h: f64, fill: bool) -> Result<Self, PlanarError> {
        let origin = (lo / h).floor() * h;
        let span = (hi - origin) / h;
        let (nx, ny) = (span.x.ceil() + 1.0, span.y.ceil() + 1.0);
        if !(nx * ny <= MAX_CELLS as f64) {
            return Err(PlanarError(format!(
                "adaptive: the region needs {nx}×{ny} cells of {h} mm; raise the resolution"
            )));
        }
        // Bounded by MAX_CELLS above.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let (nx, ny) = (nx as usize, ny as usize);
        Ok(Self {
            origin,
            h,
            nx,
            ny,
            cells: vec![fill; nx * ny],
            half: (0..HALF_SAMPLES)
                .map(|k| ((k as f64 + 0.5) * PI / HALF_SAMPLES as f64).sin_cos())
                .collect(),
            full: (0..2 * HALF_SAMPLES)
                .map(|k| DVec2::from_angle((k as f64 + 0.5) * PI / HALF_SAMPLES as f64))
                .collect(),
        })
    }

    fn index(&self, p: DVec2) -> Option<usize> {
        let u = (p - self.origin) / self.h;
        if !(u.x >= 0.0 && u.y >= 0.0) {
            return None;
        }
        // Non-negative and finite by the check above.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let (i, j) = (u.x as usize, u.y as usize);
        (i < self.nx && j < self.ny).then_some(j * self.nx + i)
    }

    /// Material at `p` (everything off the grid is material).
    fn at(&self, p: DVec2) -> bool {
        self.index(p)
            .is_none_or(|k| self.cells.get(k).copied().unwrap_or(true))
    }

    fn centre_y(&self, j: usize) -> f64 {
        self.origin.y + (j as f64 + 0.5) * self.h
    }

    /// Row range of cell centres within `[y0, y1]`.
    fn rows(&self, y0: f64, y1: f64) -> std::ops::Range<usize> {
        let a = ((y0 - self.origin.y) / self.h - 0.5).ceil().max(0.0);
        let b = ((y1 - self.origin.y) / self.h - 0.5).floor() + 1.0;
        // Clamped to the grid.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let r = (a as usize).min(self.ny)..(b.max(0.0) as usize).min(self.ny);
        r
    }

    /// Column range of cell centres within `[x0, x1]`.
    fn cols(&self, x0: f64, x1: f64) -> std::ops::Range<usize> {
        let a = ((x0 - self.origin.x) / self.h - 0.5).ceil().max(0.0);
        let b = ((x1 - self.origin.x) / self.h - 0.5).floor() + 1.0;
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let r = (a as usize).min(self.nx)..(b.max(0.0) as usize).min(self.nx);
        r
    }

    /// Sets every cell whose centre lies within `r` of `c` to `value`; returns how many changed.
    fn disc(&mut self, c: DVec2, r: f64, value: bool) -> usize {
        let mut changed = 0;
        for j in self.rows(c.y - r, c.y + r) {
            let dy = self.centre_y(j) - c.y;
            let w = (r * r - dy * dy).max(0.0).sqrt();
            let cols = self.cols(c.x - w, c.x + w);
            let row = j * self.nx;
            if let Some(cells) = self.cells.get_mut(row + cols.start..row + cols.end) {
                for v in cells {
                    if *v != value {
                        *v = value;
                        changed += 1;
                    }
                }
            }
        }
        changed
    }

    /// Cells inside `region` (even-odd over its boundaries, row by row).
    fn fill_region(&mut self, region: &Region, value: bool) {
        let elements: Vec<Element> = region
            .boundaries()
            .into_iter()
            .flat_map(|b| b.elements())
            .collect();
        let mut xs: Vec<f64> = Vec::new();
        for j in 0..self.ny {
            let y = self.centre_y(j);
            xs.clear();
            for e in &elements {
                crossings(e, y, &mut xs);
            }
            xs.sort_by(f64::total_cmp);
            for pair in xs.chunks_exact(2) {
                let (Some(&a), Some(&b)) = (pair.first(), pair.get(1)) else {
                    continue;
                };
                let cols = self.cols(a, b);
                let row = j * self.nx;
                if let Some(cells) = self.cells.get_mut(row + cols.start..row + cols.end) {
                    cells.fill(value);
                }
            }
        }
    }

    /// Engaged angle of the front half of the circle of radius `r` about `c` feeding along
    /// the unit `dir`, rad.
    fn engagement(&self, c: DVec2, dir: DVec2, r: f64) -> f64 {
        let (x, y) = (dir * r, dir.perp() * r);
        let n = self
            .half
            .iter()
            .filter(|&&(s, co)| self.at(c + x * s + y * co))
            .count();
        n as f64 * PI / HALF_SAMPLES as f64
    }

    /// True when the whole circle of radius `r` about `c` lies in cleared cells.
    fn circle_clear(&self, c: DVec2, r: f64) -> bool {
        self.full.iter().all(|&u| !self.at(c + u * r))
    }
}

/// x of the crossings of the horizontal line at `y` with an element (half-open in y).
fn crossings(e: &Element, y: f64, xs: &mut Vec<f64>) {
    match *e {
        Element::Line { a, b } => {
            if (a.y > y) != (b.y > y) {
                xs.push(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
            }
        }
        Element::Arc {
            centre,
            radius,
            start_rad,
            sweep_rad,
            ..
        } => {
            let dy = y - centre.y;
            if dy.abs() >= radius {
                return;
            }
            let dx = (radius * radius - dy * dy).sqrt();
            for x in [centre.x - dx, centre.x + dx] {
                let ang = (DVec2::new(x, y) - centre).to_angle();
                let d = if sweep_rad >= 0.0 {
                    (ang - start_rad).rem_euclid(TAU)
                } else {
                    (start_rad - ang).rem_euclid(TAU)
                };
                if d < sweep_rad.abs() {
                    xs.push(x);
                }
            }
        }
    }
}

/// One piece of the 2D plan.
enum Piece {
    /// A walk: tool-centre points joined by lines (the first is where it starts).
    Walk(Vec<DVec2>),
    /// A closed lap of lines and arcs along a boundary of the tool-centre region.
    Lap(Vec<Element>),
}

/// A piece and whether the tool reaches its start staying down.
struct Planned {
    piece: Piece,
    down: bool,
}

/// The 2D plan of one connected tool-centre area.
struct AreaPlan {
    centre: DVec2,
    helix_r: f64,
    pieces: Vec<Planned>,
}

struct Walker<'a> {
    grid: Grid,
    feasible: &'a Grid,
    r: f64,
    step: f64,
    target: f64,
}

impl Walker<'_> {
    /// The candidate after turning `theta` from `heading`: the point and whether it may be cut.
    fn try_turn(&self, p: DVec2, heading: DVec2, theta: f64) -> Option<(DVec2, DVec2, f64)> {
        let dir = DVec2::from_angle(-theta).rotate(heading);
        let q = p + dir * self.step;
        if !self.feasible.at(q) {
            return None;
        }
        let e = self.grid.engagement(q, dir, self.r);
        (e <= self.target).then_some((q, dir, e))
    }

    /// The rightmost turn (toward the material) whose engagement stays within the target; the
    /// engagement is `f64::NAN` when the sharpest right turn already keeps it (nothing to
    /// steer by).
    fn best_turn(&self, p: DVec2, heading: DVec2) -> Option<(DVec2, DVec2, f64)> {
        let coarse = 7.5f64.to_radians();
        let most = 45f64.to_radians();
        let mut bad = most + coarse;
        let mut theta = most;
        while theta >= -PI {
            if let Some(good) = self.try_turn(p, heading, theta) {
                let (mut lo, mut hi, mut best) = (theta, bad, good);
                if hi > most {
                    return Some((best.0, best.1, f64::NAN));
                }
                for _ in 0..8 {
                    let mid = 0.5 * (lo + hi);
                    if let Some(g) = self.try_turn(p, heading, mid) {
                        lo = mid;
                        best = g;
                    } else {
                        hi = mid;
                    }
                }
                return Some(best);
            }
            bad = theta;
            theta -= coarse;
        }
        None
    }

    /// One walk from `start` heading along `heading` (toward `goal` until it first cuts). It
    /// ends where no direction keeps the engagement, or after a tool radius of steps that
    /// clear next to nothing (a goal's distance more before the first cut).
    fn walk(&mut self, start: DVec2, heading: DVec2, goal: Option<DVec2>) -> (Vec<DVec2>, usize) {
        self.walk_to(start, heading, goal, false)
    }

    /// As [`Walker::walk`]; `persistent`: head for the goal whenever the engagement allows
    /// and end there.
    fn walk_to(
        &mut self,
        start: DVec2,
        heading: DVec2,
        goal: Option<DVec2>,
        persistent: bool,
    ) -> (Vec<DVec2>, usize) {
        let mut pts = vec![start];
        let (mut p, mut h) = (start, heading.normalize_or(DVec2::X));
        let mut idle = 0.0;
        let mut free = 0.0;
        let mut engaged = goal.is_none();
        let mut cleared = 0;
        let idle_limit = self.r.max(1.0);
        let approach = goal.map_or(0.0, |g| g.distance(start)) + idle_limit;
        // A step clearing less than a 0.05 mm wide strip is idle.
        let idle_cells = self.step * 0.05 / (self.grid.h * self.grid.h);
        for _ in 0..400_000 {
            if persistent && goal.is_some_and(|g| g.distance(p) < self.step) {
                break;
            }
            let toward = goal
                .filter(|_| !engaged || persistent)
                .and_then(|g| (g - p).try_normalize())
                .and_then(|d| self.try_turn(p, d, 0.0));
            let Some((q, dir, e)) = toward.or_else(|| self.best_turn(p, h)) else {
                break;
            };
            // Circling with nothing to steer by: the material on the right has run out.
            free = if e.is_nan() { free + self.step } else { 0.0 };
            if engaged && free > 1.0 {
                break;
            }
            let c = self.grid.disc(q, self.r, false);
            cleared += c;
            pts.push(q);
            (p, h) = (q, dir);
            if (c as f64) < idle_cells {
                idle += self.step;
                if idle > if engaged { idle_limit } else { approach } {
                    break;
                }
            } else {
                idle = 0.0;
                engaged = true;
            }
        }
        (pts, cleared)
    }

    /// True when a straight feed from `a` to `b` crosses only cleared area inside the region.
    fn link_clear(&self, a: DVec2, b: DVec2) -> bool {
        let n = (a.distance(b) / (2.0 * self.grid.h).max(0.05))
            .ceil()
            .clamp(1.0, 1e5);
        // A small count by the clamp above.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let n = n as usize;
        (0..=n).all(|k| {
            let q = a.lerp(b, k as f64 / n as f64);
            self.feasible.at(q) && self.grid.circle_clear(q, self.r - 3.0 * self.grid.h)
        })
    }
}

/// Points in square buckets, for the nearest point to a query.
struct Buckets {
    lo: DVec2,
    size: f64,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<DVec2>>,
}

impl Buckets {
    fn new(lo: DVec2, hi: DVec2, size: f64) -> Self {
        let n = ((hi - lo) / size)
            .ceil()
            .max(DVec2::ONE)
            .min(DVec2::splat(2000.0));
        // Bounded by the clamp above.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let (nx, ny) = (n.x as usize, n.y as usize);
        Self {
            lo,
            size,
            nx,
            ny,
            cells: vec![Vec::new(); nx * ny],
        }
    }

    fn cell(&self, p: DVec2) -> (usize, usize) {
        let u = ((p - self.lo) / self.size).max(DVec2::ZERO);
        // Clamped to the buckets.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let (i, j) = (u.x as usize, u.y as usize);
        (i.min(self.nx - 1), j.min(self.ny - 1))
    }

    fn push(&mut self, p: DVec2) {
        let (i, j) = self.cell(p);
        if let Some(c) = self.cells.get_mut(j * self.nx + i) {
            c.push(p);
        }
    }

    /// The point nearest `q`: rings of buckets outward until no nearer point can remain.
    fn nearest(&self, q: DVec2) -> Option<DVec2> {
        let (ci, cj) = self.cell(q);
        let mut best: Option<(DVec2, f64)> = None;
        for ring in 0..self.nx.max(self.ny) {
            if let Some((_, d)) = best
                && (ring as f64 - 1.0) * self.size > d.sqrt()
            {
                break;
            }
            let (i0, i1) = (ci.saturating_sub(ring), (ci + ring).min(self.nx - 1));
            let (j0, j1) = (cj.saturating_sub(ring), (cj + ring).min(self.ny - 1));
            for j in j0..=j1 {
                for i in i0..=i1 {
                    if i.abs_diff(ci) != ring && j.abs_diff(cj) != ring {
                        continue;
                    }
                    for &p in self.cells.get(j * self.nx + i).into_iter().flatten() {
                        let d = p.distance_squared(q);
                        if best.is_none_or(|b| d < b.1) {
                            best = Some((p, d));
                        }
                    }
                }
            }
        }
        best.map(|b| b.0)
    }
}

/// The point of `area` farthest from its boundaries (sampled) and that distance.
fn widest_spot(area: &Region) -> Option<(DVec2, f64)> {
    let (lo, hi) = area.bounds();
    let elements: Vec<Element> = area
        .boundaries()
        .into_iter()
        .flat_map(|b| b.elements())
        .collect();
    let dist = |p: DVec2| {
        elements
            .iter()
            .map(|e| e.distance(p))
            .fold(f64::INFINITY, f64::min)
    };
    let mut best: Option<(DVec2, f64)> = None;
    let mut h = ((hi - lo).max_element() / 60.0).max(1e-3);
    let mut box_lo = lo;
    let mut box_hi = hi;
    for _ in 0..4 {
        let mut y = box_lo.y + 0.5 * h;
        while y < box_hi.y {
            let mut x = box_lo.x + 0.5 * h;
            while x < box_hi.x {
                let p = DVec2::new(x, y);
                if area.contains(p) {
                    let d = dist(p);
                    if best.is_none_or(|b| d > b.1) {
                        best = Some((p, d));
                    }
                }
                x += h;
            }
            y += h;
        }
        let (c, _) = best?;
        box_lo = c - DVec2::splat(2.0 * h);
        box_hi = c + DVec2::splat(2.0 * h);
        h /= 4.0;
    }
    best
}

/// Splits a closed lap so that it starts at parameter `t` of element `i`.
fn lap_from(els: &[Element], i: usize, t: f64) -> Vec<Element> {
    let n = els.len();
    let mut out = Vec::with_capacity(n + 1);
    let Some(e) = els.get(i) else {
        return els.to_vec();
    };
    let (first, second) = split(e, t);
    out.extend(second);
    for k in 1..n {
        if let Some(x) = els.get((i + k) % n) {
            out.push(*x);
        }
    }
    out.extend(first);
    out
}

/// An element split at parameter `t` (pieces of zero length dropped).
fn split(e: &Element, t: f64) -> (Option<Element>, Option<Element>) {
    if t <= 1e-9 {
        return (None, Some(*e));
    }
    if t >= 1.0 - 1e-9 {
        return (Some(*e), None);
    }
    let p = e.point_at(t);
    match *e {
        Element::Line { a, b } => (
            Some(Element::Line { a, b: p }),
            Some(Element::Line { a: p, b }),
        ),
        Element::Arc {
            a,
            b,
            centre,
            radius,
            start_rad,
            sweep_rad,
        } => (
            Some(Element::Arc {
                a,
                b: p,
                centre,
                radius,
                start_rad,
                sweep_rad: sweep_rad * t,
            }),
            Some(Element::Arc {
                a: p,
                b,
                centre,
                radius,
                start_rad: start_rad + sweep_rad * t,
                sweep_rad: sweep_rad * (1.0 - t),
            }),
        ),
    }
}

/// Points along an element at most `step` apart (the start excluded).
fn samples(e: &Element, step: f64) -> Vec<DVec2> {
    let n = (e.length() / step).ceil().clamp(1.0, 1e6);
    // A bounded count by the clamp above.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let n = n as usize;
    (1..=n).map(|k| e.point_at(k as f64 / n as f64)).collect()
}

/// The 2D plan of one connected area of tool centres.
fn plan_area(
    area: &Region,
    r: f64,
    target: f64,
    o: &AdaptiveOptions,
) -> Result<AreaPlan, PlanarError> {
    let h = o.resolution_mm;
    let (lo, hi) = area.bounds();
    let margin = DVec2::splat(r + 4.0 * h + 1.0);
    let (centre, wide) = widest_spot(area)
        .ok_or_else(|| PlanarError("adaptive: the tool fits nowhere in the region".into()))?;
    let helix_r = (0.9 * wide).min(0.5 * r);
    if helix_r < 0.02 {
        return Err(PlanarError(format!(
            "adaptive: no room for a helix entry (widest spot {wide:.3} mm from the walls)"
        )));
    }
    let mut grid = Grid::new(lo - margin, hi + margin, h, true)?;
    // Feasible tool centres: inside the area by a little more than a cell's half diagonal.
    // This grid holds `true` where a centre may go.
    let mut feasible = Grid::new(lo - margin, hi + margin, h, false)?;
    feasible.fill_region(&area.offset(0.75 * h), true);
    // Material the walks must remove: all the tool reaches but a band along the walls thin
    // enough for the final laps to cut at 0.6 of the target engagement.
    let band = (r * (1.0 - (0.6 * target).cos())).max(2.0 * h).min(0.5 * r);
    let mut target_cells = Grid::new(lo - margin, hi + margin, h, false)?;
    target_cells.fill_region(&area.offset(-(r - band)), true);
    grid.disc(centre, r + helix_r, false);
    let step = (0.06 * r).clamp(0.05, 0.5).max(2.0 * h);
    let mut w = Walker {
        grid,
        feasible: &feasible,
        r,
        step,
        target,
    };
    let start = centre + DVec2::new(helix_r, 0.0);
    let mut pieces = Vec::new();
    let mut visited = Buckets::new(lo - margin, hi + margin, 1.0);
    for k in 0..72 {
        visited.push(centre + DVec2::from_angle(k as f64 * TAU / 72.0) * helix_r);
    }
    let (pts, _) = w.walk(start, DVec2::Y, None);
    let mut at = pts.last().copied().unwrap_or(start);
    for &q in &pts {
        visited.push(q);
    }
    pieces.push(Planned {
        piece: Piece::Walk(pts),
        down: true,
    });
    let mut todo: Vec<usize> = (0..target_cells.cells.len())
        .filter(|&k| target_cells.cells.get(k).copied().unwrap_or(false))
        .collect();
    let nx = target_cells.nx;
    let cell_centre =
        |k: usize| target_cells.origin + (DVec2::new((k % nx) as f64, (k / nx) as f64) + 0.5) * h;
    for _ in 0..5000 {
        todo.retain(|&k| w.grid.cells.get(k).copied().unwrap_or(false));
        let Some(m) = todo
            .iter()
            .map(|&k| cell_centre(k))
            .min_by(|a, b| a.distance_squared(at).total_cmp(&b.distance_squared(at)))
        else {
            break;
        };
        let Some(c) = visited.nearest(m) else {
            break;
        };
        let down = w.link_clear(at, c);
        let (pts, cleared) = w.walk(c, m - c, Some(m));
        if cleared < 4 {
            // No way in from here: give up the material about this cell.
            todo.retain(|&k| cell_centre(k).distance_squared(m) > 0.25);
            continue;
        }
        at = pts.last().copied().unwrap_or(c);
        for &q in &pts {
            visited.push(q);
        }
        pieces.push(Planned {
            piece: Piece::Walk(pts),
            down,
        });
    }
    // Into every corner of the tool-centre region before the laps, so that they find the
    // corners cleared.
    for b in area.boundaries() {
        let els = b.elements();
        let n = els.len();
        for (i, e) in els.iter().enumerate() {
            let Some(next) = els.get((i + 1) % n) else {
                continue;
            };
            let (t0, t1) = (e.tangent_at(1.0), next.tangent_at(0.0));
            if t0.dot(t1) > 10f64.to_radians().cos() {
                continue;
            }
            let inward = (t0.perp() + t1.perp()).normalize_or_zero();
            let half = 0.5 * t0.perp().angle_to(t1.perp()).abs();
            let goal = e.end() + inward * (4.0 * h / half.cos().max(0.2));
            if !w.feasible.at(goal) {
                continue;
            }
            let Some(c) = visited.nearest(goal) else {
                continue;
            };
            let down = w.link_clear(at, c);
            let (pts, _) = w.walk_to(c, goal - c, Some(goal), true);
            at = pts.last().copied().unwrap_or(c);
            for &q in &pts {
                visited.push(q);
            }
            pieces.push(Planned {
                piece: Piece::Walk(pts),
                down,
            });
        }
    }
    // Laps along every boundary, starting where the tool circle is already clear.
    for b in area.boundaries() {
        let els = b.elements();
        let mut start: Option<(usize, f64)> = None;
        'find: for (i, e) in els.iter().enumerate() {
            let n = (e.length() / 0.5).ceil().clamp(1.0, 1e5);
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let n = n as usize;
            for k in 0..n {
                let t = k as f64 / n as f64;
                if w.grid.circle_clear(e.point_at(t), r - 3.0 * h) {
                    start = Some((i, t));
                    break 'find;
                }
            }
        }
        let Some((i, t)) = start else { continue };
        let lap = lap_from(&els, i, t);
        let Some(s) = lap.first().map(Element::start) else {
            continue;
        };
        let down = w.link_clear(at, s);
        for e in &lap {
            for q in samples(e, step) {
                w.grid.disc(q, r, false);
            }
        }
        at = lap.last().map_or(s, Element::end);
        pieces.push(Planned {
            piece: Piece::Lap(lap),
            down,
        });
    }
    Ok(AreaPlan {
        centre,
        helix_r,
        pieces,
    })
}

/// Emits moves.
struct Out {
    tp: Toolpath,
    feed: f64,
    chord: f64,
}

impl Out {
    fn at(&self) -> Option<DVec3> {
        self.tp.poses.last().map(|p| p.tip)
    }

    fn to(&mut self, kind: MoveKind, p: DVec3) {
        if self.at().is_some_and(|a| a.distance(p) < 1e-9) {
            return;
        }
        let f = if kind == MoveKind::Rapid {
            0.0
        } else {
            self.feed
        };
        self.tp.poses.push(Pose::new(kind, p, DVec3::Z, f));
    }

    fn arc(&mut self, centre: DVec2, sweep: f64, dz: f64) -> Result<(), PlanarError> {
        let z0 = self.at().map_or(0.0, |a| a.z);
        self.tp
            .push_helix(
                centre.extend(z0),
                DVec3::Z,
                sweep,
                dz,
                MoveKind::Cut,
                self.feed,
                self.chord,
            )
            .map_err(|e| PlanarError(e.to_string()))
    }

    fn element(&mut self, e: &Element, z: f64) -> Result<(), PlanarError> {
        match *e {
            Element::Line { b, .. } => {
                self.to(MoveKind::Cut, b.extend(z));
                Ok(())
            }
            Element::Arc {
                centre, sweep_rad, ..
            } => self.arc(centre, sweep_rad, 0.0),
        }
    }

    /// Up to `safe`, over to `p` and down to `z_air`, then fed down to `z`.
    fn retract_to(&mut self, p: DVec2, safe: f64, z_air: f64, z: f64) {
        if let Some(a) = self.at()
            && a.z < safe
        {
            self.to(MoveKind::Rapid, a.truncate().extend(safe));
        }
        self.to(MoveKind::Rapid, p.extend(safe));
        self.to(MoveKind::Rapid, p.extend(z_air));
        self.to(MoveKind::Cut, p.extend(z));
    }
}

fn check(o: &AdaptiveOptions) -> Result<(), PlanarError> {
    let bad = |m: &str| Err(PlanarError(format!("adaptive: {m}")));
    let all = [
        o.top_z_mm,
        o.floor_z_mm,
        o.step_down_mm,
        o.engagement_rad,
        o.wall_allowance_mm,
        o.floor_allowance_mm,
        o.clearance_mm,
        o.ramp_angle_rad,
        o.feed_mm_per_min,
        o.chord_tol_mm,
        o.resolution_mm,
    ];
    if all.iter().any(|v| !v.is_finite()) {
        return bad("every option must be a finite number");
    }
    if o.floor_z_mm >= o.top_z_mm {
        return bad("the floor must lie below the top");
    }
    if !(o.engagement_rad >= 5f64.to_radians() && o.engagement_rad <= PI) {
        return bad("the engagement angle must lie in [5°, 180°]");
    }
    if !(o.step_down_mm > 0.0 && o.feed_mm_per_min > 0.0 && o.clearance_mm > 0.0) {
        return bad("step-down, feed and clearance must be positive");
    }
    if !(o.ramp_angle_rad > 0.0 && o.ramp_angle_rad < FRAC_PI_2) {
        return bad("the ramp angle must lie in (0°, 90°)");
    }
    if !(o.resolution_mm >= 0.005 && o.resolution_mm <= 1.0) {
        return bad("the grid resolution must lie in [0.005, 1] mm");
    }
    if o.wall_allowance_mm < 0.0
        || o.floor_allowance_mm < 0.0
        || o.floor_allowance_mm >= o.top_z_mm - o.floor_z_mm
    {
        return bad("allowances must be non-negative and the floor allowance below the depth");
    }
    Ok(())
}

/// Adaptive clearing of `region` for a flat or bull-nose cutter of the tool record.
///
/// # Errors
/// Bad options, or a region the tool does not fit or has no room for a helix entry.
pub fn adaptive(
    region: &Region,
    tool: &ToolRecord,
    o: &AdaptiveOptions,
) -> Result<Toolpath, PlanarError> {
    check(o)?;
    let r = tool.cutter.radius();
    if !(r > 0.0 && r.is_finite()) {
        return Err(PlanarError("adaptive: the tool has no radius".into()));
    }
    let (lo, hi) = region.bounds();
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(PlanarError("adaptive: the region is empty".into()));
    }
    let centres = region.offset(r + o.wall_allowance_mm);
    if centres.is_empty() {
        return Err(PlanarError(format!(
            "adaptive: a tool of radius {r} mm with {} mm allowance does not fit the region",
            o.wall_allowance_mm
        )));
    }
    let target = (o.engagement_rad - MARGIN_RAD).max(AIR_RAD * 2.0);
    let plans = centres
        .areas
        .iter()
        .map(|a| {
            plan_area(
                &Region {
                    areas: vec![a.clone()],
                },
                r,
                target,
                o,
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    let safe = o.top_z_mm + o.clearance_mm;
    let bottom = o.floor_z_mm + o.floor_allowance_mm;
    let depth = o.top_z_mm - bottom;
    let n = (depth / o.step_down_mm - 1e-9).ceil().max(1.0);
    // A level count: depth over step-down, bounded by the checks on finite options.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let levels = (n as usize).min(100_000);
    let mut out = Out {
        tp: Toolpath::new(tool.clone(), Vec::new()),
        feed: o.feed_mm_per_min,
        chord: o.chord_tol_mm.max(1e-4),
    };
    for plan in &plans {
        let entry = plan.centre + DVec2::new(plan.helix_r, 0.0);
        let mut z_prev = o.top_z_mm;
        for k in 1..=levels {
            let z = o.top_z_mm - depth * k as f64 / levels as f64;
            emit_level(&mut out, plan, entry, z_prev, z, safe, o)?;
            z_prev = z;
        }
        if let Some(a) = out.at() {
            out.to(MoveKind::Rapid, a.truncate().extend(safe));
        }
    }
    out.tp.resummarise();
    Ok(out.tp)
}

fn emit_level(
    out: &mut Out,
    plan: &AreaPlan,
    entry: DVec2,
    z_prev: f64,
    z: f64,
    safe: f64,
    o: &AdaptiveOptions,
) -> Result<(), PlanarError> {
    // Helix from just above the level cut before, counter-clockwise (climb), then a lap flat.
    let z_from = z_prev + 0.5f64.min(o.clearance_mm);
    if let Some(a) = out.at()
        && a.z < safe
    {
        out.to(MoveKind::Rapid, a.truncate().extend(safe));
    }
    out.to(MoveKind::Rapid, entry.extend(safe));
    out.to(MoveKind::Rapid, entry.extend(z_from));
    let lap = TAU * plan.helix_r;
    let dz = z_from - z;
    let laps = (dz / (lap * o.ramp_angle_rad.tan()) - 1e-9).ceil().max(1.0);
    out.arc(plan.centre, TAU * laps, -dz)?;
    out.arc(plan.centre, TAU, 0.0)?;
    let z_air = (z + 0.5).min(z_from);
    for p in &plan.pieces {
        match &p.piece {
            Piece::Walk(pts) => {
                let Some(&s) = pts.first() else { continue };
                if p.down {
                    out.to(MoveKind::Cut, s.extend(z));
                } else {
                    out.retract_to(s, safe, z_air, z);
                }
                for q in pts.iter().skip(1) {
                    out.to(MoveKind::Cut, q.extend(z));
                }
            }
            Piece::Lap(els) => {
                let Some(s) = els.first().map(Element::start) else {
                    continue;
                };
                if p.down {
                    out.to(MoveKind::Cut, s.extend(z));
                } else {
                    out.retract_to(s, safe, z_air, z);
                }
                for e in els {
                    out.element(e, z)?;
                }
            }
        }
    }
    Ok(())
}
