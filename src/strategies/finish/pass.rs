//! A pass: a polyline in parameter space (dense guide points, the "true" contact curve is its
//! image on the surface) with the predicted scallop toward the neighbouring pass at each guide.

use glam::{DVec2, DVec3};

use super::face::FacePatch;

/// One pass of contact points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pass {
    /// Guide points in parameter space, in cutting order.
    pub uv: Vec<DVec2>,
    /// Predicted scallop toward the next pass at each guide, mm (same length as `uv`).
    pub scallop: Vec<f64>,
    /// Closed loop (spiral rings): the last guide joins the first.
    pub closed: bool,
}

impl Pass {
    /// A pass through `uv` with unknown (zero) predicted scallop.
    #[must_use]
    pub fn new(uv: Vec<DVec2>) -> Self {
        let n = uv.len();
        Self {
            uv,
            scallop: vec![0.0; n],
            closed: false,
        }
    }

    /// Length of the contact curve (chords between guides on the surface), mm.
    #[must_use]
    pub fn length(&self, patch: &FacePatch<'_>) -> f64 {
        let pts: Vec<DVec3> = self
            .uv
            .iter()
            .map(|p| patch.surface.point(p.x, p.y))
            .collect();
        pts.windows(2).map(|w| w[0].distance(w[1])).sum()
    }

    /// The same pass run backwards.
    #[must_use]
    pub fn reversed(&self) -> Self {
        let mut p = self.clone();
        p.uv.reverse();
        p.scallop.reverse();
        p
    }

    /// The runs of the pass inside the patch's trimmed region (the pass itself when the patch
    /// has none, or when it lies wholly inside): a run starts and ends where the pass crosses a
    /// loop; predicted scallops are interpolated there. A closed pass that is cut becomes open
    /// runs.
    #[must_use]
    pub fn clipped(&self, patch: &FacePatch<'_>) -> Vec<Self> {
        if patch.region.is_none() {
            return vec![self.clone()];
        }
        let mut pts = self.uv.clone();
        if self.closed
            && let Some(&first) = self.uv.first()
        {
            pts.push(first);
        }
        let runs = patch.clip(&pts);
        if let [run] = runs.as_slice()
            && run.len() == pts.len()
            && run.iter().zip(&pts).all(|(a, b)| a.0 == *b)
        {
            return vec![self.clone()];
        }
        let h = |x: f64| {
            let n = self.scallop.len();
            if n == 0 {
                return 0.0;
            }
            let k = (x.floor().max(0.0) as usize).min(n - 1);
            let t = x - k as f64;
            let a = self.scallop.get(k % n).copied().unwrap_or(0.0);
            let b = self.scallop.get((k + 1) % n).copied().unwrap_or(a);
            a + (b - a) * t.clamp(0.0, 1.0)
        };
        runs.into_iter()
            .map(|r| Self {
                uv: r.iter().map(|x| x.0).collect(),
                scallop: r.iter().map(|x| h(x.1)).collect(),
                closed: false,
            })
            .collect()
    }

    /// Resample so consecutive guides are about `spacing` mm apart on the surface (at least
    /// 2 guides), interpolating in parameter space.
    #[must_use]
    pub fn resampled(&self, patch: &FacePatch<'_>, spacing: f64) -> Self {
        let pts: Vec<DVec3> = self
            .uv
            .iter()
            .map(|p| patch.surface.point(p.x, p.y))
            .collect();
        let mut cum = vec![0.0];
        for w in pts.windows(2) {
            let last = cum.last().copied().unwrap_or(0.0);
            cum.push(last + w[0].distance(w[1]));
        }
        let total = cum.last().copied().unwrap_or(0.0);
        let n = ((total / spacing).ceil() as usize).clamp(1, 100_000);
        let mut out = Pass {
            closed: self.closed,
            ..Pass::default()
        };
        let mut j = 0usize;
        for k in 0..=n {
            let s = total * k as f64 / n as f64;
            while j + 2 < cum.len() && cum.get(j + 1).is_some_and(|&c| c < s) {
                j += 1;
            }
            let (Some(&c0), Some(&c1), Some(&a), Some(&b)) = (
                cum.get(j),
                cum.get(j + 1),
                self.uv.get(j),
                self.uv.get(j + 1),
            ) else {
                break;
            };
            let t = if c1 > c0 {
                ((s - c0) / (c1 - c0)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            out.uv.push(a.lerp(b, t));
            let (ha, hb) = (
                self.scallop.get(j).copied().unwrap_or(0.0),
                self.scallop.get(j + 1).copied().unwrap_or(0.0),
            );
            out.scallop.push(ha + (hb - ha) * t);
        }
        if out.uv.len() < 2 {
            return self.clone();
        }
        out
    }
}
