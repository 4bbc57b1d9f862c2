//! Numerical disk sums (the thesis's Loops 1–3, Fig. 7.7): the flute is cut into axial disks;
//! in each disk the part of the edge that lies in the cut is found from the disk's engaged arcs,
//! and the elemental forces are integrated over it with 4-point Gauss–Legendre along z. The
//! split at the entry and exit points keeps the quadrature smooth, so the sums agree with the
//! closed forms to ~1e-12 for a flat end mill; on a ball or bull nose the same code integrates
//! the varying local radius and axial immersion angle.
//!
//! Elemental force on the tool per edge length dS = dz / sin κ, with h = f_t·sin φ·sin κ:
//! `dF = dF_t·(−cos φ, sin φ, 0) + dF_r·(−sin κ sin φ, −sin κ cos φ, cos κ)
//!      + dF_a·(cos κ sin φ, cos κ cos φ, sin κ)`; on the cylinder (κ = π/2) this is Eq. 5.7
//! with `dF_z = dF_a`.

use std::f64::consts::TAU;

use super::closed_form::Load;
use super::cut::{Arcs, Engagement};
use super::mill::{EndMill, wrap};
use super::{Coefficients, Force, LinearCoefficients};

/// Gauss–Legendre nodes on [−1, 1] (4 points).
const NODES: [f64; 4] = [
    -0.861_136_311_594_053,
    -0.339_981_043_584_856,
    0.339_981_043_584_856,
    0.861_136_311_594_053,
];
/// Gauss–Legendre weights (4 points).
const WEIGHTS: [f64; 4] = [
    0.347_854_845_137_454,
    0.652_145_154_862_546,
    0.652_145_154_862_546,
    0.347_854_845_137_454,
];

/// Call `f(z, weight)` at the 4 Gauss–Legendre nodes of [a, b].
pub fn gauss_interval(a: f64, b: f64, mut f: impl FnMut(f64, f64)) {
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    for (x, w) in NODES.iter().zip(WEIGHTS) {
        f(mid + half * x, w * half);
    }
}

/// One disk ready for evaluation: its range, arcs and coefficients at its mean chip thickness.
#[derive(Clone, Copy, Debug)]
struct PreparedDisk {
    z0: f64,
    z1: f64,
    arcs: Arcs,
    k: LinearCoefficients,
}

/// The disk-sum force model of one tool in one engagement.
#[derive(Clone, Debug)]
pub struct DiskForces<'a> {
    mill: &'a EndMill,
    feed_per_tooth: f64,
    k_beta: f64,
    disks: Vec<PreparedDisk>,
}

impl<'a> DiskForces<'a> {
    /// Prepare the disks: the exponential model's coefficients are taken at each disk's mean
    /// chip thickness `f_t·sin κ·mean(sin φ)` over its arcs.
    #[must_use]
    pub fn new(mill: &'a EndMill, coefficients: &Coefficients, engagement: &Engagement) -> Self {
        let ft = engagement.feed_per_tooth;
        let disks = engagement
            .disks
            .iter()
            .map(|d| {
                let sk = mill.local(0.5 * (d.z0 + d.z1)).sin_kappa;
                PreparedDisk {
                    z0: d.z0,
                    z1: d.z1,
                    arcs: d.arcs,
                    k: coefficients.at_mean_chip(ft * sk * d.arcs.mean_sin()),
                }
            })
            .collect();
        Self {
            mill,
            feed_per_tooth: ft,
            k_beta: mill.k_beta(),
            disks,
        }
    }

    /// Number of disks.
    #[must_use]
    pub fn len(&self) -> usize {
        self.disks.len()
    }

    /// Whether there are no disks.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.disks.is_empty()
    }

    /// Mid-height of disk `i`, mm.
    #[must_use]
    pub fn disk_mid(&self, i: usize) -> f64 {
        self.disks.get(i).map_or(0.0, |d| 0.5 * (d.z0 + d.z1))
    }

    /// One disk evaluation: the force and torque of flute `flute` in disk `disk` at rotation
    /// angle `phi` (zero for indices out of range).
    #[must_use]
    pub fn disk_load(&self, disk: usize, flute: usize, phi: f64) -> Load {
        let (Some(d), Some(theta)) = (self.disks.get(disk), self.mill.flute_angles.get(flute))
        else {
            return Load::default();
        };
        let mut load = Load::default();
        if d.arcs.is_empty() {
            return load;
        }
        let tip = phi + theta;
        let k = self.k_beta;
        if k == 0.0 {
            let u = wrap(tip);
            if d.arcs.contains(u) {
                self.integrate(d, d.z0, d.z1, tip, &mut load);
            }
            return load;
        }
        // The edge's angle runs from tip − k·z1 (top) to tip − k·z0 (bottom).
        let (lo_u, hi_u) = (tip - k * d.z1, tip - k * d.z0);
        for &(s, e) in d.arcs.as_slice() {
            let mut m = ((lo_u - e) / TAU).floor();
            let m1 = ((hi_u - s) / TAU).ceil();
            while m <= m1 {
                let lo = (s + TAU * m).max(lo_u);
                let hi = (e + TAU * m).min(hi_u);
                if hi > lo {
                    self.integrate(d, (tip - hi) / k, (tip - lo) / k, tip, &mut load);
                }
                m += 1.0;
            }
        }
        load
    }

    /// Gauss–Legendre integral of the elemental force over heights [za, zb] of an edge whose
    /// tip is at angle `tip`.
    fn integrate(&self, d: &PreparedDisk, za: f64, zb: f64, tip: f64, load: &mut Load) {
        let k = &d.k;
        let ft = self.feed_per_tooth;
        let kb = self.k_beta;
        gauss_interval(za, zb, |z, w| {
            let l = self.mill.local(z);
            if l.sin_kappa <= 0.0 {
                return;
            }
            let ds = w / l.sin_kappa;
            let (s, c) = (tip - kb * z).sin_cos();
            let h = ft * s * l.sin_kappa;
            let t = (k.kte + k.ktc * h) * ds;
            let r = (k.kre + k.krc * h) * ds;
            let a = (k.kae + k.kac * h) * ds;
            let (sk, ck) = (l.sin_kappa, l.cos_kappa);
            load.force += Force {
                fx: -t * c - r * sk * s + a * ck * s,
                fy: t * s - r * sk * c + a * ck * c,
                fz: r * ck + a * sk,
            };
            load.torque += t * l.radius;
        });
    }

    /// Force and torque of the whole tool at rotation angle `phi`; `per_disk`, when given (one
    /// slot per disk), receives each disk's share.
    pub fn load(&self, phi: f64, mut per_disk: Option<&mut [Load]>) -> Load {
        let mut total = Load::default();
        for i in 0..self.disks.len() {
            let mut disk = Load::default();
            for j in 0..self.mill.flutes() {
                disk += self.disk_load(i, j, phi);
            }
            if let Some(slot) = per_disk.as_deref_mut().and_then(|p| p.get_mut(i)) {
                *slot = disk;
            }
            total += disk;
        }
        total
    }
}
