//! The tool model in the viewport: the cutter's real profile (ball, flat, bull-nose, cone), its
//! flutes and shank, and its holder (a generic collet holder when the tool names none),
//! revolved by [`crate::render::glyphs`] and placed at the tool's tip along its axis; and the
//! work-offset marker.

use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;

use glam::{DVec3, Mat4, Quat, Vec3};

use super::ViewportState;
use crate::render::glyphs::{axes_marker, revolved_mesh};
use crate::render::{BoundingSphere, DataId, LineData, LineInstance, MeshData, MeshInstance};
use crate::tools::{Cutter, CutterKind};

/// Colour of the tool (sRGB): a darker, bluer metal than the part.
pub const TOOL_COLOUR: [u8; 4] = [104, 128, 178, 255];
/// Steps of a quarter arc in the profile (ball, corner radius).
const ARC_STEPS: usize = 12;
/// Steps around the axis.
const SEGMENTS: u32 = 48;
/// Length of the work-offset marker's axes as a fraction of the part's size.
const MARKER_FRACTION: f32 = 0.2;

/// Where the tool is: its tip and axis, and which cutter it is.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolPose {
    /// The tool tip (the lowest point on the axis), mm.
    pub tip: DVec3,
    /// Unit tool axis from the tip toward the holder.
    pub axis: DVec3,
    /// The cutter (profile, flutes, shank, holder).
    pub cutter: Cutter,
}

/// The tool's outline in its own frame as (radius, z) points from the tip on the axis upward
/// (mm): the cutting end's profile, the fluted cylinder up to the flute length, the shank up to
/// the overall length, then the holder sections, or a generic collet holder (nut, cone and body
/// scaled to the shank) when the cutter has none.
#[must_use]
pub fn tool_profile(cutter: &Cutter) -> Vec<[f32; 2]> {
    let big = cutter.radius().max(0.0);
    let mut p: Vec<[f64; 2]> = vec![[0.0, 0.0]];
    let arc = |p: &mut Vec<[f64; 2]>, centre: [f64; 2], r: f64| {
        // From straight below the centre to straight outward.
        for i in 1..=ARC_STEPS {
            let a = -FRAC_PI_2 * (1.0 - i as f64 / ARC_STEPS as f64);
            p.push([centre[0] + r * a.cos(), centre[1] + r * a.sin()]);
        }
    };
    match cutter.kind {
        CutterKind::Ball => arc(&mut p, [0.0, big], big),
        CutterKind::Flat => p.push([big, 0.0]),
        CutterKind::BullNose { corner_radius } => {
            let r = corner_radius.clamp(0.0, big);
            p.push([big - r, 0.0]);
            arc(&mut p, [big - r, r], r);
        }
        CutterKind::Cone { half_angle } => {
            let t = half_angle.tan();
            let h = if t > 0.0 && t.is_finite() {
                big / t
            } else {
                0.0
            };
            p.push([big, h]);
        }
    }
    let flute = cutter.flute_length.max(cutter.profile_height());
    p.push([big, flute]);
    let shank = 0.5 * cutter.shank_diameter.max(0.0);
    let top = cutter.overall_length.max(flute);
    p.push([shank, flute]);
    p.push([shank, top]);
    let mut z = top;
    if cutter.holder.is_empty() {
        // A generic collet holder: nut, cone, body.
        let nut = 1.8 * shank + 2.0;
        let body = 2.6 * shank + 8.0;
        let nut_length = 3.0 * shank + 10.0;
        for [r, dz] in [
            [nut, 0.0],
            [nut, nut_length],
            [body, 0.5 * nut_length],
            [body, nut_length],
        ] {
            z += dz;
            p.push([r, z]);
        }
    } else {
        for section in &cutter.holder {
            let r = 0.5 * section.diameter.max(0.0);
            p.push([r, z]);
            z += section.length.max(0.0);
            p.push([r, z]);
        }
    }
    p.into_iter()
        .filter(|q| q.iter().all(|v| v.is_finite()))
        .map(|[r, z]| [r as f32, z as f32])
        .collect()
}

/// World-from-tool: the tool frame's origin at `tip`, its +Z along `axis` (+Z when the axis is
/// not a usable direction).
#[must_use]
pub fn world_from_tool(tip: DVec3, axis: DVec3) -> Mat4 {
    let axis = axis.as_vec3().try_normalize().unwrap_or(Vec3::Z);
    Mat4::from_rotation_translation(Quat::from_rotation_arc(Vec3::Z, axis), tip.as_vec3())
}

/// The cached tool mesh: rebuilt only when the cutter changes.
#[derive(Debug)]
pub(super) struct ToolMesh {
    cutter: Cutter,
    id: DataId,
    data: Arc<MeshData>,
}

/// The cached work-offset marker, per marker size.
#[derive(Debug)]
pub(super) struct MarkerLines {
    size_bits: u32,
    id: DataId,
    data: Arc<LineData>,
}

impl ViewportState {
    /// The tool mesh at its pose and the work-offset marker (sized to `part_size` mm), when set.
    pub(super) fn tool_and_marker(
        &mut self,
        part_size: f32,
    ) -> (Option<MeshInstance>, Option<LineInstance>) {
        let tool = self.tool_pose.clone().map(|pose| {
            if self
                .tool_mesh
                .as_ref()
                .is_none_or(|m| m.cutter != pose.cutter)
            {
                self.next_id += 1;
                let data = Arc::new(revolved_mesh(&tool_profile(&pose.cutter), SEGMENTS));
                self.tool_mesh = Some(ToolMesh {
                    cutter: pose.cutter.clone(),
                    id: self.next_id,
                    data,
                });
            }
            let (id, data) = self
                .tool_mesh
                .as_ref()
                .map_or((0, Arc::default()), |m| (m.id, Arc::clone(&m.data)));
            MeshInstance {
                id,
                data,
                world_from_mesh: world_from_tool(pose.tip, pose.axis),
                colour: TOOL_COLOUR,
                scalar_map: None,
            }
        });
        let marker = self.work_offset.map(|world_from_frame| {
            let size = if part_size.is_finite() && part_size > 0.0 {
                MARKER_FRACTION * part_size
            } else {
                20.0
            };
            if self
                .marker_lines
                .as_ref()
                .is_none_or(|m| m.size_bits != size.to_bits())
            {
                self.next_id += 1;
                self.marker_lines = Some(MarkerLines {
                    size_bits: size.to_bits(),
                    id: self.next_id,
                    data: Arc::new(axes_marker(size)),
                });
            }
            let (id, data) = self
                .marker_lines
                .as_ref()
                .map_or((0, Arc::default()), |m| (m.id, Arc::clone(&m.data)));
            LineInstance {
                id,
                data,
                world_from_lines: world_from_frame,
                draw_segments: None,
            }
        });
        (tool, marker)
    }
}

/// The smallest sphere about `sphere`'s centre that also holds the box (`lo`, `hi`).
#[must_use]
pub fn enclose(sphere: BoundingSphere, lo: Vec3, hi: Vec3) -> BoundingSphere {
    let far = (0..8)
        .map(|i| {
            let corner = Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            corner.distance(sphere.centre)
        })
        .fold(sphere.radius, f32::max);
    BoundingSphere {
        centre: sphere.centre,
        radius: far,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cutter(kind: CutterKind, d: f64) -> Cutter {
        Cutter::new(kind, d).expect("valid")
    }

    #[test]
    fn the_profile_follows_the_engine_s_radius_at_height() {
        // Reference: Cutter::radius_at_height, the engine's own description of the tool.
        let kinds = [
            CutterKind::Ball,
            CutterKind::Flat,
            CutterKind::BullNose { corner_radius: 1.5 },
            CutterKind::Cone {
                half_angle: 30.0_f64.to_radians(),
            },
        ];
        for kind in kinds {
            let mut c = cutter(kind, 10.0);
            c.shank_diameter = 8.0;
            c.holder = vec![crate::tools::HolderSection {
                diameter: 20.0,
                length: 30.0,
            }];
            let p = tool_profile(&c);
            assert_eq!(p.first(), Some(&[0.0, 0.0]), "{kind:?} starts at the tip");
            // Every profile vertex strictly between steps lies on the engine's outline.
            for w in p.windows(3) {
                let [r, z] = w[1];
                if w[0][1] == z || w[2][1] == z {
                    continue; // a horizontal step: two radii at one height
                }
                let expected = c.radius_at_height(f64::from(z)).expect("inside the tool");
                assert!(
                    (f64::from(r) - expected).abs() < 1e-4,
                    "{kind:?} at z {z}: {r} vs {expected}"
                );
            }
            let top = p.last().expect("points");
            assert!((f64::from(top[1]) - (c.overall_length + 30.0)).abs() < 1e-4);
            assert!((top[0] - 10.0).abs() < 1e-6);
        }
    }

    #[test]
    fn a_tool_without_holder_gets_a_generic_one_wider_than_the_shank() {
        let c = cutter(CutterKind::Ball, 6.0);
        let p = tool_profile(&c);
        let above: Vec<_> = p
            .iter()
            .filter(|q| f64::from(q[1]) > c.overall_length + 1e-6)
            .collect();
        assert!(!above.is_empty());
        assert!(
            above
                .iter()
                .all(|q| f64::from(q[0]) > 0.5 * c.shank_diameter)
        );
        let m = revolved_mesh(&p, SEGMENTS);
        assert_eq!(m.problem(), None);
    }

    #[test]
    fn the_tool_frame_puts_the_tip_and_axis_in_place() {
        let tip = DVec3::new(10.0, -5.0, 3.0);
        let axis = DVec3::new(1.0, 0.0, 1.0).normalize();
        let m = world_from_tool(tip, axis);
        assert!((m.transform_point3(Vec3::ZERO) - tip.as_vec3()).length() < 1e-5);
        let up = m.transform_point3(Vec3::Z * 10.0);
        assert!((up - (tip + axis * 10.0).as_vec3()).length() < 1e-4);
        let fallback = world_from_tool(tip, DVec3::ZERO);
        assert!((fallback.transform_vector3(Vec3::Z) - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn meshes_are_cached_until_the_cutter_changes() {
        let mut state = ViewportState {
            tool_pose: Some(ToolPose {
                tip: DVec3::ZERO,
                axis: DVec3::Z,
                cutter: cutter(CutterKind::Ball, 6.0),
            }),
            work_offset: Some(Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0))),
            ..ViewportState::default()
        };
        let (t1, m1) = state.tool_and_marker(100.0);
        if let Some(p) = state.tool_pose.as_mut() {
            p.tip = DVec3::new(5.0, 0.0, 0.0);
        }
        let (t2, m2) = state.tool_and_marker(100.0);
        let (t1, t2, m1, m2) = (
            t1.expect("tool"),
            t2.expect("tool"),
            m1.expect("marker"),
            m2.expect("marker"),
        );
        assert_eq!(t1.id, t2.id);
        assert!(Arc::ptr_eq(&t1.data, &t2.data));
        assert_eq!(m1.id, m2.id);
        if let Some(p) = state.tool_pose.as_mut() {
            p.cutter = cutter(CutterKind::Flat, 6.0);
        }
        let (t3, _) = state.tool_and_marker(100.0);
        assert_ne!(t3.expect("tool").id, t1.id);
        // The marker is a fifth of the part long, at the work offset.
        let (lo, hi) = m1.data.bounds().expect("lines");
        assert!((hi.max_element() - 20.0).abs() < 1e-4 && lo.min_element() > -5.0);
        let origin = m1.world_from_lines.transform_point3(Vec3::ZERO);
        assert!((origin - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
    }
}
