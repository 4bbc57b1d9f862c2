//! The part's machining features in the workstation's tree (issue 33, "features in the tree,
//! each clickable"): on the 2.5D test part made with Open CASCADE (`tests/data/pocket/`), the
//! tree lists the closed pocket, the slot, the step and the outer profile with their floor
//! heights, depths, areas and corner radii as Open CASCADE's own description of the part
//! (`pocket-part.json`, written by its make_part.py) gives them; a click on a feature selects
//! its floor face.
#![cfg(feature = "gui")]

mod common;

use std::path::PathBuf;

use common::app;
use egui_kittest::kittest::Queryable;
use talas::app::WorkstationConfig;
use talas::app::document::Selection;

#[test]
fn the_tree_lists_the_parts_features_and_a_click_selects_the_floor() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/pocket");
    let occ: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data.join("pocket-part.json")).unwrap())
            .unwrap();
    let dir = std::env::temp_dir().join(format!("talas-app-features-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = app::harness(
        WorkstationConfig::isolated(Some(data.join("pocket-part.stp")), dir.clone()),
        1200.0,
    );
    app::settle_load(&mut h);
    let features = h
        .state()
        .document()
        .expect("the part")
        .part
        .features
        .clone();
    let regions = occ["regions"].as_array().unwrap();
    h.get_by_label_contains("Features (");
    for r in regions {
        let kind = match r["kind"].as_str().unwrap() {
            "closed_pocket" => "Closed pocket",
            "slot" => "Slot",
            "step" => "Step",
            "outer_profile" => "Outer profile",
            other => panic!("{other}"),
        };
        let start = format!(
            "{kind} · floor {:.3} mm · depth {:.3} mm · {:.0} mm²",
            r["floor_z_mm"].as_f64().unwrap(),
            r["depth_mm"].as_f64().unwrap(),
            r["floor_area_mm2"].as_f64().unwrap()
        );
        let row = features
            .iter()
            .find(|f| f.text.starts_with(&start))
            .unwrap_or_else(|| panic!("no feature '{start}…' in {features:#?}"));
        if let Some(c) = r["min_corner_radius_mm"].as_f64() {
            assert!(
                row.text.contains(&format!("corners R{c:.3} mm")),
                "{}",
                row.text
            );
        }
        h.get_by_label(&row.text);
    }
    // A click on the pocket selects its floor.
    let pocket = features
        .iter()
        .find(|f| f.text.starts_with("Closed pocket"))
        .unwrap()
        .clone();
    h.get_by_label(&pocket.text).click();
    h.run_steps(3);
    assert_eq!(
        h.state().document().unwrap().selection,
        Selection::Face(pocket.faces[0])
    );
    let _ = std::fs::remove_dir_all(&dir);
}
