//! The project pipeline (`project::pipeline::compute`): an operation of a project run end to end
//! on the default part, checked against closed-form contact conditions and the drop-cutter, not
//! against itself.

mod common;

use std::path::Path;

use common::data;
use glam::{DVec2, DVec3};
use talas::diagnostics::Progress;
use talas::geometry::bvh::MeshBvh;
use talas::import::{OpenOptions, Workpiece, open};
use talas::project::pipeline::{ComputeError, compute, cutting_runs};
use talas::project::{Operation, OperationKind, Project, ToolEntry};
use talas::toolpath::MoveKind;
use talas::tools::dropcutter::drop_cutter;
use talas::tools::parse_tool_spec;

fn hills() -> Workpiece {
    let options = OpenOptions {
        chord_tol_mm: Some(0.01),
    };
    open(&data("bicubic-hills.stp"), &options, &Progress::new()).expect("bicubic-hills reads")
}

fn project_with(tool: &str, op: Operation) -> Project {
    Project {
        tools: vec![ToolEntry {
            name: "T1".into(),
            cutter: parse_tool_spec(tool).expect("tool spec"),
        }],
        selected_tool: Some(0),
        operations: vec![op],
        ..Project::default()
    }
}

#[test]
fn finishing_a_face_puts_the_ball_centre_one_radius_off_the_exact_surface() {
    let part = hills();
    let mut op = Operation::new(OperationKind::IsoScallop, 0, 0);
    if let Operation::Finish { options, .. } = &mut op {
        options.scallop = 0.05;
        options.tolerance = 0.02;
    }
    let project = project_with("ball:d=6", op);
    let out = compute(&project, 0, &part, &Progress::new()).expect("iso-scallop plans");
    let tp = &out.toolpath;
    assert!(out.passes >= 5, "{} passes", out.passes);
    assert_eq!(cutting_runs(tp), out.passes, "one cutting run per pass");
    let surface = part.surface(0).expect("surface");
    let rect = surface.domain();
    let r = 3.0;
    // tolerance 0.02 mm: poses are raised by 0.01 mm.
    let mut checked = 0;
    for pose in tp.poses.iter().filter(|p| p.kind == MoveKind::Cut) {
        let centre = pose.tip + r * pose.axis;
        // The contact is on the surface, and the ball centre is one radius from the surface
        // (closest point = contact): the closed-form condition of a ball touching a surface.
        let cc = pose.cc.expect("cutting poses carry the contact");
        let on = surface.closest_point(cc, rect, None);
        assert!(
            on.distance < 1e-6,
            "contact {cc} is {} mm off the surface",
            on.distance
        );
        // Poses sit on the surface raised by half the chord tolerance (the one-sided tolerance
        // of `strategies::finish::stepping`), so the centre is R + ε/2 from the surface.
        let nearest = surface.closest_point(centre, rect, None);
        assert!(
            (nearest.distance - (r + 0.01)).abs() < 1e-5,
            "ball centre {} mm from the surface (R + ε/2 = {})",
            nearest.distance,
            r + 0.01
        );
        checked += 1;
    }
    assert!(checked > 100, "{checked} cutting poses");
    let scallop = tp
        .summary
        .predicted_max_scallop_mm
        .expect("predicted scallop");
    assert!(scallop <= 0.05 + 1e-9, "predicted {scallop} mm > 0.05 mm");
    // Deterministic: the same project gives the same path.
    let again = compute(&project, 0, &part, &Progress::new()).expect("plans again");
    assert_eq!(again.toolpath.poses, tp.poses);
}

#[test]
fn raster_never_gouges_and_touches_the_part_where_it_cuts() {
    let part = hills();
    let bvh = MeshBvh::new(&part.mesh).expect("bvh");
    let mut raster = Operation::new(OperationKind::Raster, 0, 0);
    if let Operation::Raster { scallop_mm, .. } = &mut raster {
        *scallop_mm = 0.05;
    }
    let project = project_with("ball:d=6", raster);
    let tp = compute(&project, 0, &part, &Progress::new())
        .expect("raster plans")
        .toolpath;
    let cuts: Vec<_> = tp
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut)
        .collect();
    assert!(cuts.len() > 100);
    let mut touching = 0;
    for p in &cuts {
        let d = bvh
            .closest_point(p.tip + 3.0 * p.axis)
            .expect("closest point")
            .distance;
        assert!(d >= 3.0 - 1e-6, "ball centre {d} mm from the mesh: gouge");
        if d < 3.0 + 0.02 {
            touching += 1;
        }
    }
    assert!(
        touching * 10 >= cuts.len() * 9,
        "only {touching} of {} cutting poses touch the part",
        cuts.len()
    );
}

#[test]
fn roughing_leaves_the_allowance_above_the_drop_cutter_height() {
    let part = hills();
    let bvh = MeshBvh::new(&part.mesh).expect("bvh");
    // Roughing with a flat end mill: every cutting pose is at or above the drop-cutter height
    // plus the allowance, less the roughing grid's documented slack (half the allowance).
    let mut rough = Operation::new(OperationKind::Rough, 0, 0);
    if let Operation::Rough {
        step_down_mm,
        tolerance_mm,
        ..
    } = &mut rough
    {
        // A coarse grid (0.3 mm) and few levels keep the debug-build test short.
        *step_down_mm = 4.0;
        *tolerance_mm = 0.3;
    }
    let project = project_with("flat:d=10", rough);
    let out = compute(&project, 0, &part, &Progress::new()).expect("roughing plans");
    assert!(out.passes > 0);
    let cuts: Vec<_> = out
        .toolpath
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut)
        .collect();
    let xy: Vec<DVec2> = cuts.iter().map(|p| p.tip.truncate()).collect();
    let drops = drop_cutter(&bvh, &part.mesh, &project.tools[0].cutter, &xy);
    let allowance = 0.3;
    let mut worst = f64::INFINITY;
    for (p, d) in cuts.iter().zip(&drops) {
        if let Some(d) = d {
            worst = worst.min(p.tip.z - (d.z + allowance));
        }
    }
    assert!(
        worst >= -0.5 * allowance - 1e-6,
        "roughing cuts {worst} mm into the allowance"
    );
    assert!(
        cuts.iter().all(|p| p.axis == DVec3::Z),
        "roughing is 3-axis"
    );
}

#[test]
fn bad_operations_give_errors_naming_the_operation() {
    let part = hills();
    let project = project_with("ball:d=6", Operation::new(OperationKind::IsoPlanar, 0, 7));
    match compute(&project, 0, &part, &Progress::new()) {
        Err(ComputeError::Face { operation, message }) => {
            assert_eq!(operation, "Iso-planar finishing");
            assert!(message.contains("no face number 7"), "{message}");
        }
        other => panic!("expected a face error, got {other:?}"),
    }
    let mesh_only = Workpiece::from_mesh(Path::new("hills.stl"), part.mesh.clone(), Vec::new());
    let project = project_with("ball:d=6", Operation::new(OperationKind::IsoScallop, 0, 0));
    let e = compute(&project, 0, &mesh_only, &Progress::new()).expect_err("no surface");
    assert!(e.to_string().contains("STEP"), "{e}");
    let cancelled = Progress::new();
    cancelled.cancel();
    assert_eq!(
        compute(&project, 0, &part, &cancelled).expect_err("cancelled"),
        ComputeError::Cancelled
    );
    let cone = project_with(
        "cone:d=6,angle=30",
        Operation::new(OperationKind::IsoScallop, 0, 0),
    );
    let e = compute(&cone, 0, &part, &Progress::new()).expect_err("cone refused");
    assert!(matches!(e, ComputeError::Plan { .. }), "{e:?}");
    assert!(matches!(
        compute(&cone, 3, &part, &Progress::new()),
        Err(ComputeError::NoOperation { index: 3, count: 1 })
    ));
}

#[test]
fn the_simulated_stock_keeps_the_predicted_scallop_and_no_gouge() {
    use talas::project::simulate::{SimulationSettings, simulate_toolpath};
    let part = hills();
    let mut op = Operation::new(OperationKind::Raster, 0, 0);
    if let Operation::Raster { scallop_mm, .. } = &mut op {
        *scallop_mm = 0.1;
    }
    // Flutes longer than the part is deep, so the cutter clears everything above the surface.
    let project = project_with("ball:d=6,flute=40,length=60", op);
    let out = compute(&project, 0, &part, &Progress::new()).expect("plans");
    let predicted = out
        .toolpath
        .summary
        .predicted_max_scallop_mm
        .expect("raster predicts its scallop");
    let settings = SimulationSettings {
        resolution_mm: Some(1.0),
        ..SimulationSettings::default()
    };
    let sim = simulate_toolpath(
        &project.stock,
        &part.mesh,
        &out.toolpath,
        &project.tools[0].cutter,
        &settings,
        &Progress::new(),
    )
    .expect("simulates");
    assert!(sim.report.removed_volume_mm3 > 1e5, "{:?}", sim.report);
    assert_eq!(sim.deviation_mm.len(), sim.stock_mesh.positions.len());
    // Material left over the part: at most the predicted scallop plus the raster's chord
    // tolerance (0.01 mm); the part mesh (chord 0.01 mm) may stand up to 0.01 mm off the exact
    // surface either way.
    assert!(
        sim.remaining_p99_mm <= predicted + 0.01 + 0.01,
        "p99 remaining {} mm, predicted {predicted} mm",
        sim.remaining_p99_mm
    );
    assert!(
        sim.remaining_p99_mm >= 0.3 * predicted,
        "scallops exist: {} mm",
        sim.remaining_p99_mm
    );
    assert!(sim.max_gouge_mm <= 0.012, "gouge {} mm", sim.max_gouge_mm);
}

#[test]
fn posting_writes_program_coordinates_under_the_work_offset() {
    use talas::project::Frame;
    use talas::project::posting::post_operation;
    let part = hills();
    let mut op = Operation::new(OperationKind::Raster, 0, 0);
    if let Operation::Raster { scallop_mm, .. } = &mut op {
        *scallop_mm = 0.2;
    }
    let mut project = project_with("ball:d=6", op);
    let tp = compute(&project, 0, &part, &Progress::new())
        .expect("plans")
        .toolpath;
    let at_zero = post_operation(&project, 0, &tp, 3).expect("posts");
    project.setups[0].frame = Frame {
        work_offset: 2,
        origin_mm: [10.0, -20.0, 5.0],
        ..Frame::default()
    };
    let shifted = post_operation(&project, 0, &tp, 3).expect("posts");
    assert!(!at_zero.text.contains("G55") && shifted.text.contains("G55"));
    assert!(shifted.text.contains("T3"));
    // The line that reaches each pose holds X, Y, Z of its tip less the origin.
    let word = |line: &str, c: char| -> Option<f64> {
        line.split_whitespace()
            .find_map(|w| w.strip_prefix(c).and_then(|v| v.parse::<f64>().ok()))
    };
    let lines: Vec<&str> = shifted.text.lines().collect();
    let mut checked = 0;
    for (k, line) in shifted
        .line_of_each_pose(tp.poses.len())
        .iter()
        .enumerate()
        .filter_map(|(k, l)| Some((k, (*l)?)))
    {
        let Some(text) = lines.get(line) else {
            continue;
        };
        let tip = tp.poses[k].tip;
        // Words are modal: only the coordinates that change are written.
        if let Some(x) = word(text, 'X') {
            assert!((x - (tip.x - 10.0)).abs() < 1e-3, "{text}: x vs {}", tip.x);
            checked += 1;
        }
        if let Some(y) = word(text, 'Y') {
            assert!((y - (tip.y + 20.0)).abs() < 1e-3, "{text}: y vs {}", tip.y);
        }
        if let Some(z) = word(text, 'Z') {
            assert!((z - (tip.z - 5.0)).abs() < 1e-3, "{text}: z vs {}", tip.z);
        }
    }
    assert!(checked > 50, "{checked} lines checked");
}

#[test]
fn roughing_then_finishing_on_one_stock_leaves_the_allowance_then_the_scallop() {
    use talas::project::simulate::{SimulationSettings, simulate_toolpaths};
    let part = hills();
    let mut rough = Operation::new(OperationKind::Rough, 0, 0);
    if let Operation::Rough {
        step_down_mm,
        tolerance_mm,
        stock_to_leave_mm,
        ..
    } = &mut rough
    {
        *step_down_mm = 4.0;
        *tolerance_mm = 0.5;
        *stock_to_leave_mm = 0.5;
    }
    let mut finish = Operation::new(OperationKind::Raster, 1, 0);
    if let Operation::Raster { scallop_mm, .. } = &mut finish {
        *scallop_mm = 0.1;
    }
    let mut project = project_with("flat:d=10,flute=40,length=60", rough);
    project.tools.push(ToolEntry {
        name: "T2".into(),
        cutter: parse_tool_spec("ball:d=6,flute=40,length=60").expect("spec"),
    });
    project.operations.push(finish);
    let r = compute(&project, 0, &part, &Progress::new()).expect("roughs");
    let f = compute(&project, 1, &part, &Progress::new()).expect("finishes");
    let settings = SimulationSettings {
        resolution_mm: Some(1.0),
        ..SimulationSettings::default()
    };
    let (t0, t1) = (&project.tools[0].cutter, &project.tools[1].cutter);
    let roughed = simulate_toolpaths(
        &project.stock,
        &part.mesh,
        &[(&r.toolpath, t0)],
        &settings,
        &Progress::new(),
    )
    .expect("simulates roughing");
    let both = simulate_toolpaths(
        &project.stock,
        &part.mesh,
        &[(&r.toolpath, t0), (&f.toolpath, t1)],
        &settings,
        &Progress::new(),
    )
    .expect("simulates both");
    // Roughing leaves about the allowance (0.5 mm; the roughing grid may leave up to one grid
    // spacing more, and the flat end mill leaves steps between levels on slopes).
    assert!(
        roughed.remaining_p99_mm >= 0.3,
        "roughing p99 {} mm",
        roughed.remaining_p99_mm
    );
    assert!(
        roughed.max_gouge_mm <= 0.012,
        "roughing gouge {}",
        roughed.max_gouge_mm
    );
    // With no stock defined, roughing and simulation start from the same default stock (the
    // part's box grown by 2 mm), so roughing leaves no uncut rim around the part and nothing
    // above it.
    let b = part.mesh.bbox();
    let mut ring = 0;
    for p in &roughed.stock_mesh.positions {
        assert!(
            p.z <= b.max.z + 0.5 + 1e-6,
            "material at {p} stands above the part's top {} + allowance",
            b.max.z
        );
        if p.x < b.min.x || p.x > b.max.x || p.y < b.min.y || p.y > b.max.y {
            ring += 1;
        }
    }
    assert!(
        ring > 100,
        "the default stock's margin is simulated ({ring} rays)"
    );
    // Finishing the roughed stock leaves the raster's scallop.
    let predicted = f
        .toolpath
        .summary
        .predicted_max_scallop_mm
        .expect("prediction");
    assert!(
        both.remaining_p99_mm <= predicted + 0.02,
        "after finishing p99 {} mm, predicted {predicted} mm",
        both.remaining_p99_mm
    );
    assert_eq!(both.reports.len(), 2);
    assert!(both.reports[1].removed_volume_mm3 > 0.0);
    let sum: f64 = both.reports.iter().map(|r| r.removed_volume_mm3).sum();
    assert!((both.report.removed_volume_mm3 - sum).abs() < 1e-6);
}

#[test]
fn the_workstation_simulation_and_talas_simulate_report_the_same_deviation() {
    use talas::import::stl::{StlFormat, StlOptions, read_stl, save_stl};
    use talas::project::Stock;
    use talas::project::simulate::{SimulationSettings, simulate_toolpath};
    let part = hills();
    let mut op = Operation::new(OperationKind::Raster, 0, 0);
    if let Operation::Raster { scallop_mm, .. } = &mut op {
        *scallop_mm = 0.2;
    }
    // Flutes longer than the part is deep, so the cutter clears everything above the surface.
    let mut project = project_with("ball:d=6,flute=40,length=60", op);
    let tp = compute(&project, 0, &part, &Progress::new())
        .expect("plans")
        .toolpath;
    let dir = std::env::temp_dir().join(format!("talas-pipeline-dev-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (stl, path) = (dir.join("hills.stl"), dir.join("raster.json"));
    // The part both measure against: the same STL file (single precision, welded on reading).
    save_stl(&stl, &part.mesh, StlFormat::Binary).unwrap();
    let mesh = read_stl(&stl, &StlOptions::default()).unwrap().mesh;
    tp.save(&path).unwrap();
    let b = mesh.bbox();
    let (min, max) = (
        [b.min.x - 2.0, b.min.y - 2.0, b.min.z - 2.0],
        [b.max.x + 2.0, b.max.y + 2.0, b.max.z + 2.0],
    );
    project.stock = Stock::Box {
        min_mm: min,
        max_mm: max,
    };
    let settings = SimulationSettings {
        resolution_mm: Some(0.5),
        ..SimulationSettings::default()
    };
    let sim = simulate_toolpath(
        &project.stock,
        &mesh,
        &tp,
        &project.tools[0].cutter,
        &settings,
        &Progress::new(),
    )
    .expect("simulates");
    let stock = format!(
        "box:{},{},{},{},{},{}",
        min[0], min[1], min[2], max[0], max[1], max[2]
    );
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(["simulate", path.to_str().unwrap(), "--stock", &stock])
        .args([
            "--resolution",
            "0.5",
            "--part",
            stl.to_str().unwrap(),
            "--json",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let top = &doc["top_deviation"];
    // The bicubic hills are an open sheet: the side is the normal's.
    assert_eq!(top["closed_part"].as_bool(), Some(false));
    assert_eq!(top["points"].as_u64(), Some(sim.deviation_mm.len() as u64));
    // Equal up to the last digit JSON keeps.
    let same = |json: &serde_json::Value, v: f64| {
        let j = json.as_f64().expect("a number");
        (j - v).abs() <= 1e-14 * v.abs().max(1e-300)
    };
    assert!(same(&top["max_gouge_mm"], sim.max_gouge_mm), "{top}");
    assert!(
        same(&top["remaining_p99_mm"], sim.remaining_p99_mm),
        "{top}"
    );
    assert!(same(
        &doc["removed_volume_mm3"],
        sim.report.removed_volume_mm3
    ));
    // And both are plausible: scallops below the 0.2 mm asked plus tolerances, no gouge.
    assert!(
        sim.remaining_p99_mm > 0.02 && sim.remaining_p99_mm < 0.25,
        "{}",
        sim.remaining_p99_mm
    );
    assert!(sim.max_gouge_mm < 0.02, "{}", sim.max_gouge_mm);
    // The whole-surface statistics of an open sheet measure only points above or below it.
    let dev = &doc["deviation"];
    assert_eq!(dev["closed_part"].as_bool(), Some(false));
    assert!(dev["max_gouge_mm"].as_f64().unwrap() < 0.02, "{dev}");
    std::fs::remove_dir_all(&dir).unwrap();
}
