//! Closed forms. Along the engaged flute of a flat end mill the elemental forces integrate
//! exactly (`dφ = −k_β dz`, Eqs. 5.10, 5.23): each flute contributes `(1/k_β)·[P(φ_hi) − P(φ_lo)]`
//! over the part of its angle range `[φ_j(a_a), φ_j(0)]` that lies in the cut, P being the
//! primitive of the elemental force in φ. The axial limits come from the thesis's case table
//! (§5.2.1.1) where it applies, else from intersecting the flute's angle range with every turn
//! of the engaged arc. The mean force per revolution (Eqs. 5.19, 5.26) is `N/(2π)` times the
//! same primitive over the engaged arc, summed over the disks; it is exact in φ for every
//! profile (the nose's κ(z) is integrated by Gauss–Legendre along z).

use std::f64::consts::TAU;

use super::cut::{Arcs, Engagement};
use super::disks::gauss_interval;
use super::mill::{EndMill, Profile, wrap};
use super::{Coefficients, Force, ForceError, LinearCoefficients};

/// Force and torque of an edge piece: x, y, z in N, torque about the axis in N·mm.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Load {
    /// Force, N.
    pub force: Force,
    /// Torque about the tool axis, N·mm (positive against the cutting rotation).
    pub torque: f64,
}

impl std::ops::AddAssign for Load {
    fn add_assign(&mut self, o: Self) {
        self.force += o.force;
        self.torque += o.torque;
    }
}

/// The primitive in φ of the elemental force per unit edge length at an edge with
/// `chip = f_t·sin κ` and axial immersion (sin κ, cos κ): `[P_x, P_y, P_z, P_t]` where P_t is
/// the tangential force's primitive (torque = r·P_t).
#[must_use]
pub fn primitive(phi: f64, k: &LinearCoefficients, chip: f64, sin_k: f64, cos_k: f64) -> [f64; 4] {
    let (s, c) = phi.sin_cos();
    let (s2, c2) = (2.0 * phi).sin_cos();
    let sq = 0.25 * (2.0 * phi - s2); // ∫ sin²
    let sc = -0.25 * c2; // ∫ sin·cos
    let edge_rad = cos_k * k.kae - sin_k * k.kre;
    let cut_rad = cos_k * k.kac - sin_k * k.krc;
    let px = -k.kte * s - k.ktc * chip * sc - edge_rad * c + cut_rad * chip * sq;
    let py = -k.kte * c + k.ktc * chip * sq + edge_rad * s + cut_rad * chip * sc;
    let pz = (cos_k * k.kre + sin_k * k.kae) * phi - (cos_k * k.krc + sin_k * k.kac) * chip * c;
    let pt = k.kte * phi - k.ktc * chip * c;
    [px, py, pz, pt]
}

/// The engaged height ranges of flute j by the thesis's case table, for a flute whose tip is
/// at angle `phi_tip` (φ + θ_j), lag rate `k` > 0, axial depth `a` and one arc `[st, ex]`;
/// `None` when the flute is out of the cut (cases 4 and φ_j(0) < φ_st). Valid when
/// `k·a ≤ 2π − ex` (no part of the flute can re-enter the cut one turn later).
#[must_use]
pub fn case_table(phi_tip: f64, k: f64, a: f64, st: f64, ex: f64) -> Option<(f64, f64)> {
    let p0 = wrap(phi_tip);
    let p1 = p0 - k * a;
    if p0 >= st && p0 <= ex {
        // Cases 0 and 1.
        let z2 = if p1 > st { a } else { (p0 - st) / k };
        Some((0.0, z2))
    } else if p0 > ex && p1 < ex {
        // Cases 2 and 3.
        let z1 = (p0 - ex) / k;
        let z2 = if p1 > st { a } else { (p0 - st) / k };
        Some((z1, z2))
    } else {
        None
    }
}

/// Whether [`case_table`] applies to depth `a` at lag rate `k` for an arc ending at `ex`.
#[must_use]
pub fn case_table_applies(k: f64, a: f64, ex: f64) -> bool {
    k * a <= TAU - ex
}

/// The angle ranges `[lo, hi]` (unwrapped, lo < hi) of the flute `u ∈ [phi_tip − k·a, phi_tip]`
/// that fall in any turn of the arcs.
fn engaged_ranges(phi_tip: f64, k: f64, a: f64, arcs: &Arcs, out: &mut Vec<(f64, f64)>) {
    out.clear();
    let (lo_u, hi_u) = (phi_tip - k * a, phi_tip);
    for &(s, e) in arcs.as_slice() {
        let m0 = ((lo_u - e) / TAU).floor();
        let m1 = ((hi_u - s) / TAU).ceil();
        let mut m = m0;
        while m <= m1 {
            let (lo, hi) = ((s + TAU * m).max(lo_u), (e + TAU * m).min(hi_u));
            if hi > lo {
                out.push((lo, hi));
            }
            m += 1.0;
        }
    }
}

/// Instantaneous force and torque of a flat end mill in a cut of depth `a` engaged on `arcs`
/// (the same on every disk), rotation angle `phi`, by the closed-form flute integrals.
///
/// # Errors
/// [`ForceError::Tool`] for a ball or bull-nose mill (their κ(z) has no closed form here).
pub fn flute_integrals(
    mill: &EndMill,
    k: &LinearCoefficients,
    feed_per_tooth: f64,
    a: f64,
    arcs: &Arcs,
    phi: f64,
) -> Result<Load, ForceError> {
    if mill.profile != Profile::Flat {
        return Err(ForceError::Tool(
            "the closed-form flute integrals are for flat end mills".into(),
        ));
    }
    let kb = mill.k_beta();
    let mut load = Load::default();
    let mut ranges = Vec::new();
    let table = match arcs.as_slice() {
        [(st, ex)] if kb > 0.0 && case_table_applies(kb, a, *ex) => Some((*st, *ex)),
        _ => None,
    };
    for &theta in &mill.flute_angles {
        let tip = phi + theta;
        if kb == 0.0 {
            if arcs.contains(wrap(tip)) {
                let g = element(wrap(tip), k, feed_per_tooth);
                load.force += Force {
                    fx: g[0] * a,
                    fy: g[1] * a,
                    fz: g[2] * a,
                };
                load.torque += g[3] * a * mill.radius;
            }
            continue;
        }
        ranges.clear();
        if let Some((st, ex)) = table {
            if let Some((z1, z2)) = case_table(tip, kb, a, st, ex) {
                let p0 = wrap(tip);
                ranges.push((p0 - kb * z2, p0 - kb * z1));
            }
        } else {
            engaged_ranges(tip, kb, a, arcs, &mut ranges);
        }
        for &(lo, hi) in &ranges {
            let ph = primitive(hi, k, feed_per_tooth, 1.0, 0.0);
            let pl = primitive(lo, k, feed_per_tooth, 1.0, 0.0);
            load.force += Force {
                fx: (ph[0] - pl[0]) / kb,
                fy: (ph[1] - pl[1]) / kb,
                fz: (ph[2] - pl[2]) / kb,
            };
            load.torque += mill.radius * (ph[3] - pl[3]) / kb;
        }
    }
    Ok(load)
}

/// The elemental force per unit length on the cylinder at angle φ: `[x, y, z, tangential]`.
fn element(phi: f64, k: &LinearCoefficients, ft: f64) -> [f64; 4] {
    let (s, c) = phi.sin_cos();
    let h = ft * s;
    let t = k.kte + k.ktc * h;
    let r = k.kre + k.krc * h;
    [-t * c - r * s, t * s - r * c, k.kae + k.kac * h, t]
}

/// Mean force and torque over one revolution (Eqs. 5.19, 5.26 generalised to any per-disk
/// engagement and profile): `N/(2π)·Σ_disks ∫ [P(φ_ex) − P(φ_st)] dS`.
#[must_use]
pub fn mean_load(mill: &EndMill, coefficients: &Coefficients, engagement: &Engagement) -> Load {
    let n = mill.flutes() as f64;
    let ft = engagement.feed_per_tooth;
    let mut total = Load::default();
    for disk in &engagement.disks {
        if disk.arcs.is_empty() {
            continue;
        }
        let mid = mill.local(0.5 * (disk.z0 + disk.z1));
        let k = coefficients.at_mean_chip(ft * mid.sin_kappa * disk.arcs.mean_sin());
        let mut acc = [0.0; 4];
        gauss_interval(disk.z0, disk.z1, |z, w| {
            let l = mill.local(z);
            if l.sin_kappa <= 0.0 {
                return;
            }
            let ds = w / l.sin_kappa;
            let chip = ft * l.sin_kappa;
            for &(s, e) in disk.arcs.as_slice() {
                let pe = primitive(e, &k, chip, l.sin_kappa, l.cos_kappa);
                let ps = primitive(s, &k, chip, l.sin_kappa, l.cos_kappa);
                for ((a, e), s) in acc.iter_mut().zip(pe).zip(ps).take(3) {
                    *a += (e - s) * ds;
                }
                acc[3] += (pe[3] - ps[3]) * ds * l.radius;
            }
        });
        let f = n / TAU;
        total += Load {
            force: Force {
                fx: f * acc[0],
                fy: f * acc[1],
                fz: f * acc[2],
            },
            torque: f * acc[3],
        };
    }
    total
}
