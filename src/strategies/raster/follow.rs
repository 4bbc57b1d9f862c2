//! Following the true cutter-location curve along a straight XY line with a polyline.
//!
//! Drop-cutter gives exact CL points; between two of them the tool moves on a straight chord.
//! Each chord is checked at its quarter, half and three-quarter points; while the true CL
//! deviates from the chord by more than half the chord tolerance the chord is bisected
//! (reusing the points already dropped). Where the true CL lies above an accepted chord (convex
//! regions) the chord would gouge, so both its ends are lifted by the largest such excess: the
//! polyline then lies on or above the true CL at every checked point and at most half the
//! tolerance above it. Finally points are dropped where the polyline without them stays within
//! half the tolerance above them (never below them by more than 1e-7 mm), so straight runs keep
//! only their ends. Thinning may merge chords whose true CL bulges between the points refined
//! before, so every final chord is checked again about every quarter millimetre and both its ends
//! lifted by any excess found.

use glam::{DVec2, DVec3};

use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::tools::Cutter;
use crate::tools::dropcutter::{ClPoint, drop_cutter_at};

/// One point of a followed CL polyline.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ClSample {
    /// Parameter along the line, mm.
    pub t: f64,
    /// Tool tip (lifted where needed), mm.
    pub tip: DVec3,
    /// The exact drop-cutter result at this XY.
    pub cl: ClPoint,
}

/// What the follower needs: the mesh, its hierarchy, the cutter and the chord tolerance.
pub(crate) struct Follower<'a> {
    pub bvh: &'a MeshBvh,
    pub mesh: &'a TriMesh,
    pub cutter: &'a Cutter,
    pub chord_tol: f64,
}

/// Shortest chord the refinement produces, mm.
const MIN_CHORD: f64 = 1.0e-3;
/// Spacing of the true-CL checks along a final chord, mm.
const VERIFY_STEP: f64 = 0.25;
/// How far a dropped point may lie above the chord that replaces it, mm.
const ABOVE_EPS: f64 = 1.0e-7;

#[derive(Clone, Copy)]
struct Node {
    t: f64,
    cl: Option<ClPoint>,
}

impl Follower<'_> {
    fn drop_at(&self, origin: DVec2, dir: DVec2, t: f64) -> Node {
        Node {
            t,
            cl: drop_cutter_at(self.bvh, self.mesh, self.cutter, origin + dir * t),
        }
    }

    /// Follow the CL along `origin + t·dir` through the given samples (ascending t, all with a
    /// CL point). Returns the thinned, lifted polyline.
    pub(crate) fn follow(
        &self,
        origin: DVec2,
        dir: DVec2,
        samples: &[(f64, ClPoint)],
    ) -> Vec<ClSample> {
        let mut pts: Vec<(f64, ClPoint)> = Vec::new();
        let mut gouge: Vec<f64> = Vec::new();
        for w in samples.windows(2) {
            let [(ta, a), (tb, b)] = w else { continue };
            if pts.is_empty() {
                pts.push((*ta, *a));
            }
            self.refine(
                origin,
                dir,
                (*ta, *a),
                (*tb, *b),
                None,
                0,
                &mut pts,
                &mut gouge,
            );
        }
        if pts.is_empty()
            && let Some(&(t, cl)) = samples.first()
        {
            pts.push((t, cl));
        }
        let lifted: Vec<ClSample> = pts
            .iter()
            .enumerate()
            .map(|(i, &(t, cl))| {
                let before = if i > 0 { gouge.get(i - 1) } else { None };
                let lift = before
                    .copied()
                    .unwrap_or(0.0)
                    .max(gouge.get(i).copied().unwrap_or(0.0));
                let xy = origin + dir * t;
                ClSample {
                    t,
                    tip: xy.extend(cl.z + lift),
                    cl,
                }
            })
            .collect();
        let mut out = self.thin(lifted);
        self.verify(origin, dir, &mut out);
        out
    }

    /// Check every final chord against the true CL at points about every quarter millimetre
    /// (thinning may merge chords whose true CL bulges between the points refined before) and
    /// lift both ends of a chord by the largest excess found, so that no chord dips under it.
    fn verify(&self, origin: DVec2, dir: DVec2, pts: &mut [ClSample]) {
        let lifts: Vec<f64> = pts
            .windows(2)
            .map(|w| {
                let [a, b] = w else { return 0.0 };
                let span = b.t - a.t;
                let n = (span / VERIFY_STEP).ceil().clamp(1.0, 32.0) as usize;
                (1..n)
                    .filter_map(|i| {
                        let t = a.t + span * i as f64 / n as f64;
                        let cl = self.drop_at(origin, dir, t).cl?;
                        let chord = a.tip.z + (b.tip.z - a.tip.z) * (t - a.t) / span;
                        Some(cl.z - chord)
                    })
                    .fold(0.0_f64, f64::max)
            })
            .collect();
        for (k, p) in pts.iter_mut().enumerate() {
            let before = k.checked_sub(1).and_then(|i| lifts.get(i)).copied();
            let lift = before
                .unwrap_or(0.0)
                .max(lifts.get(k).copied().unwrap_or(0.0));
            p.tip.z += lift;
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn refine(
        &self,
        origin: DVec2,
        dir: DVec2,
        a: (f64, ClPoint),
        b: (f64, ClPoint),
        mid: Option<Node>,
        depth: u32,
        pts: &mut Vec<(f64, ClPoint)>,
        gouge: &mut Vec<f64>,
    ) {
        let (ta, tb) = (a.0, b.0);
        let at = |f: f64| ta + (tb - ta) * f;
        let m = mid.unwrap_or_else(|| self.drop_at(origin, dir, at(0.5)));
        let q1 = self.drop_at(origin, dir, at(0.25));
        let q3 = self.drop_at(origin, dir, at(0.75));
        let chord = |n: &Node| {
            let f = (n.t - ta) / (tb - ta);
            n.cl.map(|c| c.z - (a.1.z + (b.1.z - a.1.z) * f))
        };
        let devs = [chord(&q1), chord(&m), chord(&q3)];
        let worst = devs
            .iter()
            .flatten()
            .fold(0.0_f64, |acc, d| acc.max(d.abs()));
        let can_split = depth < 30 && tb - ta > 2.0 * MIN_CHORD;
        if worst > 0.5 * self.chord_tol
            && can_split
            && let Some(mcl) = m.cl
        {
            self.refine(origin, dir, a, (m.t, mcl), Some(q1), depth + 1, pts, gouge);
            self.refine(origin, dir, (m.t, mcl), b, Some(q3), depth + 1, pts, gouge);
            return;
        }
        let above = devs.iter().flatten().fold(0.0_f64, |acc, d| acc.max(*d));
        gouge.push(above);
        pts.push(b);
    }

    /// Drop points that the chord of their neighbours passes over by at most half the tolerance.
    fn thin(&self, pts: Vec<ClSample>) -> Vec<ClSample> {
        if pts.len() < 3 {
            return pts;
        }
        let mut out = Vec::with_capacity(pts.len());
        let mut anchor = 0;
        out.extend(pts.first().copied());
        while anchor + 1 < pts.len() {
            let mut end = anchor + 1;
            while end + 1 < pts.len() && self.fits(&pts, anchor, end + 1) {
                end += 1;
            }
            out.extend(pts.get(end).copied());
            anchor = end;
        }
        out
    }

    fn fits(&self, pts: &[ClSample], from: usize, to: usize) -> bool {
        let (Some(a), Some(b)) = (pts.get(from), pts.get(to)) else {
            return false;
        };
        let span = b.t - a.t;
        if !(span > 0.0) {
            return false;
        }
        pts.get(from + 1..to).is_some_and(|inner| {
            inner.iter().all(|p| {
                let chord = a.tip.z + (b.tip.z - a.tip.z) * (p.t - a.t) / span;
                let over = chord - p.tip.z;
                over >= -ABOVE_EPS && over <= 0.5 * self.chord_tol
            })
        })
    }
}
