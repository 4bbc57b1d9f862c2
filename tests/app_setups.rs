//! The job's setups in the workstation (egui_kittest, headless): a setup added from the project
//! tree (turned over, starting from what the first leaves), a vise added in its editor and
//! drawn, a new operation going into the setup in focus, and "Post job" writing one program
//! per setup that reads back.
#![cfg(feature = "gui")]

use std::path::PathBuf;
use std::time::Duration;

use egui_kittest::Harness;
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

fn harness(config: WorkstationConfig) -> Harness<'static, Workstation> {
    let ws = Workstation::new(&egui::Context::default(), None, config);
    Harness::builder()
        .with_size(egui::vec2(1400.0, 1000.0))
        .with_accessibility_check(false)
        .build_ui_state(|ui, ws: &mut Workstation| ws.frame_ui(ui), ws)
}

fn settle_while(h: &mut Harness<'static, Workstation>, what: &str, busy: fn(&Workstation) -> bool) {
    for _ in 0..6000 {
        h.step();
        if !busy(h.state()) {
            h.step();
            return;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    panic!("the {what} never finished");
}

fn job(ws: &Workstation) -> &JobSetups {
    ws.feature_ref().expect("the job feature is registered")
}

#[test]
fn setups_are_added_held_in_a_vise_and_posted_one_program_each() {
    let dir = data_dir("post");
    let mut h = harness(WorkstationConfig::isolated(None, dir.clone()));
    settle_while(&mut h, "load", |ws| {
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
    settle_while(&mut h, "post", |ws| job(ws).is_posting());
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
