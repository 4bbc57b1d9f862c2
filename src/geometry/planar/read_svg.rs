//! SVG path data to a profile: segments through `svgtypes`, y mirrored to point up, circular
//! arcs kept, Béziers flattened within a tolerance, elliptical arcs refused.

use glam::DVec2;
use svgtypes::{PathParser, PathSegment};

use super::{Profile, ProfileError, Vertex};

struct Builder<'a> {
    file: &'a str,
    line: usize,
    vertices: Vec<Vertex>,
    closed: bool,
    /// Current point in SVG coordinates (y down).
    cur: DVec2,
    /// Last control point of a cubic (for S) and a quadratic (for T).
    last_cubic: Option<DVec2>,
    last_quad: Option<DVec2>,
    tolerance: f64,
}

impl Builder<'_> {
    fn err(&self, seg: usize, msg: impl Into<String>) -> ProfileError {
        ProfileError::new(self.file, format!("line {}, segment {seg}", self.line), msg)
    }

    /// Appends a point given in SVG coordinates, joined by an element of `bulge` (y-up sense).
    fn to(&mut self, p: DVec2, bulge: f64) {
        let q = DVec2::new(p.x, -p.y);
        if let Some(last) = self.vertices.last()
            && last.pos() == q
        {
            self.cur = p;
            return;
        }
        super::read::push_to_pub(&mut self.vertices, q, bulge);
        self.cur = p;
    }

    fn arc(
        &mut self,
        seg: usize,
        r: (f64, f64),
        large: bool,
        sweep: bool,
        p: DVec2,
    ) -> Result<(), ProfileError> {
        let (rx, ry) = (r.0.abs(), r.1.abs());
        if (rx - ry).abs() > 1e-9 * rx.max(ry) {
            return Err(self.err(
                seg,
                format!("elliptical arc (rx {rx}, ry {ry}) is not supported; only circular arcs"),
            ));
        }
        let chord = (p - self.cur).length();
        if chord == 0.0 {
            return Ok(());
        }
        if rx == 0.0 {
            self.to(p, 0.0);
            return Ok(());
        }
        // SVG scales a radius that is too small up to half the chord.
        let r = rx.max(chord / 2.0);
        let minor = 2.0 * (chord / (2.0 * r)).clamp(-1.0, 1.0).asin();
        let mag = if large {
            std::f64::consts::TAU - minor
        } else {
            minor
        };
        // The sweep flag 1 turns toward increasing angle in SVG's y-down frame, which is
        // clockwise once y is mirrored to point up.
        let signed = if sweep { -mag } else { mag };
        self.to(p, (signed / 4.0).tan());
        Ok(())
    }

    fn flatten(&mut self, ctrl: &[DVec2]) {
        if self.flatten_straight(ctrl) {
            return;
        }
        // Uniform steps bound the chord error by h²·max|B''|/8 with |B''| ≤ n(n−1)·max|Δ²P|.
        let deg = ctrl.len() - 1;
        let mut second: f64 = 0.0;
        for w in ctrl.windows(3) {
            if let [a, b, c] = w {
                second = second.max((*a - 2.0 * *b + *c).length());
            }
        }
        let m = (deg * (deg - 1)) as f64 * second;
        let n = ((m / (8.0 * self.tolerance)).sqrt().ceil() as usize).clamp(1, 100_000);
        for k in 1..=n {
            let t = k as f64 / n as f64;
            let p = de_casteljau(ctrl, t);
            self.to(p, 0.0);
        }
    }
}

impl Builder<'_> {
    /// A degenerate Bézier, whose control points all lie within a quarter of the tolerance of
    /// one line, is that line walked back and forth: its points at the ends and where its
    /// motion along the line turns back (the roots of the derivative of the projection) are
    /// within half the tolerance of the curve, between them the curve is monotone along the
    /// line. A 3 KB SVG of 200 such curves spanning 2 m flattened to 346 000 points with
    /// uniform steps and stalled `talas profile` (issue 36); now 3 points each at most.
    fn flatten_straight(&mut self, ctrl: &[DVec2]) -> bool {
        let (Some(&first), Some(&last)) = (ctrl.first(), ctrl.last()) else {
            return true;
        };
        // The line through the two control points farthest apart.
        let mut axis = (first, last);
        let mut widest = 0.0;
        for (k, a) in ctrl.iter().enumerate() {
            for b in ctrl.iter().skip(k + 1) {
                let d = (*b - *a).length_squared();
                if d > widest {
                    widest = d;
                    axis = (*a, *b);
                }
            }
        }
        if widest == 0.0 {
            self.to(last, 0.0);
            return true;
        }
        let dir = (axis.1 - axis.0).normalize();
        let off = ctrl
            .iter()
            .map(|p| (*p - axis.0).perp_dot(dir).abs())
            .fold(0.0_f64, f64::max);
        if off > 0.25 * self.tolerance {
            return false;
        }
        // The projection s(t) = Σ B_k(t) s_k; its derivative is a Bézier of degree n − 1 in
        // the differences, a polynomial a t² + b t + c (cubic) or b t + c (quadratic).
        let s: Vec<f64> = ctrl.iter().map(|p| (*p - axis.0).dot(dir)).collect();
        let mut turns: Vec<f64> = Vec::new();
        match s.as_slice() {
            [s0, s1, s2] => {
                let (d0, d1) = (s1 - s0, s2 - s1);
                if d0 - d1 != 0.0 {
                    turns.push(d0 / (d0 - d1));
                }
            }
            [s0, s1, s2, s3] => {
                let (d0, d1, d2) = (s1 - s0, s2 - s1, s3 - s2);
                let a = d0 - 2.0 * d1 + d2;
                let b = 2.0 * (d1 - d0);
                let c = d0;
                if a.abs() > 1e-15 * (d0.abs() + d1.abs() + d2.abs()) {
                    let disc = b * b - 4.0 * a * c;
                    if disc >= 0.0 {
                        let r = disc.sqrt();
                        turns.push((-b - r) / (2.0 * a));
                        turns.push((-b + r) / (2.0 * a));
                    }
                } else if b != 0.0 {
                    turns.push(-c / b);
                }
            }
            _ => return false,
        }
        turns.retain(|t| *t > 0.0 && *t < 1.0);
        turns.sort_by(f64::total_cmp);
        for t in turns {
            self.to(de_casteljau(ctrl, t), 0.0);
        }
        self.to(last, 0.0);
        true
    }
}

fn de_casteljau(ctrl: &[DVec2], t: f64) -> DVec2 {
    let mut pts = ctrl.to_vec();
    while pts.len() > 1 {
        pts = pts.windows(2).map(|w| w[0].lerp(w[1], t)).collect();
    }
    pts.first().copied().unwrap_or(DVec2::ZERO)
}

/// Parses the path data `d` (from the `<path>` on `line` of `file`).
pub(super) fn parse_path(
    d: &str,
    file: &str,
    line: usize,
    tolerance: f64,
) -> Result<Profile, ProfileError> {
    let mut b = Builder {
        file,
        line,
        vertices: Vec::new(),
        closed: false,
        cur: DVec2::ZERO,
        last_cubic: None,
        last_quad: None,
        tolerance,
    };
    for (k, seg) in PathParser::from(d).enumerate() {
        let n = k + 1;
        let seg = seg.map_err(|e| b.err(n, e.to_string()))?;
        if b.vertices.len() > super::MAX_PROFILE_POINTS {
            return Err(b.err(
                n,
                format!(
                    "the curves flatten to more than {} points; raise --tolerance",
                    super::MAX_PROFILE_POINTS
                ),
            ));
        }
        if b.closed {
            return Err(b.err(n, "more than one subpath (one contour per file)"));
        }
        let abs_pt = |abs: bool, x: f64, y: f64, cur: DVec2| {
            if abs {
                DVec2::new(x, y)
            } else {
                cur + DVec2::new(x, y)
            }
        };
        let (cubic, quad) = (b.last_cubic.take(), b.last_quad.take());
        match seg {
            PathSegment::MoveTo { abs, x, y } => {
                if !b.vertices.is_empty() {
                    return Err(b.err(n, "more than one subpath (one contour per file)"));
                }
                b.to(abs_pt(abs, x, y, b.cur), 0.0);
            }
            PathSegment::LineTo { abs, x, y } => b.to(abs_pt(abs, x, y, b.cur), 0.0),
            PathSegment::HorizontalLineTo { abs, x } => {
                let p = DVec2::new(if abs { x } else { b.cur.x + x }, b.cur.y);
                b.to(p, 0.0);
            }
            PathSegment::VerticalLineTo { abs, y } => {
                let p = DVec2::new(b.cur.x, if abs { y } else { b.cur.y + y });
                b.to(p, 0.0);
            }
            PathSegment::CurveTo {
                abs,
                x1,
                y1,
                x2,
                y2,
                x,
                y,
            } => {
                let c = b.cur;
                let (p1, p2, p) = (
                    abs_pt(abs, x1, y1, c),
                    abs_pt(abs, x2, y2, c),
                    abs_pt(abs, x, y, c),
                );
                b.flatten(&[c, p1, p2, p]);
                b.last_cubic = Some(p2);
            }
            PathSegment::SmoothCurveTo { abs, x2, y2, x, y } => {
                let c = b.cur;
                let p1 = cubic.map_or(c, |q| 2.0 * c - q);
                let (p2, p) = (abs_pt(abs, x2, y2, c), abs_pt(abs, x, y, c));
                b.flatten(&[c, p1, p2, p]);
                b.last_cubic = Some(p2);
            }
            PathSegment::Quadratic { abs, x1, y1, x, y } => {
                let c = b.cur;
                let (p1, p) = (abs_pt(abs, x1, y1, c), abs_pt(abs, x, y, c));
                b.flatten(&[c, p1, p]);
                b.last_quad = Some(p1);
            }
            PathSegment::SmoothQuadratic { abs, x, y } => {
                let c = b.cur;
                let p1 = quad.map_or(c, |q| 2.0 * c - q);
                let p = abs_pt(abs, x, y, c);
                b.flatten(&[c, p1, p]);
                b.last_quad = Some(p1);
            }
            PathSegment::EllipticalArc {
                abs,
                rx,
                ry,
                x_axis_rotation: _,
                large_arc,
                sweep,
                x,
                y,
            } => {
                let p = abs_pt(abs, x, y, b.cur);
                b.arc(n, (rx, ry), large_arc, sweep, p)?;
            }
            PathSegment::ClosePath { .. } => {
                if let (Some(first), Some(last)) =
                    (b.vertices.first().copied(), b.vertices.last().copied())
                    && first.pos() == last.pos()
                    && b.vertices.len() > 1
                {
                    b.vertices.pop();
                }
                b.closed = true;
            }
        }
    }
    if !b.closed {
        b.closed = super::read::close_if_repeated_pub(&mut b.vertices);
    }
    Ok(Profile {
        vertices: b.vertices,
        closed: b.closed,
    })
}
