//! Offset contours on a grid: the Euclidean distance transform of a free/blocked mask
//! (Felzenszwalb–Huttenlocher, exact on the grid's nodes) and marching squares for its level
//! sets, stitched into closed loops and thinned by Douglas–Peucker.

use glam::DVec2;
use std::collections::HashMap;

/// A scalar field on a regular grid (row-major, row ↔ y).
pub(crate) struct Field {
    pub origin: DVec2,
    pub step: f64,
    pub nx: usize,
    pub ny: usize,
    pub values: Vec<f64>,
}

const BIG: f64 = 1.0e20;

/// 1-D squared distance transform of `f` (in grid units²), Felzenszwalb–Huttenlocher.
#[allow(clippy::indexing_slicing)] // v, z have n + 1 slots and k ≤ q < n
fn dt1(f: &[f64]) -> Vec<f64> {
    let n = f.len();
    let mut d = vec![0.0; n];
    if n == 0 {
        return d;
    }
    let mut v = vec![0usize; n];
    let mut z = vec![0.0; n + 1];
    let mut k = 0usize;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    let meet = |q: usize, p: usize| {
        ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q as f64 - p as f64))
    };
    for q in 1..n {
        let mut s = meet(q, v[k]);
        while s <= z[k] {
            k -= 1;
            s = meet(q, v[k]);
        }
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (q, out) in d.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let dq = q as f64 - v[k] as f64;
        *out = dq * dq + f[v[k]];
    }
    d
}

impl Field {
    /// Distance (mm) from every node to the nearest blocked node (`free == false`).
    #[allow(clippy::indexing_slicing)]
    pub(crate) fn distance(origin: DVec2, step: f64, nx: usize, ny: usize, free: &[bool]) -> Self {
        let mut g: Vec<f64> = free.iter().map(|&f| if f { BIG } else { 0.0 }).collect();
        g.resize(nx * ny, 0.0);
        for j in 0..ny {
            let row = dt1(&g[j * nx..(j + 1) * nx]);
            g[j * nx..(j + 1) * nx].copy_from_slice(&row);
        }
        let mut col = vec![0.0; ny];
        for i in 0..nx {
            for j in 0..ny {
                col[j] = g[j * nx + i];
            }
            let d = dt1(&col);
            for j in 0..ny {
                g[j * nx + i] = d[j];
            }
        }
        let values = g.into_iter().map(|v| v.min(BIG).sqrt() * step).collect();
        Self {
            origin,
            step,
            nx,
            ny,
            values,
        }
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.values.get(j * self.nx + i).copied().unwrap_or(0.0)
    }

    fn node(&self, i: usize, j: usize) -> DVec2 {
        self.origin + DVec2::new(i as f64, j as f64) * self.step
    }

    /// The largest value.
    pub(crate) fn max(&self) -> f64 {
        self.values.iter().copied().fold(0.0, f64::max)
    }

    /// The closed loops where the field equals `c` (the border must lie below `c`).
    pub(crate) fn contours(&self, c: f64) -> Vec<Vec<DVec2>> {
        let (nx, ny) = (self.nx, self.ny);
        if nx < 2 || ny < 2 {
            return Vec::new();
        }
        // Edge ids: horizontal edge from (i, j) = 2·(j·nx + i), vertical = 2·(j·nx + i) + 1.
        let h = |i: usize, j: usize| 2 * (j * nx + i);
        let v = |i: usize, j: usize| 2 * (j * nx + i) + 1;
        let point = |e: usize| {
            let k = e / 2;
            let (i, j) = (k % nx, k / nx);
            let (a, b, pa, pb) = if e.is_multiple_of(2) {
                (
                    self.at(i, j),
                    self.at(i + 1, j),
                    self.node(i, j),
                    self.node(i + 1, j),
                )
            } else {
                (
                    self.at(i, j),
                    self.at(i, j + 1),
                    self.node(i, j),
                    self.node(i, j + 1),
                )
            };
            let f = if (b - a).abs() > 0.0 {
                ((c - a) / (b - a)).clamp(0.0, 1.0)
            } else {
                0.5
            };
            pa + (pb - pa) * f
        };
        let mut segs: Vec<(usize, usize)> = Vec::new();
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let s0 = self.at(i, j) >= c;
                let s1 = self.at(i + 1, j) >= c;
                let s2 = self.at(i + 1, j + 1) >= c;
                let s3 = self.at(i, j + 1) >= c;
                let (eb, er, et, el) = (h(i, j), v(i + 1, j), h(i, j + 1), v(i, j));
                let case = usize::from(s0)
                    | usize::from(s1) << 1
                    | usize::from(s2) << 2
                    | usize::from(s3) << 3;
                let centre = 0.25
                    * (self.at(i, j)
                        + self.at(i + 1, j)
                        + self.at(i + 1, j + 1)
                        + self.at(i, j + 1))
                    >= c;
                match case {
                    1 | 14 => segs.push((el, eb)),
                    2 | 13 => segs.push((eb, er)),
                    3 | 12 => segs.push((el, er)),
                    4 | 11 => segs.push((er, et)),
                    6 | 9 => segs.push((eb, et)),
                    7 | 8 => segs.push((el, et)),
                    5 => {
                        if centre {
                            segs.push((el, et));
                            segs.push((eb, er));
                        } else {
                            segs.push((el, eb));
                            segs.push((er, et));
                        }
                    }
                    10 => {
                        if centre {
                            segs.push((el, eb));
                            segs.push((er, et));
                        } else {
                            segs.push((eb, er));
                            segs.push((el, et));
                        }
                    }
                    _ => {}
                }
            }
        }
        // Stitch: every edge id is shared by exactly two segments on a closed level set.
        let mut at_edge: HashMap<usize, Vec<usize>> = HashMap::new();
        for (k, (a, b)) in segs.iter().enumerate() {
            at_edge.entry(*a).or_default().push(k);
            at_edge.entry(*b).or_default().push(k);
        }
        let mut used = vec![false; segs.len()];
        let mut loops = Vec::new();
        for start in 0..segs.len() {
            if used.get(start).copied().unwrap_or(true) {
                continue;
            }
            let Some(&(e0, mut e)) = segs.get(start) else {
                continue;
            };
            if let Some(u) = used.get_mut(start) {
                *u = true;
            }
            let mut pts = vec![point(e0), point(e)];
            while e != e0 {
                let next = at_edge.get(&e).and_then(|ks| {
                    ks.iter()
                        .copied()
                        .find(|k| !used.get(*k).copied().unwrap_or(true))
                });
                let Some(k) = next else { break };
                if let Some(u) = used.get_mut(k) {
                    *u = true;
                }
                let Some(&(a, b)) = segs.get(k) else { break };
                e = if a == e { b } else { a };
                pts.push(point(e));
            }
            if pts.len() >= 4 {
                loops.push(pts);
            }
        }
        loops
    }
}

/// Douglas–Peucker thinning of a closed loop (first point repeated at the end) to `tol`.
pub(crate) fn thin_loop(pts: &[DVec2], tol: f64) -> Vec<DVec2> {
    if pts.len() < 4 {
        return pts.to_vec();
    }
    let mut keep = vec![false; pts.len()];
    if let Some(k) = keep.first_mut() {
        *k = true;
    }
    if let Some(k) = keep.last_mut() {
        *k = true;
    }
    // Split at the point farthest from the start so the closed loop has two open halves.
    let first = pts.first().copied().unwrap_or_default();
    let far = pts
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.distance(first).total_cmp(&b.1.distance(first)))
        .map_or(0, |(i, _)| i);
    if let Some(k) = keep.get_mut(far) {
        *k = true;
    }
    let mut stack = vec![(0, far), (far, pts.len() - 1)];
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (pa, pb) = (
            pts.get(a).copied().unwrap_or_default(),
            pts.get(b).copied().unwrap_or_default(),
        );
        let mut worst = (0.0, a);
        for (k, p) in pts.iter().enumerate().take(b).skip(a + 1) {
            let d = seg_dist(*p, pa, pb);
            if d > worst.0 {
                worst = (d, k);
            }
        }
        if worst.0 > tol {
            if let Some(k) = keep.get_mut(worst.1) {
                *k = true;
            }
            stack.push((a, worst.1));
            stack.push((worst.1, b));
        }
    }
    pts.iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(p, _)| *p)
        .collect()
}

fn seg_dist(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let e = b - a;
    let l2 = e.length_squared();
    let s = if l2 > 0.0 {
        ((p - a).dot(e) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + e * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The distance transform of a single blocked node is the Euclidean distance (brute force).
    #[test]
    fn distance_is_euclidean() {
        let (nx, ny) = (13, 9);
        let mut free = vec![true; nx * ny];
        free[4 * nx + 3] = false;
        free[nx + 10] = false;
        let f = Field::distance(DVec2::ZERO, 0.5, nx, ny, &free);
        for j in 0..ny {
            for i in 0..nx {
                let p = DVec2::new(i as f64, j as f64);
                let want = p
                    .distance(DVec2::new(3.0, 4.0))
                    .min(p.distance(DVec2::new(10.0, 1.0)))
                    * 0.5;
                assert!((f.at(i, j) - want).abs() < 1e-12, "{i},{j}");
            }
        }
    }

    /// The level set of the distance to a blocked border is a closed loop of the right size.
    #[test]
    fn contour_of_a_square() {
        let n = 21;
        let free: Vec<bool> = (0..n * n)
            .map(|k| {
                let (i, j) = (k % n, k / n);
                i > 0 && j > 0 && i < n - 1 && j < n - 1
            })
            .collect();
        let f = Field::distance(DVec2::ZERO, 1.0, n, n, &free);
        let loops = f.contours(3.5);
        assert_eq!(loops.len(), 1);
        for p in &loops[0] {
            let d = p.x.min(p.y).min(20.0 - p.x).min(20.0 - p.y);
            assert!((d - 3.5).abs() < 0.6, "{p}");
        }
    }
}
