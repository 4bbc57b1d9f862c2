//! The finishing planner's gouge repair, axis smoothing, lead-in/lead-out arcs and iso-planar
//! edge coverage, each checked independently: the checks module's dense verification
//! (penetration of the swept tools, remaining height), the largest axis change within the
//! passes before and after smoothing, the arcs' geometry (circle fit through their poses: radius
//! and tangent) with the ball centre's distance to the exact surface, and the report of gouges
//! no lead up to 45° fixes.

mod common;

use glam::DVec3;
use talas::checks::oracle::surface::VerifyOptions;
use talas::geometry::brep::Part;
use talas::geometry::surface::{ParamRect, SurfaceGeom};
use talas::import::step::read_step;
use talas::strategies::finish::axis::AxisMode;
use talas::strategies::finish::face::FacePatch;
use talas::strategies::finish::plan::{FinishResult, plan_finish};
use talas::strategies::finish::repair::{max_axis_change, plan_passes};
use talas::strategies::finish::setup::Setup;
use talas::strategies::finish::{FinishOptions, Strategy};
use talas::toolpath::{MoveKind, Pose};
use talas::tools::parse_tool_spec;

fn part(name: &str) -> Part {
    read_step(&common::data(name)).expect(name)
}

/// The face's sub-rectangle between the fractions `a..b` of both parameters, and its side.
fn region(p: &Part, a: f64, b: f64) -> (SurfaceGeom, ParamRect, f64) {
    let f = p.faces.first().expect("face");
    let side = FacePatch::from_face(f).expect("patch").side;
    let d = f.surface.domain();
    let sub = |i: talas::geometry::Interval| talas::geometry::Interval::new(i.lerp(a), i.lerp(b));
    let rect = ParamRect {
        u: sub(d.u),
        v: sub(d.v),
    };
    (f.surface.clone(), rect, side)
}

fn plan(
    s: &SurfaceGeom,
    rect: ParamRect,
    side: f64,
    tool: &str,
    o: &FinishOptions,
) -> FinishResult {
    plan_with(s, rect, side, tool, Strategy::IsoScallop, o)
}

fn plan_with(
    s: &SurfaceGeom,
    rect: ParamRect,
    side: f64,
    tool: &str,
    st: Strategy,
    o: &FinishOptions,
) -> FinishResult {
    let cutter = parse_tool_spec(tool).expect("tool");
    let patch = FacePatch::new(s, rect, side).expect("patch");
    plan_finish(patch, &cutter, tool, st, o).expect("plan")
}

/// Largest penetration (mm) of the path's swept tools below the region, by the checks
/// module's verification on a 30 × 30 grid.
fn penetration(s: &SurfaceGeom, rect: ParamRect, side: f64, tool: &str, poses: &[Pose]) -> f64 {
    let cutter = parse_tool_spec(tool).expect("tool");
    let gp = talas::checks::FacePatch::new(s, rect, side < 0.0).expect("patch");
    let o = VerifyOptions {
        nu: 30,
        nv: 30,
        ..VerifyOptions::default()
    };
    let r = talas::checks::oracle::surface::verify(&gp, &cutter, poses, &o).expect("verify");
    r.max_penetration_mm
}

fn normal(lead_deg: f64) -> AxisMode {
    AxisMode::Normal {
        lead: lead_deg.to_radians(),
        tilt: 0.0,
    }
}

/// A flat end mill with a 1° lead inside the trough (concave radius 60 mm across: the lead
/// that clears it is about asin(3/60) = 2.9°), the face-wide lead raise switched off: without
/// the repair the path gouges; with it (exact check) nothing is left and the independent
/// verification finds no penetration beyond 1 µm.
#[test]
fn flat_gouges_in_the_trough_are_repaired() {
    let p = part("rational-trough.stp");
    let (s, rect, side) = region(&p, 0.4, 0.55);
    let tool = "flat:d=6";
    let o = FinishOptions {
        scallop: 0.05,
        tolerance: 0.01,
        axis: normal(1.0),
        curvature_lead: false,
        ..FinishOptions::default()
    };
    let raw = plan(&s, rect, side, tool, &o);
    let before = penetration(&s, rect, side, tool, &raw.toolpath.poses);
    let fixed = plan(
        &s,
        rect,
        side,
        tool,
        &FinishOptions {
            exact_check: true,
            ..o
        },
    );
    let g = fixed.toolpath.summary.gouge.expect("report");
    let after = penetration(&s, rect, side, tool, &fixed.toolpath.poses);
    eprintln!(
        "trough flat 1°: penetration {before} mm before, {after} mm after; {g:?}; {} → {} poses; {:?}",
        raw.toolpath.poses.len(),
        fixed.toolpath.poses.len(),
        fixed.diagnostics
    );
    assert!(before > 0.01, "the unrepaired path should gouge: {before}");
    assert!(g.found_before_repair > 0, "{g:?}");
    assert_eq!(g.gouging_poses, 0, "{g:?}");
    let lead = g.repair_lead_deg.expect("lead raised");
    assert!(lead > 2.5 && lead < 6.0, "repair lead {lead}°");
    assert!(after <= 1e-3, "penetration {after} mm after the repair");
}

/// Ball end mill on bicubic-hills, lead 5°, tilt 0: the largest axis change between
/// consecutive cut poses drops with the smoothing, and the path still verifies.
#[test]
fn smoothing_lowers_the_largest_axis_change() {
    let p = part("bicubic-hills.stp");
    let (s, rect, side) = region(&p, 0.0, 1.0);
    let tool = "ball:d=6";
    let o = FinishOptions {
        scallop: 0.1,
        tolerance: 0.01,
        axis: normal(5.0),
        ..FinishOptions::default()
    };
    let r = plan(&s, rect, side, tool, &o);
    let cutter = parse_tool_spec(tool).expect("tool");
    let setup = Setup::new(
        FacePatch::new(&s, rect, side).expect("patch"),
        &cutter,
        r.used,
    );
    // Per pass (the passes as planned, each stepped on its own), on the scan's passes: not
    // the closing passes along the domain's edges (all their points on one edge).
    let on_edge = |p: &talas::strategies::finish::pass::Pass| {
        let all = |f: &dyn Fn(glam::DVec2) -> bool| p.uv.iter().all(|q| f(*q));
        all(&|q| q.x <= rect.u.t0)
            || all(&|q| q.x >= rect.u.t1)
            || all(&|q| q.y <= rect.v.t0)
            || all(&|q| q.y >= rect.v.t1)
    };
    let scan: Vec<_> = r.passes.iter().filter(|p| !on_edge(p)).cloned().collect();
    let largest = |smooth: bool| {
        plan_passes(&setup, &scan, false, smooth)
            .iter()
            .map(|q| max_axis_change(&q.poses))
            .fold(0.0, f64::max)
    };
    let (a, b) = (largest(false), largest(true));
    let planned = max_axis_change(&r.toolpath.poses);
    let pen = penetration(&s, rect, side, tool, &r.toolpath.poses);
    eprintln!(
        "largest axis change {:.3}° raw, {:.3}° smoothed, {:.3}° in the plan; penetration {pen}",
        a.to_degrees(),
        b.to_degrees(),
        planned.to_degrees()
    );
    assert!(b < 0.9 * a, "{b} vs {a}");
    assert!(planned <= o.max_axis_step + 1e-9, "{planned}");
    assert!(pen <= 1e-3, "penetration {pen} mm");
}

/// Centre and radius of the circle through three points.
fn circle(a: DVec3, b: DVec3, c: DVec3) -> (DVec3, f64) {
    let (ab, ac) = (b - a, c - a);
    let n = ab.cross(ac);
    let centre = a
        + (n.cross(ab) * ac.length_squared() + ac.cross(n) * ab.length_squared())
            / (2.0 * n.length_squared());
    (centre, centre.distance(a))
}

/// Checks one arc (tip points in motion order, `t_end`: the point where it meets the pass,
/// `d`: the cut direction there, `at_start`: the pass end is the arc's first point); returns
/// (radius, angle between the arc's tangent at the pass and `d`, rad).
fn arc_geometry(points: &[DVec3], at_start: bool, d: DVec3) -> (f64, f64) {
    let (a, b, c) = (
        points[0],
        points[points.len() / 2],
        points[points.len() - 1],
    );
    let (centre, radius) = circle(a, b, c);
    let plane = (b - a).cross(c - a).normalize();
    let (t_pt, neighbour) = if at_start {
        (a, points[1])
    } else {
        (c, points[points.len() - 2])
    };
    let mut tangent = plane.cross(t_pt - centre).normalize();
    // Orient along the motion at the pass end.
    let motion = if at_start {
        neighbour - t_pt
    } else {
        t_pt - neighbour
    };
    if tangent.dot(motion) < 0.0 {
        tangent = -tangent;
    }
    // All points on the circle.
    for p in points {
        assert!(
            (p.distance(centre) - radius).abs() < 1e-9,
            "not a circle: {} vs {radius}",
            p.distance(centre)
        );
    }
    (radius, tangent.angle_between(d.normalize()))
}

/// One-way iso-parametric passes with 3 mm lead-in/lead-out arcs and a ball end mill on
/// bicubic-hills: every pass entered from above starts with a quarter circle of radius 3
/// tangent to the first cut move and ends with one tangent to the last, the arcs marked
/// plunge (in) and link (out), and every arc's ball centre stays a radius away from the
/// exact surface.
#[test]
fn lead_arcs_are_tangent_quarter_circles_above_the_surface() {
    let p = part("bicubic-hills.stp");
    let (s, rect, side) = region(&p, 0.0, 0.5);
    let tool = "ball:d=6";
    let o = FinishOptions {
        scallop: 0.2,
        tolerance: 0.01,
        axis: normal(5.0),
        lead_arc_mm: 3.0,
        ..FinishOptions::default()
    };
    let st = Strategy::IsoParametric {
        pattern: talas::strategies::finish::Pattern::Oneway,
    };
    let r = plan_with(&s, rect, side, tool, st, &o);
    let poses = &r.toolpath.poses;
    let dom = s.domain();
    let mut clearance = f64::INFINITY;
    let mut ball_clear = |q: &Pose| {
        let centre = q.tip + q.axis * 3.0;
        let cp = s.closest_point(centre, dom, None);
        clearance = clearance.min(cp.distance);
    };
    let (mut ins, mut outs, mut worst_angle, mut worst_radius) = (0, 0, 0.0_f64, 0.0_f64);
    let mut i = 0;
    while i < poses.len() {
        let kind = poses[i].kind;
        let j = (i..poses.len())
            .find(|&j| poses[j].kind != kind)
            .unwrap_or(poses.len());
        if kind == MoveKind::Plunge && j < poses.len() && poses[j].kind == MoveKind::Cut {
            // Lead-in: the plunge poses end at the pass start; the next move cuts.
            let pts: Vec<DVec3> = poses[i..j].iter().map(|q| q.tip).collect();
            assert!(pts.len() >= 3, "no lead-in arc before pose {j}");
            let d = poses[j].tip - poses[j - 1].tip;
            let (radius, angle) = arc_geometry(&pts, false, d);
            poses[i..j].iter().for_each(&mut ball_clear);
            worst_angle = worst_angle.max(angle);
            worst_radius = worst_radius.max((radius - 3.0).abs());
            ins += 1;
        }
        if kind == MoveKind::Link && i > 0 && poses[i - 1].kind == MoveKind::Cut {
            // Lead-out: from the last cut pose.
            let mut pts = vec![poses[i - 1].tip];
            pts.extend(poses[i..j].iter().map(|q| q.tip));
            let d = poses[i - 1].tip - poses[i - 2].tip;
            let (radius, angle) = arc_geometry(&pts, true, d);
            poses[i..j].iter().for_each(&mut ball_clear);
            worst_angle = worst_angle.max(angle);
            worst_radius = worst_radius.max((radius - 3.0).abs());
            assert_eq!(poses.get(j).map(|q| q.kind), Some(MoveKind::Rapid));
            outs += 1;
        }
        i = j;
    }
    let passes = r.passes.len();
    eprintln!(
        "{passes} passes, {ins} lead-in and {outs} lead-out arcs; worst tangent angle {:.2e}°, \
         radius error {worst_radius:.2e} mm, ball centre ≥ {clearance:.4} mm from the surface",
        worst_angle.to_degrees()
    );
    assert_eq!(ins, passes, "one lead-in per pass");
    assert_eq!(outs, passes, "one lead-out per pass");
    assert!(
        worst_angle.to_degrees() < 1.0,
        "tangent off by {worst_angle} rad"
    );
    assert!(worst_radius < 1e-6, "radius off by {worst_radius} mm");
    assert!(
        clearance >= 3.0 - 1e-3,
        "ball centre {clearance} mm from the surface"
    );
    let pen = penetration(&s, rect, side, tool, poses);
    assert!(pen <= 1e-3, "penetration {pen} mm");
}

/// Iso-planar passes at 0° and 90° on rational-trough with a ball: the trough's end edges
/// run nearly along the planes, so no contour ends there; the edge passes keep the strip along
/// them within the scallop limit (before: 98.8 % of the samples within h + ε, up to 0.17 mm
/// remaining at the edges). Independent verification: ≥ 99.5 % within h + ε, no penetration.
#[test]
fn isoplanar_covers_the_trough_up_to_its_edges() {
    let p = part("rational-trough.stp");
    let (s, rect, side) = region(&p, 0.0, 1.0);
    let tool = "ball:d=6";
    let (h, eps) = (0.05, 0.01);
    let o = FinishOptions {
        scallop: h,
        tolerance: eps,
        axis: normal(0.0),
        ..FinishOptions::default()
    };
    let cutter = parse_tool_spec(tool).expect("tool");
    let gp = talas::checks::FacePatch::new(&s, rect, side < 0.0).expect("patch");
    for deg in [0.0_f64, 90.0] {
        let st = Strategy::IsoPlanar {
            angle: deg.to_radians(),
        };
        let r = plan_with(&s, rect, side, tool, st, &o);
        let v = talas::checks::oracle::surface::verify(
            &gp,
            &cutter,
            &r.toolpath.poses,
            &VerifyOptions {
                nu: 50,
                nv: 50,
                threshold_mm: h + eps,
                ..VerifyOptions::default()
            },
        )
        .expect("verify");
        eprintln!(
            "iso-planar {deg}°: {} passes, {} within h + ε, max {} mm at {:?}, uncovered {}",
            r.passes.len(),
            v.within_threshold,
            v.max_remaining_mm,
            v.max_remaining_at.map(|a| a.point),
            v.uncovered
        );
        assert_eq!(v.uncovered, 0);
        assert!(
            v.within_threshold >= 0.995,
            "{deg}°: {}",
            v.within_threshold
        );
        assert!(v.max_penetration_mm <= 1e-3, "{}", v.max_penetration_mm);
    }
}

/// A flat end mill of 10 mm inside a cylinder of radius 6 mm: no lead up to 45° clears it
/// (asin(5/6) = 56°), so the repair leaves the gouges and the report gives their number,
/// depth and place, with one diagnostic per gouge (up to ten) in mm and µm.
#[test]
fn unfixable_gouges_are_reported_with_place_and_depth() {
    use talas::geometry::Interval;
    use talas::geometry::frame::Frame;
    use talas::geometry::surface::Cylinder;
    let cyl = SurfaceGeom::Cylinder(Cylinder {
        frame: Frame::WORLD,
        radius: 6.0,
    });
    let rect = ParamRect {
        u: Interval::new(4.2, 5.2),
        v: Interval::new(0.0, 4.0),
    };
    let o = FinishOptions {
        scallop: 0.5,
        tolerance: 0.05,
        axis: normal(0.0),
        exact_check: true,
        ..FinishOptions::default()
    };
    let r = plan(&cyl, rect, -1.0, "flat:d=10", &o);
    let g = r.toolpath.summary.gouge.expect("report");
    let lines: Vec<&str> = r
        .diagnostics
        .iter()
        .map(|d| d.message.as_str())
        .filter(|m| m.contains("µm deep at"))
        .collect();
    eprintln!("{g:?}\n{lines:?}");
    assert!(g.local_gouge, "min_lead should find no clearing lead");
    assert!(g.gouging_poses > 0 && g.max_depth_mm > 1e-3, "{g:?}");
    let at = g.worst_at.expect("place");
    // On the cylinder (radius 6 about z).
    assert!((at.truncate().length() - 6.0).abs() < 1e-3, "{at:?}");
    assert_eq!(lines.len(), g.gouging_poses.min(10));
}
