//! Manual motion: homing, jogging (continuous, incremental, handwheel) and MDI lines.

use crate::control::{Mode, codes};
use crate::feed::path::{JointVector, slot_of};
use crate::gcode::{MotionBlock, MotionKind};

use super::{Control, ControlError, Kind, refuse};

impl Control {
    pub(super) fn home(&mut self) -> Result<(), ControlError> {
        self.can_move()?;
        if self.busy() {
            return refuse("homing needs the machine at rest");
        }
        self.mode = Mode::Ref;
        self.home_queue = self.cfg.home_order.iter().copied().collect();
        self.next_home_axis();
        Ok(())
    }

    pub(super) fn next_home_axis(&mut self) {
        let Some(axis) = self.home_queue.pop_front() else {
            return;
        };
        let Some(k) = slot_of(axis) else {
            return;
        };
        let mut target = self.pos;
        target[k] = self.cfg.home_position[k];
        let feed = self.axis_feed(axis, self.cfg.home_feed_mm_per_min);
        let block = self.line_block(&target, feed, 0);
        self.start_run(vec![block], Kind::Home(axis), None);
    }

    /// A jog-style feed in the block's units: mm/min, or rad/min on a rotary axis (the
    /// planner measures a rotary-only block in rad).
    pub(super) fn axis_feed(&self, axis: char, feed_mm_per_min: f64) -> f64 {
        if matches!(axis, 'A' | 'B' | 'C') {
            feed_mm_per_min.to_radians()
        } else {
            feed_mm_per_min
        }
    }

    pub(super) fn line_block(&self, target: &JointVector, feed: f64, line: usize) -> MotionBlock {
        MotionBlock {
            kind: MotionKind::Linear,
            start: self.joints(&self.pos),
            end: self.joints(target),
            feed_mm_per_min: feed,
            inverse_time: false,
            source_line: line,
            tool: 0,
            tool_length_h: None,
            spindle_rpm: 0.0,
            coolant: false,
            tcp: false,
            cycle: None,
        }
    }

    /// The target of a jog by `d` (mm or deg) clamped to the travel, and the limit it stops at.
    pub(super) fn jog_target(
        &self,
        axis: char,
        d: f64,
    ) -> Result<(JointVector, Option<(char, f64)>), ControlError> {
        if !d.is_finite() {
            return refuse(format!("jog distance {d} is not a number"));
        }
        if axis == crate::control::tool_axis::TOOL_AXIS {
            return Ok(crate::control::tool_axis::tool_axis_target(
                &self.cfg.machine,
                &self.pos,
                d,
            ));
        }
        let (Some(ax), Some(k)) = (self.cfg.machine.axis(axis), slot_of(axis)) else {
            return refuse(format!("the machine has no axis {axis}"));
        };
        let d = if ax.is_rotary() { d.to_radians() } else { d };
        let mut target = self.pos;
        let want = self.pos[k] + d;
        target[k] = want.clamp(ax.min, ax.max);
        let scale = if ax.is_rotary() {
            180.0 / std::f64::consts::PI
        } else {
            1.0
        };
        let limit = (target[k] != want).then_some((axis, target[k] * scale));
        Ok((target, limit))
    }

    pub(super) fn jog_by(&mut self, axis: char, d: f64, kind: Kind) -> Result<(), ControlError> {
        self.can_move()?;
        if !matches!(self.mode, Mode::Jog | Mode::Mpg) {
            return refuse("jogging needs JOG or MPG mode");
        }
        if self.busy() {
            // A key pressed again while the axis moves does not queue a move.
            return Ok(());
        }
        let (target, limit) = self.jog_target(axis, d)?;
        self.start_jog(axis, target, limit, kind);
        Ok(())
    }

    pub(super) fn start_jog(
        &mut self,
        axis: char,
        target: JointVector,
        limit: Option<(char, f64)>,
        kind: Kind,
    ) {
        let still = target
            .iter()
            .zip(&self.pos)
            .all(|(t, p)| (t - p).abs() <= 1e-12);
        if still {
            if let Some((axis, lim)) = limit {
                self.soft_limit_alarm(axis, lim);
            }
            return;
        }
        let feed = self.axis_feed(axis, self.jog_feed);
        let block = self.line_block(&target, feed, 0);
        self.start_run(vec![block], kind, limit);
    }

    pub(super) fn soft_limit_alarm(&mut self, axis: char, limit: f64) {
        let unit = if matches!(axis, 'A' | 'B' | 'C') {
            "°"
        } else {
            " mm"
        };
        let p = self.position();
        let a = self.alarm(
            codes::SOFT_LIMIT,
            format!("axis {axis} stopped at its soft limit {limit:.4}{unit}"),
        );
        a.axis = Some(axis);
        a.position = Some([p[0], p[1], p[2]]);
    }

    pub(super) fn jog_start(&mut self, axis: char, direction: f64) -> Result<(), ControlError> {
        self.can_move()?;
        if self.mode != Mode::Jog {
            return refuse("continuous jog needs JOG mode");
        }
        if self.busy() {
            // Held keys and auto-repeat never queue moves.
            return Ok(());
        }
        // Planned to the boundary: the whole travel in the jog direction.
        let (target, limit) = self.jog_target(axis, direction.signum() * 1e9)?;
        self.start_jog(axis, target, limit, Kind::Jog { continuous: true });
        Ok(())
    }

    pub(super) fn mpg(&mut self, axis: char, detents: i32) -> Result<(), ControlError> {
        self.can_move()?;
        if self.mode != Mode::Mpg {
            return refuse("the handwheel needs MPG mode");
        }
        let d = f64::from(detents) * self.increment;
        let moving_this = self
            .active
            .as_ref()
            .is_some_and(|a| a.kind == Kind::Mpg(axis) && !a.run.braking());
        if moving_this {
            // Position mode: detents turned while the axis moves are added to its target.
            match &mut self.mpg_pending {
                Some((pa, pd)) if *pa == axis => *pd += d,
                Some(_) => {}
                None => self.mpg_pending = Some((axis, d)),
            }
            return Ok(());
        }
        if self.busy() {
            return Ok(());
        }
        let (target, limit) = self.jog_target(axis, d)?;
        self.start_jog(axis, target, limit, Kind::Mpg(axis));
        Ok(())
    }

    pub(super) fn homed_all(&self) -> bool {
        self.cfg
            .machine
            .axes
            .iter()
            .all(|a| slot_of(a.name).is_some_and(|k| self.homed[k]))
    }

    pub(super) fn mdi(&mut self, line: &str) -> Result<(), ControlError> {
        self.can_move()?;
        if self.mode != Mode::Mdi {
            return refuse("MDI lines need MDI mode");
        }
        if self.busy() {
            return refuse("an MDI line waits for the machine to come to rest");
        }
        if !self.homed_all() {
            self.alarm(codes::NOT_HOMED, "home the machine before MDI".into());
            return Ok(());
        }
        self.mdi_count += 1;
        let n = self.mdi_count;
        self.session.set_position(self.joints(&self.pos));
        let result = match self.session.run_line(line, n) {
            Ok(r) => r,
            Err(e) => {
                self.alarm(codes::GCODE, format!("MDI {e}")).line = Some(n);
                return Ok(());
            }
        };
        self.spindle_dir = self.session.modal().spindle_direction;
        if !self.travel_ok(&result.program.blocks) {
            self.session.set_position(self.joints(&self.pos));
            return Ok(());
        }
        let dwell: f64 = result.program.dwells.iter().map(|d| d.seconds).sum();
        self.dwell_left += dwell;
        self.dwell_phase = None;
        if !result.program.blocks.is_empty() {
            self.start_run(result.program.blocks, Kind::Mdi, None);
        }
        Ok(())
    }
}
