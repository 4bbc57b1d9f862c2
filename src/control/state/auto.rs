//! AUTO mode: the program interpreted line by line (with the travel check), cycle start and
//! the next line's motion.

use std::collections::{BTreeMap, VecDeque};

use crate::control::{Mode, codes};
use crate::feed::travel_violations;
use crate::gcode::{MotionBlock, Session};

use super::{AutoRun, Control, ControlError, Item, Kind, refuse};

impl Control {
    /// Interprets the loaded program from its first line without running it or raising an
    /// alarm: the first line that cannot be read, as AUTO's alarm would name it. `talas
    /// control` refuses such a program before its script runs (exit 2), where AUTO alone
    /// would only raise alarm 30 at cycle start.
    ///
    /// # Errors
    /// [`ControlError::Refused`] naming the line; also when no program is loaded.
    pub fn check_program(&self) -> Result<(), ControlError> {
        let Some((_, text)) = &self.program else {
            return refuse("no program loaded");
        };
        let mut session = Session::new(self.interp_options())
            .map_err(|e| ControlError::Refused(e.to_string()))?;
        for (i, raw) in text.lines().enumerate() {
            let r = session
                .run_line(raw, i + 1)
                .map_err(|e| ControlError::Refused(e.to_string()))?;
            if r.program_end {
                break;
            }
        }
        Ok(())
    }

    /// Refuse motion leaving the travel with an alarm naming the first block and axis.
    pub(super) fn travel_ok(&mut self, blocks: &[MotionBlock]) -> bool {
        let (v, _) = travel_violations(blocks, &self.cfg.machine, 1);
        let Some(v) = v.first() else {
            return true;
        };
        let unit = if matches!(v.axis, 'A' | 'B' | 'C') {
            "°"
        } else {
            " mm"
        };
        let a = self.alarm(
            codes::TRAVEL,
            format!(
                "line {}: axis {} would reach {:.4}{unit}, beyond its travel limit {:.4}{unit}; \
                 refused before it started",
                v.line, v.axis, v.value, v.limit
            ),
        );
        a.axis = Some(v.axis);
        a.line = Some(v.line);
        false
    }

    pub(super) fn cycle_start(&mut self, from_line: usize) -> Result<(), ControlError> {
        self.can_move()?;
        if let Some(h) = self.held.take() {
            if self.active.is_some() {
                self.held = Some(h);
                return refuse("still braking");
            }
            if h.by_override && (self.overrides[0] <= 0.0 || self.overrides[1] <= 0.0) {
                self.held = Some(h);
                return refuse("a 0 % override holds the motion: raise it to resume");
            }
            self.start_run(h.blocks, h.kind, None);
            return Ok(());
        }
        if self.mode != Mode::Auto {
            return refuse("cycle start runs a program in AUTO mode (or resumes a hold)");
        }
        if self.auto.is_some() {
            if self.stopped && self.is_idle() {
                self.stopped = false;
                self.auto_next();
            }
            return Ok(());
        }
        if !self.is_idle() {
            return refuse("the machine is moving");
        }
        if !self.homed_all() {
            self.alarm(codes::NOT_HOMED, "home the machine before AUTO".into());
            return Ok(());
        }
        let Some((name, text)) = self.program.clone() else {
            return refuse("no program loaded");
        };
        if let Some(run) = self.interpret_program(&name, &text, from_line.max(1)) {
            self.auto = Some(run);
            self.stopped = false;
            self.auto_next();
        }
        Ok(())
    }

    /// The whole program interpreted from the present position, checked against the travel.
    ///
    /// Run from line: the lines before `from_line` are interpreted for their modal state only
    /// (units, plane, distance mode, offsets, feed, spindle, tool, TCP), without motion; the
    /// first block from `from_line` on starts at the present position.
    pub(super) fn interpret_program(
        &mut self,
        name: &str,
        text: &str,
        from_line: usize,
    ) -> Option<AutoRun> {
        let Ok(mut session) = Session::new(self.interp_options()) else {
            return None;
        };
        let mut run = AutoRun {
            items: VecDeque::new(),
            modal: BTreeMap::new(),
            stop_after_run: false,
        };
        let mut all = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let r = match session.run_line(raw, i + 1) {
                Ok(r) => r,
                Err(e) => {
                    self.alarm(codes::GCODE, format!("{name}: {e}")).line = Some(e.line);
                    return None;
                }
            };
            if i + 2 == from_line {
                session.set_position(self.joints(&self.pos));
            }
            if r.program_end && i + 1 < from_line {
                let text = format!(
                    "{name}: the program ends at line {} before line {from_line}",
                    i + 1
                );
                self.alarm(codes::GCODE, text).line = Some(from_line);
                return None;
            }
            if i + 1 < from_line {
                continue;
            }
            run.modal.insert(i + 1, session.modal());
            all.extend(r.program.blocks.iter().cloned());
            run.items.push_back(Item {
                blocks: r.program.blocks,
                dwell_s: r.program.dwells.iter().map(|d| d.seconds).sum(),
                stop: r.program_stop,
                optional_stop: r.optional_stop,
                end: r.program_end,
            });
            if r.program_end {
                break;
            }
        }
        self.travel_ok(&all).then_some(run)
    }

    /// Start the next stretch of the program: blocks up to a stop, a dwell or the end.
    pub(super) fn auto_next(&mut self) {
        let single = self.single_block;
        let optional = self.optional_stop;
        let Some(auto) = &mut self.auto else {
            return;
        };
        let mut chunk: Vec<MotionBlock> = Vec::new();
        let mut stop_after = false;
        let mut dwell = 0.0;
        while let Some(item) = auto.items.front() {
            if item.dwell_s > 0.0 && !chunk.is_empty() {
                break;
            }
            let Some(item) = auto.items.pop_front() else {
                break;
            };
            if item.dwell_s > 0.0 {
                dwell = item.dwell_s;
                break;
            }
            let moved = !item.blocks.is_empty();
            chunk.extend(item.blocks);
            if item.stop || (item.optional_stop && optional) || (single && moved) {
                stop_after = true;
                break;
            }
            if item.end {
                auto.items.clear();
                break;
            }
        }
        auto.stop_after_run = stop_after;
        let finished = auto.items.is_empty() && !stop_after && dwell <= 0.0;
        if dwell > 0.0 {
            self.dwell_left = dwell;
            return;
        }
        if chunk.is_empty() {
            if stop_after {
                self.stopped = true;
            } else if finished {
                self.auto = None;
            }
            return;
        }
        if finished {
            auto.stop_after_run = false;
        }
        self.start_run(chunk, Kind::Auto, None);
    }
}
