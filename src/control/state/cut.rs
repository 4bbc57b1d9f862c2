//! Live cutting of the control's motion: the motion played since the last cut goes into the
//! stock, on this thread or on a [`CutWorker`]; collisions and cuts with the spindle stopped
//! become alarms that stop the machine.
//!
//! With a worker the motion runs ahead of the confirmed cutting by at most
//! [`MAX_PENDING_CUTS`] pieces (each about 20 ms of motion): past that the call or the
//! simulated clock waits for the worker ([`Control::pace_motion_by_cutting`]), and at the end of every motion (and before a replan or a reset)
//! the control waits for every piece sent. The jobs are the same as on this thread, in the
//! same order, so the stock is the same bit for bit; an alarm from the worker names the same
//! block and position, and the machine brakes from where it is when the answer arrives (at most
//! [`MAX_PENDING_CUTS`] pieces later, never past the end of the motion holding the block).

use std::collections::VecDeque;

use super::{Control, Kind};
use crate::control::cutting::{CutJob, CutOutcome, CutWorker};
use crate::control::{CutPiece, codes};
use crate::gcode::{MotionBlock, MotionKind};
use crate::geometry::mesh::TriMesh;
use crate::simulation::{Collision, CollisionKind};
use crate::tools::Cutter;

/// Most pieces of motion the worker may have unconfirmed before the clock waits for it.
pub const MAX_PENDING_CUTS: usize = 5;

/// The control's end of a [`CutWorker`].
pub(super) struct WorkerLink {
    worker: CutWorker,
    cutter: Cutter,
    removed_mm3: f64,
    pending: VecDeque<u64>,
    /// The worker's stock failed: nothing more is sent.
    failed: bool,
    /// The motion waits for the cutting instead of the caller.
    paced: bool,
    /// A stock mesh has been asked for and not yet taken.
    mesh_asked: bool,
    /// The removed volume (mm³) confirmed when the last mesh was asked for: a new mesh is
    /// asked for only after the stock has changed.
    meshed_at_mm3: Option<f64>,
}

impl Control {
    /// Move the stock to a worker thread: from now on the stock is cut off this thread
    /// (the operator panel's way; [`Control::stock`] is then `None`).
    pub fn start_cutting_worker(&mut self) {
        if self.worker.is_some() {
            return;
        }
        let Some(stock) = self.cfg.stock.take() else {
            return;
        };
        self.worker = Some(WorkerLink {
            cutter: stock.cutter.clone(),
            removed_mm3: stock.removed_mm3(),
            worker: CutWorker::spawn(stock, self.cfg.machine.clone()),
            pending: VecDeque::new(),
            failed: false,
            paced: false,
            mesh_asked: false,
            meshed_at_mm3: None,
        });
    }

    /// Wait for every piece sent, stop the worker and take the stock back onto this thread.
    pub fn stop_cutting_worker(&mut self) {
        self.wait_for_cutting();
        if let Some(link) = self.worker.take() {
            self.cfg.stock = link.worker.finish();
        }
    }

    /// The tool in the spindle (of the stock, here or on the worker).
    #[must_use]
    pub fn cutter(&self) -> Option<&Cutter> {
        match &self.worker {
            Some(w) => Some(&w.cutter),
            None => self.cfg.stock.as_ref().map(|s| &s.cutter),
        }
    }

    /// A closed mesh of the stock to draw, in table coordinates: at once when the stock is cut
    /// on this thread; with a worker, the newest mesh it has made since the last call (a new
    /// one is asked for when none is on its way and the stock has changed since the last, so
    /// calling this once per frame gives a mesh as often as the worker can make one between
    /// its cuts). `None` without a stock, while the worker's mesh is on its way, or when the
    /// stock has not changed since the last mesh.
    pub fn stock_mesh(&mut self) -> Option<TriMesh> {
        match &mut self.worker {
            Some(link) => {
                let mesh = link.worker.take_mesh();
                if mesh.is_some() {
                    link.mesh_asked = false;
                }
                if !link.mesh_asked && link.meshed_at_mm3 != Some(link.removed_mm3) {
                    link.worker.request_mesh();
                    link.mesh_asked = true;
                    link.meshed_at_mm3 = Some(link.removed_mm3);
                }
                mesh
            }
            None => self.cfg.stock.as_ref().map(|s| s.stock.closed_mesh()),
        }
    }

    /// Removed stock volume confirmed so far, mm³.
    #[must_use]
    pub fn removed_mm3(&self) -> f64 {
        match &self.worker {
            Some(w) => w.removed_mm3,
            None => self
                .cfg
                .stock
                .as_ref()
                .map_or(0.0, crate::control::LiveStock::removed_mm3),
        }
    }

    /// Pieces of motion sent to the worker and not yet answered.
    pub(super) fn cuts_pending(&self) -> usize {
        self.worker.as_ref().map_or(0, |w| w.pending.len())
    }

    /// Take one answer of the worker (waiting for it when `wait`); false when none came.
    fn take_answer(&mut self, wait: bool) -> bool {
        let Some(link) = &mut self.worker else {
            return false;
        };
        if link.pending.is_empty() {
            return false;
        }
        let Some(done) = link.worker.receive(wait) else {
            if wait {
                // The worker has gone: nothing will answer.
                link.pending.clear();
                link.failed = true;
            }
            return false;
        };
        link.pending.retain(|&id| id != done.id);
        link.removed_mm3 = done.removed_mm3;
        if matches!(done.outcome, CutOutcome::Failed(_)) {
            link.failed = true;
        }
        self.apply_outcome(done.outcome);
        true
    }

    /// Take the answers the worker has ready.
    pub(super) fn poll_cutting(&mut self) {
        while self.take_answer(false) {}
    }

    /// Take the ready answers; then, while [`MAX_PENDING_CUTS`] pieces or more are
    /// unanswered, wait for the worker (or, when the motion is paced by the cutting, say so:
    /// false means the motion waits).
    pub(super) fn cutting_keeps_up(&mut self) -> bool {
        self.poll_cutting();
        while self.cuts_pending() >= MAX_PENDING_CUTS {
            if self.worker.as_ref().is_some_and(|w| w.paced) {
                return false;
            }
            if !self.take_answer(true) {
                break;
            }
        }
        true
    }

    /// Wait until the worker has answered every piece sent.
    pub(super) fn wait_for_cutting(&mut self) {
        while self.take_answer(true) {}
    }

    /// With a worker: when the cutting falls five pieces of motion behind, the motion
    /// waits for it (`paced`, the panel: a frame never waits for the cutting, the simulated
    /// clock slows instead) or the call waits (the default: the motion on the simulated clock
    /// is the same as without a worker).
    pub fn pace_motion_by_cutting(&mut self, paced: bool) {
        if let Some(w) = &mut self.worker {
            w.paced = paced;
        }
    }

    /// After a reset: the worker cuts again what it is sent.
    pub(super) fn resume_cutting(&mut self) {
        if let Some(link) = &self.worker {
            link.worker.resume();
        }
    }

    /// Cut the motion played since the last cut into the stock; collisions, and fed motion
    /// that removes material while the spindle stands, become alarms and stop the motion.
    pub(super) fn cut_pending(&mut self) {
        let Some(a) = &mut self.active else {
            return;
        };
        let live = match &self.worker {
            Some(w) => !w.failed,
            None => self.cfg.stock.is_some(),
        };
        if !live {
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
        let stopped = |p: &CutPiece| {
            let b = &p.block;
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
            let job = CutJob {
                pieces: group.to_vec(),
                spindle_off: off,
            };
            if self.dispatch(job) {
                return;
            }
        }
    }

    /// Cut `job` here (true when its outcome stopped the machine) or send it to the worker.
    fn dispatch(&mut self, job: CutJob) -> bool {
        if let Some(link) = &mut self.worker {
            let id = link.worker.send(job);
            link.pending.push_back(id);
            return false;
        }
        let Some(stock) = &mut self.cfg.stock else {
            return true;
        };
        let outcome = stock.run_job(job, &self.cfg.machine);
        let stops = outcome.stops();
        self.apply_outcome(outcome);
        stops
    }

    /// Raise the alarms of a cut's outcome and stop the machine when it says so.
    fn apply_outcome(&mut self, outcome: CutOutcome) {
        match outcome {
            CutOutcome::Clean => return,
            CutOutcome::Collisions(collisions) => {
                for c in collisions {
                    self.collision_alarm(&c);
                }
            }
            CutOutcome::SpindleStopped { block, removed_mm3 } => {
                self.spindle_alarm(&block, removed_mm3);
            }
            CutOutcome::Failed(e) => {
                self.alarm(codes::SIMULATION, format!("stock simulation: {e}"));
                self.cfg.stock = None;
                return;
            }
        }
        self.blocked = true;
        self.stop_all();
    }

    fn spindle_alarm(&mut self, block: &MotionBlock, removed_mm3: f64) {
        let line = (block.source_line > 0).then_some(block.source_line);
        let where_ = line.map_or(String::new(), |l| format!("line {l}: "));
        let p = block.start.xyz;
        let text = format!(
            "{where_}the tool cut {removed_mm3:.3} mm³ of the stock with the spindle stopped, \
             from ({:.3}, {:.3}, {:.3}) mm",
            p.x, p.y, p.z
        );
        let al = self.alarm(codes::SPINDLE_STOPPED, text);
        al.bodies = vec!["tool".into(), "stock".into()];
        al.position = Some(p.to_array());
        al.line = line;
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
