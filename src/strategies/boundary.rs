//! Boundaries of 3-axis finishing: a planned tool path is limited to a region of the XY plane
//! or of the part, the cutting moves outside it are removed and the pieces left are joined by
//! retract, rapid and plunge moves at the path's own clearance height.
//!
//! A region is a drawn polygon (even-odd rule, any number of vertices), the part's silhouette
//! (the points a vertical line through which meets the mesh) or a set of selected faces (given
//! as the mesh triangles they were tessellated into). The rule says which point of a pose must
//! lie in the region:
//! - **tool centre**: the tool tip's XY position; for selected faces, the first triangle a
//!   vertical line down through the tip meets must be selected;
//! - **contact point**: where the cutter touches the part — the pose's recorded contact when the
//!   planner gave one, else for a ball end mill the mesh point nearest the ball's centre (exact
//!   for a ball); for faces, the contact's triangle must be selected.
//!
//! Each cutting segment is sampled at most `probe_step_mm` apart, and every change of
//! inside/outside is located by bisection to 1e-9 of the segment, so a cut ends on the
//! boundary itself. Between two poses the tip is the straight segment; the contact of an
//! interpolated pose is recomputed (ball) or taken on the chord between the two contacts.

use glam::{DVec2, DVec3};

use crate::geometry::bvh::MeshBvh;
use crate::toolpath::{MoveKind, Pose, Toolpath};
use crate::tools::CutterKind;

/// The region a path is limited to.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Region {
    /// A closed polygon in XY, mm (the last vertex joins the first).
    Polygon(Vec<[f64; 2]>),
    /// The part's outline seen from above.
    Silhouette,
    /// Selected faces, as indices of the mesh triangles they cover.
    Faces(Vec<usize>),
}

/// Which point of the cutter must lie in the region.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BoundaryRule {
    /// The tool tip's (centre's) XY position.
    #[default]
    ToolCentre,
    /// The cutter contact point on the part.
    Contact,
}

/// A region and its rule.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Boundary {
    /// Where the path may cut.
    pub region: Region,
    /// Which point of the cutter is tested.
    #[serde(default)]
    pub rule: BoundaryRule,
}

/// Counts of [`limit`]'s work.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LimitReport {
    /// Cutting pieces kept.
    pub pieces: usize,
    /// Cutting poses of the input whose point lay outside the region.
    pub removed: usize,
}

/// Largest distance between two probes of a cutting segment, mm.
const PROBE_STEP_MM: f64 = 0.25;

impl Boundary {
    /// Parse the command line's text: `silhouette`, `faces:F,F,...` (face numbers), or a
    /// polygon `X,Y;X,Y;X,Y[;...]` in mm.
    ///
    /// # Errors
    /// A message naming the vertex that is not two finite numbers, or a polygon of fewer than
    /// three vertices or no area.
    pub fn parse(text: &str, rule: BoundaryRule) -> Result<Self, String> {
        let t = text.trim();
        if t.eq_ignore_ascii_case("silhouette") {
            return Ok(Self {
                region: Region::Silhouette,
                rule,
            });
        }
        if let Some(list) = t.strip_prefix("faces:") {
            let mut faces = Vec::new();
            for v in list.split(',') {
                let f = v
                    .trim()
                    .parse::<usize>()
                    .map_err(|_| format!("boundary face '{}' is not a face number", v.trim()))?;
                faces.push(f);
            }
            let b = Self {
                region: Region::Faces(faces),
                rule,
            };
            b.validate()?;
            return Ok(b);
        }
        let mut poly = Vec::new();
        for (k, v) in t.split(';').enumerate() {
            let xy: Vec<&str> = v.split(',').map(str::trim).collect();
            let parsed: Vec<f64> = xy.iter().filter_map(|s| s.parse::<f64>().ok()).collect();
            if xy.len() != 2 || parsed.len() != 2 || parsed.iter().any(|x| !x.is_finite()) {
                return Err(format!(
                    "boundary vertex {} '{}' is not X,Y in mm (polygon X,Y;X,Y;X,Y or 'silhouette')",
                    k + 1,
                    v.trim()
                ));
            }
            poly.push([parsed[0], parsed[1]]);
        }
        let b = Self {
            region: Region::Polygon(poly),
            rule,
        };
        b.validate()?;
        Ok(b)
    }

    /// Check a polygon has at least three vertices and an area.
    ///
    /// # Errors
    /// The reason the region cannot limit a path.
    pub fn validate(&self) -> Result<(), String> {
        match &self.region {
            Region::Polygon(p) => {
                if p.len() < 3 {
                    return Err(format!(
                        "a boundary polygon needs at least 3 vertices, got {}",
                        p.len()
                    ));
                }
                if p.iter().flatten().any(|x| !x.is_finite()) {
                    return Err("a boundary vertex is not a finite number".into());
                }
                let area: f64 = (0..p.len())
                    .map(|i| {
                        let (a, b) = (p[i], p[(i + 1) % p.len()]);
                        a[0] * b[1] - b[0] * a[1]
                    })
                    .sum();
                if area.abs() < 1e-12 {
                    return Err("the boundary polygon has no area".into());
                }
                Ok(())
            }
            Region::Faces(f) if f.is_empty() => {
                Err("no faces are selected for the boundary".into())
            }
            _ => Ok(()),
        }
    }
}

/// A closed loop from CSV text: one vertex `X,Y` (mm) a line (`;`, tab or spaces also
/// separate), blank lines and lines starting with `#` skipped, a first line of column names
/// allowed.
///
/// # Errors
/// The line (1-based) that is not two finite numbers, or a loop of fewer than three vertices.
pub fn polygon_from_csv(text: &str) -> Result<Vec<[f64; 2]>, String> {
    let mut poly = Vec::new();
    let mut header = false;
    for (k, line) in text.lines().enumerate() {
        let l = line.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let parts: Vec<&str> = l
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|p| !p.is_empty())
            .collect();
        let xy: Vec<f64> = parts.iter().filter_map(|p| p.parse::<f64>().ok()).collect();
        if parts.len() == 2 && xy.len() == 2 && xy.iter().all(|v| v.is_finite()) {
            poly.push([xy[0], xy[1]]);
        } else if poly.is_empty() && xy.is_empty() && !header {
            header = true;
        } else {
            return Err(format!("line {}: '{l}' is not X,Y in mm", k + 1));
        }
    }
    if poly.len() < 3 {
        return Err(format!(
            "a boundary loop needs at least 3 vertices, got {}",
            poly.len()
        ));
    }
    Ok(poly)
}

/// The first closed loop of a DXF file's ENTITIES: an `LWPOLYLINE` (its group 10/20 pairs) or
/// a `POLYLINE` (its `VERTEX` entities), in mm, with straight edges.
///
/// # Errors
/// The line (1-based) of a group code or coordinate that is not a number or of an arc segment
/// (a non-zero bulge, group 42), or no loop of at least three vertices.
pub fn polygon_from_dxf(text: &str) -> Result<Vec<[f64; 2]>, String> {
    let lines: Vec<&str> = text.lines().map(str::trim).collect();
    let mut poly: Vec<[f64; 2]> = Vec::new();
    let (mut started, mut entity) = (false, "");
    let mut x = None;
    for k in (0..lines.len().saturating_sub(1)).step_by(2) {
        let code: i32 = lines[k]
            .parse()
            .map_err(|_| format!("line {}: group code '{}' is not a number", k + 1, lines[k]))?;
        let value = lines[k + 1];
        let number = || {
            value
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("line {}: '{value}' is not a number", k + 2))
        };
        match code {
            0 => {
                let vertex = value == "VERTEX" && matches!(entity, "POLYLINE" | "VERTEX");
                if started && !vertex {
                    break;
                }
                entity = value;
                started |= matches!(value, "LWPOLYLINE" | "POLYLINE");
            }
            10 if matches!(entity, "LWPOLYLINE" | "VERTEX") => x = Some(number()?),
            20 if matches!(entity, "LWPOLYLINE" | "VERTEX") => {
                if let Some(px) = x.take() {
                    poly.push([px, number()?]);
                }
            }
            42 if matches!(entity, "LWPOLYLINE" | "VERTEX") && number()? != 0.0 => {
                return Err(format!(
                    "line {}: an arc segment (bulge {value}) is not supported: give the outline \
                     as straight segments",
                    k + 2
                ));
            }
            _ => {}
        }
    }
    if poly.len() < 3 {
        return Err(format!(
            "no LWPOLYLINE or POLYLINE of at least 3 vertices (found {})",
            poly.len()
        ));
    }
    Ok(poly)
}

/// Whether `p` lies inside the polygon (even-odd rule).
#[must_use]
pub fn in_polygon(poly: &[[f64; 2]], p: DVec2) -> bool {
    let mut inside = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + n - 1) % n]);
        if (a[1] > p.y) != (b[1] > p.y) {
            let x = a[0] + (p.y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// The tests of one path against one boundary.
struct Tester<'a> {
    bvh: &'a MeshBvh,
    boundary: &'a Boundary,
    ball_radius: Option<f64>,
    top: f64,
}

impl Tester<'_> {
    /// Whether the pose between `a` and `b` at parameter `t` lies in the region.
    fn inside(&self, a: &Pose, b: &Pose, t: f64) -> Result<bool, String> {
        let tip = a.tip.lerp(b.tip, t);
        match self.boundary.rule {
            BoundaryRule::ToolCentre => Ok(self.centre_in(tip)),
            BoundaryRule::Contact => {
                let (c, tri) = self.contact(a, b, t, tip)?;
                Ok(match &self.boundary.region {
                    Region::Polygon(p) => in_polygon(p, c.truncate()),
                    Region::Silhouette => true,
                    Region::Faces(f) => tri.is_some_and(|i| f.binary_search(&i).is_ok()),
                })
            }
        }
    }

    fn centre_in(&self, tip: DVec3) -> bool {
        match &self.boundary.region {
            Region::Polygon(p) => in_polygon(p, tip.truncate()),
            Region::Silhouette | Region::Faces(_) => {
                let from = tip.truncate().extend(self.top + 1.0);
                match self.bvh.ray_cast(from, DVec3::NEG_Z, f64::INFINITY) {
                    None => false,
                    Some(hit) => match &self.boundary.region {
                        Region::Faces(f) => f.binary_search(&hit.triangle).is_ok(),
                        _ => true,
                    },
                }
            }
        }
    }

    /// The contact point (and its triangle when found on the mesh) of the interpolated pose.
    fn contact(
        &self,
        a: &Pose,
        b: &Pose,
        t: f64,
        tip: DVec3,
    ) -> Result<(DVec3, Option<usize>), String> {
        if let Some(r) = self.ball_radius {
            let centre = tip + r * a.axis.lerp(b.axis, t).normalize_or(DVec3::Z);
            let hit = self
                .bvh
                .closest_point(centre)
                .ok_or("a pose of the path is not a finite point")?;
            return Ok((hit.point, Some(hit.triangle)));
        }
        match (a.cc, b.cc) {
            (Some(p), Some(q)) => {
                let c = p.lerp(q, t);
                let tri = self.bvh.closest_point(c).map(|h| h.triangle);
                Ok((c, tri))
            }
            _ => Err(
                "the contact-point rule needs the contact points: this path has none \
                      for its cutter (use a ball end mill or the tool-centre rule)"
                    .into(),
            ),
        }
    }

    /// The parameters in (0, 1) where the segment from `a` to `b` enters or leaves the region,
    /// and whether it starts inside.
    fn crossings(&self, a: &Pose, b: &Pose) -> Result<(bool, Vec<f64>), String> {
        let len = a.tip.distance(b.tip);
        let n = ((len / PROBE_STEP_MM).ceil() as usize).clamp(1, 100_000);
        let first = self.inside(a, b, 0.0)?;
        let mut out = Vec::new();
        let (mut t0, mut s0) = (0.0, first);
        for k in 1..=n {
            let t1 = k as f64 / n as f64;
            let s1 = self.inside(a, b, t1)?;
            if s1 != s0 {
                let (mut lo, mut hi) = (t0, t1);
                while hi - lo > 1e-9 {
                    let m = 0.5 * (lo + hi);
                    if self.inside(a, b, m)? == s0 {
                        lo = m;
                    } else {
                        hi = m;
                    }
                }
                out.push(if s0 { lo } else { hi });
            }
            (t0, s0) = (t1, s1);
        }
        Ok((first, out))
    }
}

/// Limit `path` (planned on the mesh of `bvh`) to `boundary`: the cutting moves outside are
/// removed, cuts end on the boundary, and the pieces are joined by a retract to the path's
/// highest height, a rapid and a plunge.
///
/// # Errors
/// The boundary's own error, or the contact rule on a path without contact points.
pub fn limit(
    path: &Toolpath,
    bvh: &MeshBvh,
    boundary: &Boundary,
) -> Result<(Toolpath, LimitReport), String> {
    boundary.validate()?;
    let mut boundary = boundary.clone();
    if let Region::Faces(f) = &mut boundary.region {
        f.sort_unstable();
        f.dedup();
    }
    let cutter = &path.tool.cutter;
    let tester = Tester {
        bvh,
        boundary: &boundary,
        ball_radius: (cutter.kind == CutterKind::Ball).then(|| cutter.radius()),
        top: bvh.bbox().max.z,
    };
    let clear = path
        .poses
        .iter()
        .map(|p| p.tip.z)
        .fold(tester.top + 1.0, f64::max);
    let cut_feed = path
        .poses
        .iter()
        .find(|p| p.kind == MoveKind::Cut)
        .map_or(1000.0, |p| p.feed_mm_per_min);
    let plunge_feed = path
        .poses
        .iter()
        .find(|p| p.kind == MoveKind::Plunge)
        .map_or(0.3 * cut_feed, |p| p.feed_mm_per_min);
    let mut pieces: Vec<Vec<Pose>> = Vec::new();
    let mut report = LimitReport::default();
    let mut open = false;
    for (i, b) in path.poses.iter().enumerate() {
        if b.kind != MoveKind::Cut || i == 0 {
            open = false;
            continue;
        }
        let a = &path.poses[i - 1];
        let (start_in, cross) = tester.crossings(a, b)?;
        let end_in = start_in ^ (cross.len() % 2 == 1);
        if !end_in {
            report.removed += 1;
        }
        let mut inside = start_in;
        let mut ts = vec![0.0];
        ts.extend(&cross);
        ts.push(1.0);
        for w in ts.windows(2) {
            if inside {
                let p0 = interpolate(a, b, w[0]);
                let p1 = interpolate(a, b, w[1]);
                if !(open && w[0] == 0.0) {
                    pieces.push(vec![Pose {
                        kind: MoveKind::Cut,
                        ..p0
                    }]);
                }
                if let Some(piece) = pieces.last_mut() {
                    piece.push(p1);
                }
            }
            inside = !inside;
        }
        open = end_in;
    }
    report.pieces = pieces.len();
    let mut poses = Vec::new();
    for piece in &pieces {
        let (first, last) = (piece[0], piece[piece.len() - 1]);
        poses.push(Pose::new(
            MoveKind::Rapid,
            first.tip.truncate().extend(clear),
            first.axis,
            cut_feed,
        ));
        poses.push(Pose {
            kind: MoveKind::Plunge,
            feed_mm_per_min: plunge_feed,
            ..first
        });
        poses.extend(piece[1..].iter().copied());
        poses.push(Pose::new(
            MoveKind::Rapid,
            last.tip.truncate().extend(clear),
            last.axis,
            cut_feed,
        ));
    }
    Ok((Toolpath::new(path.tool.clone(), poses), report))
}

/// The pose at parameter `t` between `a` and `b` (a cut to `b`'s feed).
fn interpolate(a: &Pose, b: &Pose, t: f64) -> Pose {
    if t >= 1.0 {
        return *b;
    }
    Pose {
        tip: a.tip.lerp(b.tip, t),
        axis: a.axis.lerp(b.axis, t).normalize_or(b.axis),
        kind: MoveKind::Cut,
        cc: match (a.cc, b.cc) {
            (Some(p), Some(q)) => Some(p.lerp(q, t)),
            _ => None,
        },
        feed_mm_per_min: b.feed_mm_per_min,
        scallop_mm: b.scallop_mm,
        contact: b.contact,
    }
}

#[cfg(test)]
mod tests {
    use super::polygon_from_dxf;

    const SQUARE: &str = "0\nLWPOLYLINE\n90\n4\n10\n0\n20\n0\n10\n10\n20\n0\n42\nBULGE\n10\n10\n20\n10\n10\n0\n20\n10\n0\nENDSEC\n";

    #[test]
    fn a_dxf_outline_with_an_arc_is_refused_naming_the_line() {
        let straight = SQUARE.replace("42\nBULGE\n", "42\n0\n");
        assert_eq!(
            polygon_from_dxf(&straight).expect("straight outline"),
            vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]
        );
        let arc = SQUARE.replace("BULGE", "0.5");
        let e = polygon_from_dxf(&arc).expect_err("an arc");
        assert!(e.starts_with("line 14: an arc segment (bulge 0.5)"), "{e}");
    }
}
