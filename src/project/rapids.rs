//! Rapids above the in-process stock (issue 35 "safe heights"): one pass over a finished tool
//! path that lifts every rapid crossing material (the stock the earlier operations left) to the
//! highest stock under the tool's swept footprint plus a clearance.
//!
//! The stock is read through a height function `top(x, y)` (the highest material at a point,
//! `None` where there is none), so the pass is pure and independent of how the stock is held
//! (dexels, a height field, the raw block). A rapid that is safe is left as it is, so a path
//! with no unsafe rapid comes back unchanged (byte-identical posted programs).
//!
//! An unsafe rapid from `a` to `b` becomes three rapids: straight up from `a` to the safe
//! height, across at that height, and down to `b`. The descent ends at `b`, which the planner
//! chose (a feed height or an entry): it is not moved.

use crate::toolpath::{MoveKind, Pose, Toolpath};
use glam::DVec3;

/// What [`lift_rapids`] changed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RapidLift {
    /// Rapids found below the stock + clearance and lifted.
    pub lifted: usize,
    /// The deepest a rapid ran below the stock + clearance before the lift, mm.
    pub worst_depth_mm: f64,
    /// Rapids that came down into the stock (or within the clearance of it) at their end,
    /// now a rapid to the clearance over the stock there and a fed plunge the rest of the way.
    pub fed_down: usize,
    /// Rapids that left a cut upwards with the tool still in the stock, now a fed move up to
    /// the clearance over it and a rapid from there.
    pub fed_up: usize,
}

/// The lowest tip height at `tip`'s (x, y) where the lower surface of `cutter` (vertical)
/// clears the stock `top`, sampled every `step` mm over the disc less one `step` at its rim
/// (material touching the rim is contact at the stock's resolution, as beside a wall just
/// cut), `None` where no material lies under it.
fn entry_height(
    top: &dyn Fn(f64, f64) -> Option<f64>,
    cutter: &crate::tools::Cutter,
    tip: DVec3,
    step: f64,
) -> Option<f64> {
    let radius = (cutter.radius() - step).max(0.0);
    let mut best: Option<f64> = top(tip.x, tip.y);
    let rings = ((radius / step).ceil() as usize).clamp(1, 64);
    for r in 1..=rings {
        let rr = radius * r as f64 / rings as f64;
        let lift = cutter.height_at_radius(rr).unwrap_or(0.0);
        let n = ((std::f64::consts::TAU * rr / step).ceil() as usize).clamp(8, 512);
        for k in 0..n {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            if let Some(z) = top(tip.x + rr * t.cos(), tip.y + rr * t.sin()) {
                best = Some(best.map_or(z - lift, |b: f64| b.max(z - lift)));
            }
        }
    }
    best
}

/// The feed of the first fed pose of `rest` (its plunge or cut), for a rapid turned into a
/// plunge; the slowest feed of the path's plunges where none follows.
fn plunge_feed(rest: &[Pose]) -> f64 {
    rest.iter()
        .find(|p| p.kind == MoveKind::Plunge || p.kind == MoveKind::Cut)
        .map(|p| p.feed_mm_per_min)
        .filter(|f| f.is_finite() && *f > 0.0)
        .unwrap_or(100.0)
}

/// Highest material under a disc of radius `radius` (mm) centred at (x, y), sampled every
/// `step` mm (at least 9 points: centre, and rings), or `None` where there is none.
fn footprint_top(
    top: &dyn Fn(f64, f64) -> Option<f64>,
    x: f64,
    y: f64,
    radius: f64,
    step: f64,
) -> Option<f64> {
    let mut best: Option<f64> = top(x, y);
    let rings = ((radius / step).ceil() as usize).clamp(1, 64);
    for r in 1..=rings {
        let rr = radius * r as f64 / rings as f64;
        let n = ((std::f64::consts::TAU * rr / step).ceil() as usize).clamp(8, 512);
        for k in 0..n {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            if let Some(z) = top(x + rr * t.cos(), y + rr * t.sin()) {
                best = Some(best.map_or(z, |b: f64| b.max(z)));
            }
        }
    }
    best
}

/// The lowest a rapid from `a` to `b` runs below the stock + `clearance` under the tool's
/// footprint (mm, positive = below), and the safe height over its whole length; `None` when
/// it is clear.
fn rapid_shortfall(
    top: &dyn Fn(f64, f64) -> Option<f64>,
    a: DVec3,
    b: DVec3,
    radius: f64,
    step: f64,
    clearance: f64,
) -> Option<(f64, f64)> {
    let len = (b - a).truncate().length();
    let n = ((len / step).ceil() as usize).clamp(1, 100_000);
    let mut worst = 0.0_f64;
    let mut safe = f64::NEG_INFINITY;
    // The end point is the planner's (feed height or entry): only the samples before it count.
    for k in 0..n {
        let p = a.lerp(b, k as f64 / n as f64);
        if let Some(z) = footprint_top(top, p.x, p.y, radius, step) {
            let need = z + clearance;
            safe = safe.max(need);
            worst = worst.max(need - p.z);
        }
    }
    (worst > 1e-9).then_some((worst, safe))
}

/// Lift every rapid of a 3-axis `toolpath` (tool axis +Z) that runs below the stock `top`
/// plus `clearance` (mm) under the tool's footprint (its radius), sampled every `step` mm
/// (the stock's resolution). Returns what was changed; paths with a tilted tool axis are left
/// as they are.
pub fn lift_rapids(
    toolpath: &mut Toolpath,
    top: &dyn Fn(f64, f64) -> Option<f64>,
    clearance: f64,
    step: f64,
) -> RapidLift {
    lift_rapids_mapped(toolpath, top, clearance, step).0
}

/// [`lift_rapids`], with the index each old pose has in the changed path (empty when the path
/// is unchanged), so pose-indexed findings can follow their poses.
fn lift_rapids_mapped(
    toolpath: &mut Toolpath,
    top: &dyn Fn(f64, f64) -> Option<f64>,
    clearance: f64,
    step: f64,
) -> (RapidLift, Vec<usize>) {
    let mut out = RapidLift::default();
    if toolpath.poses.len() < 2
        || !step.is_finite()
        || step <= 0.0
        || toolpath
            .poses
            .iter()
            .any(|p| (p.axis - DVec3::Z).length() > 1e-9)
    {
        return (out, Vec::new());
    }
    let radius = toolpath.tool.cutter.radius();
    let mut poses: Vec<Pose> = Vec::with_capacity(toolpath.poses.len());
    // Old pose index → new pose index, to keep the exact segments on their poses.
    let mut map: Vec<usize> = Vec::with_capacity(toolpath.poses.len());
    for (i, pose) in toolpath.poses.iter().enumerate() {
        // A rapid along the tool axis alone (a retract up out of the cut, or the planner's
        // approach down to its feed height) runs where the tool and its shank already are or
        // are about to be: only rapids that move across are checked.
        let across =
            i > 0 && (pose.tip - toolpath.poses[i - 1].tip).truncate().length() > ACROSS_MM;
        // A rapid leaving a fed move upwards while the tool is still in the stock (the
        // material beside the cut, which the stock before the operation still holds): feed
        // up until the tool clears it by the clearance, then rapid.
        if pose.kind == MoveKind::Rapid
            && i > 0
            && toolpath.poses[i - 1].kind != MoveKind::Rapid
            && pose.tip.z > toolpath.poses[i - 1].tip.z
        {
            let prev = toolpath.poses[i - 1];
            if let Some(touch) = entry_height(top, &toolpath.tool.cutter, prev.tip, step)
                && prev.tip.z < touch
            {
                let up = (touch + clearance).min(pose.tip.z);
                let mut p = prev;
                p.kind = MoveKind::Link;
                p.tip.z = up;
                p.cc = None;
                p.contact = None;
                out.fed_up += 1;
                if up < pose.tip.z - ACROSS_MM || across {
                    poses.push(p);
                }
            }
        }
        if across && pose.kind == MoveKind::Rapid {
            let a = toolpath.poses[i - 1].tip;
            let b = pose.tip;
            if let Some((depth, safe)) = rapid_shortfall(top, a, b, radius, step, clearance) {
                out.lifted += 1;
                out.worst_depth_mm = out.worst_depth_mm.max(depth);
                let z = safe.max(a.z).max(b.z);
                for tip in [DVec3::new(a.x, a.y, z), DVec3::new(b.x, b.y, z)] {
                    let mut p = *pose;
                    p.tip = tip;
                    p.cc = None;
                    p.contact = None;
                    poses.push(p);
                }
            }
        }
        // A rapid coming down into the stock (or within the clearance of it) at its end:
        // rapid down to the clearance over the stock there, then feed the rest of the way.
        let mut end = *pose;
        if pose.kind == MoveKind::Rapid
            && let Some(from) = poses.last().map(|p| p.tip)
            && pose.tip.z < from.z
            && let Some(touch) = entry_height(top, &toolpath.tool.cutter, pose.tip, step)
            && pose.tip.z < touch + clearance
        {
            let feed_z = touch + clearance;
            out.fed_down += 1;
            if from.z > feed_z + ACROSS_MM {
                let mut stop = *pose;
                stop.tip.z = feed_z;
                stop.cc = None;
                stop.contact = None;
                poses.push(stop);
            }
            end.kind = MoveKind::Plunge;
            end.feed_mm_per_min = plunge_feed(&toolpath.poses[i..]);
        }
        map.push(poses.len());
        poses.push(end);
    }
    if out.lifted == 0 && out.fed_down == 0 && out.fed_up == 0 {
        return (out, Vec::new());
    }
    let mut exact = std::mem::take(&mut toolpath.exact);
    for seg in &mut exact {
        seg.from = map[seg.from];
        seg.to = map[seg.to];
    }
    let tool = toolpath.tool.clone();
    *toolpath = Toolpath::new(tool, poses);
    toolpath.exact = exact;
    (out, map)
}

/// The highest material of `stock`'s Z dexels at (x, y), mm (`None` outside its grid or where
/// the ray holds no material): the height function [`lift_rapids`] reads.
#[must_use]
pub fn dexel_top(stock: &crate::simulation::DexelStock, x: f64, y: f64) -> Option<f64> {
    use crate::simulation::RayAxis;
    let fam = stock.families.iter().find(|f| f.axis == RayAxis::Z)?;
    let fi = ((x - fam.origin.x) / fam.spacing).floor();
    let fj = ((y - fam.origin.y) / fam.spacing).floor();
    if !fi.is_finite() || !fj.is_finite() || fi < 0.0 || fj < 0.0 {
        return None;
    }
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let (i, j) = (fi as usize, fj as usize);
    if i >= fam.nu || j >= fam.nv {
        return None;
    }
    let hi = fam.dexels[j * fam.nu + i].intervals().last()?[1];
    Some(fam.origin.z + f64::from(hi))
}

/// Clearance kept between a rapid and the in-process stock under it, mm.
pub const STOCK_CLEARANCE_MM: f64 = 1.0;

/// A rapid moving less than this across (mm) is a move along the tool axis.
const ACROSS_MM: f64 = 1e-6;

/// [`lift_rapids`] on a computed path over the in-process stock `dexels` (its Z dexels,
/// sampled at the stock's resolution, [`STOCK_CLEARANCE_MM`] above it), with a note in
/// `diagnostics` saying how many rapids were lifted and how deep the worst ran before.
pub fn lift_rapids_over(
    toolpath: &mut Toolpath,
    diagnostics: &mut Vec<crate::diagnostics::Diagnostic>,
    dexels: &crate::simulation::DexelStock,
) -> RapidLift {
    lift_rapids_over_mapped(toolpath, diagnostics, dexels).0
}

/// [`lift_rapids_over`], with the old → new pose indices of [`lift_rapids_mapped`].
fn lift_rapids_over_mapped(
    toolpath: &mut Toolpath,
    diagnostics: &mut Vec<crate::diagnostics::Diagnostic>,
    dexels: &crate::simulation::DexelStock,
) -> (RapidLift, Vec<usize>) {
    let top = |x: f64, y: f64| dexel_top(dexels, x, y);
    let step = dexels.resolution_mm.max(0.05);
    let (r, map) = lift_rapids_mapped(toolpath, &top, STOCK_CLEARANCE_MM, step);
    if r.lifted > 0 {
        diagnostics.push(crate::diagnostics::Diagnostic::info(
            None,
            format!(
                "{} rapid(s) lifted above the in-process stock (+{STOCK_CLEARANCE_MM} mm): the \
                 deepest ran {:.3} mm below it",
                r.lifted, r.worst_depth_mm
            ),
        ));
    }
    if r.fed_up > 0 {
        diagnostics.push(crate::diagnostics::Diagnostic::info(
            None,
            format!(
                "{} retract(s) left the cut inside the in-process stock: they now feed up to \
                 {STOCK_CLEARANCE_MM} mm above it before the rapid",
                r.fed_up
            ),
        ));
    }
    if r.fed_down > 0 {
        diagnostics.push(crate::diagnostics::Diagnostic::info(
            None,
            format!(
                "{} rapid(s) came down into the in-process stock: they now stop \
                 {STOCK_CLEARANCE_MM} mm above it and feed the rest of the way",
                r.fed_down
            ),
        ));
    }
    (r, map)
}

/// An operation's path as it runs: its stored path with the rapids lifted over the stock
/// before it ([`link`]), and what the lift and the check of the fed links found.
#[derive(Clone, Debug)]
pub struct Linked {
    /// The path to post and to simulate.
    pub toolpath: Toolpath,
    /// The rapids lifted.
    pub lift: RapidLift,
    /// Fed links (G1 moves between cuts, [`MoveKind::Link`]) whose tool centre runs through
    /// the stock (more than one dexel below its top), and the deepest, mm. They are left: a
    /// fed link cuts what it meets at its feed, and lifting it would change the planner's
    /// entry into the next pass.
    pub fed_links_through_stock: usize,
    /// The deepest of those fed links below the stock's top, mm.
    pub fed_link_worst_depth_mm: f64,
    /// Notes for the operation (how many rapids were lifted, the fed links through stock).
    pub diagnostics: Vec<crate::diagnostics::Diagnostic>,
    /// The index in `toolpath` of each pose of the stored path, where the lift added poses
    /// (empty when the path is the stored one): pose-indexed findings follow it
    /// ([`Linked::pose_index`]).
    pub pose_map: Vec<usize>,
}

impl Linked {
    /// `computed` as it runs: its path replaced by the linked one, the lift's notes added to
    /// its diagnostics, and its pose-indexed findings (part hits) moved onto the linked path's
    /// poses.
    pub fn apply_to(&self, computed: &mut super::computed::Computed) {
        computed.toolpath = self.toolpath.clone();
        computed
            .diagnostics
            .extend(self.diagnostics.iter().cloned());
        for hit in &mut computed.part_hits {
            hit.pose = self.pose_index(hit.pose);
        }
    }

    /// The index in the linked path of the stored path's pose `stored` (the same index when
    /// nothing was added; the last pose for an index past the stored path's end).
    #[must_use]
    pub fn pose_index(&self, stored: usize) -> usize {
        if self.pose_map.is_empty() {
            return stored;
        }
        self.pose_map
            .get(stored)
            .or(self.pose_map.last())
            .copied()
            .unwrap_or(stored)
    }
}

/// The fed links ([`MoveKind::Link`] moves across) of `toolpath` whose centre runs more than
/// `step` (one dexel) below the stock `top` between their ends: how many, and the deepest, mm.
fn fed_links_through(
    toolpath: &Toolpath,
    top: &dyn Fn(f64, f64) -> Option<f64>,
    step: f64,
) -> (usize, f64) {
    let (mut count, mut worst) = (0, 0.0_f64);
    for w in toolpath.poses.windows(2) {
        let (a, b) = (w[0].tip, w[1].tip);
        let len = (b - a).truncate().length();
        if w[1].kind != MoveKind::Link || len <= ACROSS_MM {
            continue;
        }
        let n = ((len / step).ceil() as usize).clamp(2, 100_000);
        let deepest = (1..n)
            .filter_map(|k| {
                let p = a.lerp(b, k as f64 / n as f64);
                top(p.x, p.y).map(|z| z - p.z)
            })
            .fold(0.0_f64, f64::max);
        if deepest > step {
            count += 1;
            worst = worst.max(deepest);
        }
    }
    (count, worst)
}

/// `toolpath` linked over the stock `dexels` (the in-process stock before it, in the path's
/// frame): its rapids lifted ([`lift_rapids_over`]), its fed links through the stock counted
/// and reported. The one linking step every consumer of a stored path runs before posting or
/// simulating it (`Results::linked`, `talas job`).
#[must_use]
pub fn link(toolpath: &Toolpath, dexels: &crate::simulation::DexelStock) -> Linked {
    let mut out = toolpath.clone();
    let mut diagnostics = Vec::new();
    let (lift, pose_map) = lift_rapids_over_mapped(&mut out, &mut diagnostics, dexels);
    let top = |x: f64, y: f64| dexel_top(dexels, x, y);
    let step = dexels.resolution_mm.max(0.05);
    let (fed, fed_worst) = if out
        .poses
        .iter()
        .all(|p| (p.axis - DVec3::Z).length() <= 1e-9)
    {
        fed_links_through(&out, &top, step)
    } else {
        (0, 0.0)
    };
    if fed > 0 {
        diagnostics.push(crate::diagnostics::Diagnostic::warning(
            None,
            format!(
                "{fed} fed link(s) between passes run through the in-process stock (the deepest \
                 {fed_worst:.3} mm below its top): they cut it at the link feed"
            ),
        ));
    }
    Linked {
        toolpath: out,
        lift,
        fed_links_through_stock: fed,
        fed_link_worst_depth_mm: fed_worst,
        diagnostics,
        pose_map,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::ToolRecord;

    fn path(poses: Vec<Pose>) -> Toolpath {
        let cutter = crate::tools::Cutter::new(crate::tools::CutterKind::Flat, 6.0)
            .expect("a 6 mm flat cutter");
        Toolpath::new(
            ToolRecord {
                spec: "flat 6".into(),
                cutter,
            },
            poses,
        )
    }

    fn pose(kind: MoveKind, x: f64, y: f64, z: f64) -> Pose {
        Pose::new(kind, DVec3::new(x, y, z), DVec3::Z, 1000.0)
    }

    /// A wall of stock 10 mm high at 20 ≤ x ≤ 22: a rapid at z = 5 across it is lifted to
    /// 10 + clearance; one at z = 12 is left alone (byte-identical path).
    #[test]
    fn lifts_only_the_rapid_that_crosses_the_wall() {
        let top = |x: f64, _y: f64| ((20.0..=22.0).contains(&x)).then_some(10.0);
        let mut low = path(vec![
            pose(MoveKind::Cut, 0.0, 0.0, 5.0),
            pose(MoveKind::Rapid, 40.0, 0.0, 5.0),
        ]);
        let r = lift_rapids(&mut low, &top, 1.0, 0.25);
        assert_eq!(r.lifted, 1);
        assert!((r.worst_depth_mm - 6.0).abs() < 1e-9, "{r:?}");
        assert_eq!(low.poses.len(), 4);
        assert!((low.poses[1].tip.z - 11.0).abs() < 1e-9);
        assert!((low.poses[2].tip - DVec3::new(40.0, 0.0, 11.0)).length() < 1e-9);
        assert_eq!(low.poses[3].tip, DVec3::new(40.0, 0.0, 5.0));
        let high = path(vec![
            pose(MoveKind::Cut, 0.0, 0.0, 12.0),
            pose(MoveKind::Rapid, 40.0, 0.0, 12.0),
        ]);
        let mut same = high.clone();
        assert_eq!(
            lift_rapids(&mut same, &top, 1.0, 0.25),
            RapidLift::default()
        );
        assert_eq!(same, high);
    }

    /// The old → new pose map follows the lifted rapid: the stored path's poses 0 and 1 are
    /// the linked path's 0 and 3 (two lift poses between), each with its own tip.
    #[test]
    fn the_pose_map_follows_the_inserted_lift() {
        let top = |x: f64, _y: f64| ((20.0..=22.0).contains(&x)).then_some(10.0);
        let stored = path(vec![
            pose(MoveKind::Cut, 0.0, 0.0, 5.0),
            pose(MoveKind::Rapid, 40.0, 0.0, 5.0),
            pose(MoveKind::Cut, 41.0, 0.0, 5.0),
        ]);
        let mut linked = stored.clone();
        let (r, map) = lift_rapids_mapped(&mut linked, &top, 1.0, 0.25);
        assert_eq!(r.lifted, 1);
        assert_eq!(map, vec![0, 3, 4]);
        for (old, &new) in map.iter().enumerate() {
            assert_eq!(stored.poses[old].tip, linked.poses[new].tip);
        }
        let l = Linked {
            toolpath: linked,
            lift: r,
            fed_links_through_stock: 0,
            fed_link_worst_depth_mm: 0.0,
            diagnostics: Vec::new(),
            pose_map: map,
        };
        assert_eq!(
            (l.pose_index(1), l.pose_index(2), l.pose_index(9)),
            (3, 4, 4)
        );
        let mut same = stored.clone();
        let high = |_x: f64, _y: f64| Some(-10.0);
        assert!(lift_rapids_mapped(&mut same, &high, 1.0, 0.25).1.is_empty());
    }

    /// The footprint counts: a rapid passing 2.5 mm beside a post (tool radius 3) is lifted.
    #[test]
    fn the_tool_footprint_counts() {
        let top = |x: f64, y: f64| (x.hypot(y - 2.5) < 0.5).then_some(10.0);
        let mut p = path(vec![
            pose(MoveKind::Cut, -10.0, 0.0, 5.0),
            pose(MoveKind::Rapid, 10.0, 0.0, 5.0),
        ]);
        assert_eq!(lift_rapids(&mut p, &top, 1.0, 0.1).lifted, 1);
    }

    /// A retract straight up out of a cut beside the wall, and the approach straight down to
    /// the next feed height, run along the tool axis: left alone (the footprint at the cut
    /// touches the wall, which would otherwise count).
    #[test]
    fn moves_along_the_axis_are_left_alone() {
        let top = |x: f64, _y: f64| ((20.0..=22.0).contains(&x)).then_some(10.0);
        let poses = vec![
            pose(MoveKind::Cut, 17.0, 0.0, 2.0),
            pose(MoveKind::Rapid, 17.0, 0.0, 15.0),
            pose(MoveKind::Rapid, 30.0, 0.0, 15.0),
            pose(MoveKind::Rapid, 30.0, 0.0, 1.0),
        ];
        let mut p = path(poses.clone());
        assert_eq!(lift_rapids(&mut p, &top, 1.0, 0.1), RapidLift::default());
        assert_eq!(p.poses, poses);
    }

    /// A rapid coming down into the wall's material stops 1 mm above it and feeds the rest.
    #[test]
    fn a_rapid_down_into_the_stock_feeds_from_above_it() {
        let top = |x: f64, _y: f64| ((20.0..=22.0).contains(&x)).then_some(10.0);
        let mut p = path(vec![
            pose(MoveKind::Rapid, 21.0, 0.0, 15.0),
            pose(MoveKind::Rapid, 21.0, 0.0, 5.0),
            pose(MoveKind::Cut, 30.0, 0.0, 5.0),
        ]);
        let r = lift_rapids(&mut p, &top, 1.0, 0.1);
        assert_eq!((r.lifted, r.fed_down), (0, 1), "{r:?}");
        let kinds: Vec<_> = p.poses.iter().map(|q| (q.kind, q.tip.z)).collect();
        assert_eq!(
            kinds,
            vec![
                (MoveKind::Rapid, 15.0),
                (MoveKind::Rapid, 11.0),
                (MoveKind::Plunge, 5.0),
                (MoveKind::Cut, 5.0)
            ]
        );
        assert!((p.poses[2].feed_mm_per_min - 1000.0).abs() < 1e-12);
    }
}
