//! What to draw: meshes and line sets (with stable ids so the GPU copies are reused across
//! frames), the camera, and display options. Plain data; no GPU types.

use std::sync::Arc;

use glam::{Mat4, Vec3};

use super::camera::Camera;
use super::colour_map::ColourMap;

/// An sRGB colour with alpha, 0..255 per channel.
pub type Rgba8 = [u8; 4];

/// Triangle mesh data in f32 world units (mm).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Per-vertex normals (need not be unit length; same length as `positions`).
    pub normals: Vec<[f32; 3]>,
    /// Optional per-vertex scalar shown through the colour map (empty: none).
    pub scalars: Vec<f32>,
    /// Vertex indices, three per triangle.
    pub indices: Vec<u32>,
}

impl MeshData {
    /// Flat-shaded data of a triangle mesh (mm): each triangle its own three vertices and its
    /// face normal (an index out of range reads as the origin).
    #[must_use]
    pub fn flat(vertices: &[glam::DVec3], triangles: &[[u32; 3]]) -> Self {
        let mut out = Self::default();
        for t in triangles {
            let p = t.map(|i| {
                vertices
                    .get(i as usize)
                    .copied()
                    .unwrap_or(glam::DVec3::ZERO)
            });
            let n = (p[1] - p[0])
                .cross(p[2] - p[0])
                .normalize_or_zero()
                .as_vec3();
            for q in p {
                let i = u32::try_from(out.positions.len()).unwrap_or(u32::MAX);
                out.positions.push(q.as_vec3().to_array());
                out.normals.push(n.to_array());
                out.indices.push(i);
            }
        }
        out
    }

    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Axis-aligned bounds (`None` when there is no vertex).
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        bounds_of(&self.positions)
    }

    /// Why the data cannot be drawn as it is, if it cannot.
    #[must_use]
    pub fn problem(&self) -> Option<String> {
        let n = self.positions.len();
        if self.normals.len() != n {
            return Some(format!("{} normals for {n} vertices", self.normals.len()));
        }
        if !self.scalars.is_empty() && self.scalars.len() != n {
            return Some(format!("{} scalars for {n} vertices", self.scalars.len()));
        }
        if !self.indices.len().is_multiple_of(3) {
            return Some(format!(
                "{} indices is not a whole number of triangles",
                self.indices.len()
            ));
        }
        if let Some(bad) = self.indices.iter().find(|&&i| i as usize >= n) {
            return Some(format!("index {bad} out of range for {n} vertices"));
        }
        None
    }
}

/// Line segments with per-vertex colour (tool paths, edges).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LineData {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Per-vertex sRGB colours (same length as `positions`).
    pub colours: Vec<Rgba8>,
    /// Vertex indices, two per segment.
    pub indices: Vec<u32>,
}

impl LineData {
    /// A polyline through `points` (one segment between each pair of neighbours).
    #[must_use]
    pub fn polyline(points: Vec<[f32; 3]>, colours: Vec<Rgba8>) -> Self {
        let n = u32::try_from(points.len()).unwrap_or(u32::MAX);
        let indices = (1..n).flat_map(|i| [i - 1, i]).collect();
        Self {
            positions: points,
            colours,
            indices,
        }
    }

    /// Add another polyline (not joined to what is there).
    pub fn push_polyline(&mut self, points: &[[f32; 3]], colour: Rgba8) {
        let Ok(start) = u32::try_from(self.positions.len()) else {
            return;
        };
        self.positions.extend_from_slice(points);
        self.colours
            .extend(std::iter::repeat_n(colour, points.len()));
        let n = u32::try_from(points.len()).unwrap_or(0);
        self.indices
            .extend((1..n).flat_map(|i| [start + i - 1, start + i]));
    }

    /// Number of segments.
    #[must_use]
    pub fn segment_count(&self) -> usize {
        self.indices.len() / 2
    }

    /// Axis-aligned bounds (`None` when there is no vertex).
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        bounds_of(&self.positions)
    }

    /// Why the data cannot be drawn as it is, if it cannot.
    #[must_use]
    pub fn problem(&self) -> Option<String> {
        let n = self.positions.len();
        if self.colours.len() != n {
            return Some(format!("{} colours for {n} vertices", self.colours.len()));
        }
        if !self.indices.len().is_multiple_of(2) {
            return Some(format!(
                "{} indices is not a whole number of segments",
                self.indices.len()
            ));
        }
        if let Some(bad) = self.indices.iter().find(|&&i| i as usize >= n) {
            return Some(format!("index {bad} out of range for {n} vertices"));
        }
        None
    }
}

fn bounds_of(points: &[[f32; 3]]) -> Option<(Vec3, Vec3)> {
    let mut it = points
        .iter()
        .map(|p| Vec3::from_array(*p))
        .filter(|p| p.is_finite());
    let first = it.next()?;
    Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
}

/// Identifies uploaded data: the renderer keeps the GPU copy while a scene names the id.
pub type DataId = u64;

/// A mesh placed in the scene.
#[derive(Clone, Debug)]
pub struct MeshInstance {
    /// Stable id of `data` (a new id for new data).
    pub id: DataId,
    /// The mesh.
    pub data: Arc<MeshData>,
    /// World-from-mesh transform.
    pub world_from_mesh: Mat4,
    /// Base colour (sRGB) when no scalar is shown.
    pub colour: Rgba8,
    /// Show the per-vertex scalar through this colour map over `[min, max]`.
    pub scalar_map: Option<ScalarMapping>,
}

/// How a per-vertex scalar becomes colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScalarMapping {
    /// Colour map.
    pub map: ColourMap,
    /// Scalar at the start of the map.
    pub min: f32,
    /// Scalar at the end of the map.
    pub max: f32,
}

/// A line set placed in the scene.
#[derive(Clone, Debug)]
pub struct LineInstance {
    /// Stable id of `data`.
    pub id: DataId,
    /// The lines.
    pub data: Arc<LineData>,
    /// World-from-lines transform.
    pub world_from_lines: Mat4,
    /// Draw only the first this many segments (playback); `None`: all.
    pub draw_segments: Option<usize>,
}

/// Display options of a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DisplayOptions {
    /// Background gradient, top (sRGB).
    pub background_top: Rgba8,
    /// Background gradient, bottom (sRGB).
    pub background_bottom: Rgba8,
    /// Draw the ground grid.
    pub grid: bool,
    /// Grid plane height (world z, mm).
    pub grid_z: f32,
    /// Minor grid spacing (mm); major lines every ten. The grid fades out about 2.5 scene radii
    /// from the centre of the camera's scene sphere.
    pub grid_spacing: f32,
    /// Draw the axis triad in the lower-left corner.
    pub triad: bool,
}

impl Default for DisplayOptions {
    fn default() -> Self {
        Self {
            background_top: [58, 64, 76, 255],
            background_bottom: [20, 22, 27, 255],
            grid: true,
            grid_z: 0.0,
            grid_spacing: 10.0,
            triad: true,
        }
    }
}

impl DisplayOptions {
    /// A grid spacing (a power of ten, mm) that suits a scene of `size` mm.
    #[must_use]
    pub fn grid_spacing_for(size: f32) -> f32 {
        if !(size.is_finite() && size > 0.0) {
            return 10.0;
        }
        10.0_f32.powf((size / 10.0).log10().floor()).max(1e-3)
    }
}

/// Everything one frame draws.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// The camera.
    pub camera: Camera,
    /// Shaded meshes.
    pub meshes: Vec<MeshInstance>,
    /// Line sets, drawn over the meshes.
    pub lines: Vec<LineInstance>,
    /// Background, grid, triad.
    pub options: DisplayOptions,
}

impl Scene {
    /// Bounds of everything in the scene, in world space.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mesh = self
            .meshes
            .iter()
            .filter_map(|m| transformed(m.data.bounds(), m.world_from_mesh));
        let line = self
            .lines
            .iter()
            .filter_map(|l| transformed(l.data.bounds(), l.world_from_lines));
        mesh.chain(line)
            .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
    }
}

fn transformed(bounds: Option<(Vec3, Vec3)>, m: Mat4) -> Option<(Vec3, Vec3)> {
    let (lo, hi) = bounds?;
    let corners = (0..8).map(|i| {
        m.transform_point3(Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        ))
    });
    corners.fold(None, |acc: Option<(Vec3, Vec3)>, p| {
        Some(acc.map_or((p, p), |(a, b)| (a.min(p), b.max(p))))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polyline_indices_join_neighbours() {
        let l = LineData::polyline(
            vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
            vec![[255; 4]; 3],
        );
        assert_eq!(l.indices, vec![0, 1, 1, 2]);
        assert_eq!(l.problem(), None);
        let mut m = l.clone();
        m.push_polyline(&[[0.0; 3], [0.0, 0.0, 1.0]], [1, 2, 3, 4]);
        assert_eq!(m.indices, vec![0, 1, 1, 2, 3, 4]);
    }

    #[test]
    fn problems_are_reported() {
        let m = MeshData {
            positions: vec![[0.0; 3]],
            normals: vec![],
            scalars: vec![],
            indices: vec![0, 0, 0],
        };
        assert!(m.problem().is_some());
        let m = MeshData {
            normals: vec![[0.0, 0.0, 1.0]],
            indices: vec![0, 0, 1],
            ..m
        };
        assert!(m.problem().is_some_and(|p| p.contains("out of range")));
    }

    #[test]
    fn grid_spacing_is_a_power_of_ten() {
        assert!((DisplayOptions::grid_spacing_for(160.0) - 10.0).abs() < 1e-5);
        assert!((DisplayOptions::grid_spacing_for(50.0) - 1.0).abs() < 1e-6);
        assert!((DisplayOptions::grid_spacing_for(1000.0) - 100.0).abs() < 1e-3);
        assert!((DisplayOptions::grid_spacing_for(f32::NAN) - 10.0).abs() < 1e-6);
    }
}
