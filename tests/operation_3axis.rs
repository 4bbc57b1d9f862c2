//! Waterline and steep-and-shallow finishing as project operations: the same settings planned
//! through `talas plan` (the binary) and through `project::pipeline::compute` give the same
//! path, pose for pose and byte for byte in the saved JSON (but for the tool's spec text); the operations validate their
//! numbers and keep their settings through a project's JSON.

mod cli_common;

use std::path::Path;

use cli_common::{data, talas_json};
use talas::diagnostics::Progress;
use talas::import::{OpenOptions, open};
use talas::project::pipeline::compute;
use talas::project::{Operation, OperationKind, Project, ToolEntry};
use talas::strategies::waterline::Cut;
use talas::toolpath::{MoveKind, Toolpath};
use talas::tools::parse_tool_spec;

const TOOL: &str = "ball:d=6";
const SCALLOP_MM: f64 = 0.05;
const TOL_MM: f64 = 0.05;
const FEED: f64 = 1200.0;

fn op(kind: OperationKind, angle_deg: f64, cut: Cut) -> Operation {
    let mut op = Operation::new(kind, 0, 0);
    match &mut op {
        Operation::Waterline {
            scallop_mm,
            tolerance_mm,
            angle_rad,
            cut: c,
            feed_mm_per_min,
            ..
        }
        | Operation::SteepShallow {
            scallop_mm,
            tolerance_mm,
            angle_rad,
            cut: c,
            feed_mm_per_min,
            ..
        } => {
            *scallop_mm = SCALLOP_MM;
            *tolerance_mm = TOL_MM;
            *angle_rad = angle_deg.to_radians();
            *c = cut;
            *feed_mm_per_min = FEED;
        }
        _ => panic!("not a 3-axis finishing kind"),
    }
    op
}

fn project_with(op: Operation) -> Project {
    Project {
        tools: vec![ToolEntry {
            name: "T1".into(),
            cutter: parse_tool_spec(TOOL).expect("tool spec"),
        }],
        selected_tool: Some(0),
        operations: vec![op],
        ..Project::default()
    }
}

/// Plan `strategy` with the CLI and `op` with the pipeline on `part`; both paths must agree.
fn same_path(tag: &str, part: &Path, strategy: &str, op: Operation, angle: f64, pattern: &str) {
    let dir = std::env::temp_dir().join(format!("talas-op3-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cli_out = dir.join("cli.json");
    let doc = talas_json(&[
        "plan",
        part.to_str().unwrap(),
        "--tool",
        TOOL,
        "--strategy",
        strategy,
        "--scallop",
        &SCALLOP_MM.to_string(),
        "--tolerance",
        &TOL_MM.to_string(),
        "--angle",
        &angle.to_string(),
        "--pattern",
        pattern,
        "--feed",
        &FEED.to_string(),
        "--json",
        "-o",
        cli_out.to_str().unwrap(),
    ]);
    assert_eq!(doc["strategy"], strategy);
    let cli = Toolpath::load(&cli_out).expect("the CLI's path loads");

    let workpiece = open(
        part,
        &OpenOptions {
            chord_tol_mm: Some(TOL_MM),
        },
        &Progress::new(),
    )
    .expect("part reads");
    let project = project_with(op);
    let ours = compute(&project, 0, &workpiece, &Progress::new()).expect("pipeline plans");
    let tp = &ours.toolpath;

    let cuts = tp.poses.iter().filter(|p| p.kind == MoveKind::Cut).count();
    assert!(cuts > 100, "{strategy}: only {cuts} cutting poses");
    assert_eq!(tp.poses.len(), cli.poses.len(), "{strategy}: pose count");
    for (i, (a, b)) in tp.poses.iter().zip(&cli.poses).enumerate() {
        assert_eq!(a.kind, b.kind, "{strategy}: pose {i} kind");
        assert!(
            a.tip.distance(b.tip) <= 1e-12 && a.axis.distance(b.axis) <= 1e-12,
            "{strategy}: pose {i} tip {} vs {}",
            a.tip,
            b.tip
        );
        assert_eq!(
            a.feed_mm_per_min, b.feed_mm_per_min,
            "{strategy}: pose {i} feed"
        );
    }
    // The same cutter; the pipeline names it by its full spec (flute, shank, length), the CLI
    // by the spec typed. With the CLI's name, the saved files are the same bytes.
    assert_eq!(tp.tool.cutter, cli.tool.cutter, "{strategy}: cutter");
    assert_eq!(cli.tool.spec, TOOL);
    let mut tp = tp.clone();
    tp.tool.spec = cli.tool.spec.clone();
    let pipe_out = dir.join("pipeline.json");
    tp.save(&pipe_out).expect("saves");
    let (a, b) = (
        std::fs::read_to_string(&pipe_out).unwrap(),
        std::fs::read_to_string(&cli_out).unwrap(),
    );
    if let Some((i, (x, y))) = a
        .lines()
        .zip(b.lines())
        .enumerate()
        .find(|(_, (x, y))| x != y)
    {
        panic!(
            "{strategy}: saved JSON differs at line {}: {x} | {y}",
            i + 1
        );
    }
    assert_eq!(a.len(), b.len(), "{strategy}: saved JSON lengths");
}

#[test]
fn waterline_operation_plans_the_same_path_as_talas_plan() {
    let part = data("pocket-fillets.stl");
    let op = op(OperationKind::Waterline, 40.0, Cut::Conventional);
    same_path("wl", &part, "waterline", op, 40.0, "conventional");
}

#[test]
fn steep_shallow_operation_plans_the_same_path_as_talas_plan() {
    let part = data("pocket-fillets.stl");
    let op = op(OperationKind::SteepShallow, 50.0, Cut::Climb);
    same_path("ss", &part, "steep-shallow", op, 50.0, "climb");
}

#[test]
fn operations_keep_their_settings_through_json_and_refuse_bad_numbers() {
    let wl = op(OperationKind::Waterline, 40.0, Cut::Conventional);
    let ss = op(OperationKind::SteepShallow, 50.0, Cut::Climb);
    for o in [&wl, &ss] {
        let text = serde_json::to_string(o).unwrap();
        let back: Operation = serde_json::from_str(&text).unwrap();
        assert_eq!(&back, o, "{text}");
        assert!(o.validate().is_ok());
    }
    // And through the project file (TOML).
    let mut project = project_with(wl.clone());
    project.operations.push(ss.clone());
    let text = project.to_toml().expect("writes");
    let back = Project::from_toml(&text, Path::new("p.talas")).expect("reads");
    assert_eq!(back.operations, vec![wl.clone(), ss.clone()], "{text}");
    assert!(
        serde_json::to_string(&wl)
            .unwrap()
            .contains("\"kind\":\"waterline\"")
    );
    assert!(
        serde_json::to_string(&ss)
            .unwrap()
            .contains("\"kind\":\"steep_shallow\"")
    );
    // A steep/shallow threshold of 2° leaves no room for the 5° overlap band; 95° is no slope.
    let bad = [
        (
            op(OperationKind::SteepShallow, 2.0, Cut::Climb),
            "threshold",
        ),
        (op(OperationKind::Waterline, 95.0, Cut::Climb), "slope"),
    ];
    for (o, word) in bad {
        let e = o.validate().unwrap_err();
        assert!(e.contains(word) && e.contains('°'), "{e}");
    }
    let mut neg = wl.clone();
    if let Operation::Waterline { scallop_mm, .. } = &mut neg {
        *scallop_mm = -0.1;
    }
    assert!(neg.validate().unwrap_err().contains("scallop height (mm)"));
    // An operation saved before these kinds existed still reads.
    let old = r#"{"kind":"raster","name":"R","tool":0,"angle_rad":0.0}"#;
    let raster: Operation = serde_json::from_str(old).unwrap();
    assert_eq!(raster.kind(), OperationKind::Raster);
}
