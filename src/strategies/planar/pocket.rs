//! Offset pocketing: the region offset by the tool radius (plus the wall allowance), then
//! again by the step-over until nothing is left; cut from the inside out at each step-down
//! level, and once more at the floor with no allowance (the finishing level: floor and walls).
//!
//! Entry: a ramp along the innermost loop of a level (lines sloped, arcs as helices) at no
//! more than the ramp angle, never a plunge, so a cutter without centre cutting can enter;
//! the ramp lap is followed by a full lap at the level. Linking: from one loop to the next
//! outer one the tool stays down on a straight feed move when that move stays inside the
//! tool-centre region; otherwise it retracts to the clearance height, moves by rapid and
//! ramps in again from just above the level cut before.

use glam::{DVec2, DVec3};

use super::PlanarError;
use crate::geometry::planar::{Element, Profile, Region};
use crate::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};

/// Options of [`pocket`].
#[derive(Clone, Debug, PartialEq)]
pub struct PocketOptions {
    /// Height of the top of the material, mm.
    pub top_z_mm: f64,
    /// Height of the floor, mm.
    pub floor_z_mm: f64,
    /// Largest depth of one level, mm.
    pub step_down_mm: f64,
    /// Step-over as a fraction of the tool diameter (0, 1].
    pub stepover_frac: f64,
    /// Stock left on the walls by the roughing levels, mm (the finishing level leaves none).
    pub wall_allowance_mm: f64,
    /// Stock left on the floor by the roughing levels, mm.
    pub floor_allowance_mm: f64,
    /// Safe height above the top for rapids, mm above `top_z_mm`.
    pub clearance_mm: f64,
    /// Largest ramp angle of an entry, rad.
    pub ramp_angle_rad: f64,
    /// Cutting feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Chord tolerance of the sampled view of arcs, mm.
    pub chord_tol_mm: f64,
}

impl Default for PocketOptions {
    fn default() -> Self {
        Self {
            top_z_mm: 0.0,
            floor_z_mm: -5.0,
            step_down_mm: 2.0,
            stepover_frac: 0.5,
            wall_allowance_mm: 0.2,
            floor_allowance_mm: 0.2,
            clearance_mm: 5.0,
            ramp_angle_rad: 3f64.to_radians(),
            feed_mm_per_min: 1000.0,
            chord_tol_mm: 0.005,
        }
    }
}

/// Appends moves with exact arcs to a tool path.
struct Builder {
    tp: Toolpath,
    chord: f64,
}

impl Builder {
    fn at(&self) -> Option<DVec3> {
        self.tp.poses.last().map(|p| p.tip)
    }

    fn to(&mut self, kind: MoveKind, p: DVec3, feed: f64) {
        if self.at().is_some_and(|a| a.distance(p) < 1e-9) {
            return;
        }
        let f = if kind == MoveKind::Rapid { 0.0 } else { feed };
        self.tp.push_pose(Pose::new(kind, p, DVec3::Z, f));
    }

    /// One element from the current point (its start) to its end, descending `dz`.
    fn element(&mut self, e: &Element, z_end: f64, feed: f64) -> Result<(), PlanarError> {
        match *e {
            Element::Line { b, .. } => {
                self.to(MoveKind::Cut, b.extend(z_end), feed);
                Ok(())
            }
            Element::Arc {
                centre, sweep_rad, ..
            } => {
                let z0 = self.at().map_or(z_end, |a| a.z);
                self.tp
                    .push_helix(
                        centre.extend(z0),
                        DVec3::Z,
                        sweep_rad,
                        z_end - z0,
                        MoveKind::Cut,
                        feed,
                        self.chord,
                    )
                    .map_err(|e| PlanarError(e.to_string()))
            }
        }
    }
}

/// A closed loop's elements starting at the element nearest to `p` (the loop rotated).
fn rotated_to(loop_: &Profile, p: DVec2) -> Vec<Element> {
    let els = loop_.elements();
    let best = els
        .iter()
        .enumerate()
        .map(|(i, e)| (i, e.start().distance_squared(p)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(0, |b| b.0);
    let n = els.len();
    (0..n)
        .filter_map(|k| els.get((best + k) % n).copied())
        .collect()
}

/// True when the straight move from `a` to `b` stays inside `centres` (sampled every 0.2 mm).
fn segment_inside(centres: &Region, a: DVec2, b: DVec2) -> bool {
    let n = ((a.distance(b) / 0.2).ceil() as usize).clamp(1, 10_000);
    (0..=n).all(|k| centres.contains(a.lerp(b, k as f64 / n as f64)))
}

/// An offset pocket of `region` for a flat or bull-nose cutter of the tool record.
///
/// # Errors
/// Bad options (non-finite, floor above top, step-over outside (0, 1]), or a region the tool
/// does not fit.
pub fn pocket(
    region: &Region,
    tool: &ToolRecord,
    o: &PocketOptions,
) -> Result<Toolpath, PlanarError> {
    let r = tool.cutter.radius();
    let bad = |m: &str| Err(PlanarError(m.to_string()));
    let finite = [
        o.top_z_mm,
        o.floor_z_mm,
        o.step_down_mm,
        o.stepover_frac,
        o.wall_allowance_mm,
        o.floor_allowance_mm,
        o.clearance_mm,
        o.ramp_angle_rad,
        o.feed_mm_per_min,
        o.chord_tol_mm,
    ];
    if finite.iter().any(|v| !v.is_finite()) {
        return bad("pocket: every option must be a finite number");
    }
    if o.floor_z_mm >= o.top_z_mm {
        return bad("pocket: the floor must lie below the top");
    }
    if !(o.stepover_frac > 0.0 && o.stepover_frac <= 1.0) {
        return bad("pocket: step-over must be a fraction of the tool diameter in (0, 1]");
    }
    if !(o.step_down_mm > 0.0 && o.feed_mm_per_min > 0.0 && o.clearance_mm > 0.0) {
        return bad("pocket: step-down, feed and clearance must be positive");
    }
    if !(o.ramp_angle_rad > 0.0 && o.ramp_angle_rad < std::f64::consts::FRAC_PI_2) {
        return bad("pocket: the ramp angle must lie in (0°, 90°)");
    }
    if o.wall_allowance_mm < 0.0
        || o.floor_allowance_mm < 0.0
        || o.floor_allowance_mm >= o.top_z_mm - o.floor_z_mm
    {
        return bad(
            "pocket: allowances must be non-negative and the floor allowance below the depth",
        );
    }
    let step = o.stepover_frac * 2.0 * r;
    let safe = o.top_z_mm + o.clearance_mm;
    // Levels: roughing down to the floor allowance, then the floor.
    let rough_floor = o.floor_z_mm + o.floor_allowance_mm;
    let n_rough = ((o.top_z_mm - rough_floor) / o.step_down_mm - 1e-9)
        .ceil()
        .max(1.0) as usize;
    let mut levels: Vec<(f64, f64)> = (1..=n_rough)
        .map(|k| {
            (
                o.top_z_mm - (o.top_z_mm - rough_floor) * k as f64 / n_rough as f64,
                o.wall_allowance_mm,
            )
        })
        .collect();
    if o.floor_allowance_mm > 0.0 || o.wall_allowance_mm > 0.0 {
        levels.push((o.floor_z_mm, 0.0));
    }
    let mut b = Builder {
        tp: Toolpath::new(tool.clone(), Vec::new()),
        chord: o.chord_tol_mm.max(1e-4),
    };
    let (lo, hi) = region.bounds();
    if !(lo.is_finite() && hi.is_finite()) {
        return bad("pocket: the region is empty");
    }
    let start = region
        .offset(r)
        .boundaries()
        .first()
        .and_then(|p| p.vertices.first())
        .map(|v| DVec2::new(v.x, v.y))
        .ok_or_else(|| {
            PlanarError(format!(
                "pocket: a tool of radius {r} mm does not fit the region"
            ))
        })?;
    b.to(MoveKind::Rapid, start.extend(safe), 0.0);
    let mut z_prev = o.top_z_mm;
    for &(z, allowance) in &levels {
        let centres = region.offset(r + allowance);
        if centres.is_empty() {
            return Err(PlanarError(format!(
                "pocket: a tool of radius {r} mm with {allowance} mm allowance does not fit the region"
            )));
        }
        // Offset loops, outermost first.
        let mut rings: Vec<Vec<Profile>> = Vec::new();
        let mut d = 0.0;
        loop {
            let off = if d == 0.0 {
                centres.clone()
            } else {
                centres.offset(d)
            };
            if off.is_empty() || rings.len() > 100_000 {
                break;
            }
            rings.push(off.boundaries().into_iter().cloned().collect());
            d += step;
        }
        let mut down = false;
        for ring in rings.iter().rev() {
            for l in ring {
                let here = b.at().map_or(start, |p| p.truncate());
                let els = rotated_to(l, here);
                let Some(first) = els.first() else { continue };
                let s = first.start();
                if down && segment_inside(&centres, here, s) {
                    b.to(MoveKind::Cut, s.extend(z), o.feed_mm_per_min);
                    for e in &els {
                        b.element(e, z, o.feed_mm_per_min)?;
                    }
                    continue;
                }
                // Retract, move over, ramp in from just above the level cut before.
                if let Some(at) = b.at()
                    && at.z < safe
                {
                    b.to(MoveKind::Rapid, at.truncate().extend(safe), 0.0);
                }
                let z_from = z_prev + 0.5f64.min(o.clearance_mm);
                b.to(MoveKind::Rapid, s.extend(safe), 0.0);
                b.to(MoveKind::Rapid, s.extend(z_from), 0.0);
                let lap: f64 = els.iter().map(Element::length).sum();
                if lap <= 1e-9 {
                    continue;
                }
                let dz = z_from - z;
                let laps = (dz / (lap * o.ramp_angle_rad.tan()) - 1e-9).ceil().max(1.0) as usize;
                let rate = dz / (laps as f64 * lap);
                let mut zc = z_from;
                for _ in 0..laps {
                    for e in &els {
                        zc = (zc - e.length() * rate).max(z);
                        b.element(e, zc, o.feed_mm_per_min)?;
                    }
                }
                for e in &els {
                    b.element(e, z, o.feed_mm_per_min)?;
                }
                down = true;
            }
        }
        z_prev = z;
    }
    if let Some(at) = b.at() {
        b.to(MoveKind::Rapid, at.truncate().extend(safe), 0.0);
    }
    Ok(b.tp)
}
