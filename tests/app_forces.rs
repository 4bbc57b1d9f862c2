//! The cutting-forces window, driven through the workstation's UI with egui_kittest
//! (headless): opened from the Machining menu, computed in the background for a roughing
//! operation whose tool carries a force limit, plotted with units and limits, a click on the
//! plot picks the pose cut then, the path is coloured by the per-move force with the limit on
//! the legend, the deflection profile is shown for the picked pose, the feeds are scheduled
//! for a target force and applied to the operation, the coefficient library editor refuses an
//! invalid entry, and the tool editor's load-limit fields are range-checked and saved.
//!
//! `cargo test --test app_forces`
#![cfg(feature = "gui")]

mod common;

use common::app;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use talas::app::command::{Command, FeatureCommand};
use talas::app::forces::ForcesWindow;
use talas::app::{Workstation, WorkstationConfig};
use talas::project::{Edit, Operation, OperationKind, Stock, ToolEntry};
use talas::tools::parse_tool_spec;

/// The workstation's cutting-forces window (a registered feature).
fn forces(ws: &mut Workstation) -> &mut ForcesWindow {
    ws.feature::<ForcesWindow>()
        .expect("the forces feature is registered")
}

fn click(h: &mut Harness<'static, Workstation>, p: egui::Pos2) {
    h.hover_at(p);
    h.step();
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos: p,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
    }
    h.run_steps(2);
}

/// A project with one roughing operation around a 30 × 30 × 10 mm box in a stock 6 mm wider
/// on each side (one 10 mm level), with a fluted flat end mill limited to 60 N, calculated.
fn roughed(tag: &str) -> (Harness<'static, Workstation>, std::path::PathBuf) {
    let dir = std::env::temp_dir().join(format!("talas-app-forces-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let part = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/force/box30.stl");
    let mut h = app::harness(WorkstationConfig::isolated(Some(part), dir.clone()), 900.0);
    app::settle_while_mut(&mut h, "load", |w| w.is_loading() || w.is_computing_field());
    let mut cutter = parse_tool_spec("flat:d=10,flute=30,flutes=3,helix=30,rake=10").unwrap();
    cutter.limits.max_force_n = Some(60.0);
    let tool = ToolEntry {
        name: "Flat D10 Z3".into(),
        cutter,
    };
    let mut op = Operation::new(OperationKind::Rough, 0, 0);
    if let Operation::Rough {
        step_down_mm,
        step_over_fraction,
        tolerance_mm,
        ..
    } = &mut op
    {
        *step_down_mm = 10.0;
        *step_over_fraction = 0.5;
        *tolerance_mm = 0.1;
    }
    h.state_mut().apply(Command::Edit(Edit::Batch(vec![
        Edit::SetTool { index: 0, tool },
        Edit::SetStock(Stock::Box {
            min_mm: [-6.0, -6.0, 0.0],
            max_mm: [36.0, 36.0, 10.0],
        }),
        Edit::AddOperation {
            index: 0,
            operation: op,
        },
    ])));
    h.step();
    h.state_mut().apply(Command::Calculate(0));
    app::settle_while_mut(&mut h, "calculation", |w| w.is_calculating());
    // TALAS_SAVE_FORCES_PROJECT=FILE keeps the project (the screenshot opens it).
    if let Ok(file) = std::env::var("TALAS_SAVE_FORCES_PROJECT") {
        h.state_mut()
            .apply(Command::SaveProjectAs(std::path::PathBuf::from(file)));
        h.step();
    }
    assert!(
        h.state()
            .operation_result(0)
            .is_some_and(|(_, fresh)| fresh)
    );
    (h, dir)
}

#[test]
fn forces_are_computed_plotted_and_a_click_picks_the_pose() {
    let (mut h, dir) = roughed("plot");
    h.get_by_label("Machining").click();
    h.run_steps(3);
    h.get_by_label("Cutting forces…").click();
    h.run_steps(3);
    // 0.3 mm dexels.
    forces(h.state_mut()).max_rays = Some(20_000.0);
    let started = std::time::Instant::now();
    h.get_by_label("Compute forces").click();
    h.run_steps(2);
    app::settle_while_mut(&mut h, "force job", |w| forces(w).is_running());
    let (samples, limit, planned, peak, poses) = {
        let ws = h.state_mut();
        let r = forces(ws).result().expect("a result");
        (
            r.samples.clone(),
            r.limits,
            r.planned_time,
            r.forces.totals.peak_resultant_n,
            r.pose_time_s.len(),
        )
    };
    eprintln!(
        "forces in {:.1} s: {} samples, {poses} poses",
        started.elapsed().as_secs_f64(),
        samples.len()
    );
    assert!(!samples.is_empty());
    // Not posted: the clock is the programmed feeds'.
    assert!(!planned);
    assert_eq!(limit.max_force_n, Some(60.0));
    // The built-in mill's 7.5 kW spindle is the power limit.
    assert_eq!(limit.max_power_w, Some(7500.0));
    assert!(
        peak > 60.0,
        "a 10 mm roughing level with a D10 cutter: {peak} N"
    );
    // Samples run forward in time over poses of the path.
    for w in samples.windows(2) {
        assert!(w[0].t_s[0] <= w[0].t_s[1] && w[0].t_s[1] <= w[1].t_s[0] + 1e-9);
    }
    assert!(samples.iter().all(|s| s.pose < poses));
    // Units and limits are shown.
    h.get_by_label("Force (N)");
    h.get_by_label("Torque (N·m)");
    h.get_by_label("Power (W)");
    assert!(h.query_all_by_label_contains("force 60 N").next().is_some());
    assert!(
        h.query_all_by_label_contains("power 7500 W")
            .next()
            .is_some()
    );
    // A click on the plot in the middle of a piece picks that piece's pose.
    let s = samples[samples.len() / 2];
    let t = 0.5 * (s.t_s[0] + s.t_s[1]);
    let transform = forces(h.state_mut()).plot_transform.expect("drawn");
    let x = transform.position_from_point_x(t);
    let y = transform.frame().center().y;
    click(&mut h, egui::pos2(x, y));
    let picked = h.state().tool_pose_index().expect("a pose picked");
    // Within a pixel of time, the piece clicked or a neighbour of the same or next pose.
    let px = (transform.bounds().width() / f64::from(transform.frame().width())).abs();
    let near: Vec<usize> = samples
        .iter()
        .filter(|q| q.t_s[1] >= t - px && q.t_s[0] <= t + px)
        .map(|q| q.pose)
        .collect();
    assert!(near.contains(&picked), "picked {picked}, near {near:?}");

    path_is_coloured_by_force(&mut h, &samples);
    deflection_at_the_picked_pose(&mut h, picked);
    feeds_are_scheduled_and_applied(&mut h);
    let _ = std::fs::remove_dir_all(&dir);
}

/// "Colour the path": each cutting move takes the largest peak |F| of its pieces (0 in air) on
/// Turbo from 0 to the larger of the largest and the 60 N limit; other moves keep their kind's
/// colour; the legend is in N with the limit marked; the workstation draws it as the feature's
/// scene.
fn path_is_coloured_by_force(
    h: &mut Harness<'static, Workstation>,
    samples: &[talas::project::forces::ForceSample],
) {
    use talas::app::feature::Feature;
    use talas::app::toolpaths::move_colour;
    use talas::render::ColourMap;
    use talas::toolpath::MoveKind;
    h.get_by_label("Colour the path").click();
    h.run_steps(2);
    let (c, tp) = {
        let f = forces(h.state_mut());
        let c = f.coloured_path().expect("coloured").clone();
        let tp = std::sync::Arc::clone(&f.outcome().expect("result").toolpath);
        let scene = f.scene();
        assert_eq!(scene.lines.len(), 1);
        assert_eq!(scene.lines[0].id, c.id);
        assert_eq!(scene.path_legend.as_ref(), Some(&c.legend));
        (c, tp)
    };
    let mut per_pose = vec![0.0f64; tp.poses.len()];
    for s in samples {
        per_pose[s.pose] = per_pose[s.pose].max(s.peak_resultant_n);
    }
    let top = per_pose.iter().copied().fold(60.0, f64::max);
    assert!(c.legend.title.ends_with("(N)"), "{}", c.legend.title);
    assert_eq!(c.legend.mark, Some((60.0, "limit 60 N".to_string())));
    assert!((f64::from(c.legend.mapping.max) - top).abs() < 1e-4 * top);
    assert_eq!(c.lines.colours.len(), 2 * (tp.poses.len() - 1));
    let mut distinct = std::collections::BTreeSet::new();
    for (k, w) in tp.poses.windows(2).enumerate() {
        let got = c.lines.colours[2 * k];
        let want = if w[1].kind == MoveKind::Cut {
            let [r, g, b] = ColourMap::Turbo.sample((per_pose[k + 1] / top) as f32);
            distinct.insert(got);
            [r, g, b, 255]
        } else {
            move_colour(w[1].kind)
        };
        let close = got.iter().zip(want).all(|(a, b)| a.abs_diff(b) <= 1);
        assert!(close, "move into pose {k}+1: {got:?} vs {want:?}");
    }
    assert!(distinct.len() > 5, "the forces vary along a roughing path");
    // Torque: the legend follows in N·m.
    h.get_by_label("Torque (N·m)").click();
    h.run_steps(2);
    let title = forces(h.state_mut())
        .coloured_path()
        .expect("coloured")
        .legend
        .title
        .clone();
    assert!(title.ends_with("(N·m)"), "{title}");
    h.get_by_label("Force (N)").click();
    h.run_steps(2);
}

/// "Deflection at the pose": the picked pose's profile from the tip to the depth of cut, in µm
/// against mm, with the beam assumptions stated.
fn deflection_at_the_picked_pose(h: &mut Harness<'static, Workstation>, picked: usize) {
    h.get_by_label("Deflection at the pose").click();
    h.run_steps(3);
    let (pose, d) = {
        let f = forces(h.state_mut());
        let (pose, d) = f.deflection().expect("computed for the pose");
        (pose, d.clone().expect("no error").expect("the pose cuts"))
    };
    assert_eq!(pose, picked);
    assert_eq!(d.deflection.len(), 41);
    // Within the one 10 mm level, from the tip to the top of the engaged disks.
    assert!(d.depth_mm > 0.0 && d.depth_mm < 10.6, "{}", d.depth_mm);
    assert!((d.deflection[40].z_mm - d.depth_mm).abs() < 1e-9);
    let tip = d.deflection[0].dx_um.hypot(d.deflection[0].dy_um);
    let top = d.deflection[40].dx_um.hypot(d.deflection[40].dy_um);
    assert!(
        tip > top && tip > 0.0,
        "the tip bends most: {tip} vs {top} µm"
    );
    assert!(
        h.query_all_by_label_contains("tip deflection")
            .next()
            .is_some()
    );
    assert!(
        h.query_all_by_label_contains("E = 600 GPa")
            .next()
            .is_some()
    );
    assert!(h.query_all_by_label_contains(" µm").next().is_some());
}

/// "Schedule feeds" at 60 N (the tool's limit, below the path's peak): slower, with more of
/// the cutting time near the target; Apply makes it the operation's path.
fn feeds_are_scheduled_and_applied(h: &mut Harness<'static, Workstation>) {
    assert_eq!(forces(h.state_mut()).schedule.target_n, Some(60.0));
    h.get_by_label("Schedule feeds").click();
    h.run_steps(2);
    app::settle_while_mut(h, "schedule", |w| forces(w).schedule.is_running());
    let (key, s) = {
        let p = &forces(h.state_mut()).schedule;
        p.result
            .clone()
            .unwrap_or_else(|| panic!("no schedule: {:?}", p.message))
    };
    assert_eq!(key.target_n, 60.0);
    eprintln!(
        "cycle {:.2} s -> {:.2} s; within ±5 %: {:.3} -> {:.3}",
        s.before.cycle_time_s,
        s.after.cycle_time_s,
        s.before.force_spread.within_5_percent,
        s.after.force_spread.within_5_percent
    );
    assert!(s.after.cycle_time_s > s.before.cycle_time_s);
    assert!(s.after.force_spread.within_5_percent > s.before.force_spread.within_5_percent);
    assert!(s.after.force_spread.max_n < s.before.force_spread.max_n);
    assert!(h.query_all_by_label_contains("Cycle time").next().is_some());
    h.get_by_label("Apply scheduled feeds").click();
    h.run_steps(3);
    let (r, fresh) = h.state().operation_result(0).expect("computed");
    assert!(fresh);
    assert_eq!(r.toolpath(), &s.toolpath);
}

#[test]
fn tool_limits_are_edited_checked_and_saved() {
    let dir = std::env::temp_dir().join(format!("talas-app-forces-limits-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 900.0);
    app::settle_while_mut(&mut h, "load", |w| w.is_loading() || w.is_computing_field());
    assert!(!h.state().session().project.tools.is_empty());
    h.state_mut()
        .apply(Command::Inspect(talas::app::state::Focus::Tool(0)));
    h.run_steps(3);
    let typed = |h: &mut Harness<'static, Workstation>, label: &str, text: &str| {
        h.get_by_label(label).focus();
        h.step();
        h.get_by_label(label).set_text_value_accesskit(text);
        h.step();
        h.key_press(egui::Key::Enter);
        h.run_steps(2);
    };
    let limits =
        |h: &Harness<'static, Workstation>| h.state().session().project.tools[0].cutter.limits;
    typed(&mut h, "Max force (N)", "250");
    typed(&mut h, "Max power (W)", "1500 W");
    assert_eq!(limits(&h).max_force_n, Some(250.0));
    assert_eq!(limits(&h).max_power_w, Some(1500.0));
    assert_eq!(limits(&h).max_torque_nm, None);
    // Refused as the engine refuses it, with the reason; nothing applied.
    typed(&mut h, "Max torque (N·m)", "-2");
    assert_eq!(limits(&h).max_torque_nm, None);
    assert!(
        h.query_all_by_label_contains("max_torque_nm must be above 0")
            .next()
            .is_some()
    );
    typed(&mut h, "Max torque (N·m)", "12.5");
    assert_eq!(limits(&h).max_torque_nm, Some(12.5));
    // Saved to the library file.
    let lib = std::fs::read_to_string(dir.join("tools.toml")).expect("library written");
    assert!(lib.contains("max_force_n = 250.0"), "{lib}");
    assert!(lib.contains("max_torque_nm = 12.5"), "{lib}");
    // Cleared: no limit.
    typed(&mut h, "Max force (N)", "");
    assert_eq!(limits(&h).max_force_n, None);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_coefficient_editor_validates_and_saves() {
    let dir = std::env::temp_dir().join(format!("talas-app-forces-lib-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = app::harness(WorkstationConfig::isolated(None, dir.clone()), 900.0);
    h.state_mut().apply(Command::Feature(FeatureCommand {
        feature: ForcesWindow::ID,
        action: "open",
    }));
    h.run_steps(2);
    h.get_by_label("Coefficients…").click();
    h.run_steps(3);
    // The built-in library is shown with its units.
    assert!(h.query_all_by_label_contains("N/mm²").next().is_some());
    let n = {
        let ed = &mut forces(h.state_mut()).editor;
        let lib = ed.library.as_mut().expect("loaded");
        // An entry without K_tc is refused.
        lib.entries[0].ktc_n_mm2 = None;
        lib.entries.len()
    };
    h.run_steps(2);
    h.get_by_label("Save").click();
    h.run_steps(2);
    let path = dir.join("force-coefficients.toml");
    assert!(!path.exists());
    assert!(
        h.query_all_by_label_contains("entry 1: a linear entry needs ktc_n_mm2")
            .next()
            .is_some()
    );
    // Fixed, it saves and reads back.
    {
        let ed = &mut forces(h.state_mut()).editor;
        ed.library.as_mut().unwrap().entries[0].ktc_n_mm2 = Some(1234.5);
    }
    h.run_steps(2);
    h.get_by_label("Save").click();
    h.run_steps(2);
    let back = talas::force::library::Library::load(&path).expect("saved library reads");
    assert_eq!(back.entries.len(), n);
    assert_eq!(back.entries[0].ktc_n_mm2, Some(1234.5));
    let _ = std::fs::remove_dir_all(&dir);
}
