//! The hot loop of 3-axis finishing: a vertical ball end mill's step applied to a run of Z rays
//! of one grid row.
//!
//! The lowest point of the swept ball on the vertical line through (x, y) is the entry of that
//! line into the capsule of sphere centres (radius R around the segment c₀ → c₀ + d). With
//! the line's origin at the height of c₀ the entry has three candidates, all closed forms
//! quadratic in the ray's offset from c₀:
//! - the start sphere: `s = −√(R² − ρ₀²)`, ρ₀ the horizontal distance to c₀;
//! - the end sphere: `s = d_z − √(R² − ρ₁²)`;
//! - the side of the capsule (the infinite cylinder around the segment, where the foot of the
//!   entry point falls inside the segment): with `L = d_xy·o_xy`, `a = |d_xy|²`,
//!   `b = −L·d_z`, `c = |d|²·ρ₀² − L² − R²·|d|²`, `s = (−b − √(b² − a·c)) / a` when
//!   `0 < L + s·d_z < |d|²`.
//!
//! The entry is the least valid candidate. Per row the constants (the ray's y offset and its
//! square) are computed once; per ray the three candidates are computed without branches into
//! a small buffer (the compiler keeps them in vector lanes) and only then applied to the
//! dexels. A step whose body top is above every material top of the ray (the usual case: the
//! body is clipped to the stock's box) removes everything above the entry; other rays go back
//! to the general path.

use glam::DVec3;

use super::dexel::Dexel;

/// Rays computed per buffer.
pub(super) const LANES: usize = 16;

/// A vertical ball end mill's step, ready for the Z rays.
#[derive(Clone, Copy, Debug)]
pub(super) struct BallStep {
    /// Centre of the sphere at the step's start (tip + R along +Z), mm.
    c0: DVec3,
    /// The step vector, mm.
    d: DVec3,
    /// R².
    rr: f64,
    /// |d|².
    dd: f64,
    /// 1 / |d_xy|², or 0 when the step is (nearly) vertical (no side candidate).
    inv_a: f64,
    /// |d_xy|².
    a: f64,
    /// Highest material top (world z) the fast path may meet: the body's top at the step's
    /// lower end; above it the general path runs.
    top_limit: f64,
}

impl BallStep {
    /// The step from tip `p0` to `p1` of a ball of radius `r` whose body reaches `top` above
    /// the tip.
    pub(super) fn new(p0: DVec3, p1: DVec3, r: f64, top: f64) -> Self {
        let d = p1 - p0;
        let dd = d.length_squared();
        let a = d.x * d.x + d.y * d.y;
        let inv_a = if a > 1e-12 * dd.max(1e-300) {
            1.0 / a
        } else {
            0.0
        };
        Self {
            c0: p0 + DVec3::new(0.0, 0.0, r),
            d,
            rr: r * r,
            dd,
            inv_a,
            a,
            top_limit: p0.z.min(p1.z) + top,
        }
    }

    /// The entry heights (world z) of the rays at x = `xo + (i + k + ½)·dx` (k < `n`) of the
    /// row `y` into `out`; `f64::INFINITY` where a ray misses the capsule.
    pub(super) fn entries(
        &self,
        (xo, dx, i): (f64, f64, usize),
        n: usize,
        y: f64,
        out: &mut [f64; LANES],
    ) {
        let (c0, d, rr, dd) = (self.c0, self.d, self.rr, self.dd);
        let oy = y - c0.y;
        let oy2 = oy * oy;
        let ey = oy - d.y;
        let ey2 = ey * ey;
        let dyoy = d.y * oy;
        let side = self.inv_a > 0.0;
        for (k, slot) in out.iter_mut().enumerate().take(n) {
            #[allow(clippy::cast_precision_loss)]
            let ox = xo + ((i + k) as f64 + 0.5) * dx - c0.x;
            let rho2 = ox * ox + oy2;
            let h0 = rr - rho2;
            let s0 = if h0 >= 0.0 { -h0.sqrt() } else { f64::INFINITY };
            let ex = ox - d.x;
            let h1 = rr - (ex * ex + ey2);
            let s1 = if h1 >= 0.0 {
                d.z - h1.sqrt()
            } else {
                f64::INFINITY
            };
            let mut s = s0.min(s1);
            if side {
                let l = d.x * ox + dyoy;
                let b = -l * d.z;
                let c = dd * rho2 - l * l - rr * dd;
                let h = b * b - self.a * c;
                let sc = (-b - h.max(0.0).sqrt()) * self.inv_a;
                let foot = l + sc * d.z;
                if h >= 0.0 && foot > 0.0 && foot < dd {
                    s = s.min(sc);
                }
            }
            *slot = c0.z + s;
        }
    }
}

/// Lower the material of `dexel` to `lo` (offset along the ray) when the body's top is above
/// it: `Some(changed)`, or `None` when the ray needs the general path (its material reaches
/// above `limit`, the body's lowest top, or the entry was not found).
pub(super) fn cut_below(dexel: &mut Dexel, lo: f64, limit: f32) -> Option<bool> {
    if !lo.is_finite() {
        return None;
    }
    #[allow(clippy::cast_possible_truncation)]
    let lo = lo as f32;
    match dexel {
        Dexel::Empty => Some(false),
        Dexel::One([a, b]) => {
            if *b <= lo {
                Some(false)
            } else if *b > limit {
                None
            } else {
                if lo > *a {
                    *b = lo;
                } else {
                    *dexel = Dexel::Empty;
                }
                Some(true)
            }
        }
        Dexel::Many(v) => {
            let top = v.last().map_or(f32::NEG_INFINITY, |i| i[1]);
            if top <= lo {
                Some(false)
            } else if top > limit {
                None
            } else {
                Some(dexel.subtract(lo, limit))
            }
        }
    }
}

impl BallStep {
    /// The body's lowest top as an offset along rays whose origin is at height `ow`.
    pub(super) fn limit_offset(&self, ow: f64) -> f32 {
        #[allow(clippy::cast_possible_truncation)]
        let l = (self.top_limit - ow) as f32;
        l
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::exact::capsule_entry;

    #[test]
    fn entries_match_the_capsule_entry() {
        let r = 3.0;
        let steps = [
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.12, 0.0, 0.01)),
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(2.0, 1.0, -0.7)),
            (DVec3::new(0.5, 0.2, 1.0), DVec3::new(0.5, 0.2, -1.0)),
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(-1.0, 3.0, 0.0)),
        ];
        for (p0, p1) in steps {
            let s = BallStep::new(p0, p1, r, 20.0);
            let c0 = p0 + DVec3::new(0.0, 0.0, r);
            let c1 = p1 + DVec3::new(0.0, 0.0, r);
            for row in 0..40 {
                let y = -4.0 + 0.2 * f64::from(row);
                let mut out = [0.0; LANES];
                s.entries((-4.0, 0.37, 0), LANES, y, &mut out);
                for (k, got) in out.iter().enumerate() {
                    #[allow(clippy::cast_precision_loss)]
                    let x = -4.0 + (k as f64 + 0.5) * 0.37;
                    let o = DVec3::new(x, y, -20.0);
                    let want = capsule_entry(o, DVec3::Z, c0, c1, r).map(|e| o.z + e);
                    match want {
                        Some(w) => {
                            assert!((got - w).abs() < 1e-9, "{p0} {p1} ({x}, {y}): {got} {w}")
                        }
                        None => assert!(got.is_infinite(), "{p0} {p1} ({x}, {y}): {got}"),
                    }
                }
            }
        }
    }
}
