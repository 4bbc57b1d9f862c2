//! Swept bodies prepared once per step for every ray of one direction: what depends only on
//! the step and the direction is computed once, per ray only what depends on its origin.
//!
//! - [`SweptCyl`]: a finite cylinder swept along the step, the same region as
//!   [`swept_cylinder`]: a point `o + s·e` is inside when some `t ∈ [0, 1]` puts
//!   `q = o + s·e − p₀ − t·d` inside the cylinder, i.e. in the (s, t) plane the ellipse
//!   `|A s + B t + C|² ≤ ρ²` (A, B the parts of `e` and `−d` normal to the axis, C that of
//!   `o − p₀`) cut by the slabs `0 ≤ t ≤ 1` and `z₀ ≤ a·(s e − t d + o − p₀) ≤ z₁`. Written as
//!   the quadratic form `xᵀ M x + 2 g·x + k`, M, the slabs' normals and the directions of
//!   their boundary lines depend only on the step and the ray direction; per ray only g, k
//!   and the axial slab's bounds change (four dot products). The interval's ends are the
//!   least and greatest s of the candidates of [`swept_cylinder`] (the ellipse's points with
//!   a vertical tangent, ellipse–line crossings, line–line corners), each checked against
//!   every constraint with the same tolerances, now in two dimensions. Only the general case
//!   (a proper ellipse and an axial slab) is prepared; degenerate steps (moving along the
//!   axis, a ray parallel to the axis or normal to the step) stay with [`swept_cylinder`].
//! - [`SweptBall`]: a sphere swept along the step (a capsule): the entry and the exit of a
//!   line from one set of dot products, with the operations of [`capsule_entry`] in the same
//!   order, so the values are the same to the bit.
//! - [`SweepBound`]: outer bounds of a line's interval in a cylinder's sweep from planes of
//!   support, one dot product per plane; [`RowBound`]: the same planes for a row of lines
//!   along a grid axis, their constants taken once per row (one product per plane and line).

use std::f64::consts::FRAC_1_SQRT_2;

use glam::{DVec2, DVec3};

use super::exact::Cyl;
#[cfg(doc)]
use super::exact::{capsule_entry, swept_cylinder};

/// A boundary line `n·x = c` as seen by the quadratic form: direction `v = (−n_y, n_x)`,
/// `vᵀ M v` and `M v`, all per step.
#[derive(Clone, Copy, Debug)]
struct LineDir {
    n: DVec2,
    nn: f64,
    v: DVec2,
    vmv: f64,
    mv: DVec2,
}

impl LineDir {
    fn new(n: DVec2, m: [f64; 3]) -> Self {
        let v = DVec2::new(-n.y, n.x);
        let mv = DVec2::new(m[0] * v.x + m[1] * v.y, m[1] * v.x + m[2] * v.y);
        Self {
            n,
            nn: n.length_squared(),
            v,
            vmv: v.dot(mv),
            mv,
        }
    }
}

/// A cylinder's sweep along a step, for the lines of one direction.
#[derive(Clone, Copy, Debug)]
pub(super) struct SweptCyl {
    a: DVec3,
    p0: DVec3,
    /// The parts of `e` and `−d` normal to the axis.
    pa: DVec3,
    pb: DVec3,
    /// M = [[m00, m01], [m01, m11]].
    m: [f64; 3],
    rr: f64,
    z0: f64,
    z1: f64,
    /// The ellipse's vertical tangents: `m00 − m01²/m11` and `1/m11`.
    qa: f64,
    inv_m11: f64,
    /// The slab `0 ≤ t ≤ 1` and the axial slab's normal `(a·e, −a·d)`.
    t_line: LineDir,
    ax_line: LineDir,
    /// Whether the two slabs cross (their corners are candidates).
    corners: bool,
}

impl SweptCyl {
    /// The sweep of `cyl` from tip `p0` by `d`, for lines along the unit `e`; `None` when
    /// degenerate (then [`swept_cylinder`] decides).
    pub(super) fn new(e: DVec3, p0: DVec3, d: DVec3, cyl: Cyl) -> Option<Self> {
        let Cyl { a, rho, z0, z1 } = cyl;
        if !(z1 > z0) {
            return None;
        }
        let perp = |v: DVec3| v - a * a.dot(v);
        let (pa, pb) = (perp(e), -perp(d));
        let axial = DVec2::new(a.dot(e), -a.dot(d));
        let (aa, bb) = (pa.length_squared(), pb.length_squared());
        let cross = pa.cross(pb).length_squared();
        if axial.length_squared() < 1e-24
            || aa + bb < 1e-24
            || cross <= 1e-18 * aa * bb
            || aa < 1e-24
            || bb < 1e-24
        {
            return None;
        }
        let m = [aa, pa.dot(pb), bb];
        let qa = m[0] - m[1] * m[1] / m[2];
        if !(qa >= 1e-30) {
            return None;
        }
        let t_n = DVec2::new(0.0, 1.0);
        let det = t_n.x * axial.y - t_n.y * axial.x;
        Some(Self {
            a,
            p0,
            pa,
            pb,
            m,
            rr: rho * rho,
            z0,
            z1,
            qa,
            inv_m11: 1.0 / m[2],
            t_line: LineDir::new(t_n, m),
            ax_line: LineDir::new(axial, m),
            corners: det.abs() > 1e-15 * t_n.length() * axial.length(),
        })
    }

    /// Interval of s on the line `o + s·e` inside the sweep.
    pub(super) fn interval(&self, o: DVec3) -> Option<(f64, f64)> {
        let y = o - self.p0;
        let ay = self.a.dot(y);
        let c = y - self.a * ay;
        let g = DVec2::new(self.pa.dot(c), self.pb.dot(c));
        let k = c.length_squared() - self.rr;
        let (lo, hi) = (self.z0 - ay, self.z1 - ay);
        let m = self.m;
        let q = |x: DVec2| {
            m[0] * x.x * x.x + 2.0 * m[1] * x.x * x.y + m[2] * x.y * x.y + 2.0 * g.dot(x) + k
        };
        let ax = self.ax_line.n;
        let eps_t = 1e-9 * 2.0;
        let eps_ax = 1e-9 * (1.0 + lo.abs().max(hi.abs()));
        let q_tol = 1e-9 * self.rr + 1e-12;
        let (mut s_lo, mut s_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut take = |x: DVec2, check_q: bool| {
            // Within the ends found so far it changes nothing (the checks are spared).
            if s_lo <= x.x && x.x <= s_hi {
                return;
            }
            let v = ax.dot(x);
            let inside = x.is_finite()
                && x.y >= -eps_t
                && x.y <= 1.0 + eps_t
                && v >= lo - eps_ax
                && v <= hi + eps_ax
                && (!check_q || q(x) <= q_tol);
            if inside {
                s_lo = s_lo.min(x.x);
                s_hi = s_hi.max(x.x);
            }
        };
        // The ellipse's points of extreme s: ∂Q/∂t = 0.
        let qb = g.x - m[1] * g.y * self.inv_m11;
        let qc = k - g.y * g.y * self.inv_m11;
        let disc = qb * qb - self.qa * qc;
        // The form's least value is −disc/qa: above the tolerance of every candidate's
        // check, no candidate can be taken (the line crossings need q = 0 on the line, the
        // corners q ≤ q_tol), so the line misses the sweep.
        if disc < -self.qa * q_tol {
            return None;
        }
        if disc >= 0.0 {
            let sq = disc.sqrt();
            for s in [(-qb - sq) / self.qa, (-qb + sq) / self.qa] {
                let t = -(m[1] * s + g.y) * self.inv_m11;
                take(DVec2::new(s, t), true);
            }
        }
        // Crossings of the ellipse with the slabs' boundary lines.
        for (line, cs) in [(&self.t_line, [0.0, 1.0]), (&self.ax_line, [lo, hi])] {
            for cval in cs {
                let p = line.n * (cval / line.nn);
                let mp = line.mv.dot(p) + g.dot(line.v);
                let qp = q(p);
                let disc = mp * mp - line.vmv * qp;
                if line.vmv < 1e-30 || disc < 0.0 {
                    continue;
                }
                let sq = disc.sqrt();
                take(p + line.v * ((-mp - sq) / line.vmv), true);
                take(p + line.v * ((-mp + sq) / line.vmv), true);
            }
        }
        // The slabs' corners.
        if self.corners {
            for t in [0.0, 1.0] {
                for cval in [lo, hi] {
                    let x = DVec2::new((cval - ax.y * t) / ax.x, t);
                    take(x, true);
                }
            }
        }
        (s_lo <= s_hi).then_some((s_lo, s_hi))
    }
}

/// Side planes per bound (the tangent planes of the cylinder's side at these angles from
/// the side facing the lines, and the end cap): three and the cap fill one group of four
/// lanes. Fewer, looser planes than the 13 of before (−60° to 60° by 10°) send a few more
/// lines to the exact solve (+9 % of its instructions) but cost a quarter per line; the
/// bounds only pass lines over, so the result is the same either way.
const SIDE_ANGLES_DEG: [f64; 3] = [-45.0, 0.0, 45.0];
/// `(cos, sin)` of [`SIDE_ANGLES_DEG`] (the bound holds for any normals; these are only
/// spared the trigonometry per step).
const SIDE_COS_SIN: [(f64, f64); 3] = [
    (FRAC_1_SQRT_2, -FRAC_1_SQRT_2),
    (1.0, 0.0),
    (FRAC_1_SQRT_2, FRAC_1_SQRT_2),
];
/// Planes of a bound: the side planes and the cap.
const PLANES: usize = SIDE_ANGLES_DEG.len() + 1;
/// Slack of a bound beyond the exact sweep, mm: more than the tolerances of the exact
/// solve (1e-9 of the offsets and of ρ², over `n·e` ≥ 0.1) and the rounding of the bound.
const BOUND_SLACK_MM: f64 = 1e-5;

/// Bounds of the offsets where a line `o + s·e` can be inside a cylinder's sweep, without a
/// square root: for any unit `n`, every point x of the sweep has `n·x ≥ H(n)` with
/// `H(n) = n·p₀ + min(0, n·d) + min(z₀ n·a, z₁ n·a) − ρ·|n − a (n·a)|`, so along the line
/// `s ≥ (H − n·o)/(n·e)` where `n·e > 0` and `s ≤` the same where `n·e < 0`. The planes are
/// the cap's and tangent planes of the side facing the line (below: lower bounds; above:
/// upper bounds); where the line meets the sweep within 45° of the side facing it the
/// bounds are within about `ρ·(1/cos 22.5° − 1)/(n·e)` of its ends. Per line: one dot
/// product per plane, the four planes of a side (three side planes and the cap) at once (the
/// planes are stored by coordinate, padded with planes that bound nothing).
#[derive(Clone, Copy, Debug)]
pub(super) struct SweepBound {
    /// `s ≥ c − m·o` for every plane.
    lower: Planes,
    /// `s ≤ c − m·o` for every plane.
    upper: Planes,
}

/// Plane slots of a [`Planes`]: [`PLANES`] rounded up to whole groups of four.
const SLOTS: usize = PLANES.div_ceil(4) * 4;

/// Planes `c − m·o` of one side of a [`SweepBound`], by coordinate in groups of four.
#[derive(Clone, Copy, Debug)]
struct Planes {
    mx: [[f64; 4]; SLOTS / 4],
    my: [[f64; 4]; SLOTS / 4],
    mz: [[f64; 4]; SLOTS / 4],
    c: [[f64; 4]; SLOTS / 4],
    /// Planes set.
    count: usize,
}

impl Planes {
    /// No plane: every slot `c = fill`, `m = 0`.
    fn new(fill: f64) -> Self {
        Self {
            mx: [[0.0; 4]; SLOTS / 4],
            my: [[0.0; 4]; SLOTS / 4],
            mz: [[0.0; 4]; SLOTS / 4],
            c: [[fill; 4]; SLOTS / 4],
            count: 0,
        }
    }

    fn push(&mut self, m: DVec3, c: f64) {
        let (g, l) = (self.count / 4, self.count % 4);
        if let (Some(x), Some(y), Some(z), Some(cc)) = (
            self.mx.get_mut(g).and_then(|r| r.get_mut(l)),
            self.my.get_mut(g).and_then(|r| r.get_mut(l)),
            self.mz.get_mut(g).and_then(|r| r.get_mut(l)),
            self.c.get_mut(g).and_then(|r| r.get_mut(l)),
        ) {
            (*x, *y, *z, *cc) = (m.x, m.y, m.z, c);
            self.count += 1;
        }
    }

    /// `c − m·o` of every slot (the dot product in the order of `DVec3::dot`).
    fn values(&self, o: DVec3) -> [[f64; 4]; SLOTS / 4] {
        let mut out = [[0.0; 4]; SLOTS / 4];
        for (g, row) in out.iter_mut().enumerate() {
            let (Some(x), Some(y), Some(z), Some(c)) = (
                self.mx.get(g),
                self.my.get(g),
                self.mz.get(g),
                self.c.get(g),
            ) else {
                continue;
            };
            for l in 0..4 {
                row[l] = c[l] - (x[l] * o.x + y[l] * o.y + z[l] * o.z);
            }
        }
        out
    }

    /// The greatest value (−∞ with no plane).
    fn max(&self, o: DVec3) -> f64 {
        lane_max(&self.values(o))
    }

    /// The least value (+∞ with no plane).
    fn min(&self, o: DVec3) -> f64 {
        lane_min(&self.values(o))
    }
}

/// The greatest of the slots (−∞ with none): four lanes reduced together, then pairwise.
#[inline]
fn lane_max(v: &[[f64; 4]; SLOTS / 4]) -> f64 {
    let mut acc = [f64::NEG_INFINITY; 4];
    for row in v {
        for l in 0..4 {
            acc[l] = if row[l] > acc[l] { row[l] } else { acc[l] };
        }
    }
    let a = if acc[1] > acc[0] { acc[1] } else { acc[0] };
    let b = if acc[3] > acc[2] { acc[3] } else { acc[2] };
    if b > a { b } else { a }
}

/// The least of the slots (+∞ with none), as [`lane_max`].
#[inline]
fn lane_min(v: &[[f64; 4]; SLOTS / 4]) -> f64 {
    let mut acc = [f64::INFINITY; 4];
    for row in v {
        for l in 0..4 {
            acc[l] = if row[l] < acc[l] { row[l] } else { acc[l] };
        }
    }
    let a = if acc[1] < acc[0] { acc[1] } else { acc[0] };
    let b = if acc[3] < acc[2] { acc[3] } else { acc[2] };
    if b < a { b } else { a }
}

/// The planes of one side of a [`SweepBound`] along a row of lines `o = o₀ + x·û` (`û` a
/// grid axis): `c − m·o = k − (m·û)·x` with `k = c − m·o₀`, one product per plane and line.
#[derive(Clone, Copy, Debug, Default)]
struct RowPlanes {
    k: [[f64; 4]; SLOTS / 4],
    m: [[f64; 4]; SLOTS / 4],
}

impl Planes {
    /// The planes along the row from `o₀` along the grid axis `u` (0, 1, 2: x, y, z), into
    /// `out`.
    fn along_into(&self, o0: DVec3, u: usize, out: &mut RowPlanes) {
        out.k = self.values(o0);
        out.m = match u {
            0 => self.mx,
            1 => self.my,
            _ => self.mz,
        };
    }
}

impl RowPlanes {
    /// `k − m·x` of every slot.
    #[inline]
    fn values(&self, x: f64) -> [[f64; 4]; SLOTS / 4] {
        let mut out = self.k;
        for (row, m) in out.iter_mut().zip(&self.m) {
            for l in 0..4 {
                row[l] -= m[l] * x;
            }
        }
        out
    }

    /// The greatest value (−∞ with no plane).
    #[inline]
    fn max(&self, x: f64) -> f64 {
        lane_max(&self.values(x))
    }

    /// The least value (+∞ with no plane).
    #[inline]
    fn min(&self, x: f64) -> f64 {
        lane_min(&self.values(x))
    }
}

/// A [`SweepBound`] for the lines of one row, `o = o₀ + x·û`: the same planes, their
/// constants taken at `o₀` once per row. The values differ from [`SweepBound::range`] at
/// `o` only by rounding (about 1e-16 of `|m|·|o|`), far inside [`BOUND_SLACK_MM`], so they
/// bound the exact interval all the same.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct RowBound {
    lower: RowPlanes,
    upper: RowPlanes,
}

impl RowBound {
    /// The lower bound at `x` along the row (as [`SweepBound::lower`]).
    #[inline]
    pub(super) fn lower(&self, x: f64) -> f64 {
        let lo = self.lower.max(x);
        lo - (BOUND_SLACK_MM + 1e-12 * lo.abs().min(1e6))
    }

    /// The upper bound at `x` along the row (as [`SweepBound::upper`]).
    #[inline]
    pub(super) fn upper(&self, x: f64) -> f64 {
        let hi = self.upper.min(x);
        hi + (BOUND_SLACK_MM + 1e-12 * hi.abs().min(1e6))
    }
}

impl SweepBound {
    /// The bound for the row of lines `o₀ + x·û` along the grid axis `u`.
    #[cfg(test)]
    pub(super) fn along(&self, o0: DVec3, u: usize) -> RowBound {
        let mut out = RowBound::default();
        self.along_into(o0, u, &mut out);
        out
    }

    /// [`SweepBound::along`] written into `out` (no copy of the result).
    pub(super) fn along_into(&self, o0: DVec3, u: usize, out: &mut RowBound) {
        self.lower.along_into(o0, u, &mut out.lower);
        self.upper.along_into(o0, u, &mut out.upper);
    }

    /// The bound of `cyl` swept from tip `p0` by `d`, for lines along the unit `e`; with
    /// `ball` = R, of its union with the sphere of radius R centred R above the tip on the
    /// axis (a ball end mill: the body is the hull of both, its support the least of theirs).
    pub(super) fn new(e: DVec3, p0: DVec3, d: DVec3, cyl: Cyl, ball: Option<f64>) -> Self {
        let Cyl { a, rho, z0, z1 } = cyl;
        let mut out = Self {
            lower: Planes::new(f64::NEG_INFINITY),
            upper: Planes::new(f64::INFINITY),
        };
        let support = |n: DVec3| {
            let na = n.dot(a);
            let shaft = (z0 * na).min(z1 * na) - rho * (n - a * na).length();
            let end = ball.map_or(f64::INFINITY, |r| r * na - r * n.length());
            n.dot(p0) + n.dot(d).min(0.0) + shaft.min(end)
        };
        let mut add = |n: DVec3| {
            let ne = n.dot(e);
            if ne.abs() < 0.1 {
                return;
            }
            let (m, c) = (n / ne, support(n) / ne);
            if ne > 0.0 {
                out.lower.push(m, c);
            } else {
                out.upper.push(m, c);
            }
        };
        let pe = e - a * a.dot(e);
        if let Some(p) = pe.try_normalize() {
            let q = a.cross(p);
            for (cos, sin) in SIDE_COS_SIN {
                let n = p * cos + q * sin;
                add(n);
                add(-n);
            }
        }
        add(a);
        add(-a);
        out
    }

    /// Bounds `(lo, hi)` of the offsets of the line `o + s·e` inside the sweep (outer: the
    /// exact interval lies within them), widened by [`BOUND_SLACK_MM`].
    pub(super) fn range(&self, o: DVec3) -> (f64, f64) {
        (self.lower(o), self.upper(o))
    }

    /// The lower bound of [`SweepBound::range`].
    pub(super) fn lower(&self, o: DVec3) -> f64 {
        let lo = self.lower.max(o);
        lo - (BOUND_SLACK_MM + 1e-12 * lo.abs().min(1e6))
    }

    /// The upper bound of [`SweepBound::range`].
    pub(super) fn upper(&self, o: DVec3) -> f64 {
        let hi = self.upper.min(o);
        hi + (BOUND_SLACK_MM + 1e-12 * hi.abs().min(1e6))
    }
}

/// A sphere of radius r swept from `pa` to `pb` (a capsule), for the lines along one unit `e`.
#[derive(Clone, Copy, Debug)]
pub(super) struct SweptBall {
    e: DVec3,
    pa: DVec3,
    pb: DVec3,
    ba: DVec3,
    rr: f64,
    baba: f64,
    bard: f64,
    /// `|ba|² − (ba·e)²`, and whether the capsule's side is met at all (not along the axis).
    a: f64,
    side: bool,
}

/// Entry and exit of a line into a sphere, from `e·(o − c)` and `|o − c|² − r²`.
fn sphere_interval(b: f64, c: f64) -> Option<(f64, f64)> {
    let h = b * b - c;
    (h >= 0.0).then(|| {
        let sq = h.sqrt();
        (-b - sq, -b + sq)
    })
}

impl SweptBall {
    /// The sphere of radius `r` swept from centre `pa` to `pb`, for lines along `e`.
    pub(super) fn new(e: DVec3, pa: DVec3, pb: DVec3, r: f64) -> Self {
        let ba = pb - pa;
        let baba = ba.length_squared();
        let bard = ba.dot(e);
        let a = baba - bard * bard;
        Self {
            e,
            pa,
            pb,
            ba,
            rr: r * r,
            baba,
            bard,
            a,
            side: a > 1e-12 * baba.max(1e-300),
        }
    }

    /// Entry and exit offsets (each `None` where the line misses) of the line `o + s·e`.
    pub(super) fn entry_exit(&self, o: DVec3) -> (Option<f64>, Option<f64>) {
        let (e, ba, baba, bard) = (self.e, self.ba, self.baba, self.bard);
        let oa = o - self.pa;
        let baoa = ba.dot(oa);
        let rdoa = e.dot(oa);
        let oaoa = oa.length_squared();
        let (mut lo, mut hi): (Option<f64>, Option<f64>) = (None, None);
        let mut keep_lo = |s: f64| lo = Some(lo.map_or(s, |v: f64| v.min(s)));
        let mut keep_hi = |s: f64| hi = Some(hi.map_or(s, |v: f64| v.max(s)));
        if self.side {
            // capsule_entry along e and along −e (b changes sign, h is the same).
            let b = baba * rdoa - baoa * bard;
            let c = baba * oaoa - baoa * baoa - self.rr * baba;
            let h = b * b - self.a * c;
            if h >= 0.0 {
                let sq = h.sqrt();
                let s = (-b - sq) / self.a;
                let y = baoa + s * bard;
                if y > 0.0 && y < baba {
                    keep_lo(s);
                }
                let x = -((b - sq) / self.a);
                let y = baoa + x * bard;
                if y > 0.0 && y < baba {
                    keep_hi(x);
                }
            }
        }
        let ob = o - self.pb;
        for (oc, occ) in [(oa, oaoa), (ob, ob.length_squared())] {
            if let Some((s0, s1)) = sphere_interval(e.dot(oc), occ - self.rr) {
                keep_lo(s0);
                keep_hi(s1);
            }
        }
        (lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::exact::swept_cylinder;

    #[test]
    fn prepared_sweep_matches_swept_cylinder() {
        let axes = [
            DVec3::new(0.0, 0.3, 1.0).normalize(),
            DVec3::new(0.5, -0.2, 0.8).normalize(),
            DVec3::new(-0.7, 0.1, 0.7).normalize(),
        ];
        let moves = [
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::new(3.0, 2.0, -1.0),
            DVec3::new(0.02, -0.01, 0.005),
        ];
        let (mut prepared, mut hits) = (0, 0);
        for a in axes {
            let cyl = Cyl {
                a,
                rho: 3.0,
                z0: 3.0,
                z1: 18.0,
            };
            for d in moves {
                for e in [DVec3::X, DVec3::Y, DVec3::Z] {
                    let p0 = DVec3::new(0.4, -0.3, 1.0);
                    let Some(sw) = SweptCyl::new(e, p0, d, cyl) else {
                        continue;
                    };
                    prepared += 1;
                    for k in 0..900 {
                        let (u, v) = (f64::from(k % 30) - 14.5, f64::from(k / 30) - 14.5);
                        let o = if e == DVec3::X {
                            DVec3::new(-40.0, u, v)
                        } else if e == DVec3::Y {
                            DVec3::new(v, -40.0, u)
                        } else {
                            DVec3::new(u, v, -40.0)
                        };
                        let want = swept_cylinder(o, e, p0, d, cyl);
                        let got = sw.interval(o);
                        match (got, want) {
                            (Some(g), Some(w)) => {
                                hits += 1;
                                assert!(
                                    (g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9,
                                    "{a} {d} {o} {e}: {g:?} {w:?}"
                                );
                            }
                            (None, None) => {}
                            other => panic!("{a} {d} {o} {e}: {other:?}"),
                        }
                    }
                }
            }
        }
        assert!(prepared >= 20 && hits > 1000, "{prepared} {hits}");
    }

    #[test]
    fn sweep_bound_holds_the_exact_interval_closely() {
        let mut hits = 0;
        let mut worst = 0.0_f64;
        for a in [
            DVec3::new(0.0, 0.3, 1.0).normalize(),
            DVec3::new(0.5, -0.2, 0.8).normalize(),
            DVec3::new(-0.7, 0.1, 0.7).normalize(),
        ] {
            let cyl = Cyl {
                a,
                rho: 3.0,
                z0: 3.0,
                z1: 18.0,
            };
            for d in [DVec3::new(0.08, 0.01, -0.02), DVec3::new(3.0, 2.0, -1.0)] {
                let p0 = DVec3::new(0.4, -0.3, 1.0);
                for e in [DVec3::X, DVec3::Y, DVec3::Z] {
                    let bound = SweepBound::new(e, p0, d, cyl, None);
                    for k in 0..3600 {
                        let (u, v) = (
                            f64::from(k % 60) * 0.5 - 14.7,
                            f64::from(k / 60) * 0.5 - 14.7,
                        );
                        let o = if e == DVec3::X {
                            DVec3::new(-40.0, u, v)
                        } else if e == DVec3::Y {
                            DVec3::new(v, -40.0, u)
                        } else {
                            DVec3::new(u, v, -40.0)
                        };
                        let Some((s0, s1)) = swept_cylinder(o, e, p0, d, cyl) else {
                            continue;
                        };
                        let (lo, hi) = bound.range(o);
                        assert!(lo <= s0 && s1 <= hi, "{a} {d} {e} {o}: {lo} {hi} {s0} {s1}");
                        // Along the row from u = −14.7: the same bounds but for rounding.
                        let (axis, o0) = if e == DVec3::X {
                            (1, DVec3::new(-40.0, -14.7, v))
                        } else if e == DVec3::Y {
                            (2, DVec3::new(v, -40.0, -14.7))
                        } else {
                            (0, DVec3::new(-14.7, v, -40.0))
                        };
                        let row = bound.along(o0, axis);
                        let (rlo, rhi) = (row.lower(u + 14.7), row.upper(u + 14.7));
                        assert!(rlo <= s0 && s1 <= rhi, "{a} {d} {e} {o}: {rlo} {rhi}");
                        assert!((rlo - lo).abs() < 1e-9 && (rhi - hi).abs() < 1e-9, "{o}");
                        worst = worst.max((s0 - lo).max(hi - s1) * e.dot(a).abs().max(0.1));
                        hits += 1;
                    }
                }
            }
        }
        // Outer, and finite: within ρ·(1/cos 22.5° − 1) = 0.25 mm of the ends across the
        // planes' normals, more along lines that graze the side (2.5 mm here).
        assert!(hits > 5000, "{hits}");
        assert!(worst < 5.0, "{worst}");
    }

    /// The planes in lanes give the same greatest / least value as one plane at a time
    /// (`c − m·o` with `DVec3::dot`, folded by `f64::max` / `f64::min`), to the bit.
    #[test]
    fn bound_lanes_are_the_planes_one_at_a_time() {
        let scalar = |p: &Planes, o: DVec3, upper: bool| {
            let mut out = if upper {
                f64::INFINITY
            } else {
                f64::NEG_INFINITY
            };
            for k in 0..p.count {
                let (g, l) = (k / 4, k % 4);
                let m = DVec3::new(p.mx[g][l], p.my[g][l], p.mz[g][l]);
                let v = p.c[g][l] - m.dot(o);
                out = if upper { out.min(v) } else { out.max(v) };
            }
            out
        };
        let cyl = Cyl {
            a: DVec3::new(0.3, -0.2, 0.9).normalize(),
            rho: 3.0,
            z0: 3.0,
            z1: 18.0,
        };
        let mut planes = 0;
        for e in [DVec3::X, DVec3::Y, DVec3::Z] {
            for ball in [None, Some(3.0)] {
                let b = SweepBound::new(
                    e,
                    DVec3::new(0.4, -0.3, 1.0),
                    DVec3::new(0.1, 0.02, -0.01),
                    cyl,
                    ball,
                );
                planes += b.lower.count + b.upper.count;
                for k in 0..400 {
                    let o = DVec3::new(
                        f64::from(k % 20) * 0.37 - 3.5,
                        f64::from(k / 20) * 0.41 - 4.0,
                        f64::from(k % 7) - 20.0,
                    );
                    assert_eq!(
                        b.lower.max(o).to_bits(),
                        scalar(&b.lower, o, false).to_bits()
                    );
                    assert_eq!(
                        b.upper.min(o).to_bits(),
                        scalar(&b.upper, o, true).to_bits()
                    );
                }
            }
        }
        assert!(planes > 36, "{planes}");
    }

    #[test]
    fn prepared_ball_is_capsule_entry_to_the_bit() {
        use crate::simulation::exact::capsule_entry;
        let r = 3.0;
        for (pa, pb) in [
            (DVec3::new(0.0, 0.0, 3.0), DVec3::new(0.3, -0.1, 3.05)),
            (DVec3::new(1.0, 2.0, 0.0), DVec3::new(1.0, 2.0, 0.0)),
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.0, 0.0, 2.0)),
        ] {
            for e in [DVec3::X, DVec3::Y, DVec3::Z] {
                let b = SweptBall::new(e, pa, pb, r);
                for k in 0..400 {
                    let (u, v) = (
                        f64::from(k % 20) * 0.37 - 3.5,
                        f64::from(k / 20) * 0.37 - 3.5,
                    );
                    let o = DVec3::new(u, v, -20.0);
                    let o = if e == DVec3::X {
                        DVec3::new(-20.0, u, v)
                    } else if e == DVec3::Y {
                        DVec3::new(v, -20.0, u)
                    } else {
                        o
                    };
                    let (entry, exit) = b.entry_exit(o);
                    let want_in = capsule_entry(o, e, pa, pb, r);
                    let want_out = capsule_entry(o, -e, pa, pb, r).map(|s| -s);
                    assert_eq!(
                        entry.map(f64::to_bits),
                        want_in.map(f64::to_bits),
                        "{o} {e}"
                    );
                    assert_eq!(
                        exit.map(f64::to_bits),
                        want_out.map(f64::to_bits),
                        "{o} {e}"
                    );
                }
            }
        }
    }
}
