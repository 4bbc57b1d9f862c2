//! The three-setup job of `tests/data/job/job-part.talas` on `job-part.stp` (made by
//! `tests/data/job/make_part.py` with Open CASCADE): in a vise from the top (face, pocket,
//! contour, peck drilling), turned on its side (the side slot), and tilted on the trt-ac
//! machine to the front (the front pocket with its boss). Every setup posts a program that
//! Talas's interpreter reads back; the floors and the hole depths, measured on the stock each
//! setup's paths cut (simulated at 0.1 mm in the setup's work plane), are make_part.py's numbers
//! within the simulation's resolution.

use std::path::Path;

use glam::DVec3;
use talas::diagnostics::Progress;
use talas::gcode::{InterpretOptions, Syntax, interpret};
use talas::import::{OpenOptions, Workpiece, open};
use talas::project::job::{plan_in_setup, post_setup, setup_stock};
use talas::project::setups::{Placement, placements, transform_toolpath, workpiece_in_plane};
use talas::project::simulate::{SimulationSettings, simulate_toolpaths};
use talas::project::{Operation, Project};
use talas::toolpath::{ExactMove, Toolpath};

const RESOLUTION_MM: f64 = 0.1;

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/job")
        .join(name)
}

fn part() -> Workpiece {
    open(
        &data("job-part.stp"),
        &OpenOptions::default(),
        &Progress::new(),
    )
    .expect("job-part.stp")
}

fn project() -> Project {
    Project::load(&data("job-part.talas")).expect("job-part.talas")
}

/// The highest point of `mesh` over (x, y) (a vertical ray from above), `None` off the mesh.
fn top_at(mesh: &talas::geometry::mesh::TriMesh, x: f64, y: f64) -> Option<f64> {
    let q = glam::DVec2::new(x + 1.234e-7, y + 2.345e-7);
    let mut best: Option<f64> = None;
    for t in 0..mesh.triangles.len() {
        let Some(c) = mesh.triangle_corners(t) else {
            continue;
        };
        let (a, b, cc) = (c[0].truncate(), c[1].truncate(), c[2].truncate());
        let area = (b - a).perp_dot(cc - a);
        if area.abs() < 1e-14 {
            continue;
        }
        let w0 = (b - q).perp_dot(cc - q) / area;
        let w1 = (cc - q).perp_dot(a - q) / area;
        let w2 = 1.0 - w0 - w1;
        if w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0 {
            let z = w0 * c[0].z + w1 * c[1].z + w2 * c[2].z;
            best = Some(best.map_or(z, |m: f64| m.max(z)));
        }
    }
    best
}

/// Plan, post and read back setup `s`; simulate its paths in its work plane from its starting
/// stock. The placement, the paths (setup frame), the program and the simulated stock mesh.
fn machine_setup(
    project: &Project,
    part: &Workpiece,
    s: usize,
) -> (
    Placement,
    Vec<Toolpath>,
    String,
    talas::geometry::mesh::TriMesh,
) {
    let setup = &project.setups[s];
    let paths: Vec<Toolpath> = setup
        .operations
        .iter()
        .map(|&op| {
            plan_in_setup(project, op, part, &Progress::new())
                .unwrap_or_else(|e| panic!("{}: {e}", project.operations[op].name()))
                .toolpath
        })
        .collect();
    let posted = post_setup(project, s, &paths).unwrap_or_else(|e| panic!("{}: {e}", setup.name));
    let program = interpret(
        &posted.text,
        &InterpretOptions::for_syntax(Syntax::from_name("linuxcnc").unwrap()),
    )
    .unwrap_or_else(|e| panic!("{}: the program does not read back: {e}", setup.name));
    assert!(
        program.blocks.len() > 20,
        "{}: {} blocks",
        setup.name,
        program.blocks.len()
    );
    let pl = placements(project, Some(part)).unwrap()[s];
    // In the work plane the tool axis is +Z: the Z-dexel simulation cuts there.
    let to_plane = pl.work_plane.transpose();
    let in_plane: Vec<Toolpath> = paths
        .iter()
        .map(|tp| transform_toolpath(tp, to_plane, DVec3::ZERO))
        .collect();
    for tp in &in_plane {
        assert!(tp.poses.iter().all(|p| (p.axis - DVec3::Z).length() < 1e-9));
    }
    let stock = setup_stock(project, s, part).unwrap();
    let part_in_plane = workpiece_in_plane(part, &pl);
    let cutters: Vec<_> = setup
        .operations
        .iter()
        .map(|&op| project.tools[project.operations[op].tool()].cutter.clone())
        .collect();
    let runs: Vec<(&Toolpath, &talas::tools::Cutter)> = in_plane.iter().zip(&cutters).collect();
    let sim = simulate_toolpaths(
        &stock,
        &part_in_plane.mesh,
        &runs,
        &SimulationSettings {
            resolution_mm: Some(RESOLUTION_MM),
            ..SimulationSettings::default()
        },
        &Progress::new(),
    )
    .unwrap_or_else(|e| panic!("{}: {e}", setup.name));
    assert!(sim.resolution_mm <= RESOLUTION_MM + 1e-12);
    (pl, paths, posted.text, sim.stock_mesh)
}

/// The simulated stock's height over the part point `p` (taken into the work plane), and the
/// height `p` itself has there.
fn measured(pl: &Placement, stock: &talas::geometry::mesh::TriMesh, p: DVec3) -> (f64, f64) {
    let q = pl.to_plane(p);
    let z = top_at(stock, q.x, q.y).unwrap_or_else(|| panic!("no stock over {p}"));
    (z, q.z)
}

#[test]
fn the_job_part_is_faced_pocketed_contoured_and_drilled_in_three_setups() {
    let part = part();
    let project = project();
    assert_eq!(project.setups.len(), 3);
    // The committed project holds the new kinds.
    assert!(matches!(project.operations[0], Operation::Face(_)));
    assert!(matches!(project.operations[3], Operation::Holes(_)));
    // Within the simulation's resolution (a dexel's height is exact; its place is within half
    // a cell, and the drill's 118° point then reads up to 0.03 mm shallow).
    let tol = RESOLUTION_MM;

    // Setup 1, from the top: the faced top at z = 25, the pocket floor at z = 20 (5 mm deep),
    // the two Ø6 holes 8 mm deep (the drill's tip at z = 17).
    let (pl, paths, text, stock) = machine_setup(&project, &part, 0);
    let (top, want) = measured(&pl, &stock, DVec3::new(-25.0, 15.0, 25.0));
    assert!((top - want).abs() < tol, "faced top {top} vs {want}");
    let (floor, want) = measured(&pl, &stock, DVec3::new(0.0, 0.0, 20.0));
    assert!((floor - want).abs() < tol, "pocket floor {floor} vs {want}");
    for x in [-22.0, 22.0] {
        let (bottom, want) = measured(&pl, &stock, DVec3::new(x, 0.0, 17.0));
        let depth = top - bottom;
        assert!(
            (depth - 8.0).abs() < tol,
            "hole at x = {x}: {depth} mm deep, {bottom} vs {want}"
        );
    }
    // The contour cut the outline: no stock left 1 mm outside the part's side.
    let q = pl.to_plane(DVec3::new(31.0, 0.0, 0.0));
    let outside = top_at(&stock, q.x, q.y).unwrap_or(f64::NEG_INFINITY);
    assert!(
        outside < q.z + 0.5,
        "stock outside the outline up to {outside}"
    );
    // The holes stay canned cycles: G83 pecks, two of them, in the program.
    let drill = &paths[3];
    let cycles = drill
        .exact
        .iter()
        .filter(|s| matches!(s.exact, ExactMove::Cycle(_)))
        .count();
    assert_eq!(cycles, 2);
    assert!(text.contains("G83"), "no peck cycle in the program");

    // Setup 2, on its side (+X up): the slot's floor at x = 27, 3 mm below the side.
    let (pl, _, _, stock) = machine_setup(&project, &part, 1);
    let (floor, want) = measured(&pl, &stock, DVec3::new(27.0, 0.0, 15.0));
    assert!((floor - want).abs() < tol, "slot floor {floor} vs {want}");
    let side = pl.to_plane(DVec3::new(30.0, 0.0, 15.0)).z;
    assert!((side - floor - 3.0).abs() < tol);

    // Setup 3, tilted to the front: the pocket's floor at y = −16 (4 mm deep) beside the boss,
    // and the boss left standing (its top at y = −19; no facing in this setup, so the stock's
    // margin above the front stays over it).
    let (pl, _, text, stock) = machine_setup(&project, &part, 2);
    for x in [-7.0, 7.0] {
        let (floor, want) = measured(&pl, &stock, DVec3::new(x, -16.0, 12.5));
        assert!(
            (floor - want).abs() < tol,
            "front pocket floor at x = {x}: {floor} vs {want}"
        );
    }
    let (boss, want) = measured(&pl, &stock, DVec3::new(0.0, -19.0, 12.5));
    assert!(
        boss > want - tol,
        "the boss was cut into: {boss} vs its top {want}"
    );
    assert!(
        text.contains("A"),
        "the tilted program positions no rotary axis"
    );
}

#[test]
fn old_and_new_operations_round_trip_through_the_project_file() {
    let project = project();
    let dir = std::env::temp_dir().join(format!("talas-job-part-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("job-part.talas");
    project.save(&file).unwrap();
    let again = Project::load(&file).unwrap();
    assert_eq!(again.operations, project.operations);
    let _ = std::fs::remove_dir_all(&dir);
}
