//! The profile editor driven through its UI with egui_kittest (headless): points clicked onto
//! the canvas, inserted on a segment and deleted, one dragged; a bad row typed into the table
//! and its message seen; the radius changed and the plunge flag following it, its depth
//! checked against its closed form; import and
//! export of profiles and G-code; the window opened from the workstation's menu.
#![cfg(feature = "gui")]

use std::path::PathBuf;
use std::time::Duration;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::DVec2;
use talas::app::profile_editor::ProfileEditor;
use talas::app::profile_editor::rows::Row;
use talas::app::{Workstation, WorkstationConfig};
use talas::profile::FlagKind;

fn harness(editor: ProfileEditor) -> Harness<'static, ProfileEditor> {
    let mut h = Harness::builder()
        .with_size(egui::vec2(1300.0, 820.0))
        .with_accessibility_check(false)
        .build_ui_state(|ui, ed: &mut ProfileEditor| ed.ui(ui), editor);
    h.run_steps(2);
    h
}

/// Step until the shown result is the one for the table.
fn settle(h: &mut Harness<'static, ProfileEditor>) {
    for _ in 0..2000 {
        h.step();
        if !h.state().is_computing() {
            h.step();
            return;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    panic!("the profile path was never computed");
}

fn at(h: &Harness<'static, ProfileEditor>, x: f64, y: f64) -> egui::Pos2 {
    h.state()
        .screen_of(DVec2::new(x, y))
        .expect("the canvas has been drawn")
}

fn click(h: &mut Harness<'static, ProfileEditor>, p: egui::Pos2, button: egui::PointerButton) {
    h.hover_at(p);
    h.step();
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos: p,
            button,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
    }
    h.run_steps(2);
}

fn cells(h: &Harness<'static, ProfileEditor>) -> Vec<(String, String)> {
    h.state()
        .rows()
        .iter()
        .map(|r| (r.x.clone(), r.y.clone()))
        .collect()
}

fn xy(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
    pairs
        .iter()
        .map(|(x, y)| ((*x).to_string(), (*y).to_string()))
        .collect()
}

/// Gouge of the per-point centre at the kink (0, 0) between the flanks to (−6, 0) and to
/// (6, `rise`): the normal is that of the chord between the neighbours (at angle φ to the first
/// flank's normal, ψ − φ to the second's, ψ the kink's turn), so the centre lies R cos φ and
/// R cos(ψ − φ) from the flanks' lines, both closest points inside the flanks.
fn kink_gouge(r: f64, rise: f64) -> f64 {
    let phi = rise.atan2(12.0);
    let psi = rise.atan2(6.0);
    r * (1.0 - phi.max(psi - phi).cos())
}

fn type_into(h: &mut Harness<'static, ProfileEditor>, label: &str, text: &str) {
    h.get_by_label(label).focus();
    h.step();
    h.get_by_label(label).set_text_value_accesskit(text);
    h.run_steps(2);
}

#[test]
fn click_insert_delete_drag_and_the_radius_moves_the_plunge_flag() {
    let mut h = harness(ProfileEditor::empty());
    // Three clicks on the canvas: three rows (snapped to the 1 mm grid).
    for (x, y) in [(-6.0, 0.0), (0.0, 0.0), (6.0, 1.0)] {
        let p = at(&h, x + 0.2, y - 0.15);
        click(&mut h, p, egui::PointerButton::Primary);
    }
    assert_eq!(cells(&h), xy(&[("-6", "0"), ("0", "0"), ("6", "1")]));
    // A click on the first segment inserts a point there; a right click deletes it.
    let p = at(&h, -3.0, 0.0);
    click(&mut h, p, egui::PointerButton::Primary);
    assert_eq!(
        cells(&h),
        xy(&[("-6", "0"), ("-3", "0"), ("0", "0"), ("6", "1")])
    );
    click(&mut h, p, egui::PointerButton::Secondary);
    assert_eq!(cells(&h), xy(&[("-6", "0"), ("0", "0"), ("6", "1")]));

    // Drag the last point from (6, 1) to (6, 2).
    let from = at(&h, 6.0, 1.0);
    let to = at(&h, 6.0, 2.0);
    h.hover_at(from);
    h.step();
    h.drag_at(from);
    h.step();
    for k in 1..=4 {
        h.hover_at(from + (to - from) * (k as f32 / 4.0));
        h.step();
    }
    h.drop_at(to);
    h.run_steps(2);
    assert_eq!(cells(&h), xy(&[("-6", "0"), ("0", "0"), ("6", "2")]));

    // R = 1.5 mm: the per-point centre at the kink plunges into the first flank.
    settle(&mut h);
    let rise = 2.0;
    let r = h.state().result().expect("computed");
    assert!((r.radius_mm - 1.5).abs() < 1e-12);
    assert_eq!(r.flags.len(), 1, "{:?}", r.flags);
    let f = r.flags[0];
    assert_eq!((f.kind, f.point_index), (FlagKind::Plunge, 1));
    let want = kink_gouge(1.5, rise);
    assert!((f.depth_mm - want).abs() < 1e-9, "{} vs {want}", f.depth_mm);
    // A sharp concave corner: no electrode reaches it.
    assert_eq!(r.max_gouge_free_radius_mm, 0.0);
    assert!(r.max_distance_error_mm < 1e-9);
    h.get_by_label_contains("Plunge: 0.0204 mm deep");
    // The flag in the list: a click selects it and centres the canvas on it.
    h.get_by_label_contains("Plunge at point 2 (x 0 mm, y 0 mm)")
        .click();
    h.run_steps(2);
    assert_eq!(h.state().selected_flag(), Some(0));
    assert!((h.state().view().centre - f.deepest).length() < 1e-12);

    // R = 0.05 mm: the gouge, 0.68 µm, is within the 1 µm tolerance; no flag.
    type_into(&mut h, "Electrode radius R", "0.05");
    h.key_press(egui::Key::Enter);
    h.run_steps(2);
    assert!((h.state().radius_mm() - 0.05).abs() < 1e-15);
    settle(&mut h);
    assert!(kink_gouge(0.05, rise) < 1e-3);
    let r = h.state().result().expect("computed");
    assert!((r.radius_mm - 0.05).abs() < 1e-15);
    assert!(r.flags.is_empty(), "{:?}", r.flags);
    h.get_by_label_contains("0 plunge(s), 0 side collision(s)");
    // And back to 3 mm: the flag returns, deeper.
    type_into(&mut h, "Electrode radius R", "3 mm");
    h.key_press(egui::Key::Enter);
    h.run_steps(2);
    settle(&mut h);
    let r = h.state().result().expect("computed");
    assert_eq!(r.flags.len(), 1);
    assert!((r.flags[0].depth_mm - kink_gouge(3.0, rise)).abs() < 1e-9);
}

#[test]
fn bad_rows_are_reported_on_their_row_and_nothing_is_computed() {
    let rows = [("0", "0"), ("2", "1"), ("4", "0")]
        .iter()
        .map(|(x, y)| Row {
            x: (*x).into(),
            y: (*y).into(),
            bulge: String::new(),
        })
        .collect();
    let mut ed = ProfileEditor::empty();
    ed.set_rows(rows);
    let mut h = harness(ed);
    settle(&mut h);
    assert!(h.state().result().is_some());

    // A new row, with text where x should be.
    h.get_by_label("+ Row").click();
    h.run_steps(2);
    assert_eq!(h.state().rows().len(), 4);
    type_into(&mut h, "x, row 4", "abc");
    assert_eq!(h.state().rows()[3].x, "abc");
    h.get_by_label("row 4: x 'abc' is not a number");
    h.get_by_label_contains("Fix the rows marked in red");
    assert!(h.state().computed().is_none());
    assert!(!h.state().is_computing());

    // x = 4 again: a vertical wall, against the rule y = f(x).
    type_into(&mut h, "x, row 4", "4");
    type_into(&mut h, "y, row 4", "2");
    h.get_by_label_contains("row 4: x = 4 mm repeats row 3: a vertical wall");
    // Without the rule the wall is fine and the path is computed.
    h.get_by_label("Rule y = f(x)").click();
    h.run_steps(2);
    assert!(h.query_by_label_contains("vertical wall").is_none());
    settle(&mut h);
    assert!(h.state().result().is_some_and(|r| !r.paths.is_empty()));
    // Out of range and a bad bulge.
    type_into(&mut h, "y, row 2", "2e7");
    h.get_by_label("row 2: y = 20000000 mm lies beyond ±1000000 mm");
    type_into(&mut h, "y, row 2", "1");
    type_into(&mut h, "bulge, row 2", "3");
    h.get_by_label_contains("row 2: bulge = 3 lies beyond ±1");
    // Deleting the row fixes the table.
    h.get_by_label("delete row 2").click();
    h.run_steps(2);
    assert_eq!(h.state().rows().len(), 3);
    assert!(!h.state().checked().has_errors());
}

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("talas-app-profile-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&d);
    d.join(name)
}

#[test]
fn import_export_profiles_and_gcode() {
    let csv = temp("arc.csv");
    // An open profile with an arc (bulge 0.4) between two lines.
    std::fs::write(&csv, "x,y,bulge\n0,0,0\n4,0,0.4\n8,0,0\n12,2,0\n").expect("write");
    let mut ed = ProfileEditor::empty();
    let said = ed.import_from(&csv).expect("read");
    assert!(said.contains("4 points (open)"), "{said}");
    assert_eq!(ed.rows()[1].bulge, "0.4");
    let ctx = egui::Context::default();
    assert!(ed.wait(&ctx, Duration::from_secs(20)));
    let r = ed.result().expect("computed").clone();
    assert!(r.max_distance_error_mm < 1e-9);

    // DXF out and back in: the same points and bulges.
    let dxf = temp("arc.dxf");
    ed.export_profile_to(&dxf).expect("dxf");
    let mut again = ProfileEditor::empty();
    again.import_from(&dxf).expect("read dxf");
    assert_eq!(again.rows(), ed.rows());

    // G-code: arcs kept, the chosen plane, byte-identical when written twice.
    let ngc = temp("arc.ngc");
    ed.export_gcode_to(&ngc).expect("gcode");
    let text = std::fs::read_to_string(&ngc).expect("read gcode");
    assert!(text.contains("G18"), "{text}");
    assert!(text.contains("G2") || text.contains("G3"), "{text}");
    let first = text.clone();
    ed.export_gcode_to(&ngc).expect("gcode");
    assert_eq!(std::fs::read_to_string(&ngc).expect("again"), first);
    // The program runs through the interpreter without errors.
    let program = talas::gcode::interpret(
        &first,
        &talas::gcode::InterpretOptions::for_syntax(talas::gcode::Syntax::default()),
    );
    assert!(program.is_ok(), "{program:?}");

    // A broken file: one line naming the file and the row; the table is kept.
    let bad = temp("bad.csv");
    std::fs::write(&bad, "x,y\n0,0\n1,zz\n").expect("write");
    let e = ed.import_from(&bad).expect_err("bad row");
    assert!(e.contains("bad.csv") && e.contains("row 3"), "{e}");
    assert_eq!(ed.rows().len(), 4);
    // Nothing to post while the table has errors.
    ed.set_rows(vec![Row {
        x: "q".into(),
        y: "0".into(),
        bulge: String::new(),
    }]);
    assert!(ed.export_gcode_to(&ngc).is_err());
    assert!(ed.export_profile_to(&temp("never.csv")).is_err());
}

#[test]
fn the_workstation_menu_opens_the_editor() {
    let dir = std::env::temp_dir().join(format!("talas-app-profile-ws-{}", std::process::id()));
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
            .feature::<ProfileEditor>()
            .is_some_and(|p| !p.open)
    );
    h.get_by_label("Machining").click();
    h.run_steps(3);
    h.get_by_label("2D profile / EDM electrode…").click();
    h.run_steps(3);
    assert!(
        h.state_mut()
            .feature::<ProfileEditor>()
            .is_some_and(|p| p.open)
    );
    h.get_by_label_contains("Profile editor · ball electrode");
    // The example profile is computed and its gouges listed.
    for _ in 0..2000 {
        h.step();
        if !h
            .state_mut()
            .feature::<ProfileEditor>()
            .is_some_and(|p| p.is_computing())
        {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    h.run_steps(2);
    let flags = h
        .state_mut()
        .feature::<ProfileEditor>()
        .and_then(|p| p.result())
        .map_or(0, |r| r.flags.len());
    assert!(flags > 0);
    h.get_by_label_contains("Largest gouge-free radius: 0 mm");
}
