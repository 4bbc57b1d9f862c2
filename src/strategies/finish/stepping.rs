//! Forward steps from the chord tolerance, on the tool-tip path the machine follows (the thesis's
//! chord criterion, applied to the tip rather than only the contact points): from each accepted pose the step is
//! grown or halved until the straight tip move stays within ε of the true tip curve (checked at
//! interior samples) and the axis turns by at most the allowed angle; the step update uses
//! `Δ ← Δ·√(ε/e)` (the chord error e grows as Δ²), bounded.
//!
//! The tolerance is one-sided, outside the part: poses are placed on the surface raised by ε/2
//! along the normal and chords may deviate by ε/2 from that raised tip curve, so the straight
//! moves never dip below the nominal surface (convex stretches) and never stand more than ε
//! above it (concave ones).
//!
//! A pass is a curve in its index parameter σ (0 at the first guide point, one per guide);
//! `PassCurve` evaluates it with an optional lead profile along σ (normal-relative axes: the
//! gouge repair raises the lead locally) and steps it, optionally through given σ values.

use glam::{DVec2, DVec3};

use super::axis::{AxisMode, axis_angle};
use super::pass::Pass;
use super::setup::Setup;
use crate::toolpath::{ContactKind, MoveKind, Pose};
use crate::tools::CutterKind;
use crate::tools::effective::contact_to_tip;

/// A point of the true pass curve at index parameter σ.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CurvePoint {
    /// Contact point on the surface.
    pub cc: DVec3,
    /// Contact raised by ε/2 along the normal.
    pub lifted: DVec3,
    /// Tool tip.
    pub tip: DVec3,
    /// Unit tool axis.
    pub axis: DVec3,
    /// Tool-side unit normal.
    pub n: DVec3,
    /// Unit feed direction (tangent).
    pub f: DVec3,
    /// Predicted scallop.
    pub scallop: f64,
}

/// Interior samples per chord check.
const CHECKS: usize = 7;

/// A pass as a tool-tip curve in its index parameter σ ∈ [0, n − 1].
pub(crate) struct PassCurve<'a, 'b> {
    setup: &'b Setup<'a>,
    pass: &'b Pass,
    feeds: Vec<DVec3>,
}

impl<'a, 'b> PassCurve<'a, 'b> {
    /// The curve of `pass`; `None` for passes of fewer than two points.
    pub fn new(setup: &'b Setup<'a>, pass: &'b Pass) -> Option<Self> {
        let n = pass.uv.len();
        if n < 2 {
            return None;
        }
        // Unit feed per guide from neighbouring chords (a smooth, C0 field along the pass).
        let pts: Vec<DVec3> = pass
            .uv
            .iter()
            .map(|p| setup.patch.surface.point(p.x, p.y))
            .collect();
        let feeds = (0..n)
            .map(|i| {
                let a = pts.get(i.saturating_sub(1)).copied().unwrap_or_default();
                let b = pts.get((i + 1).min(n - 1)).copied().unwrap_or_default();
                (b - a).normalize_or_zero()
            })
            .collect();
        Some(Self { setup, pass, feeds })
    }

    /// Largest σ.
    pub fn end(&self) -> f64 {
        (self.pass.uv.len() - 1) as f64
    }

    /// The curve point at σ; `lead` replaces the lead of a normal-relative axis mode.
    pub fn eval(&self, sigma: f64, lead: Option<f64>) -> Option<CurvePoint> {
        let setup = self.setup;
        let n = self.pass.uv.len();
        let s = sigma.clamp(0.0, (n - 1) as f64);
        let i = (s.floor() as usize).min(n - 2);
        let t = s - i as f64;
        let uv: DVec2 = self.pass.uv.get(i)?.lerp(*self.pass.uv.get(i + 1)?, t);
        let frame = setup.patch.frame(uv)?;
        let f0 = self.feeds.get(i)?.lerp(*self.feeds.get(i + 1)?, t);
        let f = (f0 - frame.n * f0.dot(frame.n)).try_normalize()?;
        let axis = match (setup.opts.axis, lead) {
            (AxisMode::Normal { tilt, .. }, Some(lead)) => {
                AxisMode::Normal { lead, tilt }.axis(frame.p, frame.n, f)
            }
            _ => setup.axis(&frame, f),
        };
        let lifted = frame.p + frame.n * (0.5 * setup.opts.tolerance);
        let tip = contact_to_tip(setup.cutter, lifted, frame.n, axis, f)?;
        let h0 = self.pass.scallop.get(i).copied().unwrap_or(0.0);
        let h1 = self.pass.scallop.get(i + 1).copied().unwrap_or(0.0);
        Some(CurvePoint {
            cc: frame.p,
            lifted,
            tip,
            axis,
            n: frame.n,
            f,
            scallop: h0 + (h1 - h0) * t,
        })
    }

    /// Forward steps along the curve with the lead profile `lead_at(σ)` (`None`: the mode's
    /// own axis), every σ of `through` (sorted) being a pose; poses with their σ.
    pub fn step(&self, lead_at: &dyn Fn(f64) -> Option<f64>, through: &[f64]) -> Vec<(Pose, f64)> {
        let setup = self.setup;
        let eval = |s: f64| self.eval(s, lead_at(s));
        let end = self.end();
        let eps = 0.5 * setup.opts.tolerance;
        let mut poses = Vec::new();
        let mut sigma = 0.0;
        let Some(mut cur) = eval(0.0) else {
            return poses;
        };
        poses.push((make_pose(setup, &cur), 0.0));
        let mut step = 1.0_f64;
        let min_step = 1e-6;
        while sigma < end {
            // Do not step over a σ that must be a pose.
            let stop = through
                .iter()
                .copied()
                .find(|&s| s > sigma + min_step)
                .map_or(end, |s| s.min(end));
            let mut tries = 0;
            loop {
                tries += 1;
                let s1 = (sigma + step).min(stop);
                let Some(next) = eval(s1) else {
                    // Undefined normal ahead: skip a small step.
                    sigma = s1;
                    break;
                };
                let dev = chord_deviation(setup, &eval, sigma, s1, &cur, &next);
                let turn = axis_angle(cur.axis, next.axis);
                let ok = dev <= eps && turn <= setup.opts.max_axis_step;
                if ok || step <= min_step || tries > 60 {
                    poses.push((make_pose(setup, &next), s1));
                    sigma = s1;
                    cur = next;
                    // Grow for the next step, by the error ratio (e ∝ Δ²), at most ×2.
                    let ratio = if dev > 0.0 { (eps / dev).sqrt() } else { 2.0 };
                    step = (step * ratio.clamp(0.5, 2.0)).max(min_step);
                    break;
                }
                let ratio = if dev > eps {
                    (eps / dev).sqrt() * 0.9
                } else {
                    0.5
                };
                step = (step * ratio.clamp(0.1, 0.5)).max(min_step);
            }
        }
        poses
    }
}

/// Largest distance between the straight move from `a` to `b` (tip linear, axis normalised
/// linear) and the true curve between σ0 and σ1, at interior samples: both the tip and the
/// cutter point that should touch the (lifted) contact are compared, so a turning axis that
/// swings the cutter's rim into the surface is caught too.
fn chord_deviation(
    setup: &Setup<'_>,
    eval: &impl Fn(f64) -> Option<CurvePoint>,
    s0: f64,
    s1: f64,
    a: &CurvePoint,
    b: &CurvePoint,
) -> f64 {
    let ab = b.tip - a.tip;
    let len2 = ab.length_squared();
    let mut worst: f64 = 0.0;
    for k in 1..=CHECKS {
        let frac = k as f64 / (CHECKS + 1) as f64;
        let s = s0 + (s1 - s0) * frac;
        let Some(p) = eval(s) else { continue };
        let t = if len2 > 0.0 {
            ((p.tip - a.tip).dot(ab) / len2).clamp(0.0, 1.0)
        } else {
            frac
        };
        let tip = a.tip + ab * t;
        worst = worst.max(p.tip.distance(tip));
        // The cutter at the interpolated pose: where is its point for this contact? Not for a
        // flat or toroidal bottom touching with the axis along the normal: any point of the
        // bottom touches there, and the rim point picked for a slightly turned axis would jump
        // by the flat radius (the tip check covers it).
        if setup.cutter.kind != CutterKind::Ball && p.axis.dot(p.n) > 1.0 - 1e-9 {
            continue;
        }
        let axis = a.axis.lerp(b.axis, t).normalize_or(p.axis);
        let offset = |ax: DVec3| {
            contact_to_tip(setup.cutter, DVec3::ZERO, p.n, ax, DVec3::ZERO).unwrap_or(DVec3::ZERO)
        };
        // Only the height of that point along the normal matters (a gap or a gouge): it used to
        // be the full distance, but for a flat or toroidal bottom tilted by a small lead the
        // touching rim point is ill-conditioned (its direction is the normal projected on the
        // bottom, |n − (a·n)a| = sin S), so an axis interpolated 0.1° off the true one slid it
        // sideways by R_f·0.1°/S, tenths of a mm along the surface at no change of height,
        // and the steps were cut far below what the tolerance needs.
        let touch = tip - offset(axis);
        worst = worst.max((touch - p.lifted).dot(p.n).abs());
    }
    worst
}

/// The cut pose of a curve point.
pub(crate) fn make_pose(setup: &Setup<'_>, c: &CurvePoint) -> Pose {
    let kind = match setup.cutter.kind {
        CutterKind::Ball => ContactKind::Ball,
        _ if c.axis.dot(c.n) > 1.0 - 1e-9 => ContactKind::Bottom,
        _ => ContactKind::Corner,
    };
    Pose::new(MoveKind::Cut, c.tip, c.axis, setup.opts.feed)
        .with_contact(c.cc, kind)
        .with_scallop(c.scallop)
}
