//! The move model shared by the checks: between two consecutive poses the tool tip moves on the
//! straight segment and the axis turns on the great circle between the two axes (slerp), both
//! uniformly in the same parameter s ∈ [0, 1].

use glam::DVec3;

use crate::toolpath::{MoveKind, Pose};

/// A tool placement: tip and unit axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Placement {
    pub tip: DVec3,
    pub axis: DVec3,
}

impl Placement {
    pub fn of(p: &Pose) -> Self {
        Self {
            tip: p.tip,
            axis: p.axis,
        }
    }
}

/// Angle between two unit vectors, rad (robust near 0 and π).
pub(crate) fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// Great-circle interpolation of unit vectors (falls back to a normalised lerp for tiny angles;
/// for opposite vectors it turns about any perpendicular).
pub(crate) fn slerp(a: DVec3, b: DVec3, s: f64) -> DVec3 {
    let theta = angle_between(a, b);
    if theta < 1e-9 {
        return (a + (b - a) * s).try_normalize().unwrap_or(a);
    }
    let sin_t = theta.sin();
    if sin_t < 1e-12 {
        let perp = a.any_orthonormal_vector();
        let phi = theta * s;
        return a * phi.cos() + perp * phi.sin();
    }
    let wa = ((1.0 - s) * theta).sin() / sin_t;
    let wb = (s * theta).sin() / sin_t;
    (a * wa + b * wb).try_normalize().unwrap_or(a)
}

/// The placement at parameter `s` of the move from `a` to `b`.
pub(crate) fn interpolate(a: Placement, b: Placement, s: f64) -> Placement {
    Placement {
        tip: a.tip + (b.tip - a.tip) * s,
        axis: slerp(a.axis, b.axis, s),
    }
}

/// Upper bound of the distance any point of a tool (up to height `top` above the tip, radius up to
/// `radius`) moves over the whole move from `a` to `b`: |Δtip| + (top + radius)·Δθ.
pub(crate) fn motion_bound(a: Placement, b: Placement, top: f64, radius: f64) -> f64 {
    (b.tip - a.tip).length() + (top + radius) * angle_between(a.axis, b.axis)
}

/// Does the move reaching a pose of this kind cut (fed into material)?
pub(crate) fn cuts(kind: MoveKind) -> bool {
    matches!(kind, MoveKind::Cut | MoveKind::Plunge)
}

/// The cutting moves of a path as `(start pose index, end pose index)`: the move into pose `i`
/// counts when pose `i` is a cut or plunge pose; a cut pose whose predecessor does not exist (the
/// first pose) counts as a move of zero length onto itself.
pub(crate) fn cutting_moves(poses: &[Pose]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for (i, p) in poses.iter().enumerate() {
        if cuts(p.kind) {
            out.push((i.saturating_sub(1), i));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slerp_stays_on_the_great_circle() {
        let a = DVec3::Z;
        let b = DVec3::new(1.0, 0.0, 1.0).normalize();
        for k in 0..=10 {
            let s = f64::from(k) / 10.0;
            let v = slerp(a, b, s);
            assert!((v.length() - 1.0).abs() < 1e-12);
            let want = s * std::f64::consts::FRAC_PI_4;
            assert!((angle_between(a, v) - want).abs() < 1e-12);
        }
        let w = slerp(DVec3::Z, -DVec3::Z, 0.5);
        assert!(w.dot(DVec3::Z).abs() < 1e-12);
    }
}
