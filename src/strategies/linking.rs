//! Linking passes into one tool path: approach from the clearance plane (rapid down to a safe
//! height above the start, then a plunge at feed), stay down between neighbouring passes when
//! the link is short (the link is itself stepped over the surface, so it cannot gouge), else
//! retract along the axis to the clearance plane, rapid across, and plunge; depart to the
//! clearance plane at the end. Rapids are marked `rapid`.

use glam::{DQuat, DVec3};

use super::axis::{AxisMode, axis_angle};
use super::finish::Setup;
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

/// The point above `p` on its axis at height `z` (straight up when the axis is nearly level).
fn above(p: &Pose, z: f64) -> DVec3 {
    if p.axis.z > 0.1 {
        p.tip + p.axis * ((z - p.tip.z) / p.axis.z).max(0.0)
    } else {
        DVec3::new(p.tip.x, p.tip.y, z.max(p.tip.z))
    }
}

/// Join the runs (cut poses per pass) with approach, links, retracts and departure.
/// `one_way`: never stay down between passes (one-way zig-zag returns at clearance).
#[must_use]
pub fn link(setup: &Setup<'_>, runs: &[Vec<Pose>], clearance: f64, one_way: bool) -> Vec<Pose> {
    let feed = setup.opts.feed;
    let stay_down = 2.5 * setup.cutter.diameter;
    let mut out: Vec<Pose> = Vec::new();
    for run in runs.iter().filter(|r| !r.is_empty()) {
        let (Some(first), Some(last_prev)) = (run.first(), out.last().copied()) else {
            if let Some(first) = run.first() {
                out.extend(approach(first, clearance, feed));
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
            surface_link(setup, &last_prev, first)
        } else {
            None
        };
        match link_run {
            Some(link) => {
                out.extend(link);
                out.extend(run.iter().copied());
            }
            None => {
                out.push(Pose::new(
                    MoveKind::Rapid,
                    above(&last_prev, clearance),
                    last_prev.axis,
                    feed,
                ));
                out.extend(approach(first, clearance, feed));
                out.extend(run.iter().skip(1).copied());
            }
        }
    }
    if let Some(last) = out.last().copied() {
        out.push(Pose::new(
            MoveKind::Rapid,
            above(&last, clearance),
            last.axis,
            feed,
        ));
    }
    out
}

/// Rapid to the clearance plane above `first`, rapid down to the approach height, plunge to it.
fn approach(first: &Pose, clearance: f64, feed: f64) -> Vec<Pose> {
    let top = above(first, clearance);
    let near = above(first, (first.tip.z + APPROACH_HEIGHT).min(clearance));
    let mut plunge = *first;
    plunge.kind = MoveKind::Plunge;
    vec![
        Pose::new(MoveKind::Rapid, top, first.axis, feed),
        Pose::new(MoveKind::Rapid, near, first.axis, feed),
        plunge,
    ]
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
