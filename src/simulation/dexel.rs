//! Dexels: one ray's material as a sorted list of disjoint intervals, and a family of parallel
//! rays on a square grid.
//!
//! Interval ends are `f32` offsets along the ray from the family's origin plane. Stocks up to
//! a metre long keep them to 6·10⁻⁵ mm, far below any useful resolution, and the common case
//! (one interval per ray) costs 16 bytes a ray.

use glam::DVec3;

/// The material of one ray: disjoint intervals `[lo, hi]` (lo < hi), sorted, as offsets along
/// the ray (mm).
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Dexel {
    /// No material.
    #[default]
    Empty,
    /// One interval (the common case, stored inline).
    One([f32; 2]),
    /// Two or more intervals.
    Many(Box<Vec<[f32; 2]>>),
}

impl Dexel {
    /// A dexel from sorted, disjoint intervals (empty ones are dropped).
    #[must_use]
    pub fn from_intervals(list: &[[f32; 2]]) -> Self {
        let kept: Vec<[f32; 2]> = list.iter().copied().filter(|[a, b]| a < b).collect();
        match kept.as_slice() {
            [] => Self::Empty,
            [one] => Self::One(*one),
            _ => Self::Many(Box::new(kept)),
        }
    }

    /// The intervals, in order.
    #[must_use]
    pub fn intervals(&self) -> &[[f32; 2]] {
        match self {
            Self::Empty => &[],
            Self::One(i) => std::slice::from_ref(i),
            Self::Many(v) => v.as_slice(),
        }
    }

    /// Total material length along the ray, mm (summed in `f64`, in order).
    #[must_use]
    pub fn length(&self) -> f64 {
        self.intervals()
            .iter()
            .map(|[a, b]| f64::from(*b) - f64::from(*a))
            .sum()
    }

    /// Length of material inside `[lo, hi]`, mm.
    #[must_use]
    pub fn overlap(&self, lo: f32, hi: f32) -> f64 {
        self.intervals()
            .iter()
            .map(|[a, b]| (f64::from(b.min(hi)) - f64::from(a.max(lo))).max(0.0))
            .sum()
    }

    /// The first stretch of material inside `[lo, hi]` (clipped), if any.
    #[must_use]
    pub fn first_overlap(&self, lo: f32, hi: f32) -> Option<[f32; 2]> {
        self.intervals().iter().find_map(|[a, b]| {
            let (x, y) = (a.max(lo), b.min(hi));
            (x < y).then_some([x, y])
        })
    }

    /// Remove `[lo, hi]` from the material. Returns whether anything changed.
    pub fn subtract(&mut self, lo: f32, hi: f32) -> bool {
        if !(lo < hi) {
            return false;
        }
        match self {
            Self::Empty => false,
            Self::One([a, b]) => {
                let (a, b) = (*a, *b);
                if hi <= a || lo >= b {
                    return false;
                }
                *self = match (lo > a, hi < b) {
                    (false, false) => Self::Empty,
                    (true, false) => Self::One([a, lo]),
                    (false, true) => Self::One([hi, b]),
                    (true, true) => Self::Many(Box::new(vec![[a, lo], [hi, b]])),
                };
                true
            }
            Self::Many(v) => {
                // The intervals are sorted and disjoint: those that `[lo, hi]` meets are a
                // run `f..=l`. Of them only the first's part below `lo` and the last's part
                // above `hi` remain; the run is replaced in place (no allocation unless one
                // interval splits in two beyond the vector's capacity).
                let Some(f) = v.iter().position(|[a, b]| lo < *b && hi > *a) else {
                    return false;
                };
                let run = v
                    .get(f + 1..)
                    .map_or(0, |rest| rest.iter().take_while(|[a, _]| hi > *a).count());
                let l = f + run;
                let (Some(&[a, _]), Some(&[_, b])) = (v.get(f), v.get(l)) else {
                    return false;
                };
                let below = (lo > a).then_some([a, lo]);
                let above = (hi < b).then_some([hi, b]);
                let pieces = [below, above];
                let mut kept = pieces.iter().flatten().copied();
                let (first, second) = (kept.next(), kept.next());
                match (first, second) {
                    (Some(x), Some(y)) => {
                        if let Some(slot) = v.get_mut(f) {
                            *slot = x;
                        }
                        if l > f {
                            if let Some(slot) = v.get_mut(f + 1) {
                                *slot = y;
                            }
                            v.drain(f + 2..=l);
                        } else {
                            v.insert(f + 1, y);
                        }
                    }
                    (Some(x), None) => {
                        if let Some(slot) = v.get_mut(f) {
                            *slot = x;
                        }
                        v.drain(f + 1..=l);
                    }
                    _ => {
                        v.drain(f..=l);
                    }
                }
                match v.as_slice() {
                    [] => *self = Self::Empty,
                    [one] => *self = Self::One(*one),
                    _ => {}
                }
                true
            }
        }
    }

    /// Add `[lo, hi]` to the material (union).
    pub fn add(&mut self, lo: f32, hi: f32) {
        if !(lo < hi) {
            return;
        }
        let mut all: Vec<[f32; 2]> = self.intervals().to_vec();
        all.push([lo, hi]);
        all.sort_by(|x, y| x[0].total_cmp(&y[0]));
        let mut merged: Vec<[f32; 2]> = Vec::with_capacity(all.len());
        for [a, b] in all {
            match merged.last_mut() {
                Some(last) if a <= last[1] => last[1] = last[1].max(b),
                _ => merged.push([a, b]),
            }
        }
        *self = Self::from_intervals(&merged);
    }

    /// Heap bytes owned by this dexel beyond its inline size.
    #[must_use]
    pub fn heap_bytes(&self) -> usize {
        match self {
            Self::Many(v) => std::mem::size_of::<Vec<[f32; 2]>>() + v.capacity() * 8,
            Self::Empty | Self::One(_) => 0,
        }
    }
}

/// Ray direction of a dexel family.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
pub enum RayAxis {
    /// Rays along +X on a (Y, Z) grid.
    X,
    /// Rays along +Y on a (Z, X) grid.
    Y,
    /// Rays along +Z on an (X, Y) grid.
    Z,
}

impl RayAxis {
    /// Indices (u, v, w) into XYZ: grid axes u (fast), v (slow) and the ray axis w.
    #[must_use]
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Self::X => (1, 2, 0),
            Self::Y => (2, 0, 1),
            Self::Z => (0, 1, 2),
        }
    }

    /// Unit ray direction.
    #[must_use]
    pub fn direction(self) -> DVec3 {
        match self {
            Self::X => DVec3::X,
            Self::Y => DVec3::Y,
            Self::Z => DVec3::Z,
        }
    }
}

/// Rays a side of the square tiles a family's volume is summed by (and the removal's culling
/// tiles).
pub const VOLUME_TILE: usize = 16;

/// Parallel rays through the centres of a square grid of cells.
#[derive(Clone, Debug, PartialEq)]
pub struct DexelFamily {
    /// Ray direction.
    pub axis: RayAxis,
    /// Grid corner: the smallest (u, v) cell corner, and the offset origin along the ray, mm.
    pub origin: DVec3,
    /// Cell size, mm.
    pub spacing: f64,
    /// Cells along u.
    pub nu: usize,
    /// Cells along v.
    pub nv: usize,
    /// Rays, row-major: index `j * nu + i` for cell (i, j).
    pub dexels: Vec<Dexel>,
}

impl DexelFamily {
    /// The point where ray (i, j) passes offset 0 (its grid origin), mm.
    #[must_use]
    pub fn ray_origin(&self, i: usize, j: usize) -> DVec3 {
        let (u, v, _) = self.axis.axes();
        let mut p = self.origin.to_array();
        #[allow(clippy::cast_precision_loss)]
        let (fi, fj) = (i as f64 + 0.5, j as f64 + 0.5);
        if let Some(x) = p.get_mut(u) {
            *x += fi * self.spacing;
        }
        if let Some(x) = p.get_mut(v) {
            *x += fj * self.spacing;
        }
        DVec3::from_array(p)
    }

    /// The point at offset `s` along ray (i, j), mm.
    #[must_use]
    pub fn point(&self, i: usize, j: usize, s: f64) -> DVec3 {
        self.ray_origin(i, j) + self.axis.direction() * s
    }

    /// Material volume, mm³, summed tile by tile (`VOLUME_TILE` rays a side, in tile order,
    /// each tile in ray order: deterministic, and the sum the live cutting keeps up to date
    /// tile by tile without visiting every ray).
    #[must_use]
    pub fn volume(&self) -> f64 {
        let (tu, tv) = (self.nu.div_ceil(VOLUME_TILE), self.nv.div_ceil(VOLUME_TILE));
        let mut total = 0.0;
        for k in 0..tu * tv {
            let (ci, cj) = (k % tu, k / tu);
            let (i0, i1) = (ci * VOLUME_TILE, ((ci + 1) * VOLUME_TILE).min(self.nu));
            let mut tile = 0.0;
            for j in cj * VOLUME_TILE..((cj + 1) * VOLUME_TILE).min(self.nv) {
                for d in self
                    .dexels
                    .get(j * self.nu + i0..j * self.nu + i1)
                    .unwrap_or(&[])
                {
                    if !d.intervals().is_empty() {
                        tile += d.length();
                    }
                }
            }
            total += tile;
        }
        total * self.spacing * self.spacing
    }

    /// Index range of cells whose centres lie in `[lo, hi]` along grid axis u or v (n cells
    /// from `start`), empty when outside.
    #[must_use]
    pub fn cell_range(start: f64, spacing: f64, n: usize, lo: f64, hi: f64) -> (usize, usize) {
        let a = ((lo - start) / spacing - 0.5).ceil().max(0.0);
        let b = ((hi - start) / spacing - 0.5).floor() + 1.0;
        #[allow(clippy::cast_precision_loss)]
        let b = b.min(n as f64);
        if !(a < b) {
            return (0, 0);
        }
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        (a as usize, b as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subtract_splits_and_trims() {
        let mut d = Dexel::One([0.0, 10.0]);
        assert!(d.subtract(2.0, 3.0));
        assert_eq!(d.intervals(), &[[0.0, 2.0], [3.0, 10.0]]);
        assert!(d.subtract(-1.0, 1.0));
        assert!(d.subtract(9.0, 11.0));
        assert_eq!(d.intervals(), &[[1.0, 2.0], [3.0, 9.0]]);
        assert!((d.length() - 7.0).abs() < 1e-12);
        assert!(!d.subtract(2.0, 3.0));
        assert!(d.subtract(1.5, 4.0));
        assert_eq!(d.intervals(), &[[1.0, 1.5], [4.0, 9.0]]);
        assert!(d.subtract(0.0, 2.0));
        assert_eq!(d, Dexel::One([4.0, 9.0]));
        assert!(d.subtract(0.0, 100.0));
        assert_eq!(d, Dexel::Empty);
        d.add(1.0, 2.0);
        d.add(3.0, 4.0);
        d.add(1.5, 3.5);
        assert_eq!(d, Dexel::One([1.0, 4.0]));
    }

    /// Subtraction in place against a point oracle: a point is material after it exactly
    /// when it was before and lies outside `[lo, hi]`; the intervals stay sorted, disjoint
    /// and non-empty, and the variant is the smallest that holds them.
    #[test]
    fn subtract_in_place_matches_a_point_oracle() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            #[allow(clippy::cast_precision_loss)]
            let v = (seed % n) as f32;
            v
        };
        let inside = |list: &[[f32; 2]], x: f32| list.iter().any(|[a, b]| *a <= x && x <= *b);
        for _ in 0..3000 {
            // Up to five intervals on a grid of quarter millimetres.
            let mut ends: Vec<f32> = (0..2 + 2 * next(5) as usize)
                .map(|_| next(80) * 0.25)
                .collect();
            ends.sort_by(f32::total_cmp);
            ends.dedup();
            let list: Vec<[f32; 2]> = ends.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
            let mut d = Dexel::from_intervals(&list);
            let before = d.intervals().to_vec();
            let (lo, hi) = (next(84) * 0.25 - 0.5, next(84) * 0.25 - 0.5);
            let changed = d.subtract(lo, hi);
            let after = d.intervals();
            assert!(after.iter().all(|[a, b]| a < b));
            assert!(after.windows(2).all(|w| w[0][1] < w[1][0]), "{after:?}");
            assert_eq!(matches!(d, Dexel::Many(_)), after.len() > 1);
            // Points at eighths (between and on every end).
            for k in -8..=180 {
                #[allow(clippy::cast_precision_loss)]
                let x = k as f32 * 0.125;
                let want = inside(&before, x) && !(lo < x && x < hi);
                let on_cut = lo < hi && (x == lo || x == hi);
                if !on_cut {
                    assert_eq!(inside(after, x), want, "{before:?} − [{lo}, {hi}] at {x}");
                }
            }
            assert_eq!(
                changed,
                after != before.as_slice(),
                "{before:?} − [{lo}, {hi}]"
            );
        }
    }

    #[test]
    fn cell_ranges_take_centres_inside() {
        // cells centred at 0.5, 1.5, ..., 9.5
        assert_eq!(DexelFamily::cell_range(0.0, 1.0, 10, 1.2, 3.6), (1, 4));
        assert_eq!(DexelFamily::cell_range(0.0, 1.0, 10, -5.0, 0.5), (0, 1));
        assert_eq!(DexelFamily::cell_range(0.0, 1.0, 10, 20.0, 30.0), (0, 0));
        assert_eq!(DexelFamily::cell_range(0.0, 1.0, 10, -5.0, 50.0), (0, 10));
    }
}
