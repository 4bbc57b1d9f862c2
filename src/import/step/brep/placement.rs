//! Rigid placements of assembly components and mapped items: a rotation plus a translation, and
//! its application to every geometry kind the B-rep carries.

use glam::{DMat3, DVec3};

use crate::geometry::curve::{Circle, CurveGeom, Ellipse, Line};
use crate::geometry::frame::Frame;
use crate::geometry::nurbs::{BSplineCurve, BSplineSurface};
use crate::geometry::surface::{
    Cone, Cylinder, Extrusion, Plane, Revolution, Sphere, SurfaceGeom, Torus,
};

/// A rigid motion `p ↦ rot·p + shift` (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rigid {
    /// Rotation (orthonormal, determinant +1).
    pub rot: DMat3,
    /// Translation, mm.
    pub shift: DVec3,
}

impl Rigid {
    /// No motion.
    pub const IDENTITY: Self = Self {
        rot: DMat3::IDENTITY,
        shift: DVec3::ZERO,
    };

    /// The motion taking the frame `from` onto the frame `to` (origin to origin, axes to axes):
    /// `to_world ∘ from_local`.
    #[must_use]
    pub fn between(from: &Frame, to: &Frame) -> Self {
        let r_from = DMat3::from_cols(from.x, from.y, from.z);
        let r_to = DMat3::from_cols(to.x, to.y, to.z);
        let rot = r_to * r_from.transpose();
        Self {
            rot,
            shift: to.origin - rot * from.origin,
        }
    }

    /// `self ∘ inner`: apply `inner` first.
    #[must_use]
    pub fn then_after(&self, inner: &Self) -> Self {
        Self {
            rot: self.rot * inner.rot,
            shift: self.rot * inner.shift + self.shift,
        }
    }

    /// The inverse motion.
    #[must_use]
    pub fn inverse(&self) -> Self {
        let rot = self.rot.transpose();
        Self {
            rot,
            shift: -(rot * self.shift),
        }
    }

    /// Move a point.
    #[must_use]
    pub fn point(&self, p: DVec3) -> DVec3 {
        self.rot * p + self.shift
    }

    /// Turn a vector (no translation).
    #[must_use]
    pub fn vector(&self, v: DVec3) -> DVec3 {
        self.rot * v
    }

    /// Move a frame.
    #[must_use]
    pub fn frame(&self, f: &Frame) -> Frame {
        Frame {
            origin: self.point(f.origin),
            x: self.vector(f.x),
            y: self.vector(f.y),
            z: self.vector(f.z),
        }
    }

    /// Move a curve.
    #[must_use]
    pub fn curve(&self, c: &CurveGeom) -> CurveGeom {
        match c {
            CurveGeom::Line(l) => CurveGeom::Line(Line {
                origin: self.point(l.origin),
                dir: self.vector(l.dir),
            }),
            CurveGeom::Circle(k) => CurveGeom::Circle(Circle {
                frame: self.frame(&k.frame),
                radius: k.radius,
            }),
            CurveGeom::Ellipse(e) => CurveGeom::Ellipse(Ellipse {
                frame: self.frame(&e.frame),
                ..*e
            }),
            CurveGeom::BSpline(b) => CurveGeom::BSpline(BSplineCurve {
                poles: b.poles.iter().map(|p| self.point(*p)).collect(),
                ..b.clone()
            }),
        }
    }

    /// Move a surface.
    #[must_use]
    pub fn surface(&self, s: &SurfaceGeom) -> SurfaceGeom {
        match s {
            SurfaceGeom::BSpline(b) => SurfaceGeom::BSpline(BSplineSurface {
                poles: b.poles.iter().map(|p| self.point(*p)).collect(),
                ..b.clone()
            }),
            SurfaceGeom::Plane(p) => SurfaceGeom::Plane(Plane {
                frame: self.frame(&p.frame),
            }),
            SurfaceGeom::Cylinder(c) => SurfaceGeom::Cylinder(Cylinder {
                frame: self.frame(&c.frame),
                ..*c
            }),
            SurfaceGeom::Cone(c) => SurfaceGeom::Cone(Cone {
                frame: self.frame(&c.frame),
                ..*c
            }),
            SurfaceGeom::Sphere(c) => SurfaceGeom::Sphere(Sphere {
                frame: self.frame(&c.frame),
                ..*c
            }),
            SurfaceGeom::Torus(t) => SurfaceGeom::Torus(Torus {
                frame: self.frame(&t.frame),
                ..*t
            }),
            SurfaceGeom::Revolution(r) => SurfaceGeom::Revolution(Revolution {
                meridian: Box::new(self.curve(&r.meridian)),
                axis_origin: self.point(r.axis_origin),
                axis_dir: self.vector(r.axis_dir),
            }),
            SurfaceGeom::Extrusion(e) => SurfaceGeom::Extrusion(Extrusion {
                profile: Box::new(self.curve(&e.profile)),
                dir: self.vector(e.dir),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(o: DVec3, z: DVec3, x: DVec3) -> Frame {
        Frame::from_axis_ref(o, z, Some(x)).unwrap()
    }

    #[test]
    fn between_maps_frame_onto_frame_and_inverts() {
        let a = frame(
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(0.0, 1.0, 1.0),
            DVec3::X,
        );
        let b = frame(
            DVec3::new(-4.0, 0.5, 7.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::Y,
        );
        let t = Rigid::between(&a, &b);
        let moved = t.frame(&a);
        assert!((moved.origin - b.origin).length() < 1e-12);
        assert!((moved.x - b.x).length() < 1e-12 && (moved.z - b.z).length() < 1e-12);
        // A point given in a's local coordinates lands at the same local coordinates in b.
        let local = DVec3::new(0.3, -2.0, 5.0);
        assert!((t.point(a.to_world(local)) - b.to_world(local)).length() < 1e-12);
        let round = t.inverse().then_after(&t);
        assert!((round.point(local) - local).length() < 1e-12);
        assert!(Rigid::between(&a, &a).point(local).distance(local) < 1e-12);
    }

    #[test]
    fn curves_and_surfaces_move_rigidly() {
        let t = Rigid::between(
            &Frame::WORLD,
            &frame(DVec3::new(10.0, 0.0, 0.0), DVec3::Y, DVec3::Z),
        );
        let c = t.curve(&CurveGeom::Circle(Circle {
            frame: Frame::WORLD,
            radius: 2.0,
        }));
        let CurveGeom::Circle(c) = c else {
            panic!("kind changed")
        };
        assert!((c.frame.origin - DVec3::new(10.0, 0.0, 0.0)).length() < 1e-12);
        assert!((c.frame.z - DVec3::Y).length() < 1e-12);
        assert!((c.radius - 2.0).abs() < 1e-15);
        let s = t.surface(&SurfaceGeom::Sphere(Sphere {
            frame: Frame::WORLD,
            radius: 3.0,
        }));
        assert_eq!(s.kind(), "sphere");
        let l = t.curve(&CurveGeom::Line(Line {
            origin: DVec3::ZERO,
            dir: DVec3::X,
        }));
        let CurveGeom::Line(l) = l else {
            panic!("kind changed")
        };
        // World X maps to the target frame's x axis (Z).
        assert!((l.dir - DVec3::Z).length() < 1e-12);
    }
}
