//! The virtual control's AUTO runs programs other CAM systems post (canned cycles with their
//! repeats and dwells, G41/G42 cutter compensation from the tool table, O-word subroutines
//! and loops) as the interpreter reads them: one interpretation, the one checked against
//! LinuxCNC's `rs274` in `tests/gcode_linuxcnc.rs`. The machine runs every block the
//! interpreter gives (end points within 1e-4 mm), `talas control` cuts the stock `talas
//! simulate` cuts, and the snapshot shows the canned cycle's peck under way.

mod common;

use common::{data, talas_json, temp_file};
use talas::control::{Action, Control, ControlConfig, Mode, RunState, machine_interpret_options};
use talas::gcode::{CycleStep, LengthUnit, MotionBlock, Syntax, ToolTable, interpret};
use talas::machine::Machine;

fn corpus(name: &str) -> (String, ToolTable) {
    let text = std::fs::read_to_string(data(&format!("gcode/{name}.ngc"))).unwrap();
    let table = std::fs::read_to_string(data(&format!("gcode/{name}.tbl"))).map_or_else(
        |_| ToolTable::default(),
        |t| ToolTable::parse(&t, LengthUnit::Inch).unwrap(),
    );
    (text, table)
}

/// A homed mill-3axis control in AUTO with the program loaded and the tool table set.
fn control_with(name: &str) -> (Control, String, ToolTable) {
    let (text, table) = corpus(name);
    let mut cfg = ControlConfig::new(Machine::builtin("mill-3axis").unwrap());
    cfg.tool_table = Some(table.clone());
    let mut c = Control::new(cfg).unwrap();
    c.apply(Action::Home).unwrap();
    c.advance_until_idle(1e4);
    c.apply(Action::SetMode(Mode::Auto)).unwrap();
    c.apply(Action::LoadProgram {
        name: name.into(),
        text: text.clone(),
    })
    .unwrap();
    (c, text, table)
}

/// The interpreter's motion of the program on the machine (`talas interpret --machine`).
fn interpreted(text: &str, table: &ToolTable) -> talas::gcode::Program {
    let machine = Machine::builtin("mill-3axis").unwrap();
    let mut opts = machine_interpret_options(&machine, Syntax::Rs274);
    opts.tool_table = Some(table.clone());
    interpret(text, &opts).unwrap()
}

fn far(a: &MotionBlock, b: &MotionBlock) -> bool {
    a.end.xyz.distance(b.end.xyz) > 1e-4
        || a.source_line != b.source_line
        || std::mem::discriminant(&a.kind) != std::mem::discriminant(&b.kind)
}

#[test]
fn auto_runs_cycles_compensation_and_subroutines_as_the_interpreter_reads_them() {
    for name in [
        "fusion-peck-g83",
        "fusion-drill-g81-g82",
        "fusion-chipbreak-g73",
        "fusion-contour-comp",
        "hand-comp-g41-square",
        "hand-oword-sub-holes",
        "hand-g91-cycle-repeats",
    ] {
        let (mut c, text, table) = control_with(name);
        c.log_played(true);
        let t0 = c.time_s();
        c.apply(Action::CycleStart).unwrap();
        c.advance_until_idle(1e5);
        assert!(c.alarms().is_empty(), "{name}: {:?}", c.alarms());
        assert_eq!(c.run_state(), RunState::Idle, "{name}");
        let want = interpreted(&text, &table);
        let got = c.played();
        assert!(want.blocks.len() > 10, "{name}");
        assert_eq!(got.len(), want.blocks.len(), "{name}: blocks run");
        for (k, (g, w)) in got.iter().zip(&want.blocks).enumerate() {
            assert!(
                !far(g, w),
                "{name}: block {k}: ran {g:?}, interpreter {w:?}"
            );
        }
        // The machine stands where the program ends, and stood still for its dwells.
        let end = want.blocks.last().unwrap().end.xyz;
        let p = c.position();
        assert!(
            (p[0] - end.x).abs() < 1e-9
                && (p[1] - end.y).abs() < 1e-9
                && (p[2] - end.z).abs() < 1e-9,
            "{name}: at {p:?}, program ends at {end}"
        );
        let run_s = c.time_s() - t0;
        assert!(
            run_s > want.dwell_s(),
            "{name}: {run_s} s run, {} s of dwells",
            want.dwell_s()
        );
    }
}

#[test]
fn the_g82_dwell_stands_still_at_the_bottom_of_each_hole() {
    // Six spot holes with P0.5: the machine stands 0.5 s at Z -2 (program) each time, and the
    // hole's motion around the dwell is run (the old AUTO dropped a line's motion when the
    // line also dwelt).
    let (mut c, text, table) = control_with("fusion-drill-g81-g82");
    let want = interpreted(&text, &table);
    assert_eq!(want.dwells.len(), 6);
    c.apply(Action::CycleStart).unwrap();
    let mut dwell_s = 0.0;
    let mut dwell_z = Vec::new();
    let (mut dwelling, mut dwells_shown) = (false, 0);
    let dt = 0.01;
    for _ in 0..1_000_000 {
        if c.is_idle() {
            break;
        }
        c.advance(dt);
        if c.run_state() == RunState::Dwell {
            dwell_s += dt;
            dwell_z.push(c.position()[2]);
            // The panel shows the dwell as the cycle's phase while the machine stands still.
            let phase = c.snapshot().cycle.expect("the dwell's cycle phase");
            assert_eq!((phase.cycle, phase.step), ("G82", CycleStep::Dwell));
            assert!((phase.dwell_s - 0.5).abs() < 1e-12, "{phase:?}");
            assert!(
                (phase.depth_mm - phase.bottom_mm).abs() < 1e-12,
                "{phase:?}"
            );
            let text = phase.describe();
            assert!(text.contains("dwell 0.5 s at "), "{text}");
            if !dwelling {
                dwells_shown += 1;
            }
            dwelling = true;
            continue;
        } else if let Some(phase) = c.snapshot().cycle {
            assert_ne!(phase.step, CycleStep::Dwell, "{phase:?} while moving");
        }
        dwelling = false;
    }
    assert!(c.is_idle());
    // The dwell was shown at every hole (and only in the dwell).
    assert_eq!(dwells_shown, 6);
    // The bottom: where the block before the first dwell ends (Z-2 plus T4's length).
    let bottom = want.blocks[want.dwells[0].before_block - 1].end.xyz.z;
    assert!((dwell_s - 3.0).abs() < 6.0 * dt + 1e-9, "dwelt {dwell_s} s");
    assert!(
        dwell_z.iter().all(|z| (z - bottom).abs() < 1e-9),
        "{dwell_z:?} vs {bottom}"
    );
}

#[test]
fn the_snapshot_shows_each_peck_of_a_g83_while_it_runs() {
    // The first G83: R5, Z-15, Q3: 20 mm below R in pecks of 3 mm: ceil(20 / 3) = 7 pecks,
    // at 3, 6, ..., 18 mm and the bottom at 20 mm.
    let (mut c, _, _) = control_with("fusion-peck-g83");
    c.apply(Action::CycleStart).unwrap();
    let mut seen: Vec<(u32, u32, CycleStep, f64)> = Vec::new();
    let mut deepest_feed = [f64::INFINITY; 8];
    for _ in 0..1_000_000 {
        if c.is_idle() {
            break;
        }
        c.advance(0.002);
        let snap = c.snapshot();
        let Some(phase) = snap.cycle else {
            continue;
        };
        assert_eq!(phase.cycle, "G83");
        if snap.line == Some(20) {
            assert_eq!((phase.hole, phase.holes, phase.pecks), (1, 1, 7));
            assert!((phase.bottom_mm - 20.0).abs() < 1e-12);
            let key = (phase.hole, phase.peck, phase.step, phase.depth_mm);
            if seen.last() != Some(&key) {
                seen.push(key);
            }
            if phase.step == CycleStep::Feed {
                let k = phase.peck as usize;
                deepest_feed[k] = deepest_feed[k].min(c.position()[2]);
            }
        }
    }
    let feeds: Vec<(u32, f64)> = seen
        .iter()
        .filter(|s| s.2 == CycleStep::Feed)
        .map(|s| (s.1, s.3))
        .collect();
    let want: Vec<(u32, f64)> = (1..=7)
        .map(|k| (k, if k < 7 { 3.0 * f64::from(k) } else { 20.0 }))
        .collect();
    assert_eq!(feeds.len(), 7, "{seen:?}");
    for ((k, d), (wk, wd)) in feeds.iter().zip(&want) {
        assert_eq!(k, wk);
        assert!((d - wd).abs() < 1e-9, "peck {k} to {d} mm, want {wd} mm");
    }
    // While peck k feeds, the tool goes down to R − depth (machine Z: R5 + the 25.4 mm tool
    // length of T1, 1.0 in, minus the depth), never deeper.
    for (k, wd) in &want {
        let z = deepest_feed[*k as usize];
        let target = 5.0 + 25.4 - wd;
        assert!(
            z >= target - 1e-6 && z < target + 1.5,
            "peck {k}: deepest {z}, target {target}"
        );
    }
    // Retracts and re-entries between pecks were shown too.
    assert!(seen.iter().any(|s| s.2 == CycleStep::Retract && s.1 == 3));
    assert!(seen.iter().any(|s| s.2 == CycleStep::Reenter && s.1 == 3));
}

fn script(tag: &str) -> std::path::PathBuf {
    temp_file(
        tag,
        "script.txt",
        "home\nmode auto\ncycle-start\nwait 4\nwait-idle\n",
    )
}

#[test]
fn talas_control_cuts_what_talas_simulate_cuts_for_a_g83_and_a_g41_program() {
    for (name, stock) in [
        ("fusion-peck-g83", "box:0,0,0,60,40,25"),
        ("fusion-contour-comp", "box:-10,-10,40,70,50,48"),
    ] {
        let prog = data(&format!("gcode/{name}.ngc"));
        let table = data(&format!("gcode/{name}.tbl"));
        let s = script(name);
        let common = [
            "--machine",
            "mill-3axis",
            "--tool-table",
            table.to_str().unwrap(),
            "--tool-table-units",
            "inch",
            "--stock",
            stock,
            "--tool",
            "flat:d=6",
            "--resolution",
            "0.25",
        ];
        let mut args = vec!["control", "--program", prog.to_str().unwrap()];
        args.extend(common);
        args.extend(["--script", s.to_str().unwrap(), "--json"]);
        let ctl = talas_json(&args);
        assert!(
            ctl["alarms"].as_array().unwrap().is_empty(),
            "{name}: {}",
            ctl["alarms"]
        );
        let mut args = vec!["simulate", prog.to_str().unwrap()];
        args.extend(common);
        args.push("--json");
        let sim = talas_json(&args);
        let (got, want) = (
            ctl["removed_volume_mm3"].as_f64().unwrap(),
            sim["removed_volume_mm3"].as_f64().unwrap(),
        );
        assert!(
            want > 10.0 && ((got - want) / want).abs() < 1e-9,
            "{name}: control removed {got} mm³, simulate {want} mm³"
        );
        if name == "fusion-peck-g83" {
            // Four seconds in, the first hole's pecks are running.
            let at = &ctl["actions"][3];
            assert_eq!(at["cycle"]["cycle"].as_str(), Some("G83"), "{at}");
            assert!(at["cycle"]["peck"].as_u64().unwrap() >= 1, "{at}");
        }
    }
}

#[test]
fn interpret_feed_and_simulate_read_a_program_on_the_machine_as_control_runs_it() {
    let prog = data("gcode/fusion-peck-g83.ngc");
    let table = data("gcode/fusion-peck-g83.tbl");
    let (p, t) = (prog.to_str().unwrap(), table.to_str().unwrap());
    let on_machine = [
        "--machine",
        "mill-3axis",
        "--tool-table",
        t,
        "--tool-table-units",
        "inch",
    ];
    let mut args = vec!["interpret", p, "--json"];
    args.extend(on_machine);
    let doc = talas_json(&args);
    assert_eq!(doc["machine"].as_str(), Some("mill-3axis"));
    assert_eq!(doc["travel_violation_count"].as_u64(), Some(0));
    let moves = doc["moves"].as_array().unwrap();
    // From the home switches of assets/machines/mill-3axis.json (X 300, Y 200, Z 100: the top
    // of each travel): `G28 G91 Z0.` stays there, `G0 X10. Y10.` moves at Z 100, and the last
    // `G28 G91 X0. Y0.` goes back to X 300 Y 200.
    let first = &moves[0]["end"];
    assert_eq!(
        (
            first["X"].as_f64(),
            first["Y"].as_f64(),
            first["Z"].as_f64()
        ),
        (Some(10.0), Some(10.0), Some(100.0))
    );
    let last = &moves.last().unwrap()["end"];
    assert_eq!(
        (last["X"].as_f64(), last["Y"].as_f64()),
        (Some(300.0), Some(200.0))
    );
    // Without a machine the program starts at the origin and G28 goes to machine zero.
    let plain = talas_json(&[
        "interpret",
        p,
        "--json",
        "--tool-table",
        t,
        "--tool-table-units",
        "inch",
    ]);
    assert_eq!(plain["moves"][0]["end"]["Z"].as_f64(), Some(0.0));
    assert!(plain.get("travel_violations").is_none());

    // A program beyond the travel: the machine's joint limits name it.
    let far = temp_file(
        "machine-interpret",
        "far.ngc",
        "G21 G90\nG0 X350 Y0 Z50\nM2\n",
    );
    let doc = talas_json(&[
        "interpret",
        far.to_str().unwrap(),
        "--machine",
        "mill-3axis",
        "--json",
    ]);
    let v = &doc["travel_violations"][0];
    assert_eq!(
        (v["line"].as_u64(), v["axis"].as_str()),
        (Some(2), Some("X"))
    );
    assert_eq!(
        (v["value"].as_f64(), v["limit"].as_f64()),
        (Some(350.0), Some(300.0))
    );

    // `talas feed` plans what the control runs: the same cycle time as AUTO on the machine.
    let mut args = vec!["feed", p, "--json"];
    args.extend(on_machine);
    let feed = talas_json(&args);
    let s = temp_file(
        "machine-feed",
        "script.txt",
        "home\nmode auto\ncycle-start\nwait-idle\n",
    );
    let mut args = vec![
        "control",
        "--program",
        p,
        "--script",
        s.to_str().unwrap(),
        "--json",
    ];
    args.extend(on_machine);
    let ctl = talas_json(&args);
    let started = ctl["actions"][2]["t_s"].as_f64().unwrap();
    let auto_s = ctl["time_s"].as_f64().unwrap() - started;
    let feed_s = feed["cycle_time_s"].as_f64().unwrap();
    assert!(feed_s > 10.0, "{feed_s} s");
    assert!(
        ((auto_s - feed_s) / feed_s).abs() < 2e-3,
        "AUTO ran {auto_s} s, talas feed plans {feed_s} s"
    );
}
