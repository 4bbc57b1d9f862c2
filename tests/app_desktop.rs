//! The workstation's desktop behaviour, driven headless with egui_kittest (no window, no GPU):
//! the unsaved-changes question before New, Open and Quit (the window's close button included),
//! Save As naming an untitled project and keeping the view, a new project dropping everything
//! derived from the old one, the number fields (one undo step, out-of-range values refused with
//! the reason), picking and stepping poses with the G-code pane following, the "Stock here"
//! report and its tolerance band, the project tree following a picked face, and the in-window
//! file chooser with its file types and recent files.
#![cfg(feature = "gui")]

mod common;

use std::path::{Path, PathBuf};
use std::time::Duration;

use common::app::{
    gcode_line_of_pose, gcode_pane, is_posting, is_simulating, program, simulation, simulation_of,
};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use talas::app::command::{Command, PlaybackCommand};
use talas::app::document::Selection;
use talas::app::file_chooser::ChooserPurpose;
use talas::app::panels::properties::Focus;
use talas::app::{Workstation, WorkstationConfig};
use talas::project::{Edit, Operation, OperationKind, Project};
use talas::render::{Projection, StandardView};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// A fresh data folder for one test.
fn data_dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("talas-desktop-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let _ = std::fs::create_dir_all(&d);
    d
}

fn harness(file: Option<PathBuf>, dir: &Path) -> Harness<'static, Workstation> {
    let config = WorkstationConfig::isolated(file, dir.to_path_buf());
    let ws = Workstation::new(&egui::Context::default(), None, config);
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .with_accessibility_check(false)
        .build_ui_state(|ui, ws: &mut Workstation| ws.frame_ui(ui), ws)
}

/// Step frames while `busy` says a background job runs (at most 30 s), then one more.
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

fn settle(h: &mut Harness<'static, Workstation>) {
    settle_while(h, "load", |w| w.is_loading() || w.is_computing_field());
}

fn press(h: &mut Harness<'static, Workstation>, modifiers: egui::Modifiers, key: egui::Key) {
    h.key_press_modifiers(modifiers, key);
    h.step();
    h.step();
}

fn click(h: &mut Harness<'static, Workstation>, label: &str) {
    h.get_by_label(label).click();
    h.run_steps(2);
}

fn rename(h: &mut Harness<'static, Workstation>, name: &str) {
    h.state_mut()
        .apply(Command::Edit(Edit::Rename(name.to_string())));
    h.step();
}

fn waiting(h: &Harness<'static, Workstation>) -> Option<Command> {
    h.state().waiting_for_unsaved_answer().cloned()
}

fn sent(h: &Harness<'static, Workstation>, command: &egui::ViewportCommand) -> bool {
    h.output()
        .viewport_output
        .get(&egui::ViewportId::ROOT)
        .is_some_and(|v| v.commands.contains(command))
}

#[test]
fn unsaved_changes_are_asked_about_before_new_open_and_quit() {
    let dir = data_dir("unsaved");
    let mut h = harness(None, &dir);
    settle(&mut h);
    let name = |h: &Harness<'static, Workstation>| h.state().session().project.name.clone();

    // Nothing unsaved: New does not ask.
    h.state_mut().apply(Command::NewProject);
    h.step();
    assert_eq!(waiting(&h), None);
    settle(&mut h);

    // Ctrl+N with a change asks; Cancel keeps the project and its change.
    rename(&mut h, "Bracket");
    press(&mut h, egui::Modifiers::COMMAND, egui::Key::N);
    assert_eq!(waiting(&h), Some(Command::NewProject));
    h.get_by_label_contains("Save the changes to 'Bracket'");
    click(&mut h, "Cancel");
    assert_eq!(waiting(&h), None);
    assert_eq!(name(&h), "Bracket");
    assert!(h.state().session().is_dirty());

    // Ctrl+N again; Discard starts the new project.
    press(&mut h, egui::Modifiers::COMMAND, egui::Key::N);
    click(&mut h, "Discard");
    assert_eq!(name(&h), "Untitled");
    assert!(!h.state().session().is_dirty());
    settle(&mut h);

    // Open Project with a change asks; after Discard the chooser opens (no system dialog here).
    rename(&mut h, "Bracket 2");
    h.state_mut().apply(Command::OpenProjectDialog);
    h.run_steps(2);
    assert_eq!(waiting(&h), Some(Command::OpenProjectDialog));
    assert!(
        h.state().chooser().is_none(),
        "nothing opens before the answer"
    );
    click(&mut h, "Discard");
    assert_eq!(
        h.state().chooser().map(|c| c.purpose()),
        Some(ChooserPurpose::OpenProject)
    );
    press(&mut h, egui::Modifiers::NONE, egui::Key::Escape);
    assert!(h.state().chooser().is_none(), "Escape closes the chooser");

    // The window's close button: the close is held back and the question asked.
    h.input_mut()
        .viewports
        .entry(egui::ViewportId::ROOT)
        .or_default()
        .events
        .push(egui::ViewportEvent::Close);
    h.step();
    assert!(sent(&h, &egui::ViewportCommand::CancelClose));
    h.step();
    assert_eq!(waiting(&h), Some(Command::Quit));
    click(&mut h, "Cancel");
    assert!(!sent(&h, &egui::ViewportCommand::Close));

    // Ctrl+Q on a saved project: Save writes the change, then the window closes.
    let path = dir.join("bracket.talas");
    h.state_mut().apply(Command::SaveProjectAs(path.clone()));
    rename(&mut h, "Bracket 3");
    press(&mut h, egui::Modifiers::COMMAND, egui::Key::Q);
    assert_eq!(waiting(&h), Some(Command::Quit));
    h.get_by_label("Save").click();
    h.step();
    assert!(sent(&h, &egui::ViewportCommand::Close));
    assert!(!h.state().session().is_dirty());
    assert_eq!(Project::load(&path).expect("saved").name, "Bracket 3");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn save_as_names_an_untitled_project_and_keeps_the_view() {
    let dir = data_dir("save-as");
    let mut h = harness(None, &dir);
    settle(&mut h);
    h.state_mut()
        .apply(Command::StandardView(StandardView::Right));
    h.state_mut()
        .apply(Command::SetProjection(Projection::Orthographic));
    h.step();
    let path = dir.join("hills bracket.talas");
    h.state_mut().apply(Command::SaveProjectAs(path.clone()));
    h.step();
    assert_eq!(h.state().session().project.name, "hills bracket");
    assert!(h.state().title().starts_with("hills bracket — "));
    let saved = Project::load(&path).expect("saved");
    assert_eq!(saved.name, "hills bracket");
    // The right view: the eye on +X (yaw 0, level), orthographic.
    assert!(saved.view.yaw_rad.abs() < 1e-6 && saved.view.pitch_rad.abs() < 1e-6);
    assert!(saved.view.orthographic);
    let camera = *h.state().camera();
    assert!((saved.view.distance_mm - f64::from(camera.distance)).abs() < 1e-3);

    // A new project fits the default view; opening the saved one brings its view back.
    h.state_mut().apply(Command::NewProject);
    settle(&mut h);
    h.step();
    assert!(h.state().camera().yaw_rad.abs() > 0.1);
    h.state_mut().apply(Command::OpenProject(path.clone()));
    settle(&mut h);
    let c = h.state().camera();
    assert!(c.yaw_rad.abs() < 1e-6 && c.pitch_rad.abs() < 1e-6);
    assert_eq!(c.projection, Projection::Orthographic);
    assert!((f64::from(c.distance) - saved.view.distance_mm).abs() < 1e-3);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Type `text` into the number field labelled `label` and confirm it with Enter.
fn type_number(h: &mut Harness<'static, Workstation>, label: &str, text: &str) {
    h.get_by_label(label).focus();
    h.step();
    h.get_by_label(label).set_text_value_accesskit(text);
    h.step();
    press(h, egui::Modifiers::NONE, egui::Key::Enter);
}

#[test]
fn number_fields_apply_once_and_refuse_out_of_range_values() {
    let dir = data_dir("numbers");
    let mut h = harness(None, &dir);
    settle(&mut h);
    h.state_mut().apply(Command::Edit(Edit::AddOperation {
        index: 0,
        operation: Operation::new(OperationKind::Raster, 0, 0),
    }));
    h.state_mut().apply(Command::Inspect(Focus::Operation(0)));
    h.run_steps(2);
    let raster =
        |h: &Harness<'static, Workstation>| match &h.state().session().project.operations[0] {
            Operation::Raster {
                scallop_mm,
                feed_mm_per_min,
                ..
            } => (*scallop_mm, *feed_mm_per_min),
            other => panic!("{other:?}"),
        };
    let (scallop0, feed0) = raster(&h);

    // Typing 0.07 changes nothing until Enter, then is one edit: one undo restores the old value.
    h.get_by_label("Scallop height").focus();
    h.step();
    h.get_by_label("Scallop height")
        .set_text_value_accesskit("0.07");
    h.run_steps(2);
    assert_eq!(raster(&h).0, scallop0, "nothing applied while typing");
    press(&mut h, egui::Modifiers::NONE, egui::Key::Enter);
    assert!((raster(&h).0 - 0.07).abs() < 1e-12, "{}", raster(&h).0);
    assert_eq!(
        h.state().session().history.undo_label(),
        Some("Edit operation")
    );
    press(&mut h, egui::Modifiers::COMMAND, egui::Key::Z);
    assert_eq!(raster(&h).0, scallop0, "one undo step per typed value");
    assert_eq!(
        h.state().session().history.undo_label(),
        Some("Add operation")
    );

    // 250000 mm/min is refused with the reason; nothing changes, no undo step.
    type_number(&mut h, "Feed", "250000");
    assert_eq!(raster(&h).1, feed0);
    h.get_by_label("Not applied: 250000 mm/min is above the largest value allowed, 100000 mm/min");
    assert_eq!(
        h.state().session().history.undo_label(),
        Some("Add operation")
    );
    assert_eq!(h.get_by_label("Feed").value().as_deref(), Some("1000"));
    // A value in range is applied and clears the reason.
    type_number(&mut h, "Feed", "2500 mm/min");
    assert_eq!(raster(&h).1, 2500.0);
    assert!(
        h.query_all_by_label_contains("Not applied")
            .next()
            .is_none()
    );

    // The Edit menu names the step the user took.
    h.get_by_label("Edit").click();
    h.run_steps(3);
    h.get_by_label_contains("Undo Edit operation");
    press(&mut h, egui::Modifiers::NONE, egui::Key::Escape);

    // The spindle speed shows as a whole number of rpm.
    h.state_mut().apply(Command::Inspect(Focus::Machine));
    h.run_steps(2);
    assert_eq!(
        h.get_by_label("Spindle speed").value().as_deref(),
        Some("10000")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_tree_follows_a_picked_face_and_the_pick_follows_the_selection() {
    let dir = data_dir("faces");
    let mut h = harness(Some(data("pocket-fillets.stp")), &dir);
    settle(&mut h);
    let faces = h.state().document().expect("loaded").part.faces.len();
    assert!(faces > 20, "{faces} faces");
    let last = format!("Face {faces} ");
    // The face list shows the first faces only.
    assert!(h.query_all_by_label_contains(&last).next().is_none());
    // A pick on the last face (as a click in the viewport makes it): the list scrolls to it.
    let part = &h.state().document().expect("loaded").part;
    let face = &part.faces[faces - 1];
    let triangle = part
        .face_of_triangle()
        .iter()
        .position(|&f| f as usize == faces - 1)
        .expect("a triangle of the face");
    let vertex = part.mesh().positions[part.mesh().triangles[triangle][0] as usize];
    let pick = talas::app::viewport::picking::surface_pick(faces - 1, face, vertex);
    h.state_mut()
        .apply(Command::Select(Selection::Face(faces - 1)));
    h.state_mut().apply(Command::SetPick(pick));
    h.run_steps(3);
    assert!(h.state().pick().is_some());
    assert!(h.query_all_by_label_contains(&last).next().is_some());
    // Selecting another face forgets the point picked on the last one.
    h.state_mut().apply(Command::Select(Selection::Face(0)));
    h.step();
    assert!(h.state().pick().is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_file_chooser_opens_where_no_system_dialog_is() {
    let dir = data_dir("chooser");
    let mut h = harness(None, &dir);
    settle(&mut h);
    let stl = data("bicubic-hills.stl");
    h.state_mut().apply(Command::Open(stl.clone()));
    settle(&mut h);
    // Ctrl+O: opening the part made a change (the project's part): Discard it, then the
    // chooser opens with the part file types and the recent file beside it.
    press(&mut h, egui::Modifiers::COMMAND, egui::Key::O);
    assert_eq!(waiting(&h), Some(Command::OpenDialog));
    click(&mut h, "Discard");
    settle(&mut h);
    assert_eq!(
        h.state().chooser().map(|c| c.purpose()),
        Some(ChooserPurpose::OpenPart)
    );
    h.get_by_label("STEP (.stp, .step)").click();
    h.run_steps(2);
    assert_eq!(
        h.state().chooser().map(|c| c.file_type().0),
        Some("STEP (.stp, .step)")
    );
    assert!(
        h.query_all_by_label_contains("bicubic-hills.stl ·")
            .next()
            .is_none(),
        "an STL file is not listed under STEP"
    );
    h.get_by_label("Talas project (.talas)").click();
    h.run_steps(2);
    h.get_by_label("None of this type yet");
    h.get_by_label("STL (.stl)").click();
    h.run_steps(2);
    // A click on the recent file opens it.
    h.get_by_label("bicubic-hills.stl · data").click();
    h.run_steps(2);
    assert!(h.state().chooser().is_none());
    assert!(h.state().is_loading(), "the recent file opens");
    settle(&mut h);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_new_project_forgets_the_old_path_simulation_and_program() {
    let dir = data_dir("derived");
    let mut h = harness(None, &dir);
    settle(&mut h);
    let mut op = Operation::new(OperationKind::Raster, 0, 0);
    if let Operation::Raster { scallop_mm, .. } = &mut op {
        *scallop_mm = 0.1;
    }
    h.state_mut().apply(Command::Edit(Edit::AddOperation {
        index: 0,
        operation: op.clone(),
    }));
    h.state_mut().apply(Command::Inspect(Focus::Operation(0)));
    h.state_mut().apply(Command::Calculate(0));
    settle_while(&mut h, "calculation", Workstation::is_calculating);
    let poses = h
        .state()
        .operation_result(0)
        .expect("computed")
        .0
        .toolpath()
        .poses
        .len();
    press(&mut h, egui::Modifiers::NONE, egui::Key::F7);
    settle_while(&mut h, "post", is_posting);
    h.run_steps(2);
    assert!(gcode_pane(h.state()).is_some());

    // Playback in use, then a pick (a collision entry or a G-code line makes the same
    // command): the tool stands at the picked pose.
    h.state_mut()
        .apply(Command::Playback(PlaybackCommand::Seek(5.0)));
    h.step();
    let pick = poses * 3 / 4;
    h.state_mut().apply(Command::PickPose(Some(pick)));
    h.run_steps(2);
    assert_eq!(h.state().tool_pose_index(), Some(pick));
    // Stepping with '.' goes on from the pick and the G-code pane follows (selects and shows
    // the pose's line).
    press(&mut h, egui::Modifiers::NONE, egui::Key::Period);
    h.run_steps(2);
    let stepped = h.state().tool_pose_index().expect("a pose");
    assert!(stepped > pick, "{pick} -> {stepped}");
    let line = (0..=stepped)
        .rev()
        .find_map(|p| gcode_line_of_pose(h.state(), p))
        .expect("a line of the stepped pose");
    let (selected, shown) = gcode_pane(h.state()).expect("pane");
    assert_eq!(selected, Some(line));
    assert!(shown.contains(&line), "{line} not in {shown:?}");

    // Stock here: the stock at the playback pose gets its report in the editor (cut from the
    // stock keyframes the whole simulation kept).
    h.state_mut().apply(Command::Simulate(0));
    settle_while(&mut h, "simulation", is_simulating);
    assert_eq!(
        simulation_of(h.state(), 0).map(|s| s.up_to_pose()),
        Some(None)
    );
    h.state_mut().apply(Command::SimulateToPlayback);
    settle_while(&mut h, "simulation", is_simulating);
    h.run_steps(2);
    let sim = simulation_of(h.state(), 0).expect("the report of the stock here");
    assert_eq!(sim.up_to_pose(), Some(stepped));
    // The deviation is coloured against ± the operation's scallop (0.1 mm), not ± the largest
    // deviation.
    assert!((sim.band_mm - 0.1).abs() < 1e-12);
    let m = sim.mapping();
    assert!((m.max - 0.2).abs() < 1e-6 && (m.min + 0.2).abs() < 1e-6);
    h.get_by_label("Deepest gouge");
    h.get_by_label_contains("(Stock here)");
    type_number(&mut h, "Tolerance band ±", "0.02");
    let band = simulation(h.state()).shown().expect("shown").band_mm;
    assert!((band - 0.02).abs() < 1e-12, "{band}");

    // Clicking a G-code line (the top one shown, above the stepped pose's) picks the pose its
    // block reaches: the tool stands there and the playback clock moves to it.
    let header = h.get_by_label_contains(" lines · ").rect();
    let at = egui::pos2(header.center().x, header.bottom() + 14.0);
    h.hover_at(at);
    h.step();
    h.drag_at(at);
    h.step();
    h.drop_at(at);
    h.run_steps(2);
    let clicked = gcode_pane(h.state()).and_then(|(s, _)| s).expect("a line");
    assert!(clicked < line, "clicked {clicked}, stepped to {line}");
    let pose = program(h.state())
        .pose_of_line(clicked)
        .expect("the line's pose");
    assert_eq!(h.state().tool_pose_index(), Some(pose));
    // The playback stands at the last pose reached at the picked pose's planned time (a
    // zero-length move may end there too).
    let at_pose = h.state().playback_position().expect("playing back");
    assert!(
        at_pose >= pose && at_pose < stepped,
        "{pose} {at_pose} {stepped}"
    );
    // Posting again restarts the playback (the whole path shown) and shows the new program's
    // G-code (the dock switches from the log to it).
    h.get_by_label("Log").click();
    h.run_steps(2);
    h.state_mut().apply(Command::PostActive);
    settle_while(&mut h, "post", is_posting);
    h.run_steps(2);
    assert_eq!(h.state().playback_position(), None);
    let (_, shown) = gcode_pane(h.state()).expect("the new program's pane");
    assert!(!shown.is_empty(), "the G-code tab is shown");

    // New project (Discard the changes): nothing of the old one stays attached.
    h.state_mut().apply(Command::NewProject);
    h.run_steps(2);
    click(&mut h, "Discard");
    settle(&mut h);
    h.state_mut().apply(Command::Edit(Edit::AddOperation {
        index: 0,
        operation: op,
    }));
    h.state_mut().apply(Command::Inspect(Focus::Operation(0)));
    h.run_steps(2);
    assert!(h.state().operation_result(0).is_none(), "no old path");
    assert!(gcode_pane(h.state()).is_none(), "no old program");
    assert!(simulation(h.state()).shown().is_none(), "no old stock");
    assert_eq!(h.state().tool_pose_index(), None);
    h.get_by_label("Not calculated yet.");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Face groups in the workstation: ctrl-click in the face tree selects several faces, the
/// "Tangent-connected faces" button selects the tangent chain of the last clicked face, a
/// button creates the group operation over the chain.
#[test]
fn a_face_group_is_selected_by_clicks_and_tangent_chain_and_becomes_one_operation() {
    let dir = data_dir("group");
    let mut h = harness(Some(data("pocket-fillets.stp")), &dir);
    settle(&mut h);
    // Selecting a face opens the tree's face list at it.
    h.state_mut().apply(Command::Select(Selection::Face(13)));
    h.run_steps(3);
    h.get_by_label_contains("Face 14 ").click();
    h.run_steps(2);
    h.get_by_label_contains("Face 17 ")
        .click_modifiers(egui::Modifiers::COMMAND);
    h.run_steps(2);
    h.get_by_label_contains("2 faces (");
    assert_eq!(
        h.state().document().expect("part").selection,
        Selection::Face(16)
    );
    // The tangent chain of face 16 (0-based) replaces the two.
    click(&mut h, "Tangent-connected faces");
    let part = h.state().document().expect("part").part.workpiece.clone();
    let chain = talas::geometry::brep::tangent_connected(
        part.part.as_ref().expect("B-rep"),
        16,
        1f64.to_radians(),
    );
    assert!(chain.len() > 2, "{chain:?}");
    h.get_by_label_contains(&format!("{} faces (", chain.len()));
    click(&mut h, "Iso-planar finishing on the group");
    let op = h.state().session().project.operations[0].clone();
    assert_eq!(op.faces(), chain);
    assert_eq!(op.kind(), OperationKind::IsoPlanar);

    let _ = std::fs::remove_dir_all(&dir);
}

/// Opening a part into a saved project with an operation and a stock starts a new project for
/// that part: the last part's operations, stock and machine do not stay on it, and Save does
/// not overwrite the last project's file (issue 35). A part that fails to open changes nothing.
#[test]
fn opening_a_part_starts_a_new_project() {
    use talas::project::Stock;
    let dir = data_dir("open-part-new-project");
    let mut h = harness(None, &dir);
    settle(&mut h);
    h.state_mut().apply(Command::Edit(Edit::AddOperation {
        index: 0,
        operation: Operation::new(OperationKind::Raster, 0, 0),
    }));
    let stock = Stock::Box {
        min_mm: [-1.0, -1.0, -1.0],
        max_mm: [1.0, 1.0, 1.0],
    };
    h.state_mut().apply(Command::Edit(Edit::SetStock(stock)));
    h.state_mut()
        .apply(Command::Edit(Edit::SetMachine("trt-ac".into())));
    let file = dir.join("first.talas");
    h.state_mut().apply(Command::SaveProjectAs(file.clone()));
    h.run_steps(2);
    let saved = std::fs::read_to_string(&file).expect("saved");
    assert_eq!(h.state().session().path.as_deref(), Some(file.as_path()));
    // A malformed part: an error, and the project stays as it was.
    h.state_mut().apply(Command::Open(data("bad/bad-enum.stp")));
    settle(&mut h);
    assert_eq!(h.state().session().project.operations.len(), 1);
    assert_eq!(h.state().session().path.as_deref(), Some(file.as_path()));
    // A good part: a new, untitled project on it.
    let stl = data("bicubic-hills.stl");
    h.state_mut().apply(Command::Open(stl.clone()));
    settle(&mut h);
    let session = h.state().session();
    assert!(session.project.operations.is_empty());
    assert_eq!(session.project.stock, Stock::None);
    assert_eq!(session.project.machine, Project::default().machine);
    assert_eq!(session.path, None, "Save must not overwrite first.talas");
    assert_eq!(
        session.project.part.as_ref().map(|p| p.path.clone()),
        Some(stl)
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), saved);
    let _ = std::fs::remove_dir_all(&dir);
}
