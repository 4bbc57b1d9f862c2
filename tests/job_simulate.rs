//! The job's stock carried from setup to setup (`project::job_sim`), checked against closed
//! forms: a 40 × 40 × 10 mm box, a flat Ø6 mm slot 2 mm deep right through it from the top in
//! the first setup, the part turned over (Rx 180°), and a slot 9 mm deep right through it in
//! the second setup over the first slot (now at the bottom), so 1 mm of the second slot's
//! depth is already gone. The grid (0.0625 mm) puts the slot walls on cell boundaries, so the
//! dexel volumes are the closed forms up to rounding. And the vise: a jaw in the way of a
//! planned raster is reported by the simulation at the pose (and program line) planning
//! reports.

use std::path::Path;

use glam::DVec3;
use talas::diagnostics::Progress;
use talas::import::{OpenOptions, Workpiece, open};
use talas::project::job::{plan_in_setup, post_setup};
use talas::project::job_sim::{obstacles, simulate_job, workholding_hits};
use talas::project::setups::placements;
use talas::project::simulate::SimulationSettings;
use talas::project::{
    Operation, OperationKind, Orientation, Project, Setup, SetupStock, ToolEntry, Workholding,
};
use talas::simulation::{DexelMode, DexelStock, StockShape};
use talas::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};
use talas::tools::parse_tool_spec;

const TOOL: &str = "flat:d=6,flute=15,shank=6,length=40";
const RES: f64 = 0.0625;

fn part() -> Workpiece {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/plate-hole.stp");
    open(&p, &OpenOptions::default(), &Progress::new()).expect("plate-hole.stp")
}

/// A straight slot along X at `y`, its floor at `z`, from x = −10 to 50 (through the box),
/// approached and left from 20 mm above.
fn slot(y: f64, z: f64, top: f64) -> Toolpath {
    let tool = ToolRecord {
        spec: TOOL.into(),
        cutter: parse_tool_spec(TOOL).unwrap(),
    };
    let pose = |k, x, zz| Pose::new(k, DVec3::new(x, y, zz), DVec3::Z, 600.0);
    Toolpath::new(
        tool,
        vec![
            pose(MoveKind::Rapid, -10.0, top + 20.0),
            pose(MoveKind::Plunge, -10.0, z),
            pose(MoveKind::Cut, 50.0, z),
            pose(MoveKind::Rapid, 50.0, top + 20.0),
        ],
    )
}

fn two_setups(second: SetupStock) -> Project {
    let mut p = Project {
        name: "Slots".into(),
        machine: "mill-3axis".into(),
        tools: vec![ToolEntry {
            name: "Flat 6".into(),
            cutter: parse_tool_spec(TOOL).unwrap(),
        }],
        ..Project::default()
    };
    let mut first = Setup::named("Top");
    first.stock = SetupStock::Box {
        min_mm: [0.0, 0.0, 0.0],
        max_mm: [40.0, 40.0, 10.0],
    };
    let mut flip = Setup::named("Flipped");
    flip.frame.orientation = Orientation::Angles {
        rx_rad: std::f64::consts::PI,
        ry_rad: 0.0,
        rz_rad: 0.0,
    };
    flip.stock = second;
    p.setups = vec![first, flip];
    p
}

fn settings() -> SimulationSettings {
    SimulationSettings {
        resolution_mm: Some(RES),
        ..SimulationSettings::default()
    }
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

#[test]
fn the_second_setup_starts_from_what_the_first_left_and_cuts_it() {
    let part = part();
    let project = two_setups(SetupStock::Previous);
    // Setup 1: slot at y = 10, floor at z = 8 (2 mm deep). Setup 2 (y → −y, z → −z): the
    // first slot lies at y ∈ [−13, −7], z ∈ [−10, −8]; the second, at y = −10 with its floor
    // at z = −9, goes 9 mm down from the top (z = 0).
    let paths = vec![vec![slot(10.0, 8.0, 10.0)], vec![slot(-10.0, -9.0, 0.0)]];
    let sims = simulate_job(
        &project,
        &part,
        Path::new("."),
        &paths,
        &settings(),
        &Progress::new(),
    )
    .unwrap();
    let box_v = 40.0 * 40.0 * 10.0;
    let first_cut = 6.0 * 2.0 * 40.0;
    let second_cut = 6.0 * 9.0 * 40.0 - 6.0 * 1.0 * 40.0;
    assert!(!sims[0].carried && sims[1].carried);
    assert!(
        close(sims[0].start_volume_mm3, box_v, 1e-9),
        "{}",
        sims[0].start_volume_mm3
    );
    assert!(
        close(sims[0].end_volume_mm3, box_v - first_cut, 1e-3),
        "setup 1 ends at {} mm³, the closed form {}",
        sims[0].end_volume_mm3,
        box_v - first_cut
    );
    // Continuity: what setup 2 starts from is what setup 1 left (and the carried mesh
    // holds that volume by the divergence theorem).
    assert!(
        close(sims[1].start_volume_mm3, sims[0].end_volume_mm3, 1e-3),
        "{} vs {}",
        sims[1].start_volume_mm3,
        sims[0].end_volume_mm3
    );
    assert!(close(
        sims[1].carried_mesh_volume_mm3,
        sims[0].end_volume_mm3,
        1e-6
    ));
    assert!(
        close(sims[1].removed_volume_mm3, second_cut, 1e-3),
        "setup 2 removes {} mm³, the closed form {second_cut}",
        sims[1].removed_volume_mm3
    );
    assert!(
        close(sims[1].end_volume_mm3, box_v - first_cut - second_cut, 1e-3),
        "{}",
        sims[1].end_volume_mm3
    );
    // From a fresh box in setup 2's frame the same slot removes its whole 6 × 9 × 40 mm.
    let fresh = two_setups(SetupStock::Box {
        min_mm: [0.0, -40.0, -10.0],
        max_mm: [40.0, 0.0, 0.0],
    });
    let f = simulate_job(
        &fresh,
        &part,
        Path::new("."),
        &paths,
        &settings(),
        &Progress::new(),
    )
    .unwrap();
    assert!(!f[1].carried);
    assert!(close(f[1].removed_volume_mm3, 6.0 * 9.0 * 40.0, 1e-3));
    assert!(sims[1].removed_volume_mm3 < f[1].removed_volume_mm3 - 200.0);
}

#[test]
fn a_turned_box_mesh_loads_its_closed_form_volume() {
    // A 20 × 10 × 5 mm box turned 30° about Z (and 1e-3 rad about X), as a mesh stock: the
    // rays see its volume, 1000 mm³, within the grid's error; a ray on a shared diagonal
    // counts once (the top and bottom are two triangles each).
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let r = glam::DMat3::from_rotation_x(1e-3)
        * glam::DMat3::from_cols_array(&[c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0]);
    let b = talas::project::workholding::box_mesh(DVec3::ZERO, DVec3::new(20.0, 10.0, 5.0));
    let turned = talas::project::setups::transform_mesh(&b, r, DVec3::new(3.0, -2.0, 1.0));
    let shape = StockShape::mesh(turned).unwrap();
    let stock = DexelStock::new(vec![shape], 0.05, DexelMode::Tri, 1 << 30).unwrap();
    for f in &stock.families {
        let v = f.volume();
        assert!(close(v, 1000.0, 2e-3), "{:?}: {v} mm³", f.axis);
    }
    // An axis-aligned box whose edges and diagonals meet ray feet exactly: exact.
    let b = talas::project::workholding::box_mesh(DVec3::ZERO, DVec3::new(4.0, 4.0, 2.0));
    let stock = DexelStock::new(
        vec![StockShape::mesh(b).unwrap()],
        0.5,
        DexelMode::Z,
        1 << 30,
    )
    .unwrap();
    assert!(
        close(stock.volume_mm3(), 32.0, 1e-12),
        "{}",
        stock.volume_mm3()
    );
}

fn raster(name: &str) -> Operation {
    let mut op = Operation::new(OperationKind::Raster, 0, 0);
    if let Operation::Raster {
        name: n,
        scallop_mm,
        clearance_mm,
        ..
    } = &mut op
    {
        *n = name.into();
        *scallop_mm = 0.4;
        *clearance_mm = 5.0;
    }
    op
}

#[test]
fn a_vise_jaw_in_the_way_is_reported_by_the_simulation_at_the_pose_and_line_planning_reports() {
    let part = part();
    let mut p = Project {
        name: "Vise".into(),
        machine: "mill-3axis".into(),
        tools: vec![ToolEntry {
            name: "Ball 6".into(),
            cutter: parse_tool_spec("ball:d=6").unwrap(),
        }],
        selected_tool: Some(0),
        operations: vec![raster("Top")],
        ..Project::default()
    };
    let mut vise = Setup::named("Vise");
    vise.frame.origin_mm = [0.0, 0.0, 5.0];
    vise.stock = SetupStock::Around { margin_mm: 2.0 };
    // Jaws gripping 6.5 mm of the 7 mm stock: their tops above the part's top.
    vise.workholding = vec![Workholding::Vise {
        jaw_width_mm: 80.0,
        jaw_height_mm: 25.0,
        jaw_thickness_mm: 15.0,
        grip_mm: 6.5,
        opening_mm: None,
        along_y: false,
    }];
    vise.operations = vec![0];
    p.setups = vec![vise];
    p.check().unwrap();
    let tp = plan_in_setup(&p, 0, &part, &Progress::new())
        .unwrap()
        .toolpath;
    let pls = placements(&p, Some(&part)).unwrap();
    let obs = obstacles(&p, 0, &pls, &part.mesh.bbox(), Path::new(".")).unwrap();
    let planned = workholding_hits(std::slice::from_ref(&tp), &obs);
    let planned = planned[0].as_ref().expect("planning sees the jaw");
    let sims = simulate_job(
        &p,
        &part,
        Path::new("."),
        &[vec![tp.clone()]],
        &SimulationSettings::default(),
        &Progress::new(),
    )
    .unwrap();
    let simulated = sims[0].workholding[0]
        .as_ref()
        .expect("the simulation sees the jaw");
    assert_eq!(simulated.block, planned.block);
    assert_eq!(simulated.hit.obstacle_name, "vise");
    assert!(simulated.hit.tip.distance(planned.hit.tip) < 0.3);
    // The tip the contact is at is beside a jaw: outside the stock's X sides (±17 mm) less
    // the tool's radius.
    assert!(
        simulated.hit.tip.x.abs() > 17.0 - 3.0 - 1e-9,
        "{}",
        simulated.hit.tip
    );
    // One line of the program holds that pose.
    let posted = post_setup(&p, 0, std::slice::from_ref(&tp)).unwrap();
    assert!(
        posted
            .source_of_line
            .iter()
            .any(|s| s.operation == 0 && s.pose == Some(simulated.block))
    );
    // Jaws gripping 1.5 mm: nothing in the way, for either.
    if let Workholding::Vise { grip_mm, .. } = &mut p.setups[0].workholding[0] {
        *grip_mm = 1.5;
    }
    let sims = simulate_job(
        &p,
        &part,
        Path::new("."),
        &[vec![tp]],
        &SimulationSettings::default(),
        &Progress::new(),
    )
    .unwrap();
    assert_eq!(sims[0].workholding[0], None);
}
