//! Min/max decimation of a time series for drawing: the time span is cut into equal buckets
//! (about one per pixel column) and each bucket keeps its smallest and largest value in time
//! order, so every peak stays visible however far the plot is zoomed out.

/// Streams `(t, value)` samples (time non-decreasing) into at most `max_points` points.
#[derive(Clone, Debug)]
pub struct MinMaxDecimator {
    t0: f64,
    bucket_s: f64,
    bucket: Option<i64>,
    /// (t, value, tag) of the bucket's smallest and largest value.
    min: (f64, f64, f64),
    max: (f64, f64, f64),
    out: Vec<[f64; 3]>,
}

impl MinMaxDecimator {
    /// A decimator for samples over `[t0, t1]` keeping at most `max_points` points (at least 2).
    #[must_use]
    pub fn new(t0: f64, t1: f64, max_points: usize) -> Self {
        let buckets = (max_points / 2).max(1);
        let span = if t1 > t0 && (t1 - t0).is_finite() {
            t1 - t0
        } else {
            1.0
        };
        Self {
            t0,
            // Slightly wider buckets so that `t1` itself falls in the last one.
            bucket_s: span / buckets as f64 * (1.0 + 1e-9),
            bucket: None,
            min: (0.0, f64::INFINITY, 0.0),
            max: (0.0, f64::NEG_INFINITY, 0.0),
            out: Vec::with_capacity(max_points.min(1 << 20)),
        }
    }

    /// Add one sample (non-finite values are skipped).
    pub fn push(&mut self, t: f64, value: f64) {
        self.push_tagged(t, value, 0.0);
    }

    /// Add one sample carrying a tag that is kept with it (e.g. the path position at `t`).
    pub fn push_tagged(&mut self, t: f64, value: f64, tag: f64) {
        if !(t.is_finite() && value.is_finite()) {
            return;
        }
        let bucket = ((t - self.t0) / self.bucket_s).floor() as i64;
        if self.bucket != Some(bucket) {
            self.flush();
            self.bucket = Some(bucket);
        }
        if value < self.min.1 {
            self.min = (t, value, tag);
        }
        if value > self.max.1 {
            self.max = (t, value, tag);
        }
    }

    fn flush(&mut self) {
        if self.bucket.is_none() {
            return;
        }
        let (a, b) = if self.min.0 <= self.max.0 {
            (self.min, self.max)
        } else {
            (self.max, self.min)
        };
        self.out.push([a.0, a.1, a.2]);
        if b != a {
            self.out.push([b.0, b.1, b.2]);
        }
        self.min = (0.0, f64::INFINITY, 0.0);
        self.max = (0.0, f64::NEG_INFINITY, 0.0);
        self.bucket = None;
    }

    /// The decimated points `[t, value]`, in time order.
    #[must_use]
    pub fn finish(self) -> Vec<[f64; 2]> {
        self.finish_tagged()
            .into_iter()
            .map(|[t, v, _]| [t, v])
            .collect()
    }

    /// The decimated points with their tags, `[t, value, tag]`, in time order.
    #[must_use]
    pub fn finish_tagged(mut self) -> Vec<[f64; 3]> {
        self.flush();
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic noisy signal with narrow spikes (one sample wide).
    fn signal(n: usize) -> Vec<(f64, f64)> {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        (0..n)
            .map(|i| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let noise = (state % 1000) as f64 / 1000.0;
                let t = i as f64 * 1e-3;
                let spike = match i % 9973 {
                    0 => 50.0,
                    4000 => -70.0,
                    _ => 0.0,
                };
                (t, (t * 3.0).sin() * 10.0 + noise + spike)
            })
            .collect()
    }

    #[test]
    fn keeps_every_bucket_extreme_and_the_size_bound() {
        let n = 1_000_000;
        let s = signal(n);
        let t1 = s.last().map_or(0.0, |p| p.0);
        let max_points = 20_000;
        let mut d = MinMaxDecimator::new(0.0, t1, max_points);
        for &(t, v) in &s {
            d.push(t, v);
        }
        let out = d.finish();
        assert!(out.len() <= max_points, "{}", out.len());
        assert!(out.len() >= max_points / 2, "{}", out.len());
        assert!(out.windows(2).all(|w| w[0][0] <= w[1][0]), "time order");
        // Brute force: every window of the original between two bucket edges has its min and
        // max among the output points of that window; in particular every spike survives.
        let bucket_s = t1 / (max_points / 2) as f64 * (1.0 + 1e-9);
        let mut k = 0;
        while k < s.len() {
            let b = (s[k].0 / bucket_s).floor();
            let end = s[k..]
                .iter()
                .position(|p| (p.0 / bucket_s).floor() != b)
                .map_or(s.len(), |p| k + p);
            let (lo, hi) = s[k..end]
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                    (l.min(p.1), h.max(p.1))
                });
            let kept: Vec<f64> = out
                .iter()
                .filter(|p| (p[0] / bucket_s).floor() == b)
                .map(|p| p[1])
                .collect();
            assert!(kept.contains(&lo) && kept.contains(&hi), "bucket {b}");
            k = end;
        }
        let spikes = out.iter().filter(|p| p[1] > 45.0).count();
        assert_eq!(spikes, s.iter().filter(|p| p.1 > 45.0).count());
    }

    #[test]
    fn short_series_pass_through_and_bad_values_are_skipped() {
        let mut d = MinMaxDecimator::new(0.0, 1.0, 1000);
        for (t, v) in [(0.0, 1.0), (0.5, f64::NAN), (0.5, 2.0), (1.0, 3.0)] {
            d.push(t, v);
        }
        assert_eq!(d.finish(), vec![[0.0, 1.0], [0.5, 2.0], [1.0, 3.0]]);
        assert!(MinMaxDecimator::new(0.0, 0.0, 10).finish().is_empty());
    }
}
