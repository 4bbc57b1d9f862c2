//! Glyph geometry built on the render side: solids of revolution (the tool model) and the
//! work-offset axes marker. Plain data in ([`MeshData`], [`LineData`]); no engine types.

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};

use super::scene::{LineData, MeshData};
use super::triad::AXIS_COLOURS;

/// Profile corners sharper than this (between neighbouring segments' normals) get split normals;
/// gentler bends are shaded smooth.
const CREASE_COS: f32 = 0.866; // cos 30°

/// Shortest profile segment kept, in the profile's units (shorter ones are dropped).
const MIN_SEGMENT: f32 = 1e-6;

/// A solid of revolution about +Z.
///
/// `profile` is a list of (radius, z) points, ordered so that the solid lies on the left when
/// walking along it in the (radius, z) half-plane: for a tool, from the tip on the axis upward
/// (radius ≥ 0; negative or non-finite points are ignored). `segments` (at least 3) is the number
/// of steps around the axis. Normals are smooth along the profile except at corners sharper than
/// 30°, which are creased; the ends are closed by flat caps where their radius is positive.
#[must_use]
pub fn revolved_mesh(profile: &[[f32; 2]], segments: u32) -> MeshData {
    let segments = segments.max(3);
    let mut points: Vec<Vec2> = Vec::with_capacity(profile.len());
    for p in profile {
        let q = Vec2::from_array(*p);
        // A radius a rounding error below zero is on the axis.
        if !(q.is_finite() && q.x >= -MIN_SEGMENT) {
            continue;
        }
        let q = Vec2::new(q.x.max(0.0), q.y);
        if points.last().is_none_or(|l| l.distance(q) > MIN_SEGMENT) {
            points.push(q);
        }
    }
    let mut mesh = MeshData::default();
    let (Some(&first), Some(&last)) = (points.first(), points.last()) else {
        return mesh;
    };
    if first.x > MIN_SEGMENT {
        add_band(
            &mut mesh,
            segments,
            [Vec2::new(0.0, first.y), first],
            [None, None],
        );
    }
    // Outward normal of each segment: (dz, −dr), the right-hand side of the walk.
    let normals: Vec<Vec2> = points
        .windows(2)
        .map(|w| segment_normal(w[0], w[1]))
        .collect();
    for (i, w) in points.windows(2).enumerate() {
        let n = normals[i];
        let joined = |other: Option<&Vec2>| {
            other
                .filter(|o| o.dot(n) >= CREASE_COS)
                .map(|o| (*o + n).normalize_or(n))
        };
        let start = joined(i.checked_sub(1).and_then(|j| normals.get(j)));
        let end = joined(normals.get(i + 1));
        add_band(&mut mesh, segments, [w[0], w[1]], [start, end]);
    }
    if last.x > MIN_SEGMENT && points.len() > 1 {
        add_band(
            &mut mesh,
            segments,
            [last, Vec2::new(0.0, last.y)],
            [None, None],
        );
    }
    mesh
}

fn segment_normal(a: Vec2, b: Vec2) -> Vec2 {
    let d = b - a;
    Vec2::new(d.y, -d.x).normalize_or(Vec2::X)
}

/// The surface swept by the segment `ends` (radius, z) about +Z, with the profile normals at its
/// two ends (`None`: the segment's own normal).
fn add_band(mesh: &mut MeshData, segments: u32, ends: [Vec2; 2], normals: [Option<Vec2>; 2]) {
    let own = segment_normal(ends[0], ends[1]);
    let Ok(base) = u32::try_from(mesh.positions.len()) else {
        return;
    };
    for (p, n) in ends.iter().zip(normals) {
        let n = n.unwrap_or(own);
        for k in 0..segments {
            let (s, c) = (TAU * k as f32 / segments as f32).sin_cos();
            mesh.positions.push([p.x * c, p.x * s, p.y]);
            mesh.normals.push([n.x * c, n.x * s, n.y]);
        }
    }
    for k in 0..segments {
        let j = (k + 1) % segments;
        let (a0, a1, b0, b1) = (base + k, base + j, base + segments + k, base + segments + j);
        mesh.indices.extend_from_slice(&[a0, a1, b1, a0, b1, b0]);
    }
}

/// A work-offset marker: three axes from the origin, `size` long, X red, Y green, Z blue (the
/// triad's colours), each with a small four-line arrow head at its end.
#[must_use]
pub fn axes_marker(size: f32) -> LineData {
    let size = if size.is_finite() && size > 0.0 {
        size
    } else {
        1.0
    };
    let (head_length, head_width) = (0.18 * size, 0.06 * size);
    let axes = [Vec3::X, Vec3::Y, Vec3::Z];
    let mut lines = LineData::default();
    for (k, axis) in axes.iter().enumerate() {
        let colour = AXIS_COLOURS[k];
        let tip = *axis * size;
        lines.push_polyline(&[[0.0; 3], tip.to_array()], colour);
        let back = tip - *axis * head_length;
        for side in [axes[(k + 1) % 3], axes[(k + 2) % 3]] {
            for sign in [-1.0, 1.0] {
                let barb = back + side * (sign * head_width);
                lines.push_polyline(&[tip.to_array(), barb.to_array()], colour);
            }
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(p: [f32; 3]) -> Vec3 {
        Vec3::from_array(p)
    }

    /// Signed volume by the divergence theorem (outward-wound triangles give a positive volume).
    fn volume(m: &MeshData) -> f32 {
        m.indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|i| v(m.positions[t[i] as usize]));
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn a_closed_cylinder_has_the_closed_form_volume_and_outward_normals() {
        let (r, h, n) = (2.0_f32, 5.0_f32, 256);
        let m = revolved_mesh(&[[r, 0.0], [r, h]], n);
        assert_eq!(m.problem(), None);
        // An inscribed n-gon prism: (n/2) r² sin(2π/n) h.
        let expected = 0.5 * n as f32 * r * r * (TAU / n as f32).sin() * h;
        assert!(
            (volume(&m) - expected).abs() < 1e-3 * expected,
            "{} vs {expected}",
            volume(&m)
        );
        // Every normal points away from the centre of the solid.
        let centre = Vec3::new(0.0, 0.0, h / 2.0);
        for (p, nrm) in m.positions.iter().zip(&m.normals) {
            assert!(v(*nrm).dot(v(*p) - centre) > 0.0, "{p:?} {nrm:?}");
        }
        // Creased: the caps' normals are ±Z, the sides' horizontal.
        assert!(m.normals.iter().any(|n| (v(*n) - Vec3::Z).length() < 1e-6));
        assert!(m.normals.iter().any(|n| (v(*n) + Vec3::Z).length() < 1e-6));
    }

    #[test]
    fn a_hemisphere_profile_has_smooth_radial_normals_and_a_top_cap() {
        // Ball of radius 3 centred at z = 3, lower half, from the tip up to the equator.
        let r = 3.0_f32;
        let profile: Vec<[f32; 2]> = (0..=32)
            .map(|i| {
                let a = -std::f32::consts::FRAC_PI_2 * (1.0 - i as f32 / 32.0);
                [r * a.cos(), r + r * a.sin()]
            })
            .collect();
        let m = revolved_mesh(&profile, 64);
        assert_eq!(m.problem(), None);
        let centre = Vec3::new(0.0, 0.0, r);
        let mut checked = 0;
        for (p, n) in m.positions.iter().zip(&m.normals) {
            let p = v(*p);
            if (v(*n) - Vec3::Z).length() < 1e-6 {
                continue; // the cap
            }
            let radial = (p - centre).normalize();
            // Smooth: within half a profile step (π/64) of the exact sphere normal.
            assert!(
                radial.dot(v(*n).normalize()) > (TAU / 256.0).cos() - 1e-4,
                "{p} {n:?}"
            );
            checked += 1;
        }
        assert!(checked > 64 * 32);
        // Volume of the half ball, (2/3) π r³, within the polygonal shortfall.
        let expected = 2.0 / 3.0 * std::f32::consts::PI * r.powi(3);
        assert!((volume(&m) - expected).abs() < 0.01 * expected);
    }

    #[test]
    fn bad_points_are_skipped_and_nothing_gives_an_empty_mesh() {
        assert_eq!(revolved_mesh(&[], 16), MeshData::default());
        let m = revolved_mesh(&[[f32::NAN, 0.0], [1.0, 0.0], [-1.0, 1.0], [1.0, 2.0]], 2);
        assert_eq!(m.problem(), None);
        assert!(m.positions.iter().all(|p| p.iter().all(|c| c.is_finite())));
    }

    #[test]
    fn the_axes_marker_has_coloured_axes_of_the_given_length() {
        let l = axes_marker(10.0);
        assert_eq!(l.problem(), None);
        // One shaft and four barbs per axis.
        assert_eq!(l.segment_count(), 15);
        for (k, axis) in [Vec3::X, Vec3::Y, Vec3::Z].iter().enumerate() {
            let tip = *axis * 10.0;
            let tip_vertex = l
                .positions
                .iter()
                .position(|p| (v(*p) - tip).length() < 1e-6)
                .expect("the axis reaches its tip");
            assert_eq!(l.colours[tip_vertex], AXIS_COLOURS[k]);
        }
        let (lo, hi) = l.bounds().expect("bounds");
        assert!(lo.min_element() > -1.0 && (hi - Vec3::splat(10.0)).length() < 1e-5);
    }
}
