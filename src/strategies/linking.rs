//! Linking passes into one tool path: approach from the clearance plane (rapid down to a safe
//! height above the start, then a plunge at feed), stay down between neighbouring passes when
//! the link is short (the link is itself stepped over the surface, so it cannot gouge), else
//! retract along the axis to the clearance plane, rapid across, and plunge; depart to the
//! clearance plane at the end. Rapids are marked `rapid`.

use glam::DVec3;

use super::finish::Setup;
use super::pass::Pass;
use super::stepping::pass_poses;
use crate::toolpath::{MoveKind, Pose};

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
        let near = last_prev.tip.distance(first.tip) <= stay_down;
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
/// a contact point): the parameter-space segment between them, stepped like a pass; moves
/// marked `link`. `None` when a contact cannot be inverted onto the face.
fn surface_link(setup: &Setup<'_>, a: &Pose, b: &Pose) -> Option<Vec<Pose>> {
    let (ca, cb) = (a.cc?, b.cc?);
    let pa = setup
        .patch
        .surface
        .closest_point(ca, setup.patch.domain, None);
    let pb = setup
        .patch
        .surface
        .closest_point(cb, setup.patch.domain, Some(pa.uv));
    if pa.distance > 1e-3 || pb.distance > 1e-3 {
        return None;
    }
    let pass = Pass::new(vec![pa.uv, pb.uv]).resampled(&setup.patch, setup.guide_spacing);
    let mut poses = pass_poses(setup, &pass);
    if poses.len() < 2 {
        return None;
    }
    poses.remove(0);
    poses.pop();
    for p in &mut poses {
        p.kind = MoveKind::Link;
        p.scallop_mm = None;
    }
    Some(poses)
}
