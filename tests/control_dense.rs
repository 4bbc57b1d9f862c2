//! The control's AUTO runs the plan `talas feed` makes (issue 35): on dense programs (a circle
//! of R50 in 1 000 and 10 000 blocks) the simulated run takes the planned cycle time within
//! 1 %, instead of stopping at every block.
//!
//! `cargo test --no-default-features --test control_dense`

use std::f64::consts::TAU;

use talas::control::{Action, Control, ControlConfig, Mode};
use talas::feed::{DEFAULT_CORNERS, PlanInput, PlanOptions, machine_limits, plan};
use talas::gcode::{InterpretOptions, Joints, interpret};
use talas::machine::Machine;

fn circle(n: usize) -> String {
    let mut text = String::from("G21 G90 G17 G94\nG1 F2000\n");
    for i in 1..=n {
        let a = TAU * i as f64 / n as f64;
        text += &format!("X{:.6} Y{:.6}\n", 50.0 * a.cos(), 50.0 * a.sin());
    }
    text
}

/// The AUTO run of `text` from machine (50, 0, 0) on the mill, s.
fn auto_time(text: &str) -> f64 {
    let mut cfg = ControlConfig::new(Machine::builtin("mill-3axis").unwrap());
    cfg.home_feed_mm_per_min = 30000.0;
    let mut c = Control::new(cfg).unwrap();
    c.apply(Action::Home).unwrap();
    c.advance_until_idle(600.0);
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    c.apply(Action::Mdi("G0 X50 Y0 Z0".into())).unwrap();
    c.advance_until_idle(600.0);
    c.apply(Action::SetMode(Mode::Auto)).unwrap();
    c.apply(Action::LoadProgram {
        name: "circle".into(),
        text: text.into(),
    })
    .unwrap();
    let t0 = c.time_s();
    c.apply(Action::CycleStart).unwrap();
    c.advance_until_idle(2000.0);
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    let end = c.snapshot().machine_position;
    assert!(
        (end[0] - 50.0).abs() < 1e-6 && end[1].abs() < 1e-6,
        "{end:?}"
    );
    c.time_s() - t0
}

fn planned_time(text: &str) -> f64 {
    let m = Machine::builtin("mill-3axis").unwrap();
    let prog = interpret(
        text,
        &InterpretOptions::starting_at(Joints::xyz(50.0, 0.0, 0.0)),
    )
    .unwrap();
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
}

#[test]
fn auto_keeps_the_feed_on_dense_programs_as_the_plan_does() {
    for n in [1000, 10_000] {
        let text = circle(n);
        let (run, planned) = (auto_time(&text), planned_time(&text));
        eprintln!("{n} blocks: AUTO {run:.4} s, talas feed's plan {planned:.4} s");
        assert!(
            (run - planned).abs() <= 0.01 * planned,
            "{n} blocks: AUTO {run} s against the plan's {planned} s"
        );
        // At the feed: 2π·50 mm at 2000 mm/min is 9.42 s.
        assert!(run < 9.42 * 1.05, "{n} blocks: {run} s");
    }
}
