//! The virtual control driven as a panel would: homing, jogs, MPG, MDI, AUTO with live
//! cutting, feed hold, overrides. Every test that moves records the machine position every
//! millisecond and checks velocity, acceleration and jerk (finite differences of the recorded
//! positions, independent of the planner's own derivatives) and the travel against the
//! machine file's limits.

use glam::DVec3;
use talas::control::{
    Action, Control, ControlConfig, CutPiece, LiveStock, Mode, OverrideKind, RunState, codes,
    sub_block,
};
use talas::diagnostics::Progress;
use talas::feed::{PlanInput, PlanOptions, machine_limits, plan};
use talas::gcode::{InterpretOptions, Joints, interpret};
use talas::machine::Machine;
use talas::simulation::{
    DexelMode, DexelStock, SimOptions, StepOptions, StockShape, plan_program, simulate,
};
use talas::tools::parse_tool_spec;

const H: f64 = 1e-3;

/// Positions (mm, deg) recorded every millisecond.
struct Recorder {
    samples: Vec<Vec<f64>>,
}

impl Recorder {
    fn new(c: &Control) -> Self {
        Self {
            samples: vec![c.snapshot().machine_position],
        }
    }

    fn step(&mut self, c: &mut Control, seconds: f64) {
        let n = (seconds / H).round() as usize;
        for _ in 0..n {
            c.advance(H);
            self.samples.push(c.snapshot().machine_position);
        }
    }

    /// Step until the control is idle (at most `max_s`).
    fn until_idle(&mut self, c: &mut Control, max_s: f64) {
        let n = (max_s / H) as usize;
        for _ in 0..n {
            if c.is_idle() {
                return;
            }
            c.advance(H);
            self.samples.push(c.snapshot().machine_position);
        }
        panic!("the control did not come to rest within {max_s} s");
    }

    /// Every axis's finite-difference velocity, acceleration and jerk stay within the
    /// machine's limits (+0.1 %), positions within the travel.
    fn check_limits(&self, m: &Machine) {
        let s = &self.samples;
        for (i, ax) in m.axes.iter().enumerate() {
            let unit = if ax.is_rotary() {
                180.0 / std::f64::consts::PI
            } else {
                1.0
            };
            let (v, a, j) = (ax.velocity * unit, ax.acceleration * unit, ax.jerk * unit);
            let (lo, hi) = (ax.min * unit, ax.max * unit);
            let x: Vec<f64> = s.iter().map(|p| p[i]).collect();
            let (mut pv, mut pa, mut pj) = (0.0f64, 0.0f64, 0.0f64);
            for k in 0..x.len() {
                assert!(
                    x[k] >= lo - 1e-9 && x[k] <= hi + 1e-9,
                    "axis {} at {} outside [{lo}, {hi}]",
                    ax.name,
                    x[k]
                );
                if k >= 1 {
                    pv = pv.max(((x[k] - x[k - 1]) / H).abs());
                }
                if k >= 2 {
                    pa = pa.max(((x[k] - 2.0 * x[k - 1] + x[k - 2]) / (H * H)).abs());
                }
                if k >= 3 {
                    let d3 = x[k] - 3.0 * x[k - 1] + 3.0 * x[k - 2] - x[k - 3];
                    pj = pj.max((d3 / (H * H * H)).abs());
                }
            }
            // The third difference of values near 500 carries ~1e-13/1e-9 = 1e-4 of rounding.
            assert!(pv <= v * 1.001, "axis {}: velocity {pv} > {v}", ax.name);
            assert!(pa <= a * 1.001, "axis {}: acceleration {pa} > {a}", ax.name);
            assert!(pj <= j * 1.001 + 1e-3, "axis {}: jerk {pj} > {j}", ax.name);
        }
    }
}

fn control(machine: &str) -> Control {
    let m = Machine::builtin(machine).unwrap();
    Control::new(ControlConfig::new(m)).unwrap()
}

fn home(c: &mut Control, rec: &mut Recorder) {
    c.apply(Action::Home).unwrap();
    rec.until_idle(c, 120.0);
}

#[test]
fn homing_moves_z_first_then_x_y_to_their_switches() {
    let mut c = control("mill-3axis");
    let mut rec = Recorder::new(&c);
    home(&mut c, &mut rec);
    let snap = c.snapshot();
    assert_eq!(snap.homed, vec![true, true, true]);
    assert_eq!(snap.machine_position, vec![300.0, 200.0, 100.0]);
    // Z reached its switch before X moved, X before Y (within the same millisecond at most).
    let first_move = |i: usize| {
        rec.samples
            .iter()
            .position(|p| p[i] != rec.samples[0][i])
            .unwrap()
    };
    let z_done = rec.samples.iter().position(|p| p[2] == 100.0).unwrap();
    let x_done = rec.samples.iter().position(|p| p[0] == 300.0).unwrap();
    assert!(
        first_move(0) >= z_done && first_move(1) >= x_done,
        "X moves at {}, Z done at {z_done}, Y moves at {}, X done at {x_done}",
        first_move(0),
        first_move(1)
    );
    assert!(snap.alarms.is_empty());
    rec.check_limits(c.machine());
}

#[test]
fn incremental_jogs_and_mpg_land_exactly_on_linear_and_rotary_axes() {
    let mut c = control("trt-ac");
    let mut rec = Recorder::new(&c);
    c.apply(Action::SetMode(Mode::Jog)).unwrap();
    let mut expect = c.snapshot().machine_position;
    for (axis, i) in [('X', 0), ('Z', 2), ('A', 3), ('C', 4)] {
        for inc in [0.001, 0.01, 0.1, 1.0] {
            c.apply(Action::SetIncrement(inc)).unwrap();
            c.apply(Action::JogIncrement {
                axis,
                direction: -1.0,
            })
            .unwrap();
            rec.until_idle(&mut c, 10.0);
            expect[i] -= inc;
            let got = c.snapshot().machine_position[i];
            assert!(
                (got - expect[i]).abs() < 1e-9,
                "{axis} -{inc}: {got} vs {}",
                expect[i]
            );
        }
    }
    // The handwheel: 7 detents at ×10 (0.01 mm), then 3 back.
    c.apply(Action::SetMode(Mode::Mpg)).unwrap();
    c.apply(Action::SetIncrement(0.01)).unwrap();
    c.apply(Action::Mpg {
        axis: 'Y',
        detents: 7,
    })
    .unwrap();
    // Turned on while the axis moves: counts are kept (position mode).
    rec.step(&mut c, 0.002);
    c.apply(Action::Mpg {
        axis: 'Y',
        detents: -3,
    })
    .unwrap();
    rec.until_idle(&mut c, 10.0);
    expect[1] += 0.04;
    let got = c.snapshot().machine_position[1];
    assert!(
        (got - expect[1]).abs() < 1e-9,
        "MPG Y: {got} vs {}",
        expect[1]
    );
    assert!(c.alarms().is_empty());
    rec.check_limits(c.machine());
}

#[test]
fn continuous_jog_stops_exactly_at_the_soft_limit_with_an_alarm_and_brakes_on_release() {
    let mut c = control("mill-3axis");
    let mut rec = Recorder::new(&c);
    c.apply(Action::JogFeed(6000.0)).unwrap();
    c.apply(Action::JogStart {
        axis: 'X',
        direction: 1.0,
    })
    .unwrap();
    // Auto-repeat of the held key: nothing queues.
    for _ in 0..5 {
        c.apply(Action::JogStart {
            axis: 'X',
            direction: 1.0,
        })
        .unwrap();
        rec.step(&mut c, 0.01);
    }
    rec.until_idle(&mut c, 30.0);
    let snap = c.snapshot();
    assert_eq!(snap.machine_position[0], 300.0);
    assert_eq!(snap.alarms.len(), 1);
    assert_eq!(snap.alarms[0].code, codes::SOFT_LIMIT);
    assert_eq!(snap.alarms[0].axis, Some('X'));
    // Pressing on at the limit moves nothing and says so again.
    c.apply(Action::JogStart {
        axis: 'X',
        direction: 1.0,
    })
    .unwrap();
    rec.step(&mut c, 0.05);
    assert_eq!(c.snapshot().machine_position[0], 300.0);
    assert_eq!(c.alarms().len(), 2);
    // Released half-way: it brakes within the limits and stays inside the travel.
    c.apply(Action::Reset).unwrap();
    c.apply(Action::JogStart {
        axis: 'Y',
        direction: -1.0,
    })
    .unwrap();
    rec.step(&mut c, 0.5);
    let at_release = c.snapshot().machine_position[1];
    c.apply(Action::JogStop).unwrap();
    rec.until_idle(&mut c, 5.0);
    let stopped = c.snapshot().machine_position[1];
    assert!(stopped < at_release && stopped > -200.0);
    // Braking from 100 mm/s with J = 25000 mm/s³ (A²/J = 160 mm/s > v, so no phase at
    // A = 2000 mm/s²): jerk −J then +J, each sqrt(v/J) long, covering v·sqrt(v/J) = 6.3246 mm.
    let want = 100.0 * (100.0f64 / 25000.0).sqrt();
    let d = at_release - stopped;
    assert!(
        (d - want).abs() < 1e-6,
        "braking distance {d} mm, closed form {want} mm"
    );
    assert!(c.alarms().is_empty());
    rec.check_limits(c.machine());
}

#[test]
fn mdi_lines_land_where_the_interpreter_says_with_modal_state_kept() {
    let mut c = control("mill-3axis");
    let mut rec = Recorder::new(&c);
    home(&mut c, &mut rec);
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    let lines = [
        "G0 X10 Y20 Z5",
        "G1 X30 F600",
        "Y40",
        "G2 X50 Y20 I0 J-20",
        "G91 G3 X-10 Y-10 R10",
        "G1 Z-2 F300",
        "G90 G0 Z20",
    ];
    let start = c.snapshot().machine_position;
    let prog = interpret(
        &lines.join("\n"),
        &InterpretOptions::starting_at(Joints::xyz(start[0], start[1], start[2])),
    )
    .unwrap();
    for (n, line) in lines.iter().enumerate() {
        c.apply(Action::Mdi((*line).to_string())).unwrap();
        rec.until_idle(&mut c, 60.0);
        let want = prog
            .blocks
            .iter()
            .rfind(|b| b.source_line == n + 1)
            .unwrap()
            .end
            .xyz;
        let got = c.snapshot().machine_position;
        let got = DVec3::new(got[0], got[1], got[2]);
        assert!(got.distance(want) < 1e-9, "line {}: {got} vs {want}", n + 1);
    }
    // A move beyond the travel is refused before it starts, naming line and axis.
    c.apply(Action::Mdi("G0 X400".into())).unwrap();
    rec.until_idle(&mut c, 1.0);
    let snap = c.snapshot();
    assert_eq!(snap.machine_position[0], 50.0 - 10.0);
    let a = snap.alarms.last().unwrap();
    assert_eq!(
        (a.code, a.axis, a.line),
        (codes::TRAVEL, Some('X'), Some(8))
    );
    rec.check_limits(c.machine());
}

const PROGRAM: &str = "G21 G90 G17\nG0 Z10\nG0 X-20 Y-20\nM3 S8000\nG1 Z-2 F300\n\
G1 X20 F1200\nY0\nG3 X0 Y20 I-20 J0\nG1 X-20 Y0\nG2 X-20 Y-20 I0 J-10\nG0 Z10\nM30\n";

const STOCK_MIN: DVec3 = DVec3::new(-30.0, -30.0, -10.0);
const STOCK_MAX: DVec3 = DVec3::new(30.0, 30.0, 0.0);
const RES: f64 = 0.25;

fn stock() -> DexelStock {
    DexelStock::new(
        vec![StockShape::Box {
            min: STOCK_MIN,
            max: STOCK_MAX,
        }],
        RES,
        DexelMode::Z,
        1 << 30,
    )
    .unwrap()
}

fn cutting_control() -> Control {
    cutting_control_homing_at(2000.0)
}

fn cutting_control_homing_at(home_feed_mm_per_min: f64) -> Control {
    let m = Machine::builtin("mill-3axis").unwrap();
    let mut cfg = ControlConfig::new(m);
    cfg.home_feed_mm_per_min = home_feed_mm_per_min;
    cfg.stock = Some(LiveStock::new(
        stock(),
        parse_tool_spec("flat:d=6").unwrap(),
        RES,
    ));
    Control::new(cfg).unwrap()
}

/// What `talas simulate` removes on the same program (same step bounds).
fn reference_removed() -> f64 {
    let cutter = parse_tool_spec("flat:d=6").unwrap();
    let prog = interpret(PROGRAM, &InterpretOptions::default()).unwrap();
    let steps = StepOptions {
        reach_mm: cutter.flute_length,
        chord_tolerance_mm: (0.05 * RES).clamp(1e-4, 0.01),
        axis_tolerance_mm: (0.1 * RES).clamp(1e-4, 0.02),
        ..StepOptions::default()
    };
    let plan = plan_program(&prog, None, &steps).unwrap();
    let mut s = stock();
    simulate(
        &mut s,
        &cutter,
        &plan,
        &SimOptions::default(),
        &Progress::new(),
    )
    .unwrap()
    .removed_volume_mm3
}

fn run_auto(c: &mut Control, rec: &mut Recorder, hold_at: Option<f64>) -> f64 {
    home(c, rec);
    c.apply(Action::SetMode(Mode::Auto)).unwrap();
    c.apply(Action::LoadProgram {
        name: "pocket.ngc".into(),
        text: PROGRAM.into(),
    })
    .unwrap();
    let t0 = c.time_s();
    c.apply(Action::CycleStart).unwrap();
    if let Some(t) = hold_at {
        rec.step(c, t);
        c.apply(Action::FeedHold).unwrap();
        rec.until_idle(c, 5.0);
        assert_eq!(c.run_state(), RunState::Held);
        let stop_time = c.time_s() - t0 - t;
        // Braking from at most 20 mm/s (F1200) with A = 2000, J = 25000 takes < 0.1 s.
        assert!(stop_time < 0.1, "feed hold took {stop_time} s");
        rec.step(c, 0.3);
        c.apply(Action::Resume).unwrap();
    }
    rec.until_idle(c, 600.0);
    c.time_s() - t0
}

#[test]
fn auto_run_ends_where_the_interpreter_ends_and_removes_what_simulate_removes() {
    let mut c = cutting_control();
    let mut rec = Recorder::new(&c);
    run_auto(&mut c, &mut rec, None);
    let snap = c.snapshot();
    assert_eq!(snap.state, RunState::Idle);
    assert!(snap.alarms.is_empty(), "{:?}", snap.alarms);
    let prog = interpret(PROGRAM, &InterpretOptions::default()).unwrap();
    let end = prog.blocks.last().unwrap().end.xyz;
    let got = DVec3::new(
        snap.machine_position[0],
        snap.machine_position[1],
        snap.machine_position[2],
    );
    assert!(got.distance(end) < 1e-9, "{got} vs {end}");
    let reference = reference_removed();
    let removed = snap.removed_volume_mm3;
    assert!(reference > 500.0, "the program cuts: {reference} mm³");
    assert!(
        ((removed - reference) / reference).abs() < 1e-3,
        "control removed {removed} mm³, simulate {reference} mm³"
    );
    rec.check_limits(c.machine());
}

#[test]
fn feed_hold_brakes_within_the_limits_and_resume_gives_the_same_final_state() {
    let mut plain = cutting_control();
    let mut rec_plain = Recorder::new(&plain);
    let t_plain = run_auto(&mut plain, &mut rec_plain, None);
    let mut held = cutting_control();
    let mut rec = Recorder::new(&held);
    // 1.5 s after the start: in the middle of the first fed moves.
    let t_held = run_auto(&mut held, &mut rec, Some(1.5));
    let (a, b) = (plain.snapshot(), held.snapshot());
    for i in 0..3 {
        assert!((a.machine_position[i] - b.machine_position[i]).abs() < 1e-9);
    }
    let (va, vb) = (a.removed_volume_mm3, b.removed_volume_mm3);
    assert!(((va - vb) / va).abs() < 1e-3, "{va} vs {vb} mm³");
    assert!(
        t_held > t_plain,
        "the hold took time: {t_held} vs {t_plain} s"
    );
    assert!(b.alarms.is_empty());
    rec.check_limits(held.machine());
}

/// The planned time of a program from a start point (a reference computed without the control).
fn planned_time(text: &str, start: DVec3) -> f64 {
    let m = Machine::builtin("mill-3axis").unwrap();
    let prog = interpret(
        text,
        &InterpretOptions::starting_at(Joints::xyz(start.x, start.y, start.z)),
    )
    .unwrap();
    plan(&PlanInput {
        blocks: prog.blocks.as_slice().into(),
        axes: machine_limits(&m),
        options: PlanOptions::default(),
    })
    .unwrap()
    .cycle_time_s
}

#[test]
fn overrides_change_the_time_as_expected() {
    let text = "G1 X100 F3000\nG1 Y100\nG2 X0 Y100 I-50 J0 F2000\n";
    let halved = "G1 X100 F1500\nG1 Y100\nG2 X0 Y100 I-50 J0 F1000\n";
    let run = |pct: f64| {
        let mut c = control("mill-3axis");
        let mut rec = Recorder::new(&c);
        home(&mut c, &mut rec);
        c.apply(Action::SetMode(Mode::Mdi)).unwrap();
        c.apply(Action::Mdi("G0 X0 Y0 Z0".into())).unwrap();
        rec.until_idle(&mut c, 60.0);
        c.apply(Action::SetMode(Mode::Auto)).unwrap();
        c.apply(Action::Override(OverrideKind::Feed, pct)).unwrap();
        c.apply(Action::LoadProgram {
            name: "p".into(),
            text: text.into(),
        })
        .unwrap();
        let t0 = c.time_s();
        c.apply(Action::CycleStart).unwrap();
        rec.until_idle(&mut c, 600.0);
        rec.check_limits(c.machine());
        c.time_s() - t0
    };
    let t100 = run(100.0);
    let t50 = run(50.0);
    let want100 = planned_time(text, DVec3::ZERO);
    let want50 = planned_time(halved, DVec3::ZERO);
    assert!((t100 - want100).abs() <= 2e-3, "{t100} vs {want100} s");
    assert!((t50 - want50).abs() <= 2e-3, "{t50} vs {want50} s");
    assert!(t50 > 1.8 * t100, "{t50} vs {t100} s");
    // Rapid override 25 %: a long single-axis rapid cruises at a quarter of the axis velocity.
    let mut c = control("mill-3axis");
    let mut rec = Recorder::new(&c);
    home(&mut c, &mut rec);
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    c.apply(Action::Override(OverrideKind::Rapid, 25.0))
        .unwrap();
    c.apply(Action::Mdi("G0 X-250".into())).unwrap();
    rec.until_idle(&mut c, 60.0);
    let peak = c.peaks()[0].velocity;
    assert!((peak - 125.0).abs() < 1e-6, "rapid at 25 %: {peak} mm/s");
    rec.check_limits(c.machine());
    // Out-of-range overrides are refused.
    assert!(
        c.apply(Action::Override(OverrideKind::Feed, 151.0))
            .is_err()
    );
    assert!(
        c.apply(Action::Override(OverrideKind::Rapid, 30.0))
            .is_err()
    );
    assert!(
        c.apply(Action::Override(OverrideKind::Spindle, 40.0))
            .is_err()
    );
}

#[test]
fn estop_brakes_latches_and_reset_clears_it() {
    let mut c = control("mill-3axis");
    let mut rec = Recorder::new(&c);
    c.apply(Action::JogStart {
        axis: 'Z',
        direction: -1.0,
    })
    .unwrap();
    rec.step(&mut c, 0.3);
    c.apply(Action::EStop).unwrap();
    rec.until_idle(&mut c, 5.0);
    assert_eq!(c.run_state(), RunState::EStop);
    assert!(
        c.apply(Action::JogStart {
            axis: 'Z',
            direction: 1.0
        })
        .is_err()
    );
    assert_eq!(c.alarms()[0].code, codes::ESTOP);
    c.apply(Action::Reset).unwrap();
    assert!(c.alarms().is_empty());
    c.apply(Action::JogDistance {
        axis: 'Z',
        distance: 1.0,
    })
    .unwrap();
    rec.until_idle(&mut c, 5.0);
    rec.check_limits(c.machine());
}

#[test]
fn mdi_and_auto_need_homing() {
    let mut c = control("mill-3axis");
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    c.apply(Action::Mdi("G0 X1".into())).unwrap();
    assert_eq!(c.alarms()[0].code, codes::NOT_HOMED);
    assert!(
        c.apply(Action::JogStart {
            axis: 'X',
            direction: 1.0
        })
        .is_err()
    );
}

#[test]
fn a_rapid_into_the_stock_stops_the_machine_with_a_collision_alarm() {
    let mut c = cutting_control();
    let mut rec = Recorder::new(&c);
    home(&mut c, &mut rec);
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    c.apply(Action::Mdi("G0 X-150 Y0 Z-2".into())).unwrap();
    rec.until_idle(&mut c, 60.0);
    c.apply(Action::Mdi("G0 X150".into())).unwrap();
    rec.until_idle(&mut c, 60.0);
    let snap = c.snapshot();
    let a = snap
        .alarms
        .iter()
        .find(|a| a.code == codes::COLLISION_RAPID)
        .expect("a rapid collision alarm");
    assert_eq!(a.line, Some(2));
    assert_eq!(a.bodies, vec!["tool".to_string(), "stock".to_string()]);
    // Found within 20 ms of motion after entering the stock at X −33 mm (tool radius 3 mm),
    // then braked within the limits: short of the programmed end.
    let x = a.position.unwrap()[0];
    assert!((-36.0..=-20.0).contains(&x), "collision at X {x}");
    assert!(
        snap.machine_position[0] < 150.0,
        "{:?}",
        snap.machine_position
    );
    assert!(c.apply(Action::Mdi("G0 Z20".into())).is_err());
    c.apply(Action::Reset).unwrap();
    c.apply(Action::Mdi("G0 Z20".into())).unwrap();
    rec.until_idle(&mut c, 60.0);
    assert_eq!(c.snapshot().machine_position[2], 20.0);
    rec.check_limits(c.machine());
}

#[test]
fn run_from_line_has_the_modal_state_of_a_full_run() {
    let mut c = control("mill-3axis");
    let mut rec = Recorder::new(&c);
    home(&mut c, &mut rec);
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    c.apply(Action::Mdi("G0 X20 Y-20 Z-2".into())).unwrap();
    rec.until_idle(&mut c, 60.0);
    c.apply(Action::SetMode(Mode::Auto)).unwrap();
    c.apply(Action::LoadProgram {
        name: "pocket.ngc".into(),
        text: PROGRAM.into(),
    })
    .unwrap();
    // Line 7 is `Y0`: G1 and F1200 from line 6, M3 S8000 from line 4.
    c.apply(Action::RunFromLine(7)).unwrap();
    rec.step(&mut c, 0.5);
    let codes_now = c.snapshot().active_codes;
    for code in ["G1", "G17", "G21", "G90", "M3", "F1200", "S8000"] {
        assert!(
            codes_now.iter().any(|k| k == code),
            "{code} in {codes_now:?}"
        );
    }
    assert_eq!(c.snapshot().line, Some(7));
    // Y0 at F1200 from Y −20: cruising at 20 mm/s.
    assert!((c.snapshot().feed_actual_mm_per_min - 1200.0).abs() < 1e-6);
    rec.until_idle(&mut c, 120.0);
    let prog = interpret(PROGRAM, &InterpretOptions::default()).unwrap();
    let end = prog.blocks.last().unwrap().end.xyz;
    let p = c.snapshot().machine_position;
    assert!(DVec3::new(p[0], p[1], p[2]).distance(end) < 1e-9);
    assert!(c.alarms().is_empty());
    rec.check_limits(c.machine());
}

#[test]
fn optional_stop_single_block_and_block_delete() {
    let text = "G0 X10\nM1\n/G0 Y10\nG0 Z10\nG4 P0.5\nG0 X20\nM30\n";
    let start = |c: &mut Control, rec: &mut Recorder| {
        home(c, rec);
        c.apply(Action::SetMode(Mode::Auto)).unwrap();
        c.apply(Action::LoadProgram {
            name: "p".into(),
            text: text.into(),
        })
        .unwrap();
    };
    // Optional stop on, block delete on (the default).
    let mut c = control("mill-3axis");
    let mut rec = Recorder::new(&c);
    start(&mut c, &mut rec);
    c.apply(Action::OptionalStop(true)).unwrap();
    c.apply(Action::CycleStart).unwrap();
    rec.until_idle(&mut c, 60.0);
    assert_eq!(c.run_state(), RunState::Stopped);
    assert_eq!(c.snapshot().machine_position, vec![10.0, 200.0, 100.0]);
    c.apply(Action::CycleStart).unwrap();
    let t0 = c.time_s();
    rec.until_idle(&mut c, 60.0);
    assert_eq!(c.run_state(), RunState::Idle);
    assert_eq!(c.snapshot().machine_position, vec![20.0, 200.0, 10.0]);
    assert!(c.time_s() - t0 > 0.5, "the dwell stood still");
    // Block delete off, single block: one stop per line that moves.
    let mut c = control("mill-3axis");
    let mut rec = Recorder::new(&c);
    start(&mut c, &mut rec);
    c.apply(Action::BlockDelete(false)).unwrap();
    c.apply(Action::SingleBlock(true)).unwrap();
    c.apply(Action::CycleStart).unwrap();
    let mut stops = 0;
    for _ in 0..10 {
        rec.until_idle(&mut c, 60.0);
        if c.run_state() != RunState::Stopped {
            break;
        }
        stops += 1;
        c.apply(Action::CycleStart).unwrap();
    }
    assert_eq!(stops, 4);
    assert_eq!(c.snapshot().machine_position, vec![20.0, 10.0, 10.0]);
    rec.check_limits(c.machine());
}

/// A control whose homing runs at 30 m/min (linear) and 30000 °/min (rotary, capped by the
/// axes' own limits), so the tests below home in a second or two of simulated time.
fn quick_control(m: Machine, start: Option<[f64; 6]>) -> Control {
    let mut cfg = ControlConfig::new(m);
    cfg.home_feed_mm_per_min = 30000.0;
    if let Some(s) = start {
        cfg.start = s;
    }
    Control::new(cfg).unwrap()
}

/// The axes started moving in `order`, each only after the one before it reached its switch.
fn assert_homed_in_order(rec: &Recorder, m: &Machine, order: &str) {
    let index = |c: char| m.axes.iter().position(|a| a.name == c).unwrap();
    let s = &rec.samples;
    let mut previous_done = 0;
    for c in order.chars() {
        let i = index(c);
        let ax = m.axis(c).unwrap();
        let switch = if ax.is_rotary() { 0.0 } else { ax.max };
        let first_move = s.iter().position(|p| p[i] != s[0][i]).unwrap();
        let done = s.iter().position(|p| p[i] == switch).unwrap();
        assert!(
            first_move >= previous_done,
            "{c} moved at sample {first_move}, before the axis ahead of it was home ({previous_done})"
        );
        previous_done = done;
    }
}

#[test]
fn homing_follows_the_order_of_the_machine_file() {
    // Every axis away from its switch: X −100, Y −100, Z 0 mm, A −30°, C 45°.
    let start = [
        -100.0,
        -100.0,
        0.0,
        -30f64.to_radians(),
        0.0,
        45f64.to_radians(),
    ];
    let builtin = Machine::builtin("trt-ac").unwrap();
    assert_eq!(builtin.home_order, vec!['Z', 'Y', 'X', 'A', 'C']);
    let text = include_str!("../assets/machines/trt-ac.json");
    let mut file: serde_json::Value = serde_json::from_str(text).unwrap();
    file["home_order"] = "CZAYX".into();
    let custom = Machine::from_json(&file.to_string()).unwrap();
    for (m, order) in [(builtin, "ZYXAC"), (custom, "CZAYX")] {
        let mut c = quick_control(m.clone(), Some(start));
        let mut rec = Recorder::new(&c);
        home(&mut c, &mut rec);
        assert_eq!(c.snapshot().homed, vec![true; 5]);
        assert_eq!(
            c.snapshot().machine_position,
            vec![400.0, 400.0, 400.0, 0.0, 0.0]
        );
        assert_homed_in_order(&rec, &m, order);
        assert!(c.alarms().is_empty());
        rec.check_limits(&m);
    }
    // An order that leaves out or repeats an axis, or names one the machine lacks, is refused.
    for (bad, why) in [
        ("ZYX", "leaves out axis A"),
        ("ZYXACC", "axis C is named twice"),
        ("ZYXACB", "B is not an axis"),
    ] {
        file["home_order"] = bad.into();
        let e = Machine::from_json(&file.to_string())
            .unwrap_err()
            .to_string();
        assert!(e.contains(why), "{bad}: {e}");
    }
}

/// Tool tip and axis in the work (table) frame at the control's present joints.
fn work_pose(c: &Control) -> (DVec3, DVec3) {
    let p = c.position();
    let j = talas::control::collide::machine_joints(c.machine(), &p);
    let pose = c.machine().forward(&j);
    (pose.tip, pose.axis)
}

#[test]
fn jogs_along_the_tool_axis_land_exactly_on_the_tilted_axis() {
    for name in ["trt-ac", "trt-bc"] {
        let m = Machine::builtin(name).unwrap();
        let tilt = if name == "trt-ac" { 'A' } else { 'B' };
        let mut c = Control::new(ControlConfig::new(m)).unwrap();
        let mut rec = Recorder::new(&c);
        c.apply(Action::JogFeed(6000.0)).unwrap();
        c.apply(Action::JogDistance {
            axis: tilt,
            distance: -30.0,
        })
        .unwrap();
        rec.until_idle(&mut c, 10.0);
        c.apply(Action::JogDistance {
            axis: 'C',
            distance: 40.0,
        })
        .unwrap();
        rec.until_idle(&mut c, 10.0);
        let (tip0, axis) = work_pose(&c);
        // The tool axis is tilted 30° from the table's Z in the work frame.
        assert!((axis.z - 30f64.to_radians().cos()).abs() < 1e-12, "{axis}");
        let mut along = 0.0;
        for (inc, dir, moved) in [(1.0, -1.0, -1.0), (0.1, 1.0, 0.1), (0.001, -1.0, -0.001)] {
            c.apply(Action::SetIncrement(inc)).unwrap();
            c.apply(Action::JogIncrement {
                axis: 'T',
                direction: dir,
            })
            .unwrap();
            rec.until_idle(&mut c, 10.0);
            along += moved;
            let (tip, axis_now) = work_pose(&c);
            let want = tip0 + along * axis;
            assert!(tip.distance(want) < 1e-9, "{name}: {tip} vs {want}");
            assert!(axis_now.distance(axis) < 1e-15, "the rotaries stood");
        }
        c.apply(Action::JogDistance {
            axis: 'T',
            distance: -25.0,
        })
        .unwrap();
        rec.until_idle(&mut c, 10.0);
        along -= 25.0;
        let (tip, _) = work_pose(&c);
        assert!(tip.distance(tip0 + along * axis) < 1e-9);
        // Held: the tool-axis jog ends exactly at the Z limit with the soft-limit alarm.
        c.apply(Action::JogStart {
            axis: 'T',
            direction: 1.0,
        })
        .unwrap();
        rec.until_idle(&mut c, 30.0);
        assert_eq!(c.snapshot().machine_position[2], 400.0);
        let a = c.alarms().last().unwrap();
        assert_eq!((a.code, a.axis), (codes::SOFT_LIMIT, Some('Z')));
        rec.check_limits(c.machine());
    }
}

#[test]
fn cutting_with_the_spindle_stopped_raises_an_alarm_at_the_block() {
    // MDI: the plunge of line 2 without M3.
    let mut c = cutting_control_homing_at(30000.0);
    let mut rec = Recorder::new(&c);
    home(&mut c, &mut rec);
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    c.apply(Action::Mdi("G0 X0 Y0 Z5".into())).unwrap();
    rec.until_idle(&mut c, 10.0);
    c.apply(Action::Mdi("G1 Z-2 F300".into())).unwrap();
    rec.until_idle(&mut c, 10.0);
    let a = c.alarms().last().unwrap().clone();
    assert_eq!((a.code, a.line), (codes::SPINDLE_STOPPED, Some(2)), "{a:?}");
    // The alarm names where the first cutting piece of motion (20 ms, 0.1 mm at F300) starts:
    // within 0.1 mm of the stock top (z = 0).
    let z = a.position.unwrap()[2];
    assert!(z.abs() <= 0.1, "alarm at z = {z} mm");
    let z_now = c.snapshot().machine_position[2];
    assert!(
        z_now > -2.0,
        "stopped before the block's end: z = {z_now} mm"
    );
    assert!(c.apply(Action::Mdi("G0 Z5".into())).is_err(), "blocked");
    // With the spindle on, the same block cuts without alarm.
    c.apply(Action::Reset).unwrap();
    c.apply(Action::Mdi("M3 S8000".into())).unwrap();
    c.apply(Action::Mdi("G1 Z-2 F300".into())).unwrap();
    rec.until_idle(&mut c, 10.0);
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    // AUTO: the program with M5 where it had M3 stops at its first cutting block, line 5.
    let mut c = cutting_control_homing_at(30000.0);
    let mut rec = Recorder::new(&c);
    home(&mut c, &mut rec);
    c.apply(Action::SetMode(Mode::Auto)).unwrap();
    c.apply(Action::LoadProgram {
        name: "m5.ngc".into(),
        text: PROGRAM.replace("M3 S8000", "M5"),
    })
    .unwrap();
    c.apply(Action::CycleStart).unwrap();
    rec.until_idle(&mut c, 60.0);
    let a = c.alarms().last().unwrap();
    assert_eq!((a.code, a.line), (codes::SPINDLE_STOPPED, Some(5)), "{a:?}");
    // Jogging into the stock with the spindle buttons off raises it too (no line).
    let mut c = cutting_control();
    c.apply(Action::JogFeed(6000.0)).unwrap();
    c.apply(Action::JogDistance {
        axis: 'Z',
        distance: -101.0,
    })
    .unwrap();
    c.advance_until_idle(30.0);
    let a = c.alarms().last().unwrap();
    assert_eq!((a.code, a.line), (codes::SPINDLE_STOPPED, None), "{a:?}");
    rec.check_limits(c.machine());
}

/// Time of an AUTO run of `text` from machine (0, 0, 0) on the mill with the feed override
/// at `pct`, changed to `then.1` % at `then.0` s into the run.
fn auto_time(text: &str, pct: f64, then: Option<(f64, f64)>) -> f64 {
    let mut c = quick_control(Machine::builtin("mill-3axis").unwrap(), None);
    let mut rec = Recorder::new(&c);
    home(&mut c, &mut rec);
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    c.apply(Action::Mdi("G0 X0 Y0 Z0".into())).unwrap();
    rec.until_idle(&mut c, 60.0);
    c.apply(Action::SetMode(Mode::Auto)).unwrap();
    c.apply(Action::Override(OverrideKind::Feed, pct)).unwrap();
    c.apply(Action::LoadProgram {
        name: "p".into(),
        text: text.into(),
    })
    .unwrap();
    let t0 = c.time_s();
    c.apply(Action::CycleStart).unwrap();
    if let Some((at, pct)) = then {
        rec.step(&mut c, at);
        c.apply(Action::Override(OverrideKind::Feed, pct)).unwrap();
    }
    rec.until_idle(&mut c, 600.0);
    rec.check_limits(c.machine());
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    c.time_s() - t0
}

#[test]
fn feed_override_150_and_a_change_while_running_retime_the_program() {
    let text = "G1 X100 F3000\nG1 Y100\nG2 X0 Y100 I-50 J0 F2000\n";
    let t150 = auto_time(text, 150.0, None);
    let want150 = planned_time(
        "G1 X100 F4500\nG1 Y100\nG2 X0 Y100 I-50 J0 F3000\n",
        DVec3::ZERO,
    );
    assert!((t150 - want150).abs() <= 2e-3, "{t150} vs {want150} s");
    // 50 % set 0.5 s into the first block: that block ends at its speed (exact stop), the
    // rest runs at half the programmed feeds.
    let t_mid = auto_time(text, 100.0, Some((0.5, 50.0)));
    let want_mid = planned_time("G1 X100 F3000\n", DVec3::ZERO)
        + planned_time(
            "G1 Y100 F1500\nG2 X0 Y100 I-50 J0 F1000\n",
            DVec3::new(100.0, 0.0, 0.0),
        );
    assert!((t_mid - want_mid).abs() <= 2e-3, "{t_mid} vs {want_mid} s");
}

/// Time of the MDI rapid `G0 X-250` from the home position (X 300 mm) with the rapid
/// override at `pct` (0 %: held for 0.5 s, then raised to 100 %).
fn rapid_time(pct: f64) -> f64 {
    let mut c = quick_control(Machine::builtin("mill-3axis").unwrap(), None);
    let mut rec = Recorder::new(&c);
    home(&mut c, &mut rec);
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    c.apply(Action::Override(OverrideKind::Rapid, pct)).unwrap();
    let t0 = c.time_s();
    c.apply(Action::Mdi("G0 X-250".into())).unwrap();
    if pct == 0.0 {
        rec.step(&mut c, 0.5);
        assert_eq!(c.run_state(), RunState::Held);
        assert_eq!(c.snapshot().machine_position[0], 300.0);
        c.apply(Action::Override(OverrideKind::Rapid, 100.0))
            .unwrap();
    }
    rec.until_idle(&mut c, 60.0);
    assert_eq!(c.snapshot().machine_position[0], -250.0);
    rec.check_limits(c.machine());
    c.time_s() - t0
}

#[test]
fn rapid_override_0_25_50_100_retimes_a_rapid() {
    let home_pos = DVec3::new(300.0, 200.0, 100.0);
    let t100 = rapid_time(100.0);
    let want100 = planned_time("G0 X-250\n", home_pos);
    assert!((t100 - want100).abs() <= 2e-3, "{t100} vs {want100} s");
    // 25 % and 50 %: a fed move at that fraction of X's 500 mm/s (30000 mm/min).
    for pct in [25.0, 50.0] {
        let t = rapid_time(pct);
        let want = planned_time(&format!("G1 X-250 F{}\n", 300.0 * pct), home_pos);
        assert!((t - want).abs() <= 2e-3, "{pct} %: {t} vs {want} s");
        assert!(t > t100);
    }
    let t0 = rapid_time(0.0);
    assert!((t0 - (0.5 + want100)).abs() <= 2e-3, "0 %: {t0} s");
}

/// The same AUTO run with the stock cut on a worker thread (as the operator panel does) and on
/// the control's own thread (the command line): the same stock bit for bit, the same end, and the
/// worker's stock mesh for the machine view is the inline stock's mesh.
/// `cargo test --no-default-features --test control worker`
#[test]
fn the_cutting_worker_cuts_the_same_stock_as_the_inline_cutting() {
    let mut inline = cutting_control();
    let mut rec = Recorder::new(&inline);
    let t_inline = run_auto(&mut inline, &mut rec, None);
    let mut worker = cutting_control();
    worker.start_cutting_worker();
    assert!(worker.stock().is_none() && worker.cutter().is_some());
    let mut rec = Recorder::new(&worker);
    let t_worker = run_auto(&mut worker, &mut rec, None);
    rec.check_limits(worker.machine());
    let confirmed = worker.snapshot().removed_volume_mm3;
    // The machine view's stock mesh, made by the worker, is the inline stock's mesh; once
    // taken, no new one is made while the stock stays as it is.
    let mut drawn = None;
    for _ in 0..2000 {
        drawn = worker.stock_mesh();
        if drawn.is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let drawn = drawn.expect("the worker meshes the stock");
    let here = inline.stock().unwrap().stock.closed_mesh();
    assert!(!drawn.triangles.is_empty());
    assert_eq!(
        (&drawn.positions, &drawn.triangles),
        (&here.positions, &here.triangles)
    );
    std::thread::sleep(std::time::Duration::from_millis(50));
    assert!(
        worker.stock_mesh().is_none(),
        "an unchanged stock is not meshed again"
    );
    worker.stop_cutting_worker();
    let (a, b) = (inline.stock().unwrap(), worker.stock().unwrap());
    assert_eq!(a.removed_mm3().to_bits(), b.removed_mm3().to_bits());
    assert_eq!(confirmed.to_bits(), b.removed_mm3().to_bits());
    let reference = reference_removed();
    assert_eq!(
        a.removed_mm3().to_bits(),
        reference.to_bits(),
        "AUTO vs simulate"
    );
    // Debug prints every float so that it reads back to the same bits.
    let dexels = |s: &LiveStock| format!("{:?}", s.stock.families);
    assert!(dexels(a) == dexels(b), "the dexels differ");
    assert_eq!(t_inline.to_bits(), t_worker.to_bits());
    assert_eq!(inline.position(), worker.position());
    assert!(worker.alarms().is_empty());
}

/// A rapid into the stock cut by the worker raises the alarm the inline cutting raises (same
/// line, position and text) and stops the machine short of the programmed end.
#[test]
fn the_cutting_worker_raises_the_rapid_collision_at_the_same_block() {
    let run = |threaded: bool| {
        let mut c = cutting_control();
        if threaded {
            c.start_cutting_worker();
        }
        let mut rec = Recorder::new(&c);
        home(&mut c, &mut rec);
        c.apply(Action::SetMode(Mode::Mdi)).unwrap();
        c.apply(Action::Mdi("G0 X-150 Y0 Z-2".into())).unwrap();
        rec.until_idle(&mut c, 60.0);
        c.apply(Action::Mdi("G0 X150".into())).unwrap();
        rec.until_idle(&mut c, 60.0);
        rec.check_limits(c.machine());
        let a = c
            .alarms()
            .iter()
            .find(|a| a.code == codes::COLLISION_RAPID)
            .cloned()
            .expect("a rapid collision alarm");
        (a, c.position()[0])
    };
    let (inline, x_inline) = run(false);
    let (worker, x_worker) = run(true);
    assert_eq!(inline.line, Some(2));
    assert_eq!(
        (inline.line, inline.position, &inline.text),
        (worker.line, worker.position, &worker.text)
    );
    assert!(
        x_worker < 150.0 && x_inline < 150.0,
        "{x_inline} {x_worker}"
    );
}

/// Cutting a program in pieces of its blocks (as the control cuts what each 20 ms of motion
/// played), each piece continuing the last, gives the stock of one whole `talas simulate` run
/// bit for bit (arcs are cut in their own steps as the motion passes them).
#[test]
fn piecewise_live_cutting_equals_one_whole_run() {
    let cutter = parse_tool_spec("flat:d=6").unwrap();
    let m = Machine::builtin("mill-3axis").unwrap();
    let prog = interpret(PROGRAM, &InterpretOptions::default()).unwrap();
    let mut whole = LiveStock::new(stock(), cutter.clone(), RES);
    whole.cut(prog.blocks.clone(), &m).unwrap();
    let mut pieces = LiveStock::new(stock(), cutter, RES);
    for b in &prog.blocks {
        for k in 0..7 {
            let (u0, u1) = (f64::from(k) / 7.0, f64::from(k + 1) / 7.0);
            let piece = CutPiece {
                block: b.clone(),
                piece: sub_block(b, u0, u1),
                to: u1,
            };
            pieces.cut_pieces(&[piece], &m).unwrap();
        }
    }
    let (w, p) = (whole.removed_mm3(), pieces.removed_mm3());
    assert!(w > 500.0, "the program cuts: {w} mm³");
    assert_eq!(w.to_bits(), p.to_bits(), "whole {w} mm³, pieces {p} mm³");
    let dexels = |s: &LiveStock| format!("{:?}", s.stock.families);
    assert!(dexels(&whole) == dexels(&pieces), "the dexels differ");
    let reference = reference_removed();
    assert_eq!(
        w.to_bits(),
        reference.to_bits(),
        "{w} vs simulate {reference} mm³"
    );
}
