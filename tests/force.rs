//! Cutting-force model: closed forms against numerical disk sums, the digest's half-immersion
//! mean-force formulas, profiles, calibration round trips and the cantilever.

use std::f64::consts::{PI, TAU};

use talas::force::calibrate::distribution::{self, DiskMean, DistributionTests};
use talas::force::calibrate::{calibrate_exponential, calibrate_linear};
use talas::force::closed_form::{case_table, case_table_applies, flute_integrals, mean_load};
use talas::force::coefficients::{ExponentialCoefficients, PowerLaw};
use talas::force::deflection::{BeamSpec, Cantilever};
use talas::force::disks::DiskForces;
use talas::force::measurements::{Measurement, parse_forces_csv};
use talas::force::{
    Coefficients, EndMill, Force, LinearCoefficients, Mode, Profile, RevolutionOptions,
    StraightCut, revolution,
};

/// xorshift64*: a fixed-seed generator for randomised cases.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

fn random_linear(rng: &mut Rng) -> LinearCoefficients {
    LinearCoefficients {
        ktc: rng.range(400.0, 2500.0),
        krc: rng.range(-100.0, 1500.0),
        kac: rng.range(-300.0, 600.0),
        kte: rng.range(-10.0, 40.0),
        kre: rng.range(-10.0, 40.0),
        kae: rng.range(-10.0, 20.0),
    }
}

/// A random flat-end-mill cut; `above` puts a_a above the critical depth.
fn random_cut(rng: &mut Rng, above: bool) -> (EndMill, StraightCut) {
    let d = rng.range(4.0, 25.0);
    let flutes = 1 + (rng.next() * 5.0) as u32;
    let helix = rng.range(10.0, 50.0).to_radians();
    let mill = EndMill::new(Profile::Flat, d, flutes, helix, 0.1).expect("mill");
    let crit = mill.critical_depth();
    let ap = if above {
        crit * rng.range(1.05, 2.5)
    } else {
        crit * rng.range(0.05, 0.95)
    };
    let mode = [Mode::Up, Mode::Down, Mode::Slot][(rng.next() * 3.0) as usize % 3];
    let ae = if mode == Mode::Slot {
        d
    } else {
        d * rng.range(0.05, 0.95)
    };
    let cut = StraightCut {
        radial_depth: ae,
        axial_depth: ap,
        feed_per_tooth: rng.range(0.01, 0.3),
        mode,
    };
    (mill, cut)
}

fn rel(a: Force, b: Force, scale: f64) -> f64 {
    let d = ((a.fx - b.fx).powi(2) + (a.fy - b.fy).powi(2) + (a.fz - b.fz).powi(2)).sqrt();
    d / scale.max(1e-12)
}

#[test]
fn closed_form_flute_integrals_equal_disk_sums() {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let mut worst = 0.0_f64;
    for case in 0..240 {
        let above = case % 2 == 1;
        let (mill, cut) = random_cut(&mut rng, above);
        let k = random_linear(&mut rng);
        let coeffs = Coefficients::Linear(k);
        let eng = cut
            .engagement(&mill, rng.range(0.2, 2.0))
            .expect("engagement");
        let arcs = eng.disks[0].arcs;
        let disks = DiskForces::new(&mill, &coeffs, &eng);
        // Scale: the force of the whole depth at full chip.
        let scale = cut.axial_depth * (k.ktc.abs() + k.krc.abs()) * cut.feed_per_tooth;
        for _ in 0..12 {
            let phi = rng.range(0.0, TAU);
            let closed =
                flute_integrals(&mill, &k, cut.feed_per_tooth, cut.axial_depth, &arcs, phi)
                    .expect("closed form");
            let summed = disks.load(phi, None);
            let e = rel(closed.force, summed.force, scale);
            worst = worst.max(e);
            assert!(
                e < 1e-9,
                "case {case} ({:?}, above {above}): {e:e}",
                cut.mode
            );
            let te = (closed.torque - summed.torque).abs() / (scale * mill.radius);
            assert!(te < 1e-9, "torque case {case}: {te:e}");
        }
    }
    eprintln!("closed form vs disk sums: worst relative difference {worst:e}");
}

#[test]
fn case_table_matches_interval_intersection() {
    // Where the thesis's case table applies it must give the same force as the general
    // intersection of the flute's angle range with every turn of the arc.
    let mut rng = Rng(77);
    for _ in 0..500 {
        let (st, ex) = {
            let a = rng.range(0.0, PI);
            let b = rng.range(a + 0.05, PI + 0.5);
            (a, b)
        };
        let k = rng.range(0.02, 0.4);
        let a = rng.range(0.1, (TAU - ex) / k);
        assert!(case_table_applies(k, a, ex));
        let tip = rng.range(-10.0, 10.0);
        let table = case_table(tip, k, a, st, ex);
        // Brute force: sample the flute densely.
        let n = 20_000;
        let mut inside = Vec::new();
        for i in 0..=n {
            let z = a * i as f64 / n as f64;
            let u = (tip - k * z).rem_euclid(TAU);
            if u >= st && u <= ex {
                inside.push(z);
            }
        }
        match table {
            None => assert!(
                inside.len() <= 1,
                "table says out, {} samples in",
                inside.len()
            ),
            Some((z1, z2)) => {
                let (lo, hi) = (inside[0], inside[inside.len() - 1]);
                let tol = a / n as f64 * 1.01;
                assert!(
                    (lo - z1).abs() <= tol && (hi - z2).abs() <= tol,
                    "{z1} {z2} vs {lo} {hi}"
                );
            }
        }
    }
}

/// Rotation average of the disk-sum force: composite Gauss–Legendre between the angles where
/// a flute's engagement changes at the tip or at the top of the cut.
fn rotation_average(mill: &EndMill, cut: &StraightCut, disks: &DiskForces) -> Force {
    let arcs = cut.arcs_at(mill.radius, mill.radius);
    let mut breaks = vec![0.0, TAU];
    for &(s, e) in arcs.as_slice() {
        for &theta in &mill.flute_angles {
            for z in [0.0, cut.axial_depth] {
                for edge in [s, e] {
                    breaks.push((edge - theta + mill.k_beta() * z).rem_euclid(TAU));
                }
            }
        }
    }
    breaks.sort_by(f64::total_cmp);
    let nodes = [
        -0.906_179_845_938_664,
        -0.538_469_310_105_683,
        0.0,
        0.538_469_310_105_683,
        0.906_179_845_938_664,
    ];
    let weights = [
        0.236_926_885_056_189,
        0.478_628_670_499_366,
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
    ];
    let mut sum = Force::default();
    for w in breaks.windows(2) {
        let pieces = 6;
        for p in 0..pieces {
            let a = w[0] + (w[1] - w[0]) * p as f64 / pieces as f64;
            let b = w[0] + (w[1] - w[0]) * (p + 1) as f64 / pieces as f64;
            for (x, wt) in nodes.iter().zip(weights) {
                let f = disks.load(0.5 * (a + b) + 0.5 * (b - a) * x, None).force;
                let h = 0.5 * (b - a) * wt / TAU;
                sum.fx += f.fx * h;
                sum.fy += f.fy * h;
                sum.fz += f.fz * h;
            }
        }
    }
    sum
}

#[test]
fn closed_form_means_equal_rotation_averaged_disk_sums() {
    let mut rng = Rng(0xfeed_beef);
    let mut worst = 0.0_f64;
    for case in 0..60 {
        let (mill, cut) = random_cut(&mut rng, case % 2 == 0);
        let k = random_linear(&mut rng);
        let coeffs = Coefficients::Linear(k);
        let eng = cut.engagement(&mill, 1.0).expect("engagement");
        let disks = DiskForces::new(&mill, &coeffs, &eng);
        let mean = mean_load(&mill, &coeffs, &eng).force;
        let avg = rotation_average(&mill, &cut, &disks);
        let scale = cut.axial_depth * (k.ktc.abs() + k.krc.abs()) * cut.feed_per_tooth;
        let e = rel(mean, avg, scale);
        worst = worst.max(e);
        assert!(
            e < 1e-9,
            "case {case} ({:?}): {e:e} {mean:?} {avg:?}",
            cut.mode
        );
    }
    eprintln!("closed-form mean vs averaged disk sums: worst {worst:e}");
}

#[test]
fn means_match_the_half_immersion_formulas() {
    // Digest §2.4 (Eq. 5.26 and 5.19 at half immersion), written out independently.
    let mill = EndMill::new(Profile::Flat, 12.0, 2, 30f64.to_radians(), 0.0).expect("mill");
    let (n, a, f) = (2.0, 18.0, 0.08);
    let k = LinearCoefficients {
        ktc: 900.0,
        krc: 350.0,
        kac: 0.0,
        kte: 20.0,
        kre: 15.0,
        kae: 0.0,
    };
    let c1 = n * a * f / (8.0 * PI);
    let c2 = n * a / (2.0 * PI);
    for (mode, fx, fy) in [
        (
            Mode::Up,
            -c1 * (2.0 * k.ktc + PI * k.krc) - c2 * (k.kte + k.kre),
            c1 * (PI * k.ktc - 2.0 * k.krc) + c2 * (k.kte - k.kre),
        ),
        (
            Mode::Down,
            c1 * (2.0 * k.ktc - PI * k.krc) + c2 * (k.kte - k.kre),
            c1 * (PI * k.ktc + 2.0 * k.krc) + c2 * (k.kte + k.kre),
        ),
    ] {
        let cut = StraightCut {
            radial_depth: 6.0,
            axial_depth: a,
            feed_per_tooth: f,
            mode,
        };
        let eng = cut.engagement(&mill, 0.5).expect("engagement");
        let m = mean_load(&mill, &Coefficients::Linear(k), &eng).force;
        assert!(
            (m.fx - fx).abs() < 1e-9 * fx.abs(),
            "{mode:?} fx {} vs {fx}",
            m.fx
        );
        assert!(
            (m.fy - fy).abs() < 1e-9 * fy.abs(),
            "{mode:?} fy {} vs {fy}",
            m.fy
        );
    }
    // Exponential model, C = N K_t f_t a_a / (8π), h_a = 2 f_t / π.
    let e = ExponentialCoefficients {
        kt: PowerLaw { k: 600.0, p: 0.3 },
        kr: PowerLaw { k: 0.2, p: 0.4 },
        ka: PowerLaw::constant(0.0),
    };
    let h = 2.0 * f / PI;
    let (kt, kr) = (e.kt.at(h), e.kr.at(h));
    let c = n * kt * f * a / (8.0 * PI);
    for (mode, fx, fy) in [
        (Mode::Up, c * (-2.0 - PI * kr), c * (PI - 2.0 * kr)),
        (Mode::Down, c * (2.0 - PI * kr), c * (PI + 2.0 * kr)),
    ] {
        let cut = StraightCut {
            radial_depth: 6.0,
            axial_depth: a,
            feed_per_tooth: f,
            mode,
        };
        let eng = cut.engagement(&mill, 0.5).expect("engagement");
        let m = mean_load(&mill, &Coefficients::Exponential(e), &eng).force;
        assert!(
            (m.fx - fx).abs() < 1e-9 * fx.abs(),
            "{mode:?} exp fx {} vs {fx}",
            m.fx
        );
        assert!(
            (m.fy - fy).abs() < 1e-9 * fy.abs(),
            "{mode:?} exp fy {} vs {fy}",
            m.fy
        );
    }
}

#[test]
fn slot_mean_and_single_tooth_closed_form() {
    // Slotting, straight teeth, one flute at φ: F_x = −a(K_te + K_tc f sin φ) cos φ − ...
    let mill = EndMill::new(Profile::Flat, 10.0, 1, 0.0, 0.0).expect("mill");
    let k = LinearCoefficients {
        ktc: 800.0,
        krc: 300.0,
        kac: 100.0,
        kte: 10.0,
        kre: 5.0,
        kae: 2.0,
    };
    let cut = StraightCut {
        radial_depth: 10.0,
        axial_depth: 3.0,
        feed_per_tooth: 0.1,
        mode: Mode::Slot,
    };
    let eng = cut.engagement(&mill, 0.5).expect("engagement");
    let d = DiskForces::new(&mill, &Coefficients::Linear(k), &eng);
    let phi: f64 = 1.0;
    let h = 0.1 * phi.sin();
    let (t, r, ax) = (k.kte + k.ktc * h, k.kre + k.krc * h, k.kae + k.kac * h);
    let f = d.load(phi, None).force;
    assert!((f.fx - 3.0 * (-t * phi.cos() - r * phi.sin())).abs() < 1e-9);
    assert!((f.fy - 3.0 * (t * phi.sin() - r * phi.cos())).abs() < 1e-9);
    assert!((f.fz - 3.0 * ax).abs() < 1e-9);
    // Out of the cut (φ in (π, 2π)): no force.
    assert_eq!(d.load(4.0, None).force, Force::default());
}

#[test]
fn ball_and_bull_nose_means_and_convergence() {
    let k = LinearCoefficients {
        ktc: 900.0,
        krc: 400.0,
        kac: 150.0,
        kte: 15.0,
        kre: 10.0,
        kae: 3.0,
    };
    let coeffs = Coefficients::Linear(k);
    for profile in [Profile::Ball, Profile::Bull { corner_radius: 2.0 }] {
        let mill = EndMill::new(profile, 10.0, 3, 30f64.to_radians(), 0.0).expect("mill");
        for mode in [Mode::Up, Mode::Down] {
            let cut = StraightCut {
                radial_depth: 3.0,
                axial_depth: 8.0,
                feed_per_tooth: 0.05,
                mode,
            };
            // The revolution's mean (exact in φ) equals the average of its own samples to the
            // sampling error, and the disk sums converge as the disks shrink.
            let coarse = cut.engagement(&mill, 0.5).expect("engagement");
            let fine = cut.engagement(&mill, 0.05).expect("engagement");
            let opts = RevolutionOptions {
                steps: 2000,
                spindle_rpm: Some(3000.0),
            };
            let rc = revolution(&mill, &coeffs, &coarse, &opts).expect("rev");
            let rf = revolution(&mill, &coeffs, &fine, &opts).expect("rev");
            let avg = |r: &talas::force::Revolution| {
                let n = r.samples.len() as f64;
                r.samples.iter().fold(Force::default(), |mut a, s| {
                    a.fx += s.force.fx / n;
                    a.fy += s.force.fy / n;
                    a.fz += s.force.fz / n;
                    a
                })
            };
            let scale = rf.mean.resultant();
            assert!(rel(avg(&rf), rf.mean, scale) < 2e-3, "{profile:?} {mode:?}");
            assert!(
                rel(rc.mean, rf.mean, scale) < 0.03,
                "{profile:?} {mode:?}: {:?} vs {:?}",
                rc.mean,
                rf.mean
            );
            assert!(rf.mean.fz > 0.0, "nose pushes the tool up");
            assert!(rf.peak_power_w.expect("power") > 0.0);
        }
    }
}

#[test]
fn revolution_peaks_power_and_bad_input() {
    let mill = EndMill::new(Profile::Flat, 12.0, 2, 30f64.to_radians(), 0.0).expect("mill");
    let k = Coefficients::Linear(LinearCoefficients {
        ktc: 800.0,
        krc: 300.0,
        kac: 0.0,
        kte: 10.0,
        kre: 10.0,
        kae: 0.0,
    });
    let cut = StraightCut {
        radial_depth: 6.0,
        axial_depth: 18.0,
        feed_per_tooth: 0.1,
        mode: Mode::Up,
    };
    let eng = cut.engagement(&mill, 0.5).expect("engagement");
    let rpm = 1000.0;
    let r = revolution(
        &mill,
        &k,
        &eng,
        &RevolutionOptions {
            steps: 720,
            spindle_rpm: Some(rpm),
        },
    )
    .expect("rev");
    let max_fx = r
        .samples
        .iter()
        .map(|s| s.force.fx.abs())
        .fold(0.0, f64::max);
    assert_eq!(r.peak.fx.abs(), max_fx);
    assert!(
        r.peak.fx < 0.0 && r.peak.fy > 0.0,
        "up milling: F_x < 0, F_y > 0"
    );
    // Torque: mean tangential force per tooth-period times R; power = T·ω.
    let p = r.mean_power_w.expect("power");
    assert!((p - r.mean_torque_nm * rpm * TAU / 60.0).abs() < 1e-9 * p);
    assert!(
        revolution(
            &mill,
            &k,
            &eng,
            &RevolutionOptions {
                steps: 3,
                spindle_rpm: None
            }
        )
        .is_err()
    );
    for bad in [
        StraightCut {
            radial_depth: 13.0,
            ..cut
        },
        StraightCut {
            axial_depth: -1.0,
            ..cut
        },
        StraightCut {
            feed_per_tooth: f64::NAN,
            ..cut
        },
        StraightCut {
            mode: Mode::Slot,
            ..cut
        },
    ] {
        assert!(bad.engagement(&mill, 0.5).is_err(), "{bad:?}");
    }
    assert!(EndMill::new(Profile::Flat, 10.0, 0, 0.5, 0.0).is_err());
    assert!(EndMill::new(Profile::Flat, 10.0, 2, 1.2, 0.0).is_err());
}

fn synthetic_rows(k: &Coefficients, with_fz: bool) -> Vec<Measurement> {
    let mut rows = Vec::new();
    let mut line = 2;
    for (d, mode, ae) in [
        (10.0, Mode::Up, 5.0),
        (10.0, Mode::Down, 3.0),
        (12.0, Mode::Slot, 12.0),
    ] {
        for ft in [0.03, 0.06, 0.1, 0.15] {
            let m = Measurement {
                line,
                diameter: d,
                flutes: 3,
                helix: 0.5,
                rake: 0.1,
                mode,
                ae,
                ap: 8.0,
                ft,
                fx: 0.0,
                fy: 0.0,
                fz: None,
            };
            let mill = m.mill().expect("mill");
            let eng = m.cut().engagement(&mill, 0.5).expect("eng");
            let f = mean_load(&mill, k, &eng).force;
            rows.push(Measurement {
                fx: f.fx,
                fy: f.fy,
                fz: with_fz.then_some(f.fz),
                ..m
            });
            line += 1;
        }
    }
    rows
}

#[test]
fn linear_calibration_recovers_coefficients() {
    let k = LinearCoefficients {
        ktc: 1100.0,
        krc: 420.0,
        kac: 160.0,
        kte: 18.0,
        kre: 12.0,
        kae: 4.0,
    };
    let rows = synthetic_rows(&Coefficients::Linear(k), true);
    let cal = calibrate_linear(&rows).expect("calibration");
    let Coefficients::Linear(got) = cal.coefficients else {
        panic!("linear")
    };
    for (a, b) in got.to_array().iter().zip(k.to_array()) {
        assert!((a - b).abs() < 1e-6 * b.abs().max(1.0), "{got:?}");
    }
    assert!(cal.mean_error_pct[0] < 1e-6 && cal.mean_error_pct[1] < 1e-6);
    // Without F_z the axial terms are not determined; with one feed nothing is.
    let no_z: Vec<Measurement> = rows
        .iter()
        .map(|m| Measurement {
            fz: None,
            ..m.clone()
        })
        .collect();
    let cal = calibrate_linear(&no_z).expect("calibration");
    assert!(!cal.notes.is_empty());
    let one_feed: Vec<Measurement> = rows
        .iter()
        .filter(|m| m.ft == 0.06 && m.mode == Mode::Up)
        .cloned()
        .collect();
    assert!(calibrate_linear(&one_feed).is_err());
}

#[test]
fn exponential_calibration_recovers_power_laws() {
    let e = ExponentialCoefficients {
        kt: PowerLaw { k: 520.0, p: 0.28 },
        kr: PowerLaw { k: 0.25, p: 0.35 },
        ka: PowerLaw { k: 0.1, p: 0.1 },
    };
    let rows = synthetic_rows(&Coefficients::Exponential(e), true);
    let cal = calibrate_exponential(&rows).expect("calibration");
    let Coefficients::Exponential(got) = cal.coefficients else {
        panic!("exponential")
    };
    for (a, b) in [(got.kt, e.kt), (got.kr, e.kr), (got.ka, e.ka)] {
        assert!((a.k - b.k).abs() < 1e-5 * b.k.abs(), "{got:?}");
        assert!((a.p - b.p).abs() < 1e-5, "{got:?}");
    }
}

#[test]
fn distribution_method_round_trip() {
    // Per-disk means of single-flute half-immersion tests, generated by the model, inverted by
    // the CFD method (quadratic along z, Eqs. 5.20 and 5.27) give the coefficients back.
    let mill = EndMill::new(Profile::Flat, 12.0, 1, 30f64.to_radians(), 0.0).expect("mill");
    let a = 18.0;
    let dz = 3.0;
    let k = LinearCoefficients {
        ktc: 950.0,
        krc: 380.0,
        kac: 0.0,
        kte: 14.0,
        kre: 9.0,
        kae: 0.0,
    };
    let e = ExponentialCoefficients {
        kt: PowerLaw { k: 480.0, p: 0.3 },
        kr: PowerLaw { k: 0.3, p: 0.2 },
        ka: PowerLaw::constant(0.0),
    };
    for mode in [Mode::Up, Mode::Down] {
        let series = |coeffs: &Coefficients| {
            let mut disks = Vec::new();
            for ft in [0.04, 0.08, 0.12] {
                let cut = StraightCut {
                    radial_depth: 6.0,
                    axial_depth: a,
                    feed_per_tooth: ft,
                    mode,
                };
                let eng = cut.engagement(&mill, dz).expect("eng");
                for d in &eng.disks {
                    let one = talas::force::Engagement {
                        disks: vec![*d],
                        feed_per_tooth: ft,
                    };
                    let f = mean_load(&mill, coeffs, &one).force;
                    disks.push(DiskMean {
                        z_mm: 0.5 * (d.z0 + d.z1),
                        height_mm: d.z1 - d.z0,
                        ft_mm: ft,
                        fx_n: f.fx,
                        fy_n: f.fy,
                    });
                }
            }
            DistributionTests {
                flutes: 1,
                axial_depth: a,
                mode,
                disks,
            }
        };
        let got = distribution::linear(&series(&Coefficients::Linear(k))).expect("linear");
        for (x, y) in [
            (got.ktc, k.ktc),
            (got.krc, k.krc),
            (got.kte, k.kte),
            (got.kre, k.kre),
        ] {
            assert!((x - y).abs() < 1e-8 * y.abs(), "{mode:?} {got:?}");
        }
        let got = distribution::exponential(&series(&Coefficients::Exponential(e))).expect("exp");
        assert!(
            (got.kt.k - e.kt.k).abs() < 1e-8 * e.kt.k && (got.kt.p - e.kt.p).abs() < 1e-10,
            "{got:?}"
        );
        assert!(
            (got.kr.k - e.kr.k).abs() < 1e-8 && (got.kr.p - e.kr.p).abs() < 1e-8,
            "{got:?}"
        );
    }
}

#[test]
fn cantilever_matches_textbook_and_numerical_integration() {
    let beam = Cantilever::end_mill(&BeamSpec {
        diameter: 10.0,
        flute_length: 60.0,
        shank_diameter: 10.0,
        overhang: 40.0,
        youngs_modulus: 600_000.0,
        flute_diameter_ratio: 0.8,
    })
    .expect("beam");
    let ei = 600_000.0 * PI * 8f64.powi(4) / 64.0;
    for (zs, zm) in [(0.0, 5.0), (10.0, 2.0), (3.0, 3.0), (39.0, 0.0)] {
        let (us, um): (f64, f64) = (40.0 - zs, 40.0 - zm);
        let want = if us <= um {
            us * us * (3.0 * um - us)
        } else {
            um * um * (3.0 * us - um)
        } / (6.0 * ei);
        assert!(
            (beam.influence(zs, zm) - want).abs() < 1e-12 * want.max(1e-9),
            "{zs} {zm}"
        );
    }
    // Stepped beam: integrate the curvature M/EI twice from the clamp numerically.
    let spec = BeamSpec {
        diameter: 12.0,
        flute_length: 26.0,
        shank_diameter: 12.0,
        overhang: 48.0,
        youngs_modulus: 600_000.0,
        flute_diameter_ratio: 0.8,
    };
    let beam = Cantilever::end_mill(&spec).expect("beam");
    let (zm, l) = (5.0, 48.0);
    let ei_at = |z: f64| 600_000.0 * PI * if z < 26.0 { 9.6f64 } else { 12.0 }.powi(4) / 64.0;
    let n = 200_000;
    let h = l / n as f64;
    let (mut slope, mut defl) = (0.0, vec![0.0; n + 1]);
    for i in (0..n).rev() {
        let z = (i as f64 + 0.5) * h;
        let curvature = (z - zm).max(0.0) / ei_at(z);
        slope += curvature * h;
        defl[i] = defl[i + 1] + slope * h;
    }
    for zs in [0.0, 10.0, 30.0] {
        let numeric = defl[(zs / h).round() as usize];
        let exact = beam.influence(zs, zm);
        assert!(
            (numeric - exact).abs() < 1e-4 * exact,
            "{zs}: {numeric} vs {exact}"
        );
    }
}

#[test]
fn forces_csv_reader_is_generous_and_names_rows() {
    let text = "# comment\n\nD_mm ; flutes;helix_deg;rake_deg;mode;ae_mm;ap_mm;ft_mm;fx_n;fy_n;fz_n;note\n\
                12;2;30;15;up;6;18;0.04;-130.6;277;;first\n 12 ; 2 ;30;15;Down;6;18;0.08;-1;2;3;x\n";
    let rows = parse_forces_csv(text).expect("parse");
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[0].line, 4);
    assert_eq!(rows[0].fz, None);
    assert_eq!(rows[1].fz, Some(3.0));
    assert_eq!(rows[1].mode, Mode::Down);
    for (bad, line) in [
        ("d_mm,flutes\n1,2\n", 1),
        (
            "d_mm,flutes,helix_deg,rake_deg,mode,ae_mm,ap_mm,ft_mm,fx_n,fy_n\n12,2,30,15,up,6,18,0.04,-1\n",
            2,
        ),
        (
            "d_mm,flutes,helix_deg,rake_deg,mode,ae_mm,ap_mm,ft_mm,fx_n,fy_n\n12,2,30,15,up,6,18,0.04,-1,2\n12,2,30,15,sideways,6,18,0.04,-1,2\n",
            3,
        ),
        (
            "d_mm,flutes,helix_deg,rake_deg,mode,ae_mm,ap_mm,ft_mm,fx_n,fy_n\n12,2,30,15,up,16,18,0.04,-1,2\n",
            2,
        ),
        (
            "d_mm,flutes,helix_deg,rake_deg,mode,ae_mm,ap_mm,ft_mm,fx_n,fy_n\n12,2.5,30,15,up,6,18,0.04,-1,2\n",
            2,
        ),
        (
            "d_mm,flutes,helix_deg,rake_deg,mode,ae_mm,ap_mm,ft_mm,fx_n,fy_n\n12,2,30,15,up,6,18,abc,-1,2\n",
            2,
        ),
        (
            "d_mm,flutes,helix_deg,rake_deg,mode,ae_mm,ap_mm,ft_mm,fx_n,fy_n\n",
            1,
        ),
    ] {
        let e = parse_forces_csv(bad).expect_err(bad);
        assert_eq!(e.line, line, "{bad}: {e}");
    }
}
