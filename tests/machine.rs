//! Machine definitions and kinematics: round trips over thousands of random orientations
//! (fixed seed), limits, continuity, the singularity, C unwinding, and the Can (2010) thesis
//! post-processor formulas (digest seed-000 §2.13) as an independent reference.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::{DMat3, DVec3};
use talas::machine::{Machine, MachineError, MachineJoints, ToolPose};

/// xorshift64* with a fixed seed.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

/// Unit vector with tilt `t` from +Z and azimuth `phi`.
fn dir(t: f64, phi: f64) -> DVec3 {
    DVec3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos())
}

/// Angle between unit vectors, accurate for tiny angles.
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

fn within_limits(m: &Machine, j: &MachineJoints) {
    let names = ['X', 'Y', 'Z'];
    for (n, v) in names.iter().zip(j.xyz.to_array()) {
        let a = m.axis(*n).unwrap();
        assert!(v >= a.min - 1e-9 && v <= a.max + 1e-9, "{n} = {v}");
    }
    let (t, c) = m.rotary_names().unwrap();
    let (ta, ca) = (m.axis(t).unwrap(), m.axis(c).unwrap());
    assert!(ta.contains(j.tilt_rad), "{t} = {}", j.tilt_rad.to_degrees());
    assert!(
        ca.contains(j.rotary_rad),
        "{c} = {}",
        j.rotary_rad.to_degrees()
    );
}

#[test]
fn builtin_machines_load() {
    assert_eq!(
        Machine::builtin_names(),
        vec!["mill-3axis", "trt-ac", "trt-bc"]
    );
    let ac = Machine::builtin("trt-ac").unwrap();
    let a = ac.axis('A').unwrap();
    assert!(
        (a.min - (-120f64).to_radians()).abs() < 1e-15
            && (a.max - 30f64.to_radians()).abs() < 1e-15
    );
    let c = ac.axis('C').unwrap();
    assert!((c.max - TAU).abs() < 1e-12 && (c.min + TAU).abs() < 1e-12);
    assert_eq!(ac.tilt_offset_mm, DVec3::new(0.0, 0.0, -150.0));
    assert_eq!(ac.rotary_names(), Some(('A', 'C')));
    assert_eq!(
        Machine::builtin("trt-bc").unwrap().rotary_names(),
        Some(('B', 'C'))
    );
    assert_eq!(Machine::builtin("mill-3axis").unwrap().rotary_names(), None);
    assert!(matches!(
        Machine::builtin("nope"),
        Err(MachineError::Unknown(_))
    ));
    // The files on disk are the embedded ones, and load by path too.
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/machines");
    for name in Machine::builtin_names() {
        let from_file = Machine::resolve(&format!("{dir}/{name}.json")).unwrap();
        assert_eq!(from_file, Machine::builtin(name).unwrap());
    }
    assert!(matches!(
        Machine::resolve("/nonexistent/m.json"),
        Err(MachineError::Io { .. })
    ));
}

#[test]
fn bad_files_are_errors() {
    let ok = include_str!("../assets/machines/trt-ac.json");
    assert!(matches!(
        Machine::from_json("{"),
        Err(MachineError::Parse(_))
    ));
    let swapped = ok.replace("\"min\": -120, \"max\": 30", "\"min\": 30, \"max\": -120");
    assert!(
        matches!(Machine::from_json(&swapped), Err(MachineError::Invalid(m)) if m.contains("A"))
    );
    let no_c = ok.replace("\"name\": \"C\"", "\"name\": \"B\"");
    assert!(matches!(
        Machine::from_json(&no_c),
        Err(MachineError::Invalid(_))
    ));
    let dir0 = ok.replace(
        "\"direction\": -1 },\n    { \"name\": \"C\"",
        "\"direction\": 0 },\n    { \"name\": \"C\"",
    );
    assert!(matches!(
        Machine::from_json(&dir0),
        Err(MachineError::Invalid(_))
    ));
    let zero_v = ok.replacen("\"velocity\": 833", "\"velocity\": 0", 1);
    assert!(matches!(
        Machine::from_json(&zero_v),
        Err(MachineError::Invalid(_))
    ));
}

/// forward(inverse(pose)) == pose over thousands of random orientations in the reachable cone,
/// near and away from the singularity; limits respected; no NaN.
#[test]
fn round_trip_random_orientations() {
    let mut rng = Rng(0x5EED_0001);
    for (name, max_tilt) in [("trt-ac", 120f64), ("trt-bc", 110f64)] {
        let m = Machine::builtin(name).unwrap();
        let mut worst_tip: f64 = 0.0;
        let mut worst_axis: f64 = 0.0;
        for i in 0..6000 {
            let tilt = match i % 3 {
                0 => rng.range(0.0, max_tilt.to_radians() - 1e-9),
                1 => rng.range(0.0, 1e-6) * if i % 2 == 0 { 1.0 } else { 1e-6 },
                _ => {
                    if i % 4 == 0 {
                        0.0
                    } else {
                        rng.range(0.0, 0.05)
                    }
                }
            };
            let axis = dir(tilt, rng.range(-PI, PI));
            let tip = DVec3::new(
                rng.range(-80.0, 80.0),
                rng.range(-80.0, 80.0),
                rng.range(-40.0, 60.0),
            );
            let prev = MachineJoints {
                xyz: DVec3::ZERO,
                tilt_rad: rng.range(-0.5, 0.5),
                rotary_rad: rng.range(-3.0, 3.0),
            };
            let pose = ToolPose { tip, axis };
            let j = m
                .inverse(&pose, &prev)
                .unwrap_or_else(|e| panic!("{name} {i}: {e}"));
            assert!(j.xyz.is_finite() && j.tilt_rad.is_finite() && j.rotary_rad.is_finite());
            within_limits(&m, &j);
            let back = m.forward(&j);
            worst_tip = worst_tip.max(back.tip.distance(tip));
            worst_axis = worst_axis.max(angle(back.axis, axis));
            // At the singularity C is kept.
            if tilt == 0.0 {
                assert_eq!(j.rotary_rad, prev.rotary_rad);
            }
            // Least rotary travel: no other candidate is closer.
            let cost = |c: &MachineJoints| {
                (c.tilt_rad - prev.tilt_rad).abs() + (c.rotary_rad - prev.rotary_rad).abs()
            };
            for c in m.inverse_candidates(&pose, &prev).unwrap() {
                assert!(cost(&j) <= cost(&c) + 1e-12);
            }
        }
        assert!(worst_tip < 1e-9, "{name}: tip error {worst_tip} mm");
        assert!(worst_axis < 1e-12, "{name}: axis error {worst_axis} rad");
    }
}

/// The thesis post-processor (digest seed-000 §2.13), an independent closed form:
/// `R = R_x(a)·R_z(c) = [[cos c, −sin c, 0],[cos a sin c, cos a cos c, −sin a],
/// [sin a sin c, sin a cos c, cos a]]`, `n = (sin a sin c, sin a cos c, cos a)`,
/// `x' = x + Δx; y' = y + Δy; z' = l_p − Δz + z` with DELTA X = 125, DELTA Y = 60,
/// LENGTH PIVOT l_p = 150 (no Δz), `[X Y Z]ᵀ = R·[x' y' z']ᵀ` (the column form), and NC output
/// `A = −a, C = −c`. In Talas the part sits on the table 125/60 mm off the C axis (a fixture
/// offset), and X Y Z are measured from the machine origin on the table top, so the thesis's
/// pivot-relative X Y Z are Talas's minus the tilt-axis point (0, 0, −150).
#[test]
fn reproduces_the_thesis_post_processor() {
    let m = Machine::builtin("trt-ac").unwrap();
    let mut rng = Rng(0x7E515);
    for _ in 0..2000 {
        let a = rng.range(-30f64.to_radians(), 120f64.to_radians());
        let c = rng.range(-PI, PI);
        let p = DVec3::new(
            rng.range(-50.0, 50.0),
            rng.range(-50.0, 50.0),
            rng.range(0.0, 40.0),
        );
        let r = DMat3::from_cols_array_2d(&[
            [c.cos(), a.cos() * c.sin(), a.sin() * c.sin()],
            [-c.sin(), a.cos() * c.cos(), a.sin() * c.cos()],
            [0.0, -a.sin(), a.cos()],
        ]); // columns of the printed row-major matrix
        let n = DVec3::new(a.sin() * c.sin(), a.sin() * c.cos(), a.cos());
        let expect_xyz = r * (p + DVec3::new(125.0, 60.0, 150.0));
        let prev = MachineJoints {
            xyz: DVec3::ZERO,
            tilt_rad: -a,
            rotary_rad: -c,
        };
        let pose = ToolPose {
            tip: p + DVec3::new(125.0, 60.0, 0.0),
            axis: n,
        };
        let j = m.inverse(&pose, &prev).unwrap();
        assert!((j.tilt_rad - (-a)).abs() < 1e-12, "A = -a");
        assert!(
            ((j.rotary_rad + c + PI).rem_euclid(TAU) - PI).abs() < 1e-12,
            "C = -c"
        );
        let got = j.xyz - DVec3::new(0.0, 0.0, -150.0);
        assert!(got.distance(expect_xyz) < 1e-9, "{got} vs {expect_xyz}");
        // R·n = e_z: the thesis's orientation condition.
        assert!((r * n - DVec3::Z).length() < 1e-12);
    }
}

/// Smooth paths (great-circle arcs between random axes, 0.5° steps): no rotary jump > 180°
/// between consecutive poses, limits respected; a path straight through the singularity keeps C.
#[test]
fn continuity_along_smooth_paths() {
    let mut rng = Rng(0xC0_17_1A);
    for name in ["trt-ac", "trt-bc"] {
        let m = Machine::builtin(name).unwrap();
        let mut worst: f64 = 0.0;
        for _ in 0..150 {
            let a0 = dir(rng.range(0.0, 85f64.to_radians()), rng.range(-PI, PI));
            let a1 = dir(rng.range(0.0, 85f64.to_radians()), rng.range(-PI, PI));
            let steps = (angle(a0, a1) / 0.5f64.to_radians()).ceil().max(1.0) as usize;
            let mut prev = MachineJoints::default();
            for k in 0..=steps {
                let t = k as f64 / steps as f64;
                let w = angle(a0, a1);
                let axis = if w < 1e-12 {
                    a0
                } else {
                    (a0 * ((1.0 - t) * w).sin() + a1 * (t * w).sin()) / w.sin()
                };
                let tip = DVec3::new(10.0 * t, -5.0, 3.0);
                let j = m.inverse(&ToolPose { tip, axis }, &prev).unwrap();
                within_limits(&m, &j);
                if k > 0 {
                    worst = worst
                        .max((j.rotary_rad - prev.rotary_rad).abs())
                        .max((j.tilt_rad - prev.tilt_rad).abs());
                }
                prev = j;
            }
        }
        assert!(
            worst <= PI + 1e-9,
            "{name}: rotary jump {} deg",
            worst.to_degrees()
        );
    }
    // Through the pole in the YZ plane on the A/C machine: A changes sign, C stays put.
    let m = Machine::builtin("trt-ac").unwrap();
    let mut prev = MachineJoints::default();
    for k in 0..=40 {
        let t = (20.0 - k as f64) * 1f64.to_radians();
        let axis = DVec3::new(0.0, t.sin(), t.cos());
        let j = m
            .inverse(
                &ToolPose {
                    tip: DVec3::ZERO,
                    axis,
                },
                &prev,
            )
            .unwrap();
        assert_eq!(j.rotary_rad, 0.0, "C kept at step {k}");
        assert!((j.tilt_rad - (-t)).abs() < 1e-12);
        prev = j;
    }
}

#[test]
fn singularity_unwinding_and_unreachable() {
    let m = Machine::builtin("trt-ac").unwrap();
    let prev = MachineJoints {
        xyz: DVec3::ZERO,
        tilt_rad: -0.2,
        rotary_rad: 1.234,
    };
    let j = m
        .inverse(
            &ToolPose {
                tip: DVec3::new(1.0, 2.0, 3.0),
                axis: DVec3::Z,
            },
            &prev,
        )
        .unwrap();
    assert_eq!((j.tilt_rad, j.rotary_rad), (0.0, 1.234));
    // C follows a spinning axis continuously until its +360° limit, then unwinds by one turn.
    let mut prev = MachineJoints::default();
    let mut jumps = 0;
    for k in 0..=600 {
        let phi = -(k as f64).to_radians(); // the table angle c grows, so C = −c... decreases
        let j = m
            .inverse(
                &ToolPose {
                    tip: DVec3::ZERO,
                    axis: dir(FRAC_PI_2 * 0.5, phi),
                },
                &prev,
            )
            .unwrap();
        within_limits(&m, &j);
        if k > 0 && (j.rotary_rad - prev.rotary_rad).abs() > 0.5 {
            jumps += 1;
            assert!(((j.rotary_rad - prev.rotary_rad).abs() - TAU).abs() < 0.1);
        }
        prev = j;
    }
    assert_eq!(
        jumps, 1,
        "C starts at −90°: one unwinding at −360° within 600°"
    );
    // Beyond the A limit, a zero axis, NaN, a tilted axis on the 3-axis mill.
    let far = ToolPose {
        tip: DVec3::ZERO,
        axis: dir(150f64.to_radians(), 0.3),
    };
    assert!(matches!(
        m.inverse(&far, &MachineJoints::default()),
        Err(MachineError::Unreachable(_))
    ));
    let zero = ToolPose {
        tip: DVec3::ZERO,
        axis: DVec3::ZERO,
    };
    assert!(matches!(
        m.inverse(&zero, &MachineJoints::default()),
        Err(MachineError::BadPose(_))
    ));
    let nan = ToolPose {
        tip: DVec3::new(f64::NAN, 0.0, 0.0),
        axis: DVec3::Z,
    };
    assert!(matches!(
        m.inverse(&nan, &MachineJoints::default()),
        Err(MachineError::BadPose(_))
    ));
    let outside = ToolPose {
        tip: DVec3::new(5000.0, 0.0, 0.0),
        axis: DVec3::Z,
    };
    assert!(matches!(
        m.inverse(&outside, &MachineJoints::default()),
        Err(MachineError::Unreachable(_))
    ));
    let mill = Machine::builtin("mill-3axis").unwrap();
    let tilted = ToolPose {
        tip: DVec3::ZERO,
        axis: dir(0.1, 0.0),
    };
    assert!(matches!(
        mill.inverse(&tilted, &MachineJoints::default()),
        Err(MachineError::Unreachable(_))
    ));
    let pose = ToolPose {
        tip: DVec3::new(1.0, 2.0, -3.0),
        axis: DVec3::Z,
    };
    let j = mill.inverse(&pose, &MachineJoints::default()).unwrap();
    assert_eq!(mill.forward(&j), pose);
}

/// The B/C machine with its X/Z pivot offset, checked against a hand-built chain
/// T(q_t)·R_y(−B)·T(−q_t)·R_z(−C) (table directions −1, C centre at the origin).
#[test]
fn bc_forward_matches_the_chain() {
    let m = Machine::builtin("trt-bc").unwrap();
    let qt = DVec3::new(20.0, 0.0, -100.0);
    let j = MachineJoints {
        xyz: DVec3::new(30.0, -20.0, 10.0),
        tilt_rad: 0.7,
        rotary_rad: -2.1,
    };
    let machine_from_table =
        |p: DVec3| qt + DMat3::from_rotation_y(-0.7) * (DMat3::from_rotation_z(2.1) * p - qt);
    let pose = m.forward(&j);
    assert!(machine_from_table(pose.tip).distance(j.xyz) < 1e-12);
    let spindle = machine_from_table(pose.tip + pose.axis) - machine_from_table(pose.tip);
    assert!(spindle.distance(DVec3::Z) < 1e-12);
}

/// Linearisation: with joints interpolated linearly between the returned poses, the tip stays
/// within the tolerance of the intended straight line (checked with 200 samples per sub-move,
/// against the line itself); tighter tolerances need more poses; a pure translation needs none.
#[test]
fn linearised_moves_stay_within_tolerance() {
    use talas::machine::lerp_joints;
    let m = Machine::builtin("trt-ac").unwrap();
    let from = ToolPose {
        tip: DVec3::new(50.0, 0.0, 10.0),
        axis: DVec3::Z,
    };
    let to = ToolPose {
        tip: DVec3::new(50.0, 40.0, 10.0),
        axis: dir(60f64.to_radians(), 0.5),
    };
    let line_distance = |p: DVec3| {
        let d = (to.tip - from.tip).normalize();
        let v = p - from.tip;
        (v - d * v.dot(d)).length()
    };
    let mut counts = Vec::new();
    for tol in [0.1, 0.01, 0.001] {
        let joints = m
            .linearise(&from, &to, &MachineJoints::default(), tol)
            .unwrap();
        assert!(m.forward(&joints[0]).tip.distance(from.tip) < 1e-9);
        let end = m.forward(joints.last().unwrap());
        assert!(end.tip.distance(to.tip) < 1e-9 && angle(end.axis, to.axis) < 1e-12);
        let mut worst: f64 = 0.0;
        for w in joints.windows(2) {
            within_limits(&m, &w[1]);
            for k in 0..=200 {
                let tip = m.forward(&lerp_joints(&w[0], &w[1], k as f64 / 200.0)).tip;
                worst = worst.max(line_distance(tip));
            }
        }
        assert!(worst <= tol * 1.05, "tol {tol}: deviation {worst}");
        counts.push(joints.len());
    }
    assert!(counts[0] < counts[1] && counts[1] < counts[2], "{counts:?}");
    // Without linearisation the single move would leave the line by far more.
    let one = m
        .linearise(&from, &to, &MachineJoints::default(), 1e3)
        .unwrap();
    assert_eq!(one.len(), 2);
    let mid = m.forward(&lerp_joints(&one[0], &one[1], 0.5)).tip;
    assert!(line_distance(mid) > 1.0, "{}", line_distance(mid));
    let mill = Machine::builtin("mill-3axis").unwrap();
    let a = ToolPose {
        tip: DVec3::ZERO,
        axis: DVec3::Z,
    };
    let b = ToolPose {
        tip: DVec3::new(100.0, 50.0, -20.0),
        axis: DVec3::Z,
    };
    assert_eq!(
        mill.linearise(&a, &b, &MachineJoints::default(), 1e-6)
            .unwrap()
            .len(),
        2
    );
    assert!(m.linearise(&a, &b, &MachineJoints::default(), 0.0).is_err());
}
