//! The operation commands: adding operations, calculating them on a worker thread (progress,
//! Cancel, results kept in the [`ToolpathStore`]), the paths drawn in the viewport, picking a
//! pose, and playback of the active path on its clock (the posted program's planned clock when
//! the program feature lends a current one, else the programmed feeds'). The playback stays
//! here because the operation path shares it: the path is drawn up to its pose, a pick moves
//! it, the operation editor and the features read its pose.

use std::sync::Arc;

use glam::Mat4;

use super::super::command::{Command, PlaybackCommand};
use super::super::document::Selection;
use super::super::job::{Job, JobSlot};
use super::super::panels::operation_editor::{OperationView, Sections};
use super::super::panels::playback::PlaybackView;
use super::super::posted::Posted;
use super::super::state::Focus;
use super::super::toolpaths::{ComputedOp, PathColouring, ToolpathStore};
use super::Workstation;
use crate::diagnostics::{Diagnostic, Severity};
use crate::project::pipeline::{ComputeError, Computed, digests};
use crate::project::results::{Digest, part_digest};
use crate::project::{Edit, Operation, Results, saved_paths};
use crate::render::{DataId, LineInstance, ScalarMapping};
use crate::tools::Cutter;

/// What a running calculation computes (to file the result): the operation, and the engine's
/// digest of every input the computation reads, which decides its freshness.
pub(super) struct CalcKey {
    index: usize,
    operation: Operation,
    cutter: Cutter,
    part_id: DataId,
    digest: Digest,
}

/// The highlighted move: (active operation, pose, stored result), render id, lines.
pub(super) type HighlightedMove = ((usize, usize, usize), DataId, Arc<crate::render::LineData>);

/// The operations' state of the workstation.
#[derive(Default)]
pub(super) struct Operations {
    /// Computed paths.
    pub store: ToolpathStore,
    /// The running calculation.
    pub job: JobSlot<Result<Computed, ComputeError>, CalcKey>,
    /// The operation whose path is active (drawn, played back, picked).
    pub active: Option<usize>,
    /// The pose picked in the viewport (index into the active path).
    pub picked_pose: Option<usize>,
    /// Path colouring.
    pub colouring: PathColouring,
    /// Draw every fresh path, not only the active one.
    pub show_all: bool,
    /// Operations whose paths are hidden in the viewport (by index; not drawn, not pickable),
    /// and the operation count they were hidden at (an operation added or removed shifts
    /// the indices, and the set is cleared).
    pub hidden: std::collections::BTreeSet<usize>,
    pub hidden_at_count: usize,
    /// Draw tool-axis vectors at the active path's cutting poses.
    pub show_axes: bool,
    /// The comparison window is open.
    pub compare_open: bool,
    /// The highlighted move: (active op, pose), render id and lines.
    pub highlight: Option<HighlightedMove>,
    /// Playback clock, s (`None`: the whole path).
    pub t_s: Option<f64>,
    /// Is the clock running?
    pub playing: bool,
    /// Playback speed, × real time.
    pub speed: f64,
    /// Render ids for paths.
    pub next_id: DataId,
    /// The engine's result store the calculations run in (rest from the stock reads the
    /// in-process stock from it, cut once per operation).
    pub engine: Arc<Results>,
    /// The digest of the part, by its render id (hashed once per part).
    pub part_digest: std::sync::Mutex<Option<(DataId, Digest)>>,
}

impl Operations {
    /// A fresh state (ids above the documents' and the viewport's).
    pub fn new() -> Self {
        Self {
            speed: 10.0,
            next_id: 1 << 48,
            ..Self::default()
        }
    }
}

/// Index of the last pose reached at time `t_s` on `clock` (non-decreasing times).
fn pose_at(clock: &[f64], t_s: f64) -> usize {
    clock.partition_point(|&c| c <= t_s).saturating_sub(1)
}

impl Workstation {
    /// Is an operation being calculated?
    #[must_use]
    pub fn is_calculating(&self) -> bool {
        self.ops.job.is_running()
    }

    /// The latest result for operation `index` and whether it is fresh (computed from the
    /// operation, tool and part as they are now).
    #[must_use]
    pub fn operation_result(&self, index: usize) -> Option<(&ComputedOp, bool)> {
        let (i, fresh) = self.result_index(index)?;
        Some((self.ops.store.get(i)?, fresh))
    }

    /// The pose the playback has reached (`None`: the whole path is shown).
    #[must_use]
    pub fn playback_position(&self) -> Option<usize> {
        self.playback_pose()
    }

    /// The pose the tool is drawn at: the one under the pointer in a motion plot, else the
    /// picked one, else the playback's (playback commands clear the pick).
    #[must_use]
    pub fn tool_pose_index(&self) -> Option<usize> {
        self.lent
            .hover_pose
            .or(self.ops.picked_pose)
            .or(self.playback_pose())
    }

    /// The program the program feature lends, when it is operation `index`'s current one.
    pub(super) fn posted(&self, index: usize) -> Option<&Posted> {
        let p = self.lent.get::<Posted>()?;
        p.is_current(&self.saved.session.project, self.document.as_ref(), index)
            .then_some(p)
    }

    /// The planned clock of operation `index`'s path (time each pose is reached, s), when its
    /// posted program is current and planned.
    pub(super) fn planned_clock(&self, index: usize) -> Option<&[f64]> {
        self.posted(index)?.planned_clock()
    }

    /// Tell the features the tool was moved to pose `pose` of the active path (the posted
    /// program brings its G-code line and plot cursor there).
    pub(super) fn follow_pose(&mut self, pose: usize) {
        self.with_features(|features, cx| {
            for f in features {
                f.follow_pose(pose, &cx.view);
            }
        });
    }

    /// Apply an operation command (see [`Workstation::apply`]).
    pub(super) fn apply_operation(&mut self, command: Command) {
        match command {
            Command::AddOperation(kind) => {
                let tool = self.saved.session.project.selected_tool.unwrap_or(0);
                if self.saved.session.project.tools.is_empty() {
                    let t = self.now_s();
                    self.log.notify(
                        t,
                        Severity::Warning,
                        "Add a tool to the library first (Tools > + Ball …)",
                    );
                    return;
                }
                let face = match self.document.as_ref().map(|d| d.selection) {
                    Some(Selection::Face(f)) => f,
                    _ => 0,
                };
                let project = &self.saved.session.project;
                let index = project.operations.len();
                // Its feeds and speeds from the cutting-data library when the stock has a
                // material (the editor shows where they came from).
                let operation = crate::project::cutting::with_library_speeds(
                    project,
                    Operation::new(kind, tool, face),
                );
                // Into the setup in focus (or the focused operation's), else the last one.
                let last = project.setups.len().saturating_sub(1);
                let setup = match self.focus {
                    Focus::Setup(s) => s.min(last),
                    Focus::Operation(i) => {
                        crate::project::setups::setup_of(project, i).unwrap_or(last)
                    }
                    _ => last,
                };
                let mut edits = vec![Edit::AddOperation { index, operation }];
                if project.setups.len() > 1 {
                    let position = project.setups.get(setup).map_or(0, |s| s.operations.len());
                    edits.push(Edit::MoveOperation {
                        operation: index,
                        setup,
                        position,
                    });
                }
                self.apply(Command::Edit(Edit::Batch(edits)));
                if self.saved.session.project.operations.len() > index {
                    self.apply(Command::Inspect(Focus::Operation(index)));
                }
            }
            Command::Calculate(index) => self.start_calculation(index),
            Command::CalculateActive => match self.target_operation() {
                Some(i) => self.start_calculation(i),
                None => self.log_info("Select an operation to calculate"),
            },
            Command::PickOperationPose { operation, pose } => {
                if self.ops.active != Some(operation) && self.result_index(operation).is_some() {
                    // Another operation's path becomes the active one: its own clock.
                    self.ops.active = Some(operation);
                    self.ops.t_s = None;
                    self.ops.playing = false;
                }
                if self.ops.active == Some(operation) {
                    self.apply(Command::PickPose(Some(pose)));
                }
            }
            Command::PickPose(pose) => {
                self.ops.picked_pose = pose;
                if let Some(p) = pose {
                    // With playback in use, its clock moves to the picked pose too: the path is
                    // drawn up to it and stepping goes on from it.
                    if self.ops.t_s.is_some()
                        && let Some(t) = self.active_clock().and_then(|c| c.get(p).copied())
                    {
                        self.ops.t_s = Some(t);
                        self.ops.playing = false;
                    }
                    self.follow_pose(p);
                }
            }
            Command::OpenMachineFileDialog => {
                let start = std::env::current_dir().ok();
                self.open_chooser(
                    super::super::file_chooser::ChooserPurpose::MachineFile,
                    start,
                );
            }
            Command::SetPathColouring(c) => self.ops.colouring = c,
            Command::ReplacePath(index, toolpath) => self.replace_path(index, &toolpath),
            Command::SetShowAllPaths(on) => self.ops.show_all = on,
            Command::SetPathShown { operation, shown } => {
                self.ops.hidden_at_count = self.saved.session.project.operations.len();
                if shown {
                    self.ops.hidden.remove(&operation);
                } else {
                    self.ops.hidden.insert(operation);
                }
            }
            Command::SetShowAxisVectors(on) => self.ops.show_axes = on,
            Command::CompareOperations => self.ops.compare_open = true,
            Command::Playback(p) => self.playback(p),
            _ => {}
        }
    }

    /// Make `toolpath` operation `index`'s computed path (a feed schedule applied); the posted
    /// program, made from the old path, is dropped (the stock simulation drops its keyframes).
    fn replace_path(&mut self, index: usize, toolpath: &crate::toolpath::Toolpath) {
        match self.result_index(index) {
            Some((k, true)) if self.ops.store.replace_toolpath(k, toolpath.clone()) => {
                (self.ops.highlight, self.ops.picked_pose, self.ops.t_s) = (None, None, None);
                self.log_info(format!("Operation {}: scheduled path applied", index + 1));
            }
            _ => self.log_info("Calculate the operation first"),
        }
    }

    /// The operation a menu entry or key acts on: the focused one, else the active one, else
    /// the first.
    pub(super) fn target_operation(&self) -> Option<usize> {
        let focused = match self.focus {
            Focus::Operation(i) => Some(i),
            _ => None,
        };
        let first = (!self.saved.session.project.operations.is_empty()).then_some(0);
        focused.or(self.ops.active).or(first)
    }

    fn start_calculation(&mut self, index: usize) {
        let project = &self.saved.session.project;
        let Some(operation) = project.operations.get(index).cloned() else {
            return;
        };
        let Some(doc) = &self.document else {
            let t = self.now_s();
            self.log
                .notify(t, Severity::Warning, "Open a part before calculating");
            return;
        };
        let Some(cutter) = project
            .tools
            .get(operation.tool())
            .map(|t| t.cutter.clone())
        else {
            let t = self.now_s();
            self.log.notify(
                t,
                Severity::Error,
                format!("'{}' names a tool the library lacks", operation.name()),
            );
            return;
        };
        // The engine's workpiece, shared: its BVH is built once per part, not per Calculate.
        let part = std::sync::Arc::clone(&doc.part.workpiece);
        let project = project.clone();
        let part_id = doc.ids[0];
        let Some(digest) = self.current_digest(index) else {
            return;
        };
        self.log_info(format!("Calculating '{}'", operation.name()));
        let engine = Arc::clone(&self.ops.engine);
        let job = Job::start(
            format!("Calculating {}", operation.name()),
            &self.run.ctx,
            move |progress| {
                let mut computed = engine
                    .get_or_compute(&project, &part, index, progress)
                    .map(Arc::unwrap_or_clone)?;
                // The path as it is posted and simulated: rapids linked over the stock the
                // earlier operations leave (as `talas job` and Post job link them).
                match engine.linked(&project, &part, index, progress) {
                    Ok(linked) => linked.apply_to(&mut computed),
                    Err(ComputeError::Cancelled) => return Err(ComputeError::Cancelled),
                    Err(e) => computed.diagnostics.push(Diagnostic::warning(
                        None,
                        format!("rapids not linked over the in-process stock: {e}"),
                    )),
                }
                Ok(computed)
            },
        );
        let key = CalcKey {
            index,
            operation,
            cutter,
            part_id,
            digest,
        };
        self.ops.job.start(key, job);
        self.ops.active = Some(index);
    }

    /// Collect a finished calculation.
    pub(super) fn poll_calc_job(&mut self) {
        let Some(done) = self.ops.job.poll() else {
            return;
        };
        let (calc, elapsed) = (done.key, done.elapsed_s);
        let t = self.now_s();
        match done.result {
            Some(Ok(computed)) => {
                for d in &computed.diagnostics {
                    self.log
                        .push(t, d.severity, format!("{}: {d}", calc.operation.name()));
                }
                let s = &computed.toolpath.summary;
                self.log.push(
                    t,
                    Severity::Info,
                    format!(
                        "'{}': {} poses, {:.1} mm cut, {:.1} s at feed, computed in {elapsed:.2} s",
                        calc.operation.name(),
                        s.pose_count,
                        s.cut_length_mm,
                        s.estimated_time_s
                    ),
                );
                self.ops.store.insert(ComputedOp::new(
                    calc.operation,
                    calc.cutter,
                    calc.part_id,
                    calc.digest,
                    computed,
                    elapsed,
                ));
                self.ops.active = Some(calc.index);
                self.ops.picked_pose = None;
                self.ops.t_s = None;
                self.ops.playing = false;
            }
            Some(Err(ComputeError::Cancelled)) => {}
            Some(Err(e)) => self.log.notify(t, Severity::Error, e.to_string()),
            None => self.log.notify(
                t,
                Severity::Error,
                format!("{}: the worker stopped unexpectedly", done.label),
            ),
        }
    }

    /// The engine's digest of the inputs operation `index` reads as the project and part are
    /// now ([`crate::project::pipeline::digests`]; the part hashed once per part).
    pub(super) fn current_digest(&self, index: usize) -> Option<Digest> {
        let doc = self.document.as_ref()?;
        let part_id = doc.ids[0];
        let part = {
            let mut cached = self
                .ops
                .part_digest
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            match *cached {
                Some((id, d)) if id == part_id => d,
                _ => {
                    let d = part_digest(&doc.part.workpiece);
                    *cached = Some((part_id, d));
                    d
                }
            }
        };
        digests(&self.saved.session.project, part)
            .operations
            .get(index)
            .copied()
    }

    /// Save the fresh calculated paths beside the project file `project`
    /// ([`crate::project::saved_paths`]); a failure is logged (the project itself is saved).
    pub(super) fn save_paths(&mut self, project: &std::path::Path) {
        let count = self.saved.session.project.operations.len();
        let fresh: Vec<(usize, Digest, &Computed)> = (0..count)
            .filter_map(|i| {
                let (k, fresh) = self.result_index(i)?;
                let r = self.ops.store.get(k).filter(|_| fresh)?;
                Some((i, r.digest, &r.computed))
            })
            .collect();
        let file = saved_paths::paths_file(project);
        let saved = fresh.len();
        match saved_paths::save(&file, &fresh) {
            Ok(()) if saved > 0 => {
                self.log_info(format!(
                    "Saved {saved} calculated paths in {}",
                    file.display()
                ));
            }
            Ok(()) => {}
            Err(e) => {
                let t = self.now_s();
                self.log.notify(
                    t,
                    Severity::Warning,
                    format!("The calculated paths were not saved: {e}"),
                );
            }
        }
    }

    /// Take back the paths saved beside the open project's file whose inputs are unchanged
    /// (same digest now), so reopening does not recalculate them.
    pub(super) fn restore_saved_paths(&mut self) {
        let Some(path) = self.saved.session.path.clone() else {
            return;
        };
        let Some(part_id) = self.document.as_ref().map(|d| d.ids[0]) else {
            return;
        };
        let file = saved_paths::paths_file(&path);
        let saved = match saved_paths::load(&file) {
            Ok(s) => s,
            Err(e) => {
                let t = self.now_s();
                self.log.notify(
                    t,
                    Severity::Warning,
                    format!("Calculated paths not restored: {e}"),
                );
                return;
            }
        };
        if saved.is_empty() {
            return;
        }
        let project = self.saved.session.project.clone();
        let (mut restored, mut changed) = (0, 0);
        for (i, operation) in project.operations.iter().enumerate() {
            let (Some(digest), Some(tool)) =
                (self.current_digest(i), project.tools.get(operation.tool()))
            else {
                continue;
            };
            match saved_paths::matching(&saved, i, digest) {
                Some(s) => {
                    self.ops.store.insert(ComputedOp::new(
                        operation.clone(),
                        tool.cutter.clone(),
                        part_id,
                        digest,
                        s.computed.clone(),
                        0.0,
                    ));
                    restored += 1;
                }
                None if saved.iter().any(|s| s.operation == i) => changed += 1,
                None => {}
            }
        }
        let mut text = format!(
            "Restored {restored} calculated paths from {}",
            file.display()
        );
        if changed > 0 {
            text.push_str(&format!(
                "; {changed} saved paths no longer match their inputs (calculate them again)"
            ));
        }
        self.log_info(text);
    }

    /// The stored result for operation `index` and whether it is fresh (computed from every
    /// input the engine reads for it as they are now: the engine digest); a stale one is the
    /// latest computed for an operation of the same name.
    pub(super) fn result_index(&self, index: usize) -> Option<(usize, bool)> {
        let op = self.saved.session.project.operations.get(index)?;
        let part_id = self.document.as_ref()?.ids[0];
        if let Some(digest) = self.current_digest(index)
            && let Some(i) = self.ops.store.find(digest, part_id)
        {
            return Some((i, true));
        }
        let stale = self.ops.store.latest_named(op.name())?;
        let i = self.ops.store.find(stale.digest, stale.part_id)?;
        Some((i, false))
    }

    /// The active operation's result (fresh or stale).
    pub(super) fn active_result(&self) -> Option<&ComputedOp> {
        let (i, _) = self.result_index(self.ops.active?)?;
        self.ops.store.get(i)
    }

    /// What the operation editor shows for operation `index`, with the features' `sections`.
    pub(super) fn operation_view<'a>(
        &'a self,
        index: usize,
        sections: Sections<'a>,
    ) -> OperationView<'a> {
        let result = self
            .result_index(index)
            .and_then(|(i, fresh)| Some((self.ops.store.get(i)?, fresh)));
        let running = self
            .ops
            .job
            .key()
            .filter(|c| c.index == index)
            .and(self.ops.job.job())
            .map(|j| (j.progress.fraction(), j.elapsed_s()));
        let active = self.ops.active == Some(index);
        OperationView {
            sections: Some(sections),
            project: &self.saved.session.project,
            index,
            document: self.document.as_ref(),
            result,
            running,
            picked_pose: self.ops.picked_pose.filter(|_| active),
            playback_pose: self.playback_pose().filter(|_| active),
            path_shown: !self.ops.hidden.contains(&index),
        }
    }

    /// The playback clock of the active path: the time each pose is reached in the jerk-limited
    /// plan of its posted program when that is current, else at the programmed feeds.
    pub(super) fn active_clock(&self) -> Option<&[f64]> {
        let index = self.ops.active?;
        if let Some(clock) = self.planned_clock(index) {
            return Some(clock);
        }
        Some(self.active_result()?.clock_s.as_slice())
    }

    /// Is the playback clock the jerk-limited plan's (true) or the feed estimate's?
    pub(super) fn clock_is_planned(&self) -> bool {
        self.ops
            .active
            .is_some_and(|i| self.planned_clock(i).is_some())
    }

    /// The pose the playback clock has reached, if playing back.
    pub(super) fn playback_pose(&self) -> Option<usize> {
        let t = self.ops.t_s?;
        Some(pose_at(self.active_clock()?, t))
    }

    /// The playback bar's view, when the active operation has a path.
    pub(super) fn playback_view(&self) -> Option<PlaybackView> {
        let clock = self.active_clock()?;
        let poses = clock.len();
        Some(PlaybackView {
            t_s: self.ops.t_s,
            duration_s: clock.last().copied().unwrap_or(0.0),
            playing: self.ops.playing,
            speed: self.ops.speed,
            pose: self
                .ops
                .t_s
                .map_or(poses.saturating_sub(1), |t| pose_at(clock, t)),
            poses,
            planned: self.clock_is_planned(),
        })
    }

    fn playback(&mut self, command: PlaybackCommand) {
        let Some(clock) = self.active_clock() else {
            return;
        };
        let clock = clock.to_vec();
        let duration = clock.last().copied().unwrap_or(0.0);
        // Playback takes over from a picked pose (stepping starts from it).
        let picked = match command {
            PlaybackCommand::Speed(_) => None,
            _ => self.ops.picked_pose.take(),
        };
        let pose = picked.unwrap_or_else(|| {
            self.ops
                .t_s
                .map_or(clock.len().saturating_sub(1), |t| pose_at(&clock, t))
        });
        match command {
            PlaybackCommand::Play => {
                if self.ops.t_s.is_none_or(|t| t >= duration) {
                    self.ops.t_s = Some(0.0);
                }
                self.ops.playing = true;
            }
            PlaybackCommand::Pause => self.ops.playing = false,
            PlaybackCommand::Toggle => {
                let next = if self.ops.playing {
                    PlaybackCommand::Pause
                } else {
                    PlaybackCommand::Play
                };
                self.playback(next);
            }
            PlaybackCommand::Reset => {
                self.ops.playing = false;
                self.ops.t_s = None;
            }
            PlaybackCommand::Seek(t) => {
                self.ops.t_s = Some(t.clamp(0.0, duration));
                if let Some(p) = self.playback_pose() {
                    self.follow_pose(p);
                }
            }
            PlaybackCommand::Step(n) => {
                self.ops.playing = false;
                let target = if n < 0 {
                    pose.saturating_sub(n.unsigned_abs() as usize)
                } else {
                    pose.saturating_add(n as usize)
                };
                let target = target.min(clock.len().saturating_sub(1));
                self.ops.t_s = clock.get(target).copied();
                self.follow_pose(target);
            }
            PlaybackCommand::Speed(s) if s.is_finite() && s > 0.0 => self.ops.speed = s,
            PlaybackCommand::Speed(_) => {}
        }
    }

    /// Advance the playback clock by `dt_s` of wall time.
    pub(super) fn tick_playback(&mut self, dt_s: f64) {
        if !self.ops.playing {
            return;
        }
        let Some(duration) = self.active_clock().and_then(|c| c.last().copied()) else {
            self.ops.playing = false;
            return;
        };
        let t = self.ops.t_s.unwrap_or(0.0) + dt_s.clamp(0.0, 0.25) * self.ops.speed;
        if t >= duration {
            self.ops.t_s = Some(duration);
            self.ops.playing = false;
        } else {
            self.ops.t_s = Some(t);
            self.run.ctx.request_repaint();
        }
        if let Some(p) = self.playback_pose() {
            self.follow_pose(p);
        }
    }

    /// The paths to draw: the active operation's (up to the playback pose) and, when asked, every
    /// other fresh one; plus the legend of the scallop colouring.
    pub(super) fn path_instances(
        &mut self,
    ) -> (Vec<LineInstance>, Option<(String, ScalarMapping)>) {
        let feed = if self.ops.colouring == PathColouring::PlannedFeed {
            self.feed_coloured_path()
        } else {
            None
        };
        let mut out = Vec::new();
        let mut legend = None;
        let count = self.saved.session.project.operations.len();
        if count != self.ops.hidden_at_count {
            self.ops.hidden.clear();
        }
        let active = self.ops.active.filter(|&a| a < count);
        let playback = self.playback_pose();
        for i in 0..count {
            let is_active = Some(i) == active;
            if !(is_active || self.ops.show_all) || self.ops.hidden.contains(&i) {
                continue;
            }
            let Some((k, fresh)) = self.result_index(i) else {
                continue;
            };
            if !fresh && !is_active {
                continue;
            }
            let colouring = self.ops.colouring;
            let mut next_id = self.ops.next_id;
            let Some(r) = self.ops.store.get_mut(k) else {
                continue;
            };
            let (id, data) = r.render_lines(colouring, &mut next_id);
            if is_active && colouring == PathColouring::Scallop {
                legend = r
                    .scallop_mapping()
                    .map(|m| ("Predicted scallop (mm)".to_string(), m));
            }
            let (id, data) = match (&feed, is_active) {
                (Some((fid, fdata, m)), true) => {
                    legend = Some(("Planned feed (mm/min)".to_string(), *m));
                    (*fid, Arc::clone(fdata))
                }
                _ => (id, data),
            };
            out.push(LineInstance {
                id,
                data: Arc::clone(&data),
                world_from_lines: Mat4::IDENTITY,
                draw_segments: if is_active { playback } else { None },
            });
            if is_active && self.ops.show_axes {
                // Vectors a little longer than the cutter's diameter, drawn up to the playback.
                let length = (2.0 * r.cutter.diameter).max(1.0);
                let (id, data, poses) = r.axis_lines(length, &mut next_id);
                let upto = playback.map(|p| poses.partition_point(|&q| q <= p));
                out.push(LineInstance {
                    id,
                    data,
                    world_from_lines: Mat4::IDENTITY,
                    draw_segments: upto,
                });
            }
            self.ops.next_id = next_id;
        }
        // The picked pose's move, highlighted (white, with a cross at the tip), unless that
        // path is hidden.
        if let (Some(a), Some(p), Some((k, _))) = (
            active.filter(|a| !self.ops.hidden.contains(a)),
            self.ops.picked_pose,
            active.and_then(|a| self.result_index(a)),
        ) {
            if self
                .ops
                .highlight
                .as_ref()
                .is_none_or(|(key, _, _)| *key != (a, p, k))
            {
                let size = self
                    .document
                    .as_ref()
                    .map_or(1.0, |d| 0.01 * (d.bounds.max - d.bounds.min).max_element())
                    .max(0.2) as f32;
                let lines = self
                    .active_result()
                    .and_then(|r| crate::app::toolpaths::highlight_move(r.toolpath(), p, size));
                self.ops.highlight = lines.map(|l| {
                    self.ops.next_id += 1;
                    ((a, p, k), self.ops.next_id, Arc::new(l))
                });
            }
            if let Some((_, id, data)) = &self.ops.highlight {
                out.push(LineInstance {
                    id: *id,
                    data: Arc::clone(data),
                    world_from_lines: Mat4::IDENTITY,
                    draw_segments: None,
                });
            }
        }
        (out, legend)
    }

    /// The active path coloured by planned feed, when its program is posted and current.
    fn feed_coloured_path(&self) -> Option<(DataId, Arc<crate::render::LineData>, ScalarMapping)> {
        let index = self.ops.active?;
        let (k, true) = self.result_index(index)? else {
            return None;
        };
        self.posted(index)?
            .feed_lines(self.ops.store.get(k)?.toolpath())
    }

    /// The comparison of the computed operations: strategy, tool, cut length, poses, passes,
    /// time at feed and largest predicted scallop side by side (fresh results only); the paths
    /// themselves show together with View → Tool Paths → All operations.
    pub(super) fn compare_ui(&mut self, ctx: &egui::Context, commands: &mut Vec<Command>) {
        if !self.ops.compare_open {
            return;
        }
        let mut open = true;
        let rows: Vec<(usize, &ComputedOp)> = (0..self.saved.session.project.operations.len())
            .filter_map(|i| {
                let (k, fresh) = self.result_index(i)?;
                fresh.then(|| Some((i, self.ops.store.get(k)?)))?
            })
            .collect();
        let base = rows
            .first()
            .map(|(_, r)| r.toolpath().summary.cut_length_mm);
        egui::Window::new("Compare operations")
            .open(&mut open)
            .default_width(760.0)
            .show(ctx, |ui| {
                if rows.is_empty() {
                    ui.weak("Calculate two or more operations to compare them.");
                    return;
                }
                egui::Grid::new("compare")
                    .striped(true)
                    .spacing([14.0, 4.0])
                    .show(ui, |ui| {
                        for h in [
                            "Operation",
                            "Strategy",
                            "Tool",
                            "Cut length",
                            "vs first",
                            "Poses",
                            "Passes",
                            "Time at feed",
                            "Max scallop",
                        ] {
                            ui.label(egui::RichText::new(h).strong());
                        }
                        ui.end_row();
                        for (i, r) in &rows {
                            let s = &r.toolpath().summary;
                            if ui
                                .selectable_label(self.ops.active == Some(*i), r.operation.name())
                                .clicked()
                            {
                                commands.push(Command::Inspect(
                                    super::super::state::Focus::Operation(*i),
                                ));
                            }
                            ui.label(r.operation.kind().label());
                            ui.label(crate::tools::tool_spec(&r.cutter));
                            ui.monospace(format!("{:.1} mm", s.cut_length_mm));
                            ui.monospace(base.filter(|b| *b > 0.0).map_or_else(
                                || "—".into(),
                                |b| format!("{:+.1} %", (s.cut_length_mm / b - 1.0) * 100.0),
                            ));
                            ui.monospace(s.pose_count.to_string());
                            ui.monospace(r.computed.passes.to_string());
                            ui.monospace(super::super::widgets::duration_text(s.estimated_time_s));
                            ui.monospace(
                                s.predicted_max_scallop_mm.map_or_else(
                                    || "—".into(),
                                    |h| format!("{:.1} µm", h * 1000.0),
                                ),
                            );
                            ui.end_row();
                        }
                    });
                ui.add_space(6.0);
                let mut all = self.ops.show_all;
                if ui
                    .checkbox(&mut all, "Show every operation's path in the viewport")
                    .changed()
                {
                    commands.push(Command::SetShowAllPaths(all));
                }
            });
        if !open {
            self.ops.compare_open = false;
        }
    }
}
