//! Open CASCADE reference: the rational trough (tests/data/rational-trough.stp, poles, weights
//! and knots transcribed by hand from entity #32) evaluated on OCCT's 21×21 sample grid
//! (tests/data/rational-trough.samples.csv: point, S_u × S_v normal, k_min, k_max).

use talas::geometry::DVec3;
use talas::geometry::nurbs::{BSplineSurface, expand_knots};

fn trough() -> BSplineSurface {
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let poles = vec![
        p(-49.23472396305, -56.07598596435, 18.19759743917),
        p(-7.230765200818, -65.46888692426, -26.11945198033),
        p(34.773193561419, -74.86178788416, 18.19759743917),
        p(-36.69504442061, -6.449111420999E-14, 18.19759743917),
        p(7.409349420657, -7.52935751592E-14, -26.11945198033),
        p(51.513743261931, -8.609603610841E-14, 18.19759743917),
        p(-49.23472396305, 56.075985964355, 18.19759743917),
        p(-7.230765200818, 65.468886924261, -26.11945198033),
        p(34.773193561419, 74.861787884167, 18.19759743917),
    ];
    let weights = vec![
        1.0,
        0.696706709347,
        1.0,
        0.975897449331,
        0.679914300583,
        0.975897449331,
        1.0,
        0.696706709347,
        1.0,
    ];
    let ku = expand_knots(&[6.06318530718, 6.50318530718], &[3, 3]).unwrap();
    let kv = expand_knots(&[3.912388980385, 5.512388980385], &[3, 3]).unwrap();
    BSplineSurface::new(2, 2, ku, kv, 3, 3, poles, Some(weights)).unwrap()
}

#[test]
fn rational_trough_matches_open_cascade_samples() {
    let s = trough();
    let csv = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/rational-trough.samples.csv"
    ))
    .unwrap();
    let mut rows = 0;
    let (mut worst_p, mut worst_n, mut worst_k) = (0.0_f64, 0.0_f64, 0.0_f64);
    for line in csv.lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.trim().parse().unwrap()).collect();
        let [u, v, x, y, z, nx, ny, nz, kmin, kmax] = f[..] else {
            panic!("bad row {line}")
        };
        let d = s.derivs(u, v);
        worst_p = worst_p.max(d.p.distance(DVec3::new(x, y, z)));
        let n = d.normal().unwrap();
        worst_n = worst_n.max(n.distance(DVec3::new(nx, ny, nz)));
        let pr = d.principal().unwrap();
        worst_k = worst_k
            .max((pr.k_min - kmin).abs())
            .max((pr.k_max - kmax).abs());
        rows += 1;
    }
    assert_eq!(rows, 441);
    // The CSV carries 12 significant digits.
    assert!(worst_p < 1e-8, "point error {worst_p:e} mm");
    assert!(worst_n < 1e-9, "normal error {worst_n:e}");
    assert!(worst_k < 1e-10, "curvature error {worst_k:e} 1/mm");
}
