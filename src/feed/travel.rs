//! Travel limits: where a program's motion leaves a machine's axis travel.
//!
//! Straight moves (G0, G1) interpolate the joints linearly, so their extremes are at their ends;
//! arcs are checked at their ends and every 1/64 of a quarter turn (a peak between two checks is
//! missed by at most r·(1 − cos(π/128)) ≈ 3·10⁻⁴·r). Blocks under tool-centre-point control
//! carry the tool tip, not the joints, in X Y Z, so only their rotary axes are checked.

use crate::gcode::{Joints, MotionBlock};
use crate::machine::Machine;

/// One axis leaving its travel in one block.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TravelViolation {
    /// 1-based line of the block in the program.
    pub line: usize,
    /// Axis letter.
    pub axis: char,
    /// The farthest value reached beyond the limit (mm, or degrees for rotary axes).
    pub value: f64,
    /// The limit it passes (mm or degrees).
    pub limit: f64,
}

/// Every block whose motion leaves the machine's travel, one entry per block and axis (at most
/// `max_reports`; the count of all is returned beside them).
#[must_use]
pub fn travel_violations(
    blocks: &[MotionBlock],
    machine: &Machine,
    max_reports: usize,
) -> (Vec<TravelViolation>, usize) {
    let mut out = Vec::new();
    let mut count = 0usize;
    for b in blocks {
        let points = block_extremes(b);
        for axis in &machine.axes {
            if b.tcp && !axis.is_rotary() {
                continue;
            }
            // The farthest excursion beyond either limit: (value, limit, distance beyond).
            let worst = points
                .iter()
                .filter_map(|p| coordinate(p, axis.name))
                .filter_map(|v| {
                    if v < axis.min - 1e-9 {
                        Some((v, axis.min, axis.min - v))
                    } else if v > axis.max + 1e-9 {
                        Some((v, axis.max, v - axis.max))
                    } else {
                        None
                    }
                })
                .max_by(|a, b| a.2.total_cmp(&b.2));
            let Some((value, limit, _)) = worst else {
                continue;
            };
            count += 1;
            if out.len() < max_reports {
                let scale = if axis.is_rotary() {
                    180.0 / std::f64::consts::PI
                } else {
                    1.0
                };
                out.push(TravelViolation {
                    line: b.source_line,
                    axis: axis.name,
                    value: value * scale,
                    limit: limit * scale,
                });
            }
        }
    }
    (out, count)
}

/// The positions where a block's coordinates reach their extremes.
fn block_extremes(b: &MotionBlock) -> Vec<Joints> {
    let mut points = vec![b.start, b.end];
    if let Some(arc) = b.kind.arc() {
        let steps = ((arc.sweep_rad / (std::f64::consts::FRAC_PI_2 / 64.0)).ceil() as usize)
            .clamp(4, 16_384);
        for k in 1..steps {
            points.push(b.point_at(k as f64 / steps as f64));
        }
    }
    points
}

fn coordinate(j: &Joints, axis: char) -> Option<f64> {
    match axis {
        'X' => Some(j.xyz.x),
        'Y' => Some(j.xyz.y),
        'Z' => Some(j.xyz.z),
        'A' => j.a,
        'B' => j.b,
        'C' => j.c,
        _ => None,
    }
}
