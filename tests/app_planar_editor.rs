//! The 2.5D and hole operations' editor in the workstation (issues 33, 34: "each operation's
//! editor"): a pocket added from the menu shows its own numbers and the shared record (feeds,
//! spindle, heights with what they are measured from, stock to leave), each with its unit;
//! typing a value edits the operation (undo takes the last one back), and a value out of
//! range is refused.
#![cfg(feature = "gui")]

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use talas::app::command::Command;
use talas::app::{Workstation, WorkstationConfig};
use talas::project::op_common::HeightFrom;
use talas::project::{Operation, OperationKind};

fn harness(config: WorkstationConfig) -> Harness<'static, Workstation> {
    let ws = Workstation::new(&egui::Context::default(), None, config);
    Harness::builder()
        .with_size(egui::vec2(1400.0, 1400.0))
        .with_accessibility_check(false)
        .build_ui_state(|ui, ws: &mut Workstation| ws.frame_ui(ui), ws)
}

fn settle(h: &mut Harness<'static, Workstation>) {
    for _ in 0..6000 {
        h.step();
        if !(h.state().is_loading() || h.state().is_computing_field()) {
            h.step();
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    panic!("the load never finished");
}

/// Type `text` into the number field labelled `label` and confirm it with Enter.
fn type_number(h: &mut Harness<'static, Workstation>, label: &str, text: &str) {
    h.get_by_label(label).focus();
    h.step();
    h.get_by_label(label).set_text_value_accesskit(text);
    h.step();
    h.key_press_modifiers(egui::Modifiers::NONE, egui::Key::Enter);
    h.step();
    h.step();
}

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
    let mut h = harness(WorkstationConfig::isolated(None, dir.clone()));
    settle(&mut h);
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

    type_number(&mut h, "Step-down", "1.25");
    assert_eq!(pocket(&h).step_down_mm, 1.25);
    type_number(&mut h, "Step-over", "40");
    assert!(
        (pocket(&h).step_over_fraction - 0.4).abs() < 1e-12,
        "40 % of Ø"
    );
    type_number(&mut h, "Feed", "750");
    assert_eq!(pocket(&h).common.feed_mm_per_min, 750.0);
    type_number(&mut h, "Stock to leave, walls", "0.3");
    assert_eq!(pocket(&h).common.stock_to_leave_walls_mm, 0.3);
    // Out of range: refused, the value stays.
    type_number(&mut h, "Step-down", "-2");
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
