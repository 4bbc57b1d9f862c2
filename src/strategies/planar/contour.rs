//! Contour (profile) passes around a region's boundaries: outside or inside, climb or
//! conventional (spindle turning clockwise seen from above, M3), several depths, a
//! quarter-circle lead in and out on the free side, and tabs.
//!
//! Tabs: `tab_count` spans of the tool-centre path evenly spaced along each loop, each
//! `tab_width_mm` long (the width of the tab where it meets a straight wall of the part), in
//! which passes below the tab's top ride at the tab's top; the tool rises straight up before a tab and goes down after it by
//! a ramp along the path at the ramp angle, never a plunge. The contour is a finishing
//! operation: the lead-in starts off the part by the lead radius, where earlier clearing has
//! removed the stock.

use glam::DVec3;

use super::PlanarError;
use crate::geometry::planar::{Element, Profile, Region};
use crate::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};

/// Which side of the boundaries the tool runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContourSide {
    /// Outside the region (an outer profile).
    Outside,
    /// Inside the region (a pocket's walls).
    Inside,
}

/// Options of [`contour`].
#[derive(Clone, Debug, PartialEq)]
pub struct ContourOptions {
    /// Side of the boundaries.
    pub side: ContourSide,
    /// Climb milling (else conventional).
    pub climb: bool,
    /// Height of the top of the material, mm.
    pub top_z_mm: f64,
    /// Height of the last pass, mm.
    pub bottom_z_mm: f64,
    /// Largest depth of one pass, mm.
    pub step_down_mm: f64,
    /// Stock left on the wall, mm.
    pub allowance_mm: f64,
    /// Radius of the lead-in and lead-out arcs, mm (0: none).
    pub lead_radius_mm: f64,
    /// Number of tabs per loop (0: none).
    pub tab_count: usize,
    /// Width of the material a tab keeps, mm.
    pub tab_width_mm: f64,
    /// Height of the tabs above the bottom, mm.
    pub tab_height_mm: f64,
    /// Ramp angle down after a tab, rad.
    pub ramp_angle_rad: f64,
    /// Safe height above the top, mm.
    pub clearance_mm: f64,
    /// Feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Chord tolerance of the sampled view of arcs, mm.
    pub chord_tol_mm: f64,
}

impl Default for ContourOptions {
    fn default() -> Self {
        Self {
            side: ContourSide::Outside,
            climb: true,
            top_z_mm: 0.0,
            bottom_z_mm: -5.0,
            step_down_mm: 2.0,
            allowance_mm: 0.0,
            lead_radius_mm: 2.0,
            tab_count: 0,
            tab_width_mm: 5.0,
            tab_height_mm: 1.0,
            ramp_angle_rad: 10f64.to_radians(),
            clearance_mm: 5.0,
            feed_mm_per_min: 1000.0,
            chord_tol_mm: 0.005,
        }
    }
}

fn move_to(tp: &mut Toolpath, kind: MoveKind, p: DVec3, feed: f64) {
    if tp.poses.last().is_some_and(|a| a.tip.distance(p) < 1e-9) {
        return;
    }
    let f = if kind == MoveKind::Rapid { 0.0 } else { feed };
    tp.push_pose(Pose::new(kind, p, DVec3::Z, f));
}

/// The part of element `e` from parameter `t0` to `t1` (fractions of its length), from the
/// current point, ending at height `z1`.
fn piece(
    tp: &mut Toolpath,
    e: &Element,
    t0: f64,
    t1: f64,
    z1: f64,
    feed: f64,
    chord: f64,
) -> Result<(), PlanarError> {
    match *e {
        Element::Line { .. } => {
            move_to(tp, MoveKind::Cut, e.point_at(t1).extend(z1), feed);
            Ok(())
        }
        Element::Arc {
            centre, sweep_rad, ..
        } => {
            let z0 = tp.poses.last().map_or(z1, |p| p.tip.z);
            tp.push_helix(
                centre.extend(z0),
                DVec3::Z,
                sweep_rad * (t1 - t0),
                z1 - z0,
                MoveKind::Cut,
                feed,
                chord,
            )
            .map_err(|e| PlanarError(e.to_string()))
        }
    }
}

/// One pass along a loop's elements, split at the tab breaks, at the heights `z_at` gives
/// along the arc length (rising straight up where it jumps up).
fn walk(
    tp: &mut Toolpath,
    els: &[Element],
    lengths: &[f64],
    breaks: &[f64],
    z_at: &dyn Fn(f64) -> f64,
    feed: f64,
    chord: f64,
) -> Result<(), PlanarError> {
    let mut pos = 0.0;
    for (e, &len) in els.iter().zip(lengths) {
        let mut cuts: Vec<f64> = breaks
            .iter()
            .copied()
            .filter(|b| *b > pos + 1e-9 && *b < pos + len - 1e-9)
            .collect();
        cuts.push(pos + len);
        let mut t0 = 0.0;
        for c in cuts {
            let t1 = ((c - pos) / len).clamp(0.0, 1.0);
            // Rise straight up at a tab's start.
            let z_here = z_at(pos + t0 * len + 1e-7);
            if let Some(cur) = tp.poses.last().map(|p| p.tip)
                && z_here > cur.z + 1e-9
            {
                move_to(tp, MoveKind::Link, cur.truncate().extend(z_here), feed);
            }
            let z_end = z_at(c);
            piece(tp, e, t0, t1, z_end, feed, chord)?;
            t0 = t1;
        }
        pos += len;
    }
    Ok(())
}

fn check(o: &ContourOptions) -> Result<(), PlanarError> {
    let nums = [
        o.top_z_mm,
        o.bottom_z_mm,
        o.step_down_mm,
        o.allowance_mm,
        o.lead_radius_mm,
        o.tab_width_mm,
        o.tab_height_mm,
        o.ramp_angle_rad,
        o.clearance_mm,
        o.feed_mm_per_min,
        o.chord_tol_mm,
    ];
    if nums.iter().any(|v| !v.is_finite()) {
        return Err(PlanarError(
            "contour: every option must be a finite number".into(),
        ));
    }
    if o.bottom_z_mm >= o.top_z_mm
        || o.step_down_mm <= 0.0
        || o.feed_mm_per_min <= 0.0
        || o.clearance_mm <= 0.0
    {
        return Err(PlanarError(
            "contour: the bottom must lie below the top; step-down, feed and clearance positive"
                .into(),
        ));
    }
    if o.allowance_mm < 0.0
        || o.lead_radius_mm < 0.0
        || o.tab_width_mm < 0.0
        || o.tab_height_mm < 0.0
    {
        return Err(PlanarError(
            "contour: allowance, lead radius and tab sizes must be non-negative".into(),
        ));
    }
    if o.tab_count > 0
        && !(o.ramp_angle_rad > 0.0 && o.ramp_angle_rad < std::f64::consts::FRAC_PI_2)
    {
        return Err(PlanarError(
            "contour: the ramp angle must lie in (0°, 90°)".into(),
        ));
    }
    Ok(())
}

/// A contour of `region`'s boundaries.
///
/// # Errors
/// Bad options, or no loop left after the offset.
pub fn contour(
    region: &Region,
    tool: &ToolRecord,
    o: &ContourOptions,
) -> Result<Toolpath, PlanarError> {
    check(o)?;
    let r = tool.cutter.radius();
    let d = r + o.allowance_mm;
    let path = match o.side {
        ContourSide::Outside => region.offset(-d),
        ContourSide::Inside => region.offset(d),
    };
    if path.is_empty() {
        return Err(PlanarError(format!(
            "contour: a tool of radius {r} mm fits no loop of the region"
        )));
    }
    let chord = o.chord_tol_mm.max(1e-4);
    let safe = o.top_z_mm + o.clearance_mm;
    let n = ((o.top_z_mm - o.bottom_z_mm) / o.step_down_mm - 1e-9)
        .ceil()
        .max(1.0) as usize;
    let depths: Vec<f64> = (1..=n)
        .map(|k| o.top_z_mm - (o.top_z_mm - o.bottom_z_mm) * k as f64 / n as f64)
        .collect();
    let tab_top = o.bottom_z_mm + o.tab_height_mm;
    let mut tp = Toolpath::new(tool.clone(), Vec::new());
    for boundary in path.boundaries() {
        // Direction: the material on the right for climb milling with M3. Outer boundaries
        // are counter-clockwise with the region on the left.
        let material_left = match o.side {
            ContourSide::Outside => true,
            ContourSide::Inside => false,
        };
        let reverse = material_left == o.climb;
        let l: Profile = if reverse {
            boundary.reversed()
        } else {
            boundary.clone()
        };
        let els = l.elements();
        let Some(first) = els.first() else { continue };
        let lengths: Vec<f64> = els.iter().map(Element::length).collect();
        let total: f64 = lengths.iter().sum();
        if total <= 1e-9 {
            continue;
        }
        let s = first.start();
        let t = first.tangent_at(0.0);
        // The free side: away from the material.
        let material = if o.climb { -t.perp() } else { t.perp() };
        let free = -material;
        // Tab spans (arc-length intervals) and the ramp after each.
        let span = o.tab_width_mm;
        let ramp_len = if o.tab_count > 0 {
            o.tab_height_mm.max(0.0) / o.ramp_angle_rad.tan()
        } else {
            0.0
        };
        let tabs: Vec<(f64, f64)> = (0..o.tab_count)
            .map(|k| {
                let c = total * (k as f64 + 0.5) / o.tab_count as f64;
                (c - 0.5 * span, c + 0.5 * span)
            })
            .collect();
        if o.tab_count > 0 && total / o.tab_count as f64 <= span + ramp_len {
            return Err(PlanarError(format!(
                "contour: {} tabs of {} mm and their ramps do not fit a loop of {total:.3} mm",
                o.tab_count, o.tab_width_mm
            )));
        }
        let z_at = |pos: f64, z: f64| -> f64 {
            if z >= tab_top {
                return z;
            }
            let mut zz = z;
            for &(a, b) in &tabs {
                if pos > a + 1e-9 && pos < b + 1e-9 {
                    zz = zz.max(tab_top);
                } else if pos >= b && pos < b + ramp_len {
                    zz = zz.max(tab_top - (pos - b) * o.ramp_angle_rad.tan());
                }
            }
            zz
        };
        let mut breaks: Vec<f64> = tabs
            .iter()
            .flat_map(|&(a, b)| [a, b, b + ramp_len])
            .collect();
        breaks.retain(|x| *x > 0.0 && *x < total);
        breaks.sort_by(f64::total_cmp);
        let lead = o.lead_radius_mm;
        let centre_in = s + free * lead;
        let p_in = centre_in - t * lead;
        for &z in &depths {
            let here = tp.poses.last().map(|p| p.tip);
            if let Some(h) = here {
                move_to(&mut tp, MoveKind::Rapid, h.truncate().extend(safe), 0.0);
            }
            let start_xy = if lead > 0.0 { p_in } else { s };
            move_to(&mut tp, MoveKind::Rapid, start_xy.extend(safe), 0.0);
            let z0 = z_at(0.0, z);
            move_to(
                &mut tp,
                MoveKind::Plunge,
                start_xy.extend(z0),
                o.feed_mm_per_min,
            );
            if lead > 0.0 {
                let sweep = std::f64::consts::FRAC_PI_2 * t.perp_dot(free).signum();
                tp.push_arc(
                    centre_in.extend(z0),
                    DVec3::Z,
                    sweep,
                    MoveKind::Cut,
                    o.feed_mm_per_min,
                    chord,
                )
                .map_err(|e| PlanarError(e.to_string()))?;
            }
            walk(
                &mut tp,
                &els,
                &lengths,
                &breaks,
                &|pos| z_at(pos, z),
                o.feed_mm_per_min,
                chord,
            )?;
            if lead > 0.0 {
                let end = tp.poses.last().map_or(s.extend(z), |p| p.tip);
                let centre_out = s + free * lead;
                let sweep = std::f64::consts::FRAC_PI_2 * t.perp_dot(free).signum();
                tp.push_arc(
                    centre_out.extend(end.z),
                    DVec3::Z,
                    sweep,
                    MoveKind::Cut,
                    o.feed_mm_per_min,
                    chord,
                )
                .map_err(|e| PlanarError(e.to_string()))?;
            }
        }
        if let Some(h) = tp.poses.last().map(|p| p.tip) {
            move_to(&mut tp, MoveKind::Rapid, h.truncate().extend(safe), 0.0);
        }
    }
    Ok(tp)
}
