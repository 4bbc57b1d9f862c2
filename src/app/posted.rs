//! The posted program as the workstation and its features share it: a [`Posted`] run, made
//! by the posted-program feature and lent to the others each frame (see
//! [`crate::app::feature::Lent`]), and the [`ProgramKey`] that says whether it is still the
//! program an operation would be posted to. A shared value type, not a feature: the playback,
//! the forces, the operator panel and the path colouring read it without naming the feature
//! that makes it.

use std::sync::{Arc, OnceLock};

use super::document::Document;
use crate::project::{MachiningRun, Operation, PostConfig, Project, Setup};
use crate::render::{ColourMap, DataId, LineData, ScalarMapping};
use crate::toolpath::Toolpath;
use crate::tools::Cutter;

/// What a program was posted from (it is shown as current while these are unchanged).
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramKey {
    /// The operation posted.
    pub operation: Operation,
    /// Its tool's cutter.
    pub cutter: Cutter,
    /// The render id of the part it was planned on.
    pub part_id: DataId,
    /// The machine's name.
    pub machine: String,
    /// The set-up (work offset, origin).
    pub setup: Setup,
    /// The post-processor settings.
    pub post: PostConfig,
}

impl ProgramKey {
    /// What operation `index` of `project` would be posted from on `document`'s part.
    pub fn of(project: &Project, document: Option<&Document>, index: usize) -> Option<Self> {
        let operation = project.operations.get(index)?.clone();
        Some(Self {
            cutter: project.tools.get(operation.tool())?.cutter.clone(),
            operation,
            part_id: document?.ids[0],
            machine: project.machine.clone(),
            setup: project.setup_of_operation(index),
            post: project.post.clone(),
        })
    }
}

/// A posted program as the workstation and the other features read it (shared, never changed
/// once made).
pub struct Posted {
    key: ProgramKey,
    /// The engine's run: the text, line ↔ pose ↔ planned time.
    pub run: MachiningRun,
    /// The render id of the path coloured by planned feed.
    feed_id: DataId,
    /// The path coloured by planned feed and its mapping (mm/min), built on first use.
    feed_lines: OnceLock<Option<(Arc<LineData>, ScalarMapping)>>,
}

impl Posted {
    /// A program posted from `key`, its path coloured by feed to be drawn under `feed_id`.
    #[must_use]
    pub fn new(key: ProgramKey, run: MachiningRun, feed_id: DataId) -> Self {
        Self {
            key,
            run,
            feed_id,
            feed_lines: OnceLock::new(),
        }
    }

    /// What it was posted from.
    #[must_use]
    pub fn key(&self) -> &ProgramKey {
        &self.key
    }

    /// Is this the program operation `index` of `project` would be posted to now on
    /// `document`'s part (operation, tool, part, machine, setup and post settings unchanged)?
    #[must_use]
    pub fn is_current(&self, project: &Project, document: Option<&Document>, index: usize) -> bool {
        ProgramKey::of(project, document, index).is_some_and(|k| k == self.key)
    }

    /// The G-code text.
    #[must_use]
    pub fn text(&self) -> &str {
        &self.run.text
    }

    /// The time each pose of the posted path is reached in the motion plan, s (when planned).
    #[must_use]
    pub fn planned_clock(&self) -> Option<&[f64]> {
        self.run
            .motion
            .as_ref()
            .ok()
            .map(|m| m.pose_time_s.as_slice())
    }

    /// The planned feed at each pose of the posted path, mm/min (NaN where unknown).
    #[must_use]
    pub fn planned_feed(&self) -> Option<&[f32]> {
        self.run
            .motion
            .as_ref()
            .ok()
            .map(|m| m.pose_feed_mm_min.as_slice())
    }

    /// `toolpath` (the posted path) coloured by planned feed: render id, lines and the mapping
    /// (0 to the fastest planned feed, mm/min); built once.
    #[must_use]
    pub fn feed_lines(
        &self,
        toolpath: &Toolpath,
    ) -> Option<(DataId, Arc<LineData>, ScalarMapping)> {
        let built = self.feed_lines.get_or_init(|| {
            let pose_feed = self.planned_feed()?;
            let max = pose_feed
                .iter()
                .copied()
                .filter(|f| f.is_finite())
                .fold(0.0f32, f32::max)
                .max(1.0);
            let mapping = ScalarMapping {
                map: ColourMap::Turbo,
                min: 0.0,
                max,
            };
            let lines = super::toolpaths::path_lines_by(toolpath, pose_feed, mapping);
            Some((Arc::new(lines), mapping))
        });
        built
            .as_ref()
            .map(|(lines, mapping)| (self.feed_id, Arc::clone(lines), *mapping))
    }
}
