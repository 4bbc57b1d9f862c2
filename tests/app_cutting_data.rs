//! Feeds and speeds from the stock's material in the workstation (issue 31, "each operation's
//! speeds come from it unless typed, the editor says where each number came from"), through
//! the real UI with egui_kittest: the material chosen under Stock, a new operation taking the
//! library's feed, the editor saying so, a typed feed shown as typed, and the editor's button
//! writing the library's numbers back. The numbers are checked against the closed forms of the
//! library's table (n = 1000·v_c/(π·D), v_f = f_z·z·n), not against the editor's own text.
#![cfg(feature = "gui")]

mod common;

use common::app;
use egui_kittest::kittest::Queryable;
use talas::app::WorkstationConfig;
use talas::app::command::Command;
use talas::app::panels::properties::Focus;
use talas::force::cutting_data::{self, ToolMaterial};
use talas::project::cutting::WorkMaterial;
use talas::project::{Edit, Operation};

fn raster_feed(op: &Operation) -> f64 {
    match op {
        Operation::Raster {
            feed_mm_per_min, ..
        } => *feed_mm_per_min,
        other => panic!("not a raster: {other:?}"),
    }
}

#[test]
fn a_new_operation_takes_the_materials_feed_and_the_editor_says_where_it_came_from() {
    let dir = common::temp_dir("app-cutting-data");
    let mut h = app::harness(WorkstationConfig::isolated(None, dir), 1300.0);
    app::settle_load(&mut h);

    // The stock's material, chosen in the project tree's Stock section.
    h.state_mut().apply(Command::Inspect(Focus::Stock));
    h.run_steps(3);
    // The material's combo box has no label of its own (the grid's "Material" cell names it).
    h.get(
        egui_kittest::kittest::By::new()
            .role(egui::accesskit::Role::ComboBox)
            .value("None (feeds typed)"),
    )
    .click();
    h.run_steps(2);
    h.get_by_label("aluminium 6061-T6").click();
    h.run_steps(3);
    let material = h.state().session().project.material.clone();
    assert_eq!(
        material,
        Some(WorkMaterial {
            key: "6061".into(),
            tool_material: ToolMaterial::Carbide
        })
    );

    // A raster with the default Ø6 ball: its feed is the library's for the step its scallop
    // gives (a_e = 2·√(h(D − h))), two flutes assumed.
    h.get_by_label("Machining").click();
    h.run_steps(3);
    h.get_by_label("Add Raster finishing").click();
    h.run_steps(4);
    let project = h.state().session().project.clone();
    let op = &project.operations[0];
    let Operation::Raster { scallop_mm, .. } = op else {
        panic!("raster")
    };
    let m = cutting_data::material("6061").expect("6061");
    let d = 6.0;
    let n = 1000.0 * m.vc_carbide_m_min / (std::f64::consts::PI * d);
    let ae = 2.0 * (scallop_mm * (d - scallop_mm)).sqrt();
    let thinning = (d / (2.0 * (ae * (d - ae)).sqrt())).min(cutting_data::MAX_CHIP_THINNING);
    let feed = m.chip_load_mm(d, ToolMaterial::Carbide) * thinning * 2.0 * n;
    assert!(
        (raster_feed(op) - feed.round()).abs() < 0.5,
        "feed {} mm/min, closed form {feed:.1} mm/min",
        raster_feed(op)
    );
    h.get_by_label_contains("Feeds and speeds");
    h.get_by_label("✔ The operation's feeds and speeds are the library's.");
    h.get_by_label("Where each number came from").click();
    h.run_steps(2);
    h.get_by_label_contains("2 flutes assumed");

    // A typed feed is shown as typed; the button writes the library's back.
    let mut typed = op.clone();
    if let Operation::Raster {
        feed_mm_per_min, ..
    } = &mut typed
    {
        *feed_mm_per_min = 777.0;
    }
    h.state_mut().apply(Command::Edit(Edit::SetOperation {
        index: 0,
        operation: typed,
    }));
    h.run_steps(3);
    h.get_by_label("The operation's feeds are typed.");
    h.get_by_label("Use the library's feeds and speeds").click();
    h.run_steps(3);
    let back = raster_feed(&h.state().session().project.operations[0]);
    assert!((back - feed.round()).abs() < 0.5, "{back}");
}
