//! Motion on the simulated clock: overrides, feed hold and stop, planning a run, advancing the
//! clock (cutting the stock, checking the machine for collisions) and ending a motion.

use crate::control::motion::Run;
use crate::control::{OverrideKind, codes};
use crate::feed::path::{SLOTS, joint_vector, slot_of};
use crate::gcode::{MotionBlock, MotionKind};

use super::{
    Active, AfterBrake, CUT_PERIOD_S, Control, ControlError, Held, Kind, SUB_STEP_S, refuse,
};

impl Control {
    pub(super) fn set_override(
        &mut self,
        kind: OverrideKind,
        pct: f64,
    ) -> Result<(), ControlError> {
        let ok = match kind {
            OverrideKind::Feed => (0.0..=150.0).contains(&pct),
            OverrideKind::Rapid => [0.0, 25.0, 50.0, 100.0].contains(&pct),
            OverrideKind::Spindle => (50.0..=120.0).contains(&pct),
        };
        if !ok {
            return refuse(match kind {
                OverrideKind::Feed => format!("feed override {pct} % must lie in 0–150 %"),
                OverrideKind::Rapid => format!("rapid override {pct} % must be 0, 25, 50 or 100 %"),
                OverrideKind::Spindle => format!("spindle override {pct} % must lie in 50–120 %"),
            });
        }
        let i = match kind {
            OverrideKind::Feed => 0,
            OverrideKind::Rapid => 1,
            OverrideKind::Spindle => 2,
        };
        let changed = self.overrides[i] != pct;
        self.overrides[i] = pct;
        if let Some(a) = &mut self.active
            && i < 2
            && pct > 0.0
            && changed
            && matches!(a.kind, Kind::Auto | Kind::Mdi)
            && !a.run.braking()
        {
            if a.run.rests_after_present() {
                // Planned again where the motion is at rest anyway.
                a.retime = true;
            } else {
                // Blended through: brake inside the limits and go on at the new feed.
                a.after_brake = AfterBrake::Resume;
                a.run.start_brake();
            }
        }
        if i < 2 && pct <= 0.0 {
            self.hold(true);
        } else if i < 2
            && self.overrides[0] > 0.0
            && self.overrides[1] > 0.0
            && let Some(h) = self.held.take()
        {
            if h.by_override && self.active.is_none() {
                self.start_run(h.blocks, h.kind, None);
            } else {
                self.held = Some(h);
            }
        }
        Ok(())
    }

    /// Feed hold: AUTO and MDI motion brakes and waits for a resume; jogs and homing stop.
    pub(super) fn hold(&mut self, by_override: bool) {
        let Some(a) = &mut self.active else {
            return;
        };
        if a.run.braking() {
            if a.after_brake == AfterBrake::Resume {
                // Braking for an override change: stay at rest instead.
                a.after_brake = AfterBrake::Hold { by_override };
            }
            return;
        }
        a.after_brake = match a.kind {
            Kind::Auto | Kind::Mdi => AfterBrake::Hold { by_override },
            _ => AfterBrake::Discard,
        };
        if a.after_brake == AfterBrake::Discard {
            self.home_queue.clear();
            self.mpg_pending = None;
        }
        a.run.start_brake();
    }

    /// Brake whatever moves and abandon it, the program and everything queued.
    pub(super) fn stop_all(&mut self) {
        if let Some(a) = &mut self.active {
            a.after_brake = AfterBrake::Discard;
            a.run.start_brake();
        }
        self.auto = None;
        self.held = None;
        self.stopped = false;
        self.dwell_left = 0.0;
        self.home_queue.clear();
        self.mpg_pending = None;
    }

    /// The blocks as the planner gets them: feeds scaled by the overrides, rapids slowed by
    /// the rapid override (as a fed move at that fraction of the fastest the axes allow).
    pub(super) fn planned_copy(&self, blocks: &[MotionBlock], kind: Kind) -> Vec<MotionBlock> {
        let program = matches!(kind, Kind::Auto | Kind::Mdi);
        let (feed, rapid) = (self.overrides[0] / 100.0, self.overrides[1] / 100.0);
        blocks
            .iter()
            .map(|b| {
                let mut c = b.clone();
                if !program {
                    return c;
                }
                if matches!(b.kind, MotionKind::Rapid) {
                    if rapid < 1.0 {
                        c.kind = MotionKind::Linear;
                        c.inverse_time = false;
                        c.feed_mm_per_min = rapid * self.fastest_mm_per_min(b);
                    }
                } else {
                    c.feed_mm_per_min *= feed;
                }
                c
            })
            .collect()
    }

    /// The fastest path feed of a straight block that keeps every axis within its velocity.
    pub(super) fn fastest_mm_per_min(&self, b: &MotionBlock) -> f64 {
        let (s, e) = (joint_vector(&b.start), joint_vector(&b.end));
        let xyz = b.length_mm();
        let rot = (3..SLOTS)
            .map(|k| (e[k] - s[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let len = if xyz > 1e-12 { xyz } else { rot };
        let mut v = f64::INFINITY;
        for (name, lim) in &self.axes {
            if let Some(k) = slot_of(*name) {
                let d1 = (e[k] - s[k]).abs() / len.max(1e-300);
                if d1 > 0.0 {
                    v = v.min(lim.velocity / d1);
                }
            }
        }
        if v.is_finite() { v * 60.0 } else { 1.0 }
    }

    pub(super) fn start_run(
        &mut self,
        blocks: Vec<MotionBlock>,
        kind: Kind,
        limit: Option<(char, f64)>,
    ) {
        let program = matches!(kind, Kind::Auto | Kind::Mdi);
        if program && (self.overrides[0] <= 0.0 || self.overrides[1] <= 0.0) {
            self.held = Some(Held {
                blocks,
                kind,
                by_override: true,
            });
            return;
        }
        let planned = self.planned_copy(&blocks, kind);
        let corner = if program {
            crate::feed::DEFAULT_CORNERS
        } else {
            crate::feed::CornerPolicy::ExactStop
        };
        match Run::plan(blocks, &planned, &self.axes, corner) {
            Ok(run) => {
                self.active = Some(Active {
                    run,
                    kind,
                    after_brake: AfterBrake::Discard,
                    limit_alarm: limit,
                    cut_s: 0.0,
                    since_cut: 0.0,
                    check_s: 0.0,
                    check_pos: self.pos,
                    retime: false,
                    start_contacts: self.collide.as_ref().map_or_else(Vec::new, |m| {
                        let j =
                            crate::control::collide::machine_joints(&self.cfg.machine, &self.pos);
                        m.contacts(&self.cfg.machine, &j)
                    }),
                });
            }
            Err(e) => {
                self.alarm(codes::PLAN, format!("the motion cannot be planned: {e}"));
                self.auto = None;
                self.home_queue.clear();
            }
        }
    }

    /// Run the simulated clock on by `dt` seconds (motion, dwells, cutting).
    pub fn advance(&mut self, dt: f64) {
        if !(dt > 0.0) || !dt.is_finite() {
            return;
        }
        let mut left = dt;
        while left > 1e-12 {
            self.clock_steps += 1;
            if self.active.is_some() && !self.cutting_keeps_up() {
                // The motion waits for the cutting worker.
                return;
            }
            if self.active.as_ref().is_some_and(|a| a.run.finished()) {
                self.finish_active();
                continue;
            }
            let Some(a) = &mut self.active else {
                if self.dwell_left > 0.0 {
                    let h = left.min(self.dwell_left);
                    self.dwell_left -= h;
                    self.clock += h;
                    left -= h;
                    if self.dwell_left <= 1e-12 {
                        self.dwell_left = 0.0;
                        self.auto_next();
                    }
                    continue;
                }
                self.clock += left;
                break;
            };
            let retime = a.retime;
            let used = if retime {
                a.run.step_within_segment(left.min(SUB_STEP_S))
            } else {
                a.run.step(left.min(SUB_STEP_S))
            };
            a.since_cut += used;
            self.clock += used;
            left -= used;
            let k = a.run.kinematics();
            let cut_due = a.since_cut >= CUT_PERIOD_S;
            let check_due = crate::control::collide::due(&a.check_pos, &k.position);
            for i in 0..SLOTS {
                let p = &mut self.peaks[i];
                p[0] = p[0].max(k.velocity[i].abs());
                p[1] = p[1].max(k.acceleration[i].abs());
                p[2] = p[2].max(k.jerk[i].abs());
            }
            if check_due {
                self.check_machine();
            }
            if cut_due {
                self.cut_pending();
            }
            if retime
                && self
                    .active
                    .as_ref()
                    .is_some_and(|a| a.run.at_segment_boundary())
            {
                self.retime_rest();
            }
        }
        if self.active.as_ref().is_some_and(|a| a.run.finished()) {
            self.finish_active();
        }
        self.poll_cutting();
    }

    /// Run the program (or whatever moves) as fast as possible: the clock on until the
    /// control is idle (or `max_s` has passed); returns the time run. Motion is played in the
    /// steps of a millisecond [`Control::advance`] takes (the same peaks, machine checks and
    /// 20 ms pieces of cutting, so the same stock, alarms and times as a run in real time),
    /// and a dwell passes in one step. This is the engine's "as fast as possible": about 1 ms
    /// of CPU per second of machining on a Z-level roughing (benches/README.md); a panel
    /// that wants it calls this each frame with the simulated seconds it grants the frame.
    pub fn advance_until_idle(&mut self, max_s: f64) -> f64 {
        let t0 = self.clock;
        while !self.is_idle() && self.clock - t0 < max_s {
            let left = max_s - (self.clock - t0);
            let dt = if self.active.is_none() && self.dwell_left > 0.0 {
                // Nothing moves until the dwell is over: it passes in one step.
                self.dwell_left.min(left)
            } else {
                SUB_STEP_S.min(left)
            };
            self.advance(dt);
        }
        self.clock - t0
    }

    /// Cut whatever motion has not been cut into the stock yet (the stock is otherwise cut
    /// every 20 ms of motion and at the end of each motion).
    pub fn flush_cutting(&mut self) {
        self.cut_pending();
        self.wait_for_cutting();
    }

    /// Test the motion played since the last test for machine collisions; the first contact
    /// becomes an alarm and stops the machine.
    pub(super) fn check_machine(&mut self) {
        let (Some(a), Some(model)) = (&mut self.active, &self.collide) else {
            return;
        };
        if self.blocked {
            return;
        }
        let s1 = a.run.path_position();
        let s0 = a.check_s.min(s1);
        a.check_s = s1;
        a.check_pos = a.run.position_at(s1);
        let machine = &self.cfg.machine;
        let run = &a.run;
        let Some((s, contacts)) = crate::control::collide::first_contact_along(
            model,
            machine,
            |u| run.position_at(u),
            (s0, s1),
            &a.start_contacts,
        ) else {
            return;
        };
        let p = run.position_at(s);
        let line = run
            .block_at(s)
            .and_then(|i| run.blocks().get(i))
            .map(|b| b.source_line)
            .filter(|&l| l > 0);
        let pairs: Vec<String> = contacts
            .iter()
            .map(|c| format!("{} against {}", c.bodies[0], c.bodies[1]))
            .collect();
        let where_ = line.map_or(String::new(), |l| format!("line {l}: "));
        let text = format!(
            "{where_}collision: {} at {}",
            pairs.join(", "),
            crate::control::collide::describe_position(machine, &p)
        );
        let bodies = contacts
            .first()
            .map(|c| c.bodies.to_vec())
            .unwrap_or_default();
        let al = self.alarm(codes::COLLISION_MACHINE, text);
        al.bodies = bodies;
        al.position = Some([p[0], p[1], p[2]]);
        al.line = line;
        self.blocked = true;
        self.stop_all();
    }

    /// After a machine collision the axes brake within their limits, so they come to rest
    /// past the contact: the collision alarm says where they stopped and how far past the
    /// contact that is (the DRO shows the stop, the alarm the contact; both are named).
    fn note_stop_after_contact(&mut self) {
        let stop = self.pos;
        let Some(al) = self
            .alarms
            .iter_mut()
            .rev()
            .find(|a| a.code == codes::COLLISION_MACHINE)
        else {
            return;
        };
        let Some(c) = al.position else {
            return;
        };
        if al.text.contains("; stopped at") {
            return;
        }
        let past =
            ((stop[0] - c[0]).powi(2) + (stop[1] - c[1]).powi(2) + (stop[2] - c[2]).powi(2)).sqrt();
        al.text.push_str(&format!(
            "; stopped at X{:.3} Y{:.3} Z{:.3} mm, {past:.3} mm past the contact (braking within \
             the axis limits)",
            stop[0], stop[1], stop[2]
        ));
    }

    /// Bring the cut and the machine up to date and take the active motion out, its end
    /// position made the control's (`None` when nothing moves).
    fn settle_active(&mut self) -> Option<Active> {
        self.check_machine();
        self.cut_pending();
        self.wait_for_cutting();
        let a = self.active.take()?;
        self.pos = a.run.kinematics().position;
        self.session.set_position(self.joints(&self.pos));
        Some(a)
    }

    /// At rest between two blocks after an override change: the rest of the motion is
    /// planned again with the overrides now set.
    pub(super) fn retime_rest(&mut self) {
        let Some(a) = self.settle_active() else {
            return;
        };
        let blocks = a.run.remaining_blocks();
        if blocks.is_empty() || self.blocked {
            self.active = Some(a);
            return;
        }
        self.log_played_prefix(&a, blocks.len());
        self.start_run(blocks, a.kind, a.limit_alarm);
    }

    /// The motion has ended (or braked to rest): settle the position and go on.
    pub(super) fn finish_active(&mut self) {
        let Some(a) = self.settle_active() else {
            return;
        };
        if a.run.braking() && self.blocked {
            self.note_stop_after_contact();
        }
        if a.run.braking() {
            if let AfterBrake::Hold { by_override } = a.after_brake {
                let blocks = a.run.remaining_blocks();
                if !blocks.is_empty() {
                    self.log_played_prefix(&a, blocks.len());
                    self.held = Some(Held {
                        blocks,
                        kind: a.kind,
                        by_override,
                    });
                    return;
                }
            } else if a.after_brake == AfterBrake::Resume {
                let blocks = a.run.remaining_blocks();
                if !blocks.is_empty() && !self.blocked {
                    self.log_played_prefix(&a, blocks.len());
                    self.start_run(blocks, a.kind, a.limit_alarm);
                    return;
                }
            } else {
                if a.kind == Kind::Auto {
                    self.auto = None;
                }
                return;
            }
        }
        if let Some((axis, limit)) = a.limit_alarm {
            self.soft_limit_alarm(axis, limit);
        }
        if let Some(log) = self.played.as_mut()
            && matches!(a.kind, Kind::Auto | Kind::Mdi)
        {
            log.extend(a.run.blocks().iter().cloned());
        }
        match a.kind {
            Kind::Home(axis) => {
                if let Some(k) = slot_of(axis) {
                    self.homed[k] = true;
                }
                self.next_home_axis();
            }
            Kind::Auto => {
                if self.auto.as_ref().is_some_and(|r| r.stop_after_run) {
                    self.stopped = true;
                } else {
                    self.auto_next();
                }
            }
            Kind::Mpg(axis) => {
                if let Some((_, d)) = self.mpg_pending.take()
                    && let Ok((target, limit)) = self.jog_target(axis, d)
                {
                    self.start_jog(axis, target, limit, Kind::Mpg(axis));
                }
            }
            Kind::Jog { .. } | Kind::Mdi => {}
        }
    }

    /// Log the blocks of `a` run to their end when `left` blocks (the first maybe begun)
    /// remain.
    fn log_played_prefix(&mut self, a: &Active, left: usize) {
        if let Some(log) = self.played.as_mut()
            && matches!(a.kind, Kind::Auto | Kind::Mdi)
        {
            let done = a.run.blocks().len().saturating_sub(left);
            log.extend(a.run.blocks().iter().take(done).cloned());
        }
    }

    /// Keep a log of the program and MDI blocks the machine runs to their end, in order
    /// (`on`; off by default: a long program's log is large), or drop it.
    pub fn log_played(&mut self, on: bool) {
        self.played = on.then(Vec::new);
    }

    /// The program and MDI blocks run to their end since [`Control::log_played`] was switched
    /// on (a block resumed after a hold appears once, from where it resumed).
    #[must_use]
    pub fn played(&self) -> &[MotionBlock] {
        self.played.as_deref().unwrap_or(&[])
    }
}
