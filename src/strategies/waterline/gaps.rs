//! Extra waterline levels where a steep band ends between two levels (steep-and-shallow).
//!
//! With only the steep contacts cut, a band whose slope falls below the cutting limit between
//! two levels (a fillet running into a floor) is cut at the upper level and not at the lower
//! one, so the stretch between the upper level's contacts and the band's flatter end is left
//! between one pass and none. Such a gap shows as cut contacts of the upper level with no cut
//! contact of the lower level within the horizontal distance a surface at the limit slope
//! covers over the step (Δz / tan(limit), plus two fibre spacings). A level halfway is then
//! added when it has cut contacts near the gap, and the two halves are checked again (three
//! halvings at most), so the lowest cut level of the band lies within an eighth of a step of
//! the band's end.

use glam::DVec2;

use super::Level;

/// Halvings of one step at most.
const DEPTH: usize = 3;

/// `levels` (top down) with the levels added where a steep band ends between two of them.
pub(super) fn fill(
    level: &dyn Fn(f64) -> Level,
    levels: Vec<Level>,
    limit: f64,
    sampling: f64,
) -> Vec<Level> {
    let mut out = Vec::with_capacity(levels.len());
    let mut it = levels.into_iter();
    let Some(mut upper) = it.next() else {
        return out;
    };
    for lower in it {
        let mids = between(level, &upper, &lower, limit, sampling, DEPTH);
        out.push(upper);
        out.extend(mids);
        upper = lower;
    }
    out.push(upper);
    out
}

/// The levels to add between `u` and `l` (top down).
fn between(
    level: &dyn Fn(f64) -> Level,
    u: &Level,
    l: &Level,
    limit: f64,
    sampling: f64,
    depth: usize,
) -> Vec<Level> {
    if depth == 0 {
        return Vec::new();
    }
    let gap = gap_points(u, l, limit, sampling);
    if gap.is_empty() {
        return Vec::new();
    }
    let m = level(0.5 * (u.z + l.z));
    let reach = reach(u.z - m.z, limit, sampling);
    let near = CutIndex::new(&m, limit, reach);
    if !gap.iter().any(|p| near.has_within(*p)) {
        return Vec::new();
    }
    let mut out = between(level, u, &m, limit, sampling, depth - 1);
    let below = between(level, &m, l, limit, sampling, depth - 1);
    out.push(m);
    out.extend(below);
    out
}

/// Horizontal distance between cut contacts of two levels `dz` apart on a surface at least
/// `limit` steep, with two fibre spacings for the contours' sampling.
fn reach(dz: f64, limit: f64, sampling: f64) -> f64 {
    dz / limit.tan().max(1e-3) + 2.0 * sampling
}

/// The cut contacts (tool tips, XY) of `u` with no cut contact of `l` near them.
fn gap_points(u: &Level, l: &Level, limit: f64, sampling: f64) -> Vec<DVec2> {
    let index = CutIndex::new(l, limit, reach(u.z - l.z, limit, sampling));
    cut_tips(u, limit)
        .filter(|p| !index.has_within(*p))
        .collect()
}

fn cut_tips(l: &Level, limit: f64) -> impl Iterator<Item = DVec2> + '_ {
    l.loops
        .iter()
        .flatten()
        .filter(move |p| p.slope >= limit)
        .map(|p| p.tip.truncate())
}

/// The cut tips of one level hashed on a square grid of the query radius.
struct CutIndex {
    cell: f64,
    radius: f64,
    cells: std::collections::HashMap<(i64, i64), Vec<DVec2>>,
}

impl CutIndex {
    fn new(l: &Level, limit: f64, radius: f64) -> Self {
        let cell = radius.max(1e-6);
        let mut cells: std::collections::HashMap<(i64, i64), Vec<DVec2>> =
            std::collections::HashMap::new();
        for p in cut_tips(l, limit) {
            cells.entry(key(p, cell)).or_default().push(p);
        }
        Self {
            cell,
            radius,
            cells,
        }
    }

    fn has_within(&self, p: DVec2) -> bool {
        let (i, j) = key(p, self.cell);
        (i - 1..=i + 1).any(|a| {
            (j - 1..=j + 1).any(|b| {
                self.cells
                    .get(&(a, b))
                    .is_some_and(|v| v.iter().any(|q| q.distance(p) <= self.radius))
            })
        })
    }
}

fn key(p: DVec2, cell: f64) -> (i64, i64) {
    ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64)
}
