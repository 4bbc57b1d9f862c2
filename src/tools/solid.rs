//! The cutter as a solid in its own frame: tip at the origin, axis +Z. The solid is rotationally
//! symmetric, so every query reduces to the meridian half-plane `(ρ, z)` (ρ = distance from the
//! axis ≥ 0): the signed Euclidean distance to the solid equals the 2D signed distance to its
//! meridian section, which is bounded by straight segments and circular arcs (the cutting end's
//! profile, the flute cylinder, the shank, the holder sections and the top cap).
//!
//! Signs: negative inside the solid, positive outside, zero on its boundary (mm).

use glam::{DVec2, DVec3};

use super::{Cutter, CutterKind};

/// Which part of the tool a boundary piece or a query belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ToolPart {
    /// The cutting end (ball, flat bottom, corner torus or cone) below the profile height.
    CuttingEnd,
    /// The fluted cylinder between the profile height and the flute length.
    Flutes,
    /// The shank between the flute length and the overall length.
    Shank,
    /// A holder section (index from the holder face upward).
    Holder(usize),
}

/// One boundary piece of the meridian section in the `(ρ, z)` half-plane.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Piece {
    /// Straight segment from `a` to `b`.
    Segment { a: DVec2, b: DVec2 },
    /// Lower-outer quarter arc of the circle around `centre` with `radius`: the angles from −90°
    /// (straight below the centre) to 0° (straight outward), as the ball and corner profiles.
    QuarterArc { centre: DVec2, radius: f64 },
}

impl Piece {
    fn distance(&self, q: DVec2) -> f64 {
        match *self {
            Self::Segment { a, b } => segment_distance(q, a, b),
            Self::QuarterArc { centre, radius } => {
                let d = q - centre;
                if d.x >= 0.0 && d.y <= 0.0 {
                    (d.length() - radius).abs()
                } else {
                    let p0 = centre + DVec2::new(0.0, -radius);
                    let p1 = centre + DVec2::new(radius, 0.0);
                    (q - p0).length().min((q - p1).length())
                }
            }
        }
    }
}

fn segment_distance(q: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((q - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (q - (a + ab * t)).length()
}

/// A cutter's solid: its meridian section as boundary pieces, each tagged with the tool part it
/// bounds. Build with [`Cutter::solid`] (the whole tool up to the top of the holder) or
/// [`Cutter::cutting_solid`] (the fluted part only: cutting end plus flute cylinder, capped at
/// the flute length: a convex solid for every [`CutterKind`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ToolSolid {
    pieces: Vec<(Piece, ToolPart)>,
    /// Steps of the outer radius above the cutting end: `(top height, radius, part)`, bottom up.
    bands: Vec<(f64, f64, ToolPart)>,
    kind: CutterKind,
    radius: f64,
    profile_height: f64,
    top: f64,
}

impl Cutter {
    /// The whole tool as a solid (cutting end, flutes, shank, holder sections), tip at the origin,
    /// axis +Z.
    #[must_use]
    pub fn solid(&self) -> ToolSolid {
        ToolSolid::build(self, true)
    }

    /// The fluted part only (cutting end plus the cylinder up to the flute length, with a flat
    /// cap there): the part that cuts, and a convex solid.
    #[must_use]
    pub fn cutting_solid(&self) -> ToolSolid {
        ToolSolid::build(self, false)
    }
}

impl ToolSolid {
    fn build(c: &Cutter, whole: bool) -> Self {
        let big = c.radius();
        let hp = c.profile_height();
        let mut pieces = Vec::new();
        let end = ToolPart::CuttingEnd;
        match c.kind {
            CutterKind::Ball => pieces.push((
                Piece::QuarterArc {
                    centre: DVec2::new(0.0, big),
                    radius: big,
                },
                end,
            )),
            CutterKind::Flat => pieces.push((
                Piece::Segment {
                    a: DVec2::ZERO,
                    b: DVec2::new(big, 0.0),
                },
                end,
            )),
            CutterKind::BullNose { corner_radius } => {
                let flat = big - corner_radius;
                if flat > 0.0 {
                    pieces.push((
                        Piece::Segment {
                            a: DVec2::ZERO,
                            b: DVec2::new(flat, 0.0),
                        },
                        end,
                    ));
                }
                pieces.push((
                    Piece::QuarterArc {
                        centre: DVec2::new(flat, corner_radius),
                        radius: corner_radius,
                    },
                    end,
                ));
            }
            CutterKind::Cone { .. } => pieces.push((
                Piece::Segment {
                    a: DVec2::ZERO,
                    b: DVec2::new(big, hp),
                },
                end,
            )),
        }
        let mut bands = vec![(c.flute_length, big, ToolPart::Flutes)];
        if whole {
            bands.push((c.overall_length, 0.5 * c.shank_diameter, ToolPart::Shank));
            let mut top = c.overall_length;
            for (i, h) in c.holder.iter().enumerate() {
                top += h.length;
                bands.push((top, 0.5 * h.diameter, ToolPart::Holder(i)));
            }
        }
        // Walls and steps: from the end of the profile (big, hp) up through the bands.
        let mut z = hp;
        let mut r = big;
        for &(top, radius, part) in &bands {
            if (radius - r).abs() > 0.0 {
                pieces.push((
                    Piece::Segment {
                        a: DVec2::new(r, z),
                        b: DVec2::new(radius, z),
                    },
                    part,
                ));
            }
            if top > z {
                pieces.push((
                    Piece::Segment {
                        a: DVec2::new(radius, z),
                        b: DVec2::new(radius, top),
                    },
                    part,
                ));
            }
            z = z.max(top);
            r = radius;
        }
        let last = bands.last().map_or(ToolPart::Flutes, |b| b.2);
        pieces.push((
            Piece::Segment {
                a: DVec2::new(r, z),
                b: DVec2::new(0.0, z),
            },
            last,
        ));
        Self {
            pieces,
            bands,
            kind: c.kind,
            radius: big,
            profile_height: hp,
            top: z,
        }
    }

    /// Height of the top of the solid above the tip, mm.
    #[must_use]
    pub fn top(&self) -> f64 {
        self.top
    }

    /// Largest radius of the solid, mm.
    #[must_use]
    pub fn max_radius(&self) -> f64 {
        self.bands.iter().fold(self.radius, |m, b| m.max(b.1))
    }

    /// Radius of the solid at height `z` above the tip, mm (the profile of the cutting end, then
    /// the bands); `None` below the tip, above the top or for non-finite `z`.
    #[must_use]
    pub fn radius_at_height(&self, z: f64) -> Option<f64> {
        if !(z >= 0.0 && z <= self.top) {
            return None;
        }
        if z < self.profile_height {
            let big = self.radius;
            return Some(match self.kind {
                CutterKind::Ball => (big * big - (big - z) * (big - z)).max(0.0).sqrt(),
                CutterKind::Flat => big,
                CutterKind::BullNose { corner_radius } => {
                    let q = corner_radius - z;
                    big - corner_radius + (corner_radius * corner_radius - q * q).max(0.0).sqrt()
                }
                CutterKind::Cone { half_angle } => z * half_angle.tan(),
            });
        }
        self.bands
            .iter()
            .find(|b| z <= b.0)
            .map(|b| b.1)
            .or(Some(self.radius))
    }

    /// Signed distance in the meridian half-plane: `rho` ≥ 0 from the axis, `z` along it (tip at
    /// 0), mm; negative inside.
    #[must_use]
    pub fn signed_distance_rz(&self, rho: f64, z: f64) -> f64 {
        self.signed_distance_part_rz(rho, z).0
    }

    /// As [`Self::signed_distance_rz`], with the tool part owning the nearest boundary piece.
    #[must_use]
    pub fn signed_distance_part_rz(&self, rho: f64, z: f64) -> (f64, ToolPart) {
        let q = DVec2::new(rho.abs(), z);
        let mut best = (f64::INFINITY, ToolPart::CuttingEnd);
        for &(piece, part) in &self.pieces {
            let d = piece.distance(q);
            if d < best.0 {
                best = (d, part);
            }
        }
        let inside = self.radius_at_height(z).is_some_and(|r| q.x < r);
        if inside {
            best.0 = -best.0;
        }
        best
    }

    /// Signed distance of a point given in the tool frame (tip at the origin, axis +Z), mm.
    #[must_use]
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        self.signed_distance_rz(p.x.hypot(p.y), p.z)
    }

    /// Signed distance of a part-space point `p` to this solid placed with its tip at `tip` and
    /// its unit axis `axis`, mm.
    #[must_use]
    pub fn signed_distance_at(&self, p: DVec3, tip: DVec3, axis: DVec3) -> f64 {
        let d = p - tip;
        let z = d.dot(axis);
        let rho = (d - axis * z).length();
        self.signed_distance_rz(rho, z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::HolderSection;

    fn near(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn ball_matches_sphere_and_cylinder() {
        let c = Cutter::new(CutterKind::Ball, 6.0).expect("valid");
        let s = c.cutting_solid();
        // Below the centre: distance to the sphere of radius 3 around (0, 0, 3).
        for p in [
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(1.0, 2.0, 0.5),
            DVec3::new(0.5, 0.0, 2.0),
            DVec3::new(5.0, 1.0, 1.0),
        ] {
            let want = (p - DVec3::new(0.0, 0.0, 3.0)).length() - 3.0;
            assert!(near(s.signed_distance(p), want), "{p} {want}");
        }
        // Beside the flutes: distance to the cylinder of radius 3.
        assert!(near(s.signed_distance(DVec3::new(4.0, 0.0, 10.0)), 1.0));
        assert!(near(s.signed_distance(DVec3::new(0.0, 2.5, 10.0)), -0.5));
        // Above the flute cap.
        assert!(near(s.signed_distance(DVec3::new(1.0, 0.0, 20.0)), 2.0));
    }

    #[test]
    fn flat_bull_and_cone_closed_forms() {
        let flat = Cutter::new(CutterKind::Flat, 10.0)
            .expect("valid")
            .cutting_solid();
        assert!(near(flat.signed_distance(DVec3::new(2.0, 1.0, -0.3)), 0.3));
        assert!(near(flat.signed_distance(DVec3::new(2.0, 1.0, 0.3)), -0.3));
        assert!(near(flat.signed_distance(DVec3::new(8.0, 0.0, -4.0)), 5.0));
        let bull = Cutter::new(CutterKind::BullNose { corner_radius: 2.0 }, 10.0)
            .expect("valid")
            .cutting_solid();
        // Corner torus: tube centre at ρ = 3, z = 2, radius 2.
        let q = DVec3::new(5.0, 0.0, -1.0);
        let want = DVec2::new(2.0, -3.0).length() - 2.0;
        assert!(near(bull.signed_distance(q), want));
        assert!(near(
            bull.signed_distance(DVec3::new(0.0, 1.0, -0.25)),
            0.25
        ));
        let alpha: f64 = 0.5;
        let cone = Cutter::new(CutterKind::Cone { half_angle: alpha }, 10.0)
            .expect("valid")
            .cutting_solid();
        // Point below the flank: distance to the line ρ = z tan α.
        let (rho, z) = (1.0, 0.5);
        let want = rho * alpha.cos() - z * alpha.sin();
        assert!(near(cone.signed_distance(DVec3::new(rho, 0.0, z)), want));
    }

    #[test]
    fn shank_and_holder_steps() {
        let mut c = Cutter::new(CutterKind::Flat, 10.0).expect("valid");
        c.shank_diameter = 8.0;
        c.holder = vec![HolderSection {
            diameter: 30.0,
            length: 20.0,
        }];
        c.validate().expect("valid");
        let s = c.solid();
        assert!(near(s.top(), c.overall_length + 20.0));
        let mid_shank = 0.5 * (c.flute_length + c.overall_length);
        assert!(near(
            s.signed_distance(DVec3::new(6.0, 0.0, mid_shank)),
            2.0
        ));
        assert_eq!(s.radius_at_height(mid_shank), Some(4.0));
        let (d, part) = s.signed_distance_part_rz(20.0, c.overall_length + 10.0);
        assert!(near(d, 5.0));
        assert_eq!(part, ToolPart::Holder(0));
        assert!(near(s.max_radius(), 15.0));
    }

    #[test]
    fn placed_solid_uses_axis() {
        let c = Cutter::new(CutterKind::Ball, 4.0).expect("valid");
        let s = c.cutting_solid();
        let tip = DVec3::new(1.0, 2.0, 3.0);
        let axis = DVec3::new(1.0, 0.0, 0.0);
        let centre = tip + axis * 2.0;
        let p = DVec3::new(-1.0, 2.0, 4.0);
        let want = (p - centre).length() - 2.0;
        assert!(near(s.signed_distance_at(p, tip, axis), want));
    }
}
