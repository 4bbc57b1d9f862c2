//! Forces along programs: the engagement read from the simulated stock before each move
//! against the analytic immersion of straight cuts and of a pocket corner, and the mean
//! forces of a slot against the closed form.

use std::f64::consts::PI;

use glam::DVec3;
use talas::force::closed_form::mean_load;
use talas::force::path::{
    Limits, ModeCoefficients, MoveClass, PathForces, PathOptions, path_forces,
};
use talas::force::stock::{SimulatedStock, path_moves};
use talas::force::{Coefficients, EndMill, LinearCoefficients, Mode, StraightCut};
use talas::gcode::{InterpretOptions, Syntax, interpret};
use talas::simulation::{
    DEFAULT_MEMORY_LIMIT_BYTES, DexelMode, DexelStock, StepOptions, StockShape, plan_program,
};
use talas::tools::parse_tool_spec;

const RES: f64 = 0.1;
const TOOL: &str = "flat:d=10,flute=25,flutes=2,helix=30,rake=10";

fn coefficients() -> Coefficients {
    Coefficients::Linear(LinearCoefficients {
        ktc: 900.0,
        krc: 350.0,
        kac: 120.0,
        kte: 15.0,
        kre: 10.0,
        kae: 2.0,
    })
}

fn mode_coefficients() -> ModeCoefficients {
    ModeCoefficients {
        up: coefficients(),
        down: coefficients(),
        slot: coefficients(),
    }
}

/// Run `program` over a box stock and return the forces.
fn run(program: &str, min: [f64; 3], max: [f64; 3], limits: Limits) -> PathForces {
    let cutter = parse_tool_spec(TOOL).expect("tool");
    let mill = EndMill::from_cutter(&cutter).expect("mill");
    let prog = interpret(
        program,
        &InterpretOptions::for_syntax(Syntax::detect(program)),
    )
    .expect("program");
    let plan = plan_program(&prog, None, &StepOptions::default()).expect("plan");
    let moves = path_moves(&plan, |i| prog.blocks[i].spindle_rpm.abs());
    let stock = DexelStock::new(
        vec![StockShape::Box {
            min: DVec3::from_array(min),
            max: DVec3::from_array(max),
        }],
        RES,
        DexelMode::Z,
        DEFAULT_MEMORY_LIMIT_BYTES,
    )
    .expect("stock");
    let mut work = SimulatedStock::new(stock, &cutter, &plan);
    let options = PathOptions {
        flute_length_mm: cutter.flute_length,
        limits,
        ..PathOptions::default()
    };
    path_forces(&mut work, &mill, &mode_coefficients(), &moves, &options).expect("forces")
}

fn mill() -> EndMill {
    EndMill::from_cutter(&parse_tool_spec(TOOL).expect("tool")).expect("mill")
}

/// Up clear of the stock, over to x = −40 and down to 6 mm below the stock top; F600 at S3000
/// with 2 flutes is 0.1 mm per tooth. The first cutting move is move 3.
const HEADER: &str = "G21 G90 G94\nS3000 M3\nG0 Z5\nG0 X-40 Y0\nG1 Z-6 F600\n";

#[test]
fn slot_mean_forces_equal_the_closed_form() {
    let program = format!("{HEADER}G1 X40\nG0 Z5\nM30\n");
    let out = run(
        &program,
        [-30.0, -30.0, -20.0],
        [30.0, 30.0, 0.0],
        Limits::default(),
    );
    let cut = &out.moves[3];
    assert_eq!(cut.class, MoveClass::Cut);
    assert!((cut.feed_per_tooth_mm - 0.1).abs() < 1e-12);
    let analytic = StraightCut {
        radial_depth: 10.0,
        axial_depth: 6.0,
        feed_per_tooth: 0.1,
        mode: Mode::Slot,
    };
    let exact = mean_load(
        &mill(),
        &coefficients(),
        &analytic.engagement(&mill(), 0.5).unwrap(),
    )
    .force;
    // Steady pieces: the tool fully inside the stock, more than a radius from either end.
    let steady: Vec<_> = out
        .pieces
        .iter()
        .filter(|p| p.move_index == 3 && p.from.x > -24.0 && p.to.x < 24.0)
        .collect();
    assert!(steady.len() > 60, "{} pieces", steady.len());
    for p in steady {
        assert_eq!(p.mode, Some(Mode::Slot));
        let d = p
            .engagement
            .disks
            .iter()
            .filter(|d| !d.arcs.is_empty())
            .count();
        assert_eq!(d, 12, "disks of 0.5 mm up to the 6 mm depth");
        // Feed along +x: the machine frame is the feed frame.
        for (a, b) in [
            (p.mean.fx, exact.fx),
            (p.mean.fy, exact.fy),
            (p.mean.fz, exact.fz),
        ] {
            assert!(
                (a - b).abs() <= 1e-6 * exact.resultant(),
                "{:?} vs {exact:?}",
                p.mean
            );
        }
    }
    // Entry into the stock: the engagement grows from nothing to the full slot.
    let entry: Vec<f64> = out
        .pieces
        .iter()
        .filter(|p| p.move_index == 3 && p.from.x > -36.0 && p.to.x < -24.0)
        .map(|p| p.mean.resultant())
        .collect();
    assert!(
        entry.first().copied().unwrap_or(1.0) == 0.0
            && entry.windows(2).all(|w| w[1] >= w[0] - 1e-9)
    );
    assert!(cut.limits_exceeded.is_empty());
}

#[test]
fn half_immersion_entry_and_exit_match_the_analytic_immersion() {
    // Material on the left of the +x feed (y ≥ 0): up milling, [0, π/2]; on the right:
    // down milling, [π/2, π]. A pass at y = 3 along material from y = 6 has a radial depth of
    // 2 mm: up milling [0, arccos(1 − 2/5)].
    for (min_y, max_y, y, ae, mode) in [
        (0.0, 30.0, 0.0, 5.0, Mode::Up),
        (-30.0, 0.0, 0.0, 5.0, Mode::Down),
        (6.0, 30.0, 3.0, 2.0, Mode::Up),
    ] {
        let program = format!(
            "G21 G90 G94\nS3000 M3\nG0 Z5\nG0 X-40 Y{y}\nG1 Z-6 F600\nG1 X40\nG0 Z5\nM30\n"
        );
        let out = run(
            &program,
            [-30.0, min_y, -20.0],
            [30.0, max_y, 0.0],
            Limits::default(),
        );
        let analytic = StraightCut {
            radial_depth: ae,
            axial_depth: 6.0,
            feed_per_tooth: 0.1,
            mode,
        };
        let (st, ex) = analytic.immersion(5.0);
        let tol = 1.5 * RES / 5.0 + PathOptions::default().sample.angle_step;
        let exact = mean_load(
            &mill(),
            &coefficients(),
            &analytic.engagement(&mill(), 0.5).unwrap(),
        )
        .force;
        let mut n = 0;
        for p in out
            .pieces
            .iter()
            .filter(|p| p.move_index == 3 && p.from.x > -24.0 && p.to.x < 24.0)
        {
            n += 1;
            assert_eq!(p.mode, Some(mode));
            for d in p.engagement.disks.iter().filter(|d| d.z1 <= 6.0 + 1e-9) {
                let a = d.arcs.as_slice();
                assert_eq!(a.len(), 1, "{mode:?}: {a:?}");
                assert!(
                    (a[0].0 - st).abs() <= tol && (a[0].1 - ex).abs() <= tol,
                    "{mode:?} y={y}: [{}, {}] vs [{st}, {ex}]",
                    a[0].0,
                    a[0].1
                );
            }
            let err = ((p.mean.fx - exact.fx).powi(2) + (p.mean.fy - exact.fy).powi(2)).sqrt();
            assert!(
                err < 0.03 * exact.resultant(),
                "{mode:?}: {:?} vs {exact:?}",
                p.mean
            );
        }
        assert!(n > 60);
    }
}

#[test]
fn pocket_corner_engagement_grows_as_the_analytic_corner_and_limits_are_flagged() {
    // A slot along +x to x = 10, then a slot along +y from the corner: at a distance d past
    // the corner the second leg's tool is engaged from arcsin(1 − d/R) to π (the first slot
    // cleared |y| ≤ R behind x = 10); beyond d = R it is a full slot again.
    let program = format!("{HEADER}G1 X10\nG1 Y40\nG0 Z5\nM30\n");
    let limits = Limits {
        max_force_n: Some(1.0),
        max_torque_nm: None,
        max_power_w: None,
    };
    let out = run(&program, [-30.0, -30.0, -20.0], [30.0, 30.0, 0.0], limits);
    let r = 5.0;
    let tol = 1.5 * RES / r + PathOptions::default().sample.angle_step;
    let leg: Vec<_> = out.pieces.iter().filter(|p| p.move_index == 4).collect();
    let mut checked = 0;
    let mut last = 0.0;
    for p in &leg {
        let d = 0.5 * (p.from.y + p.to.y);
        if !(0.3..=r - 0.3).contains(&d) {
            continue;
        }
        let want = (1.0 - d / r).asin();
        for disk in p.engagement.disks.iter().filter(|k| k.z1 <= 6.0 + 1e-9) {
            let a = disk.arcs.as_slice();
            assert_eq!(a.len(), 1, "d={d}: {a:?}");
            assert!(
                (a[0].0 - want).abs() <= tol && (a[0].1 - PI).abs() <= tol,
                "d={d}: [{}, {}] vs [{want}, π]",
                a[0].0,
                a[0].1
            );
        }
        // More engagement, more torque.
        assert!(p.mean_torque_nm >= last - 1e-9, "d={d}");
        last = p.mean_torque_nm;
        checked += 1;
    }
    assert!(checked >= 8, "{checked} corner pieces");
    // Past the corner it is a slot again, as on the first leg.
    let slot_first = out.moves[3].peak_resultant_n;
    let steady = leg
        .iter()
        .filter(|p| p.from.y > r + 1.0 && p.to.y < 24.0)
        .map(|p| p.peak_resultant_n)
        .fold(0.0, f64::max);
    assert!(
        (steady - slot_first).abs() < 0.02 * slot_first,
        "{steady} vs {slot_first}"
    );
    // A 1 N limit is exceeded by both cutting moves and counted.
    assert_eq!(out.moves[3].limits_exceeded, vec!["force"]);
    assert_eq!(out.moves[4].limits_exceeded, vec!["force"]);
    assert_eq!(out.totals.moves_over_limits, 2);
    assert_eq!(out.totals.cutting_moves, 2);
    // The plunge to depth is marked, not modelled.
    assert_eq!(out.moves[2].class, MoveClass::Plunge);
    assert_eq!(out.totals.moves_not_modelled, 1);
}
