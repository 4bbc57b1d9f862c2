//! The naive cycle-time estimate a shop makes from the program alone: every block at its
//! programmed feed, with no acceleration. The planned [`super::TimedPath::cycle_time_s`] is
//! compared with it.

use crate::gcode::MotionBlock;

/// The time of `blocks` at their programmed feeds, s: length / feed for G94 blocks (rapids at
/// the interpreter's rapid rate), the programmed 1/F minutes for inverse-time (G93) blocks;
/// blocks without a feed count zero.
#[must_use]
pub fn naive_time_s(blocks: &[MotionBlock]) -> f64 {
    blocks
        .iter()
        .map(|b| match b.inverse_time_duration_s() {
            Some(t) => t,
            None if b.inverse_time => 0.0,
            None if b.feed_mm_per_min > 0.0 && b.feed_mm_per_min.is_finite() => {
                b.length_mm() / (b.feed_mm_per_min / 60.0)
            }
            None => 0.0,
        })
        .filter(|t| t.is_finite())
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gcode::{InterpretOptions, interpret};

    #[test]
    fn lines_arcs_and_inverse_time_at_their_feeds() {
        // 30 mm at 600 mm/min = 3 s; a half circle of radius 10 (31.4159 mm) at 1200 mm/min
        // = 1.5708 s; a G93 block F2 = 0.5 min = 30 s; a rapid of 10 mm at the rapid rate.
        let opts = InterpretOptions::default();
        let rapid = opts.rapid_mm_per_min;
        let program = interpret(
            "G21 G90 G17 G94\nG0 X10\nG1 X40 F600\nG3 X60 Y0 I10 J0 F1200\nG93 G1 Y5 F2\n",
            &opts,
        )
        .unwrap();
        let expected = 10.0 / (rapid / 60.0) + 3.0 + std::f64::consts::PI * 10.0 / 20.0 + 30.0;
        let t = naive_time_s(&program.blocks);
        assert!((t - expected).abs() < 1e-9, "{t} vs {expected}");
        assert!(naive_time_s(&[]).abs() < f64::EPSILON);
    }
}
