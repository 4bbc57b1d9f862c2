//! Posting round trip: synthetic 5-axis tool paths posted for trt-ac and trt-bc in every
//! 5-axis dialect, read back with `gcode::interpret`, mapped through forward kinematics and
//! compared with the poses; golden files; determinism.

use glam::DVec3;
use talas::gcode::{InterpretOptions, MotionBlock, Syntax, interpret};
use talas::machine::{Machine, MachineJoints, ToolPose};
use talas::post::{Dialect, PostOptions, post};
use talas::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};
use talas::tools::parse_tool_spec;

const FIVE_AXIS_DIALECTS: [&str; 4] = ["linuxcnc", "fanuc", "siemens", "heidenhain"];
const TOLERANCE_MM: f64 = 0.01;

fn tool() -> ToolRecord {
    ToolRecord {
        spec: "ball:d=6".into(),
        cutter: parse_tool_spec("ball:d=6").unwrap(),
    }
}

fn pose(tip: DVec3, axis: DVec3, kind: MoveKind) -> Pose {
    Pose::new(kind, tip, axis.normalize(), 800.0)
}

/// A helix of radius 30 rising 2 mm a turn, the axis swinging up to ~35° from +Z.
fn helix() -> Toolpath {
    let mut poses = Vec::new();
    for k in 0..=120 {
        let t = k as f64 * std::f64::consts::TAU / 40.0;
        let tip = DVec3::new(
            30.0 * t.cos(),
            30.0 * t.sin(),
            5.0 + 2.0 * t / std::f64::consts::TAU,
        );
        let axis = DVec3::new(0.5 * (0.7 * t).sin(), 0.4 * (1.3 * t).cos(), 1.0);
        let kind = if k == 0 {
            MoveKind::Rapid
        } else {
            MoveKind::Cut
        };
        poses.push(pose(tip, axis, kind));
    }
    Toolpath::new(tool(), poses)
}

/// Meridians of a hemisphere of radius 20, the axis along the normal, through the pole (the
/// singular pose A = 0) and poses 1e-7 rad and 1e-4 rad from it.
fn hemisphere() -> Toolpath {
    let mut poses = Vec::new();
    for (m, lon) in [0.3f64, 1.9, 4.0].iter().enumerate() {
        let polar: Vec<f64> = vec![1.2, 0.9, 0.6, 0.3, 1e-4, 1e-7, 0.0];
        let mut meridian: Vec<f64> = polar.clone();
        meridian.extend(polar.iter().rev().skip(1).map(|p| -p));
        for (i, p) in meridian.iter().enumerate() {
            let n = DVec3::new(p.sin() * lon.cos(), p.sin() * lon.sin(), p.cos());
            let kind = if i == 0 {
                if m == 0 {
                    MoveKind::Rapid
                } else {
                    MoveKind::Link
                }
            } else {
                MoveKind::Cut
            };
            poses.push(pose(n * 20.0, n, kind));
        }
    }
    Toolpath::new(tool(), poses)
}

/// The interpreter options for a dialect's program syntax (block ends, units, TCP codes).
fn options_for(dialect: &str) -> InterpretOptions {
    InterpretOptions::for_syntax(Syntax::from_name(dialect).unwrap())
}

fn joints(machine: &Machine, b: &MotionBlock) -> MachineJoints {
    let tilt = if machine.rotary_names() == Some(('B', 'C')) {
        b.end.b
    } else {
        b.end.a
    };
    MachineJoints {
        xyz: b.end.xyz,
        tilt_rad: tilt.unwrap_or(0.0),
        rotary_rad: b.end.c.unwrap_or(0.0),
    }
}

fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

fn point_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let d = b - a;
    let t = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + d * t)
}

/// Largest (tip error mm, axis error rad, linearisation deviation mm, blocks).
fn round_trip(tp: &Toolpath, machine: &Machine, dialect: &str) -> (f64, f64, f64, usize, usize) {
    let d = Dialect::builtin(dialect).unwrap();
    let options = PostOptions {
        tolerance_mm: TOLERANCE_MM,
        ..PostOptions::default()
    };
    let text = post(tp, machine, &d, &options).unwrap();
    let program = interpret(&text, &options_for(dialect))
        .unwrap_or_else(|e| panic!("{dialect}/{}: {e}", machine.name));
    assert!(
        program.blocks.iter().all(|b| !b.tcp),
        "{dialect}: joint-space program read as TCP"
    );
    let blocks = &program.blocks;
    let (mut tip_err, mut axis_err, mut dev) = (0.0f64, 0.0f64, 0.0f64);
    let mut next = 0usize;
    let mut last_match: Option<usize> = None;
    let mut flips = 0usize;
    for (k, p) in tp.poses.iter().enumerate() {
        let found = (next..blocks.len()).find(|&i| {
            let f = machine.forward(&joints(machine, &blocks[i]));
            f.tip.distance(p.tip) < 1e-3 && angle(f.axis, p.axis) < 1e-6
        });
        let i = found.unwrap_or_else(|| panic!("{dialect}/{}: pose {k} not reached", machine.name));
        let f = machine.forward(&joints(machine, &blocks[i]));
        tip_err = tip_err.max(f.tip.distance(p.tip));
        axis_err = axis_err.max(angle(f.axis, p.axis));
        if let (Some(j), Some(prev)) = (last_match, k.checked_sub(1)) {
            let a = &tp.poses[prev];
            // A rapid between the poses is the safe flip to the other branch (retract, turn,
            // re-enter): only the fed blocks after it are held to the tolerance.
            let j = (j..i)
                .rev()
                .find(|&w| blocks[w + 1].kind == talas::gcode::MotionKind::Rapid)
                .map_or(j, |w| {
                    flips += 1;
                    w + 2
                });
            if p.kind != MoveKind::Rapid {
                let from = ToolPose {
                    tip: a.tip,
                    axis: a.axis,
                };
                let to = ToolPose {
                    tip: p.tip,
                    axis: p.axis,
                };
                for w in j..i {
                    let (ja, jb) = (joints(machine, &blocks[w]), joints(machine, &blocks[w + 1]));
                    dev = dev.max(machine.tip_deviation_mm(&ja, &jb, &from, &to));
                    dev = dev.max(point_segment(machine.forward(&jb).tip, a.tip, p.tip));
                }
            }
        }
        last_match = Some(i);
        next = i + 1;
    }
    (tip_err, axis_err, dev, blocks.len(), flips)
}

#[test]
fn five_axis_round_trip_in_every_dialect() {
    for machine_name in ["trt-ac", "trt-bc"] {
        let machine = Machine::builtin(machine_name).unwrap();
        for (path_name, tp) in [("helix", helix()), ("hemisphere", hemisphere())] {
            for dialect in FIVE_AXIS_DIALECTS {
                let (tip, axis, dev, n, flips) = round_trip(&tp, &machine, dialect);
                println!(
                    "{machine_name} {path_name} {dialect}: {n} blocks for {} poses, tip {tip:.2e} mm, \
                     axis {axis:.2e} rad, deviation {dev:.2e} mm, {flips} branch flips",
                    tp.poses.len()
                );
                assert!(tip < 1e-3, "tip error {tip}");
                assert!(axis < 1e-6, "axis error {axis}");
                // The tolerance, plus the rounding of the written coordinates.
                assert!(dev < TOLERANCE_MM + 2e-4, "deviation {dev}");
            }
        }
    }
}

/// Tool-centre-point output: the controller keeps the tip on the programmed line, so X Y Z are
/// the tip itself and the rotary axes give the orientation. Largest (tip error mm, axis error
/// rad) over the poses; every fed block must be read as TCP.
fn tcp_round_trip(tp: &Toolpath, machine: &Machine, dialect: &str) -> (f64, f64) {
    let options = PostOptions {
        tcp: true,
        ..PostOptions::default()
    };
    let text = post(tp, machine, &Dialect::builtin(dialect).unwrap(), &options).unwrap();
    let program = interpret(&text, &options_for(dialect))
        .unwrap_or_else(|e| panic!("{dialect}/{} TCP: {e}", machine.name));
    let blocks = &program.blocks;
    let fed: Vec<&MotionBlock> = blocks
        .iter()
        .filter(|b| b.kind != talas::gcode::MotionKind::Rapid)
        .collect();
    assert!(!fed.is_empty());
    assert!(
        fed.iter().all(|b| b.tcp),
        "{dialect}: fed block outside TCP mode"
    );
    let (mut tip_err, mut axis_err) = (0.0f64, 0.0f64);
    let mut next = 0usize;
    for (k, p) in tp.poses.iter().enumerate() {
        let axis_of = |b: &MotionBlock| machine.forward(&joints(machine, b)).axis;
        let found = (next..blocks.len()).find(|&i| {
            blocks[i].tcp
                && blocks[i].end.xyz.distance(p.tip) < 1e-3
                && angle(axis_of(&blocks[i]), p.axis) < 1e-5
        });
        let i =
            found.unwrap_or_else(|| panic!("{dialect}/{} TCP: pose {k} not reached", machine.name));
        tip_err = tip_err.max(blocks[i].end.xyz.distance(p.tip));
        axis_err = axis_err.max(angle(axis_of(&blocks[i]), p.axis));
        next = i + 1;
    }
    (tip_err, axis_err)
}

#[test]
fn five_axis_tcp_round_trip_in_every_dialect() {
    for machine_name in ["trt-ac", "trt-bc"] {
        let machine = Machine::builtin(machine_name).unwrap();
        for (path_name, tp) in [("helix", helix()), ("hemisphere", hemisphere())] {
            for dialect in FIVE_AXIS_DIALECTS {
                let (tip, axis) = tcp_round_trip(&tp, &machine, dialect);
                println!(
                    "{machine_name} {path_name} {dialect} TCP: tip {tip:.2e} mm, axis {axis:.2e} rad"
                );
                assert!(tip < 1e-3, "tip error {tip}");
                assert!(axis < 1e-6, "axis error {axis}");
            }
        }
    }
}

#[test]
fn posting_is_deterministic() {
    let machine = Machine::builtin("trt-ac").unwrap();
    for dialect in FIVE_AXIS_DIALECTS {
        let d = Dialect::builtin(dialect).unwrap();
        let a = post(&helix(), &machine, &d, &PostOptions::default()).unwrap();
        let b = post(&helix(), &machine, &d, &PostOptions::default()).unwrap();
        assert_eq!(a.as_bytes(), b.as_bytes());
    }
}

/// A small program: rapid in, a plunge, a cut that tilts the axis, a link, back.
fn small() -> Toolpath {
    Toolpath::new(
        tool(),
        vec![
            pose(DVec3::new(10.0, 0.0, 10.0), DVec3::Z, MoveKind::Rapid),
            pose(DVec3::new(10.0, 0.0, 0.0), DVec3::Z, MoveKind::Plunge),
            pose(
                DVec3::new(20.0, 0.0, 0.0),
                DVec3::new(0.0, 0.2, 1.0),
                MoveKind::Cut,
            ),
            pose(
                DVec3::new(20.0, 10.0, 0.0),
                DVec3::new(0.0, 0.2, 1.0),
                MoveKind::Cut,
            ),
            pose(
                DVec3::new(20.0, 10.0, 10.0),
                DVec3::new(0.0, 0.2, 1.0),
                MoveKind::Link,
            ),
        ],
    )
}

fn small3() -> Toolpath {
    let mut tp = small();
    for p in &mut tp.poses {
        p.axis = DVec3::Z;
    }
    tp
}

#[test]
fn golden_files_per_dialect() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/post");
    let bless = std::env::var("TALAS_BLESS").is_ok_and(|v| v == "1");
    let trt = Machine::builtin("trt-ac").unwrap();
    let mill = Machine::builtin("mill-3axis").unwrap();
    let tcp = PostOptions {
        tcp: true,
        ..PostOptions::default()
    };
    let mut cases: Vec<(String, Toolpath, &Machine, PostOptions)> = FIVE_AXIS_DIALECTS
        .iter()
        .flat_map(|d| {
            [
                (
                    format!("small-{d}.ngc"),
                    small(),
                    &trt,
                    PostOptions::default(),
                ),
                (format!("small-{d}-tcp.ngc"), small(), &trt, tcp.clone()),
            ]
        })
        .collect();
    cases.push((
        "small-grbl.ngc".into(),
        small3(),
        &mill,
        PostOptions::default(),
    ));
    for (name, tp, machine, options) in &cases {
        let dialect = name
            .trim_start_matches("small-")
            .trim_end_matches(".ngc")
            .trim_end_matches("-tcp");
        let text = post(tp, machine, &Dialect::builtin(dialect).unwrap(), options).unwrap();
        let path = dir.join(name);
        if bless {
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(&path, &text).unwrap();
        } else {
            let golden = std::fs::read_to_string(&path)
                .unwrap_or_else(|e| panic!("{}: {e} (run with TALAS_BLESS=1)", path.display()));
            assert_eq!(text, golden, "{name} differs from its golden file");
        }
    }
}

#[test]
fn cli_posts_and_lists_machines() {
    let exe = env!("CARGO_BIN_EXE_talas");
    let dir = std::env::temp_dir().join(format!("talas-post-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let input = dir.join("small.json");
    small().save(&input).unwrap();
    let out = dir.join("small.ngc");
    let run = std::process::Command::new(exe)
        .args([
            "post",
            input.to_str().unwrap(),
            "--machine",
            "trt-ac",
            "--dialect",
            "linuxcnc",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let golden = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/post/small-linuxcnc.ngc"),
    )
    .unwrap();
    assert_eq!(std::fs::read_to_string(&out).unwrap(), golden);
    // A 5-axis machine in the 3-axis GRBL dialect: exit 2, one line naming the file.
    let run = std::process::Command::new(exe)
        .args([
            "post",
            input.to_str().unwrap(),
            "--machine",
            "trt-ac",
            "--dialect",
            "grbl",
            "-o",
        ])
        .arg(dir.join("x.ngc"))
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(2));
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        err.contains("small.json") && err.contains("3-axis") && err.lines().count() == 1,
        "{err}"
    );
    let list = std::process::Command::new(exe)
        .arg("machines")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&list.stdout);
    for name in ["mill-3axis", "trt-ac", "trt-bc"] {
        assert!(text.lines().any(|l| l.starts_with(name)), "{text}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 35: a rapid that turns the table (here A by 40°, C by 90° between two passes 5 mm
/// above the part) swung the part under the tool in one G0 at the passes' height. Every rapid
/// that turns a rotary axis now runs at the clearance height: retract, turn, position, down.
#[test]
fn rapids_that_turn_the_table_do_so_at_the_clearance_height() {
    let machine = Machine::builtin("trt-ac").unwrap();
    let tilt = |deg: f64, az: f64| {
        let (t, a) = (deg.to_radians(), az.to_radians());
        DVec3::new(t.sin() * a.cos(), t.sin() * a.sin(), t.cos())
    };
    let mut poses = vec![pose(DVec3::new(0.0, 0.0, 30.0), DVec3::Z, MoveKind::Rapid)];
    for x in [-10.0, 0.0, 10.0] {
        poses.push(pose(DVec3::new(x, 5.0, 2.0), tilt(5.0, 0.0), MoveKind::Cut));
    }
    // The link to the second pass: a rapid at 5 mm, the axis swinging 35° and 90° about Z.
    poses.push(pose(
        DVec3::new(10.0, -5.0, 5.0),
        tilt(40.0, 90.0),
        MoveKind::Rapid,
    ));
    for x in [10.0, 0.0, -10.0] {
        poses.push(pose(
            DVec3::new(x, -5.0, 2.0),
            tilt(40.0, 90.0),
            MoveKind::Cut,
        ));
    }
    let tp = Toolpath::new(tool(), poses);
    for dialect in FIVE_AXIS_DIALECTS {
        let d = Dialect::builtin(dialect).unwrap();
        let options = PostOptions {
            tolerance_mm: TOLERANCE_MM,
            ..PostOptions::default()
        };
        let clearance = options.clearance_z_mm;
        let text = post(&tp, &machine, &d, &options).unwrap();
        let program = interpret(&text, &options_for(dialect)).unwrap();
        let mut turned = 0;
        for b in &program.blocks {
            let d = |x: Option<f64>, y: Option<f64>| (x.unwrap_or(0.0) - y.unwrap_or(0.0)).abs();
            let turns = d(b.end.a, b.start.a) > 1e-6 || d(b.end.c, b.start.c) > 1e-6;
            if b.kind == talas::gcode::MotionKind::Rapid && turns {
                turned += 1;
                assert!(
                    (b.start.xyz.z - clearance).abs() < 1e-6
                        && (b.end.xyz.z - clearance).abs() < 1e-6,
                    "{dialect}: line {} turns the table at Z {} → {} (clearance {clearance})",
                    b.source_line,
                    b.start.xyz.z,
                    b.end.xyz.z
                );
            }
        }
        assert!(turned >= 1, "{dialect}: no rapid turns the table");
        // And the poses are still reached exactly.
        let (tip, axis, _, _, _) = round_trip(&tp, &machine, dialect);
        assert!(tip < 1e-3 && axis < 1e-6, "{dialect}: {tip} mm, {axis} rad");
    }
}
