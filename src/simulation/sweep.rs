//! The interval of one ray inside the volume swept by a tool body along a straight step with a
//! fixed axis.
//!
//! Every body (the cutting end up to the flute length, the shank, a holder section) is convex
//! and rotationally symmetric, so its sweep along a segment is convex and meets a ray in one
//! interval. Two ways to find it:
//! - vertical tool, vertical ray (3-axis Z dexels): closed forms on the tool's height profile
//!   h(ρ). With the tip at c(t) = p₀ + t·(p₁ − p₀), the ray at horizontal distance ρ(t) from
//!   the axis meets the body from z(t) + h(ρ(t)) up to z(t) + top, for t in the set where
//!   ρ(t) ≤ R (a quadratic inequality). The top is then the larger end value; the bottom is
//!   exact for flat (end value) and ball (ray against the capsule of sphere centres) and, for
//!   bull-nose and cone, the minimum of the convex function z(t) + h(ρ(t)) by golden section
//!   to 10⁻¹² of the step.
//! - any other direction: the body is the convex hull of a few "rings" (a circle of radius r
//!   at height z around the axis, thickened by a ball of radius ρ), so its support function is
//!   cheap; the sweep's support adds the step vector when it points along the query direction,
//!   and parry's GJK ray cast (from both ends of the ray) gives the entry and exit.

use glam::{DVec2, DVec3};

use crate::geometry::minimize::golden_min;
use parry3d_f64::query::Ray;
use parry3d_f64::query::gjk::{VoronoiSimplex, cast_local_ray};
use parry3d_f64::shape::SupportMap;

use super::exact::{Cyl, capsule_entry, capsule_interval, hull, swept_cylinder};
use super::prepared::{RowBound, SweepBound, SweptBall, SweptCyl};
use crate::geometry::Aabb;
use crate::tools::{Cutter, CutterKind};

/// A convex tool body in the tool frame (tip at the origin, axis +z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Body {
    /// The cutting end up to the flute length.
    Cutting {
        /// Cutter radius R.
        radius: f64,
        /// Radius of the flat bottom (R − r for bull-nose, R for flat, 0 for ball and cone).
        flat: f64,
        /// Corner radius r (ball: R; flat: 0).
        corner: f64,
        /// Cone: tan of the half-angle (0 for the others).
        cone_tan: f64,
        /// Top of the body (flute length).
        top: f64,
    },
    /// A cylinder (shank or holder section) from `z0` to `z1`.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Bottom height above the tip.
        z0: f64,
        /// Top height above the tip.
        z1: f64,
    },
}

/// Smallest rounding of a ring in the GJK support map, mm.
const ROUND: f64 = 1e-3;

/// A ring: circle of radius `r` at height `z` around the axis, thickened by a ball `round`.
#[derive(Clone, Copy, Debug)]
struct Ring {
    z: f64,
    r: f64,
    round: f64,
}

impl Body {
    /// The cutting end of a cutter.
    pub(super) fn cutting(c: &Cutter) -> Self {
        let radius = c.radius();
        let (corner, cone_tan) = match c.kind {
            CutterKind::Ball => (radius, 0.0),
            CutterKind::Flat => (0.0, 0.0),
            CutterKind::BullNose { corner_radius } => (corner_radius, 0.0),
            CutterKind::Cone { half_angle } => (0.0, half_angle.tan()),
        };
        Self::Cutting {
            radius,
            flat: c.flat_radius(),
            corner,
            cone_tan,
            top: c.flute_length,
        }
    }

    fn rings(&self) -> ([Ring; 3], usize) {
        let zero = Ring {
            z: 0.0,
            r: 0.0,
            round: 0.0,
        };
        match *self {
            Self::Cylinder { radius, z0, z1 } => (
                [
                    Ring {
                        z: z0,
                        r: radius,
                        round: 0.0,
                    },
                    Ring {
                        z: z1,
                        r: radius,
                        round: 0.0,
                    },
                    zero,
                ],
                2,
            ),
            Self::Cutting {
                radius,
                flat,
                corner,
                cone_tan,
                top,
            } => {
                let top_ring = Ring {
                    z: top,
                    r: radius,
                    round: 0.0,
                };
                if cone_tan > 0.0 {
                    let ph = radius / cone_tan;
                    (
                        [
                            zero,
                            Ring {
                                z: ph.min(top),
                                r: radius,
                                round: 0.0,
                            },
                            top_ring,
                        ],
                        3,
                    )
                } else {
                    (
                        [
                            Ring {
                                z: corner,
                                r: flat,
                                round: corner,
                            },
                            top_ring,
                            zero,
                        ],
                        2,
                    )
                }
            }
        }
    }

    /// Largest radius.
    pub(super) fn radius(&self) -> f64 {
        match *self {
            Self::Cutting { radius, .. } | Self::Cylinder { radius, .. } => radius,
        }
    }

    /// Support point (tool frame rotated to world: axis `a`, tip at the origin).
    fn support(&self, a: DVec3, dir: DVec3) -> DVec3 {
        let (rings, n) = self.rings();
        let da = dir.dot(a);
        let perp = (dir - a * da).try_normalize().unwrap_or(DVec3::ZERO);
        let unit = dir.try_normalize().unwrap_or(DVec3::ZERO);
        let mut best = DVec3::ZERO;
        let mut best_v = f64::NEG_INFINITY;
        let used = rings.get(..n).unwrap_or(&[]);
        let zmid = 0.5
            * (used.iter().map(|r| r.z).fold(f64::INFINITY, f64::min)
                + used.iter().map(|r| r.z).fold(f64::NEG_INFINITY, f64::max));
        for ring in used {
            // A ring without rounding gets a tiny one (shrunk and moved inward by the same
            // amount), so the support point moves continuously with the direction and GJK
            // does not stall on flat faces; the shape changes by at most ROUND·(1 − 1/√2) at
            // sharp edges.
            let (r, round, z) = if ring.round < ROUND {
                let inward = if ring.z > zmid { -1.0 } else { 1.0 };
                (
                    ring.r - ROUND + ring.round,
                    ROUND,
                    ring.z + inward * (ROUND - ring.round),
                )
            } else {
                (ring.r, ring.round, ring.z)
            };
            let p = a * z + perp * r.max(0.0) + unit * round;
            let v = p.dot(dir);
            if v > best_v {
                best_v = v;
                best = p;
            }
        }
        best
    }

    /// Bounding box of the body at tip `p` with axis `a`.
    fn bbox_at(&self, p: DVec3, a: DVec3, out: &mut Aabb) {
        let (rings, n) = self.rings();
        for ring in rings.iter().take(n) {
            let c = p + a * ring.z;
            let ext = DVec3::new(
                (1.0 - a.x * a.x).max(0.0).sqrt(),
                (1.0 - a.y * a.y).max(0.0).sqrt(),
                (1.0 - a.z * a.z).max(0.0).sqrt(),
            ) * ring.r
                + DVec3::splat(ring.round);
            out.add(c - ext);
            out.add(c + ext);
        }
    }

    /// Height of the lower surface at distance `rho` ≤ R from the axis.
    fn height(&self, rho: f64) -> f64 {
        match *self {
            Self::Cylinder { z0, .. } => z0,
            Self::Cutting {
                flat,
                corner,
                cone_tan,
                ..
            } => {
                if cone_tan > 0.0 {
                    rho / cone_tan
                } else if rho <= flat {
                    0.0
                } else {
                    let q = (rho - flat).min(corner);
                    corner - (corner * corner - q * q).max(0.0).sqrt()
                }
            }
        }
    }

    /// Heights `[h0, h1]` of an axis segment whose points within [`Body::radius`] cover the
    /// body (a ball's sphere centre to its top; the tip or a cylinder's bottom otherwise).
    pub(super) fn axis_span(&self) -> (f64, f64) {
        match *self {
            Self::Cutting {
                radius,
                flat,
                corner,
                cone_tan,
                top,
            } if flat == 0.0 && cone_tan == 0.0 && corner == radius => (radius.min(top), top),
            Self::Cutting { top, .. } => (0.0, top),
            Self::Cylinder { z0, z1, .. } => (z0, z1),
        }
    }

    pub(super) fn top(&self) -> f64 {
        match *self {
            Self::Cutting { top, .. } => top,
            Self::Cylinder { z1, .. } => z1,
        }
    }

    /// Lowest height of the body above the tip.
    pub(super) fn bottom(&self) -> f64 {
        match *self {
            Self::Cutting { .. } => 0.0,
            Self::Cylinder { z0, .. } => z0,
        }
    }

    /// The body with its top lowered to `top` (and its bottom raised to `bottom` for a
    /// cylinder); `None` when nothing is left.
    pub(super) fn clipped(&self, bottom: f64, top: f64) -> Option<Self> {
        match *self {
            Self::Cutting {
                radius,
                flat,
                corner,
                cone_tan,
                top: t,
            } => {
                let top = t.min(top);
                (top > 0.0).then_some(Self::Cutting {
                    radius,
                    flat,
                    corner,
                    cone_tan,
                    top,
                })
            }
            Self::Cylinder { radius, z0, z1 } => {
                let (z0, z1) = (z0.max(bottom), z1.min(top));
                (z1 > z0).then_some(Self::Cylinder { radius, z0, z1 })
            }
        }
    }

    /// Whether [`Body::exact_interval`] has a closed form for this body (cylinders, flat and
    /// ball end mills).
    pub(super) fn has_closed_form(&self) -> bool {
        match *self {
            Self::Cylinder { .. } => true,
            Self::Cutting {
                radius,
                flat,
                corner,
                cone_tan,
                ..
            } => cone_tan == 0.0 && (corner == 0.0 || (flat == 0.0 && corner == radius)),
        }
    }

    /// The cylinder of a body with a closed form: the whole body (cylinder, flat end mill)
    /// or a ball end mill's shaft above the sphere centre; `None` for a ball without one.
    fn cylinder_part(&self, axis: DVec3) -> Option<Cyl> {
        let (rho, z0, z1) = match *self {
            Self::Cylinder { radius, z0, z1 } => (radius, z0, z1),
            Self::Cutting {
                radius,
                corner,
                top,
                ..
            } => {
                if corner == 0.0 {
                    (radius, 0.0, top)
                } else if top > radius {
                    (radius, radius, top)
                } else {
                    return None;
                }
            }
        };
        Some(Cyl {
            a: axis,
            rho,
            z0,
            z1,
        })
    }

    /// The cylinder part's sweep along `step` prepared for the lines along `e` (see
    /// [`Body::exact_interval`]); `None` without a cylinder part or when degenerate.
    pub(super) fn prepared_cylinder(&self, step: &SweepStep, e: DVec3) -> Option<SweptCyl> {
        let cyl = self.cylinder_part(step.axis)?;
        SweptCyl::new(e, step.p0, step.p1 - step.p0, cyl)
    }

    /// The interval (offsets `s` along the line `o + s·e`, unit `e`) inside the body swept
    /// along `step`, in closed form; only for bodies with [`Body::has_closed_form`].
    /// With `prepared`, the cylinder part's sweep from [`Body::prepared_cylinder`] for the
    /// same step and direction.
    pub(super) fn exact_interval(
        &self,
        step: &SweepStep,
        o: DVec3,
        e: DVec3,
        prepared: Option<&SweptCyl>,
    ) -> Option<(f64, f64)> {
        let d = step.p1 - step.p0;
        let cylinder = |cyl: Cyl| match prepared {
            Some(sw) => sw.interval(o),
            None => swept_cylinder(o, e, step.p0, d, cyl),
        };
        match *self {
            Self::Cylinder { .. } => cylinder(self.cylinder_part(step.axis)?),
            Self::Cutting { radius, corner, .. } => {
                let shaft = self.cylinder_part(step.axis).and_then(cylinder);
                if corner == 0.0 {
                    return shaft;
                }
                let c0 = step.p0 + step.axis * radius;
                hull(capsule_interval(o, e, c0, c0 + d, radius), shaft)
            }
        }
    }
}

impl Body {
    /// Whether the line `o + s·e` (unit e) enters a ball end mill's sweep at or above the
    /// offset `top` (so the sweep takes nothing from material below `top`), decided from the
    /// ball's capsule alone: the shaft above the sphere centre lies on the far side of the
    /// plane through the centre normal to the axis, so along a line that climbs the axis
    /// (e·a > 0) it cannot be entered before that plane. `false` when undecided (then
    /// [`Body::exact_interval`] decides); when `true`, the entry of
    /// [`Body::exact_interval`] is the same capsule entry, so skipping the line changes
    /// nothing.
    pub(super) fn entry_above(&self, step: &SweepStep, o: DVec3, e: DVec3, top: f32) -> bool {
        let Self::Cutting {
            radius,
            flat,
            corner,
            cone_tan,
            ..
        } = *self
        else {
            return false;
        };
        if !(flat == 0.0 && cone_tan == 0.0 && corner == radius) {
            return false;
        }
        let a = step.axis;
        let d = step.p1 - step.p0;
        let c0 = step.p0 + a * radius;
        self.entry_above_given(step, o, e, top, capsule_entry(o, e, c0, c0 + d, radius))
    }

    /// [`Body::entry_above`] given the line's entry into the ball's capsule (a ball end
    /// mill's; `false` for other bodies).
    fn entry_above_given(
        &self,
        step: &SweepStep,
        o: DVec3,
        e: DVec3,
        top: f32,
        entry: Option<f64>,
    ) -> bool {
        let Self::Cutting {
            radius,
            flat,
            corner,
            cone_tan,
            top: body_top,
        } = *self
        else {
            return false;
        };
        if !(flat == 0.0 && cone_tan == 0.0 && corner == radius) {
            return false;
        }
        let a = step.axis;
        let ea = e.dot(a);
        let d = step.p1 - step.p0;
        let c0 = step.p0 + a * radius;
        let plane = |c: DVec3| -(o - c).dot(a) / ea;
        let Some(entry) = entry else {
            // The line misses the ball: the sweep is the shaft's, which starts at or above
            // the plane through the sphere centre normal to the axis, to the shaft solve's
            // axial tolerance 1e-9·(1 + |offsets|) (twice it here, over e·a, and 1 nm).
            if !(body_top > radius && ea > 1e-3) {
                return false;
            }
            let (y, far) = (o - step.p0, 1.0 + body_top);
            let margin = 1e-6 + 2e-9 * (far + y.x.abs() + y.y.abs() + y.z.abs()) / ea;
            return f64::from(top) + margin <= plane(c0).min(plane(c0 + d));
        };
        #[allow(clippy::cast_possible_truncation)]
        if !(entry as f32 >= top) {
            return false;
        }
        if body_top <= radius {
            return true;
        }
        if !(ea > 1e-3) {
            return false;
        }
        // (o + s·e − c(t))·a ≥ 0 on the shaft, for some t in [0, 1]; 1 nm to spare for the
        // tolerance of the shaft's solve.
        entry + 1e-6 <= plane(c0).min(plane(c0 + d))
    }
}

/// A body's sweep along one step prepared for the lines of one direction: the cylinder part
/// and a ball end mill's capsule.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Prepared {
    cylinder: Option<SweptCyl>,
    ball: Option<SweptBall>,
    /// Bounds of the cylinder part's sweep along the lines (no square root).
    bound: Option<SweepBound>,
    /// Bounds of a ball end mill's whole sweep (ball and shaft).
    body_bound: Option<SweepBound>,
}

impl Prepared {
    /// Outer bounds `(lo, hi)` of the offsets where the line `o + s·e` can be inside the
    /// cylinder part's sweep (for a cylinder body: the whole body's).
    pub(super) fn cylinder_range(&self, o: DVec3) -> Option<(f64, f64)> {
        self.bound.as_ref().map(|b| b.range(o))
    }

    /// The bounds for the row of lines `o₀ + x·û` along the grid axis `u` (see
    /// [`RowBound`]), written into `out`.
    pub(super) fn along_into(&self, o0: DVec3, u: usize, out: &mut PreparedRow) {
        out.has_bound = self.bound.as_ref().is_some_and(|b| {
            b.along_into(o0, u, &mut out.bound);
            true
        });
        out.has_body_bound = self.body_bound.as_ref().is_some_and(|b| {
            b.along_into(o0, u, &mut out.body_bound);
            true
        });
    }

    /// Whether it has bounds (then [`Prepared::along`] spares work).
    pub(super) fn has_bounds(&self) -> bool {
        self.bound.is_some() || self.body_bound.is_some()
    }

    /// [`Prepared::cylinder_range`] of the line at `o`, from the row's bounds where given
    /// (`x` along the row).
    pub(super) fn cylinder_at(
        &self,
        o: DVec3,
        row: Option<(&PreparedRow, f64)>,
    ) -> Option<(f64, f64)> {
        match row {
            Some((r, x)) => r.bound().map(|b| (b.lower(x), b.upper(x))),
            None => self.cylinder_range(o),
        }
    }
}

/// The sweep bounds of a [`Prepared`] for the lines of one row (constants per row, one
/// product per plane and line).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PreparedRow {
    bound: RowBound,
    body_bound: RowBound,
    has_bound: bool,
    has_body_bound: bool,
}

impl PreparedRow {
    fn bound(&self) -> Option<&RowBound> {
        self.has_bound.then_some(&self.bound)
    }

    fn body_bound(&self) -> Option<&RowBound> {
        self.has_body_bound.then_some(&self.body_bound)
    }
}

impl Body {
    /// The body's sweep along `step` prepared for lines along `e` (bodies with
    /// [`Body::has_closed_form`]; empty for the others).
    pub(super) fn prepare(&self, step: &SweepStep, e: DVec3) -> Prepared {
        if !self.has_closed_form() {
            return Prepared::default();
        }
        let ball = match *self {
            Self::Cutting { radius, corner, .. } if corner > 0.0 => {
                let c0 = step.p0 + step.axis * radius;
                Some(SweptBall::new(e, c0, c0 + (step.p1 - step.p0), radius))
            }
            _ => None,
        };
        let (d, cyl) = (step.p1 - step.p0, self.cylinder_part(step.axis));
        let bound = cyl.map(|c| SweepBound::new(e, step.p0, d, c, None));
        let body_bound = match (cyl, *self) {
            (Some(c), Self::Cutting { radius, .. }) if ball.is_some() => {
                Some(SweepBound::new(e, step.p0, d, c, Some(radius)))
            }
            _ => None,
        };
        Prepared {
            cylinder: self.prepared_cylinder(step, e),
            ball,
            bound,
            body_bound,
        }
    }

    /// The interval of the line `o + s·e` inside the sweep ([`Body::exact_interval`]), or
    /// `None` also where it cannot change the line's `material` (non-empty, sorted): where
    /// [`Body::entry_above`] passes the line over, or the material lies outside the sweep's
    /// bounds. Where the interval leaves the sweep above all the material, its end may be
    /// any offset at or above the material's top (the ball's exit): removal and collision
    /// depth are the same.
    pub(super) fn interval_prepared(
        &self,
        step: &SweepStep,
        (o, e): (DVec3, DVec3),
        material: &[[f32; 2]],
        (prep, row): (&Prepared, Option<(&PreparedRow, f64)>),
    ) -> Option<(f64, f64)> {
        let top = material.last().map_or(f32::NEG_INFINITY, |i| i[1]);
        let Some(ball) = &prep.ball else {
            if self.entry_above(step, o, e, top) {
                return None;
            }
            return self.exact_interval(step, o, e, prep.cylinder.as_ref());
        };
        // Lines whose material lies outside the bounds of the sweep keep it all (the rounded
        // ends of the interval stay on the same side of the material's f32 ends).
        let outside = match row {
            Some((r, x)) => r.body_bound().is_some_and(|b| {
                let lo = b.lower(x);
                f64::from(top) <= lo || !material_within(material, (lo, b.upper(x)))
            }),
            None => prep.body_bound.as_ref().is_some_and(|b| {
                let lo = b.lower(o);
                f64::from(top) <= lo || !material_within(material, (lo, b.upper(o)))
            }),
        };
        if outside {
            return None;
        }
        let (entry, exit) = ball.entry_exit(o);
        if self.entry_above_given(step, o, e, top, entry) {
            return None;
        }
        let capsule = match (entry, exit) {
            (Some(a), Some(b)) if a <= b => Some((a, b)),
            _ => None,
        };
        // The same with the capsule's exact ends and the shaft's bounds.
        if let Some((lo, hi)) = prep.cylinder_at(o, row) {
            // The capsule enters below any point of the shaft and leaves above all the
            // material: the interval's start is the capsule's, and any end at or above the
            // material's top takes the same (the shaft's exact solve is spared).
            #[allow(clippy::cast_possible_truncation)]
            if let Some((a, b)) = capsule
                && a <= lo
                && b as f32 >= top
            {
                return capsule;
            }
            let (lo, hi) = capsule.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi)));
            if !material_within(material, (lo, hi)) {
                return None;
            }
        }
        let d = step.p1 - step.p0;
        let shaft = self
            .cylinder_part(step.axis)
            .and_then(|cyl| match &prep.cylinder {
                Some(sw) => sw.interval(o),
                None => swept_cylinder(o, e, step.p0, d, cyl),
            });
        hull(capsule, shaft)
    }
}

/// Whether some of the material (intervals of a ray) lies inside the offsets `(lo, hi)`.
fn material_within(material: &[[f32; 2]], (lo, hi): (f64, f64)) -> bool {
    material
        .iter()
        .any(|[a, b]| f64::from(*a) < hi && f64::from(*b) > lo)
}

/// One straight step of the tool: tip from `p0` to `p1`, fixed unit axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SweepStep {
    pub p0: DVec3,
    pub p1: DVec3,
    pub axis: DVec3,
}

impl SweepStep {
    /// Whether the axis is +Z (to 1e-12), so the closed forms apply to Z rays.
    pub(super) fn is_vertical(&self) -> bool {
        (self.axis - DVec3::Z).length_squared() < 1e-24
    }

    /// Bounding box of `body` swept along the step.
    pub(super) fn bbox(&self, body: &Body) -> Aabb {
        let mut b = Aabb {
            min: self.p0,
            max: self.p0,
        };
        body.bbox_at(self.p0, self.axis, &mut b);
        body.bbox_at(self.p1, self.axis, &mut b);
        b
    }
}

/// The t-interval of [0, 1] where |w − t·d| ≤ r.
fn disc_interval(w: DVec2, d: DVec2, r: f64) -> Option<(f64, f64)> {
    let a = d.length_squared();
    let c = w.length_squared() - r * r;
    if a < 1e-24 {
        return (c <= 0.0).then_some((0.0, 1.0));
    }
    let b = w.dot(d);
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    let (t0, t1) = (((b - sq) / a).max(0.0), ((b + sq) / a).min(1.0));
    (t0 <= t1).then_some((t0, t1))
}

/// The z-interval of the vertical line through `q` inside `body` (axis +Z) swept from `p0` to
/// `p1`.
pub(super) fn vertical_interval(body: &Body, p0: DVec3, p1: DVec3, q: DVec2) -> Option<(f64, f64)> {
    let d = (p1 - p0).truncate();
    let w = q - p0.truncate();
    let dz = p1.z - p0.z;
    let r = body.radius();
    let (ta, tb) = disc_interval(w, d, r)?;
    let z = |t: f64| p0.z + t * dz;
    let (za, zb) = (z(ta), z(tb));
    let hi = za.max(zb) + body.top();
    let lo = match *body {
        Body::Cylinder { z0, .. } => za.min(zb) + z0,
        Body::Cutting {
            flat,
            corner,
            cone_tan,
            radius,
            ..
        } => {
            if cone_tan == 0.0 && corner == 0.0 {
                za.min(zb)
            } else if cone_tan == 0.0 && flat == 0.0 {
                // Ball: the lowest point of the line in the capsule of sphere centres.
                let lift = DVec3::new(0.0, 0.0, radius);
                let o = DVec3::new(q.x, q.y, za.min(zb) - 2.0 * radius - 1.0);
                capsule_entry(o, DVec3::Z, p0 + lift, p1 + lift, radius)
                    .map_or(za.min(zb) + radius, |s| o.z + s)
            } else {
                let f = |t: f64| z(t) + body.height((w - d * t).length().min(radius));
                if dz.abs() < 1e-15 {
                    let a = d.length_squared();
                    let t = if a > 0.0 {
                        (w.dot(d) / a).clamp(ta, tb)
                    } else {
                        ta
                    };
                    f(t)
                } else {
                    golden_min(ta, tb, 60, f)
                }
            }
        }
    };
    Some((lo, hi))
}

/// A body swept along a step, as a support map for GJK (origin = the step's start tip).
struct Swept<'a> {
    body: &'a Body,
    axis: DVec3,
    d: DVec3,
}

impl SupportMap for Swept<'_> {
    fn local_support_point(&self, dir: DVec3) -> DVec3 {
        let p = self.body.support(self.axis, dir);
        if dir.dot(self.d) > 0.0 { p + self.d } else { p }
    }
}

/// The interval (offsets `s` along the line `origin + s·e`, unit `e`) inside `body` swept
/// along `step`, searched for within `[s_lo, s_hi]` (both ends outside the sweep).
pub(super) fn general_interval(
    body: &Body,
    step: &SweepStep,
    origin: DVec3,
    e: DVec3,
    s_lo: f64,
    s_hi: f64,
) -> Option<(f64, f64)> {
    let shape = Swept {
        body,
        axis: step.axis,
        d: step.p1 - step.p0,
    };
    let span = s_hi - s_lo;
    let mut simplex = VoronoiSimplex::new();
    let start = origin + e * s_lo - step.p0;
    let (t_in, _) = cast_local_ray(&shape, &mut simplex, &Ray::new(start, e), span)?;
    let end = origin + e * s_hi - step.p0;
    let (t_out, _) = cast_local_ray(&shape, &mut simplex, &Ray::new(end, -e), span)?;
    let (a, b) = (s_lo + t_in, s_hi - t_out);
    (a <= b).then_some((a, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cutters() -> Vec<Cutter> {
        [
            Cutter::new(CutterKind::Ball, 6.0),
            Cutter::new(CutterKind::Flat, 6.0),
            Cutter::new(CutterKind::BullNose { corner_radius: 1.0 }, 6.0),
            Cutter::new(CutterKind::Cone { half_angle: 0.6 }, 6.0),
        ]
        .into_iter()
        .filter_map(Result::ok)
        .collect()
    }

    /// Brute force: the lowest and highest z of the vertical line over 20001 tool positions.
    fn brute(c: &Cutter, p0: DVec3, p1: DVec3, q: DVec2) -> Option<(f64, f64)> {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for k in 0..=20_000 {
            let t = f64::from(k) / 20_000.0;
            let c0 = p0.lerp(p1, t);
            let rho = (q - c0.truncate()).length();
            if let Some(h) = c.height_at_radius(rho) {
                lo = lo.min(c0.z + h);
                hi = hi.max(c0.z + c.flute_length);
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    #[test]
    fn entry_above_never_skips_a_cut() {
        let ball =
            Body::cutting(&Cutter::new(CutterKind::Ball, 6.0).unwrap_or_else(|e| panic!("{e}")));
        let axes = [
            DVec3::Z,
            DVec3::new(0.0, 0.4, 1.0).normalize(),
            DVec3::new(-0.6, 0.3, 0.8).normalize(),
        ];
        let moves = [
            DVec3::new(0.3, 0.0, 0.0),
            DVec3::new(0.1, 0.2, -0.05),
            DVec3::ZERO,
        ];
        let (mut skipped, mut total) = (0, 0);
        for axis in axes {
            for d in moves {
                let step = SweepStep {
                    p0: DVec3::ZERO,
                    p1: d,
                    axis,
                };
                for e in [DVec3::X, DVec3::Y, DVec3::Z] {
                    for k in 0..400 {
                        let (u, v) = (f64::from(k % 20) * 0.4 - 4.0, f64::from(k / 20) * 0.4 - 4.0);
                        let o = DVec3::new(u, v, -40.0);
                        let o = if e == DVec3::X {
                            DVec3::new(-40.0, u, v)
                        } else if e == DVec3::Y {
                            DVec3::new(u, -40.0, v)
                        } else {
                            o
                        };
                        let exact = ball.exact_interval(&step, o, e, None);
                        for m in 0..40 {
                            #[allow(clippy::cast_possible_truncation)]
                            let top = (30.0 + 0.25 * f64::from(m)) as f32;
                            total += 1;
                            if ball.entry_above(&step, o, e, top) {
                                skipped += 1;
                                if let Some((lo, _)) = exact {
                                    #[allow(clippy::cast_possible_truncation)]
                                    let lo = lo as f32;
                                    assert!(lo >= top, "{axis} {d} {o} {e}: {lo} < {top}");
                                }
                            }
                        }
                    }
                }
            }
        }
        assert!(
            skipped > total / 20,
            "the bound decides too little: {skipped} of {total}"
        );
    }

    #[test]
    fn vertical_and_general_match_brute_force() {
        let moves = [
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(10.0, 0.0, 0.0)),
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(7.0, 3.0, -2.0)),
            (DVec3::new(1.0, 1.0, 2.0), DVec3::new(1.0, 1.0, -1.0)),
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(2.0, -1.0, 4.0)),
        ];
        let qs = [
            DVec2::new(2.0, 1.0),
            DVec2::new(5.0, -2.9),
            DVec2::new(1.2, 0.4),
            DVec2::new(-1.5, 0.5),
            DVec2::new(3.0, 2.5),
        ];
        for c in cutters() {
            let body = Body::cutting(&c);
            for (p0, p1) in moves {
                let step = SweepStep {
                    p0,
                    p1,
                    axis: DVec3::Z,
                };
                for q in qs {
                    let fast = vertical_interval(&body, p0, p1, q);
                    let want = brute(&c, p0, p1, q);
                    let o = DVec3::new(q.x, q.y, 0.0);
                    // GJK runs on rings rounded by ROUND: sharp edges move by ≤ 3e-4 mm along
                    // their normal, more along a ray that meets them at a grazing angle.
                    let general = general_interval(&body, &step, o, DVec3::Z, -50.0, 50.0);
                    if body.has_closed_form() {
                        let exact = body.exact_interval(&step, o, DVec3::Z, None);
                        match (exact, fast) {
                            (Some(x), Some(f)) => assert!(
                                (x.0 - f.0).abs() < 1e-6 && (x.1 - f.1).abs() < 1e-6,
                                "{c:?} {p0} {p1} {q}: exact {x:?} fast {f:?}"
                            ),
                            (None, None) => {}
                            other => panic!("{c:?} {p0} {p1} {q}: {other:?}"),
                        }
                    }
                    match (fast, want, general) {
                        (Some(f), Some(w), Some(g)) => {
                            assert!((f.0 - w.0).abs() < 2e-3, "{c:?} {p0} {p1} {q} {f:?} {w:?}");
                            assert!((f.1 - w.1).abs() < 2e-3, "{f:?} {w:?}");
                            assert!((g.0 - f.0).abs() < 2e-3, "{c:?} {q} gjk {g:?} fast {f:?}");
                            // The exit through the top rim (flute length) may be met at a grazing angle.
                            assert!((g.1 - f.1).abs() < 2e-3, "gjk {g:?} fast {f:?}");
                        }
                        (None, None, None) => {}
                        other => panic!("{c:?} {p0} {p1} {q}: {other:?}"),
                    }
                }
            }
        }
    }
}
