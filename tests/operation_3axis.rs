//! `talas plan` and the project pipeline are one path: the same settings planned through the
//! binary and through `project::pipeline::compute` give the same path, pose for pose and byte
//! for byte in the saved JSON, for every operation kind (waterline, steep-and-shallow, raster,
//! Z-level roughing with a stock, 5-axis face finishing). Waterline and steep-and-shallow
//! operations validate their numbers and keep their settings through a project's JSON.

mod common;

use std::path::Path;

use common::{data, talas_json};
use talas::diagnostics::Progress;
use talas::import::{OpenOptions, open};
use talas::project::pipeline::compute;
use talas::project::{Operation, OperationKind, Project, ToolEntry};
use talas::strategies::waterline::{Cut, Entry};
use talas::toolpath::{MoveKind, Toolpath};
use talas::tools::parse_tool_spec;

const TOOL: &str = "ball:d=6";
// Coarse settings keep the file quick in the debug build; the checks compare two planners of
// the same path, which does not need a fine one.
const SCALLOP_MM: f64 = 0.2;
const TOL_MM: f64 = 0.1;
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
    let (scallop, tol, feed, angle) = (
        SCALLOP_MM.to_string(),
        TOL_MM.to_string(),
        FEED.to_string(),
        angle.to_string(),
    );
    let args = [
        "--strategy",
        strategy,
        "--scallop",
        &scallop,
        "--tolerance",
        &tol,
        "--angle",
        &angle,
        "--pattern",
        pattern,
        "--feed",
        &feed,
    ];
    same_path_as(tag, part, &args, project_with(op), Some(TOL_MM), 100);
}

/// `talas plan PART --tool TOOL ARGS` and the pipeline on `project` (the part read at chord
/// `chord_mm`, as the CLI reads it) give the same path, pose for pose and byte for byte in the
/// saved JSON, with more than `min_cuts` cutting poses.
fn same_path_as(
    tag: &str,
    part: &Path,
    args: &[&str],
    project: Project,
    chord_mm: Option<f64>,
    min_cuts: usize,
) {
    same_path_as_with(tag, part, TOOL, args, project, chord_mm, min_cuts);
}

/// [`same_path_as`] with the CLI's tool `tool`.
fn same_path_as_with(
    tag: &str,
    part: &Path,
    tool: &str,
    args: &[&str],
    project: Project,
    chord_mm: Option<f64>,
    min_cuts: usize,
) {
    let dir = std::env::temp_dir().join(format!("talas-op3-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cli_out = dir.join("cli.json");
    let mut cli_args = vec!["plan", part.to_str().unwrap(), "--tool", tool];
    cli_args.extend_from_slice(args);
    cli_args.extend_from_slice(&["--json", "-o", cli_out.to_str().unwrap()]);
    let doc = talas_json(&cli_args);
    let strategy = doc["strategy"].as_str().unwrap_or("?").to_string();
    let cli = Toolpath::load(&cli_out).expect("the CLI's path loads");

    let workpiece = open(
        part,
        &OpenOptions {
            chord_tol_mm: chord_mm,
        },
        &Progress::new(),
    )
    .expect("part reads");
    let ours = compute(&project, 0, &workpiece, &Progress::new()).expect("pipeline plans");
    let tp = &ours.toolpath;

    let cuts = tp.poses.iter().filter(|p| p.kind == MoveKind::Cut).count();
    assert!(cuts > min_cuts, "{strategy}: only {cuts} cutting poses");
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
    // The same cutter, named by its full spec in both.
    assert_eq!(tp.tool, cli.tool, "{strategy}: tool");
    assert_eq!(doc["passes"], ours.passes, "{strategy}: passes");
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
    let _ = std::fs::remove_dir_all(&dir);
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

/// Raster finishing: the CLI's options (one-way, angle, clearance) map onto the operation.
#[test]
fn raster_operation_plans_the_same_path_as_talas_plan() {
    let op = Operation::Raster {
        name: "raster".into(),
        tool: 0,
        scallop_mm: 0.2,
        angle_rad: 30f64.to_radians(),
        one_way: true,
        tolerance_mm: TOL_MM,
        feed_mm_per_min: FEED,
        clearance_mm: 8.0,
        boundary: None,
    };
    let args = [
        "--strategy",
        "raster",
        "--scallop",
        "0.2",
        "--tolerance",
        "0.1",
        "--angle",
        "30",
        "--pattern",
        "oneway",
        "--feed",
        "1200",
        "--clearance",
        "8",
    ];
    let part = data("pocket-fillets.stl");
    same_path_as("ra", &part, &args, project_with(op), Some(TOL_MM), 100);
}

/// Z-level roughing: the one `--stock` syntax and the project's stock, separate wall and floor
/// allowances, flat levels off, a clearance.
#[test]
fn roughing_operation_plans_the_same_path_as_talas_plan() {
    let op = Operation::Rough {
        name: "zlevel-rough".into(),
        tool: 0,
        step_down_mm: 4.0,
        step_over_fraction: 0.5,
        stock_to_leave_mm: 0.4,
        stock_to_leave_axial_mm: Some(0.2),
        tolerance_mm: 0.25,
        feed_mm_per_min: FEED,
        flat_levels: false,
        clearance_mm: 3.0,
    };
    let mut project = project_with(op);
    project.stock = talas::project::Stock::Cylinder {
        base_mm: [50.0, 40.0, 0.0],
        radius_mm: 70.0,
        height_mm: 33.0,
    };
    let args = [
        "--strategy",
        "zlevel-rough",
        "--stock",
        "cylinder:50,40,70,33,0",
        "--step-down",
        "4",
        "--step-over",
        "0.5",
        "--stock-to-leave",
        "0.4",
        "--stock-to-leave-axial",
        "0.2",
        "--no-flat-levels",
        "--tolerance",
        "0.25",
        "--feed",
        "1200",
        "--clearance",
        "3",
    ];
    let part = data("pocket-fillets.stl");
    same_path_as("zr", &part, &args, project, Some(0.25), 100);
}

/// 5-axis iso-scallop finishing of one exact face: the CLI reads the part with the reader's
/// default tessellation and plans the face through the pipeline.
#[test]
fn face_finishing_operation_plans_the_same_path_as_talas_plan() {
    let mut op = Operation::new(OperationKind::IsoScallop, 0, 0);
    if let Operation::Finish { options, .. } = &mut op {
        options.scallop = 0.2;
        options.tolerance = 0.05;
        options.feed = FEED;
        options.axis = talas::strategies::finish::axis::AxisMode::Normal {
            lead: 5f64.to_radians(),
            tilt: 0.0,
        };
    }
    let args = [
        "--strategy",
        "iso-scallop",
        "--scallop",
        "0.2",
        "--tolerance",
        "0.05",
        "--feed",
        "1200",
        "--lead",
        "5",
    ];
    let part = data("bicubic-hills.stp");
    same_path_as("is", &part, &args, project_with(op), None, 100);
}

/// Pencil finishing: a Ø12 ball in pocket-fillets' R5 corners, the corner angle mapped.
#[test]
fn pencil_operation_plans_the_same_path_as_talas_plan() {
    let op = Operation::Pencil {
        name: "pencil".into(),
        tool: 0,
        angle_rad: 25f64.to_radians(),
        tolerance_mm: TOL_MM,
        feed_mm_per_min: FEED,
        clearance_mm: 6.0,
        boundary: None,
    };
    let mut project = project_with(op);
    project.tools[0].cutter = parse_tool_spec("ball:d=12").expect("tool");
    let args = [
        "--strategy",
        "pencil",
        "--angle",
        "25",
        "--tolerance",
        "0.1",
        "--feed",
        "1200",
        "--clearance",
        "6",
    ];
    let part = data("pocket-fillets.stl");
    same_path_as_with("pe", &part, "ball:d=12", &args, project, Some(TOL_MM), 20);
}

/// Rest finishing after a Ø12 ball: the reference tool is the project's second tool.
#[test]
fn rest_operation_plans_the_same_path_as_talas_plan() {
    let op = Operation::Rest {
        name: "rest".into(),
        tool: 0,
        reference_tool: 1,
        from_stock: false,
        scallop_mm: SCALLOP_MM,
        tolerance_mm: TOL_MM,
        feed_mm_per_min: FEED,
        clearance_mm: 5.0,
        boundary: None,
    };
    let mut project = project_with(op);
    project.tools.push(ToolEntry {
        name: "T2".into(),
        cutter: parse_tool_spec("ball:d=12").expect("tool"),
    });
    let args = [
        "--strategy",
        "rest",
        "--reference-tool",
        "ball:d=12",
        "--scallop",
        "0.2",
        "--tolerance",
        "0.1",
        "--feed",
        "1200",
    ];
    let part = data("pocket-fillets.stl");
    same_path_as("re", &part, &args, project, Some(TOL_MM), 100);
}

/// A rest operation's reference tool is a library index like its tool: refused when missing,
/// kept through inserts and removals, and a tool in use as a reference cannot be deleted.
#[test]
fn rest_reference_tool_follows_the_library() {
    use talas::project::Edit;
    let mut project = project_with(Operation::new(OperationKind::Rest, 0, 0));
    let big = ToolEntry {
        name: "Ball 12".into(),
        cutter: parse_tool_spec("ball:d=12").expect("tool"),
    };
    let mut rest = Operation::new(OperationKind::Rest, 0, 0);
    if let Operation::Rest { reference_tool, .. } = &mut rest {
        *reference_tool = 3;
    }
    let e = project
        .apply(Edit::AddOperation {
            index: 1,
            operation: rest,
        })
        .unwrap_err();
    assert!(e.to_string().contains('3'), "{e}");
    project
        .apply(Edit::AddTool {
            index: 1,
            tool: big.clone(),
        })
        .expect("adds");
    project
        .apply(Edit::SetOperation {
            index: 0,
            operation: match project.operations[0].clone() {
                Operation::Rest {
                    name,
                    tool,
                    scallop_mm,
                    tolerance_mm,
                    feed_mm_per_min,
                    clearance_mm,
                    ..
                } => Operation::Rest {
                    name,
                    tool,
                    reference_tool: 1,
                    from_stock: false,
                    scallop_mm,
                    tolerance_mm,
                    feed_mm_per_min,
                    clearance_mm,
                    boundary: None,
                },
                other => panic!("{other:?}"),
            },
        })
        .expect("sets");
    // A tool inserted before both shifts both.
    project
        .apply(Edit::AddTool {
            index: 0,
            tool: big,
        })
        .expect("adds");
    assert_eq!(project.operations[0].tools_used(), vec![1, 2]);
    let e = project.apply(Edit::RemoveTool { index: 2 }).unwrap_err();
    assert!(e.to_string().contains("used by"), "{e}");
    project
        .apply(Edit::RemoveTool { index: 0 })
        .expect("removes");
    assert_eq!(project.operations[0].tools_used(), vec![0, 1]);
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

/// A face group with the whole part as check and tilt-away: `talas plan --face 13,16,14
/// --check --tilt-away 30` and a finishing operation with the group and its (default)
/// tilt-away settings give the same path. The holder of this tool hits the pocket's wall
/// beside fillet face 13, so the path is tilted.
#[test]
fn face_group_operation_plans_the_same_path_as_talas_plan_face_list() {
    const HOLDER_TOOL: &str = "ball:d=6,flute=12,length=30,holder=12x30";
    let mut op = Operation::new(OperationKind::IsoParametric, 0, 13);
    if let Operation::Finish { options, group, .. } = &mut op {
        options.scallop = 0.1;
        options.tolerance = 0.02;
        options.feed = FEED;
        options.exact_check = true;
        *group = vec![16, 14];
    }
    assert_eq!(op.faces(), vec![13, 16, 14]);
    let args = [
        "--strategy",
        "iso-parametric",
        "--scallop",
        "0.1",
        "--tolerance",
        "0.02",
        "--feed",
        "1200",
        "--face",
        "13,16,14",
        "--check",
        "--tilt-away",
        "30",
    ];
    let mut project = project_with(op);
    project.tools[0].cutter = parse_tool_spec(HOLDER_TOOL).expect("tool spec");
    let part = data("pocket-fillets.stp");
    same_path_as_with("grp", &part, HOLDER_TOOL, &args, project.clone(), None, 60);
    // Tilted, the tool enters no other face.
    let workpiece = open(&part, &OpenOptions::default(), &Progress::new()).expect("part");
    let ours = compute(&project, 0, &workpiece, &Progress::new()).expect("pipeline plans");
    // Switched off, the holder enters the wall at many more poses (the tilt-away re-checks
    // its poses, not the moves between them: a move may keep a shallow hit).
    if let Operation::Finish { tilt_away, .. } = &mut project.operations[0] {
        tilt_away.enabled = false;
    }
    let plain = compute(&project, 0, &workpiece, &Progress::new()).expect("pipeline plans");
    let findings = talas::project::finish_group::findings(&plain);
    assert!(
        findings.iter().any(|f| matches!(
            f.kind,
            talas::project::finish_group::FindingKind::Collision(
                talas::tools::solid::ToolPart::Holder(_)
            )
        )),
        "{findings:?}"
    );
    assert!(
        plain.part_hits.len() > 4 * ours.part_hits.len().max(1),
        "{} hits tilted, {} not",
        ours.part_hits.len(),
        plain.part_hits.len()
    );
}

/// A boundary on a 3-axis finishing operation: a raster on pocket-fillets limited to a drawn
/// polygon (tool-centre rule) plans the same path through the pipeline as `talas plan
/// --boundary` given the polygon as a CSV file and as a DXF LWPOLYLINE, every cutting tip lies
/// inside the polygon, and the boundary survives the project file (a file without one loads
/// with none). By the contact rule on selected faces of the STEP part every cutting pose's
/// contact (the mesh point nearest the ball's centre) lies on those faces.
/// `cargo test --no-default-features --test operation_3axis boundary`
#[test]
fn a_boundary_limits_a_finishing_operation_by_centre_and_by_contact() {
    use talas::strategies::boundary::{Boundary, BoundaryRule, Region, in_polygon};
    let poly = vec![[20.0, 10.0], [70.0, 15.0], [60.0, 55.0], [25.0, 45.0]];
    let mut op = Operation::new(OperationKind::Raster, 0, 0);
    if let Operation::Raster { scallop_mm, .. } = &mut op {
        *scallop_mm = SCALLOP_MM;
    }
    *op.boundary_mut().unwrap() = Some(Boundary {
        region: Region::Polygon(poly.clone()),
        rule: BoundaryRule::ToolCentre,
    });
    let project = project_with(op.clone());
    let text = project.to_toml().unwrap();
    let back = Project::from_toml(&text, Path::new("b.toml")).unwrap();
    assert_eq!(back.operations[0], op);
    let mut plain = op.clone();
    *plain.boundary_mut().unwrap() = None;
    let plain_text = project_with(plain.clone()).to_toml().unwrap();
    assert!(!plain_text.contains("boundary"), "{plain_text}");
    let plain_back = Project::from_toml(&plain_text, Path::new("p.toml")).unwrap();
    assert_eq!(plain_back.operations[0].boundary(), None);

    let dir = std::env::temp_dir().join(format!("talas-op3-bnd-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("loop.csv");
    let mut csv_text = String::from("x,y\n");
    for p in &poly {
        csv_text.push_str(&format!("{},{}\n", p[0], p[1]));
    }
    std::fs::write(&csv, csv_text).unwrap();
    let dxf = dir.join("loop.dxf");
    let mut dxf_text = String::from("0\nSECTION\n2\nENTITIES\n0\nLWPOLYLINE\n8\n0\n90\n4\n70\n1\n");
    for p in &poly {
        dxf_text.push_str(&format!("10\n{}\n20\n{}\n", p[0], p[1]));
    }
    dxf_text.push_str("0\nENDSEC\n0\nEOF\n");
    std::fs::write(&dxf, dxf_text).unwrap();
    let part = data("pocket-fillets.stl");
    for (tag, file) in [("bcsv", &csv), ("bdxf", &dxf)] {
        let args = [
            "--strategy",
            "raster",
            "--scallop",
            "0.2",
            "--boundary",
            file.to_str().unwrap(),
        ];
        same_path_as(tag, &part, &args, project.clone(), None, 50);
    }
    let workpiece = open(&part, &OpenOptions::default(), &Progress::new()).unwrap();
    let tp = compute(&project, 0, &workpiece, &Progress::new())
        .unwrap()
        .toolpath;
    for p in tp.poses.iter().filter(|p| p.kind == MoveKind::Cut) {
        let xy = p.tip.truncate();
        // On the boundary itself (cut ends) or inside.
        let near_edge = (0..poly.len()).any(|i| {
            let (a, b) = (
                glam::DVec2::from(poly[i]),
                glam::DVec2::from(poly[(i + 1) % poly.len()]),
            );
            let t = ((xy - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            xy.distance(a + (b - a) * t) < 1e-6
        });
        assert!(
            in_polygon(&poly, xy) || near_edge,
            "cut tip {} outside",
            p.tip
        );
    }

    // Contact rule on the part's most upward-facing face (STEP, faces by number).
    let step = data("pocket-fillets.stp");
    let wp = open(&step, &OpenOptions::default(), &Progress::new()).unwrap();
    let mesh = &wp.mesh;
    let normal = |t: usize| {
        let [a, b, c] = mesh.triangles[t].map(|v| mesh.positions[v as usize]);
        (b - a).cross(c - a)
    };
    let faces = wp
        .face_of_triangle
        .iter()
        .max()
        .map_or(0, |m| *m as usize + 1);
    let mut up = vec![0.0; faces];
    for (t, f) in wp.face_of_triangle.iter().enumerate() {
        up[*f as usize] += normal(t).z.max(0.0);
    }
    let face = (0..faces).max_by(|a, b| up[*a].total_cmp(&up[*b])).unwrap();
    *op.boundary_mut().unwrap() = Some(Boundary {
        region: Region::Faces(vec![face]),
        rule: BoundaryRule::Contact,
    });
    let tp = compute(&project_with(op), 0, &wp, &Progress::new())
        .unwrap()
        .toolpath;
    let r = 3.0;
    let bvh = wp.bvh().unwrap();
    let mut n = 0;
    for p in tp.poses.iter().filter(|p| p.kind == MoveKind::Cut) {
        let c = p.tip + glam::DVec3::Z * r;
        let hit = bvh.closest_point(c).unwrap();
        if wp.face_of_triangle[hit.triangle] as usize == face {
            n += 1;
            continue;
        }
        // A contact on an edge of the face may be reported on the neighbour's triangle.
        let on_face = (0..mesh.triangles.len())
            .filter(|t| wp.face_of_triangle[*t] as usize == face)
            .any(|t| {
                let tri = mesh.triangles[t].map(|v| mesh.positions[v as usize]);
                common::geometry::closest_on_triangle(c, tri).distance(c) <= hit.distance + 1e-6
            });
        assert!(
            on_face,
            "contact {} of {} not on face {face}",
            hit.point, p.tip
        );
        n += 1;
    }
    assert!(n > 50, "{n} cutting poses on face {face}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `talas plan --strategy waterline --entry arc:2` and a waterline operation with a 2 mm arc
/// entry plan the same path; steep-shallow's ramp entry too; a bad
/// entry is refused in one line with exit code 2; the entry goes through the project file and
/// an operation saved without one reads as a plunge.
/// `cargo test --no-default-features --test operation_3axis entry`
#[test]
fn waterline_entry_through_the_cli_and_the_project() {
    let part = data("pocket-fillets.stl");
    let mut wl = op(OperationKind::Waterline, 40.0, Cut::Climb);
    let arc = Entry::Arc {
        radius_mm: Some(2.0),
    };
    if let Operation::Waterline { entry, .. } = &mut wl {
        *entry = arc;
    }
    let args = |strategy: &'static str, entry: &'static str| {
        [
            "--strategy",
            strategy,
            "--scallop",
            "0.2",
            "--tolerance",
            "0.1",
            "--angle",
            "40",
            "--feed",
            "1200",
            "--entry",
            entry,
        ]
    };
    same_path_as(
        "wl-arc",
        &part,
        &args("waterline", "arc:2"),
        project_with(wl.clone()),
        Some(TOL_MM),
        100,
    );
    let mut ss = op(OperationKind::SteepShallow, 50.0, Cut::Climb);
    let ramp = Entry::Ramp {
        angle_rad: 5f64.to_radians(),
    };
    if let Operation::SteepShallow { entry, .. } = &mut ss {
        *entry = ramp;
    }
    let mut ss_args = args("steep-shallow", "ramp").to_vec();
    ss_args[7] = "50";
    same_path_as(
        "ss-ramp",
        &part,
        &ss_args,
        project_with(ss.clone()),
        Some(TOL_MM),
        100,
    );

    let out_path =
        std::env::temp_dir().join(format!("talas-op3-entry-{}.json", std::process::id()));
    for bad in ["arc:-1", "ramp:60", "spiral", "arc:x"] {
        let out = common::talas(&[
            "plan",
            part.to_str().unwrap(),
            "--tool",
            TOOL,
            "--strategy",
            "waterline",
            "--entry",
            bad,
            "-o",
            out_path.to_str().unwrap(),
        ]);
        assert_eq!(out.status.code(), Some(2), "{bad}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(
            err.contains("--entry") && err.contains("pocket-fillets.stl"),
            "{err}"
        );
    }

    let mut project = project_with(wl.clone());
    project.operations.push(ss.clone());
    let text = project.to_toml().expect("writes");
    let back = Project::from_toml(&text, Path::new("p.talas")).expect("reads");
    assert_eq!(back.operations, vec![wl.clone(), ss], "{text}");
    let mut bad = wl.clone();
    if let Operation::Waterline { entry, .. } = &mut bad {
        *entry = Entry::Arc {
            radius_mm: Some(0.0),
        };
    }
    assert!(bad.validate().unwrap_err().contains("mm"));
    // Without an entry (as saved before entries existed): a plunge, and saved without one.
    let plain = op(OperationKind::Waterline, 40.0, Cut::Climb);
    let json = serde_json::to_string(&plain).unwrap();
    assert!(!json.contains("entry"), "{json}");
    let old: Operation = serde_json::from_str(&json).unwrap();
    assert!(matches!(
        old,
        Operation::Waterline {
            entry: Entry::Plunge,
            ..
        }
    ));
}
