//! A B-rep moved rigidly (a rotation and a translation): every point, frame and direction of its
//! vertices, edge curves and face surfaces. The parameter spaces (and so the trimming loops'
//! parameters and the edges' parameter ranges) are unchanged: a rigid motion maps each curve
//! and surface onto its image at the same parameters. Used to recognise a part's regions and
//! holes from a setup's tool axis (the recognisers look along +Z).

use glam::{DMat3, DVec3};

use super::brep::Part;
use super::curve::CurveGeom;
use super::frame::Frame;
use super::surface::SurfaceGeom;

/// `part` with every point `p` moved to `rotation·p + offset` and every direction turned by
/// `rotation` (a proper rotation: the faces' sense is kept).
#[must_use]
pub fn transform_part(part: &Part, rotation: DMat3, offset: DVec3) -> Part {
    let mut out = part.clone();
    let point = |p: DVec3| rotation * p + offset;
    for v in &mut out.vertices {
        v.point = point(v.point);
    }
    for e in &mut out.edges {
        transform_curve(&mut e.curve, rotation, offset);
    }
    for f in &mut out.faces {
        transform_surface(&mut f.surface, rotation, offset);
    }
    out
}

fn transform_frame(f: &mut Frame, rotation: DMat3, offset: DVec3) {
    f.origin = rotation * f.origin + offset;
    f.x = rotation * f.x;
    f.y = rotation * f.y;
    f.z = rotation * f.z;
}

fn transform_curve(c: &mut CurveGeom, rotation: DMat3, offset: DVec3) {
    match c {
        CurveGeom::Line(l) => {
            l.origin = rotation * l.origin + offset;
            l.dir = rotation * l.dir;
        }
        CurveGeom::Circle(c) => transform_frame(&mut c.frame, rotation, offset),
        CurveGeom::Ellipse(e) => transform_frame(&mut e.frame, rotation, offset),
        CurveGeom::BSpline(b) => {
            // Rational weights are invariant under an affine map of the poles.
            for p in &mut b.poles {
                *p = rotation * *p + offset;
            }
        }
    }
}

fn transform_surface(s: &mut SurfaceGeom, rotation: DMat3, offset: DVec3) {
    match s {
        SurfaceGeom::BSpline(b) => {
            for p in &mut b.poles {
                *p = rotation * *p + offset;
            }
        }
        SurfaceGeom::Plane(p) => transform_frame(&mut p.frame, rotation, offset),
        SurfaceGeom::Cylinder(c) => transform_frame(&mut c.frame, rotation, offset),
        SurfaceGeom::Cone(c) => transform_frame(&mut c.frame, rotation, offset),
        SurfaceGeom::Sphere(c) => transform_frame(&mut c.frame, rotation, offset),
        SurfaceGeom::Torus(c) => transform_frame(&mut c.frame, rotation, offset),
        SurfaceGeom::Revolution(r) => {
            transform_curve(&mut r.meridian, rotation, offset);
            r.axis_origin = rotation * r.axis_origin + offset;
            r.axis_dir = rotation * r.axis_dir;
        }
        SurfaceGeom::Extrusion(e) => {
            transform_curve(&mut e.profile, rotation, offset);
            e.dir = rotation * e.dir;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plane_turned_a_quarter_about_x_faces_minus_y() {
        let mut s = SurfaceGeom::Plane(crate::geometry::surface::Plane {
            frame: Frame::WORLD,
        });
        let r = DMat3::from_rotation_x(std::f64::consts::FRAC_PI_2);
        transform_surface(&mut s, r, DVec3::new(1.0, 2.0, 3.0));
        let SurfaceGeom::Plane(p) = s else {
            panic!("not a plane")
        };
        // Z turned +90° about X is -Y.
        assert!((p.frame.z - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-12);
        assert!((p.frame.origin - DVec3::new(1.0, 2.0, 3.0)).length() < 1e-12);
    }
}
