//! Live cutting of the control's motion: the motion played since the last cut goes into the
//! stock; collisions and cuts with the spindle stopped become alarms that stop the machine.

use super::{Control, Kind};
use crate::control::codes;
use crate::gcode::{MotionBlock, MotionKind};
use crate::simulation::{Collision, CollisionKind};

/// Removed volume above which a piece of motion counts as cutting (mm³).
const CUT_MM3: f64 = 1e-6;

impl Control {
    /// Cut the motion played since the last cut into the stock; collisions, and fed motion
    /// that removes material while the spindle stands, become alarms and stop the motion.
    pub(super) fn cut_pending(&mut self) {
        let Some(a) = &mut self.active else {
            return;
        };
        if self.cfg.stock.is_none() {
            return;
        }
        let s = a.run.path_position();
        let pieces = a.run.pieces(a.cut_s, s);
        a.cut_s = s;
        a.since_cut = 0.0;
        // Program blocks carry their spindle speed (0 after M5 or before M3/M4); jogs and
        // homing run with the spindle buttons' state.
        let program = matches!(a.kind, Kind::Auto | Kind::Mdi);
        let buttons_off = self.spindle_dir == 0.0;
        let stopped = |b: &MotionBlock| {
            !matches!(b.kind, MotionKind::Rapid)
                && if program {
                    b.spindle_rpm == 0.0
                } else {
                    buttons_off
                }
        };
        let mut rest = pieces.as_slice();
        while let Some(first) = rest.first() {
            let off = stopped(first);
            let n = rest.iter().take_while(|b| stopped(b) == off).count();
            let (group, tail) = rest.split_at(n);
            rest = tail;
            let done = if off {
                group.iter().any(|b| self.cut_without_spindle(b))
            } else {
                self.cut_group(group.to_vec())
            };
            if done {
                return;
            }
        }
    }

    /// Cut blocks; true when an alarm stopped the machine (or the stock is gone).
    fn cut_group(&mut self, blocks: Vec<MotionBlock>) -> bool {
        let Some(stock) = &mut self.cfg.stock else {
            return true;
        };
        match stock.cut(blocks, &self.cfg.machine) {
            Ok(collisions) if collisions.is_empty() => false,
            Ok(collisions) => {
                for c in collisions {
                    self.collision_alarm(&c);
                }
                self.blocked = true;
                self.stop_all();
                true
            }
            Err(e) => {
                self.alarm(codes::SIMULATION, format!("stock simulation: {e}"));
                self.cfg.stock = None;
                true
            }
        }
    }

    /// Cut one fed block with the spindle standing; true when it removed material (alarm
    /// [`codes::SPINDLE_STOPPED`], the machine stops) or another alarm stopped it.
    fn cut_without_spindle(&mut self, block: &MotionBlock) -> bool {
        let before = self
            .cfg
            .stock
            .as_ref()
            .map_or(0.0, crate::control::LiveStock::removed_mm3);
        if self.cut_group(vec![block.clone()]) {
            return true;
        }
        let after = self
            .cfg
            .stock
            .as_ref()
            .map_or(0.0, crate::control::LiveStock::removed_mm3);
        if after - before <= CUT_MM3 {
            return false;
        }
        let line = (block.source_line > 0).then_some(block.source_line);
        let where_ = line.map_or(String::new(), |l| format!("line {l}: "));
        let p = block.start.xyz;
        let text = format!(
            "{where_}the tool cut {:.3} mm³ of the stock with the spindle stopped, \
             from ({:.3}, {:.3}, {:.3}) mm",
            after - before,
            p.x,
            p.y,
            p.z
        );
        let al = self.alarm(codes::SPINDLE_STOPPED, text);
        al.bodies = vec!["tool".into(), "stock".into()];
        al.position = Some(p.to_array());
        al.line = line;
        self.blocked = true;
        self.stop_all();
        true
    }

    fn collision_alarm(&mut self, c: &Collision) {
        let (code, body, what) = match c.kind {
            CollisionKind::Rapid => (
                codes::COLLISION_RAPID,
                "tool",
                "the tool went through the stock on a rapid move",
            ),
            CollisionKind::Shank => (codes::COLLISION_SHANK, "shank", "the shank hit the stock"),
            CollisionKind::Holder => (
                codes::COLLISION_HOLDER,
                "holder",
                "the holder hit the stock",
            ),
        };
        let line = (c.block > 0).then_some(c.block);
        let where_ = line.map_or(String::new(), |l| format!("line {l}: "));
        let text = format!(
            "{where_}{what} at ({:.3}, {:.3}, {:.3}) mm, {:.3} mm deep",
            c.position.x, c.position.y, c.position.z, c.depth_mm
        );
        let al = self.alarm(code, text);
        al.bodies = vec![body.into(), "stock".into()];
        al.position = Some(c.position.to_array());
        al.line = line;
    }
}
