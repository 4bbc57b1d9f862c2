use super::*;
use crate::toolpath::{Pose, ToolRecord};
use crate::tools::parse_tool_spec;
use glam::DVec3;

fn path(axes: &[DVec3]) -> Toolpath {
    let poses = axes
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let kind = if k == 0 {
                MoveKind::Rapid
            } else {
                MoveKind::Cut
            };
            Pose::new(
                kind,
                DVec3::new(k as f64 * 5.0, 0.0, 0.0),
                a.normalize(),
                500.0,
            )
        })
        .collect();
    Toolpath::new(
        ToolRecord {
            spec: "ball:d=6".into(),
            cutter: parse_tool_spec("ball:d=6").unwrap(),
        },
        poses,
    )
}

#[test]
fn grbl_rejects_five_axis_machines_and_tcp() {
    let tp = path(&[DVec3::Z, DVec3::Z]);
    let grbl = Dialect::builtin("grbl").unwrap();
    let trt = Machine::builtin("trt-ac").unwrap();
    let e = post(&tp, &trt, &grbl, &PostOptions::default()).unwrap_err();
    assert!(e.to_string().contains("3-axis"), "{e}");
    let mill = Machine::builtin("mill-3axis").unwrap();
    assert!(post(&tp, &mill, &grbl, &PostOptions::default()).is_ok());
    let tcp = PostOptions {
        tcp: true,
        ..PostOptions::default()
    };
    assert!(post(&tp, &mill, &grbl, &tcp).is_err());
}

#[test]
fn tilted_pose_on_three_axes_names_the_pose() {
    let tp = path(&[DVec3::Z, DVec3::Z, DVec3::new(0.0, 1.0, 1.0)]);
    let mill = Machine::builtin("mill-3axis").unwrap();
    let lcnc = Dialect::builtin("linuxcnc").unwrap();
    match post(&tp, &mill, &lcnc, &PostOptions::default()) {
        Err(PostError::Pose { pose, .. }) => assert_eq!(pose, 2),
        other => panic!("{other:?}"),
    }
}

#[test]
fn rotary_moves_use_inverse_time_and_tcp_does_not() {
    let tp = path(&[
        DVec3::Z,
        DVec3::new(0.0, 0.3, 1.0),
        DVec3::new(0.0, 0.3, 1.0),
    ]);
    let trt = Machine::builtin("trt-ac").unwrap();
    let lcnc = Dialect::builtin("linuxcnc").unwrap();
    let text = post(&tp, &trt, &lcnc, &PostOptions::default()).unwrap();
    assert!(text.contains("G93"), "{text}");
    let tcp = PostOptions {
        tcp: true,
        ..PostOptions::default()
    };
    let text = post(&tp, &trt, &lcnc, &tcp).unwrap();
    assert!(text.contains("G43.4 H1") && !text.contains("G93"), "{text}");
}

/// An inverse-time block lasts the tip's travel over the part at the feed, unless a rotary axis
/// needs longer at its velocity limit: 5 mm at 500 mm/min with the table tilting 16.7° takes
/// 0.6 s (the tilt alone needs 0.11 s at trt-ac's 150 deg/s), and a 40° turn on the spot takes
/// 40° / 150 deg/s.
#[test]
fn inverse_time_is_the_tip_travel_at_the_feed_or_the_rotary_limit() {
    use crate::gcode::{InterpretOptions, interpret};
    let trt = Machine::builtin("trt-ac").unwrap();
    let lcnc = Dialect::builtin("linuxcnc").unwrap();
    let mut tp = path(&[DVec3::Z, DVec3::new(0.0, 0.3, 1.0)]);
    // A third pose on the spot, the axis turned 40° further about X.
    let turned = DVec3::new(0.0, (0.3f64.atan() + 40f64.to_radians()).tan(), 1.0);
    let mut spot = tp.poses[1];
    spot.axis = turned.normalize();
    tp.poses.push(spot);
    let tp = Toolpath::new(tp.tool.clone(), tp.poses);
    let text = post(&tp, &trt, &lcnc, &PostOptions::default()).unwrap();
    let program = interpret(&text, &InterpretOptions::default()).unwrap();
    // The post linearises both moves into small steps: add up each move's blocks (the
    // travel's blocks move X, the turn's do not).
    let (mut travel, mut turn) = (0.0, 0.0);
    for b in &program.blocks {
        if let Some(t) = b.inverse_time_duration_s() {
            if (b.end.xyz.x - b.start.xyz.x).abs() > 1e-9 {
                travel += t;
            } else {
                turn += t;
            }
        }
    }
    assert!((travel - 5.0 / 500.0 * 60.0).abs() < 1e-3, "{travel}");
    let a_limit_deg_s = trt.axis('A').unwrap().velocity.to_degrees();
    assert!((a_limit_deg_s - 150.0).abs() < 1e-9);
    assert!((turn - 40.0 / a_limit_deg_s).abs() < 1e-3, "{turn}");
}

/// The tip a block puts in part coordinates (forward kinematics of its end joints).
fn block_tip(machine: &Machine, b: &crate::gcode::MotionBlock) -> glam::DVec3 {
    let tilt = if machine.rotary_names() == Some(('B', 'C')) {
        b.end.b
    } else {
        b.end.a
    };
    let j = MachineJoints {
        xyz: b.end.xyz,
        tilt_rad: tilt.unwrap_or(0.0),
        rotary_rad: b.end.c.unwrap_or(0.0),
    };
    machine.forward(&j).tip
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

/// Posts `tp`, reads the text back with the interpreter and checks the line map: every line
/// tagged with pose k is a motion block whose tip (forward kinematics) lies on the move from
/// pose k-1 to pose k, the last line of pose k ends on its tip, the poses come in increasing
/// order and none is left out. Returns the largest tip error at a pose, mm.
fn check_line_map(tp: &Toolpath, machine: &str, dialect: &str) -> f64 {
    use crate::gcode::{InterpretOptions, Syntax, interpret};
    let machine = Machine::builtin(machine).unwrap();
    let d = Dialect::builtin(dialect).unwrap();
    let options = PostOptions::default();
    let posted = post_mapped(tp, &machine, &d, &options).unwrap();
    assert_eq!(
        posted.text,
        post(tp, &machine, &d, &options).unwrap(),
        "post and post_mapped differ"
    );
    assert_eq!(posted.pose_of_line.len(), posted.text.lines().count());
    let program = interpret(
        &posted.text,
        &InterpretOptions::for_syntax(Syntax::from_name(dialect).unwrap()),
    )
    .unwrap();
    let resolution = 10f64.powi(-i32::try_from(d.decimals_linear).unwrap());
    let mut worst = 0.0f64;
    let mut seen = vec![false; tp.poses.len()];
    let mut last_pose = 0usize;
    for (line, tag) in posted.pose_of_line.iter().enumerate() {
        let Some(k) = *tag else { continue };
        assert!(
            k >= last_pose,
            "{dialect}: line {line} pose {k} after {last_pose}"
        );
        last_pose = k;
        seen[k] = true;
        let block = program
            .blocks
            .iter()
            .rev()
            .find(|b| b.source_line == line + 1)
            .unwrap_or_else(|| panic!("{dialect}: line {line} tagged {k} is not a motion"));
        let tip = block_tip(&machine, block);
        let a = tp.poses[k.saturating_sub(1)].tip;
        let b = tp.poses[k].tip;
        // On the way to the pose (linearised), or at the previous pose (the feed-in of a flip).
        let off = point_segment(tip, a, b);
        assert!(
            off < 2.0 * resolution,
            "{dialect}: line {line} {off} mm off"
        );
        let next_tag = posted.pose_of_line.get(line + 1).copied().flatten();
        if next_tag != Some(k) {
            let e = tip.distance(b);
            assert!(
                e < 2.0 * resolution,
                "{dialect}: line {line} ends {e} mm from pose {k}"
            );
            worst = worst.max(e);
        }
    }
    assert!(seen.iter().all(|&s| s), "{dialect}: a pose has no line");
    let lines = posted.line_of_each_pose(tp.poses.len());
    for (k, line) in lines.iter().enumerate() {
        let l = line.unwrap_or_else(|| panic!("{dialect}: pose {k} has no line"));
        assert_eq!(posted.pose_of_line[l], Some(k));
        assert_ne!(posted.pose_of_line.get(l + 1).copied().flatten(), Some(k));
    }
    // Preamble and comments are not motions.
    assert_eq!(posted.pose_of_line.first(), Some(&None));
    let mapped = posted.pose_of_line.iter().filter(|p| p.is_some()).count();
    eprintln!(
        "{dialect}/{}: {mapped} of {} lines mapped to {} poses, worst tip error {worst:.2e} mm",
        machine.name,
        posted.pose_of_line.len(),
        tp.poses.len()
    );
    worst
}

#[test]
fn every_motion_line_maps_to_its_pose() {
    // 5 axes: the axis swings (linearised moves of several blocks each).
    let tilted = path(&[
        DVec3::Z,
        DVec3::Z,
        DVec3::new(0.0, 0.4, 1.0),
        DVec3::new(0.3, 0.4, 1.0),
        DVec3::new(0.3, -0.2, 1.0),
        DVec3::Z,
    ]);
    for dialect in ["linuxcnc", "siemens", "heidenhain", "fanuc"] {
        let e = check_line_map(&tilted, "trt-ac", dialect);
        assert!(e < 1e-3, "{dialect}: {e}");
    }
    let e = check_line_map(&tilted, "trt-bc", "linuxcnc");
    assert!(e < 1e-3, "{e}");
    // 3 axes: one line per pose.
    let straight = path(&[DVec3::Z; 5]);
    for dialect in ["grbl", "linuxcnc"] {
        let e = check_line_map(&straight, "mill-3axis", dialect);
        assert!(e < 1e-3, "{dialect}: {e}");
    }
}

#[test]
fn a_dialect_file_needs_only_its_name_and_what_differs() {
    let d = Dialect::from_json(r#"{"name": "shop", "decimals_linear": 4}"#, "shop.json").unwrap();
    let linuxcnc = Dialect::builtin("linuxcnc").unwrap();
    assert_eq!(d.name, "shop");
    assert_eq!(d.decimals_linear, 4);
    assert_eq!(d.rapid, linuxcnc.rapid);
    assert_eq!(d.footer, linuxcnc.footer);
    let e = Dialect::from_json(r#"{"decimals_linear": 4}"#, "shop.json").unwrap_err();
    assert!(
        e.to_string().contains("shop.json") && e.to_string().contains("name"),
        "{e}"
    );
    let e =
        Dialect::from_json(r#"{"name": "shop", "decimal_linear": 4}"#, "shop.json").unwrap_err();
    assert!(e.to_string().contains("decimal_linear"), "{e}");
    let e = Dialect::from_json("{\n\"name\": ", "shop.json").unwrap_err();
    assert!(e.to_string().contains("shop.json: line 2"), "{e}");
}

#[test]
fn program_names_and_work_offsets_that_could_inject_blocks_are_refused() {
    let tp = crate::toolpath::Toolpath::from_json(
        r#"{"tool": {"spec": "ball:d=6"}, "poses": [{"tip": [0, 0, 5], "kind": "rapid"}]}"#,
        "t.json",
    )
    .unwrap();
    let m = Machine::builtin("mill-3axis").unwrap();
    let d = Dialect::builtin("heidenhain").unwrap();
    for name in ["A\nG0 Z-5", "X *", "", "%X"] {
        let o = PostOptions {
            program_name: name.into(),
            ..PostOptions::default()
        };
        assert!(
            matches!(post(&tp, &m, &d, &o), Err(PostError::Options(_))),
            "{name:?}"
        );
    }
    let o = PostOptions {
        work_offset: "G54\nG0 Z-5".into(),
        ..PostOptions::default()
    };
    assert!(matches!(post(&tp, &m, &d, &o), Err(PostError::Options(_))));
}
