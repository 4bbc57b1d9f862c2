use super::*;
use crate::tools::parse_tool_spec;

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
