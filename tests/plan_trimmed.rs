//! 5-axis finishing on real, trimmed faces: every non-planar face of at least 100 mm² of the
//! two real CATIA parts plans with iso-scallop and iso-planar, and every cut contact lies on its
//! face. The check is independent of the planner's clipping: each contact's distance to the
//! face's own fine tessellation (triangles inside the loops only, 1 µm chord tolerance) must be
//! within 0.01 mm. A B-spline face trimmed by an outer loop and a hole: no contact in the hole
//! or outside the outline, and a line of passes that crosses the hole is split into runs.

mod common;

use std::path::Path;

use glam::{DVec2, DVec3};
use talas::geometry::brep::{Edge, Face, Loop, OrientedEdge, Part, Shell, Vertex};
use talas::geometry::bvh::MeshBvh;
use talas::geometry::curve::CurveGeom;
use talas::geometry::mesh::TriMesh;
use talas::geometry::nurbs::BSplineCurve;
use talas::geometry::surface::SurfaceGeom;
use talas::geometry::tessellate::{TessellationOptions, discretize_edge, tessellate_face};
use talas::geometry::trim::TrimRegion;
use talas::import::step::read_step;
use talas::strategies::finish::axis::AxisMode;
use talas::strategies::finish::face::FacePatch;
use talas::strategies::finish::plan::{FinishResult, plan_finish};
use talas::strategies::finish::{FinishOptions, Pattern, Strategy};
use talas::toolpath::MoveKind;
use talas::tools::parse_tool_spec;

/// Contacts must lie within this distance of their face, mm.
const ON_FACE_MM: f64 = 0.01;

fn part(name: &str) -> Part {
    read_step(&common::data(name)).expect(name)
}

fn opts() -> FinishOptions {
    FinishOptions {
        scallop: 0.05,
        tolerance: 0.01,
        axis: AxisMode::Normal {
            lead: 0.0,
            tilt: 0.0,
        },
        ..FinishOptions::default()
    }
}

fn plan(p: &Part, index: usize, strategy: Strategy) -> Result<FinishResult, String> {
    let face = &p.faces[index];
    let region = TrimRegion::of_face(face, p, 0.002)?;
    let patch = FacePatch::trimmed(p, index, &region).map_err(|e| e.to_string())?;
    let cutter = parse_tool_spec("ball:d=6").expect("tool");
    plan_finish(patch, &cutter, "ball:d=6", strategy, &opts()).map_err(|e| e.to_string())
}

/// The face's fine tessellation (its own triangles only) with a BVH.
fn face_bvh(p: &Part, index: usize) -> MeshBvh {
    let o = TessellationOptions::with_chord_tol(0.001);
    let polylines: Vec<Vec<DVec3>> = p
        .edges
        .iter()
        .map(|e| discretize_edge(e, &p.vertices, &o))
        .collect();
    let fm = tessellate_face(&p.faces[index], p, &polylines, &o).expect("tessellation");
    assert!(!fm.triangles.is_empty(), "face {index} has no triangles");
    MeshBvh::new(&TriMesh::new(fm.positions, fm.triangles)).expect("bvh")
}

/// The largest distance of a cut contact from the face's tessellation, and the contact count.
fn worst_contact(r: &FinishResult, bvh: &MeshBvh) -> (f64, usize) {
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for pose in &r.toolpath.poses {
        if pose.kind != MoveKind::Cut {
            continue;
        }
        let Some(cc) = pose.cc else { continue };
        let d = bvh.closest_point(cc).map_or(f64::INFINITY, |h| h.distance);
        worst = worst.max(d);
        n += 1;
    }
    (worst, n)
}

/// Non-planar faces of at least 100 mm² (area from the part's tessellation).
fn curved_faces(p: &Part) -> Vec<usize> {
    let mesh = talas::geometry::tessellate::tessellate_part(p, &TessellationOptions::default());
    (0..p.faces.len())
        .filter(|&i| {
            !matches!(p.faces[i].surface, SurfaceGeom::Plane(_))
                && mesh.faces.get(i).is_some_and(|f| f.area_mm2 >= 100.0)
        })
        .collect()
}

fn all_faces_on_their_face(file: &str, expected_faces: usize) {
    let p = part(file);
    let faces = curved_faces(&p);
    assert_eq!(
        faces.len(),
        expected_faces,
        "{file}: curved faces ≥ 100 mm²"
    );
    let mut failures = Vec::new();
    for &i in &faces {
        let bvh = face_bvh(&p, i);
        for (name, s) in [
            ("iso-scallop", Strategy::IsoScallop),
            ("iso-planar", Strategy::IsoPlanar { angle: 0.0 }),
            (
                "iso-parametric",
                Strategy::IsoParametric {
                    pattern: Pattern::Zigzag,
                },
            ),
        ] {
            match plan(&p, i, s) {
                Err(e) => failures.push(format!("face {i} {name}: {e}")),
                Ok(r) => {
                    let (worst, n) = worst_contact(&r, &bvh);
                    eprintln!("{file} face {i} {name}: {n} contacts, worst {worst:.5} mm off");
                    if n == 0 || worst > ON_FACE_MM {
                        failures.push(format!(
                            "face {i} {name}: {n} contacts, one {worst:.4} mm off the face"
                        ));
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{file}:\n{}", failures.join("\n"));
}

#[test]
fn schenkel_curved_faces_plan_on_their_trimmed_faces() {
    all_faces_on_their_face("real/freecad/Schenkel.stp", 18);
}

#[test]
fn as1_curved_faces_plan_on_their_trimmed_faces() {
    all_faces_on_their_face("real/freecad/as1-ac-214_small.stp", 12);
}

/// The sphere face (the workstation's Face 292): the path stays on the face and within the
/// part's box (the untrimmed sphere ran 74 mm beyond the part in y).
#[test]
fn schenkel_sphere_face_stays_on_the_face() {
    let p = part("real/freecad/Schenkel.stp");
    assert!(matches!(p.faces[291].surface, SurfaceGeom::Sphere(_)));
    let bbox = p.rough_bbox();
    let bvh = face_bvh(&p, 291);
    for s in [Strategy::IsoScallop, Strategy::IsoPlanar { angle: 0.0 }] {
        let r = plan(&p, 291, s).expect("plan");
        let (worst, n) = worst_contact(&r, &bvh);
        assert!(
            n > 0 && worst <= ON_FACE_MM,
            "{n} contacts, worst {worst} mm"
        );
        for pose in r.toolpath.poses.iter().filter(|q| q.kind == MoveKind::Cut) {
            let cc = pose.cc.expect("contact");
            assert!(
                cc.y <= bbox.max.y + 1e-6 && cc.y >= bbox.min.y - 1e-6,
                "contact {cc} outside the part's y range"
            );
        }
    }
}

/// A degree-1 B-spline edge through `uv` points mapped onto `s` (closed: first = last).
fn edge_on(s: &SurfaceGeom, uv: &[DVec2], vertex: usize, id: u64) -> Edge {
    let poles: Vec<DVec3> = uv.iter().map(|q| s.point(q.x, q.y)).collect();
    let n = poles.len();
    let mut knots = vec![0.0];
    knots.extend((0..n).map(|k| k as f64 / (n - 1) as f64));
    knots.push(1.0);
    Edge {
        start: vertex,
        end: vertex,
        curve: CurveGeom::BSpline(BSplineCurve {
            degree: 1,
            knots,
            poles,
            weights: None,
        }),
        t_start: 0.0,
        t_end: 1.0,
        source_id: id,
    }
}

/// bicubic-hills' B-spline surface trimmed (edges are dense polylines of surface points, so
/// they lie on the surface within a few µm) to uv [0.1, 0.9]² with a round hole of uv radius
/// 0.15 at the centre, as a one-face part.
fn holed_hills() -> (Part, DVec2, f64) {
    let hills = part("bicubic-hills.stp");
    let s = hills.faces[0].surface.clone();
    let mut outer = Vec::new();
    let corners = [
        DVec2::new(0.1, 0.1),
        DVec2::new(0.9, 0.1),
        DVec2::new(0.9, 0.9),
        DVec2::new(0.1, 0.9),
    ];
    for k in 0..4 {
        for j in 0..200 {
            outer.push(corners[k].lerp(corners[(k + 1) % 4], f64::from(j) / 200.0));
        }
    }
    outer.push(corners[0]);
    let (c, r) = (DVec2::new(0.5, 0.5), 0.15);
    let hole: Vec<DVec2> = (0..=480)
        .map(|k| {
            let a = -std::f64::consts::TAU * f64::from(k) / 480.0;
            c + DVec2::new(a.cos(), a.sin()) * r
        })
        .collect();
    let vertices = vec![
        Vertex {
            point: s.point(outer[0].x, outer[0].y),
            source_id: 1,
        },
        Vertex {
            point: s.point(hole[0].x, hole[0].y),
            source_id: 2,
        },
    ];
    let edges = vec![edge_on(&s, &outer, 0, 3), edge_on(&s, &hole, 1, 4)];
    let face = Face {
        surface: s,
        same_sense: true,
        loops: vec![
            Loop::Edges(vec![OrientedEdge {
                edge: 0,
                forward: true,
            }]),
            Loop::Edges(vec![OrientedEdge {
                edge: 1,
                forward: true,
            }]),
        ],
        outer: Some(0),
        source_id: 5,
    };
    let p = Part {
        name: "holed hills".into(),
        vertices,
        edges,
        faces: vec![face],
        shells: vec![Shell {
            faces: vec![0],
            closed: false,
            source_id: 6,
        }],
        diagnostics: Vec::new(),
    };
    (p, c, r)
}

#[test]
fn bspline_face_with_a_hole_has_no_contact_outside_its_region() {
    let (p, c, r) = holed_hills();
    let bvh = face_bvh(&p, 0);
    let s = &p.faces[0].surface;
    for strategy in [
        Strategy::IsoScallop,
        Strategy::IsoPlanar { angle: 0.3 },
        Strategy::IsoParametric {
            pattern: Pattern::Zigzag,
        },
    ] {
        let res = plan(&p, 0, strategy).expect("plan");
        let (worst, n) = worst_contact(&res, &bvh);
        assert!(
            n > 100 && worst <= ON_FACE_MM,
            "{strategy:?}: {n} contacts, worst {worst} mm"
        );
        // Independently in parameter space: no contact inside the hole or beyond the outline
        // (each contact inverted onto the surface; 0.002 in uv is about 0.3 mm here).
        let rect = s.domain();
        for pose in res
            .toolpath
            .poses
            .iter()
            .filter(|q| q.kind == MoveKind::Cut)
        {
            let cc = pose.cc.expect("contact");
            let uv = s.closest_point(cc, rect, None).uv;
            assert!(
                uv.distance(c) >= r - 2e-3,
                "{strategy:?}: contact {cc} at uv {uv} in the hole"
            );
            assert!(
                uv.min_element() >= 0.1 - 2e-3 && uv.max_element() <= 0.9 + 2e-3,
                "{strategy:?}: contact {cc} at uv {uv} outside the outline"
            );
        }
        // Passes that cross the hole are split: more passes than lines for iso-parametric.
        if let Strategy::IsoParametric { .. } = strategy {
            let crossing = res
                .passes
                .iter()
                .filter(|q| {
                    q.uv.first().is_some_and(|a| (a.x - c.x).abs() < 0.5 * r)
                        && (q.uv.iter().all(|a| a.y < c.y) || q.uv.iter().all(|a| a.y > c.y))
                })
                .count();
            assert!(crossing >= 2, "no pass was split by the hole");
        }
    }
}

/// The holed face's finish over its whole region, by the checks module's swept-tool oracle
/// (independent of the planner: samples on a 121 × 121 grid of the surface, the remaining
/// height along the normal to the union of the balls swept along the cutting moves), counting
/// only samples inside the outline and outside the hole: the fraction within h + chord
/// tolerance (0.06 mm) and the deepest penetration of the face.
fn region_coverage(strategy: Strategy) -> (f64, f64) {
    use talas::checks::oracle::surface::{VerifyOptions, verify_masked};
    let (p, c, r) = holed_hills();
    let face = &p.faces[0];
    let side = FacePatch::from_face(face).expect("patch").side;
    let check = talas::checks::FacePatch::new(&face.surface, face.surface.domain(), side < 0.0)
        .expect("check patch");
    let inside =
        |uv: DVec2| uv.min_element() >= 0.1 && uv.max_element() <= 0.9 && uv.distance(c) >= r;
    let o = opts();
    let limit = o.scallop + o.tolerance;
    let res = plan(&p, 0, strategy).expect("plan");
    let v = VerifyOptions {
        nu: 121,
        nv: 121,
        threshold_mm: limit,
        ..VerifyOptions::default()
    };
    let cutter = &res.toolpath.tool.cutter;
    let rep = verify_masked(&check, cutter, &res.toolpath.poses, &v, &inside).expect("verify");
    eprintln!(
        "{strategy:?}: {} samples counted ({} masked), {} uncovered, {:.4} within {limit:.2} mm, \
         p50/90/99/99.9 {:.4?} mm, max {:.4} mm at {:?}, penetration {:.5} mm",
        rep.counted,
        rep.masked,
        rep.uncovered,
        rep.within_threshold,
        rep.remaining_percentiles_mm,
        rep.max_remaining_mm,
        rep.max_remaining_at.map(|a| a.uv),
        rep.max_penetration_mm
    );
    assert!(
        rep.counted > 5_000 && rep.masked > 1_000,
        "{strategy:?}: the mask counts"
    );
    (rep.within_threshold, rep.max_penetration_mm)
}

/// Every strategy finishes the holed face's whole region: at least 99 % of the samples within
/// h + chord tolerance and no penetration beyond the chord tolerance (measured: 100 % for
/// all three). The edge samples are the point: the clipped iso-scallop and iso-parametric
/// passes nearest a side of the outline can lie up to a side step inside it (an iso-line on
/// the side itself can be clipped away), and without the passes along the region's loops they
/// left 0.21 mm (98.2 % within) and 0.26 mm (97.7 %) on those strips.
#[test]
fn bspline_face_with_a_hole_is_finished_within_the_scallop_over_its_region() {
    for strategy in [
        Strategy::IsoScallop,
        Strategy::IsoPlanar { angle: 0.3 },
        Strategy::IsoParametric {
            pattern: Pattern::Zigzag,
        },
    ] {
        let (within, penetration) = region_coverage(strategy);
        assert!(within >= 0.99, "{strategy:?}: only {within} within h + ε");
        assert!(
            penetration <= opts().tolerance,
            "{strategy:?}: {penetration} mm"
        );
    }
}

/// Is `p` inside the closed mesh? Parity of the crossings of a ray (skewed off the axes so it
/// misses edges and vertices).
fn inside_solid(bvh: &MeshBvh, p: DVec3) -> bool {
    let dir = DVec3::new(0.0123, 0.0371, 1.0).normalize();
    let mut origin = p;
    let mut crossings = 0;
    while let Some(hit) = bvh.ray_cast(origin, dir, 1e6) {
        crossings += 1;
        origin = hit.point + dir * 1e-7;
        assert!(crossings < 1000, "ray parity did not end");
    }
    crossings % 2 == 1
}

/// pocket-fillets: every curved face, reversed (`.F.`) ones included (the concave spherical
/// fillet Face 15 among them), is machined from the air side: the ball's centre of every cut
/// pose lies outside the solid, a radius from it (parity of ray crossings on the part's mesh,
/// independent of the face's sense).
#[test]
fn reversed_faces_put_the_tool_on_the_air_side() {
    let p = part("pocket-fillets.stp");
    let mesh = talas::geometry::tessellate::tessellate_part(&p, &TessellationOptions::default());
    let bvh = MeshBvh::new(&mesh.mesh).expect("bvh");
    let curved: Vec<usize> = (0..p.faces.len())
        .filter(|&i| !matches!(p.faces[i].surface, SurfaceGeom::Plane(_)))
        .collect();
    assert!(curved.contains(&14) && !p.faces[14].same_sense);
    for i in curved {
        let r = plan(&p, i, Strategy::IsoScallop).expect("plan");
        let mut n = 0;
        for pose in r.toolpath.poses.iter().filter(|q| q.kind == MoveKind::Cut) {
            let centre = pose.tip + pose.axis * 3.0;
            assert!(
                !inside_solid(&bvh, centre),
                "face {i}: ball centre {centre} inside the material"
            );
            let d = bvh.closest_point(centre).map_or(0.0, |h| h.distance);
            assert!(
                d >= 3.0 - 0.02,
                "face {i}: ball centre {centre} only {d} mm from the part"
            );
            n += 1;
        }
        assert!(n > 0, "face {i}: no cut poses");
    }
}

/// A 5-axis finishing operation planned for a 3-axis machine is flagged when it is planned
/// (the post refuses it later); for a table-tilting machine it is not.
#[test]
fn a_five_axis_path_is_flagged_at_planning_on_a_three_axis_machine() {
    use talas::diagnostics::Progress;
    use talas::import::{OpenOptions, Workpiece};
    use talas::project::pipeline::compute;
    use talas::project::{Operation, OperationKind, Project, ToolEntry};
    let geometry = Workpiece::from_part(
        std::path::Path::new("bicubic-hills.stp"),
        part("bicubic-hills.stp"),
        &OpenOptions::default(),
    );
    let mut op = Operation::new(OperationKind::IsoScallop, 0, 0);
    if let Operation::Finish { options, .. } = &mut op {
        options.scallop = 0.1;
        options.tolerance = 0.02;
    }
    let mut project = Project {
        tools: vec![ToolEntry {
            name: "T1".into(),
            cutter: parse_tool_spec("ball:d=6").expect("tool"),
        }],
        selected_tool: Some(0),
        operations: vec![op],
        ..Project::default()
    };
    let flagged = |project: &Project| {
        compute(project, 0, &geometry, &Progress::new())
            .expect("plans")
            .diagnostics
            .iter()
            .any(|d| d.message.contains("cannot reach"))
    };
    for name in talas::machine::Machine::builtin_names() {
        let m = talas::machine::Machine::builtin(name).expect("machine");
        project.machine = name.to_string();
        let three = m.rotary_names().is_none();
        assert_eq!(flagged(&project), three, "machine {name}");
    }
}

/// The full Done-when sweep (slow: every curved face ≥ 100 mm² of both real parts, iso-scallop
/// and iso-planar, ball Ø6, h 0.05 mm, each path checked exactly against its own face and
/// against every other face of the part, the tool tilting away as the pipeline does). Prints
/// one line per face and strategy; fails on a planning error, an exact gouge deeper than
/// 1 µm, a remaining entry into another face deeper than 1 µm, or a cut contact farther than
/// 0.01 mm from the face's own fine tessellation.
/// `cargo test --release --no-default-features --test plan_trimmed -- --ignored --nocapture`
#[test]
#[ignore = "minutes in the debug build; run by hand, figures in benches/README.md"]
fn real_parts_plan_without_gouges_against_any_face() {
    use talas::checks::part::PartCheck;
    use talas::import::{OpenOptions, Workpiece};
    use talas::strategies::finish::plan::plan_finish_in;
    use talas::strategies::finish::tiltaway::{PartContext, TiltAway};
    let mut failures = Vec::new();
    for file in [
        "real/freecad/Schenkel.stp",
        "real/freecad/as1-ac-214_small.stp",
    ] {
        if std::env::var("SWEEP_FILES").is_ok_and(|only| !file.contains(only.as_str())) {
            continue;
        }
        let p = part(file);
        let mut faces = curved_faces(&p);
        if let Ok(only) = std::env::var("SWEEP_FACES") {
            let only: Vec<usize> = only.split(',').filter_map(|t| t.parse().ok()).collect();
            faces.retain(|f| only.contains(f));
        }
        let wp = Workpiece::from_part(Path::new(file), p.clone(), &OpenOptions::default());
        let bvh = wp.bvh().expect("bvh");
        let cutter = parse_tool_spec("ball:d=6").expect("tool");
        for &i in &faces {
            let skip = [i];
            let face_mesh = face_bvh(&p, i);
            let context = PartContext {
                check: PartCheck::of_workpiece(&wp, &bvh, &skip),
                tilt: Some(TiltAway {
                    steep_angle_rad: std::f64::consts::FRAC_PI_2,
                    ..TiltAway::default()
                }),
            };
            for (name, s) in [
                ("iso-scallop", Strategy::IsoScallop),
                ("iso-planar", Strategy::IsoPlanar { angle: 0.0 }),
            ] {
                let t0 = std::time::Instant::now();
                let region = TrimRegion::of_face(&p.faces[i], &p, 0.002).expect("region");
                let patch = FacePatch::trimmed(&p, i, &region).expect("patch");
                let o = FinishOptions {
                    exact_check: true,
                    ..opts()
                };
                match plan_finish_in(patch, &cutter, "ball:d=6", s, &o, Some(&context)) {
                    Err(e) => failures.push(format!("{file} face {i} {name}: {e}")),
                    Ok(r) => {
                        let g = r.toolpath.summary.gouge.unwrap_or_default();
                        let part_depth = r.part_hits.iter().map(|h| h.depth_mm).fold(0.0, f64::max);
                        let seconds = t0.elapsed().as_secs_f64();
                        let (off, contacts) = worst_contact(&r, &face_mesh);
                        eprintln!(
                            "{file} face {i} {name}: {seconds:.2} s, {} poses, exact gouge {:.4} mm \
                             at {} poses, other faces {} hits {:.4} mm, {} spans left out, \
                             {contacts} contacts, worst {off:.5} mm off the face",
                            r.toolpath.poses.len(),
                            g.max_depth_mm,
                            g.gouging_poses,
                            r.part_hits.len(),
                            part_depth,
                            r.left_out.len()
                        );
                        if let Some(h) = r
                            .part_hits
                            .iter()
                            .max_by(|a, b| a.depth_mm.total_cmp(&b.depth_mm))
                        {
                            let ps = &r.toolpath.poses;
                            let (a, b) = (&ps[h.pose.saturating_sub(1)], &ps[h.pose]);
                            let tip = a.tip.lerp(b.tip, h.move_param);
                            let axis = a.axis.lerp(b.axis, h.move_param).normalize();
                            let centre = tip + axis * 3.0;
                            let d = other_face_distance(&wp, i, centre);
                            eprintln!(
                                "   deepest hit pose {} ({:?} after {:?}, s {:.2}) {:?} face {} \
                                 {:.3} mm at {:.2?}; ball centre {:.2?} is {:.3} mm from \
                                 other faces (independent depth {:.3} mm), move {:.2} mm",
                                h.pose,
                                b.kind,
                                a.kind,
                                h.move_param,
                                h.tool_part,
                                h.face,
                                h.depth_mm,
                                h.point,
                                centre,
                                d,
                                3.0 - d,
                                a.tip.distance(b.tip)
                            );
                        }
                        for d in r
                            .diagnostics
                            .iter()
                            .filter(|d| d.message.contains("unfixed"))
                            .take(4)
                        {
                            let k = d
                                .place
                                .as_deref()
                                .and_then(|l| l.strip_prefix("pose "))
                                .and_then(|n| n.parse::<usize>().ok())
                                .map(|n| {
                                    (
                                        r.toolpath.poses[n.saturating_sub(1)].kind,
                                        r.toolpath.poses[n].kind,
                                    )
                                });
                            eprintln!("   {d:?} {k:?}");
                        }
                        for l in r.left_out.iter().take(3) {
                            eprintln!("   left out {l:?}");
                        }
                        if off > ON_FACE_MM {
                            failures.push(format!(
                                "{file} face {i} {name}: a contact {off:.4} mm off the face"
                            ));
                        }
                        if g.max_depth_mm > 0.001 || part_depth > 0.001 {
                            failures.push(format!(
                                "{file} face {i} {name}: exact {:.4} mm, other faces {part_depth:.4} mm",
                                g.max_depth_mm
                            ));
                        }
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Distance from `p` to the nearest triangle of `wp`'s mesh outside face `skip` (brute force).
fn other_face_distance(wp: &talas::import::Workpiece, skip: usize, p: DVec3) -> f64 {
    let mut best = f64::INFINITY;
    for t in 0..wp.mesh.triangles.len() {
        if wp
            .face_of_triangle
            .get(t)
            .is_some_and(|&f| f as usize == skip)
        {
            continue;
        }
        let Some([a, b, c]) = wp.mesh.triangle_corners(t) else {
            continue;
        };
        best = best.min(common::geometry::closest_on_triangle(p, [a, b, c]).distance(p));
    }
    best
}
