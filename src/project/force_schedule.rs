//! Feed scheduling of a path whose forces are computed: the feeds of its engaged pieces
//! rewritten by [`crate::force::schedule::schedule_feeds`] so that the peak resultant force
//! stays at a target (within the feed range and the machine's X/Y velocity), the pieces merged
//! back into straight segments (collinear neighbours of one move whose feeds agree within
//! 0.5 %), both the programmed and the scheduled paths timed by the jerk-limited feed planner
//! ([`crate::feed::plan`], clothoid blends of 0.05 mm), and the spread of the peak force over
//! the planned cutting time ([`crate::force::schedule::spread`], one sample per 2 ms at the
//! actual speed). `talas forces --schedule-force` and the workstation's force window both
//! call [`schedule_path`].

use glam::DVec3;

use crate::diagnostics::Progress;
use crate::feed::{CornerPolicy, PlanInput, PlanOptions, TimedPath, machine_limits, plan};
use crate::force::path::{ModeCoefficients, MoveClass, PathForces, PathMove, PathOptions};
use crate::force::schedule::{ScheduleOptions, Spread, TimeSample, schedule_feeds, spread};
use crate::force::{EndMill, ForceError};
use crate::gcode::{Joints, MotionBlock, MotionKind};
use crate::machine::Machine;
use crate::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};

/// Corner tolerance of the planner's blends when the paths are timed, mm.
pub const CORNER_TOLERANCE_MM: f64 = 0.05;

/// What a path's feed schedule is computed from.
pub struct ScheduleInput<'a> {
    /// The path's moves at their programmed feeds.
    pub moves: &'a [PathMove],
    /// Its forces, move by move and piece by piece (the engagements).
    pub forces: &'a PathForces,
    /// The tool.
    pub tool: &'a ToolRecord,
    /// Coefficients per milling mode.
    pub coefficients: &'a ModeCoefficients,
    /// The machine whose limits time the paths.
    pub machine: &'a Machine,
    /// Target peak resultant force, N.
    pub target_n: f64,
    /// Lowest feed the schedule may set, mm/min.
    pub min_feed_mm_per_min: f64,
    /// Highest feed, mm/min (capped by the machine's X/Y velocity; `None`: that velocity).
    pub max_feed_mm_per_min: Option<f64>,
}

/// One path timed by the planner.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TimedVariant {
    /// Planned cycle time, s.
    pub cycle_time_s: f64,
    /// Straight blocks.
    pub blocks: usize,
    /// Spread of the peak force over the cutting time.
    pub force_spread: Spread,
}

/// A path's feed schedule.
#[derive(Clone, Debug)]
pub struct Schedule {
    /// The scheduled path (a pose per segment end, vertical tool).
    pub toolpath: Toolpath,
    /// The programmed path, timed.
    pub before: TimedVariant,
    /// The scheduled path, timed.
    pub after: TimedVariant,
    /// The feed range used, mm/min.
    pub feed_range_mm_per_min: [f64; 2],
}

/// The feed schedule of `input`'s path; `progress` goes from 0 to 1 and a cancel stops it.
///
/// # Errors
/// [`ForceError::Input`] for a tilted tool, a target or feed range out of range, a cancel, or
/// a plan the feed planner refuses; the errors of [`schedule_feeds`].
pub fn schedule_path(
    input: &ScheduleInput<'_>,
    progress: &Progress,
) -> Result<Schedule, ForceError> {
    let tilted = input
        .moves
        .iter()
        .flat_map(|m| &m.steps)
        .any(|s| s.axis.normalize_or_zero().z < 1.0 - 1e-9);
    if tilted {
        return Err(ForceError::Input(
            "feed scheduling handles 3-axis paths (a vertical tool) only".into(),
        ));
    }
    let mill = EndMill::from_cutter(&input.tool.cutter)?;
    let axes = machine_limits(input.machine);
    let vmax = axes
        .iter()
        .filter(|(n, _)| matches!(n, 'X' | 'Y'))
        .map(|(_, l)| l.velocity * 60.0)
        .fold(f64::INFINITY, f64::min);
    let max_feed = input.max_feed_mm_per_min.unwrap_or(vmax).min(vmax);
    let steps = PathOptions::default().revolution_steps;
    let forces = input.forces;
    let feeds = schedule_feeds(
        &mill,
        input.coefficients,
        &forces.pieces,
        |i| input.moves.get(i).map_or(0.0, |m| m.feed_mm_per_min),
        &ScheduleOptions {
            target_n: input.target_n,
            min_feed_mm_per_min: input.min_feed_mm_per_min,
            max_feed_mm_per_min: max_feed,
            revolution_steps: steps,
        },
    )?;
    progress.set(0.3);
    let programmed: Vec<f64> = forces
        .pieces
        .iter()
        .map(|p| {
            input
                .moves
                .get(p.move_index)
                .map_or(0.0, |m| m.feed_mm_per_min)
        })
        .collect();
    let mut timed = Vec::with_capacity(2);
    let mut scheduled = Vec::new();
    for (k, f) in [&programmed, &feeds].into_iter().enumerate() {
        if progress.is_cancelled() {
            return Err(ForceError::Input("cancelled".into()));
        }
        let segs = segments(input.moves, forces, f);
        let path = plan(&PlanInput {
            blocks: blocks(&segs, max_feed).into(),
            axes: axes.clone(),
            options: PlanOptions {
                corner: CornerPolicy::Blend {
                    tolerance_mm: CORNER_TOLERANCE_MM,
                },
                ..PlanOptions::default()
            },
        })
        .map_err(|e| ForceError::Input(e.to_string()))?;
        let samples = time_samples(&path, &segs, forces);
        let sp = spread(
            &mill,
            input.coefficients,
            &forces.pieces,
            input.target_n,
            steps,
            samples,
        )?;
        timed.push(TimedVariant {
            cycle_time_s: path.cycle_time_s,
            blocks: segs.len(),
            force_spread: sp,
        });
        progress.set(0.3 + 0.35 * (k + 1) as f64);
        scheduled = segs;
    }
    let after = timed.pop().unwrap_or_else(empty_variant);
    let before = timed.pop().unwrap_or_else(empty_variant);
    Ok(Schedule {
        toolpath: toolpath_of(input.tool, &scheduled)?,
        before,
        after,
        feed_range_mm_per_min: [input.min_feed_mm_per_min, max_feed],
    })
}

fn empty_variant() -> TimedVariant {
    TimedVariant {
        cycle_time_s: 0.0,
        blocks: 0,
        force_spread: Spread::default(),
    }
}

/// A straight segment of the rewritten path: the pieces it covers (consecutive, collinear).
struct Segment {
    from: DVec3,
    to: DVec3,
    feed: f64,
    kind: MoveKind,
    rpm: f64,
    pieces: Vec<usize>,
}

/// Segments of the path with `feed[piece]` on the pieces of modelled moves and the programmed
/// feed elsewhere; collinear neighbours of one move whose feeds agree within 0.5 % merge (at
/// the lower feed).
fn segments(moves: &[PathMove], forces: &PathForces, feed: &[f64]) -> Vec<Segment> {
    let mut out: Vec<Segment> = Vec::new();
    let mut k = 0;
    for (i, m) in moves.iter().enumerate() {
        let kind = match forces.moves.get(i).map(|f| f.class) {
            Some(MoveClass::Rapid) => MoveKind::Rapid,
            Some(MoveClass::Plunge) => MoveKind::Plunge,
            _ => MoveKind::Cut,
        };
        let start = k;
        while forces.pieces.get(k).is_some_and(|p| p.move_index == i) {
            k += 1;
        }
        if start == k {
            for s in &m.steps {
                out.push(Segment {
                    from: s.from,
                    to: s.to,
                    feed: m.feed_mm_per_min,
                    kind,
                    rpm: m.spindle_rpm,
                    pieces: Vec::new(),
                });
            }
            continue;
        }
        for (j, p) in forces.pieces.iter().enumerate().take(k).skip(start) {
            let f = feed.get(j).copied().unwrap_or(m.feed_mm_per_min);
            if let Some(last) = out.last_mut() {
                let (a, b) = (
                    (last.to - last.from).normalize_or_zero(),
                    (p.to - p.from).normalize_or_zero(),
                );
                let mergeable = last
                    .pieces
                    .last()
                    .is_some_and(|q| forces.pieces.get(*q).is_some_and(|q| q.move_index == i))
                    && a.dot(b) > 1.0 - 1e-12
                    && last.to.distance(p.from) < 1e-9
                    && (last.feed - f).abs() <= 0.005 * last.feed.max(f);
                if mergeable {
                    last.to = p.to;
                    last.feed = last.feed.min(f);
                    last.pieces.push(j);
                    continue;
                }
            }
            out.push(Segment {
                from: p.from,
                to: p.to,
                feed: f,
                kind,
                rpm: m.spindle_rpm,
                pieces: vec![j],
            });
        }
    }
    out
}

fn blocks(segs: &[Segment], rapid_feed: f64) -> Vec<MotionBlock> {
    segs.iter()
        .enumerate()
        .map(|(i, s)| MotionBlock {
            kind: if s.kind == MoveKind::Rapid {
                MotionKind::Rapid
            } else {
                MotionKind::Linear
            },
            start: Joints::xyz(s.from.x, s.from.y, s.from.z),
            end: Joints::xyz(s.to.x, s.to.y, s.to.z),
            feed_mm_per_min: if s.kind == MoveKind::Rapid {
                rapid_feed
            } else {
                s.feed
            },
            inverse_time: false,
            source_line: i + 1,
            tool: 1,
            tool_length_h: None,
            spindle_rpm: s.rpm,
            coolant: false,
            tcp: false,
            cycle: None,
        })
        .collect()
}

/// The time samples of `timed` mapped to the pieces (by projecting the position on the
/// block's segment), every 2 ms.
fn time_samples(timed: &TimedPath, segs: &[Segment], forces: &PathForces) -> Vec<TimeSample> {
    let period = 2e-3;
    timed
        .samples_every(period)
        .filter_map(|s| {
            let seg = segs.get(s.block)?;
            let first = *seg.pieces.first()?;
            let pos = DVec3::new(s.position[0], s.position[1], s.position[2]);
            let d = seg.to - seg.from;
            let len = d.length();
            let t = if len > 0.0 {
                ((pos - seg.from).dot(d) / len).clamp(0.0, len)
            } else {
                0.0
            };
            let mut piece = first;
            for &j in &seg.pieces {
                let p = forces.pieces.get(j)?;
                if p.from.distance(seg.from) <= t + 1e-9 {
                    piece = j;
                }
            }
            Some(TimeSample {
                dt_s: period,
                piece,
                feed_mm_per_min: s.feed * 60.0,
                programmed_mm_per_min: seg.feed,
            })
        })
        .collect()
}

/// The scheduled segments as a tool path: a rapid to the first segment's start, then a pose
/// per segment end with its feed (rapids without one).
fn toolpath_of(tool: &ToolRecord, segs: &[Segment]) -> Result<Toolpath, ForceError> {
    let Some(first) = segs.first() else {
        return Err(ForceError::Input("the path has no moves".into()));
    };
    let mut poses = vec![Pose::new(MoveKind::Rapid, first.from, DVec3::Z, 0.0)];
    for s in segs {
        let feed = if s.kind == MoveKind::Rapid {
            0.0
        } else {
            s.feed
        };
        poses.push(Pose::new(s.kind, s.to, DVec3::Z, feed));
    }
    Ok(Toolpath::new(tool.clone(), poses))
}
