//! Edge chains: checking that a loop's oriented edges join end to start, and repairing loops that
//! writers list out of order or with an edge the wrong way round (as Open CASCADE's wire fixing
//! does), so that every [`Loop::Edges`](crate::geometry::brep::Loop::Edges) runs as a chain.

use crate::geometry::brep::{OrientedEdge, Part};

/// Vertices closer than this (mm) join even when the file gave them different ids.
const JOIN_TOLERANCE_MM: f64 = 1e-4;

/// Start and end vertex of an oriented edge, as the loop runs.
fn ends(part: &Part, oe: OrientedEdge) -> Option<(usize, usize)> {
    let e = part.edges.get(oe.edge)?;
    Some(if oe.forward {
        (e.start, e.end)
    } else {
        (e.end, e.start)
    })
}

/// Do vertices `a` and `b` coincide?
fn joins(part: &Part, a: usize, b: usize) -> bool {
    a == b
        || match (part.vertices.get(a), part.vertices.get(b)) {
            (Some(p), Some(q)) => p.point.distance(q.point) <= JOIN_TOLERANCE_MM,
            _ => false,
        }
}

/// Does the loop run as a closed chain?
pub(super) fn is_chain(part: &Part, edges: &[OrientedEdge]) -> bool {
    let Some(ends) = edges
        .iter()
        .map(|oe| ends(part, *oe))
        .collect::<Option<Vec<_>>>()
    else {
        return false;
    };
    ends.iter()
        .zip(ends.iter().cycle().skip(1))
        .all(|(a, b)| joins(part, a.1, b.0))
}

/// Reorder and reorient `edges` into a closed chain, keeping the direction most edges had. `None`
/// when no closed chain uses every edge once.
pub(super) fn repair(part: &Part, edges: &[OrientedEdge]) -> Option<Vec<OrientedEdge>> {
    let first = *edges.first()?;
    let mut used = vec![false; edges.len()];
    *used.first_mut()? = true;
    let mut chain = vec![first];
    let (start, mut at) = ends(part, first)?;
    let mut flipped = 0usize;
    while chain.len() < edges.len() {
        let mut next = None;
        for (i, oe) in edges.iter().enumerate() {
            if used.get(i).copied().unwrap_or(true) {
                continue;
            }
            let (s, e) = ends(part, *oe)?;
            if joins(part, s, at) {
                next = Some((i, *oe, e));
                break;
            }
            if next.is_none() && joins(part, e, at) {
                next = Some((
                    i,
                    OrientedEdge {
                        edge: oe.edge,
                        forward: !oe.forward,
                    },
                    s,
                ));
            }
        }
        let (i, oe, end) = next?;
        if let Some(u) = used.get_mut(i) {
            *u = true;
        }
        if edges.get(i).is_some_and(|orig| orig.forward != oe.forward) {
            flipped += 1;
        }
        chain.push(oe);
        at = end;
    }
    if !joins(part, at, start) {
        return None;
    }
    if 2 * flipped > edges.len() {
        chain.reverse();
        for oe in &mut chain {
            oe.forward = !oe.forward;
        }
    }
    Some(chain)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::DVec3;
    use crate::geometry::brep::{Edge, Vertex};
    use crate::geometry::curve::{CurveGeom, Line};

    /// A unit square's corners 0..4 and its four edges i → i+1.
    fn square() -> Part {
        let pts = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let mut part = Part {
            vertices: pts
                .iter()
                .map(|&point| Vertex {
                    point,
                    source_id: 0,
                })
                .collect(),
            ..Part::default()
        };
        for i in 0..4 {
            let (a, b) = (pts[i], pts[(i + 1) % 4]);
            part.edges.push(Edge {
                start: i,
                end: (i + 1) % 4,
                curve: CurveGeom::Line(Line {
                    origin: a,
                    dir: (b - a).normalize(),
                }),
                t_start: 0.0,
                t_end: 1.0,
                source_id: 0,
            });
        }
        part
    }

    fn oe(edge: usize, forward: bool) -> OrientedEdge {
        OrientedEdge { edge, forward }
    }

    #[test]
    fn chains_are_recognised_and_repaired() {
        let part = square();
        let good = [oe(0, true), oe(1, true), oe(2, true), oe(3, true)];
        assert!(is_chain(&part, &good));
        // Out of order, and edge 0 the wrong way round.
        let bad = [oe(0, false), oe(2, true), oe(1, true), oe(3, true)];
        assert!(!is_chain(&part, &bad));
        let fixed = repair(&part, &bad).unwrap();
        assert!(is_chain(&part, &fixed));
        // The majority direction (counter-clockwise) is kept: only edge 0 was turned.
        assert!(fixed.iter().all(|e| e.forward));
        // Three edges cannot close.
        assert!(repair(&part, &good[..3]).is_none());
    }
}
