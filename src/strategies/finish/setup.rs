//! The shared context of the finishing strategies: the face, the cutter and the options
//! ([`Setup`]), a guide point of a pass ([`Guide`]) and the cross-feed section there
//! ([`SectionAt`]), from which the pass planners choose their side steps.

use glam::{DVec2, DVec3};

use super::axis::AxisMode;
use super::face::{FacePatch, LocalFrame};
use super::pass::Pass;
use super::scallop::Section;
use super::{Direction, FinishOptions};
use crate::tools::Cutter;
use crate::tools::effective::CrossProfile;

/// Everything a strategy needs: the face, the cutter, the options and internal resolutions.
#[derive(Clone, Debug)]
pub struct Setup<'a> {
    /// The face.
    pub patch: FacePatch<'a>,
    /// The cutter (ball, flat or bull-nose).
    pub cutter: &'a Cutter,
    /// Options (the lead may have been raised against local gouging).
    pub opts: FinishOptions,
    /// Spacing of guide points along a pass, mm.
    pub guide_spacing: f64,
    /// Sub-step of marches along the surface, mm.
    pub march_substep: f64,
    /// Passes shorter than this are dropped, mm.
    pub min_pass_length: f64,
}

/// A guide point of a pass: frame, unit feed and unit cross direction toward the next pass.
#[derive(Clone, Copy, Debug)]
pub struct Guide {
    /// Frame at the guide.
    pub frame: LocalFrame,
    /// Unit feed direction (tangent).
    pub f: DVec3,
    /// Unit tangent ⟂ f toward increasing across-parameter (the next pass).
    pub tau: DVec3,
}

/// The cross-feed section at a guide: this pass's and the next pass's profiles and κ.
#[derive(Clone, Debug)]
pub struct SectionAt {
    a: CrossProfile,
    b: CrossProfile,
    kappa: f64,
    h: f64,
    symmetric: bool,
}

impl SectionAt {
    fn section(&self) -> Section<'_> {
        Section {
            a: &self.a,
            b: &self.b,
            kappa: self.kappa,
            symmetric: self.symmetric,
        }
    }

    /// Side step for the requested scallop and the predicted height there.
    #[must_use]
    pub fn step(&self) -> (f64, f64) {
        self.section().step_for(self.h)
    }

    /// Scallop for contacts `w` apart.
    #[must_use]
    pub fn height(&self, w: f64) -> f64 {
        self.section().height(w)
    }

    /// Material left on a boundary `d` mm beside this pass.
    #[must_use]
    pub fn boundary_height(&self, d: f64) -> f64 {
        let y = self.a.height(d);
        if y.is_finite() {
            (y - 0.5 * self.kappa * d * d).max(0.0)
        } else {
            0.0
        }
    }
}

impl<'a> Setup<'a> {
    /// The setup of a face, a cutter and (already adjusted) options, with the planner's
    /// internal resolutions (guide spacing min(0.5 mm, R), 0.5 mm march sub-steps, passes
    /// shorter than R dropped).
    #[must_use]
    pub fn new(patch: FacePatch<'a>, cutter: &'a Cutter, opts: FinishOptions) -> Self {
        Self {
            patch,
            cutter,
            opts,
            guide_spacing: 0.5_f64.min(cutter.radius()),
            march_substep: 0.5,
            min_pass_length: cutter.radius(),
        }
    }

    /// Parameter index across the passes (0: u, 1: v).
    #[must_use]
    pub fn across(&self) -> usize {
        match self.opts.direction {
            Direction::V => 0,
            Direction::U => 1,
        }
    }

    /// Parameters from (across, along) fractions.
    #[must_use]
    pub fn at(&self, across: f64, along: f64) -> DVec2 {
        match self.opts.direction {
            Direction::V => self.patch.at(across, along),
            Direction::U => self.patch.at(along, across),
        }
    }

    /// The iso-parametric pass at `across` fraction `s`, resampled to the guide spacing.
    #[must_use]
    pub fn iso_pass(&self, s: f64) -> Pass {
        let n = 64;
        let uv = (0..=n)
            .map(|k| self.at(s, f64::from(k) / f64::from(n)))
            .collect();
        Pass::new(uv).resampled(&self.patch, self.guide_spacing)
    }

    /// The runs of the iso-parametric pass at `across` fraction `s` inside the trimmed region,
    /// each resampled to the guide spacing.
    #[must_use]
    pub fn iso_runs(&self, s: f64) -> Vec<Pass> {
        self.iso_pass(s)
            .clipped(&self.patch)
            .into_iter()
            .map(|p| p.resampled(&self.patch, self.guide_spacing))
            .collect()
    }

    /// The pass along the edge at `along` fraction `s` (the iso-curve across the passes),
    /// resampled to the guide spacing.
    #[must_use]
    pub fn edge_pass(&self, s: f64) -> Pass {
        let n = 64;
        let uv = (0..=n)
            .map(|k| self.at(f64::from(k) / f64::from(n), s))
            .collect();
        Pass::new(uv).resampled(&self.patch, self.guide_spacing)
    }

    /// The guide at index `i` of `pass`.
    #[must_use]
    pub fn guide(&self, pass: &Pass, i: usize) -> Option<Guide> {
        self.guide_spanning(pass, i, 1)
    }

    /// The guide at index `i` of `pass`, its feed taken from the chord between the points `k`
    /// guides before and after (clamped to the pass): a wide chord keeps the cross direction
    /// steady against wiggles much shorter than the side step.
    #[must_use]
    pub fn guide_spanning(&self, pass: &Pass, i: usize, k: usize) -> Option<Guide> {
        let uv = *pass.uv.get(i)?;
        let frame = self.patch.frame(uv)?;
        let k = k.max(1);
        let last = pass.uv.len().saturating_sub(1);
        let prev = pass.uv.get(i.saturating_sub(k)).copied().unwrap_or(uv);
        let next = pass.uv.get((i + k).min(last)).copied().unwrap_or(uv);
        let chord =
            self.patch.surface.point(next.x, next.y) - self.patch.surface.point(prev.x, prev.y);
        let f = (chord - frame.n * chord.dot(frame.n)).try_normalize()?;
        let mut tau = frame.n.cross(f);
        let dp = FacePatch::param_dir(&frame.d, tau);
        let comp = if self.across() == 0 { dp.x } else { dp.y };
        if comp < 0.0 {
            tau = -tau;
        }
        Some(Guide { frame, f, tau })
    }

    /// Tool axis at a contact.
    #[must_use]
    pub fn axis(&self, frame: &LocalFrame, f: DVec3) -> DVec3 {
        self.opts.axis.axis(frame.p, frame.n, f)
    }

    /// The cross-feed section at a guide; the next pass runs along `−f` when `next_reversed`.
    /// `None` for cutters without a cross profile (cones).
    #[must_use]
    pub fn section(&self, g: &Guide, next_reversed: bool) -> Option<SectionAt> {
        let fa = g.f;
        let fb = if next_reversed { -g.f } else { g.f };
        let aa = self.axis(&g.frame, fa);
        let ab = self.axis(&g.frame, fb);
        let symmetric = matches!(self.opts.axis, AxisMode::Normal { tilt, .. } if tilt == 0.0);
        let a = CrossProfile::new(self.cutter, aa, g.frame.n, fa, g.tau)?;
        let b = if symmetric {
            a.clone()
        } else {
            CrossProfile::new(self.cutter, ab, g.frame.n, fb, g.tau)?
        };
        Some(SectionAt {
            a,
            b,
            kappa: self.patch.curvature_along(&g.frame, g.tau),
            h: self.opts.scallop,
            // Normal-relative axes without sideways tilt give a mirror-symmetric outline, the
            // same for both feed senses (reflecting f → −f leaves the projection along f).
            symmetric,
        })
    }
}
