//! Closed-form ray queries against capsules and spheres (the swept ball).

use glam::DVec3;

/// First parameter t ≥ 0 at which the ray `o + t·d` (unit `d`, `o` outside) meets the capsule
/// of radius `r` around the segment `a`–`b` (I. Quilez's closed form).
pub(crate) fn ray_capsule(o: DVec3, d: DVec3, a: DVec3, b: DVec3, r: f64) -> Option<f64> {
    let ba = b - a;
    let oa = o - a;
    let baba = ba.dot(ba);
    let bard = ba.dot(d);
    let baoa = ba.dot(oa);
    let rdoa = d.dot(oa);
    let oaoa = oa.dot(oa);
    let qa = baba - bard * bard;
    if baba > 0.0 && qa > 1e-14 * baba {
        let qb = baba * rdoa - baoa * bard;
        let qc = baba * oaoa - baoa * baoa - r * r * baba;
        let h = qb * qb - qa * qc;
        if h < 0.0 {
            return None;
        }
        let t = (-qb - h.sqrt()) / qa;
        let y = baoa + t * bard;
        if y > 0.0 && y < baba {
            return (t >= 0.0).then_some(t);
        }
        // The hit is on a cap: the sphere at the end it passed.
        let oc = if y <= 0.0 { oa } else { o - b };
        return ray_sphere(oc, d, r);
    }
    // Degenerate segment or ray along it: the nearer of the two end spheres.
    match (ray_sphere(oa, d, r), ray_sphere(o - b, d, r)) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, y) => x.or(y),
    }
}

/// First t ≥ 0 where `o + t·d` meets the sphere of radius `r` at the origin (`oc` = o − centre).
fn ray_sphere(oc: DVec3, d: DVec3, r: f64) -> Option<f64> {
    let b = d.dot(oc);
    let c = oc.dot(oc) - r * r;
    let h = b * b - c;
    if h < 0.0 {
        return None;
    }
    let t = -b - h.sqrt();
    (t >= 0.0).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::checks::sweep::capsule_distance;

    /// Brute force: march the ray in 1e-5 steps until the capsule distance is ≤ 0, then bisect.
    fn marched(o: DVec3, d: DVec3, a: DVec3, b: DVec3, r: f64) -> Option<f64> {
        let f = |t: f64| capsule_distance(o + d * t, a, b, r);
        let mut t = 0.0;
        while t < 20.0 {
            if f(t + 1e-3) <= 0.0 {
                let (mut lo, mut hi) = (t, t + 1e-3);
                for _ in 0..60 {
                    let m = 0.5 * (lo + hi);
                    if f(m) <= 0.0 { hi = m } else { lo = m }
                }
                return Some(hi);
            }
            t += 1e-3;
        }
        None
    }

    #[test]
    fn ray_capsule_matches_marching() {
        let a = DVec3::new(0.0, 0.0, 1.0);
        let b = DVec3::new(3.0, 1.0, 2.0);
        let mut hits = 0;
        for i in 0..12 {
            for j in 0..6 {
                let o = DVec3::new(-2.0 + 0.6 * f64::from(i), -1.5 + 0.5 * f64::from(j), -2.0);
                let d = DVec3::new(0.1 * f64::from(j) - 0.2, 0.05 * f64::from(i) - 0.3, 1.0)
                    .normalize();
                let want = marched(o, d, a, b, 1.0);
                let got = ray_capsule(o, d, a, b, 1.0);
                match (want, got) {
                    (Some(w), Some(g)) => {
                        hits += 1;
                        assert!((w - g).abs() < 1e-9, "{o} {d}: {w} vs {g}");
                    }
                    (None, None) => {}
                    other => panic!("{o} {d}: {other:?}"),
                }
            }
        }
        assert!(hits > 20, "{hits}");
        // Along the axis and a degenerate capsule (a sphere).
        let t = ray_capsule(
            DVec3::new(-5.0, 0.0, 0.0),
            DVec3::X,
            DVec3::ZERO,
            DVec3::X,
            1.0,
        );
        assert!((t.expect("hit") - 4.0).abs() < 1e-12);
        let t = ray_capsule(
            DVec3::new(0.0, 0.0, -5.0),
            DVec3::Z,
            DVec3::ZERO,
            DVec3::ZERO,
            2.0,
        );
        assert!((t.expect("hit") - 3.0).abs() < 1e-12);
    }
}
