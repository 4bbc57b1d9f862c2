//! Checks against closed forms: scallop of a ball between parallel passes on a plane and on a
//! sphere, bull-nose scallop on a plane, lifted and lowered poses, a flat end mill gouging a
//! concave cylinder (depth from a 1D root, lead from asin(r/ρ)), curvature scans of sphere,
//! cylinder and torus, and curvatures against Open CASCADE's samples.

mod common;

use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::path::Path;

use glam::{DVec2, DVec3};
use talas::checks::oracle::surface::{VerifyOptions, verify};
use talas::checks::{
    FacePatch, GougeKind, GougeOptions, analyze, check_path, check_pose, curvature_at,
    curvature_margin, effective_radius, min_lead_for_radius, pose_from_contact, required_lead,
};
use talas::geometry::Interval;
use talas::geometry::frame::Frame;
use talas::geometry::surface::{Cylinder, ParamRect, Plane, Sphere, SurfaceGeom, Torus};
use talas::toolpath::{MoveKind, Pose};
use talas::tools::{Cutter, CutterKind};

fn rect(u0: f64, u1: f64, v0: f64, v1: f64) -> ParamRect {
    ParamRect {
        u: Interval::new(u0, u1),
        v: Interval::new(v0, v1),
    }
}

fn cut(tip: DVec3, axis: DVec3) -> Pose {
    Pose::new(MoveKind::Cut, tip, axis, 1000.0)
}

fn rapid(tip: DVec3, axis: DVec3) -> Pose {
    Pose::new(MoveKind::Rapid, tip, axis, 0.0)
}

/// Zig-zag passes along x at y = k·ω (k = 0..passes), tip at height z, x from −5 to 25.
fn plane_passes(omega: f64, passes: usize, z: f64, step: f64) -> Vec<Pose> {
    let mut poses = Vec::new();
    let n = (30.0 / step).round() as usize;
    for k in 0..passes {
        let y = k as f64 * omega;
        poses.push(rapid(DVec3::new(-5.0, y, 10.0), DVec3::Z));
        for i in 0..=n {
            poses.push(cut(DVec3::new(-5.0 + i as f64 * step, y, z), DVec3::Z));
        }
        poses.push(rapid(DVec3::new(25.0, y, 10.0), DVec3::Z));
    }
    poses
}

fn plane() -> SurfaceGeom {
    SurfaceGeom::Plane(Plane {
        frame: Frame::WORLD,
    })
}

fn opts(n: usize, margin: f64) -> VerifyOptions {
    VerifyOptions {
        nu: n,
        nv: n,
        margin_mm: margin,
        ..VerifyOptions::default()
    }
}

#[test]
fn ball_scallop_on_a_plane_is_the_closed_form() {
    let s = plane();
    let patch = FacePatch::new(&s, rect(0.0, 20.0, 0.0, 20.0), false).expect("patch");
    let ball = Cutter::new(CutterKind::Ball, 6.0).expect("tool");
    let omega = 1.0;
    let poses = plane_passes(omega, 21, 0.0, 1.0);
    // 81 × 81 samples: every 0.25 mm, so the midlines y = (k + ½)ω are sampled.
    let r = verify(&patch, &ball, &poses, &opts(81, 0.5)).expect("verify");
    let want = 3.0 - (9.0 - 0.25_f64).sqrt();
    assert!(
        (r.max_remaining_mm - want).abs() < 1e-9,
        "{} vs {want}",
        r.max_remaining_mm
    );
    assert!(r.max_penetration_mm < 1e-9, "{}", r.max_penetration_mm);
    assert_eq!(r.uncovered, 0);
    assert!(r.counted > 5000);
    let at = r.max_remaining_at.expect("located");
    let frac = (at.point.y / omega).fract();
    assert!((frac - 0.5).abs() < 1e-9, "scallop at y = {}", at.point.y);

    // The whole path lifted by 0.01 mm: remaining at the pass centres 0.01, maximum + 0.01.
    let lifted = plane_passes(omega, 21, 0.01, 1.0);
    let r = verify(&patch, &ball, &lifted, &opts(81, 0.5)).expect("verify");
    assert!((r.max_remaining_mm - (want + 0.01)).abs() < 1e-9);
    let mut o = opts(81, 0.5);
    o.threshold_mm = 0.01 + 1e-9;
    let r = verify(&patch, &ball, &lifted, &o).expect("verify");
    assert!(
        r.within_threshold > 0.0,
        "samples under the pass centres sit at 0.01"
    );
    assert!(r.max_penetration_mm == 0.0);
}

#[test]
fn one_lowered_pose_shows_its_penetration() {
    let s = plane();
    let patch = FacePatch::new(&s, rect(0.0, 20.0, 0.0, 20.0), false).expect("patch");
    let mut poses = plane_passes(1.0, 21, 0.0, 1.0);
    // Pose at x = 10 on the pass y = 10: lower it by 0.01 mm.
    let k = poses
        .iter()
        .position(|p| p.kind == MoveKind::Cut && p.tip.distance(DVec3::new(10.0, 10.0, 0.0)) < 1e-9)
        .expect("pose");
    poses[k].tip.z -= 0.01;
    for (kind, tol) in [
        (CutterKind::Ball, 1e-9),
        (CutterKind::BullNose { corner_radius: 1.0 }, 1e-7),
        (CutterKind::Flat, 1e-7),
    ] {
        let c = Cutter::new(kind, 6.0).expect("tool");
        // 17 × 17 samples on [8, 12]², every 0.25 mm: (10, 10) is one of them.
        let o = VerifyOptions {
            rect: Some(rect(8.0, 12.0, 8.0, 12.0)),
            ..opts(17, 0.0)
        };
        let r = verify(&patch, &c, &poses, &o).expect("verify");
        assert!(
            (r.max_penetration_mm - 0.01).abs() < tol,
            "{kind:?}: {}",
            r.max_penetration_mm
        );
        let at = r.max_penetration_at.expect("located");
        assert!(
            at.pose == k || at.pose == k + 1,
            "{kind:?} pose {}",
            at.pose
        );
        assert!(at.point.distance(DVec3::new(10.0, 10.0, 0.0)) < 3.0);
    }
}

#[test]
fn bull_nose_scallop_on_a_plane_is_the_closed_form() {
    let s = plane();
    let patch = FacePatch::new(&s, rect(0.0, 20.0, 0.0, 20.0), false).expect("patch");
    // d = 6, r_c = 2: flat radius 1; passes 4 mm apart leave h = r_c − √(r_c² − (ω/2 − R_f)²).
    let c = Cutter::new(CutterKind::BullNose { corner_radius: 2.0 }, 6.0).expect("tool");
    let omega = 4.0;
    let poses = plane_passes(omega, 6, 0.0, 2.0);
    let mut o = opts(41, 0.5);
    o.max_height_mm = Some(3.0);
    let r = verify(&patch, &c, &poses, &o).expect("verify");
    let want = 2.0 - (4.0 - 1.0_f64).sqrt();
    assert!(
        (r.max_remaining_mm - want).abs() < 1e-7,
        "{} vs {want}",
        r.max_remaining_mm
    );
    assert!(r.max_penetration_mm < 1e-9);
}

#[test]
fn ball_scallop_on_a_sphere_is_the_closed_form() {
    // Convex sphere ρ = 50; 5-axis ball r = 3 along meridians Δφ apart, axis on the normal.
    let (rho, r) = (50.0, 3.0);
    let s = SurfaceGeom::Sphere(Sphere {
        frame: Frame::WORLD,
        radius: rho,
    });
    let dphi = 0.03;
    let dlat = 0.0005;
    let mut poses = Vec::new();
    for k in 0..9 {
        let phi = k as f64 * dphi;
        let e = |lat: f64| DVec3::new(lat.cos() * phi.cos(), lat.cos() * phi.sin(), lat.sin());
        poses.push(rapid(e(-0.06) * (rho + 20.0), e(-0.06)));
        for i in 0..=240 {
            let lat = -0.06 + i as f64 * dlat;
            poses.push(cut(e(lat) * rho, e(lat)));
        }
    }
    // Samples on the equator band, u from φ = Δφ to 7Δφ (every Δφ/8), v = 0 included.
    let patch = FacePatch::new(&s, rect(dphi, 7.0 * dphi, -0.01, 0.01), false).expect("patch");
    let mut o = opts(49, 0.0);
    o.nv = 21;
    let rep = verify(
        &patch,
        &Cutter::new(CutterKind::Ball, 2.0 * r).expect("tool"),
        &poses,
        &o,
    )
    .expect("verify");
    let c = rho + r;
    let half = 0.5 * dphi;
    let want = c * half.cos() - (r * r - (c * half.sin()).powi(2)).sqrt() - rho;
    // Chord error of the tip polyline: ρ·Δlat²/8.
    let chord = rho * dlat * dlat / 8.0;
    assert!(
        (rep.max_remaining_mm - want).abs() < chord + 1e-8,
        "{} vs {want} (chord {chord})",
        rep.max_remaining_mm
    );
    assert!(rep.max_penetration_mm < chord + 1e-9);
}

fn concave_cylinder() -> SurfaceGeom {
    // Radius 20 around the x axis; u = 0 at −z (frame x = −Z), so u near 0 is the bottom.
    SurfaceGeom::Cylinder(Cylinder {
        frame: Frame::from_axis_ref(DVec3::ZERO, DVec3::X, Some(-DVec3::Z)).expect("frame"),
        radius: 20.0,
    })
}

#[test]
fn flat_end_mill_gouging_a_concave_cylinder() {
    let s = concave_cylinder();
    let patch = FacePatch::new(&s, rect(-1.0, 1.0, -20.0, 20.0), true).expect("patch");
    let flat = Cutter::new(CutterKind::Flat, 10.0).expect("tool");
    let bottom = DVec3::new(0.0, 0.0, -20.0);
    // The tool-side normal at the bottom points up (+Z) to the cylinder's axis.
    let (p, n) = patch.point_normal(DVec2::ZERO).expect("normal");
    assert!(p.distance(bottom) < 1e-12 && n.distance(DVec3::Z) < 1e-12);
    let pose = cut(bottom, DVec3::Z).with_contact(bottom, talas::toolpath::ContactKind::Bottom);
    let g = check_pose(&patch, &flat, &pose, 7, &GougeOptions::default()).expect("gouge");
    // The rim at y = ±5 lies √(5² + 20²) − 20 outside the cylinder: the deepest tool point.
    let want = 425.0_f64.sqrt() - 20.0;
    assert!((g.depth_mm - want).abs() < 1e-7, "{} vs {want}", g.depth_mm);
    assert_eq!(g.pose, 7);
    assert!(matches!(g.kind, GougeKind::Rear | GougeKind::Local));

    // A path of such poses along the generator: every pose gouges, by the same depth.
    let poses: Vec<Pose> = (0..6)
        .map(|i| cut(DVec3::new(f64::from(i) - 2.5, 0.0, -20.0), DVec3::Z))
        .collect();
    let o = GougeOptions {
        fix_leads: false,
        ..GougeOptions::default()
    };
    let rep = check_path(&patch, &flat, &poses, &o).expect("report");
    assert_eq!(rep.gouges.len(), 6);
    assert!((rep.max_depth_mm - want).abs() < 1e-7);

    // The independent verification agrees.
    let vr = verify(
        &patch,
        &flat,
        &poses,
        &VerifyOptions {
            nu: 41,
            nv: 5,
            rect: Some(rect(0.15, 0.35, -2.0, 2.0)),
            ..VerifyOptions::default()
        },
    )
    .expect("verify");
    // Around the rim (y = 20 sin u ≈ 4.85 at u ≈ 0.245) samples every 0.1 mm across the feed;
    // the depth falls off the rim at slope ≤ 1: within 0.05 mm.
    assert!(
        vr.max_penetration_mm <= want + 1e-7,
        "{}",
        vr.max_penetration_mm
    );
    assert!(
        vr.max_penetration_mm > want - 0.05,
        "{}",
        vr.max_penetration_mm
    );

    // Feed along the generator: the lead that clears it is asin(r/ρ) = 14.4775°.
    // Near the exact lead the depth grows as ~9.4 mm/rad²·ε², so a 1e-6 mm tolerance puts the
    // bisection within ~3e-4 rad of it.
    let fine = GougeOptions {
        tolerance_mm: 1e-6,
        ..GougeOptions::default()
    };
    let lead = required_lead(&patch, &flat, DVec2::ZERO, DVec3::X, 0.0, 0.0, &fine)
        .expect("some lead clears");
    let exact = min_lead_for_radius(&flat, 20.0).expect("fits");
    assert!((exact.to_degrees() - 14.4775).abs() < 1e-4);
    assert!(
        (lead - exact).abs() < 0.05_f64.to_radians(),
        "{} vs {}",
        lead.to_degrees(),
        exact.to_degrees()
    );
}

#[test]
fn curvature_scans_of_sphere_cylinder_and_torus() {
    let sphere = SurfaceGeom::Sphere(Sphere {
        frame: Frame::WORLD,
        radius: 10.0,
    });
    let p = FacePatch::new(&sphere, rect(0.0, PI, -1.0, 1.0), false).expect("patch");
    let a = analyze(&p, 21).expect("scan");
    let conv = a.min_convex_principal.expect("convex");
    assert!((conv.radius_mm - 10.0).abs() < 1e-9);
    assert!(a.min_concave_principal.is_none());
    // Seen from inside, the same sphere is concave.
    let a = analyze(&FacePatch { flip: true, ..p }, 21).expect("scan");
    assert!((a.min_concave_u.expect("concave").radius_mm - 10.0).abs() < 1e-9);

    let cyl = SurfaceGeom::Cylinder(Cylinder {
        frame: Frame::WORLD,
        radius: 7.0,
    });
    let p = FacePatch::new(&cyl, rect(0.0, PI, 0.0, 10.0), false).expect("patch");
    let a = analyze(&p, 21).expect("scan");
    assert!((a.min_convex_u.expect("u").radius_mm - 7.0).abs() < 1e-9);
    assert!(a.min_convex_v.is_none() && a.min_concave_v.is_none());

    // Torus R = 20, r = 5: along v (tube) convex 5; along u convex 25 (outer equator) and
    // concave 15 (inner equator); principal: convex 5, concave 15.
    let torus = SurfaceGeom::Torus(Torus {
        frame: Frame::WORLD,
        major_radius: 20.0,
        minor_radius: 5.0,
    });
    let p = FacePatch::new(&torus, rect(0.0, TAU, 0.0, TAU), false).expect("patch");
    let a = analyze(&p, 17).expect("scan");
    let close = |x: Option<talas::checks::RadiusExtreme>, want: f64| {
        let x = x.expect("present");
        assert!(
            (x.radius_mm - want).abs() < 1e-6,
            "{} vs {want}",
            x.radius_mm
        );
        x
    };
    close(a.min_convex_v, 5.0);
    close(a.min_convex_u, 25.0);
    let inner = close(a.min_concave_u, 15.0);
    assert!((inner.uv.y - PI).abs() < 1e-4, "at v = {}", inner.uv.y);
    close(a.min_convex_principal, 5.0);
    close(a.min_concave_principal, 15.0);
    assert!(a.min_concave_v.is_none());

    // Per-point values against the closed form.
    let uvs: Vec<DVec2> = (0..10)
        .map(|i| DVec2::new(0.3, f64::from(i) * 0.6))
        .collect();
    for (uv, c) in uvs.iter().zip(curvature_at(&p, &uvs)) {
        let c = c.expect("regular");
        let k_par = -uv.y.cos() / (20.0 + 5.0 * uv.y.cos());
        let (lo, hi) = if k_par < -0.2 {
            (k_par, -0.2)
        } else {
            (-0.2, k_par)
        };
        assert!((c.k_min - lo).abs() < 1e-9 && (c.k_max - hi).abs() < 1e-9);
        assert!((c.gaussian - lo * hi).abs() < 1e-9);
        assert!((c.mean - 0.5 * (lo + hi)).abs() < 1e-9);
        let _ = FRAC_PI_2;
    }
}

fn occt_rows(name: &str) -> Vec<[f64; 10]> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    let text = std::fs::read_to_string(path).expect("samples");
    text.lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l
                .split(',')
                .map(|x| x.trim().parse().expect("number"))
                .collect();
            let mut row = [0.0; 10];
            row.copy_from_slice(&v);
            row
        })
        .collect()
}

#[test]
fn curvatures_agree_with_open_cascade() {
    for (stp, csv) in [
        ("bicubic-hills.stp", "bicubic-hills.samples.csv"),
        ("rational-trough.stp", "rational-trough.samples.csv"),
    ] {
        let part = talas::import::step::read_step(&common::data(stp)).expect("read");
        let face = part.faces.first().expect("one face");
        let patch = FacePatch::whole(&face.surface, false).expect("patch");
        let rows = occt_rows(csv);
        let uvs: Vec<DVec2> = rows.iter().map(|r| DVec2::new(r[0], r[1])).collect();
        let mut worst: f64 = 0.0;
        for (row, c) in rows.iter().zip(curvature_at(&patch, &uvs)) {
            let c = c.expect("regular");
            worst = worst
                .max((c.k_min - row[8]).abs())
                .max((c.k_max - row[9]).abs());
        }
        assert!(worst < 1e-6, "{stp}: {worst}");
    }
}

#[test]
fn leaning_flat_end_mill_rear_gouge_on_a_concave_cylinder() {
    // Cylinder ρ = 20 around the y axis, tool inside; feed along x (around the circle), so the
    // feed direction is concave and the cross-feed direction straight.
    let s = SurfaceGeom::Cylinder(Cylinder {
        frame: Frame::from_axis_ref(DVec3::ZERO, DVec3::Y, Some(-DVec3::Z)).expect("frame"),
        radius: 20.0,
    });
    let (rho, r) = (20.0, 5.0);
    // Here S_u × S_v points away from the axis: the tool side is the flipped one.
    let patch = FacePatch::new(&s, rect(-1.0, 1.0, -20.0, 20.0), true).expect("patch");
    let (cc, n) = patch.point_normal(DVec2::ZERO).expect("normal");
    assert!(n.distance(DVec3::Z) < 1e-12);
    let flat = Cutter::new(CutterKind::Flat, 2.0 * r).expect("tool");
    let feed = DVec3::X;
    let lead = 10f64.to_radians();
    let (tip, axis) = pose_from_contact(&flat, cc, n, feed, lead, 0.0).expect("pose");
    // Contact at the front edge: the lowest rim point in the feed direction is the contact.
    assert!((tip + (feed * lead.cos() - n * lead.sin()) * r).distance(cc) < 1e-12);
    let pose = cut(tip, axis).with_contact(cc, talas::toolpath::ContactKind::Corner);
    let g = check_pose(&patch, &flat, &pose, 0, &GougeOptions::default()).expect("gouge");
    assert_eq!(g.kind, GougeKind::Rear);
    // The heel (rim point 2r behind the contact along the tilted bottom) lies
    // √(4r² − 4ρr sin S + ρ²) − ρ outside the circle.
    let want = (4.0 * r * r - 4.0 * rho * r * lead.sin() + rho * rho).sqrt() - rho;
    assert!((g.depth_mm - want).abs() < 1e-7, "{} vs {want}", g.depth_mm);
    assert!(g.point.x < -9.0, "at the heel: {}", g.point);
    // The chord from the tangent point at angle S meets the circle at 2ρ sin S: clear once
    // 2r ≤ 2ρ sin S, i.e. S = asin(r/ρ).
    let fine = GougeOptions {
        tolerance_mm: 1e-6,
        ..GougeOptions::default()
    };
    let need = required_lead(&patch, &flat, DVec2::ZERO, feed, 0.0, 0.0, &fine).expect("lead");
    let exact = (r / rho).asin();
    assert!(
        (need - exact).abs() < 0.01_f64.to_radians(),
        "{} vs {}",
        need.to_degrees(),
        exact.to_degrees()
    );
    // A curvature check alone misses it: across the feed the surface is straight.
    let m = curvature_margin(&patch, &flat, DVec2::ZERO, axis).expect("margin");
    assert!(m >= 0.0, "{m}");
}

#[test]
fn local_gouge_margin_matches_the_effective_radius() {
    // Generator of the ρ = 20 cylinder along x, feed along it: across the feed the surface is
    // concave with radius 20, so a bull-nose d = 10, r_c = 2 needs R_f/sin S + r_c ≤ 20.
    let s = concave_cylinder();
    let patch = FacePatch::new(&s, rect(-1.0, 1.0, -20.0, 20.0), true).expect("patch");
    let (cc, n) = patch.point_normal(DVec2::ZERO).expect("normal");
    let bull = Cutter::new(CutterKind::BullNose { corner_radius: 2.0 }, 10.0).expect("tool");
    let exact = min_lead_for_radius(&bull, 20.0).expect("fits");
    assert!((effective_radius(&bull, exact).expect("torus") - 20.0).abs() < 1e-12);
    for (lead, sign) in [(exact - 0.01, -1.0), (exact + 0.01, 1.0)] {
        let (_, axis) = pose_from_contact(&bull, cc, n, DVec3::X, lead, 0.0).expect("pose");
        let m = curvature_margin(&patch, &bull, DVec2::ZERO, axis).expect("margin");
        // Across the feed: sin S/(R_f + r_c sin S) − 1/20.
        let want = lead.sin() / (3.0 + 2.0 * lead.sin()) - 0.05;
        assert!((m - want).abs() < 1e-12 && m * sign > 0.0, "{m} vs {want}");
    }
    // And the tool solid agrees: the smallest lead without penetration is that lead.
    let fine = GougeOptions {
        tolerance_mm: 1e-7,
        ..GougeOptions::default()
    };
    let need = required_lead(&patch, &bull, DVec2::ZERO, DVec3::X, 0.0, 0.0, &fine).expect("lead");
    assert!(
        (need - exact).abs() < 0.1_f64.to_radians(),
        "{} vs {}",
        need.to_degrees(),
        exact.to_degrees()
    );
}

#[test]
fn path_check_finds_only_the_lowered_pose() {
    let s = plane();
    let patch = FacePatch::new(&s, rect(-10.0, 30.0, -10.0, 30.0), false).expect("patch");
    let ball = Cutter::new(CutterKind::Ball, 6.0).expect("tool");
    let mut poses = plane_passes(1.0, 3, 0.0, 1.0);
    let o = GougeOptions::default();
    let clean = check_path(&patch, &ball, &poses, &o).expect("report");
    assert!(clean.gouges.is_empty(), "{:?}", clean.gouges.first());
    assert!(clean.placements > 1000);
    let k = poses
        .iter()
        .position(|p| p.tip.distance(DVec3::new(10.0, 1.0, 0.0)) < 1e-9)
        .expect("pose");
    poses[k].tip.z -= 0.01;
    let rep = check_path(&patch, &ball, &poses, &o).expect("report");
    // The moves into and out of the lowered pose gouge; the deepest is the pose itself.
    assert!(
        !rep.gouges.is_empty() && rep.gouges.len() <= 2,
        "{:?}",
        rep.gouges
    );
    assert!(
        (rep.max_depth_mm - 0.01).abs() < 1e-9,
        "{}",
        rep.max_depth_mm
    );
    let g = rep
        .gouges
        .iter()
        .find(|g| g.pose == k)
        .expect("at the pose");
    assert!((g.depth_mm - 0.01).abs() < 1e-9 && g.move_param == 1.0);
    assert!(
        g.point.distance(DVec3::new(10.0, 1.0, 0.0)) < 1e-4,
        "{}",
        g.point
    );
}

#[test]
fn rational_trough_has_the_tube_radius_across() {
    // tests/data/README.md: the inside of a tube R = 60 mm around a 300 mm ring. Across the
    // trough the radius is 60 everywhere: concave seen from inside the tube (the side opposite
    // to S_u × S_v here, as Open CASCADE's k_min = −1/60 says), convex from the other side.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/rational-trough.stp");
    let part = talas::import::step::read_step(&path).expect("read");
    let face = part.faces.first().expect("one face");
    let inside = FacePatch::whole(&face.surface, true).expect("patch");
    let a = analyze(&inside, 25).expect("scan");
    let c = a.min_concave_principal.expect("concave");
    assert!((c.radius_mm - 60.0).abs() < 1e-6, "{}", c.radius_mm);
    let outside = FacePatch::whole(&face.surface, false).expect("patch");
    let a = analyze(&outside, 25).expect("scan");
    let c = a.min_convex_principal.expect("convex");
    assert!((c.radius_mm - 60.0).abs() < 1e-6, "{}", c.radius_mm);
}
