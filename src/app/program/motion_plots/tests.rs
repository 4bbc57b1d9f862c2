use super::*;
use crate::feed::{PlanInput, PlanOptions, machine_limits, plan};
use crate::gcode::{InterpretOptions, interpret};
use crate::machine::Machine;
use egui_plot::PlotPoint;

/// A 5-axis program planned on the A/C trunnion: linear moves, a move with A and C, an arc.
fn planned() -> TimedPath {
    let machine = Machine::builtin("trt-ac").unwrap();
    let text = "G21 G90 G17 G94\nG1 X0 Y0 Z10 A0 C0 F3000\nG1 X40 F6000\nG1 Y30 A-20 C45 F2000\n\
                G2 X60 Y10 I10 J-10 F2400\nG1 Z0\n";
    let prog = interpret(text, &InterpretOptions::default()).unwrap();
    plan(&PlanInput {
        blocks: prog.blocks.as_slice().into(),
        axes: machine_limits(&machine),
        options: PlanOptions::default(),
    })
    .unwrap()
}

fn max_abs(points: &[PlotPoint]) -> f64 {
    points.iter().fold(0.0, |m, p| m.max(p.y.abs()))
}

/// The decimated curves keep the planner's own peaks exactly (brute force over every sample
/// in `TimedPath::peaks`), in degrees for the rotary axes, and the limits are converted alike.
#[test]
fn curves_keep_the_peaks_in_display_units() {
    let tp = planned();
    let plots = MotionPlots::new(&tp);
    assert_eq!(plots.sample_count, tp.samples().count());
    let peaks = tp.peaks();
    assert_eq!(plots.axes.len(), peaks.len());
    let deg = 180.0 / std::f64::consts::PI;
    for (a, p) in plots.axes.iter().zip(&peaks) {
        assert_eq!(a.axis, p.axis);
        let scale = if a.rotary { deg } else { 1.0 };
        assert_eq!(a.rotary, "ABC".contains(a.axis));
        for (q, peak) in [
            (Quantity::Velocity, p.velocity),
            (Quantity::Acceleration, p.acceleration),
            (Quantity::Jerk, p.jerk),
        ] {
            let curve = a.curve(q).unwrap();
            let got = max_abs(&curve.by_time);
            assert!((max_abs(&curve.by_path) - got).abs() < f64::EPSILON);
            assert!(
                (got - peak * scale).abs() <= 1e-9 * (1.0 + peak * scale),
                "{} {q:?}: {got} vs {}",
                a.axis,
                peak * scale
            );
            assert!(curve.by_time.len() <= MAX_POINTS);
        }
        let (_, limit) = tp.axes.iter().find(|(c, _)| *c == a.axis).unwrap();
        assert!((a.limit.velocity - limit.velocity * scale).abs() < 1e-9 * a.limit.velocity);
    }
    let peak_feed = tp.samples().fold(0.0f64, |m, s| m.max(s.feed));
    assert!((max_abs(&plots.feed.by_time) - peak_feed).abs() < 1e-12);
    assert_eq!(
        plots.feed.by_time.last().map(|p| p.x),
        Some(tp.cycle_time_s),
        "the curves run to the cycle time"
    );
    // The plan can only be slower than the program at its programmed feeds.
    assert!(plots.naive_time_s > 0.0 && plots.cycle_time_s > plots.naive_time_s);
    assert!(
        plots.summary().contains("cycle time"),
        "{}",
        plots.summary()
    );
}

/// Path length against time: the curves' path positions are the plan's own (state_at), and
/// time → path → time comes back (the path grows strictly while the tool moves).
#[test]
fn path_length_axis_matches_the_plan() {
    let tp = planned();
    let plots = MotionPlots::new(&tp);
    for p in plots
        .feed
        .by_time
        .iter()
        .zip(&plots.feed.by_path)
        .step_by(97)
    {
        let s = tp.state_at(p.0.x).path_position;
        assert!((p.1.x - s).abs() < 1e-9, "t {}: {} vs {s}", p.0.x, p.1.x);
    }
    let total: f64 = tp
        .blocks()
        .iter()
        .map(crate::gcode::MotionBlock::length_mm)
        .sum();
    assert!((plots.path_at_time(tp.cycle_time_s) - total).abs() < 1e-6);
    for t in [0.3, 1.1, 2.0, 2.9] {
        let s = plots.path_at_time(t);
        let exact = tp.state_at(t).path_position;
        // Linear interpolation between decimated points (spacing ≤ the sample period here).
        assert!((s - exact).abs() < 1e-3, "t {t}: {s} vs {exact}");
        assert!((plots.time_at_path(s) - t).abs() < 2e-3, "t {t}");
    }
}

#[test]
fn interpolation_through_a_monotone_table() {
    let from = [
        PlotPoint::new(0.0, 0.0),
        PlotPoint::new(1.0, 0.0),
        PlotPoint::new(3.0, 0.0),
    ];
    let to = [
        PlotPoint::new(10.0, 0.0),
        PlotPoint::new(20.0, 0.0),
        PlotPoint::new(60.0, 0.0),
    ];
    assert!((interpolate_x(&from, &to, 2.0) - 40.0).abs() < 1e-12);
    assert!((interpolate_x(&from, &to, 0.5) - 15.0).abs() < 1e-12);
    assert!((interpolate_x(&from, &to, -1.0) - 10.0).abs() < 1e-12);
    assert!((interpolate_x(&from, &to, 9.0) - 60.0).abs() < 1e-12);
    assert!((interpolate_x(&[], &[], 9.0) - 9.0).abs() < 1e-12);
}

#[test]
fn grid_steps_are_1_2_5_and_divide_each_other() {
    let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9 * y);
    assert!(close(grid_steps(0.7), [1.0, 5.0, 10.0]));
    assert!(close(grid_steps(130.0), [200.0, 1000.0, 2000.0]));
    assert!(close(grid_steps(3.2e3), [5e3, 1e4, 5e4]));
    assert!(close(grid_steps(7.0), [10.0, 50.0, 100.0]));
    for base in [1e-4, 0.03, 2.5, 999.0, 1.2e6] {
        let [a, b, c] = grid_steps(base);
        assert!(a >= base * (1.0 - 1e-12) && a <= 2.5 * base, "{base}: {a}");
        for (x, y) in [(a, b), (b, c)] {
            let r = y / x;
            assert!((r - r.round()).abs() < 1e-9, "{base}: {y} / {x}");
        }
    }
}

#[test]
fn units_per_quantity_and_axis_kind() {
    assert_eq!(Quantity::Velocity.unit(false), "mm/s");
    assert_eq!(Quantity::Acceleration.unit(true), "deg/s²");
    assert_eq!(Quantity::Jerk.unit(false), "mm/s³");
    assert_eq!(duration_text(12.3456), "12.346 s");
    assert_eq!(duration_text(245.2), "4 min 05.2 s");
    assert_eq!(duration_text(3725.0), "1 h 02 min");
}

/// Headless: every quantity draws, and a click in the plot reports a time inside the program.
#[test]
fn clicking_a_plot_reports_its_time() {
    struct State {
        plots: MotionPlots,
        events: Vec<PlotEvent>,
    }
    let tp = planned();
    let mut plots = MotionPlots::new(&tp);
    plots.set_cursor_time(Some(0.5 * tp.cycle_time_s));
    let mut h = egui_kittest::Harness::builder()
        .with_size(egui::vec2(800.0, 500.0))
        .build_ui_state(
            |ui, s: &mut State| {
                if let Some(e) = s.plots.ui(ui) {
                    s.events.push(e);
                }
            },
            State {
                plots,
                events: Vec::new(),
            },
        );
    for x in [XAxis::PathLength, XAxis::Time] {
        h.state_mut().plots.set_x_axis(x);
        for q in Quantity::ALL {
            h.state_mut().plots.set_quantity(q);
            h.run_steps(2);
        }
    }
    h.state_mut().plots.set_quantity(Quantity::Feed);
    h.run_steps(2);
    let pos = egui::pos2(450.0, 300.0);
    h.hover_at(pos);
    h.step();
    h.drag_at(pos);
    h.step();
    h.drop_at(pos);
    h.run_steps(2);
    let Some(t) = h.state().events.iter().rev().find_map(|e| match e {
        PlotEvent::TimeClicked(t) => Some(*t),
        PlotEvent::TimeHovered(_) => None,
    }) else {
        panic!("no click event");
    };
    // Hovering reports the time under the pointer too.
    assert!(
        h.state()
            .events
            .iter()
            .any(|e| matches!(e, PlotEvent::TimeHovered(_)))
    );
    assert!(t > 0.0 && t < tp.cycle_time_s, "{t} of {}", tp.cycle_time_s);
    assert_eq!(h.state().plots.cursor_time(), Some(0.5 * tp.cycle_time_s));
}
