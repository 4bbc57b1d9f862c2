//! The axis triad: three shaded arrows (X red, Y green, Z blue) drawn in a corner of the view.

use std::f32::consts::TAU;

use glam::{Mat4, Quat, Vec3};

use super::scene::{MeshData, Rgba8};

/// Colours of the X, Y and Z arrows (sRGB).
pub const AXIS_COLOURS: [Rgba8; 3] = [[230, 70, 60, 255], [90, 200, 80, 255], [70, 130, 240, 255]];

/// An arrow along +Z from the origin, length 1: a shaft cylinder and a cone head, with smooth
/// side normals and flat caps.
#[must_use]
pub fn arrow_mesh(segments: u32) -> MeshData {
    let segments = segments.max(3);
    let (shaft_r, head_r, head_start) = (0.045_f32, 0.11_f32, 0.72_f32);
    let mut m = MeshData::default();
    let ring = |m: &mut MeshData, radius: f32, z: f32, normal_z: f32, flat: Option<Vec3>| -> u32 {
        let start = u32::try_from(m.positions.len()).unwrap_or(0);
        for i in 0..segments {
            let a = TAU * i as f32 / segments as f32;
            let (s, c) = a.sin_cos();
            m.positions.push([radius * c, radius * s, z]);
            let n = flat.unwrap_or_else(|| Vec3::new(c, s, normal_z).normalize());
            m.normals.push(n.to_array());
        }
        start
    };
    let band = |m: &mut MeshData, a: u32, b: u32| {
        for i in 0..segments {
            let j = (i + 1) % segments;
            m.indices
                .extend_from_slice(&[a + i, a + j, b + j, a + i, b + j, b + i]);
        }
    };
    // Shaft.
    let s0 = ring(&mut m, shaft_r, 0.0, 0.0, None);
    let s1 = ring(&mut m, shaft_r, head_start, 0.0, None);
    band(&mut m, s0, s1);
    // Head: cone side (normal tilted by the half angle), then its base cap.
    let slope = head_r / (1.0 - head_start);
    let h0 = ring(&mut m, head_r, head_start, slope, None);
    let tip_ring = ring(&mut m, 1e-4, 1.0, slope, None);
    band(&mut m, h0, tip_ring);
    let cap = ring(&mut m, head_r, head_start, 0.0, Some(-Vec3::Z));
    let centre = u32::try_from(m.positions.len()).unwrap_or(0);
    m.positions.push([0.0, 0.0, head_start]);
    m.normals.push([0.0, 0.0, -1.0]);
    for i in 0..segments {
        m.indices
            .extend_from_slice(&[centre, cap + (i + 1) % segments, cap + i]);
    }
    m
}

/// World-from-arrow transforms for the X, Y and Z arrows.
#[must_use]
pub fn axis_transforms() -> [Mat4; 3] {
    [
        Mat4::from_quat(Quat::from_rotation_arc(Vec3::Z, Vec3::X)),
        Mat4::from_quat(Quat::from_rotation_arc(Vec3::Z, Vec3::Y)),
        Mat4::IDENTITY,
    ]
}

/// Where the triad is drawn in a target of `size` pixels: `[x, y, width, height]` from the
/// top-left, or `None` when the target is too small.
#[must_use]
pub fn viewport_rect(size: [u32; 2]) -> Option<[f32; 4]> {
    let (w, h) = (size[0] as f32, size[1] as f32);
    let side = (w.min(h) * 0.16).clamp(56.0, 130.0);
    let margin = 8.0;
    (w > side + 2.0 * margin && h > side + 2.0 * margin).then_some([
        margin,
        h - side - margin,
        side,
        side,
    ])
}

/// Half the extent of the triad's orthographic view (arrows have length 1).
pub const VIEW_HALF_EXTENT: f32 = 1.25;

/// Pixel positions (from the target's top-left) just beyond the X, Y and Z arrow tips, for
/// labels, seen with the camera axes `right` and `up`.
#[must_use]
pub fn label_positions(size: [u32; 2], right: Vec3, up: Vec3) -> Option<[[f32; 2]; 3]> {
    let [x, y, w, h] = viewport_rect(size)?;
    let at = |axis: Vec3| {
        let p = axis * 1.15;
        [
            x + w * 0.5 * (1.0 + p.dot(right) / VIEW_HALF_EXTENT),
            y + h * 0.5 * (1.0 - p.dot(up) / VIEW_HALF_EXTENT),
        ]
    };
    Some([at(Vec3::X), at(Vec3::Y), at(Vec3::Z)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrow_is_valid_and_spans_zero_to_one() {
        let m = arrow_mesh(16);
        assert_eq!(m.problem(), None);
        let (lo, hi) = m.bounds().unwrap_or((Vec3::ZERO, Vec3::ZERO));
        assert!(lo.z.abs() < 1e-6 && (hi.z - 1.0).abs() < 1e-6);
        assert!(
            axis_transforms()[0]
                .transform_vector3(Vec3::Z)
                .abs_diff_eq(Vec3::X, 1e-6)
        );
    }
}
