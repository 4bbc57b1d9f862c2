//! The order of the holes: an open tour from a start point, nearest neighbour first, then
//! improved by 2-opt (reverse a stretch) and Or-opt (move a run of one to three holes elsewhere,
//! either way round) until neither shortens it.

use glam::DVec3;

/// Length of the open tour through `points` in `order`, mm.
#[must_use]
pub fn tour_length_mm(points: &[DVec3], order: &[usize]) -> f64 {
    order
        .windows(2)
        .map(|w| points[w[0]].distance(points[w[1]]))
        .sum()
}

/// An open tour through all `points`, starting at the one nearest `start` (or at the first).
#[must_use]
pub fn order_holes(points: &[DVec3], start: Option<DVec3>) -> Vec<usize> {
    let n = points.len();
    if n < 2 {
        return (0..n).collect();
    }
    let d = |a: usize, b: usize| points[a].distance(points[b]);
    let first = start.map_or(0, |s| {
        (0..n)
            .min_by(|&a, &b| points[a].distance(s).total_cmp(&points[b].distance(s)))
            .unwrap_or(0)
    });
    let mut used = vec![false; n];
    let mut tour = vec![first];
    used[first] = true;
    for _ in 1..n {
        let last = tour[tour.len() - 1];
        let next = (0..n)
            .filter(|&j| !used[j])
            .min_by(|&a, &b| d(last, a).total_cmp(&d(last, b)));
        let Some(next) = next else { break };
        used[next] = true;
        tour.push(next);
    }
    improve(&mut tour, &d);
    tour
}

/// 2-opt and Or-opt on an open tour whose first point stays first.
fn improve(tour: &mut Vec<usize>, d: &impl Fn(usize, usize) -> f64) {
    let n = tour.len();
    let eps = 1e-12;
    for _round in 0..1000 {
        let mut better = false;
        // 2-opt: reverse tour[i+1..=j]; edges (i, i+1) and (j, j+1) (j + 1 may be the end).
        for i in 0..n - 1 {
            for j in i + 1..n {
                let (a, b) = (tour[i], tour[i + 1]);
                let c = tour[j];
                let old = d(a, b) + if j + 1 < n { d(c, tour[j + 1]) } else { 0.0 };
                let new = d(a, c) + if j + 1 < n { d(b, tour[j + 1]) } else { 0.0 };
                if new < old - eps {
                    tour[i + 1..=j].reverse();
                    better = true;
                }
            }
        }
        // Or-opt: move tour[i..i+len] between tour[k] and tour[k+1] (or to the end).
        for len in 1..=3usize {
            let mut i = 1;
            while i + len <= n {
                let seg: Vec<usize> = tour[i..i + len].to_vec();
                let prev = tour[i - 1];
                let next = tour.get(i + len).copied();
                let removed = d(prev, seg[0]) + next.map_or(0.0, |x| d(seg[len - 1], x))
                    - next.map_or(0.0, |x| d(prev, x));
                let rest: Vec<usize> = tour[..i].iter().chain(&tour[i + len..]).copied().collect();
                let mut best: Option<(f64, usize, bool)> = None;
                for k in 0..rest.len() {
                    let (p, q) = (rest[k], rest.get(k + 1).copied());
                    for rev in [false, true] {
                        let (s0, s1) = if rev {
                            (seg[len - 1], seg[0])
                        } else {
                            (seg[0], seg[len - 1])
                        };
                        let add =
                            d(p, s0) + q.map_or(0.0, |x| d(s1, x)) - q.map_or(0.0, |x| d(p, x));
                        if add < removed - eps && best.is_none_or(|b| add < b.0) {
                            best = Some((add, k, rev));
                        }
                    }
                }
                if let Some((_, k, rev)) = best {
                    let mut s = seg;
                    if rev {
                        s.reverse();
                    }
                    let mut t = rest[..=k].to_vec();
                    t.extend(s);
                    t.extend(&rest[k + 1..]);
                    *tour = t;
                    better = true;
                }
                i += 1;
            }
        }
        if !better {
            break;
        }
    }
}
