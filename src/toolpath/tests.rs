use super::*;
use crate::tools::parse_tool_spec;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

fn sample() -> Toolpath {
    let pose = |x: f64, kind| Pose::new(kind, DVec3::new(x, 0.0, 0.0), DVec3::Z, 600.0);
    let cutter = parse_tool_spec("ball:d=6").unwrap();
    Toolpath::new(
        ToolRecord {
            spec: "ball:d=6".into(),
            cutter,
        },
        vec![
            pose(0.0, MoveKind::Rapid),
            pose(10.0, MoveKind::Cut),
            pose(13.0, MoveKind::Link),
        ],
    )
}

#[test]
fn json_matches_the_contract_and_round_trips() {
    let tp = sample();
    let text = tp.to_json().unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["units"], "mm");
    assert_eq!(v["tool"]["spec"], "ball:d=6");
    assert_eq!(v["poses"][1]["kind"], "cut");
    assert_eq!(v["poses"][1]["tip"], serde_json::json!([10.0, 0.0, 0.0]));
    assert_eq!(v["poses"][1]["axis"], serde_json::json!([0.0, 0.0, 1.0]));
    assert!(v["poses"][1]["cc"].is_null());
    assert_eq!(v["poses"][1]["feed_mm_per_min"], 600.0);
    assert_eq!(Toolpath::from_json(&text, "t.json").unwrap(), tp);
}

#[test]
fn summary_by_hand() {
    let s = sample().summary;
    assert_eq!(s.pose_count, 3);
    assert!((s.cut_length_mm - 10.0).abs() < 1e-12);
    assert!((s.other_length_mm - 3.0).abs() < 1e-12);
    // 13 mm at 600 mm/min = 1.3 s.
    assert!((s.estimated_time_s - 1.3).abs() < 1e-12);
    assert_eq!(s.bbox_max, DVec3::new(13.0, 0.0, 0.0));
    // The pose clock is the same rule: 10 mm then 3 mm at 600 mm/min, ending at the estimate.
    let t = super::pose_times_at_feed(&sample().poses);
    assert_eq!(t.len(), 3);
    assert!(
        (t[1] - 1.0).abs() < 1e-12 && (t[2] - 1.3).abs() < 1e-12,
        "{t:?}"
    );
    assert_eq!(t[2], s.estimated_time_s);
}

#[test]
fn errors_name_file_and_place() {
    let e = Toolpath::from_json("{\"units\": \"mm\",\n \"poses\": [}", "p.json").unwrap_err();
    assert_eq!(e.file, "p.json");
    assert!(e.place.starts_with("line 2"), "{e}");
    let mut tp = sample();
    tp.poses[2].axis = DVec3::new(0.0, 0.0, 2.0);
    let text = tp.to_json().unwrap();
    let e = Toolpath::from_json(&text, "p.json").unwrap_err();
    assert_eq!(e.place, "pose 2");
    tp.units = "inch".into();
    assert_eq!(tp.validate("x").unwrap_err().place, "units");
}

#[test]
fn atomic_save_and_load() {
    let dir = std::env::temp_dir().join(format!("talas-toolpath-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("a.json");
    let tp = sample();
    tp.save(&path).unwrap();
    assert_eq!(Toolpath::load(&path).unwrap(), tp);
    assert!(!dir.join("a.json.tmp").exists());
    let e = Toolpath::load(&dir.join("missing.json")).unwrap_err();
    assert_eq!(e.place, "file");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A path as another program writes it: the tool by its spec alone, null or missing feeds on
/// rapids, a modal feed, no axis (+Z), no summary, unknown keys.
const FOREIGN: &str = r#"{
  "tool": {"spec": "ball:d=6", "vendor_id": 17},
  "poses": [
    {"tip": [0, 0, 10], "kind": "rapid", "feed_mm_per_min": null},
    {"tip": [0, 0, 1], "kind": "plunge", "feed_mm_per_min": 300},
    {"tip": [10, 0, 1], "kind": "cut", "feed_mm_per_min": 600, "colour": "red"},
    {"tip": [10, 5, 1], "kind": "cut"},
    {"tip": [10, 5, 10], "kind": "rapid"}
  ],
  "generator": "other-cam 1.0"
}"#;

#[test]
fn a_foreign_path_is_read_generously_with_warnings() {
    let (tp, warnings) = Toolpath::from_json_with_warnings(FOREIGN, "f.json").unwrap();
    assert_eq!(tp.units, "mm");
    assert_eq!(tp.tool.cutter, parse_tool_spec("ball:d=6").unwrap());
    assert_eq!(tp.poses.len(), 5);
    assert!(tp.poses.iter().all(|p| p.axis == DVec3::Z));
    // The feed is modal on fed moves; rapids carry none.
    assert_eq!(tp.poses[3].feed_mm_per_min, 600.0);
    assert_eq!(tp.poses[0].feed_mm_per_min, 0.0);
    // The summary is computed: 9 mm plunge + 10 + 5 mm cut, 9 mm rapid.
    assert_eq!(tp.summary.pose_count, 5);
    assert!((tp.summary.cut_length_mm - 24.0).abs() < 1e-12);
    assert!((tp.summary.other_length_mm - 9.0).abs() < 1e-12);
    let mut w = warnings.clone();
    w.sort();
    assert_eq!(
        w,
        vec![
            "f.json: unknown key 'generator' ignored",
            "f.json: unknown key 'poses.2.colour' ignored",
            "f.json: unknown key 'tool.vendor_id' ignored",
        ]
    );
}

#[test]
fn the_foreign_path_equals_the_same_path_written_by_talas() {
    let foreign = Toolpath::from_json(FOREIGN, "f.json").unwrap();
    let text = foreign.to_json().unwrap();
    let (again, warnings) = Toolpath::from_json_with_warnings(&text, "t.json").unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(again, foreign);
}

#[test]
fn tool_fields_must_agree_with_the_spec_and_fed_moves_need_a_feed() {
    let e = Toolpath::from_json(
        r#"{"tool": {"spec": "ball:d=6", "diameter": 8}, "poses": []}"#,
        "t.json",
    )
    .unwrap_err();
    assert_eq!(e.place, "tool");
    assert!(e.message.contains("diameter 8"), "{e}");
    let e = Toolpath::from_json(
        r#"{"tool": {"spec": "ball:d=6", "kind": {"type": "flat"}}, "poses": []}"#,
        "t.json",
    )
    .unwrap_err();
    assert_eq!(e.place, "tool");
    let e = Toolpath::from_json(r#"{"tool": {}, "poses": []}"#, "t.json").unwrap_err();
    assert!(e.message.contains("spec"), "{e}");
    // Without a spec the fields define the cutter.
    let tp = Toolpath::from_json(
        r#"{"tool": {"kind": {"type": "flat"}, "diameter": 10}, "poses": []}"#,
        "t.json",
    )
    .unwrap();
    assert_eq!(tp.tool.cutter.diameter, 10.0);
    assert!(tp.tool.spec.starts_with("flat:d=10"), "{}", tp.tool.spec);
    let e = Toolpath::from_json(
        r#"{"tool": {"spec": "ball:d=6"}, "poses": [{"tip": [0,0,0], "kind": "cut"}]}"#,
        "t.json",
    )
    .unwrap_err();
    assert_eq!(e.place, "pose 0");
    let e = Toolpath::from_json(
        r#"{"units": "inch", "tool": {"spec": "ball:d=6"}, "poses": []}"#,
        "t.json",
    )
    .unwrap_err();
    assert_eq!(e.place, "units");
}

#[test]
fn the_published_schema_is_the_one_the_reader_uses() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/schema/toolpath.schema.json");
    let generated = schema();
    if std::env::var_os("TALAS_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &generated).unwrap();
    }
    let published = std::fs::read_to_string(&path).unwrap();
    assert!(
        published == generated,
        "assets/schema/toolpath.schema.json is stale: re-bless with TALAS_BLESS=1"
    );
    let v: serde_json::Value = serde_json::from_str(&published).unwrap();
    let required: Vec<&str> = v["required"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|x| x.as_str())
        .collect();
    assert_eq!(required, ["tool", "poses"]);
}

#[test]
fn a_tool_with_flutes_round_trips_without_warnings() {
    let spec = "flat:d=12,flutes=2,helix=30,rake=15";
    let cutter = parse_tool_spec(spec).unwrap();
    let tp = Toolpath::new(
        ToolRecord {
            spec: spec.into(),
            cutter,
        },
        vec![Pose::new(MoveKind::Rapid, DVec3::Z, DVec3::Z, 0.0)],
    );
    let (again, warnings) =
        Toolpath::from_json_with_warnings(&tp.to_json().unwrap(), "f.json").unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(again, tp);
    let e = Toolpath::from_json(
        r#"{"tool": {"spec": "flat:d=12,flutes=2", "flutes": {"count": 3, "helix": 0.5, "rake": 0}}, "poses": []}"#,
        "f.json",
    )
    .unwrap_err();
    assert!(e.message.contains("flutes"), "{e}");
}

fn ball6() -> ToolRecord {
    ToolRecord {
        spec: "ball:d=6".into(),
        cutter: parse_tool_spec("ball:d=6").unwrap(),
    }
}

/// From (10, 0, 0): a quarter arc about +Z, a half arc about +Y, a helix about +X.
fn arcs() -> Toolpath {
    let mut tp = Toolpath::new(
        ball6(),
        vec![Pose::new(
            MoveKind::Rapid,
            DVec3::new(10.0, 0.0, 0.0),
            DVec3::Z,
            0.0,
        )],
    );
    tp.push_arc(DVec3::ZERO, DVec3::Z, FRAC_PI_2, MoveKind::Cut, 500.0, 0.01)
        .unwrap();
    tp.push_arc(
        DVec3::new(0.0, 10.0, 5.0),
        DVec3::Y,
        -PI,
        MoveKind::Cut,
        500.0,
        0.01,
    )
    .unwrap();
    tp.push_helix(
        DVec3::new(0.0, 0.0, 3.0),
        DVec3::X,
        2.5 * TAU,
        4.0,
        MoveKind::Cut,
        400.0,
        0.005,
    )
    .unwrap();
    tp
}

#[test]
fn arcs_and_helices_sample_within_the_chord_tolerance_and_end_where_a_rotation_puts_them() {
    let tp = arcs();
    assert_eq!(tp.exact.len(), 3);
    // Independent reference: glam's quaternion rotation about the normal.
    let rot =
        |n: DVec3, a: f64, p: DVec3, c: DVec3| c + glam::DQuat::from_axis_angle(n, a) * (p - c);
    let e0 = rot(DVec3::Z, FRAC_PI_2, DVec3::new(10.0, 0.0, 0.0), DVec3::ZERO);
    assert!(tp.poses[tp.exact[0].to].tip.distance(e0) < 1e-12);
    assert!(e0.distance(DVec3::new(0.0, 10.0, 0.0)) < 1e-12);
    // The second arc starts at (0, 10, 0) about (0, 10, 5): radius 5 in the ZX plane.
    let e1 = rot(DVec3::Y, -PI, e0, DVec3::new(0.0, 10.0, 5.0));
    assert!(tp.poses[tp.exact[1].to].tip.distance(e1) < 1e-12, "{e1}");
    let start2 = tp.poses[tp.exact[2].from].tip;
    let e2 = rot(DVec3::X, 2.5 * TAU, start2, DVec3::new(start2.x, 0.0, 3.0)) + DVec3::X * 4.0;
    assert!(tp.poses[tp.exact[2].to].tip.distance(e2) < 1e-9, "{e2}");
    // Every chord within tolerance: the chord midpoint is within tol of the circle (planar arcs).
    for (s, tol) in tp.exact.iter().zip([0.01, 0.01, 0.005]) {
        let ExactMove::Arc(a) = s.exact else { panic!() };
        let start = tp.poses[s.from].tip;
        let r = a.radius_mm(start);
        for w in tp.poses[s.from..=s.to].windows(2) {
            let mid = 0.5 * (w[0].tip + w[1].tip);
            let d = mid - a.centre;
            let radial = (d - a.normal * d.dot(a.normal)).length();
            assert!(
                r - radial <= tol + 1e-12 && r - radial >= 0.0,
                "{} {}",
                r,
                radial
            );
            let radial_end = {
                let d = w[1].tip - a.centre;
                (d - a.normal * d.dot(a.normal)).length()
            };
            assert!((radial_end - r).abs() < 1e-9);
        }
        // Not more chords than needed: one fewer would exceed the tolerance.
        let n = s.to - s.from;
        let step = a.sweep_rad.abs() / (n - 1) as f64;
        assert!(
            r * (1.0 - (step / 2.0).cos()) > tol,
            "{n} chords is more than needed"
        );
    }
    // The summary counts the sampled length: quarter of 2π·10 plus half of 2π·5 plus the helix.
    let helix_len = (start2.y.hypot(start2.z - 3.0) * 2.5 * TAU).hypot(4.0);
    let exact_len = 5.0 * PI + 5.0 * PI + helix_len;
    assert!(tp.summary.cut_length_mm < exact_len && tp.summary.cut_length_mm > exact_len * 0.999);
    assert!(tp.validate("x").is_ok());
}

#[test]
fn a_path_with_arcs_and_cycles_round_trips_exactly_through_json() {
    let mut tp = arcs();
    tp.push_cycle(CycleMove {
        cycle: CycleKind::Peck { peck_mm: 3.0 },
        surface: DVec3::new(20.0, 5.0, 0.0),
        axis: DVec3::Z,
        depth_mm: 7.0,
        clearance_mm: 2.0,
        retract_mm: 20.0,
        retract: CycleRetract::Initial,
        feed_mm_per_min: 100.0,
    })
    .unwrap();
    let text = tp.to_json().unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["exact"][0]["move"], "arc");
    assert_eq!(v["exact"][3]["move"], "cycle");
    assert_eq!(v["exact"][3]["cycle"]["type"], "peck");
    let (again, warnings) = Toolpath::from_json_with_warnings(&text, "a.json").unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    // serde_json writes the shortest text that names each f64; without its `float_roundtrip`
    // feature (a Cargo.toml change, not made here) it reads some 17-digit numbers back one unit
    // in the last place off. Everything else comes back as written.
    let ulps = |a: f64, b: f64| (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs();
    let v3 = |a: DVec3, b: DVec3| (0..3).map(|i| ulps(a[i], b[i])).max().unwrap_or(0);
    assert_eq!(again.exact.len(), tp.exact.len());
    for (a, b) in again.exact.iter().zip(&tp.exact) {
        assert_eq!((a.from, a.to), (b.from, b.to));
        match (a.exact, b.exact) {
            (ExactMove::Arc(x), ExactMove::Arc(y)) => {
                assert!(v3(x.centre, y.centre) <= 1 && v3(x.normal, y.normal) <= 1);
                assert!(ulps(x.sweep_rad, y.sweep_rad) <= 1 && ulps(x.helix_mm, y.helix_mm) <= 1);
            }
            (ExactMove::Cycle(x), ExactMove::Cycle(y)) => assert_eq!(x, y),
            _ => panic!("{a:?} read back as {b:?}"),
        }
    }
    for (k, (a, b)) in again.poses.iter().zip(&tp.poses).enumerate() {
        assert!(v3(a.tip, b.tip) <= 1 && a.axis == b.axis, "pose {k}");
        assert_eq!(
            (a.kind, a.feed_mm_per_min),
            (b.kind, b.feed_mm_per_min),
            "pose {k}"
        );
    }
    assert_eq!(again.poses.len(), tp.poses.len());
}

#[test]
fn a_file_written_before_exact_moves_still_reads() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/toolpath/before-exact-moves.json");
    let (tp, warnings) = Toolpath::load_with_warnings(&path).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(tp.exact.is_empty());
    assert_eq!(tp.poses.len(), 4);
    assert_eq!(tp.poses[2].contact, Some(ContactKind::Ball));
    // The file's summary, recomputed: 9 mm plunge at 300 + 10 mm at 600 + 9 mm rapid.
    assert!((tp.summary.estimated_time_s - 2.854).abs() < 1e-12);
    assert_eq!(tp.summary.gouge.map(|g| g.checked_poses), Some(4));
    assert_eq!(
        tp.moves(),
        vec![
            Move::Line { to: 1 },
            Move::Line { to: 2 },
            Move::Rapid { to: 3 }
        ]
    );
    // Written again, it has no `exact` key: old readers read it.
    assert!(!tp.to_json().unwrap().contains("\"exact\""));
}

/// A G83 as LinuxCNC's `rs274 -g` runs it (LinuxCNC 2.9, `G98 G83 X10 Y5 Z-7 R2 Q3 F100`
/// from Z20): the STRAIGHT_TRAVERSE / STRAIGHT_FEED Z values it prints.
const RS274_G83_Z: [(bool, f64); 9] = [
    (false, 2.0),
    (true, -1.0),
    (false, 2.0),
    (false, -0.746),
    (true, -4.0),
    (false, 2.0),
    (false, -3.746),
    (true, -7.0),
    (false, 20.0),
];
/// `G99 G73 X20 Z-7 R2 Q3` from Z20, as `rs274 -g` prints it.
const RS274_G73_Z: [(bool, f64); 7] = [
    (false, 2.0),
    (true, -1.0),
    (false, -0.746),
    (true, -4.0),
    (false, -3.746),
    (true, -7.0),
    (false, 2.0),
];

#[test]
fn peck_cycles_move_as_linuxcnc_runs_them() {
    for (kind, retract, reference) in [
        (
            CycleKind::Peck { peck_mm: 3.0 },
            CycleRetract::Initial,
            &RS274_G83_Z[..],
        ),
        (
            CycleKind::ChipBreak { peck_mm: 3.0 },
            CycleRetract::RPlane,
            &RS274_G73_Z[..],
        ),
    ] {
        let c = CycleMove {
            cycle: kind,
            surface: DVec3::new(10.0, 5.0, 0.0),
            axis: DVec3::Z,
            depth_mm: 7.0,
            clearance_mm: 2.0,
            retract_mm: 20.0,
            retract,
            feed_mm_per_min: 100.0,
        };
        let mut tp = Toolpath::new(ball6(), Vec::new());
        tp.push_cycle(c).unwrap();
        let got: Vec<(bool, f64)> = tp.poses[1..]
            .iter()
            .map(|p| (p.kind == MoveKind::Plunge, p.tip.z))
            .collect();
        assert_eq!(got.len(), reference.len(), "{got:?}");
        for (g, r) in got.iter().zip(reference) {
            assert_eq!(g.0, r.0);
            assert!((g.1 - r.1).abs() < 1e-12, "{got:?}");
        }
        assert!(tp.poses.iter().all(|p| p.tip.x == 10.0 && p.tip.y == 5.0));
    }
}

#[test]
fn exact_moves_that_disagree_with_their_poses_are_refused() {
    let mut tp = arcs();
    let to = tp.exact[0].to;
    tp.poses[to].tip.x += 0.01;
    let e = tp.validate("a.json").unwrap_err();
    assert_eq!(e.place, "exact move 0");
    let mut tp = arcs();
    tp.exact[1].from = 0;
    assert_eq!(tp.validate("a.json").unwrap_err().place, "exact move 1");
    let mut v: serde_json::Value = serde_json::from_str(&arcs().to_json().unwrap()).unwrap();
    v["exact"][2]["sweep_rad"] = serde_json::json!(0.0);
    let e = Toolpath::from_json(&v.to_string(), "a.json").unwrap_err();
    assert_eq!(
        (e.file.as_str(), e.place.as_str()),
        ("a.json", "exact move 2"),
        "{e}"
    );
    let mut tp = arcs();
    assert!(
        tp.push_arc(DVec3::ZERO, DVec3::Z, 1.0, MoveKind::Cut, 500.0, 0.0)
            .is_err()
    );
    assert!(
        tp.push_arc(DVec3::ZERO, DVec3::Z, 1.0, MoveKind::Cut, 500.0, 1e-300)
            .is_err()
    );
    assert!(
        tp.push_arc(DVec3::ZERO, DVec3::Z, f64::NAN, MoveKind::Cut, 500.0, 0.01)
            .is_err()
    );
    let bad = CycleMove {
        cycle: CycleKind::Peck { peck_mm: 0.0 },
        surface: DVec3::ZERO,
        axis: DVec3::Z,
        depth_mm: 5.0,
        clearance_mm: 2.0,
        retract_mm: 1.0,
        retract: CycleRetract::Initial,
        feed_mm_per_min: 100.0,
    };
    assert!(tp.push_cycle(bad).is_err());
}
