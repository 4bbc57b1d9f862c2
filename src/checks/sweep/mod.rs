//! The union of the tool envelopes swept along the cutting moves of a path, as a signed distance
//! field with a spatial index, and the ray query "how far along the normal to the union".
//!
//! Move model: see `motion` (tip linear, axis slerp). Each move is cut into pieces:
//! - **Ball end mill**: the ball centre `tip + R·axis` follows a straight segment when the axis is
//!   constant and a slightly bent curve when it turns; a move is cut into pieces whose centre
//!   curve stays within `tolerance_mm` of its chord (sagitta `R(1 − cos(Δθ/2)) ≤ tolerance`),
//!   and each piece is the capsule of radius R around its chord: the swept ball is exact to
//!   `tolerance_mm`. Only the ball is swept (the flute cylinder above the ball's equator is not:
//!   it can only matter on walls steeper than the tool axis).
//! - **Other cutters**: the fluted solid ([`crate::tools::Cutter::cutting_solid`], convex) is
//!   swept. A move is cut into pieces in which no tool point moves more than `piece_mm`; the
//!   distance to a piece is the minimum over the piece's parameter of the distance to the placed
//!   solid, found by golden-section search after evaluating the two ends. With a constant axis
//!   (3-axis, 3+2) that function is convex, so the search is exact (to 1e-9 of the piece's
//!   motion). With a turning axis it is exact when the minimum is unimodal and never worse than
//!   the two end placements, whose union lies within `piece_mm / 2` of the true sweep: the
//!   distance error is at most `piece_mm / 2` (the bound reported as `bound_mm`).

use std::collections::HashMap;

use glam::DVec3;

use crate::geometry::minimize::{golden_iterations, golden_min};

mod ray;

use crate::checks::CheckError;
use crate::checks::motion::{Placement, angle_between, cutting_moves, interpolate, motion_bound};
use crate::toolpath::Pose;
use crate::tools::solid::ToolSolid;
use crate::tools::{Cutter, CutterKind};
use ray::ray_capsule;

/// Smallest step of the ray marches, mm: a tool sliver thinner than this along the normal may
/// be stepped over (then the next tool surface beyond it is reported).
const MIN_STEP_MM: f64 = 1e-3;

/// One piece of a swept move.
#[derive(Clone, Copy, Debug)]
struct Piece {
    a: Placement,
    b: Placement,
    /// Bound of the motion of any tool point over the piece, mm.
    motion: f64,
    /// The axis does not turn over the piece (a pure translation).
    translation: bool,
    /// Index of the pose the move ends at.
    pose: usize,
    lo: DVec3,
    hi: DVec3,
}

/// The swept union of a cutter along a path's cutting moves.
#[derive(Clone, Debug)]
pub struct SweptTool {
    solid: ToolSolid,
    ball_radius: Option<f64>,
    pieces: Vec<Piece>,
    cell: f64,
    reach: f64,
    grid: HashMap<(i64, i64, i64), Vec<u32>>,
    bound: f64,
}

/// Distance from a point to the swept union and the pose that owns the nearest piece.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweptDistance {
    /// Signed distance, mm (negative inside the swept tool).
    pub distance_mm: f64,
    /// Index of the pose at the end of the move that is nearest.
    pub pose: usize,
}

pub(crate) fn capsule_distance(p: DVec3, a: DVec3, b: DVec3, r: f64) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).length() - r
}

impl SweptTool {
    /// Build the sweep of `cutter` along the cutting moves of `poses` (see the module doc for
    /// the move model). `tolerance_mm` bounds the ball's chord error; `piece_mm` the motion per
    /// piece for the other cutters; `reach_mm` is the largest distance the queries need (the
    /// index finds every piece within it).
    ///
    /// # Errors
    /// [`CheckError::BadPose`] for a non-finite tip or axis; [`CheckError::BadOption`] for
    /// non-positive tolerances; [`CheckError::Tool`] for an invalid cutter.
    pub fn new(
        cutter: &Cutter,
        poses: &[Pose],
        tolerance_mm: f64,
        piece_mm: f64,
        reach_mm: f64,
    ) -> Result<Self, CheckError> {
        cutter.validate()?;
        for (name, v) in [
            ("tolerance_mm", tolerance_mm),
            ("piece_mm", piece_mm),
            ("reach_mm", reach_mm),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(CheckError::BadOption {
                    name,
                    message: format!("must be a positive length, got {v}"),
                });
            }
        }
        for (index, p) in poses.iter().enumerate() {
            let ok = p.tip.is_finite() && p.axis.is_finite() && p.axis.length() > 0.5;
            if !ok {
                return Err(CheckError::BadPose { index });
            }
        }
        let solid = cutter.cutting_solid();
        let r = cutter.radius();
        let ball_radius = matches!(cutter.kind, CutterKind::Ball).then_some(r);
        let mut pieces = Vec::new();
        for (i0, i1) in cutting_moves(poses) {
            let (Some(p0), Some(p1)) = (poses.get(i0), poses.get(i1)) else {
                continue;
            };
            let mut a = Placement::of(p0);
            let mut b = Placement::of(p1);
            a.axis = a.axis.normalize();
            b.axis = b.axis.normalize();
            let theta = angle_between(a.axis, b.axis);
            let count = match ball_radius {
                Some(r) => {
                    // Sagitta R(1 − cos(θp/2)) ≤ tolerance.
                    let c = (1.0 - tolerance_mm / r).clamp(-1.0, 1.0);
                    let theta_p = 2.0 * c.acos();
                    (theta / theta_p.max(1e-9)).ceil()
                }
                None => (motion_bound(a, b, solid.top(), r) / piece_mm).ceil(),
            };
            let n = count.clamp(1.0, 1.0e5) as usize;
            for k in 0..n {
                let s0 = k as f64 / n as f64;
                let s1 = (k + 1) as f64 / n as f64;
                let pa = interpolate(a, b, s0);
                let pb = interpolate(a, b, s1);
                let motion = motion_bound(pa, pb, solid.top(), r);
                pieces.push(Self::piece(pa, pb, motion, i1, &solid, ball_radius));
            }
        }
        let cell = (2.0 * solid.max_radius()).max(reach_mm).max(1e-3);
        let mut me = Self {
            solid,
            ball_radius,
            pieces,
            cell,
            reach: reach_mm,
            grid: HashMap::new(),
            bound: match ball_radius {
                Some(_) => tolerance_mm,
                None => 0.5 * piece_mm,
            },
        };
        me.index();
        Ok(me)
    }

    fn piece(
        a: Placement,
        b: Placement,
        motion: f64,
        pose: usize,
        solid: &ToolSolid,
        ball: Option<f64>,
    ) -> Piece {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        let (top, pad) = match ball {
            Some(r) => (r, r),
            None => (solid.top(), solid.max_radius() + 0.5 * motion),
        };
        for q in [a, b] {
            let c0 = if ball.is_some() {
                q.tip + q.axis * top
            } else {
                q.tip
            };
            let c1 = q.tip + q.axis * top;
            lo = lo.min(c0.min(c1));
            hi = hi.max(c0.max(c1));
        }
        Piece {
            a,
            b,
            motion,
            translation: angle_between(a.axis, b.axis) < 1e-12,
            pose,
            lo: lo - DVec3::splat(pad),
            hi: hi + DVec3::splat(pad),
        }
    }

    fn key(&self, p: DVec3) -> (i64, i64, i64) {
        let k = (p / self.cell).floor();
        (k.x as i64, k.y as i64, k.z as i64)
    }

    fn index(&mut self) {
        let reach = DVec3::splat(self.reach);
        let mut grid: HashMap<(i64, i64, i64), Vec<u32>> = HashMap::new();
        for (i, pc) in self.pieces.iter().enumerate() {
            let k0 = self.key(pc.lo - reach);
            let k1 = self.key(pc.hi + reach);
            for x in k0.0..=k1.0 {
                for y in k0.1..=k1.1 {
                    for z in k0.2..=k1.2 {
                        grid.entry((x, y, z)).or_default().push(i as u32);
                    }
                }
            }
        }
        self.grid = grid;
    }

    /// Bound on the distance error of the discretised sweep, mm (see the module doc).
    #[must_use]
    pub fn bound_mm(&self) -> f64 {
        self.bound
    }

    /// Pieces that may lie within the reach of the segment from `p` to `q` (sorted, unique).
    fn candidates(&self, p: DVec3, q: DVec3) -> Vec<u32> {
        let k0 = self.key(p.min(q));
        let k1 = self.key(p.max(q));
        let mut out = Vec::new();
        for x in k0.0..=k1.0 {
            for y in k0.1..=k1.1 {
                for z in k0.2..=k1.2 {
                    if let Some(v) = self.grid.get(&(x, y, z)) {
                        // Only pieces whose box, grown by the reach, meets the query box.
                        let (lo, hi) = (p.min(q), p.max(q));
                        out.extend(v.iter().copied().filter(|&i| {
                            self.pieces.get(i as usize).is_some_and(|pc| {
                                let r = DVec3::splat(self.reach);
                                (pc.lo - r).cmple(hi).all() && (pc.hi + r).cmpge(lo).all()
                            })
                        }));
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    fn piece_distance(&self, pc: &Piece, p: DVec3) -> f64 {
        if let Some(r) = self.ball_radius {
            let ca = pc.a.tip + pc.a.axis * r;
            let cb = pc.b.tip + pc.b.axis * r;
            return capsule_distance(p, ca, cb, r);
        }
        let f = |s: f64| {
            let q = interpolate(pc.a, pc.b, s);
            self.solid.signed_distance_at(p, q.tip, q.axis)
        };
        if pc.motion <= 1e-12 {
            return f(0.0).min(f(1.0));
        }
        // Golden-section search on [0, 1] (convex for a constant axis), to 1e-9 mm of motion.
        golden_min(0.0, 1.0, golden_iterations(pc.motion, 1e-9, 80), f)
    }

    /// Lower bound of the distance to a piece: the placement at the piece's middle less half its
    /// motion (Lipschitz), or with `tight` for a translation the convexity bound.
    fn piece_lower_bound(&self, pc: &Piece, p: DVec3, tight: bool) -> f64 {
        if self.ball_radius.is_some() {
            return self.piece_distance(pc, p);
        }
        let q = interpolate(pc.a, pc.b, 0.5);
        let fm = self.solid.signed_distance_at(p, q.tip, q.axis);
        if tight && pc.translation {
            // Convex in the piece's parameter (a convex solid translated along a line): on each
            // half the function stays above the secant through the middle and the far end, so
            // min ≥ f(½) − max(f(0) − f(½), f(1) − f(½), 0).
            let fa = self.solid.signed_distance_at(p, pc.a.tip, pc.a.axis);
            let fb = self.solid.signed_distance_at(p, pc.b.tip, pc.b.axis);
            return fm - (fa - fm).max(fb - fm).max(0.0);
        }
        fm - 0.5 * pc.motion
    }

    /// Lower bounds of the distances from `p` to the candidate pieces, ascending (exact
    /// distances for ball capsules).
    fn bounds_at(&self, p: DVec3, cand: &[u32]) -> Vec<(f64, u32)> {
        // Pieces farther than the reach from p cannot matter within the reach of p.
        let mut out: Vec<(f64, u32)> = cand
            .iter()
            .filter_map(|&i| {
                let pc = self.pieces.get(i as usize)?;
                let lb = self.piece_lower_bound(pc, p, false);
                (lb <= self.reach).then_some((lb, i))
            })
            .collect();
        out.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        out
    }

    /// Signed distance to the union at `x`, a point within `t` of the point `p` at which
    /// `sorted` holds the bounds (a piece's distance at `x` is at least its bound at `p` less
    /// `t`, so the scan stops early). `(∞, usize::MAX)` when there are no pieces.
    fn union_near(&self, x: DVec3, t: f64, sorted: &[(f64, u32)]) -> (f64, usize) {
        let mut best = (f64::INFINITY, usize::MAX);
        for &(lb, i) in sorted {
            if lb - t >= best.0 {
                break;
            }
            let Some(pc) = self.pieces.get(i as usize) else {
                continue;
            };
            let d = if self.ball_radius.is_some() {
                self.piece_distance(pc, x)
            } else {
                let lbx = self.piece_lower_bound(pc, x, true);
                if lbx >= best.0 {
                    continue;
                }
                self.piece_distance(pc, x)
            };
            if d < best.0 {
                best = (d, pc.pose);
            }
        }
        best
    }

    /// Signed distance from `p` to the swept union; `None` when no piece lies within the reach.
    #[must_use]
    pub fn distance(&self, p: DVec3) -> Option<SweptDistance> {
        let cand = self.candidates(p, p);
        let sorted = self.bounds_at(p, &cand);
        let (d, pose) = self.union_near(p, 0.0, &sorted);
        (pose != usize::MAX).then_some(SweptDistance {
            distance_mm: d,
            pose,
        })
    }

    /// Deviation of a surface point `p` with unit tool-side normal `n`: negative = penetration
    /// (the swept tool reaches that far below `p` along −n: the distance from `p` to the union's
    /// exit along −n), positive = the distance along `n` from `p` to the swept union (remaining
    /// height). `None` when the ray
    /// meets no tool within the reach (uncovered). Sphere tracing on the exact distance field,
    /// to 1e-9 mm.
    #[must_use]
    pub fn deviation(&self, p: DVec3, n: DVec3) -> Option<SweptDistance> {
        let cand = self.candidates(p - n * self.reach, p + n * self.reach);
        let sorted = self.bounds_at(p, &cand);
        let (d0, pose0) = self.union_near(p, 0.0, &sorted);
        if pose0 == usize::MAX {
            return None;
        }
        if d0 <= 0.0 {
            // Inside: march along −n to the exit of the union (−d is a lower bound of the
            // distance to the union's boundary, so each step stays inside).
            // Steps are at least MIN_STEP_MM (a grazing exit would otherwise take tiny steps);
            // an overshoot is bisected back to the boundary.
            let f = |t: f64| self.union_near(p - n * t, t, &sorted).0;
            let (mut t, mut d) = (0.0, d0);
            for _ in 0..2000 {
                if d > -1e-10 || t > self.reach {
                    break;
                }
                let next = t + (-d).max(MIN_STEP_MM);
                let dn = f(next);
                if dn > 0.0 {
                    let (mut lo, mut hi) = (t, next);
                    for _ in 0..40 {
                        let mid = 0.5 * (lo + hi);
                        if f(mid) > 0.0 {
                            hi = mid;
                        } else {
                            lo = mid;
                        }
                    }
                    t = lo;
                    break;
                }
                (t, d) = (next, dn);
            }
            return Some(SweptDistance {
                distance_mm: -t,
                pose: pose0,
            });
        }
        if let Some(r) = self.ball_radius {
            // Exact: first hit of the ray with any capsule. A capsule's hit is no nearer than
            // its distance from p, so the scan in order of distance stops early.
            let mut best = (f64::INFINITY, usize::MAX);
            for &(dp, i) in &sorted {
                if dp >= best.0 {
                    break;
                }
                let Some(pc) = self.pieces.get(i as usize) else {
                    continue;
                };
                let ca = pc.a.tip + pc.a.axis * r;
                let cb = pc.b.tip + pc.b.axis * r;
                if let Some(t) = ray_capsule(p, n, ca, cb, r)
                    && t < best.0
                {
                    best = (t, pc.pose);
                }
            }
            return (best.0 <= self.reach).then_some(SweptDistance {
                distance_mm: best.0,
                pose: best.1,
            });
        }
        // Sphere tracing with steps of at least MIN_STEP_MM; an overshoot into a tool is
        // bisected back to its boundary.
        let f = |t: f64| self.union_near(p + n * t, t, &sorted);
        let mut t = 0.0;
        let (mut d, mut pose) = (d0, pose0);
        for _ in 0..2000 {
            if d < 1e-9 {
                break;
            }
            let next = t + d.max(MIN_STEP_MM);
            if next > self.reach {
                return None;
            }
            let (dn, pn) = f(next);
            if pn == usize::MAX {
                return None;
            }
            if dn < 0.0 {
                let (mut lo, mut hi) = (t, next);
                pose = pn;
                for _ in 0..40 {
                    let mid = 0.5 * (lo + hi);
                    let (dm, pm) = f(mid);
                    if dm < 0.0 {
                        (hi, pose) = (mid, pm);
                    } else {
                        lo = mid;
                    }
                }
                t = hi;
                break;
            }
            (t, d, pose) = (next, dn, pn);
        }
        Some(SweptDistance {
            distance_mm: t,
            pose,
        })
    }
}
