//! Computed tool paths of the project's operations, kept beside the document: each result
//! remembers the operation, the cutter and the part it was computed from, so it is shown exactly
//! while those are unchanged (undo brings an earlier result back) and marked stale otherwise.
//! Also the paths in render form (coloured by move kind or by predicted scallop), the time at
//! feed of every pose for playback, and picking a pose near the cursor.

use std::sync::Arc;

use glam::{Mat4, Vec2};

use crate::project::Operation;
use crate::project::pipeline::Computed;
use crate::project::results::Digest;
use crate::render::{ColourMap, DataId, LineData, Rgba8, ScalarMapping};
use crate::toolpath::{MoveKind, Toolpath};
use crate::tools::Cutter;

/// How paths are coloured in the viewport.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PathColouring {
    /// By move kind: cut, link, rapid, plunge.
    #[default]
    MoveKind,
    /// Cutting moves by the predicted scallop height at their end pose; others by kind.
    Scallop,
    /// Cutting moves by the feed the jerk-limited plan of the posted program reaches there
    /// (needs a posted program); others by kind.
    PlannedFeed,
}

impl PathColouring {
    /// Every colouring, menu order.
    pub const ALL: [Self; 3] = [Self::MoveKind, Self::Scallop, Self::PlannedFeed];

    /// Name for menus.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::MoveKind => "Move kind",
            Self::Scallop => "Predicted scallop",
            Self::PlannedFeed => "Planned feed (after posting)",
        }
    }
}

/// Colour of each move kind (sRGB): cut, link, rapid, plunge.
#[must_use]
pub fn move_colour(kind: MoveKind) -> Rgba8 {
    match kind {
        MoveKind::Cut => [70, 170, 255, 255],
        MoveKind::Link => [240, 200, 60, 255],
        MoveKind::Rapid => [235, 75, 75, 255],
        MoveKind::Plunge => [255, 140, 40, 255],
    }
}

/// Rapid speed used for the playback clock and the time estimate, mm/min (the engine's one
/// default, [`crate::units::DEFAULT_RAPID_MM_PER_MIN`]).
pub const RAPID_MM_PER_MIN: f64 = crate::units::DEFAULT_RAPID_MM_PER_MIN;

/// One computed operation.
#[derive(Debug)]
pub struct ComputedOp {
    /// The operation as it was when computed.
    pub operation: Operation,
    /// The tool as it was when computed.
    pub cutter: Cutter,
    /// Render id of the part it was computed on.
    pub part_id: DataId,
    /// The engine's digest of every input the computation read
    /// ([`crate::project::pipeline::digests`]): the result is fresh while the project gives
    /// the same.
    pub digest: Digest,
    /// The pipeline's result.
    pub computed: Computed,
    /// Wall time of the computation, s.
    pub elapsed_s: f64,
    /// Time at feed when each pose is reached, s (rapids at [`RAPID_MM_PER_MIN`]).
    pub clock_s: Vec<f64>,
    /// Predicted scallop range of the cutting poses, mm (`None` when no pose predicts one).
    pub scallop_range_mm: Option<(f64, f64)>,
    render: Option<(PathColouring, DataId, Arc<LineData>)>,
    axes: Option<(DataId, Arc<LineData>, Vec<usize>)>,
}

impl ComputedOp {
    /// A result for `operation` with `cutter` on part `part_id`, computed from the inputs whose
    /// digest is `digest`.
    #[must_use]
    pub fn new(
        operation: Operation,
        cutter: Cutter,
        part_id: DataId,
        digest: Digest,
        computed: Computed,
        elapsed_s: f64,
    ) -> Self {
        let clock_s = pose_clock(&computed.toolpath);
        let scallop_range_mm = computed
            .toolpath
            .poses
            .iter()
            .filter(|p| p.kind == MoveKind::Cut)
            .filter_map(|p| p.scallop_mm)
            .filter(|h| h.is_finite())
            .fold(None, |acc: Option<(f64, f64)>, h| {
                Some(acc.map_or((h, h), |(lo, hi)| (lo.min(h), hi.max(h))))
            });
        Self {
            operation,
            cutter,
            part_id,
            digest,
            computed,
            elapsed_s,
            clock_s,
            scallop_range_mm,
            render: None,
            axes: None,
        }
    }

    /// The tool path.
    #[must_use]
    pub fn toolpath(&self) -> &Toolpath {
        &self.computed.toolpath
    }

    /// The colour mapping of the scallop colouring (0 to the largest predicted scallop).
    #[must_use]
    pub fn scallop_mapping(&self) -> Option<ScalarMapping> {
        let (_, hi) = self.scallop_range_mm?;
        Some(ScalarMapping {
            map: ColourMap::Turbo,
            min: 0.0,
            max: (hi as f32).max(1e-6),
        })
    }

    /// The path in render form for `colouring` (built once per colouring; `next_id` supplies a
    /// fresh render id when it is rebuilt).
    pub fn render_lines(
        &mut self,
        colouring: PathColouring,
        next_id: &mut DataId,
    ) -> (DataId, Arc<LineData>) {
        if let Some((c, id, data)) = &self.render
            && *c == colouring
        {
            return (*id, Arc::clone(data));
        }
        *next_id += 1;
        let mapping = match colouring {
            PathColouring::MoveKind | PathColouring::PlannedFeed => None,
            PathColouring::Scallop => self.scallop_mapping(),
        };
        let data = Arc::new(path_lines(self.toolpath(), mapping));
        self.render = Some((colouring, *next_id, Arc::clone(&data)));
        (*next_id, data)
    }

    /// The tool-axis vectors in render form (built once; `length_mm` long) and, per segment, the
    /// pose it stands at.
    pub fn axis_lines(
        &mut self,
        length_mm: f64,
        next_id: &mut DataId,
    ) -> (DataId, Arc<LineData>, &[usize]) {
        if self.axes.is_none() {
            *next_id += 1;
            let (lines, poses) = axis_vectors(self.toolpath(), length_mm);
            self.axes = Some((*next_id, Arc::new(lines), poses));
        }
        match &self.axes {
            Some((id, data, poses)) => (*id, Arc::clone(data), poses.as_slice()),
            None => (0, Arc::new(LineData::default()), &[]),
        }
    }
}

/// Time at which each pose is reached when moves run at their feed (rapids at
/// [`RAPID_MM_PER_MIN`]), s: the engine's one rule, [`crate::toolpath::pose_times_at_feed`].
#[must_use]
pub fn pose_clock(toolpath: &Toolpath) -> Vec<f64> {
    crate::toolpath::pose_times_at_feed(&toolpath.poses)
}

/// The path as line segments, two vertices per segment so each keeps its own colour: segment
/// `i` is the move from pose `i` to pose `i + 1`, coloured by that move's kind, or for cutting
/// moves by the scallop predicted at pose `i + 1` through `scallop` when given.
#[must_use]
pub fn path_lines(toolpath: &Toolpath, scallop: Option<ScalarMapping>) -> LineData {
    match scallop {
        Some(m) => {
            let values: Vec<f32> = toolpath
                .poses
                .iter()
                .map(|p| p.scallop_mm.map_or(f32::NAN, |h| h as f32))
                .collect();
            path_lines_by(toolpath, &values, m)
        }
        None => path_lines_by(
            toolpath,
            &[],
            ScalarMapping {
                map: ColourMap::Turbo,
                min: 0.0,
                max: 1.0,
            },
        ),
    }
}

/// The path as line segments (see [`path_lines`]), cutting moves coloured by `values` (one per
/// pose, the value at the move's end pose) through `mapping`; moves without a finite value, and
/// every move when `values` is empty, by their kind (cuts without a value grey).
#[must_use]
pub fn path_lines_by(toolpath: &Toolpath, values: &[f32], mapping: ScalarMapping) -> LineData {
    let n = toolpath.poses.len().saturating_sub(1);
    let mut out = LineData {
        positions: Vec::with_capacity(2 * n),
        colours: Vec::with_capacity(2 * n),
        indices: Vec::with_capacity(2 * n),
    };
    for (k, w) in toolpath.poses.windows(2).enumerate() {
        let [a, b] = w else { continue };
        let value = values.get(k + 1).copied();
        let colour = match (values.is_empty(), b.kind, value) {
            (false, MoveKind::Cut, Some(v)) if v.is_finite() => {
                let t = (v - mapping.min) / (mapping.max - mapping.min).max(1e-12);
                let [r, g, bl] = mapping.map.sample(t);
                [r, g, bl, 255]
            }
            (false, MoveKind::Cut, _) => [200, 200, 200, 255],
            (_, kind, _) => move_colour(kind),
        };
        out.positions.push(a.tip.as_vec3().to_array());
        out.positions.push(b.tip.as_vec3().to_array());
        out.colours.extend([colour, colour]);
        let i = u32::try_from(2 * k).unwrap_or(u32::MAX - 1);
        out.indices.extend([i, i + 1]);
    }
    out
}

/// Colour of the highlighted move (sRGB).
pub const HIGHLIGHT_COLOUR: Rgba8 = [255, 255, 255, 255];

/// The move into pose `index` (from the pose before it) and a cross of half-size `size` mm at the
/// pose's tip, for highlighting a picked pose or G-code line.
#[must_use]
pub fn highlight_move(toolpath: &Toolpath, index: usize, size: f32) -> Option<LineData> {
    let p = toolpath.poses.get(index)?;
    let tip = p.tip.as_vec3();
    let mut out = LineData::default();
    if let Some(prev) = index.checked_sub(1).and_then(|i| toolpath.poses.get(i)) {
        out.push_polyline(
            &[prev.tip.as_vec3().to_array(), tip.to_array()],
            HIGHLIGHT_COLOUR,
        );
    }
    for d in [glam::Vec3::X, glam::Vec3::Y, glam::Vec3::Z] {
        out.push_polyline(
            &[(tip - d * size).to_array(), (tip + d * size).to_array()],
            HIGHLIGHT_COLOUR,
        );
    }
    Some(out)
}

/// Colour of the tool-axis vectors (sRGB).
pub const AXIS_VECTOR_COLOUR: Rgba8 = [120, 230, 160, 255];

/// Most tool-axis vectors drawn for one path (every k-th cutting pose beyond that).
pub const MAX_AXIS_VECTORS: usize = 4000;

/// Tool-axis vectors at the cutting poses of `toolpath` (every k-th so that at most
/// [`MAX_AXIS_VECTORS`] are drawn), each `length_mm` long from the tip along the axis; segment
/// `i` belongs to the `i`-th vector drawn, with the index of its pose in `poses`.
#[must_use]
pub fn axis_vectors(toolpath: &Toolpath, length_mm: f64) -> (LineData, Vec<usize>) {
    let cuts: Vec<usize> = toolpath
        .poses
        .iter()
        .enumerate()
        .filter(|(_, p)| p.kind == MoveKind::Cut)
        .map(|(i, _)| i)
        .collect();
    let every = cuts.len().div_ceil(MAX_AXIS_VECTORS).max(1);
    let mut out = LineData::default();
    let mut poses = Vec::new();
    for &i in cuts.iter().step_by(every) {
        let Some(p) = toolpath.poses.get(i) else {
            continue;
        };
        let a = p.tip;
        let b = p.tip + p.axis * length_mm;
        out.push_polyline(
            &[a.as_vec3().to_array(), b.as_vec3().to_array()],
            AXIS_VECTOR_COLOUR,
        );
        poses.push(i);
    }
    (out, poses)
}

/// The pose whose tip projects nearest to `cursor` (pixels, within `radius_px`) for the view
/// `clip_from_world` on a `size_px` viewport; the nearer to the eye wins a tie.
#[must_use]
pub fn pick_pose(
    toolpath: &Toolpath,
    clip_from_world: Mat4,
    size_px: Vec2,
    cursor: Vec2,
    radius_px: f32,
    up_to: Option<usize>,
) -> Option<usize> {
    let mut best: Option<(usize, f32, f32)> = None;
    let last = up_to.unwrap_or(usize::MAX);
    for (i, p) in toolpath
        .poses
        .iter()
        .enumerate()
        .take(last.saturating_add(1))
    {
        let c = clip_from_world * p.tip.as_vec3().extend(1.0);
        if c.w <= 0.0 {
            continue;
        }
        let ndc = c.truncate() / c.w;
        // Outside the near and far planes (either depth convention).
        if ndc.z.abs() > 1.0 {
            continue;
        }
        let px = Vec2::new(
            (ndc.x + 1.0) * 0.5 * size_px.x,
            (1.0 - ndc.y) * 0.5 * size_px.y,
        );
        let d = px.distance(cursor);
        if d > radius_px {
            continue;
        }
        let better = best.is_none_or(|(_, bd, bz)| d < bd - 0.5 || (d < bd + 0.5 && ndc.z < bz));
        if better {
            best = Some((i, d, ndc.z));
        }
    }
    best.map(|(i, _, _)| i)
}

/// The computed operations (a bounded list; the oldest result goes first).
#[derive(Debug, Default)]
pub struct ToolpathStore {
    results: Vec<ComputedOp>,
}

/// Results kept at most (each holds its path).
const KEEP: usize = 24;

impl ToolpathStore {
    /// Keep `result`, replacing one computed from the same inputs (digest) on the same part.
    pub fn insert(&mut self, result: ComputedOp) {
        self.results
            .retain(|r| !(r.digest == result.digest && r.part_id == result.part_id));
        self.results.push(result);
        if self.results.len() > KEEP {
            self.results.remove(0);
        }
    }

    /// The result computed from the inputs whose engine digest is `digest` on part `part_id`,
    /// if any (the digest covers the operation, its tool, the stock, the machine, the earlier
    /// operations and the reference tool where the computation reads them).
    #[must_use]
    pub fn find(&self, digest: Digest, part_id: DataId) -> Option<usize> {
        self.results
            .iter()
            .rposition(|r| r.digest == digest && r.part_id == part_id)
    }

    /// The result at `index` (from [`ToolpathStore::find`]).
    #[must_use]
    pub fn get(&self, index: usize) -> Option<&ComputedOp> {
        self.results.get(index)
    }

    /// The result at `index`, mutable (to build its render data).
    pub fn get_mut(&mut self, index: usize) -> Option<&mut ComputedOp> {
        self.results.get_mut(index)
    }

    /// Replace the path of the result at `index` (e.g. by its feed schedule): its clock and
    /// render data follow; false when there is no such result.
    pub fn replace_toolpath(&mut self, index: usize, toolpath: Toolpath) -> bool {
        let Some(r) = self.results.get_mut(index) else {
            return false;
        };
        r.clock_s = pose_clock(&toolpath);
        r.computed.toolpath = toolpath;
        r.render = None;
        r.axes = None;
        true
    }

    /// The latest result computed for an operation named `name` (shown as stale when the
    /// operation has changed since).
    #[must_use]
    pub fn latest_named(&self, name: &str) -> Option<&ComputedOp> {
        self.results
            .iter()
            .rev()
            .find(|r| r.operation.name() == name)
    }

    /// Forget everything (a new part or project).
    pub fn clear(&mut self) {
        self.results.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::{Pose, ToolRecord};
    use crate::tools::parse_tool_spec;
    use glam::DVec3;

    fn path() -> Toolpath {
        let tool = ToolRecord {
            spec: "ball:d=6".into(),
            cutter: parse_tool_spec("ball:d=6").expect("spec"),
        };
        let mut poses = vec![
            Pose::new(MoveKind::Rapid, DVec3::new(0.0, 0.0, 10.0), DVec3::Z, 0.0),
            Pose::new(MoveKind::Plunge, DVec3::new(0.0, 0.0, 0.0), DVec3::Z, 300.0),
            Pose::new(MoveKind::Cut, DVec3::new(10.0, 0.0, 0.0), DVec3::Z, 600.0),
            Pose::new(MoveKind::Cut, DVec3::new(20.0, 0.0, 0.0), DVec3::Z, 600.0),
        ];
        poses[2].scallop_mm = Some(0.01);
        poses[3].scallop_mm = Some(0.02);
        Toolpath::new(tool, poses)
    }

    #[test]
    fn clock_follows_the_feeds() {
        let c = pose_clock(&path());
        // 10 mm plunge at 300 mm/min = 2 s; 10 mm cuts at 600 mm/min = 1 s each.
        assert_eq!(c.len(), 4);
        assert!((c[1] - 2.0).abs() < 1e-12);
        assert!((c[3] - 4.0).abs() < 1e-12);
    }

    #[test]
    fn segments_take_the_colour_of_their_move() {
        let tp = path();
        let lines = path_lines(&tp, None);
        assert_eq!(lines.segment_count(), 3);
        assert_eq!(lines.problem(), None);
        assert_eq!(lines.colours[0], move_colour(MoveKind::Plunge));
        assert_eq!(lines.colours[2], move_colour(MoveKind::Cut));
        let m = ScalarMapping {
            map: ColourMap::Turbo,
            min: 0.0,
            max: 0.02,
        };
        let by_scallop = path_lines(&tp, Some(m));
        let [r, g, b] = ColourMap::Turbo.sample(1.0);
        assert_eq!(by_scallop.colours[4], [r, g, b, 255]);
        assert_eq!(by_scallop.colours[0], move_colour(MoveKind::Plunge));
    }

    #[test]
    fn the_highlight_is_the_move_into_the_pose_and_a_cross_at_it() {
        let tp = path();
        let h = highlight_move(&tp, 2, 1.0).expect("pose 2");
        assert_eq!(h.segment_count(), 4);
        assert_eq!(h.positions[0], [0.0, 0.0, 0.0]);
        assert_eq!(h.positions[1], [10.0, 0.0, 0.0]);
        assert_eq!(
            highlight_move(&tp, 0, 1.0).expect("pose 0").segment_count(),
            3
        );
        assert!(highlight_move(&tp, 9, 1.0).is_none());
    }

    #[test]
    fn axis_vectors_stand_on_the_cutting_poses() {
        let tp = path();
        let (lines, poses) = axis_vectors(&tp, 5.0);
        assert_eq!(poses, vec![2, 3]);
        assert_eq!(lines.segment_count(), 2);
        assert_eq!(lines.positions[0], [10.0, 0.0, 0.0]);
        assert_eq!(lines.positions[1], [10.0, 0.0, 5.0]);
    }

    #[test]
    fn picking_finds_the_pose_under_the_cursor() {
        let tp = path();
        // Orthographic top view of x in [-5, 25], y in [-15, 15] on a 300 × 300 px viewport.
        let clip =
            glam::camera::rh::proj::directx::orthographic(-5.0, 25.0, -15.0, 15.0, -100.0, 100.0);
        let size = Vec2::new(300.0, 300.0);
        // Pose 2 (x = 10) is at pixel x = 150, y = 150.
        assert_eq!(
            pick_pose(&tp, clip, size, Vec2::new(152.0, 149.0), 8.0, None),
            Some(2)
        );
        assert_eq!(
            pick_pose(&tp, clip, size, Vec2::new(100.0, 100.0), 8.0, None),
            None
        );
        // Poses beyond the playback index are not pickable.
        assert_eq!(
            pick_pose(&tp, clip, size, Vec2::new(250.0, 150.0), 8.0, Some(2)),
            None
        );
    }
}
