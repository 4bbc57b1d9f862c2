//! Feed scheduling from the force window: a target peak force (N; by default the tool's force
//! limit, else 80 % of the computed peak), a background job (progress, Cancel) running
//! [`crate::project::force_schedule::schedule_path`] on the computed forces, its report (planned
//! cycle time before and after in s, and how the peak force spreads over the cutting time),
//! and Apply, which makes the scheduled path the operation's computed path (so playback,
//! posting, export and simulation use it until the operation is calculated again).

use std::sync::Arc;

use super::Outcome;
use crate::app::command::Command;
use crate::app::job::{Job, JobSlot};
use crate::diagnostics::Progress;
use crate::force::ForceError;
use crate::machine::Machine;
use crate::project::force_schedule::{Schedule, ScheduleInput, TimedVariant, schedule_path};
use crate::toolpath::ToolRecord;

/// Lowest feed a schedule may set, mm/min.
pub const MIN_FEED_MM_PER_MIN: f64 = 10.0;

/// What a schedule was computed for.
#[derive(Clone, Debug, PartialEq)]
pub struct ScheduleKey {
    /// The operation.
    pub index: usize,
    /// The force result it was computed from (its serial number).
    pub result: u64,
    /// Target peak force, N.
    pub target_n: f64,
}

/// The feed-scheduling part of the force window.
#[derive(Default)]
pub struct SchedulePanel {
    /// Target peak resultant force, N (`None`: the default for the result).
    pub target_n: Option<f64>,
    job: JobSlot<Result<Schedule, String>, ScheduleKey>,
    /// The finished schedule.
    pub result: Option<(ScheduleKey, Arc<Schedule>)>,
    /// The last problem.
    pub message: Option<String>,
    /// The schedule applied last (operation and key).
    pub applied: Option<ScheduleKey>,
}

/// The default target: the tool's force limit, else 80 % of the computed peak (N).
#[must_use]
pub fn default_target(o: &Outcome) -> f64 {
    o.timeline.limits.max_force_n.unwrap_or_else(|| {
        let peak = o.timeline.forces.totals.peak_resultant_n;
        ((0.8 * peak) * 10.0).round().max(10.0) / 10.0
    })
}

/// One line of a timed variant.
#[must_use]
pub fn variant_text(label: &str, v: &TimedVariant, target_n: f64) -> String {
    let s = &v.force_spread;
    format!(
        "{label}: cycle {:.2} s, {} blocks · peak force within ±5 % of {target_n:.1} N for {:.1} % \
         of the {:.2} s cutting time, above for {:.1} % · median {:.1} N, 5–95 % {:.1}–{:.1} N, \
         max {:.1} N",
        v.cycle_time_s,
        v.blocks,
        100.0 * s.within_5_percent,
        s.cutting_time_s,
        100.0 * s.above_5_percent + 0.0,
        s.p50_n,
        s.p05_n,
        s.p95_n,
        s.max_n,
    )
}

impl SchedulePanel {
    /// Is a schedule being computed?
    #[must_use]
    pub fn is_running(&self) -> bool {
        self.job.is_running()
    }

    /// Its job, for the status bar.
    #[must_use]
    pub fn status(&self) -> Option<crate::app::job::JobStatus> {
        self.job.status()
    }

    /// Stop the running schedule; its label when there was one.
    pub fn cancel(&mut self) -> Option<String> {
        let label = self.job.cancel()?;
        self.message = Some("Schedule cancelled".into());
        Some(label)
    }

    /// Forget everything (a new part or project).
    pub fn reset(&mut self) {
        let _ = self.job.cancel();
        self.result = None;
        self.message = None;
        self.applied = None;
    }

    /// Start scheduling the feeds of `outcome` (result number `serial` of operation `index`)
    /// at the target, timed on the machine `machine_name`.
    pub fn start(
        &mut self,
        outcome: &Arc<Outcome>,
        (index, serial): (usize, u64),
        machine_name: &str,
        ctx: &egui::Context,
    ) {
        let target = self.target_n.unwrap_or_else(|| default_target(outcome));
        let machine = match Machine::resolve(machine_name) {
            Ok(m) => m,
            Err(e) => {
                self.message = Some(format!("Machine {machine_name}: {e}"));
                return;
            }
        };
        let key = ScheduleKey {
            index,
            result: serial,
            target_n: target,
        };
        let o = Arc::clone(outcome);
        self.cancel();
        self.message = None;
        let label = format!("Feed schedule at {target:.1} N");
        self.job.start(
            key,
            Job::start(label, ctx, move |p| run(&o, &machine, target, p)),
        );
    }

    /// Collect a finished job.
    pub fn poll(&mut self) {
        let Some(done) = self.job.poll() else { return };
        match done.result {
            Some(Ok(s)) => self.result = Some((done.key, Arc::new(s))),
            Some(Err(e)) if e == "cancelled" => self.message = Some("Schedule cancelled".into()),
            Some(Err(e)) => self.message = Some(format!("Feeds not scheduled: {e}")),
            None => self.message = Some("the worker stopped unexpectedly".into()),
        }
    }

    /// Draw the controls and the report; Apply pushes the command that makes the scheduled
    /// path the operation's.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        outcome: &Arc<Outcome>,
        current: (usize, u64),
        machine_name: &str,
        commands: &mut Vec<Command>,
    ) {
        let mut target = self.target_n.unwrap_or_else(|| default_target(outcome));
        ui.horizontal(|ui| {
            ui.label("Target peak force");
            ui.add(
                egui::DragValue::new(&mut target)
                    .range(1.0..=1.0e6)
                    .speed(1.0)
                    .suffix(" N"),
            )
            .on_hover_text(
                "The peak resultant force per revolution the feeds are set to (1 N to 1 MN)",
            );
            if let Some(job) = self.job.job() {
                ui.add(
                    egui::ProgressBar::new(job.progress.fraction() as f32)
                        .desired_width(120.0)
                        .show_percentage(),
                );
                if ui.button("Cancel schedule").clicked() {
                    self.cancel();
                }
            } else if ui
                .button("Schedule feeds")
                .on_hover_text(format!(
                    "Feeds for the target force ({MIN_FEED_MM_PER_MIN} mm/min up to the machine's \
                     X/Y velocity), both paths timed by the feed planner on {machine_name}"
                ))
                .clicked()
            {
                self.target_n = Some(target);
                self.start(outcome, current, machine_name, ui.ctx());
            }
        });
        self.target_n = Some(target);
        if let Some(m) = &self.message {
            ui.colored_label(ui.visuals().warn_fg_color, m);
        }
        let Some((key, s)) = &self.result else { return };
        if (key.index, key.result) != current {
            return;
        }
        ui.label(variant_text("Before", &s.before, key.target_n));
        ui.label(variant_text("After ", &s.after, key.target_n));
        ui.horizontal(|ui| {
            let dt = s.after.cycle_time_s - s.before.cycle_time_s;
            ui.label(format!(
                "Cycle time {:.2} s before, {:.2} s after ({dt:+.2} s); feeds {:.0}–{:.0} mm/min",
                s.before.cycle_time_s,
                s.after.cycle_time_s,
                s.feed_range_mm_per_min[0],
                s.feed_range_mm_per_min[1],
            ));
            let applied = self.applied.as_ref() == Some(key);
            if ui
                .add_enabled(!applied, egui::Button::new("Apply scheduled feeds"))
                .on_hover_text(
                    "Make the scheduled path the operation's computed path: playback, posting, \
                     export and simulation use it until the operation is calculated again",
                )
                .clicked()
            {
                commands.push(Command::ReplacePath(
                    key.index,
                    Arc::new(s.toolpath.clone()),
                ));
                self.applied = Some(key.clone());
            }
            if applied {
                ui.label("Applied");
            }
        });
    }
}

fn run(o: &Outcome, machine: &Machine, target: f64, p: &Progress) -> Result<Schedule, String> {
    let tool = ToolRecord {
        spec: crate::tools::tool_spec(&o.cutter),
        cutter: o.cutter.clone(),
    };
    schedule_path(
        &ScheduleInput {
            moves: &o.timeline.moves,
            forces: &o.timeline.forces,
            tool: &tool,
            coefficients: &o.coefficients,
            machine,
            target_n: target,
            min_feed_mm_per_min: MIN_FEED_MM_PER_MIN,
            max_feed_mm_per_min: None,
        },
        p,
    )
    .map_err(|e| match e {
        ForceError::Input(m) if m == "cancelled" => m,
        other => other.to_string(),
    })
}
