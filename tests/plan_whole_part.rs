//! The whole part as check and the tilt-away, on `pocket-fillets.stp` (a 60 × 40 × 15 mm pocket
//! with 5 mm vertical corner radii and 5 mm floor fillets, floor at z = 15).
//!
//! - A ball Ø12 on the pocket floor (face 22) runs to the floor's edge, where its centre is 5 mm
//!   from the walls: it enters the neighbouring walls by R − 5 = 1 mm (closed form). The drive
//!   face's exact check sees nothing; the whole-part check reports the walls, and its depth
//!   matches an independent distance query (ball centre to the part mesh).
//! - Tilt-away on the floor fillet (face 13, a 5 mm quarter cylinder along x): with the normal
//!   axis the top pass lies horizontal and the holder enters the opposite corner and wall. With
//!   30° allowed the path tilts and nothing is left out; an independent check of the shank and
//!   holder (axis points against the mesh) is clean. With 5° the spans are left out and reported.
//! - Tangent-connected faces: the pocket's floor fillets, corner spheres and floor.
//! - The own-wall case on `plate-hole.stp` (a 5 mm plate with a Ø10 mm hole): the normal axis
//!   lays the tool across the hole into the wall's far side; the steep tilt stands it up, checked
//!   against the hole's closed form.

use std::path::Path;

use glam::DVec3;
use talas::checks::part::PartCheck;
use talas::geometry::brep::tangent_connected;
use talas::geometry::bvh::MeshBvh;
use talas::geometry::surface::SurfaceGeom;
use talas::geometry::trim::TrimRegion;
use talas::import::{OpenOptions, Workpiece, open};
use talas::strategies::finish::axis::AxisMode;
use talas::strategies::finish::face::FacePatch;
use talas::strategies::finish::plan::{FinishResult, plan_finish_in};
use talas::strategies::finish::tiltaway::{PartContext, TiltAway};
use talas::strategies::finish::{FinishOptions, Pattern, Strategy};
use talas::toolpath::MoveKind;
use talas::tools::parse_tool_spec;
use talas::tools::solid::ToolPart;

/// The pocket's walls (planes around the floor).
const WALLS: [usize; 4] = [1, 4, 5, 8];

fn pocket() -> Workpiece {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pocket-fillets.stp");
    open(
        &path,
        &OpenOptions::default(),
        &talas::diagnostics::Progress::new(),
    )
    .expect("pocket-fillets.stp")
}

fn opts() -> FinishOptions {
    FinishOptions {
        scallop: 0.05,
        tolerance: 0.01,
        axis: AxisMode::Normal {
            lead: 0.0,
            tilt: 0.0,
        },
        exact_check: true,
        ..FinishOptions::default()
    }
}

fn plan(wp: &Workpiece, bvh: &MeshBvh, face: usize, tool: &str, tilt: Option<f64>) -> FinishResult {
    let part = wp.part.as_ref().expect("B-rep");
    let region = TrimRegion::of_face(&part.faces[face], part, 0.002).expect("region");
    let patch = FacePatch::trimmed(part, face, &region).expect("patch");
    let skip = [face];
    let context = PartContext {
        check: PartCheck::of_workpiece(wp, bvh, &skip),
        tilt: tilt.map(|deg| TiltAway {
            max_angle_rad: deg.to_radians(),
            ..TiltAway::default()
        }),
    };
    let cutter = parse_tool_spec(tool).expect("tool");
    let strategy = Strategy::IsoParametric {
        pattern: Pattern::Zigzag,
    };
    plan_finish_in(patch, &cutter, tool, strategy, &opts(), Some(&context)).expect("plan")
}

/// Distance from `p` to the part and whether `p` is outside the material (by the closest
/// triangle's outward normal).
fn outside_distance(wp: &Workpiece, bvh: &MeshBvh, p: DVec3) -> (f64, bool) {
    let hit = bvh.closest_point(p).expect("finite");
    let [a, b, c] = wp.mesh.triangle_corners(hit.triangle).expect("triangle");
    let n = (b - a).cross(c - a);
    (hit.distance, (p - hit.point).dot(n) >= -1e-9)
}

#[test]
fn a_neighbouring_wall_entered_by_the_tool_is_reported() {
    let wp = pocket();
    let bvh = wp.bvh().expect("bvh");
    let r = plan(&wp, &bvh, 22, "ball:d=12", None);
    let g = r.toolpath.summary.gouge.expect("report");
    assert!(g.exact_check && g.part_checked);
    assert_eq!(g.gouging_poses, 0, "the floor itself is not gouged");
    // The exact (drive-face) figures stay the floor's: the walls go to part_max_depth_mm.
    assert_eq!(g.max_depth_mm, 0.0, "exact depth mixed with the walls'");
    assert!(g.worst_at.is_none(), "{:?}", g.worst_at);
    assert!(!r.part_hits.is_empty(), "the walls must be reported");
    // Independent: the deepest entry at a cutting pose is R − (ball centre to the mesh).
    let mut want: f64 = 0.0;
    for p in r.toolpath.poses.iter().filter(|p| p.kind == MoveKind::Cut) {
        let (d, outside) = outside_distance(&wp, &bvh, p.tip + p.axis * 6.0);
        assert!(outside, "ball centre inside the part at {}", p.tip);
        want = want.max(6.0 - d);
    }
    assert!((want - 1.0).abs() < 0.02, "closed form 1 mm, mesh {want}");
    assert!(
        (g.part_max_depth_mm - want).abs() < 0.02,
        "check {} vs independent {want}",
        g.part_max_depth_mm
    );
    let walls = r
        .part_hits
        .iter()
        .filter(|h| WALLS.contains(&h.face))
        .count();
    assert!(walls > 0, "{:?}", &r.part_hits[..3.min(r.part_hits.len())]);
    assert!(r.part_hits.iter().all(|h| h.face != 22));
    assert!(
        r.diagnostics
            .iter()
            .any(|d| d.message.contains("enters face")),
        "the hits are named in the diagnostics"
    );
}

/// Shank and holder against the mesh, independently: points on the axis every 0.5 mm from the
/// flute length to the top of the holder must lie outside the part, and the part point
/// closest to each must not lie inside that section's cylinder (radially nearer than the radius
/// less 0.02 mm, axially within the section).
fn holder_clean(wp: &Workpiece, bvh: &MeshBvh, r: &FinishResult, tool: &str) -> bool {
    let c = parse_tool_spec(tool).expect("tool");
    let mut sections = vec![(c.flute_length, c.overall_length, 0.5 * c.shank_diameter)];
    let mut z = c.overall_length;
    for h in &c.holder {
        sections.push((z, z + h.length, 0.5 * h.diameter));
        z += h.length;
    }
    let cut = r.toolpath.poses.iter().filter(|p| p.kind == MoveKind::Cut);
    cut.clone().count() > 0
        && cut.into_iter().all(|p| {
            sections.iter().all(|&(z0, z1, radius)| {
                let n = ((z1 - z0) / 0.5).ceil() as usize;
                (0..=n).all(|k| {
                    let q = p.tip + p.axis * (z0 + (z1 - z0) * k as f64 / n as f64);
                    let (_, outside) = outside_distance(wp, bvh, q);
                    let hit = bvh.closest_point(q).expect("finite").point;
                    let along = (hit - p.tip).dot(p.axis);
                    let radial = (hit - p.tip - p.axis * along).length();
                    let inside = radial < radius - 0.02 && along > z0 + 0.02 && along < z1 - 0.02;
                    outside && !inside
                })
            })
        })
}

#[test]
fn the_tool_tilts_away_from_the_pocket_or_the_span_is_left_out() {
    let wp = pocket();
    let bvh = wp.bvh().expect("bvh");
    let tool = "ball:d=6,flute=12,length=30,holder=12x30";
    // Without tilt-away the holder enters the part (independently seen).
    let plain = plan(&wp, &bvh, 13, tool, None);
    assert!(!holder_clean(&wp, &bvh, &plain, tool));
    assert!(
        plain
            .part_hits
            .iter()
            .any(|h| matches!(h.tool_part, ToolPart::Holder(_) | ToolPart::Shank))
    );
    // 30° allowed: tilted, holder clean, whole-part check clean, and nothing left out but
    // where the pass along the fillet's end arc (x = 25 or 75, where the corner spheres join)
    // meets the floor: there the shank would enter the top face within 30°, and under 1 mm
    // of that arc is left out and reported.
    let tilted = plan(&wp, &bvh, 13, tool, Some(30.0));
    assert!(
        tilted
            .left_out
            .iter()
            .all(|l| end_arc(l) && l.length_mm < 1.0),
        "{:?}",
        tilted.left_out
    );
    assert!(tilted.part_hits.is_empty(), "{:?}", tilted.part_hits);
    assert!(holder_clean(&wp, &bvh, &tilted, tool));
    // The planned axis is the contact normal (lead and tilt 0): the tilt-away angle is the
    // angle between the axis and the normal (ball centre − contact).
    let max_tilt = largest_tilt_deg(&tilted.toolpath);
    assert!(max_tilt > 1.0 && max_tilt <= 30.0 + 1e-6, "{max_tilt}°");
    // 5° allowed: the horizontal top pass cannot be freed: left out, reported, and what is
    // kept is clean.
    let tight = plan(&wp, &bvh, 13, tool, Some(5.0));
    assert!(tight.left_out.iter().any(|l| !end_arc(l)));
    for l in tight.left_out.iter().filter(|l| !end_arc(l)) {
        assert!(l.length_mm > 40.0, "a whole 50 mm pass: {l:?}");
        assert!(matches!(l.tool_part, ToolPart::Holder(_)));
        assert!(!l.approach, "on the span itself: {l:?}");
        // Where: a whole pass on the fillet (radius 5 about the line y = 25, z = 20, from the
        // floor z = 15 up to the wall y = 20), straight along x, in its upper half; the length
        // is the distance between its ends.
        assert!((l.start.y - l.end.y).abs() < 1e-6 && (l.start.z - l.end.z).abs() < 1e-6);
        let from_axis = (l.start.y - 25.0).hypot(l.start.z - 20.0);
        assert!((from_axis - 5.0).abs() < 0.01, "{l:?}");
        assert!(l.start.z > 17.5 && l.start.z < 20.0 + 1e-6, "{l:?}");
        assert!(
            (l.length_mm - l.start.distance(l.end)).abs() < 1e-6,
            "{l:?}"
        );
        let named = format!(
            "left out {:.2} mm ({} poses) from ({:.3}, {:.3}, {:.3})",
            l.length_mm, l.poses, l.start.x, l.start.y, l.start.z
        );
        assert!(
            tight
                .diagnostics
                .iter()
                .any(|d| d.message.starts_with(&named)),
            "{named}"
        );
        // No kept cutting pose lies on the span.
        let (x0, x1) = (l.start.x.min(l.end.x), l.start.x.max(l.end.x));
        assert!(tight.toolpath.poses.iter().all(|p| {
            p.kind != MoveKind::Cut
                || (p.tip.y - l.start.y).abs() > 1e-3
                || (p.tip.z - l.start.z).abs() > 1e-3
                || p.tip.x < x0 - 1e-3
                || p.tip.x > x1 + 1e-3
        }));
    }
    assert!(tight.part_hits.is_empty());
    assert!(holder_clean(&wp, &bvh, &tight, tool));
}

/// Is the span on one of the floor fillet's end arcs (both ends' tips within 0.5 mm of x = 25
/// or of x = 75; the passes of the scan run the fillet's whole 50 mm along x)?
fn end_arc(l: &talas::strategies::finish::tiltaway::LeftOut) -> bool {
    [25.0, 75.0]
        .iter()
        .any(|x| (l.start.x - x).abs() < 0.5 && (l.end.x - x).abs() < 0.5)
}

/// Steep tilts (5° lead limit, then up to 90°) on the floor fillet (a concave quarter cylinder
/// R5): the tilt-away goes beyond the lead limit, and every kept pose and move stays within
/// 1 µm of the fillet (exact check) and of the other faces, with the holder clean. The tilts
/// here stay below 30°, short of swinging the flutes level across the fillet (the own-wall case
/// of a horizontal hole, which the ignored real-part sweep covers).
#[test]
fn a_steep_tilt_beyond_the_lead_limit_keeps_the_path_clean() {
    let wp = pocket();
    let bvh = wp.bvh().expect("bvh");
    let tool = "ball:d=6,flute=12,length=30,holder=12x30";
    let part = wp.part.as_ref().expect("B-rep");
    let region = TrimRegion::of_face(&part.faces[13], part, 0.002).expect("region");
    let patch = FacePatch::trimmed(part, 13, &region).expect("patch");
    let skip = [13];
    let context = PartContext {
        check: PartCheck::of_workpiece(&wp, &bvh, &skip),
        tilt: Some(TiltAway {
            max_angle_rad: 5f64.to_radians(),
            steep_angle_rad: std::f64::consts::FRAC_PI_2,
            ..TiltAway::default()
        }),
    };
    let cutter = parse_tool_spec(tool).expect("tool");
    let strategy = Strategy::IsoParametric {
        pattern: Pattern::Zigzag,
    };
    let r = plan_finish_in(patch, &cutter, tool, strategy, &opts(), Some(&context)).expect("plan");
    let g = r.toolpath.summary.gouge.expect("checked");
    let steepest = largest_tilt_deg(&r.toolpath);
    eprintln!(
        "steepest tilt {steepest:.1}°, exact gouge {:.4} mm at {} poses, {} left out",
        g.max_depth_mm,
        g.gouging_poses,
        r.left_out.len()
    );
    assert!(steepest > 5.0, "steep tilts used: {steepest}°");
    assert!(g.max_depth_mm <= 1e-3, "{:?}", g);
    assert!(r.part_hits.is_empty(), "{:?}", r.part_hits);
    assert!(holder_clean(&wp, &bvh, &r, tool));
}

#[test]
fn tangent_connected_faces_of_the_pocket_floor() {
    let wp = pocket();
    let part = wp.part.as_ref().expect("B-rep");
    let mut group = tangent_connected(part, 13, 1f64.to_radians());
    group.sort_unstable();
    // Floor, the four floor fillets, the four corner spheres, the four walls and the four
    // vertical corner cylinders join tangentially; the top face and the outer sides do not.
    let mut want = vec![1, 2, 3, 4, 5, 6, 7, 8, 13, 14, 15, 16, 17, 18, 19, 20, 22];
    want.sort_unstable();
    assert_eq!(group, want);
}

#[test]
fn a_scallop_the_next_pass_does_not_reach_is_counted_not_reported_as_a_height() {
    use talas::toolpath::{Pose, Summary};
    let pose = |x: f64, h: f64| Pose {
        scallop_mm: Some(h),
        ..Pose::new(MoveKind::Cut, DVec3::new(x, 0.0, 0.0), DVec3::Z, 1000.0)
    };
    let s = Summary::of(&[pose(0.0, 0.004), pose(1.0, 1e9), pose(2.0, 0.01)]);
    assert_eq!(s.predicted_max_scallop_mm, Some(0.01));
    assert_eq!(s.scallop_not_reached_poses, Some(1));
}

#[test]
fn a_face_group_plans_as_one_path_joined_at_one_clearance() {
    use talas::strategies::finish::group::plan_group;
    let wp = pocket();
    let bvh = wp.bvh().expect("bvh");
    let part = wp.part.as_ref().expect("B-rep");
    let group = [13, 14, 16];
    let context = PartContext {
        check: PartCheck::of_workpiece(&wp, &bvh, &group),
        tilt: None,
    };
    let cutter = parse_tool_spec("ball:d=6").expect("tool");
    let strategy = Strategy::IsoParametric {
        pattern: Pattern::Zigzag,
    };
    let r = plan_group(
        part,
        &group,
        &cutter,
        "ball:d=6",
        strategy,
        &opts(),
        Some(&context),
    )
    .expect("group");
    assert!((r.clearance - 35.0).abs() < 1e-6, "part top 30 mm + 5");
    assert!(r.part_hits.is_empty(), "{:?}", r.part_hits);
    // Every face contributes cuts; every cut contact lies on a face of the group.
    let mut seen = [false; 3];
    for p in r.toolpath.poses.iter().filter(|p| p.kind == MoveKind::Cut) {
        let cc = p.cc.expect("contact");
        let hit = bvh.closest_point(cc).expect("finite");
        // The mesh is the faces within its chord tolerance (0.01 mm here).
        assert!(hit.distance < 0.02, "{cc} is {} mm off", hit.distance);
        let face = wp.face_of_triangle[hit.triangle] as usize;
        let k = group.iter().position(|&g| g == face);
        // A contact on an edge may be nearest to the neighbour's triangles.
        if let Some(k) = k {
            seen[k] = true;
        }
    }
    assert!(seen.iter().all(|&s| s), "{seen:?}");
    // Between one face's last cut and the next face's first cut the tool goes up to the
    // common clearance.
    let poses = &r.toolpath.poses;
    let mut faces_left = 0;
    for w in poses.windows(2) {
        if w[0].kind != MoveKind::Cut && w[1].kind != MoveKind::Cut && w[0].tip.z >= 35.0 - 1e-6 {
            faces_left += 1;
        }
    }
    assert!(
        faces_left >= 2,
        "at least the two joins run at the clearance"
    );
    assert!(
        r.diagnostics
            .iter()
            .all(|d| d.place.as_deref().is_some_and(|p| p.starts_with("face "))),
        "every note names its face"
    );
}

/// A cutting move between two free poses that passes through the part (a long straight step
/// across a neighbouring face) is found by the tilt-away: the run is split, just the stretch
/// inside the part is left out (reported), and the two ends stay. The part is the block's
/// 30 mm high body; the move runs along x at z = 10 from 10 mm before it to 10 mm beyond it,
/// ball Ø6 with a vertical axis, so the stretch left out is the body's length plus about one
/// ball diameter (the ball touches the body ±3 mm from its sides), within the 0.25 mm steps.
#[test]
fn a_move_through_the_part_between_two_free_poses_is_left_out() {
    use talas::strategies::finish::tiltaway::{moves_clear, tilt_away};
    use talas::toolpath::Pose;
    let wp = pocket();
    let bvh = wp.bvh().expect("bvh");
    let b = bvh.bbox();
    let y = 0.5 * (b.min.y + b.max.y);
    let a = Pose::new(
        MoveKind::Cut,
        DVec3::new(b.min.x - 10.0, y, 10.0),
        DVec3::Z,
        1000.0,
    );
    let e = Pose::new(
        MoveKind::Cut,
        DVec3::new(b.max.x + 10.0, y, 10.0),
        DVec3::Z,
        1000.0,
    );
    let skip: [usize; 0] = [];
    let check = PartCheck::of_workpiece(&wp, &bvh, &skip);
    let cutter = parse_tool_spec("ball:d=6").expect("tool");
    assert!(!moves_clear(&check, &cutter, &[a, e]));
    let t = tilt_away(&check, &cutter, &[vec![a, e]], &TiltAway::default(), None);
    assert_eq!(t.runs.len(), 2, "{:?}", t.left_out);
    assert_eq!(t.left_out.len(), 1, "{:?}", t.left_out);
    let l = t.left_out[0];
    assert!(!l.approach);
    let want = (b.max.x - b.min.x) + 6.0;
    assert!(
        (l.length_mm - want).abs() < 0.6,
        "left out {} mm, body + ball {want} mm",
        l.length_mm
    );
    for run in &t.runs {
        assert!(
            check.check_path(&cutter, run).hits.is_empty(),
            "a kept run hits"
        );
    }
}

/// The largest angle (°) between a cutting pose's axis and its contact normal (ball centre −
/// contact, for the 3 mm ball of these tests): the tilt-away's tilt where lead and tilt are 0.
fn largest_tilt_deg(tp: &talas::toolpath::Toolpath) -> f64 {
    tp.poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut)
        .filter_map(|p| {
            let n = (p.tip + p.axis * 3.0 - p.cc?).normalize();
            Some(p.axis.angle_between(n).to_degrees())
        })
        .fold(0.0_f64, f64::max)
}

/// The plate with a Ø10 mm vertical through hole (`tests/data/plate-hole.stp`, made by Open
/// CASCADE: x, y −15…15, z 0…5, the hole on the z axis).
fn plate_hole() -> (Workpiece, usize) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/plate-hole.stp");
    let wp = open(
        &path,
        &OpenOptions::default(),
        &talas::diagnostics::Progress::new(),
    )
    .expect("plate-hole.stp");
    let part = wp.part.as_ref().expect("B-rep");
    let holes: Vec<usize> = (0..part.faces.len())
        .filter(|&i| matches!(part.faces[i].surface, SurfaceGeom::Cylinder(_)))
        .collect();
    assert_eq!(holes.len(), 1, "one cylinder face");
    (wp, holes[0])
}

/// How far (mm) the tool's flutes and shank at `p` reach beyond the hole's wall inside the
/// plate, by the closed form of the hole: sections every 0.1 mm along the axis from the ball
/// centre to the shank's top, 128 points round each (radius 3 mm), and a point inside the
/// plate (0 < z < 5, |x|, |y| < 15) more than 5 mm from the z axis is in the material.
fn own_wall_depth(p: &talas::toolpath::Pose, length: f64) -> f64 {
    let axis = p.axis.normalize();
    let side = axis.any_orthonormal_vector();
    let other = axis.cross(side);
    let mut deepest = 0.0_f64;
    let steps = ((length - 3.0) / 0.1).ceil() as usize;
    for k in 0..=steps {
        let c = p.tip + axis * (3.0 + (length - 3.0) * k as f64 / steps as f64);
        for j in 0..128 {
            let t = std::f64::consts::TAU * f64::from(j) / 128.0;
            let q = c + (side * t.cos() + other * t.sin()) * 3.0;
            let in_plate = q.z > 0.0 && q.z < 5.0 && q.x.abs() < 15.0 && q.y.abs() < 15.0;
            if in_plate {
                deepest = deepest.max(q.truncate().length() - 5.0);
            }
        }
    }
    deepest
}

/// The own-wall case: with the axis along the hole wall's normal the tool lies level across
/// the hole and its flutes reach the far half of the same face, which no tilt within 30°
/// frees (a Ø6 tool must stand within about 39° of vertical here: the ball centre is 2 mm
/// from the hole's axis, so tan θ ≤ (2 + 5 − 3) / 5). The steep tilt stands the tool up: every
/// cut pose's ball centre lies 2 mm from the hole axis (the contact on the wall), the flutes
/// and shank stay inside the hole (closed form of the hole, independent of the planner's
/// checks), the exact check finds no gouge. Without the steep tilt the spans are left out and
/// reported, and nothing kept enters the wall.
#[test]
fn a_hole_wall_is_cut_with_a_steep_tilt_clear_of_its_own_far_side() {
    let (wp, hole) = plate_hole();
    let bvh = wp.bvh().expect("bvh");
    let part = wp.part.as_ref().expect("B-rep");
    let tool = "ball:d=6,flute=12,length=30,holder=12x30";
    let cutter = parse_tool_spec(tool).expect("tool");
    let run = |steep: f64| {
        let region = TrimRegion::of_face(&part.faces[hole], part, 0.002).expect("region");
        let patch = FacePatch::trimmed(part, hole, &region).expect("patch");
        let skip = [hole];
        let context = PartContext {
            check: PartCheck::of_workpiece(&wp, &bvh, &skip),
            tilt: Some(TiltAway {
                steep_angle_rad: steep,
                ..TiltAway::default()
            }),
        };
        let strategy = Strategy::IsoPlanar { angle: 0.0 };
        plan_finish_in(patch, &cutter, tool, strategy, &opts(), Some(&context)).expect("plan")
    };
    let steep = run(std::f64::consts::FRAC_PI_2);
    let cuts: Vec<_> = steep
        .toolpath
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut)
        .collect();
    let g = steep.toolpath.summary.gouge.expect("checked");
    let wall = cuts
        .iter()
        .map(|p| own_wall_depth(p, cutter.overall_length))
        .fold(0.0_f64, f64::max);
    let off_wall = cuts
        .iter()
        .map(|p| ((p.tip + p.axis * 3.0).truncate().length() - 2.0).abs())
        .fold(0.0_f64, f64::max);
    let lowest_axis_z = cuts.iter().map(|p| p.axis.z).fold(1.0_f64, f64::min);
    eprintln!(
        "steep: {} cut poses, own wall {wall:.4} mm, ball centre off the wall circle {off_wall:.5} \
         mm, lowest axis z {lowest_axis_z:.3}, exact gouge {:.4} mm, {} left out, {} hits",
        cuts.len(),
        g.max_depth_mm,
        steep.left_out.len(),
        steep.part_hits.len()
    );
    assert!(cuts.len() > 50, "the wall is cut: {} poses", cuts.len());
    assert!(
        wall <= 0.01,
        "flutes or shank {wall} mm into the hole's far side"
    );
    assert!(off_wall <= 0.01, "ball centre {off_wall} mm off its circle");
    assert!(g.max_depth_mm <= 1e-3, "{g:?}");
    assert!(steep.part_hits.is_empty(), "{:?}", steep.part_hits);
    assert!(holder_clean(&wp, &bvh, &steep, tool));

    let tight = run(0.0);
    let kept = tight
        .toolpath
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut)
        .map(|p| own_wall_depth(p, cutter.overall_length))
        .fold(0.0_f64, f64::max);
    eprintln!(
        "30° only: {} spans left out, kept poses reach {kept:.4} mm into the wall",
        tight.left_out.len()
    );
    assert!(
        !tight.left_out.is_empty(),
        "no tilt within 30° frees the tool"
    );
    assert!(kept <= 0.01, "a kept pose enters the wall by {kept} mm");
    assert!(
        tight
            .diagnostics
            .iter()
            .any(|d| d.message.contains("left out")),
        "the spans are reported"
    );
}
