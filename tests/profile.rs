//! The ball-electrode profile module against independent references: exact distances written
//! in `profile_common` (not the engine's), closed forms for the seed's normal cases, V notches,
//! sines and slots, and the failure reports of the 2D offset libraries.

mod profile_common;

use glam::DVec2;
use profile_common::{Rng, Seg, dist_to, is_simple, point_dist, seg, seg_dist, seg_point, segs};
use talas::profile::{ClPath, FlagKind, Profile, Side, Vertex, compute, max_gouge_free_radius};

fn profile_of(v: &[(f64, f64, f64)], closed: bool) -> Profile {
    Profile {
        vertices: v
            .iter()
            .map(|&(x, y, bulge)| Vertex { x, y, bulge })
            .collect(),
        closed,
    }
}

fn raw(p: &Profile) -> Vec<(f64, f64, f64)> {
    p.vertices.iter().map(|v| (v.x, v.y, v.bulge)).collect()
}

fn path_segs(paths: &[ClPath]) -> Vec<Seg> {
    let mut out = Vec::new();
    for p in paths {
        let v: Vec<(f64, f64, f64)> = p
            .vertices
            .iter()
            .map(|v| (v.centre.x, v.centre.y, v.bulge))
            .collect();
        if v.len() >= 2 {
            out.extend(segs(&v, p.closed));
        }
    }
    out
}

/// Every path vertex and 16 points per path element at distance R (to `tol`), and no path
/// element closer than R − `tol` to any profile element (exact element–element distance).
fn certify(profile: &Profile, paths: &[ClPath], r: f64, tol: f64) -> Result<(), String> {
    certify_worst(profile, paths, r, tol).map(|_| ())
}

/// [`certify`], returning the largest |distance − R| seen.
fn certify_worst(profile: &Profile, paths: &[ClPath], r: f64, tol: f64) -> Result<f64, String> {
    let prof = segs(&raw(profile), profile.closed);
    let mut worst: f64 = 0.0;
    for s in path_segs(paths) {
        for k in 0..=16 {
            let p = seg_point(&s, f64::from(k) / 16.0);
            let d = dist_to(&prof, p);
            worst = worst.max((d - r).abs());
            if (d - r).abs() > tol {
                return Err(format!("path point {p:?} at distance {d}, R = {r}"));
            }
        }
        for e in &prof {
            let d = seg_dist(&s, e);
            if d < r - tol {
                return Err(format!("path element {s:?} comes to {d} of {e:?}, R = {r}"));
            }
        }
    }
    Ok(worst)
}

/// Largest distance from the vertices and midpoints of `a` to the path `b`.
fn one_sided(a: &[ClPath], b: &[Seg]) -> f64 {
    let mut worst: f64 = 0.0;
    for s in path_segs(a) {
        for t in [0.0, 0.5, 1.0] {
            worst = worst.max(dist_to(b, seg_point(&s, t)));
        }
    }
    worst
}

/// Paths equal within `tol`: every vertex and element midpoint of each lies on the other.
/// Returns how far apart they are.
fn same_path(a: &[ClPath], b: &[ClPath], tol: f64) -> Result<f64, String> {
    let (sa, sb) = (path_segs(a), path_segs(b));
    let d = one_sided(a, &sb).max(one_sided(b, &sa));
    if d > tol {
        Err(format!("paths differ by {d}"))
    } else {
        Ok(d)
    }
}

fn random_function(rng: &mut Rng) -> Profile {
    let n = 4 + rng.below(12);
    let mut x = 0.0;
    let arcs = rng.unit() < 0.5;
    let mut v = Vec::new();
    for _ in 0..n {
        let y = rng.range(-5.0, 5.0);
        let b = if arcs { rng.range(-0.2, 0.2) } else { 0.0 };
        v.push((x, y, b));
        x += rng.range(0.5, 4.0);
    }
    profile_of(&v, false)
}

fn random_contour(rng: &mut Rng) -> Profile {
    let n = 3 + rng.below(12);
    let mut angles: Vec<f64> = (0..n)
        .map(|_| rng.range(0.0, std::f64::consts::TAU))
        .collect();
    angles.sort_by(f64::total_cmp);
    let arcs = rng.unit() < 0.5;
    let v: Vec<(f64, f64, f64)> = angles
        .iter()
        .map(|a| {
            let r = rng.range(4.0, 10.0);
            let b = if arcs { rng.range(-0.25, 0.25) } else { 0.0 };
            (r * a.cos(), r * a.sin(), b)
        })
        .collect();
    profile_of(&v, true)
}

fn acceptable(p: &Profile) -> bool {
    let s = segs(&raw(p), p.closed);
    // No near-duplicate angles (tiny elements are tested on their own below).
    s.iter().all(|e| point_dist(e, seg_point(e, 0.0)) == 0.0)
        && p.elements().iter().all(|e| e.chord_length() > 0.2)
        && is_simple(&s, p.closed)
        && p.validate("<test>").is_ok()
}

fn restarted(p: &Profile, k: usize) -> Profile {
    let mut v = p.vertices.clone();
    let n = v.len();
    v.rotate_left(k % n);
    Profile {
        vertices: v,
        closed: p.closed,
    }
}

fn transformed(p: &Profile, scale: f64, shift: DVec2) -> Profile {
    let mut q = p.clone();
    for v in &mut q.vertices {
        v.x = v.x * scale + shift.x;
        v.y = v.y * scale + shift.y;
    }
    q
}

fn transformed_paths(paths: &[ClPath], scale: f64, shift: DVec2) -> Vec<ClPath> {
    let mut out = paths.to_vec();
    for p in &mut out {
        for v in &mut p.vertices {
            v.centre = v.centre * scale + shift;
        }
    }
    out
}

/// ≥ 1000 seeded random profiles (functions of x and closed contours, lines and arcs, sizes
/// of about 5 to 45 mm): the path is at distance R to 1e-9 mm and never closer, and the same
/// to 1e-9 mm when the profile is reversed or restarted (1e-9 of the size plus the shift when
/// moved, 1e-9 mm times the factor when scaled). The worst errors seen are printed.
#[test]
fn random_profiles_are_offset_exactly_and_invariantly() {
    let mut rng = Rng(0x5EED_0004);
    let mut done = 0;
    let mut tries = 0;
    let mut worst_rel: f64 = 0.0;
    let mut above_1e9 = 0;
    let mut worst_same: f64 = 0.0;
    while done < 1000 {
        tries += 1;
        assert!(tries < 20_000, "generator rejects too much");
        let closed = rng.unit() < 0.5;
        let p = if closed {
            random_contour(&mut rng)
        } else {
            random_function(&mut rng)
        };
        if !acceptable(&p) {
            continue;
        }
        let r = rng.range(0.1, 3.0);
        let side = if closed {
            if rng.unit() < 0.5 {
                Side::Outside
            } else {
                Side::Inside
            }
        } else {
            Side::Above
        };
        let res = compute(&p, r, side).unwrap();
        if res.paths.is_empty() {
            // Only an inward offset may vanish (the electrode fits nowhere).
            assert_eq!(side, Side::Inside, "case {done}: empty path");
            continue;
        }
        let scale = p.extent_mm().max(1.0);
        let tol = 1e-9;
        let worst = certify_worst(&p, &res.paths, r, tol)
            .unwrap_or_else(|e| panic!("case {done} {p:?} R {r}: {e}"));
        worst_rel = worst_rel.max(worst / scale);
        if worst > 1e-9 * scale {
            above_1e9 += 1;
        }
        let rev = compute(&p.reversed(), r, side).unwrap();
        let d = same_path(&res.paths, &rev.paths, tol)
            .unwrap_or_else(|e| panic!("case {done} reversed: {e}"));
        worst_same = worst_same.max(d);
        if closed {
            let k = 1 + rng.below(p.vertices.len() - 1);
            let re = compute(&restarted(&p, k), r, side).unwrap();
            let d = same_path(&res.paths, &re.paths, tol)
                .unwrap_or_else(|e| panic!("case {done} restart {k}: {e}"));
            worst_same = worst_same.max(d);
        }
        let shift = DVec2::new(rng.range(-1e4, 1e4), rng.range(-1e4, 1e4));
        let moved = compute(&transformed(&p, 1.0, shift), r, side).unwrap();
        same_path(
            &transformed_paths(&res.paths, 1.0, shift),
            &moved.paths,
            1e-9 * (scale + 1e4),
        )
        .unwrap_or_else(|e| panic!("case {done} moved: {e}"));
        let k = [1e-3, 1e3][rng.below(2)];
        let scaled = compute(&transformed(&p, k, DVec2::ZERO), r * k, side).unwrap();
        same_path(
            &transformed_paths(&res.paths, k, DVec2::ZERO),
            &scaled.paths,
            tol * k,
        )
        .unwrap_or_else(|e| panic!("case {done} scaled {k}: {e}"));
        assert!(
            res.max_distance_error_mm <= tol,
            "case {done}: certificate {}",
            res.max_distance_error_mm
        );
        done += 1;
    }
    println!(
        "worst |distance - R| / size: {worst_rel:e}; cases above 1e-9 of the size: {above_1e9} of {done}; reversed or restarted paths apart by at most {worst_same:e} mm"
    );
}

/// The seed's four cases (point below or above the x axis, normal angle below or above 90°):
/// the centre is (Xc − R sin φ, Yc + R cos φ) with φ the slope angle, always above the point,
/// and the exact path of a straight profile passes through it.
#[test]
fn the_papers_four_normal_cases() {
    let r = 2.0;
    for (yc, slope) in [(-3.0, 0.5), (-3.0, -0.5), (4.0, 0.75), (4.0, -0.75)] {
        let xc = 1.0;
        let pts: Vec<(f64, f64)> = [-1.0, 0.0, 1.0]
            .iter()
            .map(|dx| (xc + dx, yc + slope * dx))
            .collect();
        let p = Profile::polyline(&pts);
        let res = compute(&p, r, Side::Above).unwrap();
        let phi = f64::atan(slope);
        let expect = DVec2::new(xc - r * phi.sin(), yc + r * phi.cos());
        let got = res.naive[1].centre;
        assert!(
            (got - expect).length() < 1e-14,
            "{yc} {slope}: {got:?} vs {expect:?}"
        );
        assert!(got.y > yc);
        let normal_angle = res.naive[1]
            .normal
            .y
            .atan2(res.naive[1].normal.x)
            .to_degrees();
        assert_eq!(normal_angle < 90.0, slope < 0.0);
        // The exact path is the offset line through the same point.
        let line = &res.paths[0];
        let d = segs(
            &line
                .vertices
                .iter()
                .map(|v| (v.centre.x, v.centre.y, v.bulge))
                .collect::<Vec<_>>(),
            false,
        );
        assert!(dist_to(&d, expect) < 1e-12);
        assert!(res.flags.is_empty());
    }
}

/// A sharp V notch: the per-point centre at the vertex plunges by R(1 − L/√(L²+H²)); no radius
/// reaches the vertex. With a fillet of radius ρ the largest radius is exactly ρ.
#[test]
fn v_notch_flags_and_largest_radius() {
    let (l, h, r) = (3.0, 4.0, 1.0);
    let p = Profile::polyline(&[(-l, h), (0.0, 0.0), (l, h)]);
    let res = compute(&p, r, Side::Above).unwrap();
    let plunges: Vec<_> = res
        .flags
        .iter()
        .filter(|f| f.kind == FlagKind::Plunge)
        .collect();
    assert_eq!(plunges.len(), 1, "{:?}", res.flags);
    let expect = r * (1.0 - l / (l * l + h * h).sqrt());
    assert!(
        (plunges[0].depth_mm - expect).abs() < 1e-14,
        "{} vs {expect}",
        plunges[0].depth_mm
    );
    assert_eq!(plunges[0].point_index, 1);
    assert!(res.flags.iter().all(|f| f.kind == FlagKind::Plunge));
    assert_eq!(res.max_gouge_free_radius_mm, 0.0);
    // The exact path's lowest centre touches both flanks: at height R / sin(half angle).
    let lowest = res.paths[0]
        .vertices
        .iter()
        .map(|v| v.centre.y)
        .fold(f64::INFINITY, f64::min);
    let sin_half = l / (l * l + h * h).sqrt();
    assert!((lowest - r / sin_half).abs() < 1e-12);

    // Filleted V: flanks tangent to a circle of radius rho centred on the axis.
    let rho = 0.75;
    let half = f64::atan2(l, h); // half opening angle from the vertical
    let centre_y = rho / half.sin();
    let tangent = DVec2::new(-rho * half.cos(), centre_y - rho * half.sin());
    let sweep = std::f64::consts::PI - 2.0 * half;
    let b = (sweep / 4.0).tan();
    let top = centre_y + 5.0;
    let fp = profile_of(
        &[
            (-top * half.tan(), top, 0.0),
            (tangent.x, tangent.y, b),
            (-tangent.x, tangent.y, 0.0),
            (top * half.tan(), top, 0.0),
        ],
        false,
    );
    let left = Side::Above.is_left(&fp).unwrap();
    let got = max_gouge_free_radius(&fp, left);
    assert!((got - rho).abs() < 1e-12, "{got} vs {rho}");
}

/// A sampled sine y = A sin(kx): the circle through a trough and its neighbours has radius
/// (h² + d²)/(2d), d = A(1 − cos kh), which tends to the curve's 1/(Ak²); an electrode twice
/// that plunges at every trough, by the depth an independent distance gives.
#[test]
fn sampled_sine_concave_radius_and_plunges() {
    let (a, k) = (2.0, 0.5);
    let n = 512;
    let period = std::f64::consts::TAU / k;
    let hstep = 2.0 * period / n as f64;
    // Samples placed so a trough (kx = 3π/2) is a sample.
    let x0 = 1.5 * std::f64::consts::PI / k - 64.0 * hstep;
    let pts: Vec<(f64, f64)> = (0..=n)
        .map(|i| {
            let x = x0 + i as f64 * hstep;
            (x, a * (k * x).sin())
        })
        .collect();
    let p = Profile::polyline(&pts);
    let d = a * (1.0 - (k * hstep).cos());
    let closed_form = (hstep * hstep + d * d) / (2.0 * d);
    let res = compute(&p, 0.5 * closed_form, Side::Above).unwrap();
    let got = res.min_concave_radius_sampled_mm.unwrap();
    assert!(
        (got - closed_form).abs() < 1e-9 * closed_form,
        "{got} vs {closed_form}"
    );
    assert!((closed_form - 1.0 / (a * k * k)).abs() < 0.02 / (a * k * k));
    assert!(res.flags.is_empty(), "{:?}", res.flags);

    let r = 2.0 * closed_form;
    let res = compute(&p, r, Side::Above).unwrap();
    let prof = segs(&raw(&p), false);
    let troughs: Vec<usize> = (1..n)
        .filter(|&i| {
            ((k * pts[i].0) - 1.5 * std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) < 1e-9
                || ((k * pts[i].0) - 1.5 * std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                    > std::f64::consts::TAU - 1e-9
        })
        .collect();
    assert_eq!(troughs.len(), 2);
    for t in troughs {
        let f = res
            .flags
            .iter()
            .find(|f| f.point_index == t && f.kind == FlagKind::Plunge)
            .expect("plunge at trough");
        let c = res.naive[t].centre;
        let expect = r - dist_to(&prof, c);
        assert!(
            (f.depth_mm - expect).abs() < 1e-12,
            "{} vs {expect}",
            f.depth_mm
        );
    }
}

/// Slots of width w: with a half-circle bottom the largest radius is w/2 exactly; with a flat
/// bottom and sharp corners it is 0, and a per-point electrode of R > w/2 on a wall's middle
/// point collides with the other wall by 2R − w.
#[test]
fn narrow_slot_flags_and_largest_radius() {
    let (w, depth) = (2.0, 8.0);
    let round = profile_of(
        &[
            (-10.0, 0.0, 0.0),
            (-w / 2.0, 0.0, 0.0),
            (-w / 2.0, -depth, 1.0),
            (w / 2.0, -depth, 0.0),
            (w / 2.0, 0.0, 0.0),
            (10.0, 0.0, 0.0),
        ],
        false,
    );
    let left = Side::Above.is_left(&round).unwrap();
    assert_eq!(max_gouge_free_radius(&round, left), w / 2.0);
    // Just below w/2 the exact path reaches the slot bottom; above, it cannot.
    for (r, reaches) in [(0.999 * w / 2.0, true), (1.001 * w / 2.0, false)] {
        let res = compute(&round, r, Side::Above).unwrap();
        let low = res
            .paths
            .iter()
            .flat_map(|p| p.vertices.iter())
            .map(|v| v.centre.y)
            .fold(f64::INFINITY, f64::min);
        assert_eq!(low < -depth + w, reaches, "R {r}: lowest centre {low}");
    }

    let flat = Profile::polyline(&[
        (-10.0, 0.0),
        (-w / 2.0, 0.0),
        (-w / 2.0, -depth / 2.0),
        (-w / 2.0, -depth),
        (w / 2.0, -depth),
        (w / 2.0, -depth / 2.0),
        (w / 2.0, 0.0),
        (10.0, 0.0),
    ]);
    let left = Side::Above.is_left(&flat).unwrap();
    assert_eq!(max_gouge_free_radius(&flat, left), 0.0);
    let r = 0.8 * w;
    let res = compute(&flat, r, Side::Above).unwrap();
    for idx in [2, 5] {
        let c = res
            .flags
            .iter()
            .find(|f| f.point_index == idx && f.kind == FlagKind::Collision)
            .expect("collision on the wall");
        assert!((c.depth_mm - (2.0 * r - w)).abs() < 1e-12, "{}", c.depth_mm);
        assert!(
            !res.flags
                .iter()
                .any(|f| f.point_index == idx && f.kind == FlagKind::Plunge)
        );
    }
    // Below w/2 the wall midpoints are clean.
    let res = compute(&flat, 0.45 * w, Side::Above).unwrap();
    assert!(
        !res.flags
            .iter()
            .any(|f| f.point_index == 2 || f.point_index == 5)
    );
}

/// A keyhole: a round chamber of radius 3 under a neck of width 2: the neck's half width is
/// the bottleneck (1 mm), smaller than the chamber's concave radius.
#[test]
fn keyhole_bottleneck_is_half_the_neck() {
    let neck: f64 = 1.0;
    let rc: f64 = 3.0;
    // Chamber circle centred at (0, -6); the neck walls x = ±1 meet it at y = -6 + √(9 − 1).
    let yj = -6.0 + (rc * rc - neck * neck).sqrt();
    // Arc from (-1, yj) around the bottom to (1, yj), counter-clockwise (concave from inside).
    let start_ang = f64::atan2(yj + 6.0, -neck);
    let end_ang = f64::atan2(yj + 6.0, neck) + std::f64::consts::TAU;
    let sweep = end_ang - start_ang;
    let half_b = (sweep / 8.0).tan();
    let mid = DVec2::new(0.0, -6.0) + DVec2::from_angle(start_ang + sweep / 2.0) * rc;
    let p = profile_of(
        &[
            (-10.0, 0.0, 0.0),
            (-neck, 0.0, 0.0),
            (-neck, yj, half_b),
            (mid.x, mid.y, half_b),
            (neck, yj, 0.0),
            (neck, 0.0, 0.0),
            (10.0, 0.0, 0.0),
        ],
        false,
    );
    let left = Side::Above.is_left(&p).unwrap();
    // The neck walls meet the chamber at concave... they turn away from the free side
    // (convex corners), so the bound is the neck.
    let got = max_gouge_free_radius(&p, left);
    assert!((got - neck).abs() < 1e-12, "{got}");
}

fn ring_paths_ok(p: &Profile, r: f64, side: Side) -> Vec<ClPath> {
    let res = compute(p, r, side).unwrap();
    let tol = 1e-9 * p.extent_mm().max(1.0);
    certify(p, &res.paths, r, tol).unwrap();
    res.paths
}

/// Collapsing slivers (cavalier_contours: a degenerate loop; Clipper2 #873: a large inward
/// offset not empty): a thin triangle offset inward by more than its inradius gives nothing,
/// by less gives one small loop at distance R.
#[test]
fn regression_collapsing_sliver() {
    let p = profile_of(
        &[(0.0, 0.0, 0.0), (100.0, 0.0, 0.0), (50.0, 0.5, 0.0)],
        true,
    );
    // Inradius = area / semiperimeter.
    let a = 0.5 * 100.0 * 0.5;
    let s = 0.5 * (100.0 + 2.0 * (50.0f64.powi(2) + 0.25).sqrt());
    let inr = a / s;
    assert!(
        compute(&p, inr * 1.01, Side::Inside)
            .unwrap()
            .paths
            .is_empty()
    );
    let paths = ring_paths_ok(&p, inr * 0.5, Side::Inside);
    assert_eq!(paths.len(), 1);
    // A square offset inward by more than half its side is empty (Clipper2 #873).
    let sq = profile_of(
        &[
            (0.0, 0.0, 0.0),
            (10.0, 0.0, 0.0),
            (10.0, 10.0, 0.0),
            (0.0, 10.0, 0.0),
        ],
        true,
    );
    assert!(compute(&sq, 6.0, Side::Inside).unwrap().paths.is_empty());
}

/// Coincident segments (CavalierContours #35/#49): a contour with a zero-width slit going in
/// and back out along one line; and an outward square offset (Clipper2 #733 returned empty).
#[test]
fn regression_coincident_segments_and_square() {
    let slit = profile_of(
        &[
            (0.0, 0.0, 0.0),
            (10.0, 0.0, 0.0),
            (10.0, 10.0, 0.0),
            (5.0, 10.0, 0.0),
            (5.0, 4.0, 0.0),
            (5.0, 10.0, 0.0),
            (0.0, 10.0, 0.0),
        ],
        true,
    );
    // The slit makes a zero-length... no: it is two coincident elements; it must still offset
    // to a path at distance R outside.
    let paths = ring_paths_ok(&slit, 1.0, Side::Outside);
    assert_eq!(paths.len(), 1);
    let sq = profile_of(
        &[
            (0.0, 0.0, 0.0),
            (10.0, 0.0, 0.0),
            (10.0, 10.0, 0.0),
            (0.0, 10.0, 0.0),
        ],
        true,
    );
    let paths = ring_paths_ok(&sq, 2.0, Side::Outside);
    assert_eq!(paths.len(), 1);
    // Four quarter-circle joins (Clipper2 #1060: round joins must be round).
    let arcs = paths[0].vertices.iter().filter(|v| v.bulge != 0.0).count();
    assert_eq!(arcs, 4);
    let len = paths[0].length_mm();
    assert!((len - (40.0 + std::f64::consts::TAU * 2.0)).abs() < 1e-9);
}

/// Tiny edges (Clipper2 #1111 dropped length-1 edges; cavalier's absolute epsilons): an edge of
/// 1e-6 of the profile's size at a corner, and unit edges on a large integer polygon, still
/// give a path at distance R that touches them.
#[test]
fn regression_tiny_edges() {
    let p = profile_of(
        &[
            (0.0, 0.0, 0.0),
            (100.0, 0.0, 0.0),
            (100.0, 100.0, 0.0),
            (1e-4, 100.0, 0.0),
            (0.0, 100.0 - 1e-4, 0.0),
        ],
        true,
    );
    ring_paths_ok(&p, 3.0, Side::Outside);
    ring_paths_ok(&p, 3.0, Side::Inside);
    let big = profile_of(
        &[
            (0.0, 0.0, 0.0),
            (10_000.0, 0.0, 0.0),
            (10_000.0, 1.0, 0.0),
            (10_001.0, 1.0, 0.0),
            (10_001.0, 10_000.0, 0.0),
            (0.0, 10_000.0, 0.0),
        ],
        true,
    );
    let paths = ring_paths_ok(&big, 0.25, Side::Inside);
    // The unit edge from (10000, 1) to (10001, 1) is touched: a path point lies 0.25 above its middle.
    let s = path_segs(&paths);
    assert!(dist_to(&s, DVec2::new(10_000.5, 1.25)) < 1e-9);
}

/// Arcs keep the exact distance (Clipper2 #724: offset distance violated on arcs) and shifted
/// input gives the same result (CavalierContours #53).
#[test]
fn regression_arcs_and_shifted_input() {
    let p = profile_of(
        &[
            (0.0, 0.0, 0.4),
            (10.0, 0.0, -0.7),
            (20.0, 3.0, 0.0),
            (20.0, 10.0, 1.0),
            (0.0, 10.0, 0.0),
        ],
        true,
    );
    for side in [Side::Outside, Side::Inside] {
        let base = ring_paths_ok(&p, 1.5, side);
        let shift = DVec2::new(1.0e5, -3.0e5);
        let moved = compute(&transformed(&p, 1.0, shift), 1.5, side).unwrap();
        same_path(
            &transformed_paths(&base, 1.0, shift),
            &moved.paths,
            1e-9 * 3.0e5,
        )
        .unwrap();
    }
}

/// Seg sanity: the independent helpers agree with a hand value.
#[test]
fn independent_distance_helper() {
    let s = seg(DVec2::new(1.0, 0.0), DVec2::new(-1.0, 0.0), 1.0); // upper half circle, CCW
    assert!((point_dist(&s, DVec2::new(0.0, 3.0)) - 2.0).abs() < 1e-15);
    assert!((point_dist(&s, DVec2::new(0.0, -3.0)) - 10f64.sqrt()).abs() < 1e-15);
}

/// Readers and writers: CSV, DXF and SVG round trips keep the profile; SVG's arcs keep their
/// sense (a slot bottom drawn below stays below); curves flatten within the tolerance;
/// elliptical arcs and bad rows are refused with the place.
#[test]
fn profile_files_round_trip_and_report_places() {
    use talas::profile::{
        parse_csv, parse_dxf, parse_svg, profile_to_csv, profile_to_dxf, profile_to_svg,
    };
    let p = profile_of(
        &[
            (0.0, 0.0, 0.0),
            (10.0, 0.0, 0.5),
            (10.0, 10.0, -0.25),
            (0.0, 10.0, 0.0),
        ],
        true,
    );
    let csv = parse_csv(&profile_to_csv(&p), "t.csv").unwrap();
    assert_eq!(csv, p);
    let dxf = parse_dxf(&profile_to_dxf(&p).unwrap(), "t.dxf").unwrap();
    assert_eq!(dxf.closed, p.closed);
    for (a, b) in dxf.vertices.iter().zip(&p.vertices) {
        assert!(
            (a.x - b.x).abs() < 1e-12
                && (a.y - b.y).abs() < 1e-12
                && (a.bulge - b.bulge).abs() < 1e-12
        );
    }
    let svg = parse_svg(&profile_to_svg(&p), "t.svg", 1e-3).unwrap();
    assert_eq!(svg.vertices.len(), p.vertices.len());
    for (a, b) in svg.vertices.iter().zip(&p.vertices) {
        assert!(
            (a.x - b.x).abs() < 1e-9
                && (a.y - b.y).abs() < 1e-9
                && (a.bulge - b.bulge).abs() < 1e-9,
            "{a:?} {b:?}"
        );
    }
    // A half circle drawn below the chord in SVG (y down) is a counter-clockwise arc with y up.
    let slot = parse_svg("M -1 0 A 1 1 0 0 0 1 0", "s.svg", 1e-3).unwrap();
    assert!(slot.vertices[0].bulge > 0.0);
    let e = slot.elements()[0];
    assert!((e.point_at(0.5) - DVec2::new(0.0, -1.0)).length() < 1e-12);
    // A quadratic flattened within 1e-3: every chord midpoint within the tolerance of the curve.
    let q = parse_svg("M 0 0 Q 5 10 10 0", "q.svg", 1e-3).unwrap();
    for w in q.vertices.windows(2) {
        let m = (w[0].pos() + w[1].pos()) / 2.0;
        // y = -(x(1 - x/10))*... the curve is y_svg = 20 t (1 - t), x = 10 t, mirrored.
        let t = m.x / 10.0;
        assert!((m.y + 20.0 * t * (1.0 - t)).abs() <= 1e-3, "{m:?}");
    }
    let err = parse_svg("M 0 0 A 2 1 0 0 0 4 0", "e.svg", 1e-3).unwrap_err();
    assert!(err.to_string().contains("elliptical"), "{err}");
    let err = parse_csv("x,y\n0,0\n1\n", "b.csv").unwrap_err();
    assert_eq!(err.place, "row 3");
}

/// The dense profile: y = 5 sin(x/8) digitised at 0.05 mm (2 001 points), smallest
/// concave radius 12.8 mm (1/(5/64)). Its exact reach is 0 (every concave kink is sharp), but
/// within the 1 µm gouge tolerance a machinist expects about 12.8 mm: the suggestion lies
/// between 12.8 mm and the closed-form bound for the smooth sine at 1 µm (the ball of radius
/// 12.8·(1+ε) at a trough gouges it by about ε²/0.288 mm, ε ≤ 0.017, so 13.02 mm), and a
/// brute-force check over every segment finds no touching ball of that radius gouging more
/// than the tolerance, and one 1 % larger that does.
#[test]
fn a_densely_digitised_sine_suggests_its_smallest_concave_radius_within_the_tolerance() {
    let pts: Vec<(f64, f64)> = (0..=2000)
        .map(|i| {
            let x = i as f64 * 0.05;
            (x, 5.0 * (x / 8.0).sin())
        })
        .collect();
    let p = Profile::polyline(&pts);
    let res = compute(&p, 1.0, Side::Above).unwrap();
    assert_eq!(
        res.max_gouge_free_radius_mm, 0.0,
        "the kinks taken literally"
    );
    let got = res.max_radius_within_tolerance_mm;
    eprintln!("suggested radius {got} mm");
    assert!((12.8..=13.05).contains(&got), "{got} mm");
    // Brute force over every segment: the ball touching each vertex square to its
    // neighbours' chord (the per-point path's normal) and each segment's midpoint square to it
    // (air above).
    let prof = segs(&raw(&p), false);
    let q = |i: usize| DVec2::new(pts[i].0, pts[i].1);
    let worst_gouge = |r: f64| -> f64 {
        let mut worst: f64 = 0.0;
        for i in 0..pts.len() {
            let t = (q((i + 1).min(pts.len() - 1)) - q(i.saturating_sub(1))).normalize();
            worst = worst.max(r - dist_to(&prof, q(i) + t.perp() * r));
            if i + 1 < pts.len() {
                let t = (q(i + 1) - q(i)).normalize();
                let mid = 0.5 * (q(i) + q(i + 1));
                worst = worst.max(r - dist_to(&prof, mid + t.perp() * r));
            }
        }
        worst
    };
    assert!(worst_gouge(got) <= 1e-3 + 1e-9, "{}", worst_gouge(got));
    assert!(
        worst_gouge(1.01 * got) > 1e-3,
        "{}",
        worst_gouge(1.01 * got)
    );
}
