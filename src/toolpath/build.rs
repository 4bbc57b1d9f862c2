//! Building tool paths of exact moves: the constructors that sample arcs, helices and cycles
//! into poses, the moves view, and the checks that keep segments and poses together.

use glam::DVec3;

use super::{
    ArcMove, CycleMove, CycleStep, ExactMove, ExactSegment, Move, MoveKind, Pose, Summary,
    Toolpath, ToolpathError,
};

/// Largest distance, mm, between a segment's exact end points and the poses it names.
const ENDPOINT_TOL_MM: f64 = 1e-6;

fn memory_err(place: &str, message: String) -> ToolpathError {
    ToolpathError {
        file: "<memory>".into(),
        place: place.into(),
        message,
    }
}

impl Toolpath {
    /// Append a straight move (or the first pose).
    pub fn push_pose(&mut self, pose: Pose) {
        self.poses.push(pose);
        self.resummarise();
    }

    /// Append a planar arc from the last pose about `centre` (projected into the start point's
    /// plane), turning `sweep_rad` about the unit `normal` (positive counter-clockwise), at the
    /// last pose's tool axis; sampled into poses whose chords stay within `chord_tol_mm`.
    ///
    /// # Errors
    /// No pose to start from, a bad arc (see [`ArcMove::validate`]) or a bad tolerance.
    pub fn push_arc(
        &mut self,
        centre: DVec3,
        normal: DVec3,
        sweep_rad: f64,
        kind: MoveKind,
        feed_mm_per_min: f64,
        chord_tol_mm: f64,
    ) -> Result<(), ToolpathError> {
        self.push_helix(
            centre,
            normal,
            sweep_rad,
            0.0,
            kind,
            feed_mm_per_min,
            chord_tol_mm,
        )
    }

    /// As [`Toolpath::push_arc`], rising `helix_mm` along the normal from start to end.
    ///
    /// # Errors
    /// As [`Toolpath::push_arc`].
    #[expect(
        clippy::too_many_arguments,
        reason = "the arc's four numbers, the move kind, its feed and the chord tolerance"
    )]
    pub fn push_helix(
        &mut self,
        centre: DVec3,
        normal: DVec3,
        sweep_rad: f64,
        helix_mm: f64,
        kind: MoveKind,
        feed_mm_per_min: f64,
        chord_tol_mm: f64,
    ) -> Result<(), ToolpathError> {
        let Some(last) = self.poses.last().copied() else {
            return Err(memory_err(
                "arc",
                "an arc needs a pose to start from".into(),
            ));
        };
        if kind == MoveKind::Rapid {
            return Err(memory_err(
                "arc",
                "an arc is a fed move, not a rapid".into(),
            ));
        }
        if !(feed_mm_per_min > 0.0 && feed_mm_per_min.is_finite()) {
            return Err(memory_err(
                "arc",
                format!("feed {feed_mm_per_min} mm/min must be positive"),
            ));
        }
        let n = normal.normalize_or_zero();
        let centre = centre - n * (centre - last.tip).dot(n);
        let arc = ArcMove {
            centre,
            normal: n,
            sweep_rad,
            helix_mm,
        };
        arc.validate(last.tip).map_err(|m| memory_err("arc", m))?;
        let pieces = arc
            .pieces(last.tip, chord_tol_mm)
            .map_err(|m| memory_err("arc", m))?;
        let from = self.poses.len() - 1;
        for i in 1..=pieces {
            let t = i as f64 / pieces as f64;
            let tip = arc.point_at(last.tip, t);
            self.poses
                .push(Pose::new(kind, tip, last.axis, feed_mm_per_min));
        }
        self.exact.push(ExactSegment {
            from,
            to: self.poses.len() - 1,
            exact: ExactMove::Arc(arc),
        });
        self.resummarise();
        Ok(())
    }

    /// Append a canned cycle: a rapid to its initial plane when the last pose is elsewhere
    /// (or there is none), then its motion as poses (rapids, and plunges at the cycle's feed)
    /// at the cycle's axis.
    ///
    /// # Errors
    /// A bad cycle (see [`CycleMove::validate`]).
    pub fn push_cycle(&mut self, cycle: CycleMove) -> Result<(), ToolpathError> {
        cycle.validate().map_err(|m| memory_err("cycle", m))?;
        let start = cycle.start();
        let axis = cycle.axis;
        let at_start = self.poses.last().is_some_and(|p| {
            p.tip.distance(start) <= ENDPOINT_TOL_MM && p.axis.distance(axis) < 1e-9
        });
        if !at_start {
            self.poses
                .push(Pose::new(MoveKind::Rapid, start, axis, 0.0));
        }
        let from = self.poses.len() - 1;
        for step in cycle.steps() {
            match step {
                CycleStep::Rapid(p) => self.poses.push(Pose::new(MoveKind::Rapid, p, axis, 0.0)),
                CycleStep::Feed(p) => {
                    self.poses
                        .push(Pose::new(MoveKind::Plunge, p, axis, cycle.feed_mm_per_min))
                }
                CycleStep::Dwell(_) | CycleStep::Spindle(_) => {}
            }
        }
        self.exact.push(ExactSegment {
            from,
            to: self.poses.len() - 1,
            exact: ExactMove::Cycle(cycle),
        });
        self.resummarise();
        Ok(())
    }

    /// The moves in order: straight moves to single poses and the exact segments.
    #[must_use]
    pub fn moves(&self) -> Vec<Move<'_>> {
        let mut out = Vec::new();
        let mut segments = self.exact.iter().peekable();
        let mut k = 1;
        while k < self.poses.len() {
            if let Some(seg) = segments.next_if(|s| s.from + 1 == k) {
                out.push(Move::Exact(seg));
                k = seg.to + 1;
                continue;
            }
            let rapid = self.poses.get(k).is_some_and(|p| p.kind == MoveKind::Rapid);
            out.push(if rapid {
                Move::Rapid { to: k }
            } else {
                Move::Line { to: k }
            });
            k += 1;
        }
        out
    }

    /// Recompute the summary from the poses (cycle dwells added to the time), keeping the
    /// planner's gouge report.
    pub fn resummarise(&mut self) {
        let gouge = self.summary.gouge;
        self.summary = Summary::of(&self.poses);
        self.summary.estimated_time_s += self
            .exact
            .iter()
            .map(|s| match s.exact {
                ExactMove::Cycle(c) => c.dwell_s(),
                ExactMove::Arc(_) => 0.0,
            })
            .sum::<f64>();
        self.summary.gouge = gouge;
    }

    /// This path moved by `offset`: tips, contacts, arc centres and cycle positions.
    #[must_use]
    pub fn translated(&self, offset: DVec3) -> Self {
        let mut out = self.clone();
        for p in &mut out.poses {
            p.tip += offset;
            if let Some(cc) = p.cc.as_mut() {
                *cc += offset;
            }
        }
        for s in &mut out.exact {
            match &mut s.exact {
                ExactMove::Arc(a) => a.centre += offset,
                ExactMove::Cycle(c) => *c = c.translated(offset),
            }
        }
        out.resummarise();
        out
    }
}

/// Segments in pose order, inside the poses, not overlapping, each valid, and their exact
/// start and end on the poses they name (within 1e-6 mm); arcs at one tool axis.
pub(super) fn validate_exact(tp: &Toolpath) -> Result<(), (usize, String)> {
    let mut next_free = 0usize;
    for (k, s) in tp.exact.iter().enumerate() {
        let e = |m: String| (k, m);
        if s.to <= s.from || s.from < next_free || s.to >= tp.poses.len() {
            return Err(e(format!(
                "poses {}..={} are out of order, overlap another move or lie past the {} poses",
                s.from,
                s.to,
                tp.poses.len()
            )));
        }
        next_free = s.to;
        let (Some(first), Some(last)) = (tp.poses.get(s.from), tp.poses.get(s.to)) else {
            continue;
        };
        let (start, end) = match s.exact {
            ExactMove::Arc(a) => {
                a.validate(first.tip).map_err(e)?;
                let steady = tp
                    .poses
                    .get(s.from..=s.to)
                    .is_some_and(|ps| ps.iter().all(|p| p.axis.distance(first.axis) < 1e-9));
                if !steady {
                    return Err(e("an arc's poses must share one tool axis".into()));
                }
                (first.tip, a.end(first.tip))
            }
            ExactMove::Cycle(c) => {
                c.validate().map_err(e)?;
                let end = c.at(c.clear_mm());
                (c.start(), end)
            }
        };
        let scale = 1.0 + start.abs().max_element().max(end.abs().max_element());
        if first.tip.distance(start) > ENDPOINT_TOL_MM * scale
            || last.tip.distance(end) > ENDPOINT_TOL_MM * scale
        {
            return Err(e(format!(
                "its start {:?} and end {:?} are not on poses {} and {}",
                start.to_array(),
                end.to_array(),
                s.from,
                s.to
            )));
        }
    }
    Ok(())
}
