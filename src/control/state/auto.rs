//! AUTO mode: the program interpreted line by line (with the travel check), cycle start and
//! the next line's motion.

use std::collections::{BTreeMap, VecDeque};

use crate::control::{Mode, codes};
use crate::feed::travel_violations;
use crate::gcode::{MotionBlock, interpret_traced};

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
        interpret_traced(text, &self.interp_options(), None)
            .map(|_| ())
            .map_err(|e| ControlError::Refused(e.to_string()))
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

    /// The whole program interpreted from the present position, checked against the travel:
    /// [`crate::gcode::interpret_traced`], the interpreter's own run of the whole program
    /// (canned cycles expanded, cutter compensation from the tool table, subroutines, loops
    /// and parameters), cut into the stretches AUTO plays between its stops and dwells.
    ///
    /// Run from line: the blocks before `from_line` are interpreted for their modal state only
    /// (units, plane, distance mode, offsets, feed, spindle, tool, TCP), without motion; the
    /// first block from `from_line` on starts at the present position.
    pub(super) fn interpret_program(
        &mut self,
        name: &str,
        text: &str,
        from_line: usize,
    ) -> Option<AutoRun> {
        let here = self.joints(&self.pos);
        let restart = (from_line > 1).then_some((from_line, here));
        let traced = match interpret_traced(text, &self.interp_options(), restart) {
            Ok(t) => t,
            Err(e) => {
                self.alarm(codes::GCODE, format!("{name}: {e}")).line = Some(e.line);
                return None;
            }
        };
        let first = traced
            .steps
            .iter()
            .position(|s| s.line >= from_line)
            .unwrap_or(traced.steps.len());
        if from_line > 1 {
            let ended = traced
                .steps
                .get(..first)
                .unwrap_or(&[])
                .iter()
                .find(|s| s.program_end);
            if let Some(end) =
                ended.or_else(|| traced.steps.last().filter(|_| first == traced.steps.len()))
            {
                let text = format!(
                    "{name}: the program ends at line {} before line {from_line}",
                    end.line
                );
                self.alarm(codes::GCODE, text).line = Some(from_line);
                return None;
            }
        }
        let mut run = AutoRun {
            items: VecDeque::new(),
            modal: BTreeMap::new(),
            stop_after_run: false,
        };
        let program = traced.program;
        let (mut b0, mut d0) = first
            .checked_sub(1)
            .and_then(|k| traced.steps.get(k))
            .map_or((0, 0), |s| (s.blocks_end, s.dwells_end));
        let blocks = &program.blocks;
        let mut all: Vec<MotionBlock> = Vec::new();
        for step in traced.steps.iter().skip(first) {
            run.modal.insert(step.line, step.modal.clone());
            // The step's motion, split at its dwells (a G82 dwells at the hole's bottom).
            for d in program.dwells.get(d0..step.dwells_end).unwrap_or(&[]) {
                let upto = d.before_block.max(b0).min(step.blocks_end.max(b0));
                let part = blocks.get(b0..upto).unwrap_or(&[]).to_vec();
                if !part.is_empty() {
                    all.extend(part.iter().cloned());
                    run.items.push_back(Item::motion(part));
                }
                run.items.push_back(Item {
                    dwell_s: d.seconds,
                    dwell_cycle: d.cycle,
                    ..Item::motion(Vec::new())
                });
                b0 = upto;
            }
            let part = blocks.get(b0..step.blocks_end).unwrap_or(&[]).to_vec();
            all.extend(part.iter().cloned());
            run.items.push_back(Item {
                stop: step.program_stop,
                optional_stop: step.optional_stop,
                end: step.program_end,
                ..Item::motion(part)
            });
            b0 = b0.max(step.blocks_end);
            d0 = d0.max(step.dwells_end);
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
        let mut dwell_phase = None;
        while let Some(item) = auto.items.front() {
            if item.dwell_s > 0.0 && !chunk.is_empty() {
                break;
            }
            let Some(item) = auto.items.pop_front() else {
                break;
            };
            if item.dwell_s > 0.0 {
                dwell = item.dwell_s;
                dwell_phase = item.dwell_cycle;
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
            self.dwell_phase = dwell_phase;
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
