//! One face to finish: its carrier surface, the parameter region to cover (a rectangle, or a
//! face's trimmed region inside the rectangle that bounds it) and the side the tool comes from;
//! local frames, curvature on the tool side and marching along the surface.

use glam::{DVec2, DVec3};

use super::PlanError;
use crate::geometry::brep::{Face, Part};
use crate::geometry::diffgeom::SurfaceDerivs;
use crate::geometry::surface::{ParamRect, SurfaceGeom};
use crate::geometry::trim::TrimRegion;

/// A face patch: a surface, a finite parameter rectangle, optionally the trimmed region inside
/// it, and the tool side (+1: the tool is on the `S_u × S_v` side, −1: the opposite side).
#[derive(Clone, Copy, Debug)]
pub struct FacePatch<'a> {
    /// The carrier surface.
    pub surface: &'a SurfaceGeom,
    /// The parameter rectangle to machine (finite): the whole patch, or the bounds of `region`.
    pub domain: ParamRect,
    /// +1 or −1: which side of `S_u × S_v` the tool is on.
    pub side: f64,
    /// The face's trimmed region (`None`: the whole rectangle).
    pub region: Option<&'a TrimRegion>,
}

/// Point, tool-side unit normal and derivatives at a parameter point.
#[derive(Clone, Copy, Debug)]
pub struct LocalFrame {
    /// Parameters.
    pub uv: DVec2,
    /// Surface point, mm.
    pub p: DVec3,
    /// Unit normal on the tool side.
    pub n: DVec3,
    /// Derivatives.
    pub d: SurfaceDerivs,
}

/// Where a march along the surface ended.
#[derive(Clone, Copy, Debug)]
pub struct March {
    /// End parameters (inside the domain).
    pub uv: DVec2,
    /// Arc length travelled, mm.
    pub travelled: f64,
    /// True when the march stopped at the domain boundary.
    pub hit_boundary: bool,
}

impl<'a> FacePatch<'a> {
    /// A patch over `domain` of `surface`, tool on `side` (+1/−1).
    ///
    /// # Errors
    /// [`PlanError::Face`] when the domain is not a finite, non-empty rectangle.
    pub fn new(surface: &'a SurfaceGeom, domain: ParamRect, side: f64) -> Result<Self, PlanError> {
        let ok = domain.u.is_finite()
            && domain.v.is_finite()
            && !domain.u.is_empty()
            && !domain.v.is_empty();
        if !ok {
            return Err(PlanError::Face(format!(
                "the parameter domain u {:?}, v {:?} is not a finite rectangle",
                (domain.u.t0, domain.u.t1),
                (domain.v.t0, domain.v.t1)
            )));
        }
        Ok(Self {
            surface,
            domain,
            side: if side < 0.0 { -1.0 } else { 1.0 },
            region: None,
        })
    }

    /// The patch of face `index` of `part` inside its trimmed `region` (from
    /// [`TrimRegion::of_face`]). The tool side is the material's outside: the face normal
    /// (`S_u × S_v`, reversed for a `.F.` face) when the face bounds a solid (a closed shell);
    /// for a face of an open shell, which has no material side, the side whose normal points up
    /// (+z) on average over the region.
    ///
    /// # Errors
    /// [`PlanError::Face`] for a missing face or one without a defined normal in its region.
    pub fn trimmed(
        part: &'a Part,
        index: usize,
        region: &'a TrimRegion,
    ) -> Result<Self, PlanError> {
        let face = part.faces.get(index).ok_or_else(|| {
            PlanError::Face(format!(
                "no face {index} (the part has {})",
                part.faces.len()
            ))
        })?;
        let mut patch = Self::new(&face.surface, region.bounds(), 1.0)?;
        patch.region = Some(region);
        let solid = part
            .shells
            .iter()
            .any(|s| s.closed && s.faces.contains(&index));
        if solid {
            patch.side = if face.same_sense { 1.0 } else { -1.0 };
        } else {
            patch.side = patch.upward_side()?;
        }
        Ok(patch)
    }

    /// The side (+1/−1) whose normal points up on average over the patch (its region).
    fn upward_side(&self) -> Result<f64, PlanError> {
        let mut z = 0.0;
        let mut count = 0;
        for uv in self.samples(8) {
            if let Some(n) = self.surface.derivs(uv.x, uv.y).normal() {
                z += n.z;
                count += 1;
            }
        }
        if count == 0 {
            return Err(PlanError::Face(
                "the face has no defined normal anywhere".into(),
            ));
        }
        Ok(if z < 0.0 { -1.0 } else { 1.0 })
    }

    /// Sample parameters of the patch: an `(n + 1)²` grid of the rectangle, keeping the points
    /// inside the region, plus points along the region's loops (so a thin region is sampled).
    #[must_use]
    pub fn samples(&self, n: u32) -> Vec<DVec2> {
        let n = n.max(1);
        let mut out = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                let uv = self.at(f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                if self.contains(uv) {
                    out.push(uv);
                }
            }
        }
        if let Some(r) = self.region {
            out.extend(r.boundary_samples(4 * n as usize));
        }
        out
    }

    /// The patch without its trimmed region (the whole bounding rectangle).
    #[must_use]
    pub fn untrimmed(&self) -> Self {
        Self {
            region: None,
            ..*self
        }
    }

    /// Closed polylines around the patch: the region's loops, or the rectangle's four sides.
    #[must_use]
    pub fn boundary_loops(&self) -> Vec<Vec<DVec2>> {
        match self.region {
            Some(r) => r.loops().to_vec(),
            None => vec![vec![
                self.at(0.0, 0.0),
                self.at(1.0, 0.0),
                self.at(1.0, 1.0),
                self.at(0.0, 1.0),
            ]],
        }
    }

    /// Clip a parameter polyline to the region: the runs inside (the whole polyline when the
    /// patch has no region), each as its points and their fractional indices along `pts`.
    #[must_use]
    pub fn clip(&self, pts: &[DVec2]) -> Vec<Vec<(DVec2, f64)>> {
        match self.region {
            Some(r) => r.clip(pts),
            None => vec![
                pts.iter()
                    .enumerate()
                    .map(|(k, p)| (*p, k as f64))
                    .collect(),
            ],
        }
    }

    /// The patch of a B-rep face over its surface's natural domain (trimming loops are not
    /// used), with the tool on the side whose normal points up (+z) on average: parts are
    /// machined from above.
    ///
    /// # Errors
    /// [`PlanError::Face`] for unbounded surfaces or faces without a defined normal.
    pub fn from_face(face: &'a Face) -> Result<Self, PlanError> {
        Self::from_surface(&face.surface)
    }

    /// The patch of `surface` over its natural domain, with the tool on the side whose normal
    /// points up (+z) on average (as [`FacePatch::from_face`]).
    ///
    /// # Errors
    /// [`PlanError::Face`] for unbounded surfaces or surfaces without a defined normal.
    pub fn from_surface(surface: &'a SurfaceGeom) -> Result<Self, PlanError> {
        let mut patch = Self::new(surface, surface.domain(), 1.0)?;
        patch.side = patch.upward_side()?;
        Ok(patch)
    }

    /// Parameters at fractions `(s, t)` of the domain.
    #[must_use]
    pub fn at(&self, s: f64, t: f64) -> DVec2 {
        DVec2::new(self.domain.u.lerp(s), self.domain.v.lerp(t))
    }

    /// Is `uv` inside the domain (the rectangle with a relative slack, and the region)?
    #[must_use]
    pub fn contains(&self, uv: DVec2) -> bool {
        let su = 1e-9 * self.domain.u.len();
        let sv = 1e-9 * self.domain.v.len();
        uv.x >= self.domain.u.t0 - su
            && uv.x <= self.domain.u.t1 + su
            && uv.y >= self.domain.v.t0 - sv
            && uv.y <= self.domain.v.t1 + sv
            && self.region.is_none_or(|r| r.contains(uv))
    }

    /// Clamp into the domain.
    #[must_use]
    pub fn clamp(&self, uv: DVec2) -> DVec2 {
        DVec2::new(self.domain.u.clamp(uv.x), self.domain.v.clamp(uv.y))
    }

    /// Local frame at `uv`; `None` where the normal is undefined.
    #[must_use]
    pub fn frame(&self, uv: DVec2) -> Option<LocalFrame> {
        let d = self.surface.derivs(uv.x, uv.y);
        let n = d.normal()? * self.side;
        Some(LocalFrame { uv, p: d.p, n, d })
    }

    /// Normal curvature in the tangent direction `t`, signed positive where the surface bends
    /// toward the tool (concave seen from the tool), 1/mm.
    #[must_use]
    pub fn curvature_along(&self, f: &LocalFrame, t: DVec3) -> f64 {
        f.d.normal_curvature_along(t).map_or(0.0, |k| k * self.side)
    }

    /// Largest concave normal curvature (≥ 0) at a frame, 1/mm.
    #[must_use]
    pub fn max_concave(&self, f: &LocalFrame) -> f64 {
        f.d.principal().map_or(0.0, |p| {
            let (a, b) = (p.k_min * self.side, p.k_max * self.side);
            a.max(b).max(0.0)
        })
    }

    /// Parametric direction `(du, dv)` of a tangent vector `t` (least squares on `S_u, S_v`).
    #[must_use]
    pub fn param_dir(d: &SurfaceDerivs, t: DVec3) -> DVec2 {
        let (e, f, g) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
        let det = e * g - f * f;
        if !(det > 0.0) || !det.is_finite() {
            return DVec2::ZERO;
        }
        let (a, b) = (t.dot(d.su), t.dot(d.sv));
        DVec2::new((g * a - f * b) / det, (e * b - f * a) / det)
    }

    /// March from `uv` along the tangent direction `t` (re-projected into each local tangent
    /// plane, sign kept) for arc length `dist`, in sub-steps of at most `max_sub` mm (midpoint
    /// rule). Where a step would cross a boundary of parameter `slide` (0: u, 1: v), the march
    /// slides along that boundary; at any other boundary it stops there.
    #[must_use]
    pub fn march(
        &self,
        uv: DVec2,
        t: DVec3,
        dist: f64,
        max_sub: f64,
        slide: Option<usize>,
    ) -> March {
        let steps = ((dist / max_sub).ceil() as usize).clamp(1, 10_000);
        let h = dist / steps as f64;
        let mut p = uv;
        let mut dir = t;
        let mut travelled = 0.0;
        for _ in 0..steps {
            let Some(dp1) = self.unit_param_dir(p, &mut dir) else {
                break;
            };
            let mid = p + dp1 * (0.5 * h);
            let mut dir2 = dir;
            let mut dp = self.unit_param_dir(mid, &mut dir2).unwrap_or(dp1);
            if let Some(k) = slide.filter(|_| !self.contains(p + dp * h)) {
                {
                    let d = self.frame(p).map(|f| f.d);
                    let mut q = dp;
                    if k == 0 {
                        q.x = 0.0;
                    } else {
                        q.y = 0.0;
                    }
                    let speed = d.map_or(0.0, |d| (d.su * q.x + d.sv * q.y).length());
                    let outside_along = {
                        let next = p + dp * h;
                        let c = self.clamp(next);
                        if k == 0 {
                            (c.y - next.y).abs() <= 1e-12 * self.domain.v.len().max(1.0)
                        } else {
                            (c.x - next.x).abs() <= 1e-12 * self.domain.u.len().max(1.0)
                        }
                    };
                    if outside_along && speed > 1e-12 {
                        dp = q / speed;
                    }
                }
            }
            let next = p + dp * h;
            if !self.contains(next) {
                // Bisect to the boundary.
                let (mut lo, mut hi) = (0.0, 1.0);
                for _ in 0..40 {
                    let m = 0.5 * (lo + hi);
                    if self.contains(p + dp * (h * m)) {
                        lo = m;
                    } else {
                        hi = m;
                    }
                }
                return March {
                    uv: self.clamp(p + dp * (h * lo)),
                    travelled: travelled + h * lo,
                    hit_boundary: true,
                };
            }
            p = next;
            dir = dir2;
            travelled += h;
        }
        March {
            uv: p,
            travelled,
            hit_boundary: false,
        }
    }

    /// Parametric velocity of unit 3D speed along `dir` projected into the tangent plane at
    /// `uv`; updates `dir` to the projected unit direction.
    fn unit_param_dir(&self, uv: DVec2, dir: &mut DVec3) -> Option<DVec2> {
        let f = self.frame(uv)?;
        let t = (*dir - f.n * dir.dot(f.n)).try_normalize()?;
        *dir = t;
        let dp = Self::param_dir(&f.d, t);
        let speed = (f.d.su * dp.x + f.d.sv * dp.y).length();
        (speed > 1e-12).then(|| dp / speed)
    }
}
