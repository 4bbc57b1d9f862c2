//! Engagement read from the Z-dexel stock against the analytic immersion of straight cuts, and
//! the forces of a slot, a half-immersion pass and a pocket corner.

use std::f64::consts::PI;

use glam::DVec3;
use talas::force::closed_form::mean_load;
use talas::force::stock::{SampleOptions, engagement_at};
use talas::force::{
    Coefficients, EndMill, LinearCoefficients, Mode, Profile, RevolutionOptions, StraightCut,
    revolution,
};
use talas::simulation::{DEFAULT_MEMORY_LIMIT_BYTES, DexelMode, DexelStock, StockShape};

const RES: f64 = 0.1;

fn stock(min: [f64; 3], max: [f64; 3]) -> DexelStock {
    let shapes = vec![StockShape::Box {
        min: DVec3::from_array(min),
        max: DVec3::from_array(max),
    }];
    DexelStock::new(shapes, RES, DexelMode::Z, DEFAULT_MEMORY_LIMIT_BYTES).expect("stock")
}

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

#[test]
fn straight_cuts_match_the_analytic_immersion() {
    let mill = EndMill::new(Profile::Flat, 12.0, 2, 30f64.to_radians(), 0.0).expect("mill");
    let (r, ap, ft) = (6.0, 8.0, 0.08);
    let opts = SampleOptions::default();
    // Feed along +x; the tool's centre at the origin, its tip at z = −ap, the top at z = 0.
    let cases = [
        (
            Mode::Up,
            3.0,
            stock([-40.0, r - 3.0, -30.0], [40.0, 40.0, 0.0]),
        ),
        (
            Mode::Down,
            4.5,
            stock([-40.0, -40.0, -30.0], [40.0, -(r - 4.5), 0.0]),
        ),
        (
            Mode::Slot,
            12.0,
            stock([-40.0, -40.0, -30.0], [40.0, 40.0, 0.0]),
        ),
    ];
    for (mode, ae, material) in &cases {
        let eng = engagement_at(
            material,
            &mill,
            DVec3::new(0.0, 0.0, -ap),
            DVec3::X,
            20.0,
            ft,
            &opts,
        )
        .expect("engagement");
        let cut = StraightCut {
            radial_depth: *ae,
            axial_depth: ap,
            feed_per_tooth: ft,
            mode: *mode,
        };
        let (st, ex) = cut.immersion(r);
        // Within the stock's resolution (a cell seen from the edge) plus the angular step.
        let tol = 1.5 * RES / r + opts.angle_step;
        let top = eng.disks.last().expect("disks").z1;
        assert!(
            (top - ap).abs() <= opts.disk_height + 1e-9,
            "{mode:?}: engaged up to {top}"
        );
        for d in eng.disks.iter().filter(|d| d.z1 <= ap - 1e-9) {
            let arcs = d.arcs.as_slice();
            assert_eq!(arcs.len(), 1, "{mode:?} disk {}: {arcs:?}", d.z0);
            let (s, e) = arcs[0];
            assert!(
                (s - st).abs() <= tol && (e - ex).abs() <= tol,
                "{mode:?}: [{s}, {e}] vs [{st}, {ex}]"
            );
        }
        // Forces from the stock's engagement against the analytic cut (same disks up to ap).
        let analytic = cut.engagement(&mill, opts.disk_height).expect("analytic");
        let m_stock = mean_load(&mill, &coefficients(), &eng).force;
        let m_exact = mean_load(&mill, &coefficients(), &analytic).force;
        let rel = ((m_stock.fx - m_exact.fx).powi(2) + (m_stock.fy - m_exact.fy).powi(2)).sqrt()
            / m_exact.resultant();
        assert!(rel < 0.03, "{mode:?}: {m_stock:?} vs {m_exact:?}");
    }
}

#[test]
fn slot_half_immersion_and_pocket_corner_forces_are_plausible() {
    let mill = EndMill::new(Profile::Flat, 10.0, 3, 30f64.to_radians(), 0.0).expect("mill");
    let k = coefficients();
    let opts = SampleOptions::default();
    let rev = RevolutionOptions::default();
    let tip = DVec3::new(0.0, 0.0, -5.0);
    let run = |m: &DexelStock| {
        let eng = engagement_at(m, &mill, tip, DVec3::X, 15.0, 0.05, &opts).expect("engagement");
        revolution(&mill, &k, &eng, &rev).expect("revolution")
    };
    let slot = run(&stock([-30.0, -30.0, -20.0], [30.0, 30.0, 0.0]));
    let half = run(&stock([-30.0, 0.0, -20.0], [30.0, 30.0, 0.0]));
    // A pocket's inside corner: half immersion along the wall on the left, and the end wall
    // 2 mm ahead of the tool's centre (material at x ≥ 2 across the whole width).
    let corner = {
        let shapes = vec![
            StockShape::Box {
                min: DVec3::new(-30.0, 0.0, -20.0),
                max: DVec3::new(30.0, 30.0, 0.0),
            },
            StockShape::Box {
                min: DVec3::new(2.0, -30.0, -20.0),
                max: DVec3::new(30.0, 30.0, 0.0),
            },
        ];
        let m =
            DexelStock::new(shapes, RES, DexelMode::Z, DEFAULT_MEMORY_LIMIT_BYTES).expect("stock");
        let eng = engagement_at(&m, &mill, tip, DVec3::X, 15.0, 0.05, &opts).expect("engagement");
        let arcs = eng.disks[0].arcs.as_slice().to_vec();
        // Engaged from φ = 0 to π/2 (the wall on the left) and on to where x ≥ 2 ends,
        // φ = π − asin(2/5).
        assert_eq!(arcs.len(), 1, "{arcs:?}");
        assert!(
            arcs[0].0 < 0.02 && (arcs[0].1 - (PI - (0.4f64).asin())).abs() < 0.05,
            "{arcs:?}"
        );
        revolution(&mill, &k, &eng, &rev).expect("revolution")
    };
    // More engagement, more load: the torque (every engaged edge adds to it) orders slot >
    // corner > half immersion, per revolution and at its peak; up milling pulls the tool
    // against the feed (F_x < 0) and into the wall (F_y > 0).
    assert!(
        slot.mean_torque_nm > corner.mean_torque_nm,
        "{} {}",
        slot.mean_torque_nm,
        corner.mean_torque_nm
    );
    assert!(
        corner.mean_torque_nm > 1.3 * half.mean_torque_nm,
        "{} {}",
        corner.mean_torque_nm,
        half.mean_torque_nm
    );
    assert!(
        slot.peak_torque_nm >= corner.peak_torque_nm && corner.peak_torque_nm > half.peak_torque_nm
    );
    assert!(
        half.mean.fx < 0.0 && half.mean.fy > 0.0,
        "up milling: {:?}",
        half.mean
    );
    assert!(slot.mean.fx < 0.0, "slot: {:?}", slot.mean);
    // Outside the stock: nothing engaged.
    let empty = engagement_at(
        &stock([50.0, 50.0, -20.0], [60.0, 60.0, 0.0]),
        &mill,
        tip,
        DVec3::X,
        15.0,
        0.05,
        &opts,
    )
    .expect("engagement");
    assert!(empty.disks.is_empty());
    assert!(
        engagement_at(
            &stock([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
            &mill,
            tip,
            DVec3::Z,
            15.0,
            0.05,
            &opts
        )
        .is_err()
    );
}

#[test]
fn feed_for_a_target_peak_force() {
    use talas::force::schedule::feed_for_peak_force;
    let mill = EndMill::new(Profile::Flat, 10.0, 3, 30f64.to_radians(), 0.0).expect("mill");
    let opts = RevolutionOptions::default();
    let m = stock([-30.0, 0.0, -20.0], [30.0, 30.0, 0.0]);
    let eng = engagement_at(
        &m,
        &mill,
        DVec3::new(0.0, 0.0, -5.0),
        DVec3::X,
        15.0,
        0.05,
        &SampleOptions::default(),
    )
    .expect("engagement");
    let k = coefficients();
    let exp = Coefficients::Exponential(talas::force::ExponentialCoefficients {
        kt: talas::force::coefficients::PowerLaw { k: 500.0, p: 0.3 },
        kr: talas::force::coefficients::PowerLaw { k: 0.3, p: 0.2 },
        ka: talas::force::coefficients::PowerLaw::constant(0.1),
    });
    for coeffs in [k, exp] {
        let mut last = 0.0;
        for target in [150.0, 300.0, 600.0] {
            let ft = feed_for_peak_force(&mill, &coeffs, &eng, target, &opts).expect("feed");
            let e = talas::force::Engagement {
                feed_per_tooth: ft,
                ..eng.clone()
            };
            let peak = revolution(&mill, &coeffs, &e, &opts)
                .expect("rev")
                .peak_resultant_n;
            assert!(
                (peak - target).abs() < 1e-6 * target,
                "{target}: {peak} at {ft}"
            );
            assert!(ft > last, "a higher target allows a higher feed");
            last = ft;
        }
    }
    assert!(feed_for_peak_force(&mill, &k, &eng, 1e6, &opts).is_err());
    assert!(feed_for_peak_force(&mill, &k, &eng, 0.5, &opts).is_err());
}
