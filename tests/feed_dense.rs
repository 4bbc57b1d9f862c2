//! Dense CAM output keeps its feed (issue 35): a circle of R50 cut as 1 000, 10 000 and
//! 100 000 straight blocks plans within 2 % of the exact circle's time under the machine's
//! limits (closed form: the feed, capped by `sqrt(A·R)`, with jerk-limited start and stop
//! ramps), for every corner mode that keeps a tolerance; the time does not grow with the block
//! count; the path stays within the tolerance of the circle; and (blends) every axis keeps its
//! limits by finite differences of the sampled positions.
//!
//! `cargo test --no-default-features --test feed_dense`

use std::f64::consts::TAU;

use talas::feed::{CornerPolicy, PlanInput, PlanOptions, machine_limits, plan};
use talas::gcode::{InterpretOptions, Joints, interpret};
use talas::machine::Machine;

const R: f64 = 50.0;

/// The circle of radius `R` about the origin from (R, 0, 0), counter-clockwise, in `n` lines.
fn circle(n: usize, feed: f64) -> String {
    let mut text = format!("G21 G90 G17 G94\nG1 F{feed}\n");
    for i in 1..=n {
        let a = TAU * i as f64 / n as f64;
        text += &format!("X{:.6} Y{:.6}\n", R * a.cos(), R * a.sin());
    }
    text
}

/// Time of a jerk-limited velocity change by `dv` (a = 0 at both ends) under `a`, `j`.
fn change_time(dv: f64, a: f64, j: f64) -> f64 {
    if dv * j >= a * a {
        dv / a + a / j
    } else {
        2.0 * (dv / j).sqrt()
    }
}

/// The exact circle's time from rest to rest at `feed` (mm/min): cruise at
/// `v = min(F, sqrt(A·R))`, one ramp up and one down along Y (the tangent at the start and the
/// end) under Y's acceleration and jerk; the ramps cost `change_time(v)` more than cruising.
fn closed_form(feed: f64, a: f64, j: f64) -> f64 {
    let v = (feed / 60.0).min((a * R).sqrt());
    TAU * R / v + change_time(v, a, j)
}

fn plan_circle(n: usize, feed: f64, corner: CornerPolicy) -> (talas::feed::TimedPath, f64) {
    let machine = Machine::builtin("mill-3axis").unwrap();
    let opts = InterpretOptions {
        start: Joints::xyz(R, 0.0, 0.0),
        ..InterpretOptions::default()
    };
    let prog = interpret(&circle(n, feed), &opts).unwrap();
    let input = PlanInput {
        blocks: prog.blocks.as_slice().into(),
        axes: machine_limits(&machine),
        options: PlanOptions {
            corner,
            ..PlanOptions::default()
        },
    };
    let started = std::time::Instant::now();
    let tp = plan(&input).unwrap();
    (tp, started.elapsed().as_secs_f64())
}

#[test]
fn dense_circles_plan_at_the_exact_circles_time() {
    let machine = Machine::builtin("mill-3axis").unwrap();
    let y = machine.axis('Y').unwrap();
    let feed = 2000.0;
    let want = closed_form(feed, y.acceleration, y.jerk);
    for corner in [
        CornerPolicy::Blend { tolerance_mm: 0.05 },
        CornerPolicy::Blend { tolerance_mm: 0.01 },
        CornerPolicy::JunctionDeviation { tolerance_mm: 0.05 },
    ] {
        let mut times = Vec::new();
        for n in [1000, 10_000, 100_000] {
            let (tp, wall) = plan_circle(n, feed, corner);
            let t = tp.cycle_time_s;
            eprintln!(
                "{corner:?}, {n} blocks: {t:.4} s planned ({} segments, {wall:.2} s to plan), \
                 exact circle {want:.4} s",
                tp.block_count()
            );
            assert!(
                (t - want).abs() <= 0.02 * want,
                "{corner:?}, {n} blocks: {t} s against the exact circle's {want} s"
            );
            // Within the tolerance (and the polygon's own sagitta) of the circle.
            let tol = match corner {
                CornerPolicy::Blend { tolerance_mm }
                | CornerPolicy::JunctionDeviation { tolerance_mm } => tolerance_mm,
                CornerPolicy::ExactStop => 0.0,
            };
            let chord = TAU * R / n as f64;
            let sagitta = chord * chord / (8.0 * R);
            let worst = tp
                .samples()
                .map(|s| ((s.position[0].hypot(s.position[1])) - R).abs())
                .fold(0.0, f64::max);
            assert!(
                worst <= tol + sagitta + 1e-9,
                "{corner:?}, {n} blocks: {worst} mm off the circle"
            );
            times.push(t);
        }
        // The time does not grow with the block count.
        assert!(
            times[2] <= times[0] * 1.01,
            "{corner:?}: {times:?} s for 1 000, 10 000, 100 000 blocks"
        );
    }
}

/// Fast enough that the curvature matters (500 mm/s on R50): the plan is never faster than
/// the exact circle allows (`sqrt(A·R)`), and every axis keeps its velocity, acceleration and
/// jerk limits by finite differences (0.1 ms) of the sampled positions, with 10 000 blocks.
#[test]
fn dense_circles_keep_every_axis_limit() {
    let machine = Machine::builtin("mill-3axis").unwrap();
    let axes = machine_limits(&machine);
    let y = machine.axis('Y').unwrap();
    for feed in [2000.0, 30_000.0] {
        let (tp, _) = plan_circle(10_000, feed, CornerPolicy::Blend { tolerance_mm: 0.05 });
        let fastest = closed_form(feed, y.acceleration, y.jerk);
        eprintln!(
            "F{feed}: {:.4} s planned, exact circle {fastest:.4} s",
            tp.cycle_time_s
        );
        // (The merged lines are chords, a little shorter than the arc: 0.5 % at most here.)
        assert!(tp.cycle_time_s >= fastest * 0.995);
        let h = 1e-4;
        let steps = (tp.cycle_time_s / h).ceil() as usize;
        let pos: Vec<_> = (0..steps + 5)
            .map(|i| tp.state_at((i as f64 - 2.0) * h).position)
            .collect();
        let mut worst = [0.0f64; 3];
        for i in 2..steps + 3 {
            for (k, (_, l)) in axes.iter().enumerate() {
                let q = |j: usize| pos[j][k];
                let v = (q(i + 1) - q(i - 1)) / (2.0 * h);
                let a = (q(i + 1) - 2.0 * q(i) + q(i - 1)) / (h * h);
                let j = (q(i + 2) - 2.0 * q(i + 1) + 2.0 * q(i - 1) - q(i - 2)) / (2.0 * h * h * h);
                let r = [
                    v.abs() / l.velocity,
                    a.abs() / l.acceleration,
                    j.abs() / l.jerk,
                ];
                for (w, x) in worst.iter_mut().zip(r) {
                    *w = w.max(x);
                }
            }
        }
        eprintln!("F{feed}: worst v/a/j ratios {worst:?}");
        assert!(worst.iter().all(|r| *r <= 1.001), "F{feed}: {worst:?}");
    }
}

/// A posted 5-axis program (trt-ac, iso-scallop on `bicubic-hills.stp` at 0.5 mm scallop with a
/// 6 mm ball, G93 inverse time with A/C moves in nearly every block; the first 3 000 lines of
/// `talas plan … --strategy iso-scallop --machine trt-ac` then `talas post --machine trt-ac`):
/// the default blends keep its planned time within 1.5× of its time at the programmed feeds
/// (it stopped at nearly every block: 4.5×), and every axis, A and C included, keeps its
/// limits over the samples.
#[test]
fn posted_five_axis_program_keeps_its_feed() {
    use talas::feed::{DEFAULT_CORNERS, naive_time_s};
    use talas::gcode::Syntax;
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/fivex/trt-ac-iso-scallop.ngc"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let prog = interpret(&text, &InterpretOptions::for_syntax(Syntax::detect(&text))).unwrap();
    assert!(prog.blocks.iter().filter(|b| b.inverse_time).count() > 2000);
    let machine = Machine::builtin("trt-ac").unwrap();
    let axes = machine_limits(&machine);
    let at_feed = naive_time_s(&prog.blocks);
    for corner in [
        DEFAULT_CORNERS,
        CornerPolicy::JunctionDeviation { tolerance_mm: 0.05 },
    ] {
        let tp = plan(&PlanInput {
            blocks: prog.blocks.as_slice().into(),
            axes: axes.clone(),
            options: PlanOptions {
                corner,
                ..PlanOptions::default()
            },
        })
        .unwrap();
        let t = tp.cycle_time_s;
        eprintln!(
            "{corner:?}: {t:.2} s planned, {at_feed:.2} s at the programmed feeds ({:.3}×)",
            t / at_feed
        );
        assert!(
            t <= 1.5 * at_feed,
            "{corner:?}: {t} s against {at_feed} s at feed"
        );
        for (peak, (name, lim)) in tp.peaks().iter().zip(&axes) {
            assert_eq!(peak.axis, *name);
            assert!(
                peak.velocity <= lim.velocity * 1.001
                    && peak.acceleration <= lim.acceleration * 1.001
                    && peak.jerk <= lim.jerk * 1.001,
                "{corner:?}: axis {name} peaks {peak:?} beyond {lim:?}"
            );
        }
    }
}
