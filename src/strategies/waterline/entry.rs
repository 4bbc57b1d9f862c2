//! How the tool enters each waterline loop (or steep run): straight down onto its start (a
//! plunge), along a tangential quarter-circle lead-in in the level's plane on the free side
//! (with a matching lead-out after the loop), or down a ramp along the loop itself.
//!
//! - **Arc**: centre at distance R from the run's start on the free side (left of the travel
//!   for climb, right for conventional), the arc ending at the start tangent to the first cut;
//!   the lead-out mirrors it at the run's end, tangent to the last cut. Chords of the arcs sag
//!   at most the chord tolerance. Every chord is checked at the level with the push-cutter
//!   ([`super::link_free`]), touching the loop only at its end.
//! - **Ramp**: from [`RAMP_HEIGHT_MM`] above the level (or from the height a fed link arrives
//!   at, when lower) down along the closed loop at the angle (the Z-level roughing's ramp), then
//!   on round the loop at the level from where the ramp reached it, back to that point. With an
//!   endless shank the cutter raised over the loop occupies a subset of what it occupies on the
//!   loop, so the ramp is clear wherever the loop is; the check pushes each chord of the ramp
//!   above the level, moved off the loop to the free side by twice the chord tolerance (what a
//!   chord between contour points at most sags inside the exact contour), at its lower end's
//!   height.
//! - An entry that is not clear, or a ramp on an open run, falls back to the plunge (counted).

use std::f64::consts::FRAC_PI_2;

use glam::{DVec2, DVec3};

use super::{
    COLLINEAR_FRACTION, ContourPoint, Cut, WaterlineOptions, kept_points, link_free, push::Profile,
};
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::toolpath::{ContactKind, MoveKind, Pose};

/// Height above the level a ramp starts from (and where a plunge's rapid stops), mm.
pub const RAMP_HEIGHT_MM: f64 = 1.0;

/// How the tool enters each loop (or steep run) of a waterline level.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Entry {
    /// Straight down onto the loop's start from 1 mm above, at the plunge feed.
    #[default]
    Plunge,
    /// Quarter-circle lead-in and lead-out in the level's plane, tangent to the loop, on its
    /// free side.
    Arc {
        /// Radius, mm (`None`: the cutter's radius).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        radius_mm: Option<f64>,
    },
    /// Down along the loop from 1 mm above the level.
    Ramp {
        /// Descent angle from horizontal, rad.
        angle_rad: f64,
    },
}

/// Smallest and largest arc radius, mm.
pub const ARC_RADIUS_RANGE_MM: (f64, f64) = (0.01, 1000.0);
/// Smallest and largest ramp angle, degrees.
pub const RAMP_ANGLE_RANGE_DEG: (f64, f64) = (0.5, 45.0);

impl Entry {
    /// Checks the radius or angle; the reason when out of range.
    ///
    /// # Errors
    /// A sentence naming the value and its range.
    pub fn validate(&self) -> Result<(), String> {
        match *self {
            Self::Plunge | Self::Arc { radius_mm: None } => Ok(()),
            Self::Arc { radius_mm: Some(r) } => {
                let (lo, hi) = ARC_RADIUS_RANGE_MM;
                if (lo..=hi).contains(&r) {
                    Ok(())
                } else {
                    Err(format!(
                        "entry arc radius must be {lo} to {hi} mm, got {r} mm"
                    ))
                }
            }
            Self::Ramp { angle_rad } => {
                let (lo, hi) = RAMP_ANGLE_RANGE_DEG;
                let d = angle_rad.to_degrees();
                if (lo..=hi).contains(&d) {
                    Ok(())
                } else {
                    Err(format!(
                        "entry ramp angle must be {lo} to {hi} degrees, got {d} degrees"
                    ))
                }
            }
        }
    }
}

/// Ramp angle when none is given, degrees (as the Z-level roughing's ramp).
pub const RAMP_DEFAULT_ANGLE_DEG: f64 = 5.0;

impl std::str::FromStr for Entry {
    type Err = String;

    /// `plunge`, `arc` (radius: the cutter's), `arc:R` (mm), `ramp` (5°) or `ramp:DEG`;
    /// checked as [`Entry::validate`].
    fn from_str(s: &str) -> Result<Self, String> {
        let (kind, value) = match s.split_once(':') {
            Some((k, v)) => (k.trim(), Some(v.trim())),
            None => (s.trim(), None),
        };
        let number = |v: &str, what: &str| {
            v.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("entry {what} '{v}' is not a number"))
        };
        let e = match (kind, value) {
            ("plunge", None) => Self::Plunge,
            ("arc", None) => Self::Arc { radius_mm: None },
            ("arc", Some(v)) => Self::Arc {
                radius_mm: Some(number(v, "arc radius")?),
            },
            ("ramp", v) => Self::Ramp {
                angle_rad: match v {
                    Some(v) => number(v, "ramp angle")?,
                    None => RAMP_DEFAULT_ANGLE_DEG,
                }
                .to_radians(),
            },
            _ => {
                return Err(format!(
                    "unknown entry '{s}' (plunge, arc, arc:R in mm, ramp, ramp:DEG)"
                ));
            }
        };
        e.validate()?;
        Ok(e)
    }
}

/// The part and cutter the entries are checked against.
pub(super) struct Ctx<'a> {
    pub mesh: &'a TriMesh,
    pub bvh: &'a MeshBvh,
    pub prof: &'a Profile,
    pub contact: ContactKind,
}

/// What the tool does at one run: arrive at `start`, then make `moves`.
pub(super) struct Approach {
    /// Where the tool arrives, from a link or from above.
    pub start: DVec3,
    /// From above: rapid down to this far above `start`, then plunge (0: rapid onto `start`).
    pub gap: f64,
    /// Lead-in, the run's cuts, lead-out.
    pub moves: Vec<Pose>,
    /// The asked entry was not clear (or not possible) and the plunge is used.
    pub fell_back: bool,
}

/// The approach to `raw` (the contour points of a run; closed runs end at their start) with
/// the ramp starting `ramp_h` above the level (≤ 0: no ramp needed, the tool arrives at the
/// level). The points a line carries are dropped; a closed loop is cut on past its start to
/// the first contour point at least `loop_overlap_mm` along it (every pose stays a contour
/// point, so the lead-out leaves from the exact contour).
pub(super) fn approach(
    ctx: &Ctx,
    raw: &[ContourPoint],
    opts: &WaterlineOptions,
    ramp_h: f64,
) -> Approach {
    let feed = opts.feed_mm_per_min;
    let eps = COLLINEAR_FRACTION * opts.chord_tol_mm;
    let closed = raw.len() > 2 && raw[0].tip == raw[raw.len() - 1].tip;
    let kept = kept_points(raw, eps);
    let run: Vec<ContourPoint> = kept.iter().map(|&i| raw[i]).collect();
    let mut cut_run = run.clone();
    if closed {
        cut_run.extend(overlap(raw[0], &raw[1..], opts.loop_overlap_mm, eps));
    }
    let plunge = |fell_back| Approach {
        start: run[0].tip,
        gap: RAMP_HEIGHT_MM,
        moves: cuts(ctx, &cut_run[1..], feed),
        fell_back,
    };
    match opts.entry {
        Entry::Plunge => plunge(false),
        Entry::Arc { radius_mm } => {
            let r = radius_mm.unwrap_or_else(|| ctx.prof.radius());
            let Some((lead_in, lead_out)) = arcs(ctx, &cut_run, r, opts) else {
                return plunge(true);
            };
            let link = |p: &DVec3| Pose::new(MoveKind::Link, *p, DVec3::Z, feed);
            let mut moves: Vec<Pose> = lead_in[1..].iter().map(link).collect();
            moves.extend(cuts(ctx, &cut_run[1..], feed));
            moves.extend(lead_out[1..].iter().map(link));
            Approach {
                start: lead_in[0],
                gap: RAMP_HEIGHT_MM,
                moves,
                fell_back: false,
            }
        }
        Entry::Ramp { .. } if ramp_h <= 1e-9 => plunge(false),
        Entry::Ramp { angle_rad } => {
            match closed
                .then(|| ramp(ctx, (raw, &kept), ramp_h, angle_rad, opts))
                .flatten()
            {
                Some(a) => a,
                None => plunge(true),
            }
        }
    }
}

/// The contour points passed walking on from `from` through `pts` in order until at least
/// `dist` mm are covered (the last one is the first at or past `dist`; all of `pts` when the
/// loop is shorter), less those a line carries within `eps`.
fn overlap(from: ContourPoint, pts: &[ContourPoint], dist: f64, eps: f64) -> Vec<ContourPoint> {
    if dist <= 0.0 {
        return Vec::new();
    }
    let mut walked = vec![from];
    let mut left = dist;
    for p in pts {
        let d = walked[walked.len() - 1].tip.distance(p.tip);
        if d <= 1e-12 {
            continue;
        }
        walked.push(*p);
        left -= d;
        if left <= 1e-9 {
            break;
        }
    }
    kept_points(&walked, eps)
        .into_iter()
        .skip(1)
        .map(|i| walked[i])
        .collect()
}

/// Cutting moves through `pts`, each with its contact.
fn cuts(ctx: &Ctx, pts: &[ContourPoint], feed: f64) -> Vec<Pose> {
    pts.iter()
        .map(|p| Pose::new(MoveKind::Cut, p.tip, DVec3::Z, feed).with_contact(p.cc, ctx.contact))
        .collect()
}

/// +1 when the free side is on the left of the travel (climb: the part on the right), else −1.
fn free_side(opts: &WaterlineOptions) -> f64 {
    match opts.cut {
        Cut::Climb => 1.0,
        Cut::Conventional => -1.0,
    }
}

/// The horizontal unit direction from `a` to the first of `pts` apart from it.
fn direction<'a>(a: DVec3, pts: impl Iterator<Item = &'a ContourPoint>) -> Option<DVec2> {
    pts.map(|p| (p.tip - a).truncate())
        .find(|d| d.length() > 1e-9)
        .map(DVec2::normalize)
}

/// Quarter circle of radius `r` tangent at `p` to the unit direction `t`, its centre on
/// `side` (+1 left of `t`), ending at `p` (lead-in) or starting there (lead-out); chords sag at
/// most `tol`.
pub(super) fn quarter_arc(
    p: DVec3,
    t: DVec2,
    r: f64,
    side: f64,
    tol: f64,
    lead_in: bool,
) -> Vec<DVec3> {
    let n = DVec2::new(-t.y, t.x) * side;
    let c = p.truncate() + n * r;
    let step = 2.0 * (1.0 - (tol / r).min(1.0)).acos();
    let k = ((FRAC_PI_2 / step.max(1e-3)).ceil() as usize).clamp(4, 256);
    let mut out: Vec<DVec3> = (0..=k)
        .map(|i| {
            let f = i as f64 / k as f64;
            let phi = if lead_in {
                -FRAC_PI_2 * (1.0 - f)
            } else {
                FRAC_PI_2 * f
            };
            (c - r * (n * phi.cos() - t * phi.sin())).extend(p.z)
        })
        .collect();
    // The end on the loop is the loop's point itself.
    let at = if lead_in { k } else { 0 };
    out[at] = p;
    out
}

/// The lead-in ending at the run's start and the lead-out from its end, when both are clear.
fn arcs(
    ctx: &Ctx,
    run: &[ContourPoint],
    r: f64,
    opts: &WaterlineOptions,
) -> Option<(Vec<DVec3>, Vec<DVec3>)> {
    let (first, last) = (run.first()?.tip, run.last()?.tip);
    let t0 = direction(first, run.iter().skip(1))?;
    let te = -direction(last, run.iter().rev().skip(1))?;
    let side = free_side(opts);
    let tol = opts.chord_tol_mm;
    let lead_in = quarter_arc(first, t0, r, side, tol, true);
    let lead_out = quarter_arc(last, te, r, side, tol, false);
    let free = |pts: &[DVec3]| {
        pts.windows(2).all(|w| {
            link_free(
                ctx.mesh,
                ctx.bvh,
                ctx.prof,
                w[0].truncate(),
                w[1].truncate(),
                first.z,
            )
        })
    };
    (free(&lead_in) && free(&lead_out)).then_some((lead_in, lead_out))
}

/// The ramp from `h` above the closed run's level down along it at `angle`, then the run at
/// the level from where the ramp reached it round to that point; `None` when not clear.
fn ramp(
    ctx: &Ctx,
    (raw, kept): (&[ContourPoint], &[usize]),
    h: f64,
    angle: f64,
    opts: &WaterlineOptions,
) -> Option<Approach> {
    let run: Vec<ContourPoint> = kept.iter().map(|&i| raw[i]).collect();
    let feed = opts.feed_mm_per_min;
    let z = run[0].tip.z;
    let lp: Vec<DVec2> = run.iter().map(|p| p.tip.truncate()).collect();
    let mut down = Vec::new();
    crate::strategies::zlevel::ramp(&lp, z + h, z, angle.tan(), &mut down, feed);
    // Keep the ramp up to where it reaches the level; the loop goes on from there.
    let reach = down.iter().position(|p| p.tip.z <= z)?;
    down.truncate(reach + 1);
    let segs = lp.len() - 1;
    let seg = reach % segs;
    let start = run[0].tip.truncate().extend(z + h);
    let offset = 2.0 * opts.chord_tol_mm;
    let side = free_side(opts);
    let mut prev = start;
    for p in &down {
        let (a, b) = (prev.truncate(), p.tip.truncate());
        if let Some(t) = (b - a).try_normalize() {
            let n = DVec2::new(-t.y, t.x) * side * offset;
            if !link_free(
                ctx.mesh,
                ctx.bvh,
                ctx.prof,
                a + n,
                b + n,
                p.tip.z.min(prev.z),
            ) {
                return None;
            }
        }
        prev = p.tip;
    }
    let q = prev;
    let mut moves = down;
    // Round the loop from the reached segment's end back to it, then on to where it began.
    let rest = run[seg + 1..].iter().chain(&run[1..=seg]);
    let rest = rest.skip_while(|p| p.tip.truncate().distance(q.truncate()) <= 1e-9);
    moves.extend(
        rest.map(|p| {
            Pose::new(MoveKind::Cut, p.tip, DVec3::Z, feed).with_contact(p.cc, ctx.contact)
        }),
    );
    if q.truncate().distance(run[seg].tip.truncate()) > 1e-9 {
        moves.push(Pose::new(MoveKind::Cut, q, DVec3::Z, feed));
    }
    // On past where the level pass closed, by the overlap (through the contour points after
    // the segment the ramp reached).
    let eps = COLLINEAR_FRACTION * opts.chord_tol_mm;
    let here = ContourPoint { tip: q, ..run[seg] };
    let (a, b) = (raw[kept[seg]].tip, raw[kept[seg + 1]].tip);
    let along_seg = |p: DVec3| (p - a).dot(b - a);
    let next = (kept[seg] + 1..=kept[seg + 1])
        .find(|&i| along_seg(raw[i].tip) > along_seg(q) + 1e-12)
        .unwrap_or(kept[seg + 1]);
    let ahead: Vec<ContourPoint> = raw[next..].iter().chain(&raw[1..=next]).copied().collect();
    moves.extend(cuts(
        ctx,
        &overlap(here, &ahead, opts.loop_overlap_mm, eps),
        feed,
    ));
    Some(Approach {
        start,
        gap: 0.0,
        moves,
        fell_back: false,
    })
}
