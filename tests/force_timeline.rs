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

/// The block the slot is cut in: 20 × 20 × 10 mm, its top at z = 0.
fn slot_stock() -> Stock {
    Stock::Box {
        min_mm: [-10.0, -10.0, -10.0],
        max_mm: [10.0, 10.0, 0.0],
    }
}

#[test]
fn pieces_are_timed_at_the_feed_or_on_the_planned_clock() {
    let (stock, tp, c) = (slot_stock(), slot(), coefficients());
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

/// A uniform round carbide bar (the fluted section as thick as the shank, fluted to the
/// holder): EI = E·π·D⁴/64.
fn uniform_beam(d: f64, length: f64) -> (talas::force::deflection::Cantilever, f64) {
    use talas::force::deflection::{BeamSpec, CARBIDE_E, Cantilever};
    let beam = Cantilever::end_mill(&BeamSpec {
        diameter: d,
        flute_length: length,
        shank_diameter: d,
        overhang: length,
        youngs_modulus: CARBIDE_E,
        flute_diameter_ratio: 1.0,
    })
    .unwrap();
    (beam, CARBIDE_E * std::f64::consts::PI * d.powi(4) / 64.0)
}

#[test]
fn the_deflection_profile_is_the_cantilevers_closed_form() {
    use talas::force::deflection::deflection_profile;
    let (l, f) = (40.0, 120.0);
    let (beam, ei) = uniform_beam(10.0, l);
    // A point load F at the free end (the tip): δ(0) = F·L³/(3EI) and, z above the tip,
    // δ(z) = F·(2L³ − 3L²z + z³)/(6EI).
    let p = deflection_profile(&beam, &[(0.0, f, -0.5 * f)], 10.0, 11).unwrap();
    assert_eq!(p.len(), 11);
    // By hand: EI = 600 000 N/mm² · π · 10⁴/64 mm⁴ = 2.945e8 N·mm²; 120·40³/(3·2.945e8) mm.
    assert!((p[0].dx_um - 8.692).abs() < 1e-3, "{}", p[0].dx_um);
    assert!((p[0].dx_um - 1e3 * f * l.powi(3) / (3.0 * ei)).abs() < 1e-9 * p[0].dx_um.abs());
    for q in &p {
        let z = q.z_mm;
        let expect = 1e3 * f * (2.0 * l.powi(3) - 3.0 * l * l * z + z.powi(3)) / (6.0 * ei);
        assert!(
            (q.dx_um - expect).abs() < 1e-9 * expect,
            "z {z}: {} vs {expect}",
            q.dx_um
        );
        assert!((q.dy_um + 0.5 * expect).abs() < 1e-9 * expect);
    }
    // A load a = 30 mm from the clamp (10 mm above the tip): at the tip F·a²(3L − a)/(6EI).
    let a = 30.0;
    let p = deflection_profile(&beam, &[(l - a, f, 0.0)], 10.0, 2).unwrap();
    let expect = 1e3 * f * a * a * (3.0 * l - a) / (6.0 * ei);
    assert!((p[0].dx_um - expect).abs() < 1e-9 * expect);
    assert!(deflection_profile(&beam, &[], 50.0, 5).is_err());
    assert!(deflection_profile(&beam, &[], 5.0, 1).is_err());
}

#[test]
fn a_poses_deflection_is_its_heaviest_pieces() {
    use talas::force::deflection::{BeamSpec, Cantilever, deflection_profile};
    use talas::project::forces::pose_deflection;
    let (stock, tp, c) = (slot_stock(), slot(), coefficients());
    let r = operation_forces(&input(&stock, &tp, vec![], &c, None), &Progress::new()).unwrap();
    let cutter = &tp.tool.cutter;
    let spec = BeamSpec {
        diameter: 10.0,
        flute_length: 40.0,
        shank_diameter: 10.0,
        overhang: 40.0,
        youngs_modulus: talas::force::deflection::CARBIDE_E,
        flute_diameter_ratio: 1.0,
    };
    // The rapid and the plunge cut no side material.
    assert_eq!(pose_deflection(&r, 0, cutter, &c, &spec, 21).unwrap(), None);
    assert_eq!(pose_deflection(&r, 1, cutter, &c, &spec, 21).unwrap(), None);
    let d = pose_deflection(&r, 2, cutter, &c, &spec, 21)
        .unwrap()
        .expect("the slot move cuts");
    assert_eq!(Some(d.mode), r.forces.pieces[d.piece].mode);
    let heaviest = r
        .forces
        .pieces
        .iter()
        .map(|p| p.peak_resultant_n)
        .fold(0.0, f64::max);
    assert_eq!(r.forces.pieces[d.piece].peak_resultant_n, heaviest);
    // 3 mm deep: the profiles run from the tip to 3 mm.
    assert!((d.depth_mm - 3.0).abs() < 1e-9);
    assert_eq!(d.deflection.len(), 21);
    assert!((d.deflection[20].z_mm - 3.0).abs() < 1e-9);
    assert_eq!(d.wall.len(), 21);
    // All disks load within 3 mm of the tip of a 40 mm uniform bar: the tip deflection lies
    // between the closed forms of the summed load at the tip and at 3 mm, F·u²(3L − u)/(6EI)
    // with u = L and u = L − 3 (the disk loads point alike at a slot's peak).
    let (_, ei) = uniform_beam(10.0, 40.0);
    let (beam, _) = uniform_beam(10.0, 40.0);
    let tip = d.deflection[0].dx_um.hypot(d.deflection[0].dy_um);
    let (phi, loads) = talas::force::deflection::peak_disk_loads(
        &talas::force::EndMill::from_cutter(cutter).unwrap(),
        c.get(d.mode),
        &r.forces.pieces[d.piece].engagement,
        360,
    );
    assert!((phi - d.phi_rad).abs() < 1e-12);
    let (fx, fy) = loads
        .iter()
        .fold((0.0, 0.0), |(a, b), l| (a + l.1, b + l.2));
    let f = fx.hypot(fy);
    let at = |u: f64| 1e3 * f * u * u * (3.0 * 40.0 - u) / (6.0 * ei);
    assert!(f > 100.0, "a 3 mm slot in Al7075 with a D10: {f} N");
    assert!(
        tip <= at(40.0) * 1.0001 && tip >= at(37.0) * 0.9999,
        "{tip} µm vs [{}, {}]",
        at(37.0),
        at(40.0)
    );
    let again = deflection_profile(&beam, &loads, 3.0, 21).unwrap();
    assert_eq!(again, d.deflection);
    // The slot's wall error: a few µm to tens of µm on this stiff bar.
    assert!(d.wall.iter().all(|w| w.error_um.abs() < 100.0));
    let _ = Cantilever::end_mill(&spec).unwrap();
}
