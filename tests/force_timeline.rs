//! `project::forces::operation_forces`, what the workstation's force window runs: the time of
//! each piece at the programmed feed (length / feed) or on a given planned clock (which also
//! sets the feed per tooth), the stock left by earlier paths (a path re-run over its own slot
//! cuts air), sample lookup by time, and cancel.

use glam::DVec3;
use talas::diagnostics::Progress;
use talas::force::library::Library;
use talas::geometry::Aabb;
use talas::project::Stock;
use talas::project::forces::{ForceRunError, ForceRunInput, operation_forces};
use talas::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};
use talas::tools::parse_tool_spec;

const SPEC: &str = "flat:d=10,flute=20,flutes=2,helix=30,rake=10";

/// A 40 mm slot, 3 mm deep, along +X through a 20 × 20 × 10 box at 600 mm/min.
fn slot() -> Toolpath {
    let cutter = parse_tool_spec(SPEC).unwrap();
    let p = |k, x: f64, z: f64, f: f64| Pose::new(k, DVec3::new(x, 0.0, z), DVec3::Z, f);
    Toolpath::new(
        ToolRecord {
            spec: SPEC.into(),
            cutter,
        },
        vec![
            p(MoveKind::Rapid, -20.0, 5.0, 0.0),
            p(MoveKind::Plunge, -20.0, -3.0, 600.0),
            p(MoveKind::Cut, 20.0, -3.0, 600.0),
            p(MoveKind::Rapid, 20.0, 5.0, 0.0),
        ],
    )
}

fn coefficients() -> talas::force::path::ModeCoefficients {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/force/coefficients.toml"
    ))
    .unwrap();
    Library::parse(&text)
        .unwrap()
        .mode_coefficients(None)
        .unwrap()
        .0
}

fn input<'a>(
    stock: &'a Stock,
    tp: &'a Toolpath,
    earlier: Vec<(&'a Toolpath, &'a talas::tools::Cutter)>,
    c: &'a talas::force::path::ModeCoefficients,
    clock: Option<&'a [f64]>,
) -> ForceRunInput<'a> {
    ForceRunInput {
        stock,
        part_bounds: Aabb {
            min: DVec3::new(-10.0, -10.0, -10.0),
            max: DVec3::new(10.0, 10.0, 0.0),
        },
        earlier,
        toolpath: tp,
        cutter: &tp.tool.cutter,
        coefficients: c,
        spindle_rpm: 3000.0,
        pose_time_s: clock,
        limits: Default::default(),
        resolution_mm: 0.25,
    }
}

#[test]
fn pieces_are_timed_at_the_feed_or_on_the_planned_clock() {
    let stock = Stock::Box {
        min_mm: [-10.0, -10.0, -10.0],
        max_mm: [10.0, 10.0, 0.0],
    };
    let tp = slot();
    let c = coefficients();
    let r = operation_forces(&input(&stock, &tp, vec![], &c, None), &Progress::new()).unwrap();
    assert!(!r.planned_time);
    // Programmed clock: rapids at the default rapid rate, the plunge 8 mm and the slot 40 mm
    // at 600 mm/min (0.8 s and 4 s).
    let t_plunge_end = r.pose_time_s[2] - 4.0;
    assert!((r.pose_time_s[2] - r.pose_time_s[1] - 4.0).abs() < 1e-9);
    assert!((r.pose_time_s[1] - r.pose_time_s[0] - 0.8).abs() < 1e-9);
    // The front half of the tool is in material from x = −15 (its edge reaches the stock) to
    // x = 10 (its centre leaves the stock): 25 of the 40 mm, from 0.5 s to 3.0 s into the
    // slot (to within a 0.5 mm piece, or two at the exit where dexels on the slot walls count).
    let first = r.samples.first().unwrap();
    let last = r.samples.last().unwrap();
    assert!(
        (first.t_s[0] - (t_plunge_end + 0.5)).abs() <= 0.05 + 1e-9,
        "{first:?}"
    );
    assert!(
        (last.t_s[1] - (t_plunge_end + 3.0)).abs() <= 0.1 + 1e-9,
        "{last:?}"
    );
    assert!(r.samples.iter().all(|s| s.pose == 2));
    let slot = r.forces.moves.iter().find(|m| m.block == 2).unwrap();
    assert!((slot.feed_per_tooth_mm - 0.1).abs() < 1e-12);
    // sample_at: inside a piece, and the nearest one outside.
    let mid = r.samples[r.samples.len() / 2];
    let t = 0.5 * (mid.t_s[0] + mid.t_s[1]);
    assert_eq!(r.sample_at(t).map(|s| s.t_s), Some(mid.t_s));
    assert_eq!(r.sample_at(-1.0).map(|s| s.t_s), Some(first.t_s));
    assert_eq!(r.sample_at(1e9).map(|s| s.t_s), Some(last.t_s));

    // A planned clock twice as slow in the slot: the same pieces at twice the time and half
    // the feed per tooth.
    let mut clock = r.pose_time_s.clone();
    clock[2] = clock[1] + 8.0;
    clock[3] = clock[2] + 0.1;
    let slow = operation_forces(
        &input(&stock, &tp, vec![], &c, Some(&clock)),
        &Progress::new(),
    )
    .unwrap();
    assert!(slow.planned_time);
    let m = slow.forces.moves.iter().find(|m| m.block == 2).unwrap();
    assert!((m.feed_per_tooth_mm - 0.05).abs() < 1e-12);
    assert!((slow.samples.first().unwrap().t_s[0] - (clock[1] + 1.0)).abs() <= 0.1 + 1e-9);
    // Smaller chips, smaller forces.
    assert!(m.mean_resultant_n < slot.mean_resultant_n);
}

#[test]
fn earlier_paths_cut_the_stock_first_and_cancel_stops() {
    let stock = Stock::Box {
        min_mm: [-10.0, -10.0, -10.0],
        max_mm: [10.0, 10.0, 0.0],
    };
    let tp = slot();
    let c = coefficients();
    let earlier = vec![(&tp, &tp.tool.cutter)];
    let r = operation_forces(&input(&stock, &tp, earlier, &c, None), &Progress::new()).unwrap();
    // The slot is already there: every piece is in air (up to dexel crumbs at the walls).
    assert!(
        r.forces.totals.peak_resultant_n < 1.0,
        "{}",
        r.forces.totals.peak_resultant_n
    );
    let cancelled = Progress::new();
    cancelled.cancel();
    let e = operation_forces(&input(&stock, &tp, vec![], &c, None), &cancelled).unwrap_err();
    assert_eq!(e, ForceRunError::Cancelled);
}
