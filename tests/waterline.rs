//! Waterline contours against closed forms (a box, a pyramid frustum, a hemisphere) and against
//! the drop-cutter on `bicubic-hills.stl`; the planned path's levels, directions and links.

mod common;

use common::assert_near;

use std::f64::consts::PI;

use glam::{DVec2, DVec3};
use talas::geometry::bvh::MeshBvh;
use talas::geometry::mesh::TriMesh;
use talas::strategies::waterline::{
    ContourPoint, Cut, Entry, RAMP_HEIGHT_MM, WaterlineOptions, WaterlinePlan, contours_at,
    default_sampling_mm, waterline,
};
use talas::toolpath::{MoveKind, ToolRecord};
use talas::tools::dropcutter::drop_cutter_at;
use talas::tools::{Cutter, CutterKind, parse_tool_spec};

fn cone45() -> Cutter {
    Cutter::new(
        CutterKind::Cone {
            half_angle: 45f64.to_radians(),
        },
        10.0,
    )
    .unwrap()
}

/// A closed frustum: square base [−a, a]² at z = 0, top [−b, b]² at z = hgt (b = a: a box).
fn frustum(a: f64, b: f64, hgt: f64) -> TriMesh {
    let mut pos = Vec::new();
    for (s, z) in [(a, 0.0), (b, hgt)] {
        pos.extend([
            DVec3::new(-s, -s, z),
            DVec3::new(s, -s, z),
            DVec3::new(s, s, z),
            DVec3::new(-s, s, z),
        ]);
    }
    let mut tris = vec![[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7]];
    for i in 0..4u32 {
        let j = (i + 1) % 4;
        tris.push([i, j, 4 + j]);
        tris.push([i, 4 + j, 4 + i]);
    }
    TriMesh::new(pos, tris)
}

/// Distance outside the square [−c, c]² (its offset by r has rounded corners of radius r).
fn square_distance(p: DVec2, c: f64) -> f64 {
    let d = p.abs() - DVec2::splat(c);
    d.max(DVec2::ZERO).length() + d.max_element().min(0.0)
}

fn one_loop(loops: &[Vec<ContourPoint>]) -> &[ContourPoint] {
    assert_eq!(loops.len(), 1, "one loop expected, got {}", loops.len());
    &loops[0]
}

/// Signed area of a loop's tip polygon (positive counter-clockwise).
fn area(lp: &[ContourPoint]) -> f64 {
    let n = lp.len();
    (0..n)
        .map(|i| {
            lp[i]
                .tip
                .truncate()
                .perp_dot(lp[(i + 1) % n].tip.truncate())
        })
        .sum::<f64>()
        * 0.5
}

#[test]
fn every_cutter_around_a_box_is_the_box_offset_with_round_corners() {
    let mesh = frustum(10.0, 10.0, 20.0);
    let bvh = MeshBvh::new(&mesh).unwrap();
    let cutters = [
        Cutter::new(CutterKind::Ball, 6.0).unwrap(),
        Cutter::new(CutterKind::Flat, 10.0).unwrap(),
        Cutter::new(CutterKind::BullNose { corner_radius: 2.0 }, 10.0).unwrap(),
        cone45(),
    ];
    for c in &cutters {
        let r = c.radius();
        // Far enough below the top that the full radius meets the wall's top edge.
        for (z, want) in [
            (5.0, r),
            (20.0 - c.profile_height() - 1.0, r),
            (
                20.0 - 0.5 * c.profile_height(),
                c.radius_at_height(0.5 * c.profile_height()).unwrap_or(r),
            ),
        ] {
            let loops = contours_at(&mesh, &bvh, c, z, 0.37);
            let lp = one_loop(&loops);
            for p in lp {
                let d = square_distance(p.tip.truncate(), 10.0);
                assert!(
                    (d - want).abs() < 1e-9,
                    "{:?} at z {z}: {} is {d} from the box, want {want}",
                    c.kind,
                    p.tip
                );
                assert!((p.tip.z - z).abs() < 1e-12);
            }
            // Climb: the part on the right, so an outside loop runs clockwise.
            assert!(area(lp) < 0.0, "{:?}: loop not clockwise", c.kind);
            assert!(lp.len() > 100);
        }
    }
}

/// On a frustum face of slope θ the contact is a facet contact at the cutter's support point:
/// tip offset from the face x = d0 − z/tan θ by ρ_s − h_s/tan θ (ρ_s, h_s the support point).
#[test]
fn facet_contacts_on_a_frustum_match_the_support_point() {
    let (a, b, hgt): (f64, f64, f64) = (20.0, 8.0, 18.0);
    let tan_t = hgt / (a - b);
    let theta = tan_t.atan();
    let mesh = frustum(a, b, hgt);
    let bvh = MeshBvh::new(&mesh).unwrap();
    let support = |c: &Cutter| -> (f64, f64) {
        let r = c.radius();
        match c.kind {
            CutterKind::Ball => (r * theta.sin(), r * (1.0 - theta.cos())),
            CutterKind::Flat => (r, 0.0),
            CutterKind::BullNose { corner_radius: cr } => {
                (r - cr + cr * theta.sin(), cr * (1.0 - theta.cos()))
            }
            CutterKind::Cone { .. } => (r, c.profile_height()),
        }
    };
    let cutters = [
        Cutter::new(CutterKind::Ball, 6.0).unwrap(),
        Cutter::new(CutterKind::Flat, 10.0).unwrap(),
        Cutter::new(CutterKind::BullNose { corner_radius: 2.0 }, 10.0).unwrap(),
        cone45(),
    ];
    for c in &cutters {
        let (rs, hs) = support(c);
        let z = 3.0;
        let want = a - (z + hs) / tan_t + rs;
        let loops = contours_at(&mesh, &bvh, c, z, 0.29);
        let lp = one_loop(&loops);
        let mut checked = 0;
        for p in lp {
            let t = p.tip.truncate();
            // Points on the straight side x > 0 (away from the corners).
            if t.x > 0.0 && t.y.abs() < 0.5 * want - c.radius() {
                checked += 1;
                assert!(
                    (t.x - want).abs() < 1e-9,
                    "{:?}: x {} want {want}",
                    c.kind,
                    t.x
                );
                assert!((p.slope - theta).abs() < 1e-9 || !matches!(c.kind, CutterKind::Ball));
            }
        }
        assert!(checked > 10, "{:?}: {checked} points on the side", c.kind);
    }
}

/// The upper half of a UV sphere of radius `rs` centred at the origin (vertices on the sphere).
fn hemisphere(rs: f64, nu: usize, nv: usize) -> TriMesh {
    let mut pos = Vec::new();
    for j in 0..=nv {
        let phi = 0.5 * PI * j as f64 / nv as f64;
        for i in 0..nu {
            let th = 2.0 * PI * i as f64 / nu as f64;
            pos.push(rs * DVec3::new(phi.sin() * th.cos(), phi.sin() * th.sin(), phi.cos()));
        }
    }
    let mut tris = Vec::new();
    let id = |i: usize, j: usize| (j * nu + i % nu) as u32;
    for j in 0..nv {
        for i in 0..nu {
            tris.push([id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
        }
    }
    TriMesh::new(pos, tris)
}

#[test]
fn ball_on_a_hemisphere_is_a_circle_of_the_offset_sphere() {
    let (rs, r) = (20.0, 3.0);
    let (nu, nv) = (256, 64);
    let mesh = hemisphere(rs, nu, nv);
    let bvh = MeshBvh::new(&mesh).unwrap();
    let ball = Cutter::new(CutterKind::Ball, 2.0 * r).unwrap();
    // The mesh is inscribed: it lies within the sagitta of its longest chord inside the sphere.
    let dth = 2.0 * PI / nu as f64;
    let dphi = 0.5 * PI / nv as f64;
    let chord = rs * (dth * dth + dphi * dphi).sqrt();
    let sagitta = rs - (rs * rs - chord * chord / 4.0).sqrt();
    for z in [2.0, 8.0, 15.0] {
        let want = ((rs + r).powi(2) - (z + r).powi(2)).sqrt();
        let loops = contours_at(&mesh, &bvh, &ball, z, 0.25);
        let lp = one_loop(&loops);
        for p in lp {
            let rad = p.tip.truncate().length();
            assert!(
                rad <= want + 1e-9 && rad >= want - 2.0 * sagitta,
                "z {z}: radius {rad} want {want} (sagitta {sagitta})"
            );
            // The contact lies on the ball: R from its centre.
            let centre = p.tip + DVec3::Z * r;
            assert!((p.cc.distance(centre) - r).abs() < 1e-7);
        }
    }
}

fn hills() -> (TriMesh, MeshBvh) {
    let mesh = common::hills_stl();
    let bvh = MeshBvh::new(&mesh).unwrap();
    (mesh, bvh)
}

/// At every contour point the drop-cutter (an independent solver: it lowers the cutter
/// instead of pushing it) lands at the level's height.
#[test]
fn contours_on_bicubic_hills_sit_on_the_drop_cutter_surface() {
    let (mesh, bvh) = hills();
    let bb = bvh.bbox();
    let cutters = [
        Cutter::new(CutterKind::Ball, 6.0).unwrap(),
        Cutter::new(CutterKind::BullNose { corner_radius: 2.0 }, 10.0).unwrap(),
        Cutter::new(CutterKind::Flat, 10.0).unwrap(),
        cone45(),
    ];
    for c in &cutters {
        let z = bb.min.z + 0.55 * (bb.max.z - bb.min.z);
        let loops = contours_at(&mesh, &bvh, c, z, 0.5);
        assert!(!loops.is_empty());
        let mut n = 0;
        let mut worst = 0.0f64;
        for p in loops.iter().flatten() {
            let inside = p.tip.x > bb.min.x
                && p.tip.x < bb.max.x
                && p.tip.y > bb.min.y
                && p.tip.y < bb.max.y;
            if !inside {
                continue;
            }
            let cl = drop_cutter_at(&bvh, &mesh, c, p.tip.truncate()).expect("over the part");
            worst = worst.max((cl.z - z).abs());
            n += 1;
        }
        assert!(n > 50, "{:?}: {n} points", c.kind);
        assert!(
            worst < 1e-7,
            "{:?}: drop-cutter differs by {worst} mm",
            c.kind
        );
    }
}

fn tool(spec: &str) -> ToolRecord {
    ToolRecord {
        spec: spec.into(),
        cutter: parse_tool_spec(spec).unwrap(),
    }
}

#[test]
fn plan_on_a_hemisphere_steps_down_by_the_wall_slope_and_cuts_climb() {
    let (rs, r) = (10.0, 3.0);
    let nv = 32;
    let mesh = hemisphere(rs, 4 * nv, nv);
    let bvh = MeshBvh::new(&mesh).unwrap();
    // A facet's slope lies within one facet angle of the sphere's slope at its height.
    let facet = 0.5 * PI / nv as f64;
    let h = 0.05;
    let min_slope = 30f64.to_radians();
    let opts = WaterlineOptions {
        scallop_mm: h,
        chord_tol_mm: 0.02,
        min_slope_rad: min_slope,
        ..WaterlineOptions::default()
    };
    let plan = waterline(&mesh, &bvh, &tool("ball:d=6"), &opts).unwrap();
    let s = 2.0 * (2.0 * r * h - h * h).sqrt();
    // Between consecutive levels, the step is at most what the steeper of the two slopes
    // allows: on the offset sphere the contact's slope at tip height z is acos((z+R)/(Rs+R)).
    // Slopes under the threshold set no limit. The planner sees facets, within one facet
    // angle of the sphere, so within a facet angle of the threshold either rule may hold.
    let limit = |z: f64| {
        let slope = ((z + r) / (rs + r)).clamp(-1.0, 1.0).acos();
        if slope >= min_slope + facet {
            s * (slope + facet).min(0.5 * PI).sin()
        } else {
            opts.max_step_down_mm
        }
    };
    for w in plan.levels.windows(2) {
        let dz = w[0] - w[1];
        assert!(dz > 0.0);
        let allowed = limit(w[0]).min(limit(w[1]));
        assert!(
            dz <= allowed * 1.03 + 1e-6,
            "dz {dz} allowed {allowed} at {}",
            w[0]
        );
    }
    // Steep near the equator: the step there is close to s.
    let dz_max = plan
        .levels
        .windows(2)
        .map(|w| w[0] - w[1])
        .fold(0.0, f64::max);
    assert!(dz_max > 0.8 * s, "largest step {dz_max} vs {s}");
    // Every cut is on a level, clockwise around the dome.
    let cuts: Vec<_> = plan
        .toolpath
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut)
        .collect();
    assert!(
        cuts.iter()
            .all(|p| plan.levels.iter().any(|z| (p.tip.z - z).abs() < 1e-12))
    );
    let first = &cuts[..20];
    let turn: f64 = first
        .windows(2)
        .map(|w| w[0].tip.truncate().perp_dot(w[1].tip.truncate()))
        .sum();
    assert!(turn < 0.0, "climb runs clockwise around the part");
    // Direction and determinism on a coarser plan (fewer levels, the same rules).
    let coarse = WaterlineOptions {
        scallop_mm: 1.0,
        ..opts.clone()
    };
    let conv = waterline(
        &mesh,
        &bvh,
        &tool("ball:d=6"),
        &WaterlineOptions {
            cut: Cut::Conventional,
            ..coarse.clone()
        },
    )
    .unwrap();
    let c2: Vec<_> = conv
        .toolpath
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut)
        .take(20)
        .collect();
    let turn2: f64 = c2
        .windows(2)
        .map(|w| w[0].tip.truncate().perp_dot(w[1].tip.truncate()))
        .sum();
    assert!(turn2 > 0.0, "conventional runs counter-clockwise");
    // The same inputs give the same path.
    let once = waterline(&mesh, &bvh, &tool("ball:d=6"), &coarse).unwrap();
    let again = waterline(&mesh, &bvh, &tool("ball:d=6"), &coarse).unwrap();
    assert_eq!(again.toolpath, once.toolpath);
    assert!(once.levels.len() < plan.levels.len());
}

#[test]
fn bad_options_are_refused() {
    let mesh = frustum(10.0, 10.0, 20.0);
    let bvh = MeshBvh::new(&mesh).unwrap();
    for bad in [
        WaterlineOptions {
            scallop_mm: 0.0,
            ..WaterlineOptions::default()
        },
        WaterlineOptions {
            chord_tol_mm: f64::NAN,
            ..WaterlineOptions::default()
        },
        WaterlineOptions {
            sampling_mm: Some(1e-6),
            ..WaterlineOptions::default()
        },
        WaterlineOptions {
            min_slope_rad: 2.0,
            ..WaterlineOptions::default()
        },
    ] {
        assert!(waterline(&mesh, &bvh, &tool("ball:d=6"), &bad).is_err());
    }
}

/// In the vertical 5 mm corners of pocket-fillets at z = 22 a straight wall's offset falls on a
/// grid line, so a fibre only touches the contour there: every contour point of a 6 mm ball
/// still touches the mesh (ball centre exactly r from the nearest triangle, found by brute
/// force), never inside the material (these points were 1.5 µm inside before the tangent
/// crossings were solved). `cargo test --no-default-features --test waterline along_a_wall`
#[test]
fn ball_contour_points_touch_the_mesh_where_a_fibre_runs_along_a_wall() {
    let mesh = common::pocket_fillets_stl();
    let bvh = MeshBvh::new(&mesh).unwrap();
    let ball = Cutter::new(CutterKind::Ball, 6.0).unwrap();
    let r = ball.radius();
    let loops = contours_at(&mesh, &bvh, &ball, 22.0, 0.1);
    let p = |i: u32| mesh.positions[i as usize];
    let mut worst = 0.0f64;
    let mut n = 0;
    for q in loops.iter().flatten() {
        let centre = q.tip + DVec3::Z * r;
        let d = mesh
            .triangles
            .iter()
            .map(|t| (common::geometry::closest_on_triangle(centre, t.map(p)) - centre).length())
            .fold(f64::INFINITY, f64::min);
        worst = worst.max((d - r).abs());
        n += 1;
    }
    assert!(n > 1000, "{n} contour points");
    assert!(worst < 1e-7, "a contour point is {worst} mm off the mesh");
}

/// Largest distance between neighbouring contour points of `box_plan` (a diagonal of its
/// fibre grid: the 6 mm ball's default spacing at 0.05 mm), mm.
const BOX_STEP: f64 = 1.5 * 0.774_596_669_241_483_4;

/// The 20 mm box of `frustum(10, 10, 20)` planned coarsely with a 6 mm ball, every loop entered
/// from the clearance plane (no fed links), with `entry` and `cut`.
fn box_plan(entry: Entry, cut: Cut) -> (TriMesh, WaterlinePlan) {
    let mesh = frustum(10.0, 10.0, 20.0);
    let bvh = MeshBvh::new(&mesh).unwrap();
    let opts = WaterlineOptions {
        scallop_mm: 1.0,
        chord_tol_mm: 0.05,
        max_link_mm: 0.0,
        entry,
        cut,
        ..WaterlineOptions::default()
    };
    let plan = waterline(&mesh, &bvh, &tool("ball:d=6"), &opts).unwrap();
    (mesh, plan)
}

/// The 6 mm ball (radius `r`) with its tip at `tip` and its endless shank keeps at least
/// `r − 1e-6` from every triangle: brute force over the triangles at the ball's centre and up
/// the shank's axis in 0.25 mm steps to above the part.
fn assert_clear(mesh: &TriMesh, tip: DVec3, r: f64) {
    let p = |i: u32| mesh.positions[i as usize];
    let top = mesh.positions.iter().map(|q| q.z).fold(f64::MIN, f64::max);
    let mut c = tip + DVec3::Z * r;
    while c.z <= top + r {
        let d = mesh
            .triangles
            .iter()
            .map(|t| (common::geometry::closest_on_triangle(c, t.map(p)) - c).length())
            .fold(f64::INFINITY, f64::min);
        assert!(
            d >= r - 1e-6,
            "the cutter at {tip} meets the part ({d} mm from {c})"
        );
        c.z += 0.25;
    }
}

/// Centre and radius of the circle through three points of a plane.
fn circle3(a: DVec2, b: DVec2, c: DVec2) -> (DVec2, f64) {
    let d = 2.0 * (a.x * (b.y - c.y) + b.x * (c.y - a.y) + c.x * (a.y - b.y));
    let (a2, b2, c2) = (a.length_squared(), b.length_squared(), c.length_squared());
    let centre = DVec2::new(
        (a2 * (b.y - c.y) + b2 * (c.y - a.y) + c2 * (a.y - b.y)) / d,
        (a2 * (c.x - b.x) + b2 * (a.x - c.x) + c2 * (b.x - a.x)) / d,
    );
    (centre, centre.distance(a))
}

/// Checks one quarter-circle lead (`pts` in travel order, `on_loop` its end on the loop, `t`
/// the cut direction there): at one height, radius `want`, tangent to `t` at the loop, its
/// centre on the free side (`side` +1: left of the travel), every point clear of the part.
fn check_lead(mesh: &TriMesh, pts: &[DVec3], on_loop: DVec3, t: DVec2, want: f64, side: f64) {
    assert!(pts.len() >= 5, "{} points", pts.len());
    assert!(
        pts.iter().all(|p| p.z == on_loop.z),
        "a lead leaves the level"
    );
    let xy: Vec<DVec2> = pts.iter().map(|p| p.truncate()).collect();
    let (c, r) = circle3(xy[0], xy[xy.len() / 2], xy[xy.len() - 1]);
    assert_near!(r, want, 1e-9);
    for q in &xy {
        assert_near!(q.distance(c), want, 1e-9);
    }
    let radial = (on_loop.truncate() - c) / r;
    assert!(radial.dot(t).abs() < 1e-9, "not tangent: {}", radial.dot(t));
    assert!(
        side * t.perp_dot(c - on_loop.truncate()) > 0.0,
        "centre on the part's side"
    );
    // A quarter circle.
    let (u, v) = ((xy[0] - c) / r, (xy[xy.len() - 1] - c) / r);
    assert_near!(u.dot(v), 0.0, 1e-9);
    for w in pts.windows(2) {
        for k in 0..4 {
            assert_clear(mesh, w[0].lerp(w[1], f64::from(k) / 4.0), 3.0);
        }
    }
}

/// Arc entry on a box, climb and conventional: each loop starts with a quarter-circle of the
/// asked radius at its level, tangent to the first cut, on the free side, clear of the box
/// (brute-force distance), and ends with a lead-out tangent to its last cut.
/// `cargo test --no-default-features --test waterline arc_entry`
#[test]
fn arc_entry_leads_in_and_out_tangentially_on_the_free_side() {
    for (cut, side) in [(Cut::Climb, 1.0), (Cut::Conventional, -1.0)] {
        let radius = 2.0;
        let (mesh, plan) = box_plan(
            Entry::Arc {
                radius_mm: Some(radius),
            },
            cut,
        );
        assert_eq!(plan.entry_fallbacks, 0, "{:?}", plan.diagnostics);
        let poses = &plan.toolpath.poses;
        let mut arcs = 0;
        for (i, p) in poses.iter().enumerate() {
            if p.kind != MoveKind::Plunge {
                continue;
            }
            let lead: Vec<DVec3> = std::iter::once(p.tip)
                .chain(
                    poses[i + 1..]
                        .iter()
                        .take_while(|q| q.kind == MoveKind::Link)
                        .map(|q| q.tip),
                )
                .collect();
            let start = *lead.last().unwrap();
            let j = i + lead.len();
            assert_eq!(poses[j].kind, MoveKind::Cut);
            let t = (poses[j].tip - start).truncate().normalize();
            check_lead(&mesh, &lead, start, t, radius, side);
            // The loop closes at its start; the lead-out leaves from there.
            let cuts = poses[j..]
                .iter()
                .take_while(|q| q.kind == MoveKind::Cut)
                .count();
            let end = poses[j + cuts - 1].tip;
            let run: Vec<DVec3> = std::iter::once(start)
                .chain(poses[j..j + cuts].iter().map(|q| q.tip))
                .collect();
            assert_closes_with_overlap(&run, WaterlineOptions::default().loop_overlap_mm, BOX_STEP);
            let te = (end - poses[j + cuts - 2].tip).truncate().normalize();
            let out: Vec<DVec3> = std::iter::once(end)
                .chain(
                    poses[j + cuts..]
                        .iter()
                        .take_while(|q| q.kind == MoveKind::Link)
                        .map(|q| q.tip),
                )
                .collect();
            check_lead(&mesh, &out, end, te, radius, side);
            arcs += 1;
        }
        assert_eq!(arcs, plan.loops);
        assert!(arcs >= 5, "{arcs} loops");
    }
    // Without a radius the arc has the cutter's.
    let (mesh, plan) = box_plan(Entry::Arc { radius_mm: None }, Cut::Climb);
    let poses = &plan.toolpath.poses;
    let i = poses
        .iter()
        .position(|p| p.kind == MoveKind::Plunge)
        .unwrap();
    let lead: Vec<DVec3> = poses[i..]
        .iter()
        .take_while(|q| matches!(q.kind, MoveKind::Plunge | MoveKind::Link))
        .map(|q| q.tip)
        .collect();
    let start = *lead.last().unwrap();
    let t = (poses[i + lead.len()].tip - start).truncate().normalize();
    check_lead(&mesh, &lead, start, t, 3.0, 1.0);
}

/// Ramp entry on a box: from 1 mm above each level the tool descends along the loop at the
/// asked angle (within 1e-6 rad), every ramp point on the loop's polyline, then cuts round the
/// loop back to where the ramp reached the level. `cargo test --no-default-features --test
/// waterline ramp_entry`
#[test]
fn ramp_entry_descends_along_the_loop_at_the_angle() {
    let angle = 7f64.to_radians();
    let (_, plan) = box_plan(Entry::Ramp { angle_rad: angle }, Cut::Climb);
    assert_eq!(plan.entry_fallbacks, 0, "{:?}", plan.diagnostics);
    let poses = &plan.toolpath.poses;
    assert!(poses.iter().all(|p| p.kind != MoveKind::Plunge));
    let mut ramps = 0;
    for i in 1..poses.len() {
        // Entered from a rapid, or by a fed link straight down from the level above (where
        // the loops lie over each other and the last one's overlap ends above this one's).
        let from_above = matches!(poses[i - 1].kind, MoveKind::Rapid | MoveKind::Link);
        if !(poses[i].kind == MoveKind::Cut && from_above) {
            continue;
        }
        let start = poses[i - 1].tip;
        let run: Vec<DVec3> = poses[i..]
            .iter()
            .take_while(|q| q.kind == MoveKind::Cut)
            .map(|q| q.tip)
            .collect();
        let level = run.last().unwrap().z;
        assert!(plan.levels.contains(&level));
        assert_near!(start.z - level, RAMP_HEIGHT_MM, 1e-12);
        let reach = run.iter().position(|p| p.z == level).unwrap();
        let (down, round) = (&run[..=reach], &run[reach..]);
        // Descent angle of every ramp segment.
        let mut prev = start;
        for p in down {
            let (dz, dxy) = (prev.z - p.z, (p.tip_xy() - prev.tip_xy()).length());
            assert!(dxy > 1e-9);
            assert_near!(dz.atan2(dxy), angle, 1e-6);
            prev = *p;
        }
        // The ramp lies on the loop cut at the level, which closes where the ramp reached it
        // and goes on past it by the overlap.
        assert!(round.iter().all(|p| p.z == level));
        assert_closes_with_overlap(round, WaterlineOptions::default().loop_overlap_mm, BOX_STEP);
        for p in std::iter::once(&start).chain(down) {
            let d = round
                .windows(2)
                .map(|w| segment_distance(p.tip_xy(), w[0].tip_xy(), w[1].tip_xy()))
                .fold(f64::INFINITY, f64::min);
            assert!(d < 1e-9, "ramp point {p} is {d} mm off the loop");
        }
        ramps += 1;
    }
    assert_eq!(ramps, plan.loops);
    assert!(ramps >= 5);
    // A plunge is the default, entered straight down onto each loop's first cut.
    let (_, plunged) = box_plan(Entry::Plunge, Cut::Climb);
    let opts = WaterlineOptions::default();
    assert_eq!(opts.entry, Entry::Plunge);
    let poses = &plunged.toolpath.poses;
    // Each run is entered straight down (a plunge from the clearance plane, or a fed vertical
    // link from the level above where the loops lie over each other).
    let mut runs = 0;
    for w in poses.windows(3) {
        if w[2].kind == MoveKind::Cut && w[1].kind != MoveKind::Cut {
            runs += 1;
            assert!(matches!(w[1].kind, MoveKind::Plunge | MoveKind::Link));
            assert_eq!(w[0].tip.truncate(), w[1].tip.truncate());
            assert!(w[0].tip.z > w[1].tip.z);
        }
    }
    assert_eq!(runs, plunged.loops);
    assert!(poses.iter().any(|p| p.kind == MoveKind::Plunge));
}

/// `run` (a loop's cuts from its first point) comes back through its first point and goes on
/// past it along the loop's own polyline for at least `overlap` mm, to the next contour point
/// (at most `step` more; none at all when `overlap` is 0).
fn assert_closes_with_overlap(run: &[DVec3], overlap: f64, step: f64) {
    let start = run[0];
    let back = (1..run.len())
        .rev()
        .find(|&k| run[k].distance(start) < 1e-9)
        .unwrap_or_else(|| panic!("the loop from {start} never comes back to it"));
    assert!(back > 2, "the loop closes after {back} moves");
    let beyond: f64 = run[back..].windows(2).map(|w| w[0].distance(w[1])).sum();
    let most = if overlap > 0.0 { overlap + step } else { 0.0 };
    assert!(
        beyond >= overlap - 1e-9 && beyond <= most + 1e-9,
        "the loop goes on {beyond} mm past its start, not {overlap} to {most} mm"
    );
    // The overlap retraces the loop's first moves.
    for p in &run[back + 1..] {
        let d = run[..back]
            .windows(2)
            .map(|w| segment_distance(p.truncate(), w[0].truncate(), w[1].truncate()))
            .fold(f64::INFINITY, f64::min);
        assert!(d < 1e-9, "overlap point {p} is {d} mm off the loop");
    }
}

/// Every waterline loop (plunge entry, on the box) is closed: it comes back through its entry
/// point and cuts on past it by the overlap, so the entry leaves no gap (the first cut pose of
/// a run is the end of the run's first move, not its start). A straight wall is one move:
/// no cut pose lies within 1 % of the chord tolerance of the line through its neighbours, and
/// the path has fewer poses than the contours it follows.
/// `cargo test --no-default-features --test waterline loops_close`
#[test]
fn loops_close_past_their_start_and_straight_walls_are_one_move() {
    for overlap in [0.5, 2.0, 0.0] {
        let mesh = frustum(10.0, 10.0, 20.0);
        let bvh = MeshBvh::new(&mesh).unwrap();
        let opts = WaterlineOptions {
            scallop_mm: 1.0,
            chord_tol_mm: 0.05,
            max_link_mm: 0.0,
            loop_overlap_mm: overlap,
            ..WaterlineOptions::default()
        };
        let plan = waterline(&mesh, &bvh, &tool("ball:d=6"), &opts).unwrap();
        let poses = &plan.toolpath.poses;
        let mut loops = 0;
        for (i, p) in poses.iter().enumerate() {
            // Entered by a plunge, or by a fed link straight down onto the loop.
            let entered = i + 1 < poses.len()
                && poses[i + 1].kind == MoveKind::Cut
                && matches!(p.kind, MoveKind::Plunge | MoveKind::Link);
            if !entered {
                continue;
            }
            let run: Vec<DVec3> = std::iter::once(p.tip)
                .chain(
                    poses[i + 1..]
                        .iter()
                        .take_while(|q| q.kind == MoveKind::Cut)
                        .map(|q| q.tip),
                )
                .collect();
            assert_closes_with_overlap(&run, overlap, BOX_STEP);
            let eps = 0.01 * opts.chord_tol_mm;
            // (The loop's closing point is a pose wherever it lies.)
            for w in run.windows(3).filter(|w| w[1] != run[0]) {
                let (a, b) = (w[0], w[2]);
                let f = ((w[1] - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                let d = (a + (b - a) * f).distance(w[1]);
                assert!(
                    d > eps,
                    "{} is carried by the line {} – {}",
                    w[1],
                    w[0],
                    w[2]
                );
            }
            // The contour at this level, as read off the grid, has many more points.
            let z = p.tip.z;
            let sampling = default_sampling_mm(3.0, opts.chord_tol_mm);
            let raw = contours_at(&mesh, &bvh, &tool("ball:d=6").cutter, z, sampling);
            let raw_points: usize = raw.iter().map(Vec::len).sum();
            assert!(
                run.len() * 2 < raw_points,
                "{} cut poses for {raw_points} contour points at z = {z}",
                run.len()
            );
            loops += 1;
        }
        assert_eq!(loops, plan.loops);
        assert!(loops >= 5);
    }
}

/// Horizontal distance from `p` to the segment `a`–`b`.
fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let f = ((p - a).dot(d) / d.length_squared().max(1e-300)).clamp(0.0, 1.0);
    p.distance(a + d * f)
}

trait TipXy {
    fn tip_xy(&self) -> DVec2;
}

impl TipXy for DVec3 {
    fn tip_xy(&self) -> DVec2 {
        self.truncate()
    }
}
