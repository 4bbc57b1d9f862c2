//! The workstation's Calculate stores the path as it runs (issue 35, "heights from the
//! stock"): on pocket-fillets, a Z-level roughing that leaves 1 mm and then a one-way raster
//! with a 6 mm ball. The raster's stored path in the workstation is the engine's linked path
//! (`Results::linked`, computed here by a store of the test's own on the same part), whose
//! rapids are lifted over the stock the roughing left, so the workstation's Post G-code,
//! simulation and playback use what `talas job` and Post job post. Before, the workstation
//! kept the planner's path, whose rapids come down to 1 mm above the part through the
//! leftover terraces. And a click in one operation's list of findings or collisions makes
//! that operation's path the active one before its pose is picked (issue 35: "a click jumps
//! to another operation's pose"), a path can be hidden per operation, and the calculated
//! paths are saved with the project and taken back on reopening while their inputs are the
//! same (issue 36, "work that is lost or hidden").
#![cfg(feature = "gui")]

mod common;

use std::path::PathBuf;

use common::app;
use talas::app::command::Command;
use talas::app::{Workstation, WorkstationConfig};
use talas::diagnostics::Progress;
use talas::project::{Operation, OperationKind, PartRef, Project, Results, ToolEntry};
use talas::tools::parse_tool_spec;

fn project(part: PathBuf) -> Project {
    let entry = |name: &str, s: &str| ToolEntry {
        name: name.into(),
        cutter: parse_tool_spec(s).unwrap(),
    };
    let mut rough = Operation::new(OperationKind::Rough, 0, 0);
    if let Operation::Rough {
        stock_to_leave_mm,
        step_down_mm,
        ..
    } = &mut rough
    {
        *stock_to_leave_mm = 1.0;
        *step_down_mm = 3.0;
    }
    let mut finish = Operation::new(OperationKind::Raster, 1, 0);
    if let Operation::Raster {
        scallop_mm,
        one_way,
        ..
    } = &mut finish
    {
        *scallop_mm = 0.1;
        *one_way = true;
    }
    Project {
        tools: vec![
            entry("T1", "flat:d=10,flute=30,length=60"),
            entry("T2", "ball:d=6,flute=30,length=60"),
        ],
        selected_tool: Some(0),
        operations: vec![rough, finish],
        part: Some(PartRef {
            path: part,
            content_hash: String::new(),
            size_bytes: 0,
        }),
        ..Project::default()
    }
}

#[test]
fn calculate_stores_the_path_linked_over_the_stock_the_earlier_operations_leave() {
    let dir = std::env::temp_dir().join(format!("talas-app-linked-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let part = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/pocket-fillets.stp");
    let file = dir.join("linked.talas");
    project(part).save(&file).unwrap();

    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 900.0);
    app::settle_while(&mut h, "load", |w| w.is_loading() || w.is_computing_field());
    h.state_mut().apply(Command::OpenProject(file));
    app::settle_while(&mut h, "project", |w| {
        w.is_loading() || w.is_computing_field()
    });
    for k in 0..2 {
        h.state_mut().apply(Command::Calculate(k));
        app::settle_while(&mut h, "calculation", Workstation::is_calculating);
    }
    let (result, fresh) = h.state().operation_result(1).expect("a raster result");
    assert!(fresh);
    let shown = result.toolpath().clone();

    // The engine's own answer on the same part, from a store of the test's.
    let ws = h.state();
    let workpiece = &ws.document().expect("the part").part.workpiece;
    let project = &ws.session().project;
    let store = Results::new();
    let p = Progress::new();
    let planned = store.get_or_compute(project, workpiece, 1, &p).unwrap();
    let linked = store.linked(project, workpiece, 1, &p).unwrap();
    let moved = linked.lift.lifted + linked.lift.fed_down + linked.lift.fed_up;
    eprintln!(
        "raster: planned {} poses, linked {} ({} lifted, {} fed down, {} fed up), shown {}",
        planned.toolpath.poses.len(),
        linked.toolpath.poses.len(),
        linked.lift.lifted,
        linked.lift.fed_down,
        linked.lift.fed_up,
        shown.poses.len()
    );
    assert!(moved > 0, "the roughing's terraces leave rapids to link");
    assert_ne!(planned.toolpath.poses, linked.toolpath.poses);
    assert_eq!(
        shown.poses, linked.toolpath.poses,
        "the workstation shows the linked path"
    );

    // A click in the roughing's own list (a finding or a collision, here sent as the list
    // sends it) makes the roughing's path the active one before picking its pose: the pose
    // is never looked up on the raster's path, which was active.
    assert_eq!(h.state().active_operation(), Some(1));
    h.state_mut().apply(Command::PickOperationPose {
        operation: 0,
        pose: 3,
    });
    h.step();
    assert_eq!(h.state().active_operation(), Some(0));
    assert_eq!(h.state().picked_pose(), Some(3));
    // An operation with no path leaves the active one and its pick alone.
    h.state_mut().apply(Command::PickOperationPose {
        operation: 7,
        pose: 1,
    });
    h.step();
    assert_eq!(h.state().active_operation(), Some(0));
    assert_eq!(h.state().picked_pose(), Some(3));

    // Paths hidden per operation: with every path shown both are drawn, with the picked
    // move highlighted; hiding the roughing's (the active one, with the pick) leaves the
    // raster's alone, and showing it brings both back.
    h.state_mut().apply(Command::SetShowAllPaths(true));
    assert_eq!(h.state_mut().drawn_path_count(), 3);
    h.state_mut().apply(Command::SetPathShown {
        operation: 0,
        shown: false,
    });
    assert_eq!(h.state_mut().drawn_path_count(), 1);
    h.step();
    h.state_mut().apply(Command::SetPathShown {
        operation: 0,
        shown: true,
    });
    assert_eq!(h.state_mut().drawn_path_count(), 3);

    // Saving writes the calculated paths beside the project; reopening takes them back,
    // fresh, with nothing recalculated, and a changed operation's saved path is not taken.
    let saved = dir.join("saved.talas");
    h.state_mut().apply(Command::SaveProjectAs(saved.clone()));
    h.step();
    let paths = talas::project::saved_paths::paths_file(&saved);
    assert!(paths.is_file(), "{} written", paths.display());
    drop(h);
    let mut h = app::harness(
        WorkstationConfig::isolated(Some(saved.clone()), dir.clone()),
        900.0,
    );
    app::settle_while(&mut h, "reopen", |w| {
        w.is_loading() || w.is_computing_field()
    });
    assert!(!h.state().is_calculating());
    for k in 0..2 {
        let (r, fresh) = h.state().operation_result(k).expect("a restored path");
        assert!(fresh, "operation {k}'s restored path is fresh");
        if k == 1 {
            assert_eq!(r.toolpath().poses, shown.poses, "the linked path came back");
        }
    }
    let mut op = h.state().session().project.operations[1].clone();
    if let Operation::Raster { scallop_mm, .. } = &mut op {
        *scallop_mm = 0.2;
    }
    h.state_mut()
        .apply(Command::Edit(talas::project::Edit::SetOperation {
            index: 1,
            operation: op,
        }));
    h.step();
    assert!(
        !matches!(h.state().operation_result(1), Some((_, true))),
        "an edited operation's saved path is stale"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
