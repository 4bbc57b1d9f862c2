//! Engagement read from the material: for a tool at a tip position moving in a direction, each
//! axial disk's engaged arcs are the angles of the front half circle (φ ∈ [0, π], where the
//! edges cut) whose edge point lies in material. Points of the front half are never inside the
//! region the tool has already swept on its way there, so querying the stock as it is before
//! the move gives the engagement anywhere along the move: slots, corners and rest material
//! come out as they are in the stock.
//!
//! The frame is the force model's: x along the feed, y = z × x (left of the feed), φ clockwise
//! from +y seen from above, so material on the left of the feed is up milling. The query
//! reaches the simulation only through [`Material`], implemented for the Z-dexel stock, and
//! [`Workpiece`] (removing a move), implemented for [`SimulatedStock`]: the dexel stock cut by
//! the simulation's own move removal.

use glam::DVec3;

use super::ForceError;
use super::cut::{Arcs, DiskEngagement, Engagement};
use super::mill::EndMill;
use super::path::{PathMove, PathStep, Workpiece};
use crate::diagnostics::Progress;
use crate::simulation::{DexelStock, MovePlan, RayAxis, SimOptions};
use crate::tools::Cutter;

/// Whether a point holds material.
pub trait Material {
    /// True when `p` (mm) is inside the material.
    fn material_at(&self, p: DVec3) -> bool;
}

impl Material for DexelStock {
    /// The Z ray of the cell containing (x, y): material where z lies in one of its intervals.
    fn material_at(&self, p: DVec3) -> bool {
        let Some(fam) = self.families.iter().find(|f| f.axis == RayAxis::Z) else {
            return false;
        };
        let (u, v) = (
            (p.x - fam.origin.x) / fam.spacing,
            (p.y - fam.origin.y) / fam.spacing,
        );
        if !(u >= 0.0 && v >= 0.0) {
            return false;
        }
        // Cell indices: non-negative and finite by the check above.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let (i, j) = (u.floor() as usize, v.floor() as usize);
        if i >= fam.nu || j >= fam.nv {
            return false;
        }
        let s = p.z - fam.origin.z;
        fam.dexels.get(j * fam.nu + i).is_some_and(|d| {
            d.intervals()
                .iter()
                .any(|iv| s >= f64::from(iv[0]) && s <= f64::from(iv[1]))
        })
    }
}

/// How engagement is sampled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleOptions {
    /// Disk height, mm.
    pub disk_height: f64,
    /// Angular step on each disk, rad (default 0.5°).
    pub angle_step: f64,
}

impl Default for SampleOptions {
    fn default() -> Self {
        Self {
            disk_height: super::cut::DEFAULT_DISK_HEIGHT,
            angle_step: 0.5f64.to_radians(),
        }
    }
}

/// The engagement of `mill` with its tip at `tip`, feeding along `feed` (the tool axis is +Z;
/// only the horizontal part of `feed` counts), over the flute length `flute_length` above the
/// tip, at `feed_per_tooth`.
///
/// # Errors
/// [`ForceError::Input`] for a horizontal feed direction of zero length, a disk height or
/// angle step out of range, or a non-finite tip.
pub fn engagement_at(
    material: &impl Material,
    mill: &EndMill,
    tip: DVec3,
    feed: DVec3,
    flute_length: f64,
    feed_per_tooth: f64,
    options: &SampleOptions,
) -> Result<Engagement, ForceError> {
    let x = DVec3::new(feed.x, feed.y, 0.0);
    if !(x.length() > 1e-12) || !tip.is_finite() {
        return Err(ForceError::Input(
            "the feed direction must have a horizontal component (plunges have no side engagement)"
                .into(),
        ));
    }
    super::check_range("disk height", options.disk_height, 1e-3, 100.0, "mm")?;
    super::check_range(
        "angle step",
        options.angle_step.to_degrees(),
        0.01,
        10.0,
        "degrees",
    )?;
    super::check_range("flute length", flute_length, 1e-3, 2000.0, "mm")?;
    let x = x.normalize();
    let y = DVec3::Z.cross(x);
    // Steps over the front half: a small count by the range check above.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let n = (std::f64::consts::PI / options.angle_step).ceil() as usize;
    let step = std::f64::consts::PI / n as f64;
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let disks = (flute_length / options.disk_height).ceil().max(1.0) as usize;
    let dz = flute_length / disks as f64;
    let mut out = Vec::with_capacity(disks);
    for d in 0..disks {
        let (z0, z1) = (dz * d as f64, dz * (d + 1) as f64);
        let local = mill.local(0.5 * (z0 + z1));
        let centre = tip + DVec3::Z * (0.5 * (z0 + z1));
        let mut arcs = Arcs::empty();
        let mut run: Option<f64> = None;
        for k in 0..=n {
            let inside = k < n && {
                let phi = (k as f64 + 0.5) * step;
                let p = centre + (x * phi.sin() + y * phi.cos()) * local.radius;
                material.material_at(p)
            };
            match (inside, run) {
                (true, None) => run = Some(k as f64 * step),
                (false, Some(start)) => {
                    arcs.push(start, k as f64 * step);
                    run = None;
                }
                _ => {}
            }
        }
        out.push(DiskEngagement { z0, z1, arcs });
    }
    // Drop empty disks above the highest engaged one: they cost evaluations and add nothing.
    while out.last().is_some_and(|d| d.arcs.is_empty()) {
        out.pop();
    }
    Ok(Engagement {
        disks: out,
        feed_per_tooth,
    })
}

/// The dexel stock with the moves of a simulation plan, removed one at a time by the
/// simulation's own material removal (holder and shank checks off: forces only).
pub struct SimulatedStock<'a> {
    /// The stock as cut so far.
    pub stock: DexelStock,
    cutter: &'a Cutter,
    plan: &'a MovePlan,
    progress: Progress,
}

impl<'a> SimulatedStock<'a> {
    /// `stock` before the first move of `plan`, cut by `cutter`.
    #[must_use]
    pub fn new(stock: DexelStock, cutter: &'a Cutter, plan: &'a MovePlan) -> Self {
        Self {
            stock,
            cutter,
            plan,
            progress: Progress::new(),
        }
    }
}

impl Material for SimulatedStock<'_> {
    fn material_at(&self, p: DVec3) -> bool {
        self.stock.material_at(p)
    }
}

impl Workpiece for SimulatedStock<'_> {
    fn cut_move(&mut self, index: usize) -> Result<(), ForceError> {
        let opts = SimOptions {
            check_holder: false,
            ..SimOptions::default()
        };
        crate::simulation::simulate_moves(
            &mut self.stock,
            self.cutter,
            self.plan,
            index..index + 1,
            &opts,
            &self.progress,
        )
        .map(|_| ())
        .map_err(|e| ForceError::Input(e.to_string()))
    }
}

/// The moves of a simulation plan for the force model; `spindle_rpm(i)` gives move `i`'s
/// spindle speed (rev/min).
#[must_use]
pub fn path_moves(plan: &MovePlan, spindle_rpm: impl Fn(usize) -> f64) -> Vec<PathMove> {
    plan.moves
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let end = plan
                .moves
                .get(i + 1)
                .map_or(plan.steps.len(), |n| n.first_step);
            let steps = plan
                .steps
                .get(m.first_step..end)
                .unwrap_or(&[])
                .iter()
                .map(|s| PathStep {
                    from: s.from,
                    to: s.to,
                    axis: s.axis,
                })
                .collect();
            PathMove {
                block: m.block,
                rapid: m.rapid,
                feed_mm_per_min: if m.duration_s > 0.0 {
                    m.length_mm / m.duration_s * 60.0
                } else {
                    0.0
                },
                spindle_rpm: spindle_rpm(i),
                steps,
            }
        })
        .collect()
}
