//! Waterline finishing in the workstation, driven through its UI with egui_kittest (headless):
//! added from the Machining menu, edited in the operation editor (its fields carry units),
//! calculated in the background, and its path has poses on the part.
#![cfg(feature = "gui")]

mod common;

use common::app;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use talas::app::command::Command;
use talas::app::{Workstation, WorkstationConfig};
use talas::diagnostics::Severity;
use talas::project::{Edit, Operation, OperationKind};
use talas::strategies::boundary::{BoundaryRule, Region};
use talas::strategies::waterline::Cut;
use talas::toolpath::MoveKind;

#[test]
fn a_waterline_operation_is_added_edited_and_calculated() {
    let dir = common::temp_dir("app-op3");
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 900.0);
    app::settle_while(&mut h, "load", |w| w.is_loading() || w.is_computing_field());

    h.get_by_label("Machining").click();
    h.run_steps(3);
    h.get_by_label("Add Waterline finishing").click();
    h.run_steps(2);
    let ops = &h.state().session().project.operations;
    assert_eq!(ops.len(), 1);
    assert_eq!(ops[0].kind(), OperationKind::Waterline);
    // The editor shows the waterline's own fields.
    h.get_by_label("Slope limit");
    h.get_by_label("conventional");
    assert!(h.query_all_by_label_contains("mm/min").next().is_some());

    // Coarser settings keep the test short; conventional milling.
    let mut op = ops[0].clone();
    if let Operation::Waterline {
        scallop_mm,
        tolerance_mm,
        cut,
        ..
    } = &mut op
    {
        *scallop_mm = 0.1;
        *tolerance_mm = 0.1;
        *cut = Cut::Conventional;
    }
    h.state_mut().apply(Command::Edit(Edit::SetOperation {
        index: 0,
        operation: op,
    }));
    h.step();
    h.state_mut().apply(Command::Calculate(0));
    app::settle_while(&mut h, "calculation", Workstation::is_calculating);
    let (result, fresh) = h.state().operation_result(0).expect("a result");
    assert!(fresh);
    let tp = result.toolpath();
    let cuts = tp.poses.iter().filter(|p| p.kind == MoveKind::Cut).count();
    assert!(cuts > 100, "{cuts} cutting poses");
    // Every cutting pose lies within the part's box grown by the tool's radius sideways, and
    // between its bottom and top.
    let r = h.state().session().project.tools[0].cutter.radius();
    let b = h.state().document().expect("the default part").bounds;
    for p in tp.poses.iter().filter(|p| p.kind == MoveKind::Cut) {
        let t = p.tip;
        let inside = t.x >= b.min.x - r - 1e-6
            && t.x <= b.max.x + r + 1e-6
            && t.y >= b.min.y - r - 1e-6
            && t.y <= b.max.y + r + 1e-6
            && t.z >= b.min.z - 1e-6
            && t.z <= b.max.z + 1e-6;
        assert!(inside, "cutting pose {t} outside the part's box ± {r} mm");
    }
    h.get_by_label("Cut length");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A face-finishing operation's editor shows its face group and tilt-away limits with units;
/// unticking tilt-away edits the operation and hides the limits.
/// `cargo test --test app_operation_3axis tilt_away`
#[test]
fn the_finish_editor_edits_the_tilt_away_and_shows_the_group() {
    let dir = common::temp_dir("app-tilt");
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 900.0);
    app::settle_while(&mut h, "load", |w| w.is_loading() || w.is_computing_field());
    h.get_by_label("Machining").click();
    h.run_steps(3);
    h.get_by_label("Add Iso-scallop finishing").click();
    h.run_steps(2);
    let tilt = |h: &Harness<'static, Workstation>| match &h.state().session().project.operations[0]
    {
        Operation::Finish {
            tilt_away, group, ..
        } => (tilt_away.enabled, group.len()),
        other => panic!("not a finishing operation: {:?}", other.kind()),
    };
    assert_eq!(tilt(&h), (true, 0));
    h.get_by_label("this face only");
    h.get_by_label("Largest tilt");
    assert!(h.query_all_by_label_contains("°/mm").next().is_some());
    h.get_by_label("tilt away from walls").click();
    h.run_steps(3);
    assert_eq!(tilt(&h), (false, 0), "unticked in the editor");
    assert!(h.query_by_label("Largest tilt").is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Rest finishing's editor: the reference tool and the "from simulated stock" tick box, which
/// edits the operation (and unticks back), and the boundary (silhouette, contact rule); pencil finishing's editor shows its corner angle
/// and its calculation on the default part (no valley) logs why it gives no path.
/// `cargo test --test app_operation_3axis rest_and_pencil`
#[test]
fn the_rest_and_pencil_editors_edit_their_fields() {
    let dir = common::temp_dir("app-rest");
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 2000.0);
    app::settle_while(&mut h, "load", |w| w.is_loading() || w.is_computing_field());
    h.get_by_label("Machining").click();
    h.run_steps(3);
    h.get_by_label("Add Rest finishing").click();
    h.run_steps(2);
    let stock = |h: &Harness<'static, Workstation>| match &h.state().session().project.operations[0]
    {
        Operation::Rest { from_stock, .. } => *from_stock,
        other => panic!("not a rest operation: {:?}", other.kind()),
    };
    assert!(!stock(&h));
    h.get_by_label("Reference tool");
    h.get_by_label("from simulated stock").click();
    h.run_steps(3);
    assert!(stock(&h), "ticked in the editor");
    h.get_by_label("from simulated stock").click();
    h.run_steps(3);
    assert!(!stock(&h), "unticked again");
    // The boundary: the part's silhouette, then the contact-point rule.
    let boundary = |h: &Harness<'static, Workstation>| {
        h.state().session().project.operations[0]
            .boundary()
            .cloned()
    };
    assert_eq!(boundary(&h), None);
    // The region's combo box has no label of its own (the grid's "Boundary" cell names it).
    h.get(
        egui_kittest::kittest::By::new()
            .role(egui::accesskit::Role::ComboBox)
            .value("whole part"),
    )
    .click();
    h.run_steps(3);
    h.get_by_label("part silhouette").click();
    h.run_steps(3);
    let b = boundary(&h).expect("a boundary after choosing the silhouette");
    assert_eq!(b.region, Region::Silhouette);
    assert_eq!(b.rule, BoundaryRule::ToolCentre);
    h.get_by_label("contact point").click();
    h.run_steps(3);
    assert_eq!(boundary(&h).map(|b| b.rule), Some(BoundaryRule::Contact));

    h.get_by_label("Machining").click();
    h.run_steps(3);
    h.get_by_label("Add Pencil finishing").click();
    h.run_steps(2);
    let ops = &h.state().session().project.operations;
    assert_eq!(ops.len(), 2);
    assert_eq!(ops[1].kind(), OperationKind::Pencil);
    h.get_by_label("Corner angle");
    assert!(h.query_all_by_label_contains("°").next().is_some());
    // The default part's hills have no valley a 6 mm ball touches twice: the calculation ends
    // with no path and says why in the log (the pencil path itself is checked on
    // pocket-fillets through the pipeline in tests/operation_3axis.rs).
    h.state_mut().apply(Command::Calculate(1));
    app::settle_while(&mut h, "calculation", Workstation::is_calculating);
    assert!(h.state().operation_result(1).is_none());
    assert!(
        h.state()
            .log()
            .entries
            .iter()
            .any(|e| e.severity == Severity::Error && e.text.contains("no pencil line")),
        "the reason is logged: {:?}",
        h.state().log().entries.last()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The remaining collisions of a 5-axis finishing operation on a real face are listed under its
/// summary, and clicking one puts the tool at that pose (the pose panel shows it). The tool's
/// 12 × 30 mm holder enters the pocket's wall beside fillet face 13 when the tilt-away is off
/// (with it on, or with a tool without holder, the path is clean and the list says so).
/// `cargo test --test app_operation_3axis findings`
#[test]
fn the_findings_of_a_finishing_operation_are_listed_and_a_click_shows_the_pose() {
    use talas::app::panels::properties::Focus;
    use talas::project::ToolEntry;
    use talas::project::finish_group::{FindingKind, findings};
    use talas::tools::solid::ToolPart;
    let dir = common::temp_dir("app-findings");
    let part =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pocket-fillets.stp");
    // A tall window: the list lies below the summary.
    let mut h = app::harness(WorkstationConfig::isolated(Some(part), dir.clone()), 3000.0);
    app::settle_while(&mut h, "load", |w| w.is_loading() || w.is_computing_field());
    let cutter = talas::tools::parse_tool_spec("ball:d=6,flute=12,length=30,holder=12x30")
        .expect("tool spec");
    let tool = ToolEntry {
        name: "Ball 6 in a 12 mm holder".into(),
        cutter,
    };
    let mut op = Operation::new(OperationKind::IsoParametric, 0, 13);
    if let Operation::Finish {
        options, tilt_away, ..
    } = &mut op
    {
        options.scallop = 0.1;
        options.tolerance = 0.02;
        options.exact_check = true;
        tilt_away.enabled = false;
    }
    h.state_mut().apply(Command::Edit(Edit::Batch(vec![
        Edit::AddTool { index: 0, tool },
        Edit::SetMachine("trt-ac".into()),
        Edit::AddOperation {
            index: 0,
            operation: op,
        },
    ])));
    h.state_mut().apply(Command::Inspect(Focus::Operation(0)));
    h.state_mut().apply(Command::Calculate(0));
    app::settle_while(&mut h, "calculation", Workstation::is_calculating);
    let list = findings(&h.state().operation_result(0).expect("a result").0.computed);
    assert!(
        list.iter()
            .any(|f| matches!(f.kind, FindingKind::Collision(ToolPart::Holder(_)))),
        "{list:?}"
    );
    h.run_steps(2);
    h.get_by_label("REMAINING GOUGES AND COLLISIONS");
    // Two entries at different poses, clicked in turn: the tool follows each.
    let first = &list[0];
    let other = list
        .iter()
        .find(|f| f.pose != first.pose)
        .expect("findings at two poses");
    for f in [other, first] {
        h.get_by_label(&f.label()).click();
        h.run_steps(2);
        assert_eq!(h.state().tool_pose_index(), Some(f.pose), "{}", f.label());
        h.get_by_label("Picked pose");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
