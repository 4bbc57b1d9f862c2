//! Live cutting: the motion the control has played since the last cut, as blocks, is cut into
//! the dexel stock through the simulation's own move planner and removal (`plan_program`,
//! `run_moves`), so jogging, MDI and AUTO cut as `talas simulate` does; each piece continues
//! the step before it (as inside one whole run). Collisions the removal reports (the cutting
//! end through material on a rapid, shank or holder in the material) and fed pieces that
//! remove material with the spindle standing come back as a [`CutOutcome`] for the control to
//! raise as alarms.
//!
//! The cutting runs either on the caller's thread ([`LiveStock::run_job`], the command line
//! and the tests) or on a worker thread that owns the stock ([`CutWorker`], the operator
//! panel): the same jobs in the same order give the same stock bit for bit. After a job whose
//! outcome stops the machine the worker drops every later job until [`CutWorker::resume`], as
//! the control would not have cut them.

use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;

use crate::control::CutPiece;
use crate::diagnostics::Progress;
use crate::gcode::{MotionBlock, Program};
use crate::geometry::mesh::TriMesh;
use crate::machine::Machine;
use crate::simulation::{
    Collision, Continued, DexelStock, MovePlan, SimError, SimMove, SimOptions, Step, StepOptions,
    StockCache, plan_program, run_moves_cached,
};
use crate::tools::Cutter;

/// Removed volume above which a piece of motion counts as cutting (mm³).
pub const CUT_MM3: f64 = 1e-6;

/// The stock and the tool cutting it.
pub struct LiveStock {
    /// The stock.
    pub stock: DexelStock,
    /// The tool in the spindle.
    pub cutter: Cutter,
    /// Step bounds (from the resolution, as `talas simulate` sets them).
    pub steps: StepOptions,
    /// Volume at the start, mm³ (summed tile by tile as the removed volume is).
    pub initial_volume_mm3: f64,
    /// The last step cut (the next piece continues it when it starts where it ended).
    last_step: Option<(Step, SimMove)>,
    /// The block being cut in its own steps.
    current: Option<WholeBlock>,
    /// The stock's culling tiles and material per tile, kept between the pieces (a piece
    /// costs what it touches, not a pass over the whole stock).
    cache: StockCache,
}

/// One piece of the control's motion to cut.
#[derive(Clone, Debug)]
pub struct CutJob {
    /// Consecutive pieces of programmed blocks, in order.
    pub pieces: Vec<CutPiece>,
    /// The spindle stands during these blocks: each is cut alone and the first that removes
    /// more than [`CUT_MM3`] stops the job.
    pub spindle_off: bool,
}

/// What cutting a [`CutJob`] found.
#[derive(Clone, Debug, PartialEq)]
pub enum CutOutcome {
    /// Cut without anything to report.
    Clean,
    /// Collisions of the tool, shank or holder with the material (the machine stops).
    Collisions(Vec<Collision>),
    /// Piece `block` of the job removed `removed_mm3` with the spindle standing.
    SpindleStopped {
        /// The piece of motion that cut.
        block: Box<MotionBlock>,
        /// Volume it removed, mm³.
        removed_mm3: f64,
    },
    /// The simulation failed (the stock is dropped).
    Failed(String),
}

impl CutOutcome {
    /// Whether the machine stops on this outcome.
    #[must_use]
    pub fn stops(&self) -> bool {
        !matches!(self, Self::Clean)
    }
}

impl LiveStock {
    /// A stock cut by `cutter`, with step bounds from the stock's resolution `resolution_mm`.
    /// (The stock is then changed only through this: its culling tiles are kept here.)
    #[must_use]
    pub fn new(stock: DexelStock, cutter: Cutter, resolution_mm: f64) -> Self {
        let steps = StepOptions::for_resolution(resolution_mm, cutter.flute_length);
        let cache = StockCache::new(&stock);
        let initial_volume_mm3 = cache.volume_mm3(&stock);
        Self {
            stock,
            cutter,
            steps,
            initial_volume_mm3,
            last_step: None,
            current: None,
            cache,
        }
    }

    /// Removed volume so far, mm³ (read off the culling tiles: no pass over the stock).
    #[must_use]
    pub fn removed_mm3(&self) -> f64 {
        self.initial_volume_mm3 - self.cache.volume_mm3(&self.stock)
    }

    /// Cut `job` and say what it found.
    pub fn run_job(&mut self, job: CutJob, machine: &Machine) -> CutOutcome {
        let result = if job.spindle_off {
            self.cut_spindle_off(&job.pieces, machine)
        } else {
            self.cut_pieces(&job.pieces, machine).map(|c| {
                if c.is_empty() {
                    CutOutcome::Clean
                } else {
                    CutOutcome::Collisions(c)
                }
            })
        };
        result.unwrap_or_else(|e| CutOutcome::Failed(e.to_string()))
    }

    fn cut_spindle_off(
        &mut self,
        pieces: &[CutPiece],
        machine: &Machine,
    ) -> Result<CutOutcome, SimError> {
        for p in pieces {
            let before = self.removed_mm3();
            let collisions = self.cut_pieces(std::slice::from_ref(p), machine)?;
            if !collisions.is_empty() {
                return Ok(CutOutcome::Collisions(collisions));
            }
            let removed_mm3 = self.removed_mm3() - before;
            if removed_mm3 > CUT_MM3 {
                return Ok(CutOutcome::SpindleStopped {
                    block: Box::new(p.piece.clone()),
                    removed_mm3,
                });
            }
        }
        Ok(CutOutcome::Clean)
    }

    /// Cut whole `blocks` in order, continuing the last piece cut; the collisions found.
    ///
    /// # Errors
    /// The simulation's [`SimError`] (a block that needs more steps than allowed).
    pub fn cut(
        &mut self,
        blocks: Vec<MotionBlock>,
        machine: &Machine,
    ) -> Result<Vec<Collision>, SimError> {
        let pieces: Vec<CutPiece> = blocks
            .into_iter()
            .map(|b| CutPiece {
                piece: b.clone(),
                block: b,
                to: 1.0,
            })
            .collect();
        self.cut_pieces(&pieces, machine)
    }

    /// Cut the motion `pieces` (pieces of programmed blocks, in order, continuing the last
    /// piece cut); the collisions found. A block that `talas simulate` cuts in one straight
    /// step (a line without rotary motion) is cut piece by piece; a block of several steps
    /// (an arc, a rotary move) is cut in the whole block's own steps, each once the motion
    /// has passed its end, so that cutting a program in pieces gives the stock of one whole
    /// run, bit for bit.
    ///
    /// # Errors
    /// The simulation's [`SimError`] (a block that needs more steps than allowed).
    pub fn cut_pieces(
        &mut self,
        pieces: &[CutPiece],
        machine: &Machine,
    ) -> Result<Vec<Collision>, SimError> {
        if pieces.is_empty() {
            return Ok(Vec::new());
        }
        let mut plan = MovePlan::default();
        // The last step cut leads the plan, so that the first new step may continue it.
        if let Some((step, mv)) = self.last_step {
            plan.moves.push(SimMove {
                first_step: 0,
                ..mv
            });
            plan.steps.push(Step {
                move_index: 0,
                ..step
            });
        }
        let lead = plan.moves.len();
        for p in pieces {
            let whole = match self.current.take() {
                Some(c) if c.block == p.block => c,
                _ => WholeBlock {
                    plan: plan_one(&p.block, machine, &self.steps)?,
                    block: p.block.clone(),
                    done: 0,
                },
            };
            let n = whole.plan.steps.len();
            if n <= 1 {
                append(
                    &mut plan,
                    &plan_one(&p.piece, machine, &self.steps)?,
                    0..usize::MAX,
                );
                self.current = Some(whole);
                continue;
            }
            #[allow(clippy::cast_precision_loss, clippy::cast_possible_truncation)]
            #[allow(clippy::cast_sign_loss)]
            let passed = if p.to >= 1.0 {
                n
            } else {
                ((p.to * n as f64).floor().max(0.0) as usize).min(n)
            };
            let done = whole.done.min(passed);
            append(&mut plan, &whole.plan, done..passed);
            self.current = Some(WholeBlock {
                done: passed.max(whole.done),
                ..whole
            });
        }
        if plan.moves.len() == lead {
            return Ok(Vec::new());
        }
        let report = run_moves_cached(
            &mut self.stock,
            &self.cutter,
            &plan,
            lead..plan.moves.len(),
            &SimOptions::default(),
            &Progress::new(),
            &Continued {
                after_earlier_moves: lead > 0,
                progress: 0.0..1.0,
            },
            &mut self.cache,
        )?;
        self.last_step = plan
            .steps
            .last()
            .and_then(|s| plan.moves.get(s.move_index).map(|m| (*s, *m)));
        Ok(report.collisions)
    }
}

/// The steps of the block being cut, and how many of them are cut.
struct WholeBlock {
    block: MotionBlock,
    plan: MovePlan,
    done: usize,
}

/// The simulation's plan of one block.
fn plan_one(
    block: &MotionBlock,
    machine: &Machine,
    steps: &StepOptions,
) -> Result<MovePlan, SimError> {
    let program = Program {
        blocks: vec![block.clone()],
        ..Program::default()
    };
    plan_program(&program, Some(machine), steps)
}

/// Append the steps `range` of `src` (with their moves) to `out`.
fn append(out: &mut MovePlan, src: &MovePlan, range: std::ops::Range<usize>) {
    for (i, m) in src.moves.iter().enumerate() {
        let end = src
            .moves
            .get(i + 1)
            .map_or(src.steps.len(), |n| n.first_step);
        let (a, b) = (m.first_step.max(range.start), end.min(range.end));
        let Some(steps) = src.steps.get(a..b).filter(|s| !s.is_empty()) else {
            continue;
        };
        let move_index = out.moves.len();
        out.moves.push(SimMove {
            first_step: out.steps.len(),
            ..*m
        });
        out.steps
            .extend(steps.iter().map(|s| Step { move_index, ..*s }));
    }
}

enum ToWorker {
    Job(u64, CutJob),
    Resume,
    Mesh,
}

/// A finished job of a [`CutWorker`].
#[derive(Clone, Debug)]
pub struct CutDone {
    /// The number [`CutWorker::send`] gave the job.
    pub id: u64,
    /// What the cutting found.
    pub outcome: CutOutcome,
    /// Removed volume after the job, mm³.
    pub removed_mm3: f64,
}

/// A thread that owns a [`LiveStock`] and cuts the jobs sent to it, in order.
pub struct CutWorker {
    to: Option<Sender<ToWorker>>,
    from: Receiver<CutDone>,
    meshes: Receiver<TriMesh>,
    handle: Option<JoinHandle<LiveStock>>,
    next_id: u64,
}

impl CutWorker {
    /// Start the worker on `stock`, cutting on `machine`.
    #[must_use]
    pub fn spawn(mut stock: LiveStock, machine: Machine) -> Self {
        let (to, jobs) = channel::<ToWorker>();
        let (done, from) = channel::<CutDone>();
        let (mesh_out, meshes) = channel::<TriMesh>();
        let handle = std::thread::spawn(move || {
            let mut halted = false;
            for msg in jobs {
                match msg {
                    ToWorker::Resume => halted = false,
                    ToWorker::Mesh => {
                        // The panel may have gone; the cutting goes on regardless.
                        let _ = mesh_out.send(stock.stock.closed_mesh());
                    }
                    ToWorker::Job(id, job) => {
                        let outcome = if halted {
                            CutOutcome::Clean
                        } else {
                            stock.run_job(job, &machine)
                        };
                        halted |= outcome.stops();
                        let removed_mm3 = stock.removed_mm3();
                        if done
                            .send(CutDone {
                                id,
                                outcome,
                                removed_mm3,
                            })
                            .is_err()
                        {
                            break;
                        }
                    }
                }
            }
            stock
        });
        Self {
            to: Some(to),
            from,
            meshes,
            handle: Some(handle),
            next_id: 0,
        }
    }

    /// Queue `job`; returns its number.
    pub fn send(&mut self, job: CutJob) -> u64 {
        let id = self.next_id;
        self.next_id += 1;
        if let Some(to) = &self.to {
            // A worker that has gone (it panicked) answers nothing; `take` reports it.
            let _ = to.send(ToWorker::Job(id, job));
        }
        id
    }

    /// Cut the jobs sent after this again (after a reset of the alarm that halted it).
    pub fn resume(&self) {
        if let Some(to) = &self.to {
            let _ = to.send(ToWorker::Resume);
        }
    }

    /// Ask for a closed mesh of the stock as it is after the jobs sent so far (to draw it);
    /// [`CutWorker::take_mesh`] hands it over when it is made.
    pub fn request_mesh(&self) {
        if let Some(to) = &self.to {
            let _ = to.send(ToWorker::Mesh);
        }
    }

    /// The newest stock mesh the worker has made since the last call, if any.
    pub fn take_mesh(&self) -> Option<TriMesh> {
        self.meshes.try_iter().last()
    }

    /// A finished job, when one is ready; `wait` blocks until one is (None when the worker
    /// has gone).
    pub fn receive(&self, wait: bool) -> Option<CutDone> {
        if wait {
            return self.from.recv().ok();
        }
        self.from.try_recv().ok()
    }

    /// Stop the worker after the jobs sent and hand back the stock (None when the worker
    /// thread failed).
    pub fn finish(mut self) -> Option<LiveStock> {
        self.to = None;
        self.handle.take().and_then(|h| h.join().ok())
    }
}
