//! The virtual control's AUTO as fast as possible (issue 36): a roughing program run by
//! `Control::advance_until_idle` cuts what the batch simulation cuts (removed volume within
//! 0.1 %), raises the rapid collision at the line the batch simulation reports it, takes the
//! cycle time the motion planner plans, and ends as the same program played in the
//! operator panel's frames at ×100 (with the cutting worker) ends: same stock, alarms and
//! time. Waiting on an idle control and dwells cost one clock step, however long.
//!
//! `cargo test --no-default-features --test control_fast`

use talas::control::{Action, Control, ControlConfig, LiveStock, Mode, codes};
use talas::diagnostics::Progress;
use talas::feed::{DEFAULT_CORNERS, PlanInput, PlanOptions, machine_limits, plan};
use talas::gcode::{InterpretOptions, Joints, interpret};
use talas::machine::Machine;
use talas::simulation::{
    DexelMode, DexelStock, SimOptions, StepOptions, StockShape, plan_program, simulate,
};
use talas::tools::parse_tool_spec;

const RES: f64 = 0.5;
const TOOL: &str = "flat:d=6";

/// A Z-level roughing of the box (0, 0, -6)–(60, 40, 0) with a 6 mm flat: two levels of
/// zig-zag passes along X, 2.4 mm apart, G0 between levels; a 2 s dwell after the first
/// level. With `crash`, a rapid down into the uncut material below the last level and across
/// it; returns the text and the line of that rapid across.
fn roughing(crash: bool) -> (String, usize) {
    let mut lines = vec![
        "G21 G90 G17 G94".to_string(),
        "G0 Z10".into(),
        "G0 X-4 Y0".into(),
        "S9000 M3".into(),
    ];
    for (level, z) in [-2.0, -4.0].into_iter().enumerate() {
        lines.push("G0 X-4 Y0".into());
        lines.push(format!("G1 Z{z} F600"));
        let mut y = 0.0;
        let mut right = true;
        while y <= 40.0 + 1e-9 {
            lines.push(format!("G1 Y{y:.3} F1500"));
            lines.push(format!("G1 X{} F1500", if right { 64 } else { -4 }));
            right = !right;
            y += 2.4;
        }
        lines.push("G0 Z10".into());
        if level == 0 {
            lines.push("G4 P2".into());
        }
    }
    let mut crash_line = 0;
    if crash {
        lines.push("G0 X30 Y-10".into());
        lines.push("G0 Z-5".into());
        lines.push("G0 Y50".into());
        crash_line = lines.len();
        lines.push("G0 Z10".into());
    }
    lines.push("M30".into());
    (lines.join("\n") + "\n", crash_line)
}

fn stock() -> DexelStock {
    DexelStock::new(
        vec![StockShape::Box {
            min: glam::DVec3::new(0.0, 0.0, -6.0),
            max: glam::DVec3::new(60.0, 40.0, 0.0),
        }],
        RES,
        DexelMode::Z,
        1 << 30,
    )
    .unwrap()
}

/// A homed mill with the stock, at (-4, 0, 10) in AUTO with `text` loaded.
fn loaded(text: &str) -> Control {
    let mut cfg = ControlConfig::new(Machine::builtin("mill-3axis").unwrap());
    cfg.home_feed_mm_per_min = 30000.0;
    cfg.stock = Some(LiveStock::new(stock(), parse_tool_spec(TOOL).unwrap(), RES));
    let mut c = Control::new(cfg).unwrap();
    c.apply(Action::Home).unwrap();
    c.advance_until_idle(600.0);
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    c.apply(Action::Mdi("G0 X-4 Y0 Z10".into())).unwrap();
    c.advance_until_idle(600.0);
    c.apply(Action::SetMode(Mode::Auto)).unwrap();
    c.apply(Action::LoadProgram {
        name: "rough.ngc".into(),
        text: text.into(),
    })
    .unwrap();
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    c
}

/// What one AUTO run gave.
struct Run {
    removed_mm3: f64,
    /// (code, line, simulated time) of each alarm.
    alarms: Vec<(u32, Option<usize>, f64)>,
    /// Seconds from cycle start to the end (to the frame that saw the control at rest, and the
    /// frame before it, for the framed run).
    end_s: (f64, f64),
    clock_steps: u64,
}

/// AUTO as fast as possible: `advance_until_idle`.
fn fast(text: &str) -> Run {
    let mut c = loaded(text);
    let (t0, n0) = (c.time_s(), c.clock_steps());
    c.apply(Action::CycleStart).unwrap();
    c.advance_until_idle(1e5);
    c.flush_cutting();
    let end = c.time_s() - t0;
    Run {
        removed_mm3: c.removed_mm3(),
        alarms: c.alarms().iter().map(|a| (a.code, a.line, a.t_s)).collect(),
        end_s: (end, end),
        clock_steps: c.clock_steps() - n0,
    }
}

/// AUTO as the operator panel plays it at ×100: frames of 1/60 s × 100 of simulated time,
/// the stock cut by the cutting worker (`worker`) or on this thread.
fn framed(text: &str, worker: bool) -> Run {
    let mut c = loaded(text);
    if worker {
        c.start_cutting_worker();
    }
    let t0 = c.time_s();
    c.apply(Action::CycleStart).unwrap();
    let frame = 100.0 / 60.0;
    let mut before = 0.0;
    for _ in 0..10_000 {
        if c.is_idle() {
            break;
        }
        before = c.time_s() - t0;
        c.advance(frame);
    }
    assert!(c.is_idle(), "the program ran past 10 000 frames");
    c.stop_cutting_worker();
    Run {
        removed_mm3: c.removed_mm3(),
        alarms: c.alarms().iter().map(|a| (a.code, a.line, a.t_s)).collect(),
        end_s: (before, c.time_s() - t0),
        clock_steps: c.clock_steps(),
    }
}

/// The batch simulation of the program (`talas simulate`'s engine, the live cutting's step
/// bounds): removed volume and the G-code lines of its collisions.
fn batch(text: &str) -> (f64, Vec<usize>) {
    let m = Machine::builtin("mill-3axis").unwrap();
    let cutter = parse_tool_spec(TOOL).unwrap();
    let prog = interpret(
        text,
        &InterpretOptions::starting_at(Joints::xyz(-4.0, 0.0, 10.0)),
    )
    .unwrap();
    let steps = StepOptions::for_resolution(RES, cutter.flute_length);
    let moves = plan_program(&prog, Some(&m), &steps).unwrap();
    let mut s = stock();
    let report = simulate(
        &mut s,
        &cutter,
        &moves,
        &SimOptions::default(),
        &Progress::new(),
    )
    .unwrap();
    let lines = report.collisions.iter().map(|c| c.block).collect();
    (report.removed_volume_mm3, lines)
}

/// The planned cycle time of the program from (-4, 0, 10) (motion plus dwells), s.
fn planned_s(text: &str) -> f64 {
    let m = Machine::builtin("mill-3axis").unwrap();
    let prog = interpret(
        text,
        &InterpretOptions::starting_at(Joints::xyz(-4.0, 0.0, 10.0)),
    )
    .unwrap();
    let dwell: f64 = prog.dwells.iter().map(|d| d.seconds).sum();
    plan(&PlanInput {
        blocks: prog.blocks.as_slice().into(),
        axes: machine_limits(&m),
        options: PlanOptions {
            corner: DEFAULT_CORNERS,
            ..PlanOptions::default()
        },
    })
    .unwrap()
    .cycle_time_s
        + dwell
}

#[test]
fn auto_as_fast_as_possible_cuts_what_the_batch_simulation_cuts_in_the_planned_time() {
    let (text, _) = roughing(false);
    let run = fast(&text);
    assert!(run.alarms.is_empty(), "{:?}", run.alarms);
    let (reference, collisions) = batch(&text);
    assert!(collisions.is_empty(), "{collisions:?}");
    // Two levels of 2 mm over most of the 60 × 40 box.
    assert!(reference > 6000.0, "the program cuts: {reference} mm³");
    let got = run.removed_mm3;
    assert!(
        ((got - reference) / reference).abs() < 1e-3,
        "AUTO removed {got} mm³, the batch simulation {reference} mm³"
    );
    // AUTO plans each stretch between dwells as `talas feed` plans the whole program; the
    // clock ends on the millisecond after the end.
    let want = planned_s(&text);
    assert!(want > 60.0, "{want} s");
    assert!(
        (run.end_s.0 - want).abs() < 0.01 * want,
        "AUTO took {} s, the plan {want} s",
        run.end_s.0
    );
    // One clock step per millisecond of motion, one for the dwell.
    let ms = run.end_s.0 / 1e-3;
    assert!(
        (run.clock_steps as f64) < ms + 100.0,
        "{} steps for {ms} ms",
        run.clock_steps
    );
}

#[test]
fn auto_as_fast_as_possible_ends_as_the_panel_clock_at_x100_does() {
    // The worker stops cutting at the piece that collided, the cutting on this thread cuts
    // the brake's motion too: the crash is compared with the panel's clock cutting here, and
    // its first alarm with the worker's.
    for crash in [false, true] {
        let (text, _) = roughing(crash);
        let (fast, framed) = (fast(&text), framed(&text, !crash));
        let (a, b) = (fast.removed_mm3, framed.removed_mm3);
        assert!(
            ((a - b) / a).abs() < 1e-6,
            "crash {crash}: fast {a} mm³, framed {b} mm³"
        );
        if crash {
            let worker = self::framed(&text, true);
            assert_eq!(
                worker.alarms.first().map(|a| (a.0, a.1)),
                fast.alarms.first().map(|a| (a.0, a.1))
            );
        }
        // The same alarms at the same lines; the first raised within a piece of cutting (20 ms
        // of motion) of the other's (the brake through the material raises one per piece).
        let lines = |r: &Run| {
            let mut v: Vec<_> = r.alarms.iter().map(|a| (a.0, a.1)).collect();
            v.dedup();
            v
        };
        assert_eq!(lines(&fast), lines(&framed), "crash {crash}");
        assert_eq!(crash, !fast.alarms.is_empty());
        if let (Some(x), Some(y)) = (fast.alarms.first(), framed.alarms.first()) {
            assert!((x.2 - y.2).abs() < 0.025, "{x:?} vs {y:?}");
        }
        let (end, (lo, hi)) = (fast.end_s.0, framed.end_s);
        assert!(
            end > lo - 0.025 && end <= hi + 1e-9,
            "crash {crash}: fast ended at {end} s, framed between {lo} and {hi} s"
        );
    }
}

#[test]
fn the_rapid_collision_is_raised_at_the_line_the_batch_simulation_reports() {
    let (text, crash_line) = roughing(true);
    let run = fast(&text);
    let (_, collisions) = batch(&text);
    assert_eq!(collisions.first(), Some(&crash_line), "{collisions:?}");
    // One alarm per 20 ms piece of the rapid (and of the brake) in the material.
    assert!(!run.alarms.is_empty());
    for a in &run.alarms {
        assert_eq!(
            (a.0, a.1),
            (codes::COLLISION_RAPID, Some(crash_line)),
            "{a:?}"
        );
    }
    // The machine stopped there: the program's last lines never ran.
    assert!(run.end_s.0 < planned_s(&text));
}

#[test]
fn waiting_on_an_idle_control_and_dwells_cost_one_clock_step() {
    let mut c = Control::new(ControlConfig::new(Machine::builtin("mill-3axis").unwrap())).unwrap();
    c.apply(Action::Home).unwrap();
    c.advance_until_idle(600.0);
    assert!(c.is_idle());
    let (t0, n0) = (c.time_s(), c.clock_steps());
    c.advance(100_000.0);
    assert!((c.time_s() - t0 - 100_000.0).abs() < 1e-6);
    assert!(c.clock_steps() - n0 <= 1, "{} steps", c.clock_steps() - n0);
    // A 1000 s dwell in MDI, as fast as possible and in one long frame.
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    for long_frame in [false, true] {
        let (t0, n0) = (c.time_s(), c.clock_steps());
        c.apply(Action::Mdi("G4 P1000".into())).unwrap();
        if long_frame {
            c.advance(2000.0);
        } else {
            c.advance_until_idle(2000.0);
        }
        assert!(c.is_idle());
        let (dt, n) = (c.time_s() - t0, c.clock_steps() - n0);
        assert!(dt >= 1000.0 - 1e-9, "{dt} s");
        assert!(
            n <= 3,
            "long frame {long_frame}: {n} steps for a 1000 s dwell"
        );
    }
}
