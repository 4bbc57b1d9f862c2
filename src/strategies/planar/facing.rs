//! Facing: zig-zag or one-way passes along x over a region's bounding box, from the stock top
//! down to the face height in levels (the last one the finishing depth), the tool running past
//! the box by the over-run on both ends and on the sides, so the whole top is cut.

use glam::DVec3;

use super::PlanarError;
use crate::geometry::planar::Region;
use crate::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};

/// Options of [`facing`].
#[derive(Clone, Debug, PartialEq)]
pub struct FacingOptions {
    /// Height of the stock top, mm.
    pub stock_top_z_mm: f64,
    /// Height to face down to, mm.
    pub face_z_mm: f64,
    /// Largest depth of a roughing level, mm.
    pub step_down_mm: f64,
    /// Depth of the last (finishing) level, mm (0: none of its own).
    pub finish_depth_mm: f64,
    /// Step-over as a fraction of the tool diameter (0, 1].
    pub stepover_frac: f64,
    /// How far the tool centre runs past the region's box, beyond the tool radius, mm.
    pub overrun_mm: f64,
    /// Zig-zag (else one-way, rapid back above the stock between passes).
    pub zigzag: bool,
    /// Safe height above the stock top, mm.
    pub clearance_mm: f64,
    /// Feed, mm/min.
    pub feed_mm_per_min: f64,
}

impl Default for FacingOptions {
    fn default() -> Self {
        Self {
            stock_top_z_mm: 1.0,
            face_z_mm: 0.0,
            step_down_mm: 1.0,
            finish_depth_mm: 0.2,
            stepover_frac: 0.7,
            overrun_mm: 2.0,
            zigzag: true,
            clearance_mm: 5.0,
            feed_mm_per_min: 1000.0,
        }
    }
}

/// Facing passes over `region`'s bounding box.
///
/// # Errors
/// Bad options or an empty region.
pub fn facing(
    region: &Region,
    tool: &ToolRecord,
    o: &FacingOptions,
) -> Result<Toolpath, PlanarError> {
    let nums = [
        o.stock_top_z_mm,
        o.face_z_mm,
        o.step_down_mm,
        o.finish_depth_mm,
        o.stepover_frac,
        o.overrun_mm,
        o.clearance_mm,
        o.feed_mm_per_min,
    ];
    if nums.iter().any(|v| !v.is_finite()) {
        return Err(PlanarError(
            "facing: every option must be a finite number".into(),
        ));
    }
    if o.face_z_mm > o.stock_top_z_mm
        || o.step_down_mm <= 0.0
        || o.finish_depth_mm < 0.0
        || !(o.stepover_frac > 0.0 && o.stepover_frac <= 1.0)
        || o.overrun_mm < 0.0
        || o.clearance_mm <= 0.0
        || o.feed_mm_per_min <= 0.0
    {
        return Err(PlanarError(
            "facing: face height at most the stock top; step-down, clearance, feed positive; step-over in (0, 1]".into(),
        ));
    }
    let (lo, hi) = region.bounds();
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(PlanarError("facing: the region is empty".into()));
    }
    let r = tool.cutter.radius();
    let step = o.stepover_frac * 2.0 * r;
    let safe = o.stock_top_z_mm + o.clearance_mm;
    // Levels: roughing to face + finish depth, then the face.
    let depth = o.stock_top_z_mm - o.face_z_mm;
    let rough = (depth - o.finish_depth_mm).max(0.0);
    let n = if rough > 1e-9 {
        (rough / o.step_down_mm - 1e-9).ceil() as usize
    } else {
        0
    };
    let mut levels: Vec<f64> = (1..=n)
        .map(|k| o.stock_top_z_mm - rough * k as f64 / n as f64)
        .collect();
    if levels.last().is_none_or(|z| (z - o.face_z_mm).abs() > 1e-9) {
        levels.push(o.face_z_mm);
    }
    // Passes along x; the tool's edge reaches `overrun` past the box on every side.
    let x0 = lo.x - r - o.overrun_mm;
    let x1 = hi.x + r + o.overrun_mm;
    let y_first = lo.y - o.overrun_mm + r * (1.0 - o.stepover_frac).max(0.0);
    let y_last = hi.y + o.overrun_mm - r * (1.0 - o.stepover_frac).max(0.0);
    let passes = (((y_last - y_first) / step).max(0.0) - 1e-9).ceil() as usize + 1;
    let ys: Vec<f64> = (0..passes)
        .map(|k| {
            if passes == 1 {
                0.5 * (y_first + y_last)
            } else {
                y_first + (y_last - y_first) * k as f64 / (passes - 1) as f64
            }
        })
        .collect();
    let mut poses = Vec::new();
    let mut push = |kind: MoveKind, p: DVec3| {
        let f = if kind == MoveKind::Rapid {
            0.0
        } else {
            o.feed_mm_per_min
        };
        poses.push(Pose::new(kind, p, DVec3::Z, f));
    };
    for &z in &levels {
        for (k, &y) in ys.iter().enumerate() {
            let forward = !o.zigzag || k % 2 == 0;
            let (xa, xb) = if forward { (x0, x1) } else { (x1, x0) };
            if k == 0 || !o.zigzag {
                // Start off the stock, above it, then down beside it.
                push(MoveKind::Rapid, DVec3::new(xa, y, safe));
                push(MoveKind::Plunge, DVec3::new(xa, y, z));
            } else {
                // Step over beside the stock, at the level.
                push(MoveKind::Link, DVec3::new(xa, y, z));
            }
            push(MoveKind::Cut, DVec3::new(xb, y, z));
            if !o.zigzag || k + 1 == ys.len() {
                push(MoveKind::Rapid, DVec3::new(xb, y, safe));
            }
        }
    }
    Ok(Toolpath::new(tool.clone(), poses))
}
