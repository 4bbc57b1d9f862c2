//! `geometry::planar::Region`: offsets and booleans against closed forms (areas of offset
//! rectangles with rounded corners, circles, lenses, half discs).

use std::f64::consts::PI;
use talas::geometry::DVec2;
use talas::geometry::planar::{BooleanOp, Profile, Region, Vertex};

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Region {
    Region::rectangle(DVec2::new(x0, y0), DVec2::new(x1, y1))
}

fn close(a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{a} vs {b} (tolerance {tol})");
}

#[test]
fn inward_offset_of_a_rectangle_keeps_sharp_corners() {
    for d in [0.5, 3.0, 12.5, 29.0] {
        let r = rect(0.0, 0.0, 100.0, 60.0).offset(d);
        close(r.area_mm2(), (100.0 - 2.0 * d) * (60.0 - 2.0 * d), 1e-6);
    }
    assert!(rect(0.0, 0.0, 100.0, 60.0).offset(30.5).is_empty());
}

#[test]
fn outward_offset_of_a_rectangle_rounds_the_corners() {
    for d in [0.5, 3.0, 12.5] {
        let r = rect(0.0, 0.0, 100.0, 60.0).offset(-d);
        close(r.area_mm2(), 6000.0 + 2.0 * d * 160.0 + PI * d * d, 1e-6);
        assert_eq!(
            r.smallest_corner_radius_mm()
                .map(|x| (x * 1e9).round() / 1e9),
            Some(d)
        );
    }
}

#[test]
fn a_pocket_with_an_island_offsets_both_ways() {
    let outer = rect(0.0, 0.0, 100.0, 60.0);
    let island = Region::circle(DVec2::new(50.0, 30.0), 10.0);
    let pocket = outer.boolean(&island, BooleanOp::Difference);
    assert_eq!(pocket.areas.len(), 1);
    assert_eq!(pocket.areas[0].islands.len(), 1);
    close(pocket.area_mm2(), 6000.0 - PI * 100.0, 1e-6);
    assert!(!pocket.contains(DVec2::new(50.0, 30.0)));
    assert!(pocket.contains(DVec2::new(5.0, 5.0)));
    // The tool centre of a 6 mm cutter: the walls move in by 3, the island out by 3.
    let d = 3.0;
    let cl = pocket.offset(d);
    close(
        cl.area_mm2(),
        (100.0 - 2.0 * d) * (60.0 - 2.0 * d) - PI * (10.0 + d).powi(2),
        1e-6,
    );
    // Far enough that the island's offset meets the walls (60/2 - 10 = 20 between): two areas.
    let split = pocket.offset(10.5);
    assert_eq!(split.areas.len(), 2, "{split:?}");
}

#[test]
fn union_intersection_and_difference_of_overlapping_shapes() {
    let a = rect(0.0, 0.0, 10.0, 10.0);
    let b = rect(5.0, 5.0, 15.0, 15.0);
    close(a.boolean(&b, BooleanOp::Union).area_mm2(), 175.0, 1e-9);
    close(
        a.boolean(&b, BooleanOp::Intersection).area_mm2(),
        25.0,
        1e-9,
    );
    close(a.boolean(&b, BooleanOp::Difference).area_mm2(), 75.0, 1e-9);
    assert_eq!(a.boolean(&b, BooleanOp::Union).areas.len(), 1);
    // Half a disc: a circle centred on the rectangle's edge.
    let c = Region::circle(DVec2::new(10.0, 5.0), 3.0);
    close(
        a.boolean(&c, BooleanOp::Intersection).area_mm2(),
        PI * 9.0 / 2.0,
        1e-9,
    );
    close(
        a.boolean(&c, BooleanOp::Union).area_mm2(),
        100.0 + PI * 9.0 / 2.0,
        1e-9,
    );
    // A lens: two unit circles one radius apart, area 2π/3 − √3/2.
    let c1 = Region::circle(DVec2::ZERO, 1.0);
    let c2 = Region::circle(DVec2::new(1.0, 0.0), 1.0);
    close(
        c1.boolean(&c2, BooleanOp::Intersection).area_mm2(),
        2.0 * PI / 3.0 - 3f64.sqrt() / 2.0,
        1e-9,
    );
    // Disjoint shapes: the union keeps both, the intersection is empty.
    let far = rect(50.0, 50.0, 51.0, 52.0);
    close(a.boolean(&far, BooleanOp::Union).area_mm2(), 102.0, 1e-9);
    assert!(a.boolean(&far, BooleanOp::Intersection).is_empty());
}

#[test]
fn subtracting_a_region_with_an_island_keeps_what_the_island_covers() {
    // Frame − (ring): the ring's hole gives back its part of the frame.
    let a = rect(0.0, 0.0, 40.0, 40.0);
    let ring =
        rect(10.0, 10.0, 30.0, 30.0).boolean(&rect(15.0, 15.0, 25.0, 25.0), BooleanOp::Difference);
    close(ring.area_mm2(), 300.0, 1e-9);
    let d = a.boolean(&ring, BooleanOp::Difference);
    close(d.area_mm2(), 1600.0 - 300.0, 1e-9);
    assert_eq!(d.areas.len(), 2);
    assert!(d.contains(DVec2::new(20.0, 20.0)));
    assert!(!d.contains(DVec2::new(12.0, 20.0)));
    // The union of a region with an island and a bar across the island.
    let bar = rect(18.0, 0.0, 22.0, 40.0);
    let u = ring.boolean(&bar, BooleanOp::Union);
    // The bar (160) overlaps the ring on 4 × (20 − 10) = 40.
    close(u.area_mm2(), 300.0 + 160.0 - 40.0, 1e-9);
    assert_eq!(u.areas.len(), 1);
}

#[test]
fn boundaries_in_any_orientation_nest_into_outer_and_islands() {
    let sq = |x0: f64, y0: f64, s: f64, ccw: bool| {
        let mut p = Profile {
            vertices: vec![
                Vertex::point(x0, y0),
                Vertex::point(x0 + s, y0),
                Vertex::point(x0 + s, y0 + s),
                Vertex::point(x0, y0 + s),
            ],
            closed: true,
        };
        if !ccw {
            p = p.reversed();
        }
        p
    };
    // Outer 100 (cw as drawn), island 40 (ccw as drawn), a boss 10 inside the island.
    let r = Region::from_boundaries(&[
        sq(30.0, 30.0, 40.0, true),
        sq(0.0, 0.0, 100.0, false),
        sq(45.0, 45.0, 10.0, false),
    ])
    .expect("a region");
    assert_eq!(r.areas.len(), 2);
    close(r.area_mm2(), 10000.0 - 1600.0 + 100.0, 1e-9);
    assert!(r.contains(DVec2::new(50.0, 50.0)));
    assert!(!r.contains(DVec2::new(35.0, 35.0)));
    let open = Profile::polyline(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)]);
    assert!(Region::from_boundaries(&[open]).is_err());
}
