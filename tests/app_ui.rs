//! The workstation driven through its UI with egui_kittest (headless: no window, no GPU; the 3D
//! viewport's paint callback is simply not drawn): open the default part, select it, edit a tool
//! value, undo and redo, drop a malformed file and see the error while the old part stays,
//! autosave and recovery. Plus the surface data the UI shows, against references: curvature at
//! a picked point against Open CASCADE's samples, and the per-vertex curvature field against
//! the closed-form radii of a filleted pocket.
#![cfg(feature = "gui")]

mod common;

use std::path::{Path, PathBuf};
use std::time::Duration;

use common::app;
use common::app::{
    is_posting, is_simulating, planned_feed, program_text, simulation, simulation_of,
};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use talas::app::command::Command;
use talas::app::document_loader::load_part;
use talas::app::file_chooser::ChooserPurpose;
use talas::app::file_dialog::SavePurpose;
use talas::app::panels::properties::Focus;
use talas::app::reduction::DataReduction;
use talas::app::scalar_field::curvature_field;
use talas::app::viewport::picking::surface_pick;
use talas::app::{Workstation, WorkstationConfig};
use talas::diagnostics::Progress;
use talas::project::Project;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// A fresh data folder for one test.
fn data_dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("talas-app-ui-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let _ = std::fs::create_dir_all(&d);
    d
}

/// A file dropped on the window, as the windowing backend would hand it over.
#[derive(Debug)]
struct DroppedPath(PathBuf);

impl egui::DroppedFile for DroppedPath {
    fn path(&self) -> &Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

fn press(h: &mut Harness<'static, Workstation>, modifiers: egui::Modifiers, key: egui::Key) {
    h.key_press_modifiers(modifiers, key);
    h.step();
    h.step();
}

#[test]
fn open_select_edit_undo_redo_and_a_malformed_file() {
    let dir = data_dir("main");
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 900.0);
    app::settle_load(&mut h);

    // The default part is open and the default ball end mill is the selected tool.
    let doc = h.state().document().expect("default part loaded");
    assert_eq!(doc.part.name, "bicubic-hills");
    let triangles = doc.part.mesh().triangles.len();
    let project = &h.state().session().project;
    let t = project.selected_tool().expect("a selected tool");
    assert_eq!(t.cutter.kind, talas::tools::CutterKind::Ball);
    assert!((t.cutter.diameter - 6.0).abs() < 1e-12);
    assert!(!h.state().title().contains('*'), "{}", h.state().title());

    // Select the part in the tree: the properties panel shows it.
    h.get_by_label_contains("Part · bicubic-hills").click();
    h.step();
    h.step();
    assert_eq!(h.state().focus(), Focus::Selection);
    h.get_by_label("Surface area");
    assert!(h.query_all_by_label_contains(" mm²").next().is_some());

    // Edit the tool's diameter in the properties panel.
    h.get_by_label_contains("T1 Ball end mill Ø6").click();
    h.step();
    h.step();
    assert_eq!(h.state().focus(), Focus::Tool(0));
    h.get_by_label("Diameter").focus();
    h.step();
    h.get_by_label("Diameter").set_text_value_accesskit("8");
    h.step();
    assert_eq!(h.get_by_label("Diameter").value().as_deref(), Some("8"));
    press(&mut h, egui::Modifiers::NONE, egui::Key::Enter);
    let diameter =
        |h: &Harness<'static, Workstation>| h.state().session().project.tools[0].cutter.diameter;
    assert!(
        (diameter(&h) - 8.0).abs() < 1e-12,
        "diameter {}",
        diameter(&h)
    );
    assert!(
        h.state().title().contains('*'),
        "dirty: {}",
        h.state().title()
    );
    // The library file follows the tools.
    let lib = std::fs::read_to_string(dir.join("tools.toml")).expect("library written");
    assert!(lib.contains("diameter = 8.0"), "{lib}");

    // Undo from the Edit menu, redo with Ctrl+Shift+Z, undo with Ctrl+Z, redo with Ctrl+Y.
    h.get_by_label("Edit").click();
    h.run_steps(3);
    h.get_by_label_contains("Undo Edit tool").click();
    h.step();
    h.step();
    assert!((diameter(&h) - 6.0).abs() < 1e-12);
    assert!(!h.state().title().contains('*'), "clean after undo");
    press(
        &mut h,
        egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
        egui::Key::Z,
    );
    assert!((diameter(&h) - 8.0).abs() < 1e-12);
    press(&mut h, egui::Modifiers::COMMAND, egui::Key::Z);
    assert!((diameter(&h) - 6.0).abs() < 1e-12);
    press(&mut h, egui::Modifiers::COMMAND, egui::Key::Y);
    assert!((diameter(&h) - 8.0).abs() < 1e-12);

    // Drop a malformed STEP file: first the question about the unsaved change (Discard), then
    // an error is shown, the part stays.
    let bad = data("bad/bad-enum.stp");
    h.input_mut()
        .dropped_files
        .push(std::sync::Arc::new(DroppedPath(bad.clone())));
    h.run_steps(3);
    assert_eq!(
        h.state().waiting_for_unsaved_answer(),
        Some(&Command::Open(bad.clone()))
    );
    assert!(!h.state().is_loading(), "nothing opens before the answer");
    h.get_by_label("Discard").click();
    h.run_steps(2);
    assert!(h.state().waiting_for_unsaved_answer().is_none());
    app::settle_load(&mut h);
    let doc = h.state().document().expect("the old part stays");
    assert_eq!(doc.part.name, "bicubic-hills");
    assert_eq!(doc.part.mesh().triangles.len(), triangles);
    assert!(
        h.query_all_by_label_contains("Could not open")
            .next()
            .is_some(),
        "the error is shown"
    );
    assert!(
        h.state()
            .log()
            .entries
            .iter()
            .any(|e| e.text.contains("bad-enum.stp") && e.text.contains("unchanged")),
        "the log names the file"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn save_autosave_and_recover() {
    let dir = data_dir("recover");
    let mut config = WorkstationConfig::isolated(None, dir.clone());
    config.autosave_every = Duration::ZERO;
    let mut h = app::harness(config, 900.0);
    app::settle_load(&mut h);
    h.state_mut()
        .apply(Command::Edit(talas::project::Edit::Rename("Hills".into())));
    h.step();
    let recovery = dir.join("untitled.talas.autosave");
    let autosaved = Project::load(&recovery).expect("autosaved project");
    assert_eq!(autosaved.name, "Hills");
    drop(h);

    // A new session finds the recovery file and offers it.
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 900.0);
    app::settle_load(&mut h);
    assert_eq!(h.state().pending_recovery(), Some(recovery.as_path()));
    h.get_by_label("Recover unsaved changes?");
    h.get_by_label("Recover").click();
    h.step();
    h.step();
    assert_eq!(h.state().session().project.name, "Hills");
    assert!(h.state().title().starts_with("Hills*"));

    // Save As writes the project and removes the recovery file.
    let path = dir.join("hills.talas");
    h.state_mut().apply(Command::SaveProjectAs(path.clone()));
    h.step();
    assert!(!recovery.exists());
    assert!(!h.state().title().contains('*'));
    assert_eq!(Project::load(&path).expect("saved").name, "Hills");

    // Opening the saved project by dropping it: clean, same name.
    drop(h);
    let mut h = app::harness(
        WorkstationConfig::isolated(Some(path.clone()), dir.clone()),
        900.0,
    );
    app::settle_load(&mut h);
    assert_eq!(h.state().session().project.name, "Hills");
    assert_eq!(h.state().session().path.as_deref(), Some(path.as_path()));
    assert_eq!(h.state().pending_recovery(), None);

    // Unsaved changes to the saved project are autosaved beside it; the session ends without
    // saving (as a SIGKILL would). A plain restart (no file named) offers them from the
    // recent-files list, and Recover brings them back into that project's file.
    drop(h);
    let mut config = WorkstationConfig::isolated(Some(path.clone()), dir.clone());
    config.autosave_every = Duration::ZERO;
    let mut h = app::harness(config, 900.0);
    app::settle_load(&mut h);
    h.state_mut()
        .apply(Command::Edit(talas::project::Edit::Rename(
            "Hills v2".into(),
        )));
    h.step();
    let beside = dir.join("hills.talas.autosave");
    assert_eq!(Project::load(&beside).expect("autosaved").name, "Hills v2");
    drop(h);
    let mut config = WorkstationConfig::isolated(None, dir.clone());
    config.recent.paths = vec![
        dir.join("missing.talas"),
        dir.join("part.stp"),
        path.clone(),
    ];
    let mut h = app::harness(config, 900.0);
    app::settle_load(&mut h);
    assert_eq!(h.state().pending_recovery(), Some(beside.as_path()));
    h.get_by_label_contains(&format!("unsaved changes to {}", path.display()));
    h.get_by_label("Recover").click();
    h.step();
    h.step();
    assert_eq!(h.state().session().project.name, "Hills v2");
    assert_eq!(h.state().session().path.as_deref(), Some(path.as_path()));
    h.state_mut().apply(Command::SaveProject);
    h.step();
    assert!(!beside.exists(), "saving removes the recovery file");
    assert_eq!(Project::load(&path).expect("saved").name, "Hills v2");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Open Cascade's samples of bicubic-hills (u, v, x, y, z, nx, ny, nz, k_min, k_max).
fn occt_samples() -> Vec<[f64; 10]> {
    let text = std::fs::read_to_string(data("bicubic-hills.samples.csv")).expect("samples");
    text.lines()
        .skip(1)
        .filter_map(|l| {
            let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
            v.try_into().ok()
        })
        .collect()
}

#[test]
fn a_picked_point_shows_open_cascades_curvature() {
    let part = load_part(&data("bicubic-hills.stp"), &Progress::new()).expect("part");
    let face = &part.faces[0];
    let samples = occt_samples();
    assert_eq!(samples.len(), 441);
    let mut checked = 0;
    // Interior samples (the edges of the domain have one-sided neighbours in the inversion).
    for s in samples
        .iter()
        .filter(|s| (0.05..=0.95).contains(&s[0]) && (0.05..=0.95).contains(&s[1]))
    {
        let p = glam::DVec3::new(s[2], s[3], s[4]);
        let pick = surface_pick(0, face, p).expect("a B-spline face");
        assert!(pick.distance_mm < 1e-6, "{:?}", pick);
        // OCCT's values are about S_u × S_v; the pick's about the face normal.
        let sign = if face.same_sense { 1.0 } else { -1.0 };
        let n = pick.normal.expect("regular point") * sign;
        assert!((n - glam::DVec3::new(s[5], s[6], s[7])).length() < 1e-6);
        let (k_min, k_max) = pick.curvature.expect("curvatures");
        let (k_min, k_max) = if face.same_sense {
            (k_min, k_max)
        } else {
            (-k_max, -k_min)
        };
        assert!((k_min - s[8]).abs() < 1e-7, "k_min {k_min} vs {}", s[8]);
        assert!((k_max - s[9]).abs() < 1e-7, "k_max {k_max} vs {}", s[9]);
        checked += 1;
    }
    assert!(checked > 300, "{checked}");
}

#[test]
fn the_curvature_field_of_the_filleted_pocket_has_the_fillet_radius() {
    // pocket-fillets: planes (k = 0), R5 cylinders (k = 0 and ±1/5), R5 spheres (±1/5, ±1/5).
    let part = load_part(&data("pocket-fillets.stp"), &Progress::new()).expect("part");
    let field = curvature_field(&part, &Progress::new()).expect("not cancelled");
    let n = part.mesh().positions.len();
    assert_eq!(field.k_min.len(), n);
    let mut face_of_vertex = vec![usize::MAX; n];
    for (tri, &f) in part.mesh().triangles.iter().zip(part.face_of_triangle()) {
        for &v in tri {
            face_of_vertex[v as usize] = f as usize;
        }
    }
    let mut seen = [0usize; 3];
    for (v, &fv) in face_of_vertex.iter().enumerate() {
        let Some(face) = part.faces.get(fv) else {
            continue;
        };
        let (a, b) = (f64::from(field.k_min[v]), f64::from(field.k_max[v]));
        let mags = [a.abs(), b.abs()];
        match face.kind.as_str() {
            "plane" => {
                assert!(mags.iter().all(|&k| k < 1e-6), "plane vertex {v}: {a} {b}");
                seen[0] += 1;
            }
            "cylinder" => {
                let (lo, hi) = (mags[0].min(mags[1]), mags[0].max(mags[1]));
                assert!(
                    lo < 1e-6 && (hi - 0.2).abs() < 1e-5,
                    "cylinder {v}: {a} {b}"
                );
                seen[1] += 1;
            }
            "sphere" => {
                assert!(
                    mags.iter().all(|&k| (k - 0.2).abs() < 1e-5) && a * b > 0.0,
                    "sphere {v}: {a} {b}"
                );
                seen[2] += 1;
            }
            other => panic!("unexpected face kind {other}"),
        }
        assert!(
            (f64::from(field.mean[v]) - 0.5 * (a + b)).abs() < 1e-6,
            "mean at {v}"
        );
    }
    assert!(seen.iter().all(|&c| c > 20), "{seen:?}");
}

#[test]
fn an_operation_is_added_calculated_played_back_and_goes_stale_when_edited() {
    use talas::project::{Edit, Operation};
    let dir = data_dir("operation");
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 900.0);
    app::settle_load(&mut h);

    // A new project guides the first job: the default part is open and its tool chosen
    // (ticked), the face, the operation and Calculate still to do.
    h.get_by_label("First job");
    assert!(
        h.query_by_label_contains("✔ 1. Open a part").is_some(),
        "the part step is ticked"
    );
    h.get_by_label_contains("2. Pick a face");
    assert!(
        h.query_by_label_contains("✔ 2.").is_none(),
        "no face picked yet"
    );
    assert!(h.query_by_label_contains("✔ 3. Choose the tool").is_some());
    h.get_by_label_contains("+ Operation below");

    // Machining > Add Iso-scallop finishing: the operation appears and is being edited.
    h.get_by_label("Machining").click();
    h.run_steps(3);
    h.get_by_label("Add Iso-scallop finishing").click();
    h.run_steps(2);
    assert_eq!(h.state().session().project.operations.len(), 1);
    assert_eq!(h.state().focus(), Focus::Operation(0));
    assert!(
        h.query_by_label("First job").is_none(),
        "the guide goes with the first operation"
    );
    h.get_by_label("Calculate");
    // A coarser scallop keeps the test short (the default is 0.01 mm).
    let mut op = h.state().session().project.operations[0].clone();
    if let Operation::Finish { options, .. } = &mut op {
        options.scallop = 0.05;
        options.tolerance = 0.02;
    }
    h.state_mut().apply(Command::Edit(Edit::SetOperation {
        index: 0,
        operation: op.clone(),
    }));
    h.step();

    // F5 calculates in the background; the summary appears with units.
    press(&mut h, egui::Modifiers::NONE, egui::Key::F5);
    assert!(h.state().is_calculating() || h.state().operation_result(0).is_some());
    app::settle_calculation(&mut h);
    let (result, fresh) = h.state().operation_result(0).expect("a result");
    assert!(fresh);
    let poses = result.toolpath().poses.len();
    assert!(poses > 100, "{poses} poses");
    let predicted = result
        .toolpath()
        .summary
        .predicted_max_scallop_mm
        .expect("predicted scallop");
    assert!(predicted <= 0.05 + 1e-9, "{predicted}");
    h.get_by_label("Cut length");
    assert!(h.query_all_by_label_contains(" µm").next().is_some());
    assert!(h.query_all_by_label_contains("Stale").next().is_none());

    // The comparison window lists the computed operation with its numbers and units.
    h.state_mut().apply(Command::CompareOperations);
    h.state_mut().apply(Command::SetShowAxisVectors(true));
    h.run_steps(2);
    h.get_by_label("vs first");
    assert!(h.query_all_by_label_contains(" mm").next().is_some());

    // Space plays the path on its clock: the playback pose advances, the bar shows it.
    assert_eq!(h.state().playback_position(), None);
    press(&mut h, egui::Modifiers::NONE, egui::Key::Space);
    for _ in 0..20 {
        h.step();
        std::thread::sleep(Duration::from_millis(10));
    }
    let p1 = h.state().playback_position().expect("playing back");
    press(&mut h, egui::Modifiers::NONE, egui::Key::Period);
    let p2 = h.state().playback_position().expect("stepped");
    assert!(p2 > p1.min(poses - 2), "{p1} -> {p2}");
    assert!(
        h.query_all_by_label_contains("Playback pose")
            .next()
            .is_some()
    );

    // Editing the operation makes the path stale; undo brings the fresh path back.
    if let Operation::Finish { options, .. } = &mut op {
        options.scallop = 0.04;
    }
    h.state_mut().apply(Command::Edit(Edit::SetOperation {
        index: 0,
        operation: op,
    }));
    h.run_steps(2);
    assert!(!h.state().operation_result(0).expect("kept").1);
    assert!(h.query_all_by_label_contains("Stale").next().is_some());
    press(&mut h, egui::Modifiers::COMMAND, egui::Key::Z);
    assert!(
        h.state().operation_result(0).expect("kept").1,
        "fresh again"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_raster_path_is_simulated_and_the_stock_shows_its_deviation() {
    use talas::project::{Edit, Operation, OperationKind};
    let dir = data_dir("simulate");
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 1300.0);
    app::settle_load(&mut h);
    let mut op = Operation::new(OperationKind::Raster, 0, 0);
    if let Operation::Raster { scallop_mm, .. } = &mut op {
        *scallop_mm = 0.1;
    }
    h.state_mut().apply(Command::Edit(Edit::AddOperation {
        index: 0,
        operation: op,
    }));
    h.state_mut().apply(Command::Inspect(Focus::Operation(0)));
    h.state_mut().apply(Command::Calculate(0));
    app::settle_calculation(&mut h);
    assert!(
        h.state()
            .operation_result(0)
            .is_some_and(|(_, fresh)| fresh)
    );
    // Simulate from the operation editor's button.
    h.get_by_label("Simulate").click();
    h.run_steps(2);
    app::settle_while(&mut h, "simulation", is_simulating);
    h.run_steps(2);
    let Some(sim) = simulation_of(h.state(), 0) else {
        for m in &h.state().log().entries {
            eprintln!("log: {m:?}");
        }
        panic!("simulated");
    };
    let whole_removed = sim.simulated.report.removed_volume_mm3;
    assert!(sim.simulated.report.removed_volume_mm3 > 0.0);
    // The default tool's flutes (18 mm) are shorter than the stock is deep over the valleys:
    // the shank meets material and the collisions are listed.
    h.get_by_label("Deepest gouge");
    assert!(
        sim.simulated.max_gouge_mm < 0.02,
        "gouge {} mm",
        sim.simulated.max_gouge_mm
    );
    // The stock at a playback pose: less material removed than by the whole path.
    let whole = whole_removed;
    h.state_mut().apply(Command::Playback(
        talas::app::command::PlaybackCommand::Seek(60.0),
    ));
    h.state_mut().apply(Command::SimulateToPlayback);
    app::settle_while(&mut h, "simulation", is_simulating);
    let partial = simulation(h.state())
        .shown()
        .expect("partial stock")
        .simulated
        .report
        .removed_volume_mm3;
    assert!(
        partial > 0.0 && partial < 0.5 * whole,
        "{partial} of {whole} mm³"
    );

    // F7 posts the path and plans its motion; the G-code pane shows it, Export writes it.
    press(&mut h, egui::Modifiers::NONE, egui::Key::F7);
    app::settle_while(&mut h, "is_posting", is_posting);
    h.run_steps(2);
    let text = program_text(h.state(), 0).expect("posted").to_string();
    assert!(
        text.contains("G54") && text.contains("M30"),
        "{}",
        &text[..200.min(text.len())]
    );
    assert!(h.query_all_by_label_contains("G-code").next().is_some());
    // The jerk-limited plan of the posted program never runs faster than programmed (1000
    // mm/min) and the path can be coloured by it.
    let feeds = planned_feed(h.state(), 0).expect("planned feed");
    let (result, _) = h.state().operation_result(0).expect("result");
    let finite: Vec<f32> = feeds
        .iter()
        .zip(&result.toolpath().poses)
        .filter(|(_, p)| p.kind == talas::toolpath::MoveKind::Cut)
        .map(|(f, _)| *f)
        .filter(|f| f.is_finite())
        .collect();
    assert!(
        finite.len() * 2 > feeds.len(),
        "{} of {}",
        finite.len(),
        feeds.len()
    );
    assert!(
        finite.iter().all(|&f| f <= 1000.0 * 1.001),
        "max {}",
        finite.iter().copied().fold(0.0f32, f32::max)
    );
    let mut sorted = finite.clone();
    sorted.sort_by(f32::total_cmp);
    assert!(
        sorted[sorted.len() / 2] > 100.0,
        "median {}",
        sorted[sorted.len() / 2]
    );
    h.state_mut().apply(Command::SetPathColouring(
        talas::app::toolpaths::PathColouring::PlannedFeed,
    ));
    h.run_steps(2);
    let out = dir.join("raster.ngc");
    h.state_mut().apply(Command::FeatureFile {
        feature: "program",
        path: out.clone(),
    });
    assert_eq!(std::fs::read_to_string(&out).expect("exported"), text);
    // Showing the reduced surface hides the simulated stock (the reduction asks the
    // workstation, which passes it on to the stock simulation).
    assert!(simulation(h.state()).is_visible());
    h.state_mut().apply(DataReduction::command("open"));
    h.run_steps(2);
    h.get_by_label("Reduce").click();
    h.run_steps(2);
    app::settle_while(&mut h, "reduction", reducing);
    assert!(reduction(h.state()).is_visible());
    assert!(!simulation(h.state()).is_visible());
    // A stock change makes the simulation stale (not shown for the operation any more).
    h.state_mut()
        .apply(Command::Edit(Edit::SetStock(talas::project::Stock::Box {
            min_mm: [0.0, 0.0, -20.0],
            max_mm: [160.0, 120.0, 20.0],
        })));
    h.run_steps(2);
    assert!(simulation_of(h.state(), 0).is_none());
    // The raster reads the part and its tool, not the stock: its path stays fresh. A roughing
    // reads the stock (the engine's digest says so): calculated, then stale after a change.
    assert!(h.state().operation_result(0).expect("kept").1);
    let mut rough = Operation::new(OperationKind::Rough, 0, 0);
    if let Operation::Rough { step_down_mm, .. } = &mut rough {
        *step_down_mm = 10.0;
    }
    h.state_mut().apply(Command::Edit(Edit::AddOperation {
        index: 1,
        operation: rough,
    }));
    h.state_mut().apply(Command::Calculate(1));
    app::settle_calculation(&mut h);
    assert!(h.state().operation_result(1).expect("roughed").1);
    h.state_mut()
        .apply(Command::Edit(Edit::SetStock(talas::project::Stock::Box {
            min_mm: [0.0, 0.0, -20.0],
            max_mm: [160.0, 120.0, 25.0],
        })));
    h.run_steps(2);
    assert!(!h.state().operation_result(1).expect("kept").1, "stale");
    assert!(h.state().operation_result(0).expect("kept").1);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The data-reduction feature.
fn reduction(ws: &Workstation) -> &DataReduction {
    ws.feature_ref::<DataReduction>()
        .expect("data reduction is a registered feature")
}

/// Is a reduction running?
fn reducing(ws: &Workstation) -> bool {
    reduction(ws).is_running()
}

/// Machining → Data reduction: the part's Z-map reduced in the background. The Z-map's heights
/// against the exact B-spline surface (Newton inversion of x(u,v), y(u,v)), the singular values
/// against the Frobenius norm (Σσ² = Σz²), the rank rule's guarantee (σ_r > t ≥ σ_(r+1) and
/// every node within t), and the exported STL read back.
#[test]
fn the_data_reduction_view_reduces_the_part_within_its_tolerance() {
    use talas::geometry::zmap::zmap_from_surface;
    let dir = data_dir("reduction");
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 900.0);
    app::settle_load(&mut h);
    h.get_by_label("Machining").click();
    h.run_steps(2);
    h.get_by_label("Data reduction (Z-map SVD)…").click();
    h.run_steps(4);
    // 160 × 120 mm part: a 1 mm step (about 200 nodes along X would be 0.8 → rounded to 1).
    h.get_by_label_contains("161 × 121 nodes");
    h.get_by_label("Reduce").click();
    h.run_steps(2);
    app::settle_while(&mut h, "reduction", reducing);
    h.run_steps(2);
    let Some(talas::app::reduction::ReductionResult::Regular(r)) =
        reduction(h.state()).result().cloned()
    else {
        panic!("no regular reduction");
    };
    assert!(reduction(h.state()).is_visible());
    h.get_by_label("Bound σ(r+1)");
    let tol = 0.01;
    let red = &r.reduction;
    let (rows, cols) = (r.zmap.grid.rows(), r.zmap.grid.cols());
    assert_eq!((rows, cols), (121, 161));
    // Heights against the exact surface, sampled independently of the mesh.
    let part = talas::import::step::read_step(&data("bicubic-hills.stp")).unwrap();
    let exact = zmap_from_surface(
        &part.faces[0].surface,
        r.zmap.origin,
        r.zmap.step_mm,
        rows,
        cols,
        -1000.0,
        1e-7,
    )
    .unwrap();
    let mut worst = 0.0_f64;
    for (k, (a, b)) in r
        .zmap
        .grid
        .values()
        .iter()
        .zip(exact.grid.values())
        .enumerate()
    {
        if exact.params[k].is_some() {
            worst = worst.max((a - b).abs());
        }
    }
    eprintln!(
        "Z-map vs exact surface: worst {worst:.2e} mm, {} exact nodes, {} off the part",
        r.zmap.exact_nodes, r.zmap.misses
    );
    assert_eq!(r.zmap.misses, 0);
    // Every node refined onto the B-spline: no tessellation error left (the mesh alone is
    // 36 µm off at worst).
    assert_eq!(r.zmap.exact_nodes, rows * cols);
    assert!(worst < 1e-6, "{worst}");
    // Singular values: Σσ² equals the Z-map's squared Frobenius norm.
    let s2: f64 = red.singular_values.iter().map(|s| s * s).sum();
    let f2: f64 = r.zmap.grid.values().iter().map(|z| z * z).sum();
    assert!((s2 - f2).abs() <= 1e-9 * f2, "{s2} vs {f2}");
    // The spectral rule: σ_r > t ≥ σ_(r+1), and every node within t.
    assert!(red.rank >= 1 && red.rank < red.singular_values.len());
    assert!(red.singular_values[red.rank - 1] > tol);
    assert!(red.singular_values[red.rank] <= tol);
    let worst_error = r
        .signed_error
        .values()
        .iter()
        .fold(0.0_f64, |a, e| a.max(e.abs()));
    assert!(worst_error <= tol && (worst_error - red.max_error).abs() < 1e-12);
    assert!(
        red.stored_numbers < rows * cols / 5,
        "{}",
        red.stored_numbers
    );
    // Export through the window's button, and read the STL back.
    let out = export_through_the_chooser(&mut h, &dir);
    let back =
        talas::import::stl::read_stl(&out, &talas::import::stl::StlOptions::default()).unwrap();
    assert_eq!(back.mesh.triangles.len(), 2 * (rows - 1) * (cols - 1));
    let zmax = red.reduced.values().iter().fold(f64::MIN, |a, b| a.max(*b));
    let back_max = back.mesh.positions.iter().fold(f64::MIN, |a, p| a.max(p.z));
    assert!((zmax - back_max).abs() < 1e-4, "{zmax} vs {back_max}");
    // Hiding it shows the part again.
    h.state_mut().apply(DataReduction::command("hide"));
    h.run_steps(2);
    assert!(!reduction(h.state()).is_visible());
    // The XY-dependent Z-map of the mesh's vertices: X, Y and Z reduced separately; the report
    // shows the three ranks and the vertical error, which is the largest node error measured.
    h.get_by_label("XY-dependent").click();
    h.run_steps(2);
    h.get_by_label("Reduce").click();
    h.run_steps(2);
    app::settle_while(&mut h, "reduction", reducing);
    h.run_steps(2);
    let Some(talas::app::reduction::ReductionResult::Xy(xy)) =
        reduction(h.state()).result().cloned()
    else {
        panic!("no XY-dependent reduction");
    };
    h.get_by_label("Ranks");
    let red = &xy.reduction;
    assert!(red.x.rank >= 1 && red.y.rank >= 1 && red.z.rank >= 1);
    // The nodes are mesh vertices (or cell centres on the mesh): they lie within the mesh's
    // bounding box, and every node is covered by the reduced surface or counted as not.
    let covered = xy.signed_error.iter().flatten().count();
    assert_eq!(covered + red.uncovered, xy.map.z.values().len());
    let worst = xy
        .signed_error
        .iter()
        .flatten()
        .fold(0.0_f64, |a, e| a.max(e.abs()));
    assert!((worst - red.max_error).abs() < 1e-12);
    eprintln!(
        "XY-dependent: {}×{} nodes, ranks X {} Y {} Z {}, max vertical error {:.2e} mm, {} uncovered",
        xy.map.z.cols(),
        xy.map.z.rows(),
        red.x.rank,
        red.y.rank,
        red.z.rank,
        red.max_error,
        red.uncovered
    );
    let out = dir.join("reduced-xy.stl");
    h.state_mut().apply(reduction_file(&out));
    let back =
        talas::import::stl::read_stl(&out, &talas::import::stl::StlOptions::default()).unwrap();
    let (m2, n2) = (red.reduced.z.rows(), red.reduced.z.cols());
    assert_eq!(back.mesh.triangles.len(), 2 * (m2 - 1) * (n2 - 1));
    a_failed_export_reports_the_file_and_keeps_what_was_there(&mut h, &dir);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Export the reduced surface through the window's button: the feature's save dialog (here the
/// in-window chooser, starting beside the saved project) hands the chosen file back to the
/// feature, which writes the STL. The file written.
fn export_through_the_chooser(h: &mut Harness<'static, Workstation>, dir: &Path) -> PathBuf {
    h.state_mut()
        .apply(Command::SaveProjectAs(dir.join("reduction.talas")));
    h.get_by_label("Export STL…").click();
    h.run_steps(3);
    let Some(ChooserPurpose::Save(SavePurpose::Feature(file))) =
        h.state().chooser().map(|c| c.purpose())
    else {
        panic!("no save chooser for the reduced surface");
    };
    assert_eq!(file.feature, DataReduction::ID);
    assert_eq!(
        h.state().chooser().map(|c| c.file_type().0),
        Some("STL (.stl)")
    );
    h.get_by_label("Save").click();
    h.run_steps(3);
    assert!(h.state().chooser().is_none());
    let name = format!("{}-reduced.stl", h.state().document().unwrap().part.name);
    let out = dir.join(name);
    let logged = &h.state().log().entries.last().unwrap().text;
    assert!(logged.contains(&out.display().to_string()), "{logged}");
    out
}

/// The file chosen in the data reduction's save dialog.
fn reduction_file(path: &Path) -> Command {
    Command::FeatureFile {
        feature: DataReduction::ID,
        path: path.to_path_buf(),
    }
}

/// A save that fails (the target is a folder with a file in it) leaves what was there and
/// reports one error naming the file.
fn a_failed_export_reports_the_file_and_keeps_what_was_there(
    h: &mut Harness<'static, Workstation>,
    dir: &Path,
) {
    let blocked = dir.join("blocked.stl");
    std::fs::create_dir_all(&blocked).unwrap();
    std::fs::write(blocked.join("keep.txt"), "kept").unwrap();
    h.state_mut().apply(reduction_file(&blocked));
    let last = h.state().log().entries.last().unwrap();
    assert_eq!(last.severity, talas::diagnostics::Severity::Error);
    assert!(
        last.text.starts_with("Not exported: ")
            && last.text.contains(&blocked.display().to_string()),
        "{}",
        last.text
    );
    assert_eq!(
        std::fs::read_to_string(blocked.join("keep.txt")).unwrap(),
        "kept"
    );
}
