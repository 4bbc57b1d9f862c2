//! The job's setups in the workstation (egui_kittest, headless): a setup added from the project
//! tree (turned over, starting from what the first leaves), a vise added in its editor and
//! drawn, a new operation going into the setup in focus, and "Post job" writing one program
//! per setup that reads back.
#![cfg(feature = "gui")]

mod common;

use std::path::PathBuf;

use common::app;
use egui_kittest::kittest::Queryable;
use talas::app::command::Command;
use talas::app::job_setups::JobSetups;
use talas::app::panels::properties::Focus;
use talas::app::{Workstation, WorkstationConfig};
use talas::project::setups::SetupStock;
use talas::project::workholding::Workholding;

fn data_dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("talas-app-setups-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let _ = std::fs::create_dir_all(&d);
    d
}

fn job(ws: &Workstation) -> &JobSetups {
    ws.feature_ref().expect("the job feature is registered")
}

#[test]
fn setups_are_added_held_in_a_vise_and_posted_one_program_each() {
    let dir = data_dir("post");
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 1000.0);
    app::settle_while(&mut h, "load", |ws| {
        ws.is_loading() || ws.is_computing_field()
    });

    // The tree's "+ Setup": a second setup, turned over, from what the first leaves.
    h.get_by_label("+ Setup").click();
    h.run_steps(3);
    let project = &h.state().session().project;
    assert_eq!(project.setups.len(), 2);
    assert_eq!(project.setups[1].stock, SetupStock::Previous);
    assert_eq!(project.setups[1].frame.work_offset_code(), "G55");
    assert_eq!(h.state().focus(), Focus::Setup(1));
    h.get_by_label_contains("Setup 2 · Setup 2");

    // Its editor adds a vise; the vise is drawn around the part.
    h.get_by_label("Add workholding").click();
    h.run_steps(2);
    h.get_by_label("Vise").click();
    h.run_steps(3);
    let w = &h.state().session().project.setups[1].workholding;
    assert!(matches!(w.as_slice(), [Workholding::Vise { .. }]), "{w:?}");
    assert_eq!(
        job(h.state()).drawn_workholding(),
        1,
        "{:?}",
        job(h.state()).drawing_error()
    );

    // With the first setup in focus, a new operation goes into it.
    h.get_by_label_contains("1. Setup 1").click();
    h.run_steps(2);
    assert_eq!(h.state().focus(), Focus::Setup(0));
    h.get_by_label("Machining").click();
    h.run_steps(3);
    h.get_by_label("Add Raster finishing").click();
    h.run_steps(3);
    let project = &h.state().session().project;
    assert_eq!(project.setups[0].operations, vec![0]);
    assert!(project.setups[1].operations.is_empty());
    // Coarse, to keep the test short.
    let mut op = project.operations[0].clone();
    if let talas::project::Operation::Raster { scallop_mm, .. } = &mut op {
        *scallop_mm = 0.5;
    }
    h.state_mut()
        .apply(Command::Edit(talas::project::Edit::SetOperation {
            index: 0,
            operation: op,
        }));
    // And one in the second setup, moved there from the first.
    let copy = h.state().session().project.operations[0].clone();
    h.state_mut()
        .apply(Command::Edit(talas::project::Edit::Batch(vec![
            talas::project::Edit::AddOperation {
                index: 1,
                operation: copy,
            },
            talas::project::Edit::MoveOperation {
                operation: 1,
                setup: 1,
                position: 0,
            },
        ])));
    h.run_steps(2);
    assert_eq!(h.state().session().project.setups[1].operations, vec![1]);

    // Post job: one program per setup next to the chosen file, each in its work offset.
    let target = dir.join("plate.ngc");
    h.state_mut().apply(Command::FeatureFile {
        feature: JobSetups::ID,
        path: target.clone(),
    });
    app::settle_while(&mut h, "post", |ws| job(ws).is_posting());
    for (file, offset) in [
        ("plate-01-Setup_1.ngc", "G54"),
        ("plate-02-Setup_2.ngc", "G55"),
    ] {
        let text = std::fs::read_to_string(dir.join(file))
            .unwrap_or_else(|e| panic!("{file}: {e}; log: {:?}", h.state().log()));
        assert!(text.contains(offset), "{file} under {offset}");
        talas::gcode::interpret(&text, &Default::default())
            .unwrap_or_else(|e| panic!("{file} reads back: {e}"));
    }
}

#[test]
fn the_view_turns_with_the_setup_in_focus_so_the_part_lies_as_on_its_table() {
    use talas::render::StandardView;
    let dir = data_dir("view");
    let mut h = app::harness(WorkstationConfig::isolated(None, dir), 1000.0);
    app::settle_load(&mut h);
    // The first setup is the part as drawn: the camera orbits the part's Z.
    h.run_steps(2);
    assert_eq!(h.state().camera().frame, glam::Mat3::IDENTITY);

    // A second setup, turned over (in focus after "+ Setup"): the camera orbits its Z, so
    // Top looks down its spindle, from under the part as the CAD model lies.
    h.get_by_label("+ Setup").click();
    h.run_steps(4);
    assert_eq!(h.state().focus(), Focus::Setup(1));
    let project = h.state().session().project.clone();
    let part = &h
        .state()
        .document()
        .expect("the default part")
        .part
        .workpiece;
    let placements = talas::project::setups::placements(&project, Some(part)).expect("placed");
    // The engine's part → setup rotation, independently of the viewport: setup Z in part
    // coordinates is its transpose's third column.
    let setup_z = placements[1].rotation.transpose() * glam::DVec3::Z;
    assert!(
        setup_z.z < -0.99,
        "turned over: setup Z is the part's −Z ({setup_z})"
    );
    h.state_mut()
        .apply(Command::StandardView(StandardView::Top));
    h.run_steps(2);
    let back = h.state().camera().backward().as_dvec3();
    assert!(
        (back - setup_z).length() < 1e-5,
        "Top looks down the setup's spindle: eye toward {back}, setup Z {setup_z}"
    );
    // The work offset is marked with the setup's axes: its Z arrow points along setup Z.
    let frame = h.state().camera().frame;
    assert!((frame * glam::Vec3::Z - setup_z.as_vec3()).length() < 1e-5);

    // Off (View menu), the part keeps its own orientation; back in setup 1, its frame again.
    h.state_mut().apply(Command::SetOrientToSetup(false));
    h.run_steps(2);
    assert_eq!(h.state().camera().frame, glam::Mat3::IDENTITY);
    h.state_mut().apply(Command::SetOrientToSetup(true));
    h.get_by_label_contains("1. Setup 1").click();
    h.run_steps(3);
    assert_eq!(h.state().focus(), Focus::Setup(0));
    assert!((h.state().camera().frame * glam::Vec3::Z - glam::Vec3::Z).length() < 1e-6);
}

#[test]
fn the_job_is_simulated_setup_after_setup_and_each_setups_stock_is_shown_in_its_place() {
    let dir = data_dir("simulate");
    let mut h = app::harness(WorkstationConfig::isolated(None, dir), 1000.0);
    app::settle_load(&mut h);
    // A coarse raster in setup 1 and the same raster in a turned-over setup 2 that starts
    // from what setup 1 left, on a box stock around the part.
    h.get_by_label("+ Setup").click();
    h.run_steps(3);
    assert_eq!(h.state().session().project.setups.len(), 2);
    h.state_mut().apply(Command::Inspect(Focus::Stock));
    h.run_steps(2);
    h.get_by_label("Box around part +2 mm (sides, top)").click();
    h.run_steps(2);
    let mut op = talas::project::Operation::new(talas::project::OperationKind::Raster, 0, 0);
    if let talas::project::Operation::Raster { scallop_mm, .. } = &mut op {
        *scallop_mm = 0.5;
    }
    use talas::project::Edit;
    h.state_mut().apply(Command::Edit(Edit::Batch(vec![
        Edit::AddOperation {
            index: 0,
            operation: op.clone(),
        },
        Edit::MoveOperation {
            operation: 0,
            setup: 0,
            position: 0,
        },
        Edit::AddOperation {
            index: 1,
            operation: op,
        },
        Edit::MoveOperation {
            operation: 1,
            setup: 1,
            position: 0,
        },
    ])));
    h.run_steps(2);
    let project = &h.state().session().project;
    assert_eq!(
        (
            project.setups[0].operations.clone(),
            project.setups[1].operations.clone()
        ),
        (vec![0], vec![1])
    );
    h.state_mut().apply(Command::Inspect(Focus::Setup(1)));
    h.run_steps(2);

    h.state_mut()
        .apply(Command::Feature(talas::app::command::FeatureCommand {
            feature: JobSetups::ID,
            action: "simulate",
        }));
    h.run_steps(1);
    app::settle_while(&mut h, "job simulation", |ws| {
        job(ws).simulation.is_running()
    });
    let view = h.state().feature_view();
    let shown = job(h.state())
        .simulation
        .shown(&view)
        .unwrap_or_else(|| panic!("the job was simulated: {:?}", h.state().log()));
    assert_eq!(shown.setups.len(), 2);
    let (first, second) = (&shown.setups[0].result, &shown.setups[1].result);
    assert!(!first.carried && second.carried);
    assert!(first.removed_volume_mm3 > 0.0 && second.removed_volume_mm3 > 0.0);
    // Setup 2 starts from what setup 1 left (the carried mesh, re-gridded: within 0.5 %).
    let rel = (second.start_volume_mm3 - first.end_volume_mm3).abs() / first.end_volume_mm3;
    assert!(
        rel < 5e-3,
        "carried {} of {} mm³",
        second.start_volume_mm3,
        first.end_volume_mm3
    );
    // The report window lists both setups.
    h.get_by_label("Job simulation");
    assert!(
        h.query_all_by_label_contains("2. Setup 2").count() >= 2,
        "the tree and the report window"
    );
    // Setup 2 in focus (it was added last): its stock is drawn in place of the part.
    assert_eq!(h.state().focus(), Focus::Setup(1));
    let scene = talas::app::feature::Feature::scene(job(h.state()));
    let legend = scene.instead_of_part.map(|p| p.legend);
    assert!(
        legend
            .as_deref()
            .is_some_and(|l| l.starts_with("Stock after setup 2")),
        "{legend:?}"
    );
    // An edit of the job hides the result (it no longer matches).
    h.state_mut()
        .apply(Command::Edit(talas::project::Edit::Rename(
            "changed".into(),
        )));
    h.run_steps(2);
    let view = h.state().feature_view();
    assert!(
        job(h.state()).simulation.shown(&view).is_some(),
        "a rename changes no cut"
    );
    h.state_mut()
        .apply(Command::Edit(talas::project::Edit::RemoveOperation {
            index: 1,
        }));
    h.run_steps(2);
    let view = h.state().feature_view();
    assert!(job(h.state()).simulation.shown(&view).is_none());
}
