//! The stock as dexels: its initial shape (box, upright cylinder, closed mesh), the grid, the
//! memory estimate made before anything is allocated.

use glam::DVec3;

use super::SimError;
use super::dexel::{Dexel, DexelFamily, RayAxis};
use crate::geometry::Aabb;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::geometry::stock::Stock;

/// The raw material's initial shape (mm).
#[derive(Clone, Debug)]
pub enum StockShape {
    /// An axis-aligned box.
    Box {
        /// Minimum corner.
        min: DVec3,
        /// Maximum corner.
        max: DVec3,
    },
    /// An upright cylinder (axis +Z).
    Cylinder {
        /// Centre of the bottom face.
        base: DVec3,
        /// Radius.
        radius: f64,
        /// Height.
        height: f64,
    },
    /// A closed triangle mesh (the material is its inside).
    Mesh(Box<MeshStock>),
}

/// A closed mesh and its hierarchy, for [`StockShape::Mesh`]. The hierarchy is built the first
/// time a single ray is asked for ([`StockShape::ray_intervals`]): a whole Z grid is read by
/// one pass over the triangles without it (8.6 s of a 6.7 M-triangle carried stock's 13 s
/// load went into the hierarchy before).
#[derive(Clone, Debug)]
pub struct MeshStock {
    /// The mesh.
    pub mesh: TriMesh,
    bvh: std::sync::OnceLock<Option<MeshBvh>>,
}

impl MeshStock {
    fn bvh(&self) -> Option<&MeshBvh> {
        self.bvh
            .get_or_init(|| MeshBvh::new(&self.mesh).ok())
            .as_ref()
    }
}

impl StockShape {
    /// The dexel shape of `stock`, or of the one default stock around `part_bounds` when none is
    /// defined (see [`Stock::or_default_for`]: the same one roughing clears).
    #[must_use]
    pub fn of(stock: &Stock, part_bounds: &Aabb) -> Self {
        Self::sized(&stock.or_default_for(part_bounds)).unwrap_or(Self::Box {
            min: part_bounds.min,
            max: part_bounds.max,
        })
    }

    /// The dexel shape of a sized stock (`None` for [`Stock::None`]).
    #[must_use]
    pub fn sized(stock: &Stock) -> Option<Self> {
        match *stock {
            Stock::None => None,
            Stock::Cylinder {
                base_mm,
                radius_mm,
                height_mm,
            } => Some(Self::Cylinder {
                base: base_mm.into(),
                radius: radius_mm,
                height: height_mm,
            }),
            Stock::Box { min_mm, max_mm } => Some(Self::Box {
                min: min_mm.into(),
                max: max_mm.into(),
            }),
        }
    }

    /// A mesh stock.
    ///
    /// # Errors
    /// [`SimError::Stock`] when the mesh is not closed or has no usable triangle.
    pub fn mesh(mesh: TriMesh) -> Result<Self, SimError> {
        if !mesh.is_closed() {
            return Err(SimError::Stock(
                "a mesh stock must be closed (every edge shared by two triangles)".into(),
            ));
        }
        if let Some(v) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(SimError::Stock(format!(
                "mesh vertex {v} is not a finite point"
            )));
        }
        let usable = (0..mesh.triangles.len()).any(|i| {
            mesh.triangle_corners(i)
                .is_some_and(|[a, b, c]| (b - a).cross(c - a).length_squared() > 0.0)
        });
        if !usable {
            return Err(SimError::Stock(format!(
                "none of the mesh's {} triangles has an area",
                mesh.triangles.len()
            )));
        }
        Ok(Self::Mesh(Box::new(MeshStock {
            mesh,
            bvh: std::sync::OnceLock::new(),
        })))
    }

    /// Check the sizes: finite, positive.
    ///
    /// # Errors
    /// [`SimError::Stock`] naming what is wrong.
    pub fn validate(&self) -> Result<(), SimError> {
        match self {
            Self::Box { min, max } => {
                if !(min.is_finite() && max.is_finite() && min.cmplt(*max).all()) {
                    return Err(SimError::Stock(format!(
                        "box minimum {:?} mm must be below maximum {:?} mm on every axis",
                        min.to_array(),
                        max.to_array()
                    )));
                }
            }
            Self::Cylinder {
                base,
                radius,
                height,
            } => {
                let ok = base.is_finite()
                    && radius.is_finite()
                    && height.is_finite()
                    && *radius > 0.0
                    && *height > 0.0;
                if !ok {
                    return Err(SimError::Stock(format!(
                        "cylinder needs a finite base and positive radius and height, got \
                         radius {radius} mm, height {height} mm"
                    )));
                }
            }
            Self::Mesh(_) => {}
        }
        Ok(())
    }

    /// Bounding box.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        match self {
            Self::Box { min, max } => Aabb {
                min: *min,
                max: *max,
            },
            Self::Cylinder {
                base,
                radius,
                height,
            } => Aabb {
                min: *base - DVec3::new(*radius, *radius, 0.0),
                max: *base + DVec3::new(*radius, *radius, *height),
            },
            Self::Mesh(m) => m.mesh.bbox(),
        }
    }

    /// Material intervals (absolute coordinate along the ray axis) of the ray through `p`
    /// along `axis`, sorted and disjoint.
    #[must_use]
    pub fn ray_intervals(&self, p: DVec3, axis: RayAxis) -> Vec<[f64; 2]> {
        let (u, v, w) = axis.axes();
        let a = p.to_array();
        let (pu, pv) = (a[u], a[v]);
        match self {
            Self::Box { min, max } => {
                let (lo, hi) = (min.to_array(), max.to_array());
                if pu < lo[u] || pu > hi[u] || pv < lo[v] || pv > hi[v] {
                    return Vec::new();
                }
                vec![[lo[w], hi[w]]]
            }
            Self::Cylinder {
                base,
                radius,
                height,
            } => {
                let (dx, dy) = (p.x - base.x, p.y - base.y);
                match axis {
                    RayAxis::Z => {
                        if dx * dx + dy * dy > radius * radius {
                            Vec::new()
                        } else {
                            vec![[base.z, base.z + height]]
                        }
                    }
                    RayAxis::X | RayAxis::Y => {
                        if p.z < base.z || p.z > base.z + height {
                            return Vec::new();
                        }
                        let (off, centre) = if axis == RayAxis::X {
                            (dy, base.x)
                        } else {
                            (dx, base.y)
                        };
                        let h2 = radius * radius - off * off;
                        if h2 <= 0.0 {
                            return Vec::new();
                        }
                        let h = h2.sqrt();
                        vec![[centre - h, centre + h]]
                    }
                }
            }
            Self::Mesh(m) => m
                .bvh()
                .map_or_else(Vec::new, |bvh| mesh_intervals(bvh, &m.mesh.bbox(), p, axis)),
        }
    }
}

/// Inside intervals of a closed mesh along a ray, by successive hits (entering and leaving
/// alternate; an odd count drops the last hit).
pub(super) fn mesh_intervals(
    bvh: &MeshBvh,
    bounds: &Aabb,
    p: DVec3,
    axis: RayAxis,
) -> Vec<[f64; 2]> {
    let (_, _, w) = axis.axes();
    let dir = axis.direction();
    let lo = bounds.min.to_array()[w] - 1.0;
    let hi = bounds.max.to_array()[w] + 1.0;
    let mut start = p;
    let mut a = start.to_array();
    a[w] = lo;
    start = DVec3::from_array(a);
    let mut hits = Vec::new();
    let mut t0 = 0.0;
    let span = hi - lo;
    // Step just past each hit; a hit on a shared edge may come twice at the same place.
    while hits.len() < 10_000 {
        let Some(h) = bvh.ray_cast(start + dir * t0, dir, span - t0) else {
            break;
        };
        let t = t0 + h.t;
        hits.push(lo + t);
        t0 = t + 1e-7;
    }
    hits.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
    hits.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
}

/// How many ray families the stock keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum DexelMode {
    /// Z rays only: exact for 3-axis removal seen from above.
    Z,
    /// X, Y and Z rays: for tilted tools (walls and undercuts keep their resolution).
    Tri,
}

/// The stock: its initial shape and one or three dexel families.
#[derive(Clone, Debug)]
pub struct DexelStock {
    /// The shapes whose union is the initial stock.
    pub shapes: Vec<StockShape>,
    /// Cell size, mm.
    pub resolution_mm: f64,
    /// Families in order Z (always first), then X and Y for [`DexelMode::Tri`].
    pub families: Vec<DexelFamily>,
    /// Bounding box of the initial stock.
    pub bounds: Aabb,
}

/// Bytes a stock of `bounds` at `resolution_mm` needs, before any ray holds more than one
/// interval: `size_of::<Dexel>()` per ray per family. `None` when the grid is not finite.
#[must_use]
pub fn estimate_bytes(bounds: &Aabb, resolution_mm: f64, mode: DexelMode) -> Option<u64> {
    let size = bounds.max - bounds.min;
    if !(resolution_mm > 0.0) || !size.is_finite() {
        return None;
    }
    let cells = |x: f64| -> Option<u64> {
        let n = (x / resolution_mm).ceil().max(1.0);
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        (n < 1e12).then_some(n as u64)
    };
    let (nx, ny, nz) = (cells(size.x)?, cells(size.y)?, cells(size.z)?);
    let rays = match mode {
        DexelMode::Z => nx.checked_mul(ny)?,
        DexelMode::Tri => nx
            .checked_mul(ny)?
            .checked_add(ny.checked_mul(nz)?)?
            .checked_add(nz.checked_mul(nx)?)?,
    };
    rays.checked_mul(std::mem::size_of::<Dexel>() as u64)
}

/// Default memory ceiling of a stock: 4 GiB.
pub const DEFAULT_MEMORY_LIMIT_BYTES: u64 = 4 << 30;

impl DexelStock {
    /// The stock of the union of `shapes`, at `resolution_mm`, with one (Z) or three families.
    ///
    /// # Errors
    /// [`SimError::Stock`] for no shape or a bad one, [`SimError::Resolution`] for a
    /// non-positive resolution, [`SimError::Memory`] when the estimate exceeds
    /// `memory_limit_bytes` (nothing is allocated then).
    pub fn new(
        shapes: Vec<StockShape>,
        resolution_mm: f64,
        mode: DexelMode,
        memory_limit_bytes: u64,
    ) -> Result<Self, SimError> {
        if !(resolution_mm > 0.0 && resolution_mm.is_finite()) {
            return Err(SimError::Resolution(resolution_mm));
        }
        let mut bounds = Aabb::EMPTY;
        let mut first = true;
        for s in &shapes {
            s.validate()?;
            if first {
                bounds = s.bounds();
                first = false;
            } else {
                bounds.union(&s.bounds());
            }
        }
        if first {
            return Err(SimError::Stock("no stock shape given".into()));
        }
        let need = estimate_bytes(&bounds, resolution_mm, mode).unwrap_or(u64::MAX);
        if need > memory_limit_bytes {
            return Err(SimError::Memory {
                need_bytes: need,
                limit_bytes: memory_limit_bytes,
                resolution_mm,
            });
        }
        // Ask the allocator up front (nothing is touched, so this costs nothing when it works):
        // an estimate the limit lets through may still be more than the machine can give, and
        // a failed allocation later would abort the process instead of giving this error.
        let probe = usize::try_from(need)
            .ok()
            .and_then(|n| Vec::<u8>::new().try_reserve_exact(n).ok());
        if probe.is_none() {
            return Err(SimError::Memory {
                need_bytes: need,
                limit_bytes: need.saturating_sub(1),
                resolution_mm,
            });
        }
        let axes: &[RayAxis] = match mode {
            DexelMode::Z => &[RayAxis::Z],
            DexelMode::Tri => &[RayAxis::Z, RayAxis::X, RayAxis::Y],
        };
        let families = axes
            .iter()
            .map(|a| Self::family(&shapes, &bounds, resolution_mm, *a))
            .collect();
        Ok(Self {
            shapes,
            resolution_mm,
            families,
            bounds,
        })
    }

    fn family(shapes: &[StockShape], bounds: &Aabb, res: f64, axis: RayAxis) -> DexelFamily {
        use rayon::prelude::*;
        let (u, v, w) = axis.axes();
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let n = |k: usize| ((hi[k] - lo[k]) / res).ceil().max(1.0) as usize;
        let (nu, nv) = (n(u), n(v));
        let mut fam = DexelFamily {
            axis,
            origin: bounds.min,
            spacing: res,
            nu,
            nv,
            dexels: Vec::new(),
        };
        let base = lo[w];
        if let [StockShape::Mesh(m)] = shapes {
            fam.dexels = mesh_rays(&m.mesh, &fam);
            return fam;
        }
        let dexels: Vec<Dexel> = (0..nu * nv)
            .into_par_iter()
            .map(|k| {
                let p = fam.ray_origin(k % nu, k / nu);
                let mut d = Dexel::Empty;
                for s in shapes {
                    for [a, b] in s.ray_intervals(p, axis) {
                        #[allow(clippy::cast_possible_truncation)]
                        d.add((a - base) as f32, (b - base) as f32);
                    }
                }
                d
            })
            .collect();
        fam.dexels = dexels;
        fam
    }

    /// Which families the stock keeps.
    #[must_use]
    pub fn mode(&self) -> DexelMode {
        if self.families.len() > 1 {
            DexelMode::Tri
        } else {
            DexelMode::Z
        }
    }

    /// Material volume, mm³: the Z family's (a tri-dexel stock averages its three families).
    #[must_use]
    pub fn volume_mm3(&self) -> f64 {
        #[allow(clippy::cast_precision_loss)]
        let n = self.families.len().max(1) as f64;
        self.families.iter().map(DexelFamily::volume).sum::<f64>() / n
    }

    /// Bytes held now: the ray arrays plus intervals stored on the heap.
    #[must_use]
    pub fn memory_bytes(&self) -> u64 {
        let b: usize = self
            .families
            .iter()
            .map(|f| {
                f.dexels.capacity() * std::mem::size_of::<Dexel>()
                    + f.dexels.iter().map(Dexel::heap_bytes).sum::<usize>()
            })
            .sum();
        b as u64
    }

    /// Number of rays over all families.
    #[must_use]
    pub fn ray_count(&self) -> usize {
        self.families.iter().map(|f| f.dexels.len()).sum()
    }

    /// Whether a stock-surface point lies on the initial stock's boundary (never cut), within
    /// `tol` along the ray.
    #[must_use]
    pub fn on_initial_boundary(&self, p: DVec3, axis: RayAxis, tol: f64) -> bool {
        let (_, _, w) = axis.axes();
        let x = p.to_array()[w];
        self.shapes.iter().any(|s| {
            s.ray_intervals(p, axis)
                .iter()
                .any(|[a, b]| (x - a).abs() <= tol || (x - b).abs() <= tol)
        })
    }
}

/// The sign of the edge function of `(a, b)` at `p` in the plane, the same for both
/// triangles that share the edge (it is evaluated with the edge's ends in one fixed order) and
/// never zero: on the edge, the point counts as moved by (ε, ε²) (simulation of simplicity),
/// so a ray through a shared edge or vertex enters exactly one of the triangles around it.
fn edge_side(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> f64 {
    let (a, b, flip) = if (a[0], a[1]) <= (b[0], b[1]) {
        (a, b, 1.0)
    } else {
        (b, a, -1.0)
    };
    let value = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
    let side = if value != 0.0 {
        value
    } else if b[1] != a[1] {
        a[1] - b[1]
    } else {
        b[0] - a[0]
    };
    flip * side.signum()
}

/// The material of a closed mesh on every ray of `fam`, by one pass over the triangles: each
/// triangle not parallel to the rays is tested against the rays whose feet lie in its
/// shadow ([`edge_side`]: a ray through a shared edge counts once), a hit enters the material
/// where the triangle's normal points against the ray and leaves it where along, and each
/// ray's hits, sorted, give its intervals by their winding. Linear in the triangles plus the
/// hits (casting each ray through the hierarchy, [`mesh_intervals`], did not finish a cut
/// stock of a million rays in ten minutes).
fn mesh_rays(mesh: &TriMesh, fam: &DexelFamily) -> Vec<Dexel> {
    use rayon::prelude::*;
    let (u, v, w) = fam.axis.axes();
    let o = fam.origin.to_array();
    let h = fam.spacing;
    let (nu, nv) = (fam.nu, fam.nv);
    #[allow(clippy::cast_precision_loss)]
    let cells = |lo: f64, hi: f64, origin: f64, n: usize| -> (usize, usize) {
        let first = ((lo - origin) / h - 0.5).ceil().max(0.0);
        let last = ((hi - origin) / h - 0.5).floor().min(n as f64 - 1.0);
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        if last >= first {
            (first as usize, last as usize + 1)
        } else {
            (0, 0)
        }
    };
    let mut hits: Vec<(usize, f64, i8)> = mesh
        .triangles
        .par_iter()
        .flat_map_iter(|t| {
            let p = t.map(|i| {
                mesh.positions
                    .get(i as usize)
                    .copied()
                    .unwrap_or(DVec3::ZERO)
                    .to_array()
            });
            let q = p.map(|a| [a[u], a[v]]);
            let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
            let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
            let n = DVec3::from_array(e1)
                .cross(DVec3::from_array(e2))
                .to_array();
            let (nu_, nv_, nw) = (n[u], n[v], n[w]);
            let area = (q[1][0] - q[0][0]) * (q[2][1] - q[0][1])
                - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]);
            let mut out = Vec::new();
            if area == 0.0 || nw == 0.0 || !area.is_finite() {
                return out;
            }
            let sense = area.signum();
            let winding: i8 = if nw > 0.0 { -1 } else { 1 };
            let (lo_u, hi_u) = (
                q[0][0].min(q[1][0]).min(q[2][0]),
                q[0][0].max(q[1][0]).max(q[2][0]),
            );
            let (lo_v, hi_v) = (
                q[0][1].min(q[1][1]).min(q[2][1]),
                q[0][1].max(q[1][1]).max(q[2][1]),
            );
            let (i0, i1) = cells(lo_u, hi_u, o[u], nu);
            let (j0, j1) = cells(lo_v, hi_v, o[v], nv);
            for j in j0..j1 {
                for i in i0..i1 {
                    let foot = fam.ray_origin(i, j).to_array();
                    let f = [foot[u], foot[v]];
                    let inside = edge_side(q[0], q[1], f) == sense
                        && edge_side(q[1], q[2], f) == sense
                        && edge_side(q[2], q[0], f) == sense;
                    if inside {
                        let z = p[0][w] - (nu_ * (f[0] - q[0][0]) + nv_ * (f[1] - q[0][1])) / nw;
                        out.push((j * nu + i, z - o[w], winding));
                    }
                }
            }
            out
        })
        .collect();
    hits.par_sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut dexels = vec![Dexel::Empty; nu * nv];
    let mut k = 0;
    while k < hits.len() {
        let ray = hits[k].0;
        let mut end = k;
        while end < hits.len() && hits[end].0 == ray {
            end += 1;
        }
        let mut list: Vec<[f32; 2]> = Vec::new();
        let (mut wind, mut start) = (0i32, 0.0f64);
        for &(_, z, s) in &hits[k..end] {
            let before = wind;
            wind += i32::from(s);
            if before <= 0 && wind > 0 {
                start = z;
            } else if before > 0 && wind <= 0 {
                #[allow(clippy::cast_possible_truncation)]
                let (a, b) = (start as f32, z as f32);
                match list.last_mut() {
                    Some(last) if a <= last[1] => last[1] = last[1].max(b),
                    _ => list.push([a, b]),
                }
            }
        }
        if let Some(d) = dexels.get_mut(ray) {
            *d = Dexel::from_intervals(&list);
        }
        k = end;
    }
    dexels
}
