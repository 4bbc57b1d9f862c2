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
