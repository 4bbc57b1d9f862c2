//! The operator panel driven through its UI with egui_kittest (headless): all axes homed by
//! clicking, incremental jogs landing exactly, an MDI line moving where the G-code
//! interpreter says (through the setup's work offset), the e-stop raising its alarm and reset
//! clearing it, the AXIS keys, the handwheel; the window opened from the workstation's menu.
#![cfg(feature = "gui")]

use egui::Key;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::DVec3;
use talas::app::operator_panel::{OperatorPanel, PanelMode, PanelSource};
use talas::app::{Workstation, WorkstationConfig};
use talas::control::{RunState, codes};
use talas::gcode::{InterpretOptions, Joints, interpret};
use talas::machine::Machine;
use talas::simulation::StockShape;
use talas::tools::parse_tool_spec;

const ORIGIN: [f64; 3] = [10.0, 20.0, -30.0];

fn source() -> PanelSource<'static> {
    PanelSource {
        machine: "mill-3axis".into(),
        stock: None,
        cutter: None,
        work_offset: (1, ORIGIN),
        posted: Some(("pocket", "G90 G0 X50 Y60 Z10\nG1 Z5 F500\nM30\n")),
        setup: None,
    }
}

/// The panel on `src`, two frames drawn, at the real-time clock.
fn panel_on(src: PanelSource<'static>) -> Harness<'static, OperatorPanel> {
    let mut h = Harness::builder()
        .with_size(egui::vec2(1400.0, 950.0))
        .with_step_dt(1.0 / 60.0)
        .with_accessibility_check(false)
        .build_ui_state(
            move |ui, p: &mut OperatorPanel| p.ui(ui, &src),
            OperatorPanel::new(),
        );
    h.run_steps(2);
    h
}

fn harness() -> Harness<'static, OperatorPanel> {
    let mut h = panel_on(source());
    h.get_by_label("×100").click();
    h.run_steps(2);
    h
}

/// Step frames until the control rests (the clock runs ×100, 1/60 s per frame: 1.67 s).
fn settle(h: &mut Harness<'static, OperatorPanel>) {
    for _ in 0..3000 {
        h.step();
        if h.state().control().is_some_and(|c| c.is_idle()) {
            h.run_steps(2);
            return;
        }
    }
    panic!("the control never came to rest");
}

fn position(h: &Harness<'static, OperatorPanel>) -> Vec<f64> {
    h.state().control().unwrap().snapshot().machine_position
}

fn home(h: &mut Harness<'static, OperatorPanel>) {
    h.get_by_label("Home all").click();
    h.run_steps(1);
    settle(h);
}

#[test]
fn home_all_axes_by_clicking() {
    let mut h = harness();
    let snap = h.state().control().unwrap().snapshot();
    assert_eq!(snap.homed, vec![false, false, false]);
    home(&mut h);
    let snap = h.state().control().unwrap().snapshot();
    assert_eq!(snap.homed, vec![true, true, true]);
    assert_eq!(h.state().mode(), PanelMode::Ref);
    // Every axis at its home switch: the top of its travel in the machine file.
    let m = Machine::builtin("mill-3axis").unwrap();
    let tops: Vec<f64> = m.axes.iter().map(|a| a.max).collect();
    assert_eq!(snap.machine_position, tops);
    // The DRO shows machine and work positions with their unit.
    let work_x = format!("{:.3} mm", tops[0] - ORIGIN[0]);
    assert!(
        h.query_by_label_contains(&work_x).is_some(),
        "{work_x} not shown"
    );
    assert!(h.query_by_label_contains("No alarms").is_some());
    // Power on rebuilds the control from the project: nothing homed, back at the power-on
    // position (machine zero, Z at the top of its travel).
    h.get_by_label("Power on").click();
    h.run_steps(2);
    let snap = h.state().control().unwrap().snapshot();
    assert_eq!(snap.homed, vec![false, false, false]);
    assert_eq!(snap.machine_position, vec![0.0, 0.0, 100.0]);
}

#[test]
fn an_incremental_jog_lands_exactly() {
    let mut h = harness();
    home(&mut h);
    h.get_by_label("INC").click();
    h.run_steps(2);
    assert_eq!(h.state().mode(), PanelMode::Inc);
    let start = position(&h);
    h.get_by_label("0.1 (×100)").click();
    h.run_steps(1);
    for _ in 0..3 {
        h.get_by_label("X−").click();
        h.run_steps(1);
        settle(&mut h);
    }
    h.get_by_label("1").click();
    h.run_steps(1);
    h.get_by_label("Z−").click();
    h.run_steps(1);
    settle(&mut h);
    let p = position(&h);
    assert!((p[0] - (start[0] - 0.3)).abs() < 1e-9, "X at {} mm", p[0]);
    assert_eq!(p[1], start[1]);
    assert!((p[2] - (start[2] - 1.0)).abs() < 1e-9, "Z at {} mm", p[2]);
}

#[test]
fn an_mdi_line_moves_where_the_interpreter_says() {
    let mut h = harness();
    home(&mut h);
    h.get_all_by_label("MDI").next().unwrap().click();
    h.run_steps(2);
    let start = position(&h);
    let line = "G0 X100 Y50 Z-40";
    h.get_by_role(egui::accesskit::Role::TextInput).click();
    h.run_steps(1);
    h.get_by_role(egui::accesskit::Role::TextInput)
        .type_text(line);
    h.run_steps(1);
    assert_eq!(h.state().mdi_line(), line);
    h.get_by_label("Send").click();
    h.run_steps(1);
    settle(&mut h);
    let mut opts = InterpretOptions::starting_at(Joints::xyz(start[0], start[1], start[2]));
    opts.work_offsets[0] = DVec3::from(ORIGIN);
    let want = interpret(line, &opts)
        .unwrap()
        .blocks
        .last()
        .unwrap()
        .end
        .xyz;
    let p = position(&h);
    let got = DVec3::new(p[0], p[1], p[2]);
    assert!(
        got.distance(want) < 1e-9,
        "at {got}, interpreter says {want}"
    );
    assert_eq!(want, DVec3::new(110.0, 70.0, -70.0));
    // The line is in the history, the work DRO shows the programmed position.
    assert!(h.query_by_label(line).is_some());
    assert!(h.query_by_label_contains("100.000 mm").is_some());
    assert!(h.state().control().unwrap().alarms().is_empty());
}

#[test]
fn estop_raises_an_alarm_and_reset_clears_it() {
    let mut h = harness();
    h.get_by_label("E-STOP").click();
    h.run_steps(1);
    settle(&mut h);
    let snap = h.state().control().unwrap().snapshot();
    assert_eq!(snap.state, RunState::EStop);
    assert!(snap.alarms.iter().any(|a| a.code == codes::ESTOP));
    assert!(h.query_by_label_contains("A001").is_some());
    // Nothing moves while the e-stop is latched.
    h.get_by_label("Home all").click();
    h.run_steps(3);
    assert!(h.state().message().is_some());
    h.get_by_label("Reset").click();
    h.run_steps(2);
    let snap = h.state().control().unwrap().snapshot();
    assert!(snap.alarms.is_empty());
    assert_eq!(snap.state, RunState::Idle);
    assert!(h.query_by_label_contains("No alarms").is_some());
}

#[test]
fn axis_keys_jog_while_held_and_f1_is_the_estop() {
    let mut h = harness();
    home(&mut h);
    h.get_by_label("JOG").click();
    h.run_steps(2);
    // Keys act while the pointer is over the panel.
    h.hover_at(egui::pos2(700.0, 500.0));
    h.run_steps(1);
    let start = position(&h);
    h.key_down(Key::ArrowLeft);
    h.run_steps(5);
    assert_eq!(h.state().control().unwrap().run_state(), RunState::Moving);
    // Released with the pointer gone from the panel, the jog still stops.
    h.hover_at(egui::pos2(1395.0, 945.0));
    h.run_steps(1);
    h.key_up(Key::ArrowLeft);
    h.run_steps(1);
    settle(&mut h);
    h.hover_at(egui::pos2(700.0, 500.0));
    h.run_steps(1);
    let p = position(&h);
    assert!(
        p[0] < start[0] - 1.0,
        "X moved to {} mm from {}",
        p[0],
        start[0]
    );
    // It braked on release, well before the soft limit (X −300 mm).
    assert!(p[0] > -250.0, "X ran on to {} mm", p[0]);
    assert!(h.state().control().unwrap().alarms().is_empty());
    assert_eq!((p[1], p[2]), (start[1], start[2]));
    h.key_press(Key::F1);
    h.run_steps(1);
    settle(&mut h);
    assert_eq!(h.state().control().unwrap().run_state(), RunState::EStop);
}

#[test]
fn the_posted_program_loads_and_runs_in_auto() {
    let mut h = harness();
    home(&mut h);
    h.get_by_label("AUTO").click();
    h.run_steps(2);
    h.get_by_label("Load posted program").click();
    h.run_steps(2);
    assert!(h.query_by_label_contains("pocket · 3 lines").is_some());
    h.get_by_label("Cycle start").click();
    h.run_steps(1);
    settle(&mut h);
    let p = position(&h);
    assert_eq!(p, vec![60.0, 80.0, -25.0]);
}

#[test]
fn the_workstation_menu_opens_the_panel() {
    let dir = std::env::temp_dir().join(format!("talas-app-op-panel-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let ws = Workstation::new(
        &egui::Context::default(),
        None,
        WorkstationConfig::isolated(None, dir),
    );
    let mut h = Harness::builder()
        .with_size(egui::vec2(1600.0, 1000.0))
        .with_accessibility_check(false)
        .build_ui_state(|ui, ws: &mut Workstation| ws.frame_ui(ui), ws);
    h.run_steps(3);
    assert!(
        h.state_mut()
            .feature::<OperatorPanel>()
            .is_some_and(|p| !p.open)
    );
    h.get_by_label("Machining").click();
    h.run_steps(3);
    h.get_by_label("Operator panel…").click();
    h.run_steps(3);
    assert!(
        h.state_mut()
            .feature::<OperatorPanel>()
            .is_some_and(|p| p.open)
    );
    h.get_by_label_contains("Operator panel · virtual control");
    assert!(
        h.state_mut()
            .feature::<OperatorPanel>()
            .is_some_and(|p| p.control().is_some())
    );
    assert!(h.query_by_label("Cycle start").is_some());
}

#[test]
fn a_slot_cut_through_mdi_removes_its_closed_form_volume() {
    let src = PanelSource {
        machine: "mill-3axis".into(),
        stock: Some(StockShape::Box {
            min: DVec3::new(50.0, 50.0, -10.0),
            max: DVec3::new(100.0, 100.0, 0.0),
        }),
        cutter: Some(parse_tool_spec("flat:d=6").unwrap()),
        work_offset: (1, [0.0; 3]),
        posted: None,
        setup: None,
    };
    let mut h = Harness::builder()
        .with_size(egui::vec2(1400.0, 950.0))
        .with_step_dt(1.0 / 60.0)
        .with_accessibility_check(false)
        .build_ui_state(
            move |ui, p: &mut OperatorPanel| p.ui(ui, &src),
            OperatorPanel::new(),
        );
    h.run_steps(2);
    h.get_by_label("×100").click();
    h.run_steps(1);
    home(&mut h);
    h.get_by_label("MDI").click();
    h.run_steps(2);
    for line in [
        "G0 X60 Y75 Z5",
        "M3 S8000",
        "G1 Z-2 F500",
        "G1 X80",
        "G0 Z5",
    ] {
        h.get_by_role(egui::accesskit::Role::TextInput).click();
        h.run_steps(1);
        h.get_by_role(egui::accesskit::Role::TextInput)
            .type_text(line);
        h.run_steps(1);
        h.get_by_label("Send").click();
        h.run_steps(1);
        settle(&mut h);
    }
    let snap = h.state().control().unwrap().snapshot();
    assert!(snap.alarms.is_empty(), "{:?}", snap.alarms);
    // A Ø6 mm plunge 2 mm deep, then a 20 mm slot 6 mm wide and 2 mm deep: π·3²·2 + 20·6·2.
    let want = std::f64::consts::PI * 9.0 * 2.0 + 20.0 * 6.0 * 2.0;
    let got = snap.removed_volume_mm3;
    assert!(
        (got - want).abs() < 0.02 * want,
        "removed {got} mm³, closed form {want} mm³ (0.5 mm dexels)"
    );
}

#[test]
fn machine_camera_presets_in_the_view_menu_frame_the_whole_machine() {
    let dir = std::env::temp_dir().join(format!("talas-app-op-cam-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let ws = Workstation::new(
        &egui::Context::default(),
        None,
        WorkstationConfig::isolated(None, dir),
    );
    let mut h = Harness::builder()
        .with_size(egui::vec2(1600.0, 1000.0))
        .with_accessibility_check(false)
        .build_ui_state(|ui, ws: &mut Workstation| ws.frame_ui(ui), ws);
    h.run_steps(3);
    // The default part loads off the UI thread and the camera fits it when it arrives.
    for _ in 0..200 {
        if !h.state().is_loading() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
        h.run_steps(1);
    }
    h.run_steps(3);
    let part_distance = h.state().camera().distance;
    // (yaw, pitch) of the standard views: front looks along +Y, side along −X, top down.
    let half_pi = std::f32::consts::FRAC_PI_2;
    for (label, yaw, pitch) in [
        ("Machine Front", -half_pi, 0.0),
        ("Machine Side", 0.0, 0.0),
        ("Machine Top", -half_pi, half_pi),
    ] {
        h.get_by_label("View").click();
        h.run_steps(2);
        h.get_by_label(label).click();
        h.run_steps(3);
        assert!(
            h.state_mut()
                .feature::<OperatorPanel>()
                .is_some_and(|p| p.open)
        );
        let cam = *h.state().camera();
        assert!(
            (cam.yaw_rad - yaw).abs() < 1e-6 && (cam.pitch_rad - pitch).abs() < 1e-6,
            "{label}: yaw {} pitch {}",
            cam.yaw_rad,
            cam.pitch_rad
        );
        // The mill's bodies span about 1.0 × 1.3 × 1.6 m: the camera stands well back of a
        // part-sized view.
        assert!(
            cam.distance > 1000.0 && cam.distance > 2.0 * part_distance,
            "{label}: distance {} mm (part view {part_distance} mm)",
            cam.distance
        );
    }
}

#[test]
fn a_g83_shows_its_peck_on_the_panel_while_it_runs() {
    // R5 to Z-15 by Q3: 20 mm in ceil(20 / 3) = 7 pecks; the second feeds to 6 mm below R.
    let src = PanelSource {
        posted: Some((
            "peck",
            "G21 G90 G17\nG0 X50 Y60 Z10\nS1000 M3\nG99 G83 X50 Y60 Z-15 R5 Q3 F200\nG80\nM30\n",
        )),
        ..source()
    };
    let mut h = panel_on(src);
    home(&mut h);
    h.get_by_label("AUTO").click();
    h.run_steps(2);
    h.get_by_label("Load posted program").click();
    h.run_steps(2);
    h.get_by_label("Cycle start").click();
    let mut seen = false;
    for _ in 0..60 * 60 {
        h.step();
        if h.query_by_label_contains(
            "G83 hole 1/1, peck 2/7 feeding to 6.000 mm of 20.000 mm below R",
        )
        .is_some()
        {
            seen = true;
            break;
        }
    }
    assert!(seen, "the second peck never showed on the panel");
    let snap = h.state().control().unwrap().snapshot();
    let phase = snap.cycle.expect("a cycle runs");
    assert_eq!((phase.peck, phase.pecks), (2, 7));
}

#[test]
fn auto_stops_at_the_setups_vise_jaw_on_the_line_planning_names() {
    use talas::app::operator_panel::SetupSource;
    use talas::diagnostics::Progress;
    use talas::project::job::{plan_in_setup, post_setup};
    use talas::project::setups::{placements, stock_solid};
    use talas::project::{
        Operation, OperationKind, Project, Setup, SetupStock, ToolEntry, Workholding,
    };
    // The plate (30 × 30 × 5 mm, Open CASCADE) in a vise whose jaws grip 6.5 mm of the 7 mm
    // stock, their tops 1.5 mm above the part: the raster's passes over the X edges run into
    // them. Planning's check names the pose, the posted program its line; the panel built from
    // the setup puts the same jaws on the machine table.
    let part: &'static _ = Box::leak(Box::new(
        talas::import::open(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/plate-hole.stp"),
            &talas::import::OpenOptions::default(),
            &Progress::new(),
        )
        .unwrap(),
    ));
    let mut raster = Operation::new(OperationKind::Raster, 0, 0);
    if let Operation::Raster {
        scallop_mm,
        clearance_mm,
        ..
    } = &mut raster
    {
        *scallop_mm = 0.4;
        *clearance_mm = 5.0;
    }
    let mut vise = Setup::named("Vise");
    vise.frame.origin_mm = [0.0, 0.0, 5.0];
    vise.stock = SetupStock::Around { margin_mm: 2.0 };
    vise.workholding = vec![Workholding::Vise {
        jaw_width_mm: 80.0,
        jaw_height_mm: 25.0,
        jaw_thickness_mm: 15.0,
        grip_mm: 6.5,
        opening_mm: None,
        along_y: false,
    }];
    vise.operations = vec![0];
    let project: &'static Project = Box::leak(Box::new(Project {
        name: "Plate in a vise".into(),
        machine: "mill-3axis".into(),
        tools: vec![ToolEntry {
            name: "Ball 6".into(),
            cutter: parse_tool_spec("ball:d=6").unwrap(),
        }],
        selected_tool: Some(0),
        operations: vec![raster],
        setups: vec![vise],
        ..Project::default()
    }));
    let tp = plan_in_setup(project, 0, part, &Progress::new())
        .unwrap()
        .toolpath;
    // Linked over the stock box as `talas job --post` posts it (rapids lifted over the stock).
    let tp = talas::project::job::link_setup(project, 0, part, &[tp], false, &Progress::new())
        .unwrap()
        .0
        .remove(0)
        .toolpath;
    let pls = placements(project, Some(part)).unwrap();
    let meshes = talas::project::setups::workholding_meshes(
        project,
        0,
        &pls,
        &part.mesh.bbox(),
        std::path::Path::new("."),
    )
    .unwrap();
    let obstacles: Vec<_> = meshes
        .iter()
        .map(|m| talas::checks::collide::Obstacle::new("vise", m).unwrap())
        .collect();
    let moves: Vec<_> = tp.poses.iter().map(|p| (p.tip, p.axis)).collect();
    let tool = talas::checks::collide::assembly(&project.tools[0].cutter);
    let hit = talas::checks::collide::first_hit(&tool, &obstacles, &moves, 0.25)
        .expect("planning sees the jaw");
    let posted = post_setup(project, 0, std::slice::from_ref(&tp)).unwrap();
    let line = posted
        .source_of_line
        .iter()
        .rposition(|s| s.pose == Some(hit.index))
        .unwrap()
        + 1;
    let text: &'static str = Box::leak(posted.text.into_boxed_str());
    // Program zero 60 mm below the part's own origin on the machine: the post's 100 mm safe
    // height stays within Z's 100 mm travel.
    let origin = DVec3::new(0.0, 0.0, -60.0);
    let b = stock_solid(project, 0, &pls, &part.mesh.bbox())
        .unwrap()
        .bbox();
    let src = PanelSource {
        machine: "mill-3axis".into(),
        stock: Some(StockShape::Box {
            min: b.min + origin,
            max: b.max + origin,
        }),
        cutter: Some(project.tools[0].cutter.clone()),
        work_offset: (1, origin.to_array()),
        posted: Some(("Vise", text)),
        setup: Some(SetupSource {
            project,
            index: 0,
            part,
            base: std::path::Path::new("."),
        }),
    };
    let mut h = panel_on(src);
    assert!(
        h.state()
            .control()
            .unwrap()
            .fixtures()
            .iter()
            .any(|f| f.name == "vise"),
        "the vise is on the table"
    );
    h.get_by_label("×100").click();
    h.run_steps(2);
    home(&mut h);
    h.get_by_label("AUTO").click();
    h.run_steps(2);
    h.get_by_label("Load posted program").click();
    h.run_steps(2);
    h.get_by_label("Cycle start").click();
    h.run_steps(1);
    settle(&mut h);
    let snap = h.state().control().unwrap().snapshot();
    let alarm = snap
        .alarms
        .iter()
        .find(|a| a.code == codes::COLLISION_MACHINE)
        .unwrap_or_else(|| panic!("no collision alarm: {:?}", snap.alarms));
    assert_eq!(alarm.line, Some(line), "{}", alarm.text);
    assert!(
        alarm.bodies.iter().any(|b| b == "vise"),
        "{:?}",
        alarm.bodies
    );
    // The panel shows it.
    assert!(
        h.query_by_label_contains(&format!("line {line}: collision"))
            .is_some(),
        "{}",
        alarm.text
    );
}
