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
