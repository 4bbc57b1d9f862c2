//! 1-DoF jerk-limited profiles against hand-derived closed forms.

mod common;

use common::{Lcg, assert_rel_near};
use talas::feed::{Limits1, Profile, ProfileError, reachable_velocity};

fn lim(v: f64, a: f64, j: f64) -> Limits1 {
    Limits1 {
        velocity: v,
        acceleration: a,
        jerk: j,
    }
}

#[test]
fn full_seven_phase_rest_to_rest() {
    // Cruise and constant-acceleration phases: T = s/v + v/a + a/j (v·j ≥ a², s long).
    let p = Profile::rest_to_rest(100.0, &lim(50.0, 500.0, 20_000.0)).unwrap();
    assert_rel_near!(
        p.duration_s(),
        100.0 / 50.0 + 50.0 / 500.0 + 500.0 / 20_000.0,
        1e-12
    );
    let (s, v, a, _) = p.at_time(p.duration_s());
    assert_rel_near!(s, 100.0, 1e-15);
    assert!(v.abs() < 1e-9 && a.abs() < 1e-9);
}

#[test]
fn thesis_v8_line_duration() {
    // V8: L = |(15,20,10)|, v = 50, A = 1000, J = 20000: T = L/v + v/A + A/J = 0.63852 s.
    let l = (15.0f64 * 15.0 + 400.0 + 100.0).sqrt();
    let p = Profile::rest_to_rest(l, &lim(50.0, 1000.0, 20_000.0)).unwrap();
    assert_rel_near!(p.duration_s(), l / 50.0 + 0.1, 1e-12);
    assert!(p.duration_s() <= 0.63852 + 1e-5);
}

#[test]
fn no_cruise_no_constant_acceleration() {
    // Pure jerk pulses: s = 2·vp^(3/2)/√J, T = 4·(s/(2J))^(1/3).
    let p = Profile::rest_to_rest(1.0, &lim(1e6, 1e6, 1000.0)).unwrap();
    assert_rel_near!(p.duration_s(), 4.0 * (1.0f64 / 2000.0).cbrt(), 1e-10);
}

#[test]
fn constant_acceleration_without_cruise() {
    // vp·(vp/a + a/j) = s → vp = (−a²/j + √(a⁴/j² + 4·s·a))/2, T = 2·(vp/a + a/j).
    let (s, a, j) = (10.0f64, 100.0f64, 10_000.0f64);
    let vp = (-a * a / j + (a.powi(4) / (j * j) + 4.0 * s * a).sqrt()) / 2.0;
    let p = Profile::rest_to_rest(s, &lim(1e6, a, j)).unwrap();
    assert_rel_near!(p.duration_s(), 2.0 * (vp / a + a / j), 1e-10);
    assert_rel_near!(p.peak_velocity, vp, 1e-10);
}

#[test]
fn boundary_velocities_and_unreachable() {
    // Exactly the distance of the change 10 → 30 (A = 100, J = 1000: 20·1000 ≥ 100²):
    // T = 20/100 + 100/1000 = 0.3 s, s = 20·0.3 = 6.
    let l = lim(30.0, 100.0, 1000.0);
    let p = Profile::calculate(6.0, 10.0, 30.0, &l).unwrap();
    assert_rel_near!(p.duration_s(), 0.3, 1e-9);
    assert!(matches!(
        Profile::calculate(5.0, 10.0, 30.0, &l),
        Err(ProfileError::Unreachable { .. })
    ));
    assert_rel_near!(
        reachable_velocity(10.0, 6.0, 100.0, 100.0, 1000.0),
        30.0,
        1e-9
    );
    // Cruise only when v0 = v1 = vmax.
    let p = Profile::calculate(3.0, 30.0, 30.0, &l).unwrap();
    assert_rel_near!(p.duration_s(), 0.1, 1e-12);
    assert!(matches!(
        Profile::calculate(f64::NAN, 0.0, 0.0, &l),
        Err(ProfileError::InvalidInput)
    ));
    assert!(matches!(
        Profile::calculate(1.0, 40.0, 0.0, &l),
        Err(ProfileError::BoundaryAboveLimit { .. })
    ));
    let z = Profile::rest_to_rest(0.0, &l).unwrap();
    assert_eq!(z.duration_s(), 0.0);
}

#[test]
fn random_profiles_hold_limits_and_reach_target() {
    let mut rng = Lcg(12345);
    let mut rnd = move || rng.next();
    for _ in 0..5000 {
        let l = lim(
            1.0 + 500.0 * rnd(),
            10.0 + 5000.0 * rnd(),
            100.0 + 1e5 * rnd(),
        );
        let (v0, v1) = (l.velocity * rnd(), l.velocity * rnd());
        let s = 1e-4 + 200.0 * rnd() * rnd();
        match Profile::calculate(s, v0, v1, &l) {
            Ok(p) => {
                let t_end = p.duration_s();
                assert!(t_end.is_finite());
                for i in 0..=200 {
                    let (ps, v, a, j) = p.at_time(t_end * f64::from(i) / 200.0);
                    assert!(ps.is_finite() && v <= l.velocity * 1.000_001 && v >= 0.0);
                    assert!(a.abs() <= l.acceleration * 1.000_001 && j.abs() <= l.jerk * 1.000_001);
                }
                let (ps, v, _, _) = p.at_time(t_end);
                assert_eq!(ps, s);
                assert!((v - v1).abs() <= 1e-6 * l.velocity.max(1.0), "{v} vs {v1}");
            }
            Err(ProfileError::Unreachable { needed, distance }) => assert!(needed > distance),
            Err(e) => panic!("{e}"),
        }
    }
}
