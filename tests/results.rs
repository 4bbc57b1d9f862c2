//! The engine's result store (`project::Results`): a result is fresh exactly while the inputs
//! its computation reads are unchanged, and an unchanged project re-plans nothing (the store
//! counts the strategy's calls); the in-process stock is cut once per operation and shared.

use std::path::Path;

use glam::DVec3;
use talas::diagnostics::Progress;
use talas::geometry::mesh::TriMesh;
use talas::import::Workpiece;
use talas::project::{Operation, OperationKind, Project, Results, Stock, ToolEntry};
use talas::tools::parse_tool_spec;

/// A closed prism 20 mm long (y) over the profile of a V valley between two shoulders: a
/// floor at z = 0, the valley's flanks at 45° from x = 4 to 10 and 10 to 16, 6 mm high sides.
fn valley() -> TriMesh {
    let prof = [
        (0.0, 6.0),
        (4.0, 6.0),
        (10.0, 2.0),
        (16.0, 6.0),
        (20.0, 6.0),
    ];
    let mut pos = Vec::new();
    let mut tris = Vec::new();
    let mut id = |p: DVec3| -> u32 {
        pos.push(p);
        (pos.len() - 1) as u32
    };
    let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let mut quad = |a, b, c, d, tris: &mut Vec<[u32; 3]>| {
        let (a, b, c, d) = (id(a), id(b), id(c), id(d));
        tris.push([a, b, c]);
        tris.push([a, c, d]);
    };
    for w in prof.windows(2) {
        let ((x0, z0), (x1, z1)) = (w[0], w[1]);
        // top (outward +z), bottom, the two ends
        quad(
            v(x0, 0.0, z0),
            v(x1, 0.0, z1),
            v(x1, 20.0, z1),
            v(x0, 20.0, z0),
            &mut tris,
        );
        quad(
            v(x0, 0.0, 0.0),
            v(x0, 20.0, 0.0),
            v(x1, 20.0, 0.0),
            v(x1, 0.0, 0.0),
            &mut tris,
        );
        quad(
            v(x0, 0.0, 0.0),
            v(x1, 0.0, 0.0),
            v(x1, 0.0, z1),
            v(x0, 0.0, z0),
            &mut tris,
        );
        quad(
            v(x1, 20.0, 0.0),
            v(x0, 20.0, 0.0),
            v(x0, 20.0, z0),
            v(x1, 20.0, z1),
            &mut tris,
        );
    }
    // the two side walls
    quad(
        v(0.0, 0.0, 0.0),
        v(0.0, 0.0, 6.0),
        v(0.0, 20.0, 6.0),
        v(0.0, 20.0, 0.0),
        &mut tris,
    );
    quad(
        v(20.0, 0.0, 0.0),
        v(20.0, 20.0, 0.0),
        v(20.0, 20.0, 6.0),
        v(20.0, 0.0, 6.0),
        &mut tris,
    );
    TriMesh::new(pos, tris)
}

fn part() -> Workpiece {
    Workpiece::from_mesh(Path::new("valley.stl"), valley(), Vec::new())
}

/// Rough (flat Ø6), raster finish (ball Ø6), rest from the stock (ball Ø3, reference Ø6).
fn project() -> Project {
    let entry = |name: &str, s: &str| ToolEntry {
        name: name.into(),
        cutter: parse_tool_spec(s).unwrap(),
    };
    let mut rough = Operation::new(OperationKind::Rough, 0, 0);
    if let Operation::Rough { step_down_mm, .. } = &mut rough {
        *step_down_mm = 2.0;
    }
    let mut finish = Operation::new(OperationKind::Raster, 1, 0);
    if let Operation::Raster { scallop_mm, .. } = &mut finish {
        *scallop_mm = 0.05;
    }
    let mut rest = Operation::new(OperationKind::Rest, 2, 0);
    if let Operation::Rest {
        reference_tool,
        from_stock,
        scallop_mm,
        ..
    } = &mut rest
    {
        *reference_tool = 1;
        *from_stock = true;
        *scallop_mm = 0.05;
    }
    Project {
        tools: vec![
            entry("T1", "flat:d=6,flute=20,length=40"),
            entry("T2", "ball:d=6,flute=20,length=40"),
            entry("T3", "ball:d=3,flute=15,length=40"),
        ],
        selected_tool: Some(0),
        stock: Stock::Box {
            min_mm: [-2.0, -2.0, 0.0],
            max_mm: [22.0, 22.0, 8.0],
        },
        operations: vec![rough, finish, rest],
        ..Project::default()
    }
}

fn fresh(store: &Results, project: &Project, part: &Workpiece) -> Vec<bool> {
    let keys = Results::keys(project, part);
    (0..project.operations.len())
        .map(|k| store.fresh(&keys, k).is_some())
        .collect()
}

#[test]
fn an_unchanged_project_replans_nothing_and_the_stock_is_cut_once_per_operation() {
    let (project, part) = (project(), part());
    let store = Results::new();
    let p = Progress::new();
    // The rest reads the stock before it: the two earlier operations are planned and cut once.
    let rest = store.get_or_compute(&project, &part, 2, &p).unwrap();
    assert_eq!(store.computations(), 3);
    assert_eq!(store.stock_cuts(), 2);
    assert!(rest.toolpath.poses.len() > 2);
    let said = &rest.diagnostics[0].message;
    assert!(said.contains("simulated stock"), "{said}");
    for k in 0..3 {
        store.get_or_compute(&project, &part, k, &p).unwrap();
    }
    // The stock after the rest itself: one cut more, nothing planned again.
    let after = store.stock_after(&project, &part, 2, &p).unwrap();
    assert_eq!(store.computations(), 3);
    assert_eq!(store.stock_cuts(), 3);
    assert!(after.from_posted_runs, "{:?}", after.notes);
    let again = store.stock_before(&project, &part, 3, &p).unwrap();
    assert!(std::sync::Arc::ptr_eq(&after, &again));
    assert_eq!(store.stock_cuts(), 3);
    assert_eq!(fresh(&store, &project, &part), [true, true, true]);
    // Each stock removes material from the one before (the three tools all cut).
    let raw = store
        .stock_before(&project, &part, 0, &p)
        .unwrap()
        .volume_mm3();
    let v: Vec<f64> = (1..=3)
        .map(|k| {
            store
                .stock_before(&project, &part, k, &p)
                .unwrap()
                .volume_mm3()
        })
        .collect();
    assert!(raw > v[0] && v[0] > v[1] && v[1] > v[2], "{raw} {v:?}");
    // The box is 24 × 24 × 8 mm: on a grid of whole cells it is exact.
    assert!((raw - 24.0 * 24.0 * 8.0).abs() < 1e-6 * raw, "{raw}");
}

#[test]
fn changing_the_stock_makes_the_roughing_and_the_rest_stale_but_not_the_raster() {
    let (mut project, part) = (project(), part());
    let store = Results::new();
    let p = Progress::new();
    store.get_or_compute(&project, &part, 2, &p).unwrap();
    project.stock = Stock::Box {
        min_mm: [-3.0, -3.0, 0.0],
        max_mm: [23.0, 23.0, 9.0],
    };
    // The raster reads the part and its tool only.
    assert_eq!(fresh(&store, &project, &part), [false, true, false]);
    store.get_or_compute(&project, &part, 2, &p).unwrap();
    assert_eq!(store.computations(), 5);
}

#[test]
fn changing_an_earlier_operation_makes_the_rest_from_the_stock_stale() {
    let (mut project, part) = (project(), part());
    let store = Results::new();
    let p = Progress::new();
    store.get_or_compute(&project, &part, 2, &p).unwrap();
    if let Operation::Raster { scallop_mm, .. } = &mut project.operations[1] {
        *scallop_mm = 0.1;
    }
    assert_eq!(fresh(&store, &project, &part), [true, false, false]);
    // A rest not from the stock does not read the earlier operations.
    if let Operation::Rest { from_stock, .. } = &mut project.operations[2] {
        *from_stock = false;
    }
    store.get_or_compute(&project, &part, 2, &p).unwrap();
    assert_eq!(store.computations(), 4);
    if let Operation::Raster { scallop_mm, .. } = &mut project.operations[1] {
        *scallop_mm = 0.2;
    }
    assert_eq!(fresh(&store, &project, &part), [true, false, true]);
    // The reference tool is read: changing it makes the rest stale.
    project.tools[1].cutter = parse_tool_spec("ball:d=8,flute=20,length=40").unwrap();
    assert_eq!(fresh(&store, &project, &part), [true, false, false]);
}

#[test]
fn renaming_an_operation_or_the_project_replans_nothing() {
    let (mut project, part) = (project(), part());
    let store = Results::new();
    let p = Progress::new();
    store.get_or_compute(&project, &part, 2, &p).unwrap();
    match &mut project.operations[0] {
        Operation::Rough { name, .. } => *name = "Roughing, renamed".into(),
        _ => unreachable!(),
    }
    project.name = "Another name".into();
    project.tools[0].name = "Another tool name".into();
    assert_eq!(fresh(&store, &project, &part), [true, true, true]);
    for k in 0..3 {
        store.get_or_compute(&project, &part, k, &p).unwrap();
    }
    assert_eq!(store.computations(), 3);
    // A different part (moved by 1 µm) makes them all stale.
    let mut moved = valley();
    moved.positions[0].x += 1e-3;
    let other = Workpiece::from_mesh(Path::new("valley.stl"), moved, Vec::new());
    assert_eq!(fresh(&store, &project, &other), [false, false, false]);
    // So does another machine (the reach check and the tilt limits read it).
    project.machine = "trt-ac".into();
    assert_eq!(fresh(&store, &project, &part), [false, false, false]);
}

/// A 40 mm slot, 3 mm deep, along +X through a 20 × 20 × 10 box at 600 mm/min (a flat Ø10).
fn slot() -> talas::toolpath::Toolpath {
    use talas::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};
    let spec = "flat:d=10,flute=20,flutes=2,helix=30,rake=10";
    let p = |k, x: f64, z: f64, f: f64| Pose::new(k, DVec3::new(x, 0.0, z), DVec3::Z, f);
    Toolpath::new(
        ToolRecord {
            spec: spec.into(),
            cutter: parse_tool_spec(spec).unwrap(),
        },
        vec![
            p(MoveKind::Rapid, -20.0, 5.0, 0.0),
            p(MoveKind::Plunge, -20.0, -3.0, 600.0),
            p(MoveKind::Cut, 20.0, -3.0, 600.0),
            p(MoveKind::Rapid, 20.0, 5.0, 0.0),
        ],
    )
}

/// The forces window and the simulation read the store's stock: a slot kept as operation 0's
/// path (as a rewritten path is kept) is cut once into the in-process stock; the same slot as
/// operation 1 then cuts air, and its simulation removes nothing, while on the raw stock it
/// removes the slot's closed-form volume and meets the force of cutting the full width.
#[test]
fn forces_and_simulation_start_from_the_in_process_stock() {
    use talas::force::library::Library;
    use talas::project::forces::{ForceRunInput, operation_forces, operation_forces_on};
    use talas::project::pipeline::Computed;
    use talas::project::results::simulate_in_process;
    let tp = slot();
    let part = Workpiece::from_mesh(
        Path::new("block.stl"),
        TriMesh::new(
            vec![
                DVec3::new(-10.0, -10.0, -10.0),
                DVec3::new(10.0, -10.0, -10.0),
                DVec3::new(10.0, 10.0, -10.0),
            ],
            vec![[0, 1, 2]],
        ),
        Vec::new(),
    );
    let stock = Stock::Box {
        min_mm: [-10.0, -10.0, -10.0],
        max_mm: [10.0, 10.0, 0.0],
    };
    let project = Project {
        tools: vec![ToolEntry {
            name: "T1".into(),
            cutter: tp.tool.cutter.clone(),
        }],
        selected_tool: Some(0),
        stock,
        operations: vec![
            Operation::new(OperationKind::Rough, 0, 0),
            Operation::new(OperationKind::Rough, 0, 0),
        ],
        ..Project::default()
    };
    let store = Results::new();
    let keys = Results::keys(&project, &part);
    for k in 0..2 {
        let computed = Computed {
            toolpath: tp.clone(),
            passes: 1,
            diagnostics: Vec::new(),
            lead_rad: None,
            clearance_mm: None,
            part_hits: Vec::new(),
            left_out: Vec::new(),
        };
        store.insert(&keys, k, computed).unwrap();
    }
    let p = Progress::new();
    let first = simulate_in_process(&store, &project, &part, 0, &p).unwrap();
    let second = simulate_in_process(&store, &project, &part, 1, &p).unwrap();
    assert_eq!(
        store.computations(),
        0,
        "the kept paths are read, not planned"
    );
    // The slot: 10 mm wide, 3 mm deep, across the 20 mm box (the ball-free flat end).
    let slot_mm3 = 10.0 * 3.0 * 20.0;
    let removed = first.report.removed_volume_mm3;
    assert!(
        (removed - slot_mm3).abs() < 0.01 * slot_mm3,
        "{removed} mm³"
    );
    assert!(second.report.removed_volume_mm3 < 1e-6 * slot_mm3);
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/force/coefficients.toml"
    ))
    .unwrap();
    let c = Library::parse(&text)
        .unwrap()
        .mode_coefficients(None)
        .unwrap()
        .0;
    let bounds = part.mesh.bbox();
    let input = ForceRunInput {
        stock: &stock,
        part_bounds: bounds,
        earlier: Vec::new(),
        toolpath: &tp,
        cutter: &tp.tool.cutter,
        coefficients: &c,
        spindle_rpm: 3000.0,
        pose_time_s: None,
        limits: Default::default(),
        resolution_mm: 0.25,
    };
    let before = |k| {
        store
            .stock_before(&project, &part, k, &p)
            .unwrap()
            .dexels
            .clone()
    };
    let on_raw = operation_forces_on(before(0), &input, &p).unwrap();
    let on_cut = operation_forces_on(before(1), &input, &p).unwrap();
    // The same as the earlier-paths route on the raw stock (another grid: 2 % of the peak).
    let by_paths = operation_forces(&input, &p).unwrap();
    let (a, b) = (
        on_raw.forces.totals.peak_resultant_n,
        by_paths.forces.totals.peak_resultant_n,
    );
    assert!(a > 100.0 && (a - b).abs() < 0.02 * b, "{a} N against {b} N");
    assert!(
        on_cut.forces.totals.peak_resultant_n < 1.0,
        "{} N in air",
        on_cut.forces.totals.peak_resultant_n
    );
}
