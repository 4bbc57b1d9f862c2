//! Pencil finishing against closed forms: a V-groove (the ball touches both flanks; its tip
//! runs along the groove's axis at R·(sec α − 1) above the bottom, and the normals at the two
//! contacts differ by 2α) and the pocket of pocket-fillets.stl (pocket 60 × 40 mm, floor at
//! z = 15, walls and floor joined by R5 fillets): a ball of radius 6 > 5 touches wall and floor
//! with its tip on the floor 6 mm from each wall, a ball of radius 3 < 5 fits every fillet and
//! finds no pencil line.

use std::path::Path;

use glam::DVec3;
use talas::geometry::bvh::MeshBvh;
use talas::geometry::mesh::TriMesh;
use talas::import::stl::{StlOptions, read_stl};
use talas::strategies::pencil::{PencilError, PencilOptions, pencil, pencil_lines};
use talas::toolpath::{MoveKind, ToolRecord};
use talas::tools::dropcutter::drop_cutter_at;
use talas::tools::parse_tool_spec;

fn tool(spec: &str) -> ToolRecord {
    ToolRecord {
        spec: spec.into(),
        cutter: parse_tool_spec(spec).unwrap(),
    }
}

/// z = |x|·tan α over x ∈ [−10, 10], y ∈ [0, 20].
fn v_groove(alpha: f64) -> TriMesh {
    let t = alpha.tan();
    let p = |x: f64, y: f64| DVec3::new(x, y, x.abs() * t);
    let positions = vec![
        p(-10.0, 0.0),
        p(0.0, 0.0),
        p(10.0, 0.0),
        p(-10.0, 20.0),
        p(0.0, 20.0),
        p(10.0, 20.0),
    ];
    let triangles = vec![[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]];
    TriMesh::new(positions, triangles)
}

#[test]
fn pencil_runs_along_the_axis_of_a_v_groove() {
    let alpha = 30f64.to_radians();
    let mesh = v_groove(alpha);
    let bvh = MeshBvh::new(&mesh).unwrap();
    let r = 3.0;
    let opts = PencilOptions {
        sampling_mm: Some(0.7),
        ..PencilOptions::default()
    };
    let plan = pencil(&mesh, &bvh, &tool("ball:d=6"), &opts).unwrap();
    assert_eq!(plan.lines.len(), 1, "one line along the groove");
    let z0 = r * (1.0 / alpha.cos() - 1.0);
    let line = &plan.lines[0];
    // Points beyond the mesh's ends (y < 0, y > 20) rest on its boundary edges, lower.
    for p in line.iter().filter(|p| (0.0..=20.0).contains(&p.tip.y)) {
        assert!(p.tip.x.abs() < 1e-4, "off the axis: {:?}", p.tip);
        assert!((p.tip.z - z0).abs() < 1e-4, "tip z {} vs {z0}", p.tip.z);
        assert!(
            (p.angle_rad - 2.0 * alpha).abs() < 1e-3,
            "angle {}",
            p.angle_rad
        );
        // The two contacts lie on the flanks, R·sin α to each side of the axis.
        let xs = [p.cc.x, p.cc_other.x];
        assert!(xs.iter().all(|x| (x.abs() - r * alpha.sin()).abs() < 1e-3));
        assert!(xs[0] * xs[1] < 0.0);
    }
    let ys: Vec<f64> = line.iter().map(|p| p.tip.y).collect();
    let (lo, hi) = ys
        .iter()
        .fold((f64::MAX, f64::MIN), |a, y| (a.0.min(*y), a.1.max(*y)));
    assert!(lo <= 0.0 && hi >= 20.0, "line spans y {lo}..{hi}");
    // The length is 3D: the ends beyond the mesh dip a few µm.
    assert!(plan.length_mm >= hi - lo - 1e-9 && plan.length_mm < hi - lo + 0.05);
    // The path: one plunge, cuts along the line, a retract; every cut pose an exact drop-cutter
    // location.
    let tp = &plan.toolpath;
    tp.validate("<pencil>").unwrap();
    assert_eq!(
        tp.poses
            .iter()
            .filter(|p| p.kind == MoveKind::Plunge)
            .count(),
        1
    );
    for p in tp.poses.iter().filter(|p| p.kind == MoveKind::Cut) {
        let cl = drop_cutter_at(&bvh, &mesh, &tool("ball:d=6").cutter, p.tip.truncate()).unwrap();
        assert!((cl.z - p.tip.z).abs() < 1e-9);
    }
    // A flatter groove than the bitangency angle asks for has no pencil line.
    let flat = v_groove(5f64.to_radians());
    let fb = MeshBvh::new(&flat).unwrap();
    let err = pencil(&flat, &fb, &tool("ball:d=6"), &opts).unwrap_err();
    assert!(matches!(err, PencilError::Empty(_)), "{err}");
}

fn pocket() -> (TriMesh, MeshBvh) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pocket-fillets.stl");
    let mesh = read_stl(&path, &StlOptions::default()).unwrap().mesh;
    let bvh = MeshBvh::new(&mesh).unwrap();
    (mesh, bvh)
}

#[test]
fn pencil_in_pocket_fillets_follows_the_floor_corners_of_a_ball_larger_than_the_fillets() {
    let (mesh, bvh) = pocket();
    let r = 6.0;
    let lines = pencil_lines(&mesh, &bvh, &tool("ball:d=12"), &PencilOptions::default()).unwrap();
    // The pocket's floor loop: tip on the floor, 6 mm from the walls x = 20, 80, y = 20, 60.
    let (x0, x1, y0, y1) = (20.0 + r, 80.0 - r, 20.0 + r, 60.0 - r);
    let mut floor_len = 0.0;
    for line in &lines {
        for w in line.windows(2) {
            let (a, b) = (w[0].tip, w[1].tip);
            if a.z > 15.5 || b.z > 15.5 {
                continue;
            }
            for p in [a, b] {
                assert!((p.z - 15.0).abs() < 1e-6, "floor tip at z {}", p.z);
                let off = (p.x - x0)
                    .abs()
                    .min((p.x - x1).abs())
                    .min((p.y - y0).abs())
                    .min((p.y - y1).abs());
                assert!(
                    off < 1e-3,
                    "floor pencil point {p:?} is {off} mm off the inset"
                );
                assert!(p.x > x0 - 1e-3 && p.x < x1 + 1e-3 && p.y > y0 - 1e-3 && p.y < y1 + 1e-3);
            }
            floor_len += a.distance(b);
        }
    }
    let full = 2.0 * ((x1 - x0) + (y1 - y0));
    // Only the four corners may be cut short, by at most a grid cell each.
    assert!(
        floor_len > full - 4.0 * 2.0 * 1.5 && floor_len <= full + 1e-6,
        "{floor_len} of {full}"
    );
    // A ball of radius 3 fits the R5 fillets: no pencil line below the pocket's rim.
    let small = pencil_lines(&mesh, &bvh, &tool("ball:d=6"), &PencilOptions::default()).unwrap();
    assert!(
        small.iter().flatten().all(|p| p.tip.z > 25.0),
        "{:?}",
        small.iter().flatten().map(|p| p.tip).find(|t| t.z <= 25.0)
    );
}

#[test]
fn pencil_refuses_bad_options_and_cutters() {
    let mesh = v_groove(0.5);
    let bvh = MeshBvh::new(&mesh).unwrap();
    let o = PencilOptions::default();
    let e = pencil(&mesh, &bvh, &tool("flat:d=6"), &o).unwrap_err();
    assert!(e.to_string().contains("ball"), "{e}");
    for bad in [
        PencilOptions {
            min_angle_rad: 0.0,
            ..o.clone()
        },
        PencilOptions {
            chord_tol_mm: -1.0,
            ..o.clone()
        },
        PencilOptions {
            sampling_mm: Some(f64::NAN),
            ..o.clone()
        },
        PencilOptions {
            clearance_mm: f64::INFINITY,
            ..o.clone()
        },
    ] {
        assert!(matches!(
            pencil(&mesh, &bvh, &tool("ball:d=6"), &bad),
            Err(PencilError::Option(_))
        ));
    }
}
