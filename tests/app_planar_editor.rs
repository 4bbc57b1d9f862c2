//! The 2.5D and hole operations' editor in the workstation (issues 33, 34: "each operation's
//! editor"): a pocket added from the menu shows its own numbers and the shared record (feeds,
//! spindle, heights with what they are measured from, stock to leave), each with its unit;
//! typing a value edits the operation (undo takes the last one back), and a value out of
//! range is refused.
#![cfg(feature = "gui")]

mod common;

use common::app;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use talas::app::command::Command;
use talas::app::{Workstation, WorkstationConfig};
use talas::project::op_common::HeightFrom;
use talas::project::{Operation, OperationKind};

fn pocket(h: &Harness<'static, Workstation>) -> talas::project::op_pocket::PocketOp {
    match &h.state().session().project.operations[0] {
        Operation::Pocket(p) => p.clone(),
        other => panic!("not a pocket: {:?}", other.kind()),
    }
}

#[test]
fn a_pocket_is_edited_in_its_editor_with_units() {
    let dir = std::env::temp_dir().join(format!("talas-app-planar-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 1400.0);
    app::settle_load(&mut h);
    h.state_mut()
        .apply(Command::AddOperation(OperationKind::Pocket));
    h.run_steps(3);
    assert_eq!(h.state().session().project.operations.len(), 1);
    for row in [
        "Step-down",
        "Step-over",
        "Ramp angle",
        "Feed",
        "Plunge feed",
        "Clearance",
        "Retract",
        "Feed from",
        "Stock to leave, walls",
    ] {
        h.get_by_label(row);
    }
    assert!(h.query_all_by_label_contains("mm/min").next().is_some());
    assert!(h.query_all_by_label_contains("% of Ø").next().is_some());
    let before = pocket(&h);

    app::type_number(&mut h, "Step-down", "1.25");
    assert_eq!(pocket(&h).step_down_mm, 1.25);
    app::type_number(&mut h, "Step-over", "40");
    assert!(
        (pocket(&h).step_over_fraction - 0.4).abs() < 1e-12,
        "40 % of Ø"
    );
    app::type_number(&mut h, "Feed", "750");
    assert_eq!(pocket(&h).common.feed_mm_per_min, 750.0);
    app::type_number(&mut h, "Stock to leave, walls", "0.3");
    assert_eq!(pocket(&h).common.stock_to_leave_walls_mm, 0.3);
    // Out of range: refused, the value stays.
    app::type_number(&mut h, "Step-down", "-2");
    assert_eq!(pocket(&h).step_down_mm, 1.25);
    // Each height names what it is measured from: the clearance and the feed-from height
    // the stock's top, the retract (the cycles' R plane) the part's top, as the defaults are.
    assert_eq!(before.common.clearance.from, HeightFrom::StockTop);
    assert_eq!(before.common.retract.from, HeightFrom::PartTop);
    let combo = |h: &Harness<'static, Workstation>, value: &str| {
        h.query_all(
            egui_kittest::kittest::By::new()
                .role(egui::accesskit::Role::ComboBox)
                .value(value),
        )
        .count()
    };
    assert_eq!(combo(&h, "the stock's top"), 2);
    assert_eq!(combo(&h, "the part's top"), 1);
    assert_ne!(pocket(&h), before);
    // The last committed value is one undo step: undo takes the walls' stock back alone.
    h.state_mut().apply(Command::Undo);
    h.step();
    let p = pocket(&h);
    assert_eq!(
        p.common.stock_to_leave_walls_mm,
        before.common.stock_to_leave_walls_mm
    );
    assert_eq!(p.common.feed_mm_per_min, 750.0);
    let _ = std::fs::remove_dir_all(&dir);
}
