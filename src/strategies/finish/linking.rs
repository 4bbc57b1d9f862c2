//! Linking passes into one tool path: approach from the clearance plane (rapid down to a safe
//! height above the start, then a plunge at feed), stay down between neighbouring passes when
//! the link is short (the link is itself stepped over the surface, so it cannot gouge), else
//! retract along the axis to the clearance plane, rapid across, and plunge; depart to the
//! clearance plane at the end. Rapids are marked `rapid`.
//!
//! Lead-in/lead-out arcs (`FinishOptions::lead_arc_mm` > 0): a pass entered from above is
//! reached by a quarter circle of the tool tip in the plane of the first cut direction `d` and
//! the tool axis, tangent to `d` where it meets the pass (centre `T + ρ u`, `u` the axis's part
//! ⟂ `d`): it starts straight down (along −u) at `T − ρ d + ρ u` and ends moving along `d`; the
//! pass is left by the mirrored arc after its last pose. The axis stays that of the pass's end
//! pose. Lead-in arcs are fed moves into the material (`plunge`), lead-out arcs fed moves clear
//! of it (`link`). Every arc placement and the moves between them are checked against the
//! exact surface ([`crate::checks::check_pose`], [`crate::checks::check_move`]); a gouging arc
//! is halved (up to four times) and otherwise left out (straight plunge / retract).

use glam::{DQuat, DVec3};

use super::axis::{AxisMode, axis_angle};
use super::setup::Setup;
use crate::toolpath::{ContactKind, MoveKind, Pose};
use crate::tools::effective::contact_to_tip;

/// Height above the highest tip of the path and the face used when no clearance is given, mm.
pub const DEFAULT_CLEARANCE_ABOVE: f64 = 5.0;

/// Plunges start this far above the pass start, mm (rapid down to here, then feed).
pub const APPROACH_HEIGHT: f64 = 2.0;

/// 5 mm above the highest tip of the runs and the highest face sample.
#[must_use]
pub fn default_clearance(setup: &Setup<'_>, runs: &[Vec<Pose>]) -> f64 {
    let mut top = f64::NEG_INFINITY;
    for r in runs {
        for p in r {
            top = top.max(p.tip.z + setup.cutter.radius() * 2.0);
        }
    }
    for i in 0..=16 {
        for j in 0..=16 {
            let uv = setup.patch.at(f64::from(i) / 16.0, f64::from(j) / 16.0);
            top = top.max(setup.patch.surface.point(uv.x, uv.y).z);
        }
    }
    if top.is_finite() {
        top + DEFAULT_CLEARANCE_ABOVE
    } else {
        DEFAULT_CLEARANCE_ABOVE
    }
}

/// An axis with at most this upward component is level: the tool reaches its pose out along
/// the axis by [`APPROACH_HEIGHT`] from the point straight above (a vertical plunge would drag
/// the ball along a wall).
pub(crate) const LEVEL_AXIS_Z: f64 = 0.1;

/// The point above `p` on its axis at height `z` (straight up when the axis is nearly level).
pub(crate) fn above(p: &Pose, z: f64) -> DVec3 {
    if p.axis.z > LEVEL_AXIS_Z {
        p.tip + p.axis * ((z - p.tip.z) / p.axis.z).max(0.0)
    } else {
        DVec3::new(p.tip.x, p.tip.y, z.max(p.tip.z))
    }
}

/// Join the runs (cut poses per pass) with approach, links, retracts and departure.
/// `one_way`: never stay down between passes (one-way zig-zag returns at clearance).
/// `clear`: whether a stay-down link (its moves from the end of one run to the start of the
/// next, both included) is clear of the rest of the part; a link that is not retracts instead.
/// `route`: for a run's first or last pose, the length along the tool axis of a sideways
/// approach or retract ([`Route`]), `None` for the straight one.
#[must_use]
pub fn link(
    setup: &Setup<'_>,
    runs: &[Vec<Pose>],
    clearance: f64,
    one_way: bool,
    clear: &dyn Fn(&[Pose]) -> bool,
    route: Route<'_>,
) -> Vec<Pose> {
    let feed = setup.opts.feed;
    let stay_down = 2.5 * setup.cutter.diameter;
    let arcs = Arcs::new(setup);
    let mut out: Vec<Pose> = Vec::new();
    for run in runs.iter().filter(|r| !r.is_empty()) {
        let (Some(first), Some(last_prev)) = (run.first(), out.last().copied()) else {
            if !run.is_empty() {
                out.extend(arcs.enter(run, clearance, route));
                out.extend(run.iter().skip(1).copied());
            }
            continue;
        };
        // Stay down only with a ball and when no axis turn beyond the allowed step is needed
        // (turning a tilted flat or bull-nose cutter about its contact can gouge): else retract.
        let turn = axis_angle(last_prev.axis, first.axis);
        let near = last_prev.tip.distance(first.tip) <= stay_down
            && turn <= setup.opts.max_axis_step + 1e-6
            && setup.cutter.kind == crate::tools::CutterKind::Ball;
        let link_run = if near && !one_way {
            surface_link(setup, &last_prev, first).filter(|l| {
                let mut chain = Vec::with_capacity(l.len() + 2);
                chain.push(last_prev);
                chain.extend_from_slice(l);
                chain.push(*first);
                clear(&chain)
            })
        } else {
            None
        };
        match link_run {
            Some(link) => {
                out.extend(link);
                out.extend(run.iter().copied());
            }
            None => {
                out.extend(arcs.leave(&out));
                if let Some(last) = out.last().copied() {
                    out.extend(retract(&last, clearance, feed, route));
                }
                out.extend(arcs.enter(run, clearance, route));
                out.extend(run.iter().skip(1).copied());
            }
        }
    }
    out.extend(arcs.leave(&out));
    if let Some(last) = out.last().copied() {
        out.extend(retract(&last, clearance, feed, route));
    }
    out
}

/// The sideways approach of a pose on a part: `Some(l)` when the tool reaches it from the
/// point `l` mm out along its own axis (reached from the clearance plane straight down), `None`
/// for the straight approach (up the axis, or out along a level axis by [`APPROACH_HEIGHT`]).
pub type Route<'r> = &'r dyn Fn(&Pose) -> Option<f64>;

/// The sideways length of `p`'s approach: `route`'s, else [`APPROACH_HEIGHT`] for a level axis.
fn sideways(p: &Pose, route: Route<'_>) -> Option<f64> {
    route(p).or_else(|| (p.axis.z <= LEVEL_AXIS_Z).then_some(APPROACH_HEIGHT))
}

/// The point `l` mm out along `p`'s axis, and the point above it at the clearance plane.
fn escape_points(p: &Pose, l: f64, clearance: f64) -> (DVec3, DVec3) {
    let out = p.tip + p.axis * l;
    (out, DVec3::new(out.x, out.y, clearance.max(out.z)))
}

/// Rapid retract from `last` to the clearance plane: straight (see [`above`]), or out along
/// the axis first where `route` says so.
fn retract(last: &Pose, clearance: f64, feed: f64, route: Route<'_>) -> Vec<Pose> {
    let rapid = |tip| Pose::new(MoveKind::Rapid, tip, last.axis, feed);
    match sideways(last, route) {
        Some(l) => {
            let (out, up) = escape_points(last, l, clearance);
            vec![rapid(out), rapid(up)]
        }
        None => vec![rapid(above(last, clearance))],
    }
}

/// Rapid to the clearance plane above `first`, rapid down to the approach height, plunge to it
/// (sideways, and for a level axis: rapid to the clearance plane above the point out along the
/// axis, down to it, in along the axis to the approach height, plunge). `arc`: lead-in arc poses ending at `first`
/// (excluded); the plunge then goes to the arc's start and the arc follows.
fn approach(first: &Pose, arc: &[Pose], clearance: f64, feed: f64, route: Route<'_>) -> Vec<Pose> {
    let start = arc.first().unwrap_or(first);
    let rapid = |tip| Pose::new(MoveKind::Rapid, tip, first.axis, feed);
    let mut out = match sideways(start, route) {
        Some(l) => {
            let (away, up) = escape_points(start, l, clearance);
            let mut v = vec![rapid(up), rapid(away)];
            if l > APPROACH_HEIGHT {
                v.push(rapid(start.tip + start.axis * APPROACH_HEIGHT));
            }
            v
        }
        None => {
            let top = above(start, clearance);
            let near = above(start, (start.tip.z + APPROACH_HEIGHT).min(clearance));
            vec![rapid(top), rapid(near)]
        }
    };
    let mut plunge = *first;
    plunge.kind = MoveKind::Plunge;
    out.extend(arc.iter().copied());
    out.push(plunge);
    out
}

/// Lead-in/lead-out arcs of a setup (see the module doc).
struct Arcs<'s, 'a> {
    setup: &'s Setup<'a>,
    patch: Option<crate::checks::FacePatch<'a>>,
}

impl<'s, 'a> Arcs<'s, 'a> {
    fn new(setup: &'s Setup<'a>) -> Self {
        let patch = (setup.opts.lead_arc_mm > 0.0)
            .then(|| super::repair::check_patch(setup))
            .flatten();
        Self { setup, patch }
    }

    /// Approach into the run's first pose (with a lead-in arc when asked and clear).
    fn enter(&self, run: &[Pose], clearance: f64, route: Route<'_>) -> Vec<Pose> {
        let feed = self.setup.opts.feed;
        let Some(first) = run.first() else {
            return Vec::new();
        };
        let arc = match (run.get(1), &self.patch) {
            (Some(second), Some(gp)) => self.clear_arc(gp, first, second.tip - first.tip, true),
            _ => Vec::new(),
        };
        approach(first, &arc, clearance, feed, route)
    }

    /// Lead-out arc after the last pose of `out` when it is a cut (empty otherwise).
    fn leave(&self, out: &[Pose]) -> Vec<Pose> {
        let (Some(gp), [.., before, last]) = (&self.patch, out) else {
            return Vec::new();
        };
        if last.kind != MoveKind::Cut {
            return Vec::new();
        }
        self.clear_arc(gp, last, last.tip - before.tip, false)
    }

    /// The largest arc (the asked radius, halved up to four times) whose placements and moves
    /// clear the surface; empty when none does.
    fn clear_arc(
        &self,
        gp: &crate::checks::FacePatch<'_>,
        end: &Pose,
        dir: DVec3,
        entering: bool,
    ) -> Vec<Pose> {
        let o = super::repair::check_options();
        let cutter = self.setup.cutter;
        let mut radius = self.setup.opts.lead_arc_mm;
        for _ in 0..5 {
            let Some(arc) = lead_arc(end, dir, radius, self.setup.opts.tolerance, entering) else {
                return Vec::new();
            };
            let mut chain: Vec<Pose> = arc.clone();
            if entering {
                chain.push(*end);
            } else {
                chain.insert(0, *end);
            }
            let clear = arc
                .iter()
                .all(|p| crate::checks::check_pose(gp, cutter, p, 0, &o).is_none())
                && chain
                    .windows(2)
                    .all(|w| crate::checks::check_move(gp, cutter, &w[0], &w[1], 0, &o).is_none());
            if clear {
                return arc;
            }
            radius *= 0.5;
        }
        Vec::new()
    }
}

/// A quarter-circle arc of the tool tip of radius `radius` tangent to `dir` at `end`'s tip, in
/// the plane of `dir` and `end`'s axis, on the axis side; sampled so that its chords stay
/// within `tolerance / 2` of the circle (at most 10° apart). Entering: the poses before `end`
/// (kind `plunge`), from the arc's top; leaving: the poses after it (kind `link`). `None` when
/// `dir` is zero or along the axis, or the radius is not positive.
#[must_use]
pub fn lead_arc(
    end: &Pose,
    dir: DVec3,
    radius: f64,
    tolerance: f64,
    entering: bool,
) -> Option<Vec<Pose>> {
    let d = dir.try_normalize()?;
    let u = (end.axis - d * end.axis.dot(d)).try_normalize()?;
    if !(radius > 0.0 && radius.is_finite() && tolerance > 0.0) {
        return None;
    }
    let centre = end.tip + u * radius;
    // Sagitta ρ(1 − cos(Δφ/2)) ≤ ε/2.
    let c = (1.0 - 0.5 * tolerance / radius).clamp(-1.0, 1.0);
    let dphi = (2.0 * c.acos()).min(10f64.to_radians()).max(1e-3);
    let n = ((std::f64::consts::FRAC_PI_2 / dphi).ceil() as usize).clamp(2, 1000);
    let at = |phi: f64, side: f64| centre - (u * phi.cos() + d * (side * phi.sin())) * radius;
    let quarter = std::f64::consts::FRAC_PI_2;
    let poses = if entering {
        (0..n)
            .map(|k| {
                let phi = quarter * (1.0 - k as f64 / n as f64);
                Pose::new(
                    MoveKind::Plunge,
                    at(phi, 1.0),
                    end.axis,
                    end.feed_mm_per_min,
                )
            })
            .collect()
    } else {
        (1..=n)
            .map(|k| {
                let phi = quarter * k as f64 / n as f64;
                Pose::new(MoveKind::Link, at(phi, -1.0), end.axis, end.feed_mm_per_min)
            })
            .collect()
    };
    Some(poses)
}

/// A stay-down link over the surface from the contact of `a` to that of `b` (both must carry
/// a contact point): contacts along the parameter-space segment between them every half
/// millimetre (lifted by ε/2 like the passes), the axis of `a` carried along by the rotation
/// of the normal; then, at `b`'s contact, the axis turned to `b`'s in steps no larger than the
/// allowed axis step, the tool kept touching. Moves are marked `link`. `None` when a contact
/// cannot be inverted onto the face.
fn surface_link(setup: &Setup<'_>, a: &Pose, b: &Pose) -> Option<Vec<Pose>> {
    let (ca, cb) = (a.cc?, b.cc?);
    let dom = setup.patch.domain;
    let pa = setup.patch.surface.closest_point(ca, dom, None);
    let pb = setup.patch.surface.closest_point(cb, dom, Some(pa.uv));
    if pa.distance > 1e-3 || pb.distance > 1e-3 {
        return None;
    }
    let na = setup.patch.frame(pa.uv)?.n;
    let lift = 0.5 * setup.opts.tolerance;
    let dir = (cb - ca).try_normalize().unwrap_or(DVec3::X);
    let place = |uv: glam::DVec2, axis_of: &dyn Fn(DVec3) -> DVec3| -> Option<Pose> {
        let f = setup.patch.frame(uv)?;
        let axis = axis_of(f.n);
        let feed = (dir - f.n * dir.dot(f.n)).try_normalize().unwrap_or(dir);
        let tip = contact_to_tip(setup.cutter, f.p + f.n * lift, f.n, axis, feed)?;
        let pose = Pose::new(MoveKind::Link, tip, axis, setup.opts.feed)
            .with_contact(f.p, a.contact.unwrap_or(ContactKind::Ball));
        Some(pose)
    };
    let steps = ((ca.distance(cb) / 0.5).ceil() as usize).clamp(1, 1000);
    let mut out = Vec::with_capacity(steps + 8);
    let mut last_axis = a.axis;
    for k in 1..=steps {
        let uv = pa.uv.lerp(pb.uv, k as f64 / steps as f64);
        // Normal-relative axes follow the normal; other modes keep their own axis.
        let normal_mode = matches!(setup.opts.axis, AxisMode::Normal { .. });
        let cc = setup.patch.surface.point(uv.x, uv.y);
        let carry = |n: DVec3| {
            if normal_mode {
                DQuat::from_rotation_arc(na, n) * a.axis
            } else {
                setup.opts.axis.axis(cc, n, dir)
            }
        };
        let pose = place(uv, &carry)?;
        last_axis = pose.axis;
        out.push(pose);
    }
    // Turn the axis at b's contact.
    let turn = axis_angle(last_axis, b.axis);
    let k = ((turn / setup.opts.max_axis_step).ceil() as usize).clamp(1, 360);
    let q = DQuat::from_rotation_arc(last_axis, b.axis);
    for j in 1..k {
        let t = j as f64 / k as f64;
        let axis_at = |_: DVec3| (DQuat::IDENTITY.slerp(q, t) * last_axis).normalize();
        let pose = place(pb.uv, &axis_at)?;
        out.push(pose);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::link;
    use crate::geometry::Interval;
    use crate::geometry::frame::Frame;
    use crate::geometry::surface::{Cylinder, ParamRect, SurfaceGeom};
    use crate::strategies::finish::FinishOptions;
    use crate::strategies::finish::face::FacePatch;
    use crate::strategies::finish::setup::Setup;
    use crate::toolpath::{MoveKind, Pose};
    use crate::tools::{Cutter, CutterKind};

    /// A ball of radius 1 running around the inside of a cylinder of radius 10: a 20 mm
    /// lead-in arc is flatter than the ball centre's circle (radius 9) and would cut in behind
    /// the start, 10 mm too; halved twice, 5 mm clears. The arc's ball centres stay within 9 mm
    /// of the cylinder's axis (no penetration), and it meets the pass tangentially.
    #[test]
    fn a_gouging_lead_arc_is_shrunk() {
        let cyl = SurfaceGeom::Cylinder(Cylinder {
            frame: Frame::WORLD,
            radius: 10.0,
        });
        let rect = ParamRect {
            u: Interval::new(3.0, 6.4),
            v: Interval::new(0.0, 10.0),
        };
        let patch = FacePatch::new(&cyl, rect, -1.0).expect("patch");
        let cutter = Cutter::new(CutterKind::Ball, 2.0).expect("ball");
        let opts = FinishOptions {
            lead_arc_mm: 20.0,
            ..FinishOptions::default()
        };
        let setup = Setup::new(patch, &cutter, opts);
        let lift = 0.005;
        let run: Vec<Pose> = (0..=30)
            .map(|k| {
                let u = 3.0 * std::f64::consts::FRAC_PI_2 - 0.3 + 0.02 * f64::from(k);
                let cc = DVec3::new(10.0 * u.cos(), 10.0 * u.sin(), 5.0);
                let n = DVec3::new(-u.cos(), -u.sin(), 0.0);
                Pose::new(MoveKind::Cut, cc + n * lift, n, 1000.0)
                    .with_contact(cc, crate::toolpath::ContactKind::Ball)
            })
            .collect();
        let poses = link(
            &setup,
            std::slice::from_ref(&run),
            30.0,
            false,
            &|_| true,
            &|_| None,
        );
        let first = poses
            .iter()
            .position(|p| p.kind == MoveKind::Cut)
            .expect("cut");
        let arc: Vec<&Pose> = poses[..first]
            .iter()
            .filter(|p| p.kind == MoveKind::Plunge)
            .collect();
        assert!(arc.len() >= 3, "{arc:?}");
        // Radius from the arc's start: 5 mm behind the pass start along the cut and 5 mm up
        // along the axis.
        let (a, t) = (arc[0].tip, arc[arc.len() - 1].tip);
        let d = (run[1].tip - run[0].tip).normalize();
        let u = run[0].axis;
        let behind = (t - a).dot(d);
        let up = (a - t).dot(u - d * u.dot(d));
        assert!((behind - 5.0).abs() < 0.05, "behind {behind}");
        assert!((up - 5.0).abs() < 0.1, "up {up}");
        for p in &arc {
            let centre = p.tip + p.axis * 1.0;
            let r = centre.truncate().length();
            assert!(r <= 9.0 + 1e-3, "ball centre {r} mm from the axis");
        }
    }
}
