//! Exact moves through the posts: arcs in three planes and a helix as G2/G3 (or lines where a
//! dialect cannot write them), every canned cycle in every dialect, several operations in one
//! program, and dialect files that are refused when loaded.
//!
//! References: the arcs are read back with Talas's interpreter and compared with the model's
//! closed-form geometry; the LinuxCNC and Fanuc cycles are run through LinuxCNC's own `rs274 -g`
//! when it is installed (Debian `linuxcnc-uspace`), and GRBL's expanded cycles through Talas's
//! interpreter, against the cycle's motion.

use glam::DVec3;
use std::f64::consts::{FRAC_PI_2, PI, TAU};
use talas::gcode::{InterpretOptions, MotionKind, Program, Syntax, interpret};
use talas::machine::Machine;
use talas::post::{Dialect, Operation, PostOptions, post, post_mapped, post_program};
use talas::toolpath::{
    CycleKind, CycleMove, CycleRetract, CycleStep, ExactMove, MoveKind, Pose, ToolRecord, Toolpath,
};
use talas::tools::parse_tool_spec;

const DIALECTS: [&str; 5] = ["linuxcnc", "fanuc", "siemens", "heidenhain", "grbl"];

fn tool(spec: &str) -> ToolRecord {
    ToolRecord {
        spec: spec.into(),
        cutter: parse_tool_spec(spec).unwrap(),
    }
}

/// A quarter arc in G17, a CW half arc in G18 (ZX), a G19 arc, a 1.5-turn helix in G17, lines
/// between them.
fn arcs_path() -> Toolpath {
    let p = |kind, x, y, z| Pose::new(kind, DVec3::new(x, y, z), DVec3::Z, 600.0);
    let mut tp = Toolpath::new(
        tool("flat:d=6"),
        vec![
            p(MoveKind::Rapid, 10.0, 0.0, 5.0),
            p(MoveKind::Plunge, 10.0, 0.0, -1.0),
        ],
    );
    tp.push_arc(
        DVec3::new(0.0, 0.0, -1.0),
        DVec3::Z,
        FRAC_PI_2,
        MoveKind::Cut,
        600.0,
        0.005,
    )
    .unwrap();
    // From (0, 10, -1): a CW half turn about +Y centred 4 mm up: (0,10,-1) → (0,10,7).
    tp.push_arc(
        DVec3::new(0.0, 10.0, 3.0),
        DVec3::Y,
        -PI,
        MoveKind::Cut,
        600.0,
        0.005,
    )
    .unwrap();
    // About +X through (0, 15, 7): a quarter from (0,10,7).
    tp.push_arc(
        DVec3::new(0.0, 15.0, 7.0),
        DVec3::X,
        FRAC_PI_2,
        MoveKind::Cut,
        600.0,
        0.005,
    )
    .unwrap();
    tp.push_pose(p(MoveKind::Cut, 20.0, 20.0, 2.0));
    // A helix of radius 5 about (25, 20), 1.5 turns CW, going down 3 mm.
    tp.push_helix(
        DVec3::new(25.0, 20.0, 2.0),
        DVec3::Z,
        -1.5 * TAU,
        -3.0,
        MoveKind::Cut,
        400.0,
        0.005,
    )
    .unwrap();
    tp.push_pose(p(MoveKind::Rapid, 30.0, 20.0, 20.0));
    tp
}

fn every_cycle() -> Vec<CycleKind> {
    vec![
        CycleKind::Drill,
        CycleKind::Dwell { dwell_s: 0.5 },
        CycleKind::Peck { peck_mm: 3.0 },
        CycleKind::ChipBreak { peck_mm: 2.5 },
        CycleKind::Tap { pitch_mm: 1.0 },
        CycleKind::Bore { dwell_s: 0.0 },
        CycleKind::Bore { dwell_s: 0.25 },
        CycleKind::BoreSpindleStop { dwell_s: 0.5 },
    ]
}

/// One hole per cycle kind along X, alternately G98 and G99, from an initial plane 10 mm up.
fn cycles_path() -> Toolpath {
    let mut tp = Toolpath::new(tool("flat:d=6"), Vec::new());
    for (i, kind) in every_cycle().into_iter().enumerate() {
        let feed = match kind {
            CycleKind::Tap { pitch_mm } => pitch_mm * 1000.0,
            _ => 120.0,
        };
        tp.push_cycle(CycleMove {
            cycle: kind,
            surface: DVec3::new(10.0 * i as f64, 5.0, 0.0),
            axis: DVec3::Z,
            depth_mm: 7.0,
            clearance_mm: 2.0,
            retract_mm: 10.0,
            retract: if i % 2 == 0 {
                CycleRetract::Initial
            } else {
                CycleRetract::RPlane
            },
            feed_mm_per_min: feed,
        })
        .unwrap();
    }
    tp.push_pose(Pose::new(
        MoveKind::Rapid,
        DVec3::new(80.0, 5.0, 10.0),
        DVec3::Z,
        0.0,
    ));
    tp
}

fn options() -> PostOptions {
    PostOptions {
        spindle_rpm: 1000.0,
        ..PostOptions::default()
    }
}

fn read(text: &str, dialect: &str) -> Program {
    let syntax = Syntax::from_name(dialect).unwrap();
    let opts = InterpretOptions {
        // Fanuc's cycle dwells are in ms (the dialect's `cycle_dwell_ms`).
        cycle_dwell_ms: Dialect::builtin(dialect).is_ok_and(|d| d.cycle_dwell_ms),
        ..InterpretOptions::for_syntax(syntax)
    };
    interpret(text, &opts).unwrap_or_else(|e| panic!("{dialect}: {e}\n{text}"))
}

/// The bound of rounding to the dialect's places, over three axes, mm.
fn rounding_mm(d: &Dialect) -> f64 {
    0.5 * 10f64.powi(-(d.decimals_linear as i32)) * 3f64.sqrt() + 1e-9
}

/// Points along a read-back block (arcs sampled finely).
fn block_points(b: &talas::gcode::MotionBlock) -> Vec<DVec3> {
    match b.kind.arc() {
        None => vec![b.start.xyz, b.end.xyz],
        Some(a) => {
            let sign = if matches!(b.kind, MotionKind::ArcCcw(_)) {
                1.0
            } else {
                -1.0
            };
            (0..=2000)
                .map(|i| {
                    let t = i as f64 / 2000.0;
                    let r0 = b.start.xyz - a.centre;
                    let r0 = r0 - a.normal * r0.dot(a.normal);
                    let q = glam::DQuat::from_axis_angle(a.normal, sign * a.sweep_rad * t);
                    a.centre + q * r0 + a.normal * (a.helix_mm * t)
                })
                .collect()
        }
    }
}

fn point_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + ab * t)
}

#[test]
fn arcs_and_helices_read_back_to_the_model_in_every_dialect() {
    let tp = arcs_path();
    let mill = Machine::builtin("mill-3axis").unwrap();
    for name in DIALECTS {
        let d = Dialect::builtin(name).unwrap();
        let text = post(&tp, &mill, &d, &options()).unwrap();
        let program = read(&text, name);
        let tol = rounding_mm(&d);
        // Every arc block: centre and end on the model's arc (the first arc whose geometry
        // holds them), within the rounding.
        let mut arc_blocks = 0;
        for b in &program.blocks {
            let Some(a) = b.kind.arc() else { continue };
            arc_blocks += 1;
            let on_model = tp.exact.iter().any(|s| {
                let ExactMove::Arc(m) = s.exact else {
                    return false;
                };
                let start = tp.poses[s.from].tip;
                // The model centre at the block's start height along the normal.
                let h = (b.start.xyz - start).dot(m.normal);
                let centre = m.centre + m.normal * h;
                let r = m.radius_mm(start);
                let end_off = b.end.xyz - centre;
                let radial = (end_off - m.normal * end_off.dot(m.normal)).length();
                a.centre.distance(centre) <= tol && (radial - r).abs() <= tol
            });
            assert!(
                on_model,
                "{name}: line {} is on no arc of the model\n{text}",
                b.source_line
            );
        }
        let expected_min = match name {
            // G17 only, no helices: the quarter arc alone.
            "heidenhain" => 1,
            _ => 5,
        };
        assert!(
            arc_blocks >= expected_min,
            "{name}: {arc_blocks} arc blocks\n{text}"
        );
        // Every exact end point is reached by a block, within the rounding (1e-4 mm at four
        // places).
        for s in &tp.exact {
            let end = tp.poses[s.to].tip;
            let d_min = program
                .blocks
                .iter()
                .map(|b| b.end.xyz.distance(end))
                .fold(f64::INFINITY, f64::min);
            assert!(d_min <= tol, "{name}: end {end} missed by {d_min} mm");
            if d.decimals_linear >= 4 {
                assert!(d_min <= 1e-4, "{name}: end {end} missed by {d_min} mm");
            }
        }
        // The same sampled poses: every pose of the path is within the post tolerance (plus
        // rounding) of the motion read back.
        let pts: Vec<Vec<DVec3>> = program.blocks.iter().map(block_points).collect();
        for (k, pose) in tp.poses.iter().enumerate() {
            let dist = pts
                .iter()
                .flat_map(|ps| ps.windows(2).map(|w| point_segment(pose.tip, w[0], w[1])))
                .fold(f64::INFINITY, f64::min);
            assert!(
                dist <= options().tolerance_mm + tol + 1e-3,
                "{name}: pose {k} is {dist} mm off the program"
            );
        }
    }
}

#[test]
fn arcs_beyond_the_dialect_limits_are_lines_within_the_tolerance() {
    let tp = arcs_path();
    let mill = Machine::builtin("mill-3axis").unwrap();
    let text = r#"{"name": "tiny-arcs", "arc_max_radius_mm": 4.0, "arc_planes": ["G17", "G18"]}"#;
    let d = Dialect::from_json(text, "tiny-arcs.json").unwrap();
    let program_text = post(&tp, &mill, &d, &options()).unwrap();
    let program = interpret(&program_text, &InterpretOptions::default()).unwrap();
    let arcs: Vec<_> = program.blocks.iter().filter_map(|b| b.kind.arc()).collect();
    // Radius 10 (G17), 4 (G18: allowed), 5 (G19: plane refused), helix radius 5 (too large).
    assert!(
        !arcs.is_empty() && arcs.iter().all(|a| (a.radius_mm - 4.0).abs() < 1e-3),
        "{arcs:?}"
    );
    // The lines stay within the tolerance of the exact arcs.
    for s in &tp.exact {
        let ExactMove::Arc(m) = s.exact else { continue };
        let start = tp.poses[s.from].tip;
        let r = m.radius_mm(start);
        if (r - 4.0).abs() < 1e-9 {
            continue;
        }
        for b in program.blocks.iter().filter(|b| b.source_line > 0) {
            let mid = 0.5 * (b.start.xyz + b.end.xyz);
            let on = |p: DVec3| {
                let h = (p - start).dot(m.normal);
                let c = m.centre + m.normal * h;
                let off = p - c;
                ((off - m.normal * off.dot(m.normal)).length() - r).abs()
            };
            if on(b.start.xyz) < 1e-3 && on(b.end.xyz) < 1e-3 && b.start.xyz.distance(b.end.xyz) < r
            {
                assert!(
                    on(mid) <= options().tolerance_mm + 1e-3,
                    "chord off by {}",
                    on(mid)
                );
            }
        }
    }
}

/// The cycle motion as (rapid?, end) pairs from the start of each cycle, and the total dwell.
fn cycle_motion(tp: &Toolpath) -> (Vec<(bool, DVec3)>, f64) {
    let mut out = Vec::new();
    let mut dwell = 0.0;
    for s in &tp.exact {
        let ExactMove::Cycle(c) = s.exact else {
            continue;
        };
        for step in c.steps() {
            match step {
                CycleStep::Rapid(p) => out.push((true, p)),
                CycleStep::Feed(p) => out.push((false, p)),
                CycleStep::Dwell(t) => dwell += t,
                CycleStep::Spindle(_) => {}
            }
        }
    }
    (out, dwell)
}

/// The blocks of a program that lie on a hole's axis below the initial plane (the cycles'
/// own motion, not the rapids between holes).
fn hole_moves(moves: &[(bool, DVec3, DVec3)], tp: &Toolpath) -> Vec<(bool, DVec3)> {
    let holes: Vec<CycleMove> = tp
        .exact
        .iter()
        .filter_map(|s| match s.exact {
            ExactMove::Cycle(c) => Some(c),
            ExactMove::Arc(_) => None,
        })
        .collect();
    moves
        .iter()
        .filter(|(_, from, to)| {
            holes.iter().any(|c| {
                let on =
                    |p: DVec3| (p.x - c.surface.x).abs() < 1e-6 && (p.y - c.surface.y).abs() < 1e-6;
                // The approach from above the initial plane is the move before the cycle.
                on(*from)
                    && on(*to)
                    && from.distance(*to) > 1e-9
                    && from.z <= c.start().z + 1e-6
                    && to.z <= c.start().z + 1e-6
            })
        })
        .map(|(r, _, to)| (*r, *to))
        .collect()
}

fn same_motion(got: &[(bool, DVec3)], want: &[(bool, DVec3)], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?}\nwant {want:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert_eq!(g.0, w.0, "{what}: move {i} rapid/feed");
        assert!(
            g.1.distance(w.1) <= tol,
            "{what}: move {i} at {} not {}",
            g.1,
            w.1
        );
    }
}

#[test]
fn grbl_expands_every_cycle_into_the_cycles_motion() {
    let tp = cycles_path();
    let mill = Machine::builtin("mill-3axis").unwrap();
    let d = Dialect::builtin("grbl").unwrap();
    let text = post(&tp, &mill, &d, &options()).unwrap();
    assert!(!text.contains("G8") && !text.contains("G73"), "{text}");
    let program = read(&text, "grbl");
    let moves: Vec<(bool, DVec3, DVec3)> = program
        .blocks
        .iter()
        .map(|b| (matches!(b.kind, MotionKind::Rapid), b.start.xyz, b.end.xyz))
        .collect();
    let (want, dwell) = cycle_motion(&tp);
    same_motion(&hole_moves(&moves, &tp), &want, rounding_mm(&d), "grbl");
    assert!(
        (program.dwell_s() - dwell).abs() < 1e-9,
        "{} s of dwell",
        program.dwell_s()
    );
    // The tap reverses the spindle and turns it forward again; the G86 bore stops it.
    assert_eq!(text.matches("M4").count(), 1, "{text}");
    assert!(text.contains("M5\n"), "{text}");
}

#[test]
fn each_dialect_writes_its_own_cycles() {
    let tp = cycles_path();
    let mill = Machine::builtin("mill-3axis").unwrap();
    let expect: [(&str, &[&str]); 4] = [
        (
            "linuxcnc",
            &[
                "G98 G81", "G99 G82", "G83", "G73", "G84", "G85", "G89", "G86", "G80",
            ],
        ),
        (
            "fanuc",
            &[
                "G98 G81", "G99 G82", "G83", "G73", "G84", "G85", "G89", "G86", "P500", "G80",
            ],
        ),
        (
            "siemens",
            // The tap here goes back to the initial plane (G98), which CYCLE84 does not feed
            // to (it feeds to RFP + SDIS and rapids on): written as moves, no CYCLE84.
            &["CYCLE81(", "CYCLE82(", "CYCLE83(", "CYCLE85("],
        ),
        (
            "heidenhain",
            // As for Siemens, cycle 207 feeds out only to the set-up clearance: the tap that
            // goes back to the initial plane is written as moves.
            &["G200 ", "G205 ", "G203 ", "G201 ", "Q208=FMAX", "G79 *"],
        ),
    ];
    for (name, codes) in expect {
        let d = Dialect::builtin(name).unwrap();
        let text = post(&tp, &mill, &d, &options()).unwrap();
        for c in codes {
            assert!(text.contains(c), "{name}: no {c}\n{text}");
        }
        // Deterministic.
        assert_eq!(post(&tp, &mill, &d, &options()).unwrap(), text);
    }
}

/// STRAIGHT_TRAVERSE / STRAIGHT_FEED of `rs274 -g`, as (rapid?, from, to).
fn rs274_moves(text: &str) -> Option<Vec<(bool, DVec3, DVec3)>> {
    let dir = std::env::temp_dir().join(format!("talas-post-exact-{}", std::process::id()));
    std::fs::create_dir_all(&dir).ok()?;
    let file = dir.join("cycles.ngc");
    std::fs::write(&file, text).ok()?;
    let out = std::process::Command::new("rs274")
        .arg("-g")
        .arg(&file)
        .output()
        .ok()?;
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    std::fs::remove_dir_all(&dir).ok();
    let mut here = DVec3::ZERO;
    let mut moves = Vec::new();
    for line in stdout.lines() {
        for (key, rapid) in [("STRAIGHT_TRAVERSE(", true), ("STRAIGHT_FEED(", false)] {
            if let Some(i) = line.find(key) {
                let args: Vec<f64> = line[i + key.len()..]
                    .trim_end_matches(')')
                    .split(',')
                    .filter_map(|a| a.trim().parse().ok())
                    .collect();
                let p = DVec3::new(args[0], args[1], args[2]);
                moves.push((rapid, here, p));
                here = p;
            }
        }
    }
    Some(moves)
}

#[test]
fn linuxcnc_runs_the_linuxcnc_and_fanuc_cycles_as_the_model_moves() {
    let tp = cycles_path();
    let mill = Machine::builtin("mill-3axis").unwrap();
    let (want, _) = cycle_motion(&tp);
    for name in ["linuxcnc", "fanuc"] {
        let d = Dialect::builtin(name).unwrap();
        let mut text = post(&tp, &mill, &d, &options()).unwrap();
        if name == "fanuc" {
            // The Fanuc control reads the cycle dwell P in ms, rs274 in seconds.
            assert!(text.contains(" P500") && text.contains(" P250"), "{text}");
            text = text.replace(" P500", " P0.5").replace(" P250", " P0.25");
        }
        let Some(moves) = rs274_moves(&text) else {
            eprintln!(
                "rs274 (linuxcnc-uspace) is not installed: {name} cycles not checked against LinuxCNC"
            );
            return;
        };
        same_motion(&hole_moves(&moves, &tp), &want, 1e-4, name);
    }
}

/// The cycles as LinuxCNC, Fanuc and GRBL programs (G73/G81–G89 with G98/G99, GRBL's
/// expansion) read back with Talas's interpreter to the cycles' motion and dwell time.
#[test]
fn every_dialects_cycles_read_back_with_talas() {
    cycles_read_back(&["linuxcnc", "fanuc", "grbl"]);
}

/// The same for Siemens (CYCLE81–CYCLE85 as Sinumerik runs them).
#[test]
fn siemens_cycles_read_back_with_talas() {
    cycles_read_back(&["siemens"]);
}

/// The same for Heidenhain (cycles 200–207 defined with G2xx and called with G79).
#[test]
fn heidenhain_cycles_read_back_with_talas() {
    cycles_read_back(&["heidenhain"]);
}

fn cycles_read_back(dialects: &[&str]) {
    let tp = cycles_path();
    let mill = Machine::builtin("mill-3axis").unwrap();
    let (want, dwell) = cycle_motion(&tp);
    for &name in dialects {
        let d = Dialect::builtin(name).unwrap();
        let text = post(&tp, &mill, &d, &options()).unwrap();
        let program = read(&text, name);
        let moves: Vec<(bool, DVec3, DVec3)> = program
            .blocks
            .iter()
            .map(|b| (matches!(b.kind, MotionKind::Rapid), b.start.xyz, b.end.xyz))
            .collect();
        same_motion(&hole_moves(&moves, &tp), &want, rounding_mm(&d), name);
        assert!(
            (program.dwell_s() - dwell).abs() < 1e-3,
            "{name}: read {} s, cycles {dwell} s\n{text}",
            program.dwell_s()
        );
    }
}

#[test]
fn operations_in_one_program_change_tools_in_order() {
    let mill = Machine::builtin("mill-3axis").unwrap();
    let first = arcs_path();
    let mut second = cycles_path();
    second.tool = tool("flat:d=8");
    let ops = [
        Operation {
            toolpath: &first,
            tool_number: 3,
            spindle_rpm: 12_000.0,
            coolant: true,
        },
        Operation {
            toolpath: &second,
            tool_number: 7,
            spindle_rpm: 1000.0,
            coolant: false,
        },
    ];
    for name in DIALECTS {
        let d = Dialect::builtin(name).unwrap();
        let p = post_program(&ops, &mill, &d, &options()).unwrap();
        assert_eq!(p.source_of_line.len(), p.text.lines().count());
        // The one-operation program is the single-path post, byte for byte.
        let one = post_program(&ops[..1], &mill, &d, &options()).unwrap();
        let o = PostOptions {
            tool_number: 3,
            spindle_rpm: 12_000.0,
            ..options()
        };
        assert_eq!(
            one.text,
            post_mapped(&first, &mill, &d, &o).unwrap().text,
            "{name}"
        );
        if name == "grbl" {
            assert!(!p.text.contains("M6"), "{name}");
            continue;
        }
        let t7 = p
            .text
            .find("T7")
            .unwrap_or_else(|| panic!("{name}\n{}", p.text));
        let t3 = p.text.find("T3").unwrap();
        assert!(t3 < t7, "{name}");
        let before_t7 = &p.text[..t7];
        let stop = if name == "fanuc" { "M01" } else { "M1" };
        assert!(
            before_t7.contains(stop),
            "{name}: no optional stop before T7"
        );
        if matches!(name, "linuxcnc" | "fanuc") {
            assert!(p.text.contains("G43 H7"), "{name}");
        }
        // The second operation's lines say so.
        let line_t7 = p.text[..t7].lines().count();
        assert_eq!(p.source_of_line[line_t7].operation, 1, "{name}");
        if matches!(name, "linuxcnc" | "grbl" | "fanuc") {
            // Without cycles the reader reads it: tools and spindle speeds switch in order.
            let ops_arcs = [
                ops[0],
                Operation {
                    toolpath: &first,
                    ..ops[1]
                },
            ];
            let text = post_program(&ops_arcs, &mill, &d, &options()).unwrap().text;
            let program = read(&text, name);
            let tools: Vec<u32> = program.blocks.iter().map(|b| b.tool).collect();
            let first7 = tools.iter().position(|&t| t == 7).unwrap();
            assert!(
                tools[..first7].iter().all(|&t| t == 3) && tools[first7..].iter().all(|&t| t == 7)
            );
            assert!(
                program.blocks[first7..]
                    .iter()
                    .any(|b| b.spindle_rpm == 1000.0)
            );
            assert!(
                program.blocks[..first7]
                    .iter()
                    .all(|b| b.spindle_rpm == 12_000.0 || b.spindle_rpm == 0.0)
            );
            if name != "grbl" {
                assert_eq!(program.blocks.last().unwrap().tool_length_h, Some(7));
            }
        }
    }
}

#[test]
fn a_five_axis_machine_writes_arcs_while_its_rotaries_stand_still() {
    let tp = arcs_path();
    let trt = Machine::builtin("trt-ac").unwrap();
    for name in ["linuxcnc", "fanuc", "siemens"] {
        let d = Dialect::builtin(name).unwrap();
        let text = post(&tp, &trt, &d, &options()).unwrap();
        let program = read(&text, name);
        let radii: Vec<f64> = program
            .blocks
            .iter()
            .filter_map(|b| b.kind.arc())
            .map(|a| a.radius_mm)
            .collect();
        assert!(radii.len() >= 5, "{name}: {radii:?}");
        for r in &radii {
            assert!(
                [10.0, 4.0, 5.0].iter().any(|m| (r - m).abs() < 2e-4),
                "{name}: radius {r}"
            );
        }
        // Under TCP the arcs are lines.
        let tcp = PostOptions {
            tcp: true,
            ..options()
        };
        let text = post(&tp, &trt, &d, &tcp).unwrap();
        let program = read(&text, name);
        assert!(
            program.blocks.iter().all(|b| b.kind.arc().is_none()),
            "{name}"
        );
    }
}
