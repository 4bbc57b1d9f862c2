//! Z-level (waterline) roughing of a mesh from a box or cylinder stock.
//!
//! **Slicing.** The part is sliced through the drop-cutter CL surface on a regular grid (a CL
//! Z-map): with radial stock δr the drop-cutter runs with the cutter offset by δr (ball R + δr;
//! flat → bull-nose with corner δr; bull-nose r → r + δr), whose tip lies δr below the real
//! tip, so the real tool keeps δr from the part in every direction where
//! tip ≥ CL_offset + δr; the axial stock δa raises this to tip ≥ CL_offset + max(δr, δa). At a
//! level z the tool centre is free where that holds and where the centre lies within the stock
//! grown by 0.9·R (so the outermost pass trims the stock's skin).
//!
//! **Levels.** Every step-down from the stock top to its bottom (or the part's lowest point plus
//! the axial stock), plus, with `detect_flats`, one level per flat area of the part (faces
//! within 0.5° of horizontal, at least a quarter of the tool's footprint) at its height plus
//! the stock to leave: without it a floor between two levels keeps up to a whole step-down.
//!
//! **Clearing.** Each level's free region is cleared by offset contours of its boundary: the
//! level sets φ = d₀ + k·s of the Euclidean distance φ to the nearest blocked grid node
//! (`field`: exact distance transform, marching squares, Douglas–Peucker), d₀ = one grid step
//! (the grid's own uncertainty), s = the step-over. Contours run from the inside out (largest
//! φ first), so each level starts in the middle of its region.
//!
//! **Entry and links.** A contour is entered by a ramp along itself from the level above (a
//! region cleared at the level above, and the free region only grows upward, so the ramp is
//! clear of the part and cuts at most one step-down), at `ramp_angle_rad`: no full-width
//! plunge into material. Neighbouring contours closer than 1.5 step-overs are joined by a fed
//! move at the level when the straight link stays in the free region; otherwise the tool
//! retracts straight up from where it has just cut (over cleared area), rapids at the clearance
//! plane, rapids down to 1 mm above the level above (cleared), plunges through cleared air to
//! that level and ramps down.

mod field;

use glam::{DVec2, DVec3};

use crate::diagnostics::Diagnostic;
use crate::geometry::Aabb;
use crate::geometry::bvh::MeshBvh;
use crate::geometry::mesh::TriMesh;
use crate::geometry::stock::Stock;
use crate::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};
use crate::tools::dropcutter::drop_cutter;
use crate::tools::{Cutter, CutterKind};
use field::{Field, thin_loop};

/// The stock resolved for planning (the default around the part when none is given), mm.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Blank {
    Box {
        min: DVec3,
        max: DVec3,
    },
    Cylinder {
        centre: DVec2,
        radius: f64,
        z0: f64,
        z1: f64,
    },
}

impl Blank {
    /// `stock`, or the one default stock around `part` ([`Stock::or_default_for`]).
    fn of(stock: &Stock, part: &Aabb) -> Self {
        match stock.or_default_for(part) {
            Stock::Cylinder {
                base_mm,
                radius_mm,
                height_mm,
            } => Self::Cylinder {
                centre: DVec2::new(base_mm[0], base_mm[1]),
                radius: radius_mm,
                z0: base_mm[2],
                z1: base_mm[2] + height_mm,
            },
            Stock::Box { min_mm, max_mm } => Self::Box {
                min: min_mm.into(),
                max: max_mm.into(),
            },
            // `or_default_for` never gives `None`; the part's box is the safe reading.
            Stock::None => Self::Box {
                min: part.min,
                max: part.max,
            },
        }
    }

    fn top(&self) -> f64 {
        match self {
            Self::Box { max, .. } => max.z,
            Self::Cylinder { z1, .. } => *z1,
        }
    }

    fn bottom(&self) -> f64 {
        match self {
            Self::Box { min, .. } => min.z,
            Self::Cylinder { z0, .. } => *z0,
        }
    }

    /// XY box of the stock.
    fn xy_box(&self) -> (DVec2, DVec2) {
        match self {
            Self::Box { min, max } => (min.truncate(), max.truncate()),
            Self::Cylinder { centre, radius, .. } => (
                *centre - DVec2::splat(*radius),
                *centre + DVec2::splat(*radius),
            ),
        }
    }

    /// Distance in XY from the stock's outline (≤ 0 inside).
    fn outside_by(&self, p: DVec2) -> f64 {
        match self {
            Self::Box { min, max } => {
                let d = (min.truncate() - p).max(p - max.truncate());
                if d.x > 0.0 || d.y > 0.0 {
                    d.max(DVec2::ZERO).length()
                } else {
                    d.x.max(d.y)
                }
            }
            Self::Cylinder { centre, radius, .. } => p.distance(*centre) - radius,
        }
    }
}

/// Options of [`zlevel_rough`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ZlevelOptions {
    /// The raw material ([`Stock::None`]: the one default stock around the part).
    pub stock: Stock,
    /// Distance between levels, mm.
    pub step_down_mm: f64,
    /// Distance between neighbouring contours, mm (at most the tool diameter).
    pub step_over_mm: f64,
    /// Material left on the part in XY, mm.
    pub stock_to_leave_radial_mm: f64,
    /// Material left on the part in Z, mm.
    pub stock_to_leave_axial_mm: f64,
    /// Grid step of the CL Z-map (and so the contours' accuracy), mm.
    pub tolerance_mm: f64,
    /// Ramp angle of the entry, rad from horizontal.
    pub ramp_angle_rad: f64,
    /// Cutting feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Clearance plane above the stock top, mm.
    pub clearance_mm: f64,
    /// Detect flat areas: horizontal faces of the part (within [`FLAT_TOLERANCE_RAD`]) lying
    /// between two levels get a level of their own at their height plus the stock to leave, so
    /// floors keep the stock to leave instead of a whole staircase step.
    #[serde(default = "detect_flats_default")]
    pub detect_flats: bool,
}

fn detect_flats_default() -> bool {
    true
}

/// How far from horizontal a face may tilt and still count as a flat area, rad (0.5°).
pub const FLAT_TOLERANCE_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

impl Default for ZlevelOptions {
    fn default() -> Self {
        Self {
            stock: Stock::None,
            step_down_mm: 2.0,
            step_over_mm: 4.0,
            stock_to_leave_radial_mm: 0.3,
            stock_to_leave_axial_mm: 0.3,
            tolerance_mm: 0.25,
            ramp_angle_rad: 5f64.to_radians(),
            feed_mm_per_min: 1000.0,
            clearance_mm: 5.0,
            detect_flats: true,
        }
    }
}

/// Heights of the part's flat areas facing up (faces within [`FLAT_TOLERANCE_RAD`] of
/// horizontal, merged when within 0.01 mm of each other), with their areas, mm and mm²,
/// ascending.
#[must_use]
pub fn flat_areas(mesh: &TriMesh) -> Vec<(f64, f64)> {
    let cos_flat = FLAT_TOLERANCE_RAD.cos();
    let mut flats: Vec<(f64, f64)> = (0..mesh.triangles.len())
        .filter_map(|t| {
            let [a, b, c] = mesh.triangle_corners(t)?;
            let n = (b - a).cross(c - a);
            let area = 0.5 * n.length();
            let n = n.try_normalize()?;
            (n.z >= cos_flat && area > 0.0).then_some(((a.z + b.z + c.z) / 3.0, area))
        })
        .collect();
    flats.sort_by(|p, q| p.0.total_cmp(&q.0));
    let mut out: Vec<(f64, f64)> = Vec::new();
    for (z, area) in flats {
        match out.last_mut() {
            // Area-weighted mean height of the merged group.
            Some((mz, ma)) if z - *mz <= 0.01 => {
                *mz = (*mz * *ma + z * area) / (*ma + area);
                *ma += area;
            }
            _ => out.push((z, area)),
        }
    }
    out
}

/// The levels for flat areas: at each flat area's height plus `lift`, when no level lies already
/// at that height (within 1 µm above it), above the lowest level and below the top; floors
/// smaller than a quarter of the tool's footprint are left out.
fn flat_levels(mesh: &TriMesh, levels: &[f64], lift: f64, top: f64, tool_radius: f64) -> Vec<f64> {
    let min_area = 0.25 * std::f64::consts::PI * tool_radius * tool_radius;
    let lowest = levels.last().copied().unwrap_or(top);
    flat_areas(mesh)
        .into_iter()
        .filter(|(_, area)| *area >= min_area)
        .map(|(z, _)| z + lift)
        .filter(|z| *z < top - 1e-9 && *z > lowest + 1e-9)
        .filter(|z| !levels.iter().any(|l| *l >= *z - 1e-9 && *l <= *z + 1e-3))
        .collect()
}

/// Why roughing could not be planned.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ZlevelError {
    /// An option is out of range.
    #[error("invalid roughing option: {0}")]
    Option(String),
    /// The cutter kind is not supported (cones).
    #[error("Z-level roughing supports ball, flat and bull-nose cutters")]
    Cutter,
}

/// The roughing grid spacing (mm) for a cutter of `cutter_radius` mm: the chord tolerance, but
/// no finer than half the stock to leave `allowance_mm` (the grid may leave up to one spacing more
/// than the stock to leave, so half of it keeps roughing within 1.5× the requested allowance) and
/// coarse enough that the grid over the stock (plus the tool's reach) stays under the planner's 4
/// million nodes.
#[must_use]
pub fn roughing_grid_mm(
    stock: &Stock,
    part: &Aabb,
    cutter_radius: f64,
    tolerance_mm: f64,
    allowance_mm: f64,
) -> f64 {
    let mut g = tolerance_mm.max(0.5 * allowance_mm.max(0.0)).max(1e-3);
    let (lo, hi) = Blank::of(stock, part).xy_box();
    let size = hi - lo + DVec2::splat(2.0 * cutter_radius + 4.0 * g);
    let area = (size.x.max(0.0) + g) * (size.y.max(0.0) + g);
    let finest = (area / 3.5e6).sqrt();
    if finest.is_finite() && finest > g {
        g = finest;
    }
    g
}

/// A planned roughing path.
#[derive(Clone, Debug, PartialEq)]
pub struct ZlevelPlan {
    /// The tool path.
    pub toolpath: Toolpath,
    /// The levels (tool tip heights), from the top down, mm.
    pub levels: Vec<f64>,
    /// Number of contours cut.
    pub contours: usize,
    /// Notes.
    pub diagnostics: Vec<Diagnostic>,
}

fn offset_cutter(c: &Cutter, d: f64) -> Result<Cutter, ZlevelError> {
    if d <= 0.0 {
        return Ok(c.clone());
    }
    let kind = match c.kind {
        CutterKind::Ball => CutterKind::Ball,
        CutterKind::Flat => CutterKind::BullNose { corner_radius: d },
        CutterKind::BullNose { corner_radius } => CutterKind::BullNose {
            corner_radius: corner_radius + d,
        },
        CutterKind::Cone { .. } => return Err(ZlevelError::Cutter),
    };
    Cutter::new(kind, c.diameter + 2.0 * d).map_err(|e| ZlevelError::Option(e.to_string()))
}

fn check(opts: &ZlevelOptions, cutter: &Cutter) -> Result<(), ZlevelError> {
    for (what, v) in [
        ("step-down", opts.step_down_mm),
        ("step-over", opts.step_over_mm),
        ("tolerance", opts.tolerance_mm),
        ("ramp angle", opts.ramp_angle_rad),
        ("feed", opts.feed_mm_per_min),
    ] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(ZlevelError::Option(format!(
                "{what} must be positive, got {v}"
            )));
        }
    }
    for (what, v) in [
        ("radial stock to leave", opts.stock_to_leave_radial_mm),
        ("axial stock to leave", opts.stock_to_leave_axial_mm),
        ("clearance", opts.clearance_mm),
    ] {
        if !(v >= 0.0 && v.is_finite()) {
            return Err(ZlevelError::Option(format!("{what} must be ≥ 0, got {v}")));
        }
    }
    if opts.step_over_mm > cutter.diameter {
        return Err(ZlevelError::Option(format!(
            "step-over {} mm exceeds the tool diameter {} mm",
            opts.step_over_mm, cutter.diameter
        )));
    }
    if opts.ramp_angle_rad >= std::f64::consts::FRAC_PI_2 {
        return Err(ZlevelError::Option(
            "ramp angle must be below 90 degrees".into(),
        ));
    }
    Ok(())
}

/// Plan Z-level roughing of `mesh` (with hierarchy `bvh`) with `tool` (see the module docs).
///
/// # Errors
/// [`ZlevelError::Option`] for a bad option or a grid past 4 million nodes,
/// [`ZlevelError::Cutter`] for a cone.
pub fn zlevel_rough(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    tool: &ToolRecord,
    opts: &ZlevelOptions,
) -> Result<ZlevelPlan, ZlevelError> {
    let cutter = &tool.cutter;
    check(opts, cutter)?;
    let (dr, da) = (opts.stock_to_leave_radial_mm, opts.stock_to_leave_axial_mm);
    let off = offset_cutter(cutter, dr)?;
    let big = cutter.radius();
    let g = opts.tolerance_mm;
    let reach = 0.9 * big;
    let blank = Blank::of(&opts.stock, &bvh.bbox());
    let (lo, hi) = blank.xy_box();
    let origin = lo - DVec2::splat(reach + 2.0 * g);
    let size = hi - lo + DVec2::splat(2.0 * (reach + 2.0 * g));
    let nx = (size.x / g).ceil() as usize + 1;
    let ny = (size.y / g).ceil() as usize + 1;
    if nx.saturating_mul(ny) > 4_000_000 {
        return Err(ZlevelError::Option(format!(
            "grid of {nx}×{ny} nodes at {g} mm is too fine for this stock"
        )));
    }
    let nodes: Vec<DVec2> = (0..nx * ny)
        .map(|k| origin + DVec2::new((k % nx) as f64, (k / nx) as f64) * g)
        .collect();
    let lift = dr.max(da);
    let need: Vec<f64> = drop_cutter(bvh, mesh, &off, &nodes)
        .into_iter()
        .map(|c| c.map_or(f64::NEG_INFINITY, |c| c.z + lift))
        .collect();
    let in_reach: Vec<bool> = nodes
        .iter()
        .map(|p| blank.outside_by(*p) <= reach)
        .collect();

    let top = blank.top();
    let (levels, mut diagnostics) = cutting_levels(mesh, bvh, &blank, opts, lift, big);
    let (levels, short) = within_reach(levels, top, cutter);
    diagnostics.extend(short);

    let clear_z = top.max(bvh.bbox().max.z) + opts.clearance_mm;
    let mut poses: Vec<Pose> = Vec::new();
    let mut contours = 0;
    let s = opts.step_over_mm;
    let d0 = g;
    let mut above = top;
    for &z in &levels {
        let free: Vec<bool> = need
            .iter()
            .zip(&in_reach)
            .map(|(n, r)| *r && z >= *n - 1e-7)
            .collect();
        let field = Field::distance(origin, g, nx, ny, &free);
        let mut loops: Vec<Vec<DVec2>> = Vec::new();
        let kmax = ((field.max() - d0) / s).floor();
        if kmax >= 0.0 {
            for k in (0..=kmax as usize).rev() {
                for lp in field.contours(d0 + k as f64 * s) {
                    let lp = thin_loop(&lp, 0.1 * g);
                    if perimeter(&lp) >= 2.0 * g {
                        loops.push(lp);
                    }
                }
            }
        }
        for lp in &loops {
            contours += 1;
            let Some(&start) = lp.first() else { continue };
            let here = poses.last().map(|p| p.tip);
            let joined = here.is_some_and(|h| {
                (h.z - z).abs() < 1e-9
                    && h.truncate().distance(start) <= 1.5 * s
                    && segment_free(&field, h.truncate(), start, d0)
            });
            let cut = |p: DVec2, zz: f64| {
                Pose::new(MoveKind::Cut, p.extend(zz), DVec3::Z, opts.feed_mm_per_min)
            };
            if joined {
                poses.push(cut(start, z));
            } else {
                let rapid =
                    |p: DVec3| Pose::new(MoveKind::Rapid, p, DVec3::Z, opts.feed_mm_per_min);
                if let Some(h) = here {
                    poses.push(rapid(h.truncate().extend(clear_z)));
                }
                poses.push(rapid(start.extend(clear_z)));
                poses.push(rapid(start.extend((above + 1.0).min(clear_z))));
                poses.push(Pose::new(
                    MoveKind::Plunge,
                    start.extend(above),
                    DVec3::Z,
                    0.5 * opts.feed_mm_per_min,
                ));
                ramp(
                    lp,
                    above,
                    z,
                    opts.ramp_angle_rad.tan(),
                    &mut poses,
                    opts.feed_mm_per_min,
                );
            }
            for p in lp.iter().skip(1) {
                poses.push(cut(*p, z));
            }
        }
        above = z;
    }
    if let Some(p) = poses.last().copied() {
        poses.push(Pose::new(
            MoveKind::Rapid,
            p.tip.truncate().extend(clear_z),
            DVec3::Z,
            opts.feed_mm_per_min,
        ));
    }
    if contours == 0 {
        diagnostics.push(Diagnostic::warning(
            None,
            "no material to rough: every level is blocked by the part",
        ));
    }
    Ok(ZlevelPlan {
        toolpath: Toolpath::new(tool.clone(), poses),
        levels,
        contours,
        diagnostics,
    })
}

/// What a necked tool keeps between its holder face and the stock top, mm.
pub const HOLDER_CLEARANCE_MM: f64 = 1.0;

/// How far below the stock top `cutter` can cut a level, mm: its flute length (above the
/// flutes a shank as wide as the cut rubs the walls the levels above left), or, for a necked
/// tool (shank narrower than the cut, which stays inside the cut's walls), its length out of
/// the holder less [`HOLDER_CLEARANCE_MM`].
#[must_use]
pub fn reach_below_top_mm(cutter: &Cutter) -> f64 {
    if cutter.shank_diameter < cutter.diameter - 1e-9 {
        (cutter.overall_length - HOLDER_CLEARANCE_MM).max(cutter.flute_length)
    } else {
        cutter.flute_length
    }
}

/// Before planning: where roughing `stock` (the default around `part` when none) down to the
/// part's lowest point plus `stock_to_leave_axial_mm` would stop because `cutter` does not
/// reach that deep ([`reach_below_top_mm`]), in words; `None` when it reaches the whole depth.
#[must_use]
pub fn reach_note(
    cutter: &Cutter,
    stock: &Stock,
    part: &Aabb,
    stock_to_leave_axial_mm: f64,
) -> Option<String> {
    let blank = Blank::of(stock, part);
    let (top, floor) = (
        blank.top(),
        blank.bottom().max(part.min.z + stock_to_leave_axial_mm),
    );
    let reach = reach_below_top_mm(cutter);
    (top - floor > reach + 1e-9).then(|| {
        format!(
            "this tool reaches {reach:.3} mm below the stock top; the roughing is {:.3} mm deep \
             and stops at z = {:.3} mm",
            top - floor,
            top - reach
        )
    })
}

/// `levels` (top down) without those deeper below `top` than the tool reaches
/// ([`reach_below_top_mm`]), with a level at the deepest reachable height when some were
/// left out, and the warning that says so.
fn within_reach(levels: Vec<f64>, top: f64, cutter: &Cutter) -> (Vec<f64>, Option<Diagnostic>) {
    let reach = reach_below_top_mm(cutter);
    let deepest = top - reach;
    let Some(bottom) = levels.last().copied().filter(|z| *z < deepest - 1e-9) else {
        return (levels, None);
    };
    let cut_off = levels.iter().filter(|z| **z < deepest - 1e-9).count();
    let mut kept: Vec<f64> = levels
        .into_iter()
        .filter(|z| *z >= deepest - 1e-9)
        .collect();
    if kept.last().is_none_or(|z| *z > deepest + 1e-6) {
        kept.push(deepest);
    }
    let what = if cutter.shank_diameter < cutter.diameter - 1e-9 {
        format!(
            "its {:.3} mm out of the holder less {HOLDER_CLEARANCE_MM} mm",
            cutter.overall_length
        )
    } else {
        format!("its {:.3} mm flute length", cutter.flute_length)
    };
    let note = Diagnostic::warning(
        None,
        format!(
            "roughing stops at z = {deepest:.3} mm: the tool reaches {reach:.3} mm below the \
             stock top at z = {top:.3} mm ({what}); the {cut_off} levels below, down to \
             z = {bottom:.3} mm, need a tool that reaches {:.3} mm",
            top - bottom
        ),
    );
    (kept, Some(note))
}

/// The cutting levels, top down: every step-down from the blank's top to the stock bottom or the
/// part's lowest allowed height (its lowest point plus the axial stock to leave), a level facing
/// off the stock above the part's highest point, and with `detect_flats` one at each flat floor;
/// with the diagnostics that name the added levels. `lift` is the larger stock to leave, mm.
fn cutting_levels(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    blank: &Blank,
    opts: &ZlevelOptions,
    lift: f64,
    tool_radius: f64,
) -> (Vec<f64>, Vec<Diagnostic>) {
    let top = blank.top();
    let floor = blank
        .bottom()
        .max(bvh.bbox().min.z + opts.stock_to_leave_axial_mm);
    let mut levels = Vec::new();
    let mut z = top - opts.step_down_mm;
    while z > floor + 1e-9 {
        levels.push(z);
        z -= opts.step_down_mm;
    }
    if levels.last().is_none_or(|l| *l > floor + 1e-6) && floor < top {
        levels.push(floor);
    }
    let mut diagnostics = Vec::new();
    // Stock above the part's highest point is faced off to the allowance: without a level
    // there, a slab up to a whole step-down would stay on the part's top.
    let skim = bvh.bbox().max.z + lift;
    if skim < top - 1e-6
        && skim > floor
        && !levels
            .iter()
            .any(|l| *l >= skim - 1e-9 && *l <= skim + 1e-3)
    {
        diagnostics.push(Diagnostic::info(
            None,
            format!("top of the part: level added at z = {skim:.3}"),
        ));
        levels.push(skim);
        levels.sort_by(|a, b| b.total_cmp(a));
    }
    if opts.detect_flats {
        // On a flat floor the offset cutter's tip touches it, so the lowest allowed tip is the
        // floor plus the larger stock to leave (the radial stock is kept in every direction).
        let extra = flat_levels(mesh, &levels, lift, top, tool_radius);
        if !extra.is_empty() {
            diagnostics.push(Diagnostic::info(
                None,
                format!(
                    "flat areas: {} levels added at z = {}",
                    extra.len(),
                    extra
                        .iter()
                        .map(|z| format!("{z:.3}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
            levels.extend(extra);
            levels.sort_by(|a, b| b.total_cmp(a));
        }
    }
    (levels, diagnostics)
}

fn perimeter(lp: &[DVec2]) -> f64 {
    lp.windows(2)
        .map(|w| match w {
            [a, b] => a.distance(*b),
            _ => 0.0,
        })
        .sum()
}

/// Does the straight XY move stay where the distance field is at least `d0` (sampled at a
/// quarter grid step)?
fn segment_free(field: &Field, a: DVec2, b: DVec2, d0: f64) -> bool {
    let n = (a.distance(b) / (0.25 * field.step)).ceil().max(1.0) as usize;
    (0..=n).all(|i| {
        let p = a + (b - a) * (i as f64 / n as f64);
        let f = (p - field.origin) / field.step;
        let (i0, j0) = (f.x.floor(), f.y.floor());
        if !(i0 >= 0.0 && j0 >= 0.0) {
            return false;
        }
        let (i0, j0) = (i0 as usize, j0 as usize);
        let at = |i: usize, j: usize| {
            if i < field.nx && j < field.ny {
                field.values.get(j * field.nx + i).copied().unwrap_or(0.0)
            } else {
                0.0
            }
        };
        // The smallest of the four corners: conservative.
        at(i0, j0)
            .min(at(i0 + 1, j0))
            .min(at(i0, j0 + 1))
            .min(at(i0 + 1, j0 + 1))
            >= d0 - 0.5 * field.step
    })
}

/// Ramp along the closed loop `lp` (its last point equal to its first) from `z_from` down to
/// `z_to` at slope `k` (dz/dxy), going round as often as needed; ends back at the loop's start
/// at `z_to`. Pushes cutting moves from the loop's start at `z_from` (not pushed) onwards.
/// Shared with the waterline's ramp entry.
pub(crate) fn ramp(lp: &[DVec2], z_from: f64, z_to: f64, k: f64, out: &mut Vec<Pose>, feed: f64) {
    let per = perimeter(lp);
    if !(per > 0.0) || !(k > 0.0) || z_from <= z_to {
        return;
    }
    let mut z = z_from;
    let mut laps = 0;
    while z > z_to + 1e-9 && laps < 1000 {
        laps += 1;
        for w in lp.windows(2) {
            let [a, b] = w else { continue };
            if z <= z_to + 1e-12 {
                out.push(Pose::new(MoveKind::Cut, b.extend(z_to), DVec3::Z, feed));
                continue;
            }
            let len = a.distance(*b);
            let nz = z - k * len;
            if nz <= z_to {
                let f = (z - z_to) / (k * len).max(1e-300);
                out.push(Pose::new(
                    MoveKind::Cut,
                    (*a + (*b - *a) * f.clamp(0.0, 1.0)).extend(z_to),
                    DVec3::Z,
                    feed,
                ));
                z = z_to;
                // Finish this lap at the level so the loop then starts from its first point.
                out.push(Pose::new(MoveKind::Cut, b.extend(z_to), DVec3::Z, feed));
                continue;
            }
            z = nz;
            out.push(Pose::new(MoveKind::Cut, b.extend(z), DVec3::Z, feed));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stocks_resolve_and_measure() {
        let part = Aabb {
            min: DVec3::new(0.0, 0.0, 0.0),
            max: DVec3::new(30.0, 40.0, 10.0),
        };
        // The default box: the part's box plus 2 mm on the sides.
        let b = Blank::of(&Stock::None, &part);
        assert!((b.outside_by(DVec2::new(35.0, 46.0)) - 5.0).abs() < 1e-12);
        assert!((b.outside_by(DVec2::new(10.0, 20.0)) + 12.0).abs() < 1e-12);
        assert_eq!((b.bottom(), b.top()), (0.0, 12.0));
        let c = Blank::of(&Stock::default_cylinder_for(&part), &part);
        assert!((c.outside_by(DVec2::new(15.0, 20.0)) + 27.0).abs() < 1e-12);
        let c = Blank::of(
            &Stock::Cylinder {
                base_mm: [0.0, 0.0, -1.0],
                radius_mm: 10.0,
                height_mm: 6.0,
            },
            &part,
        );
        assert_eq!((c.bottom(), c.top()), (-1.0, 5.0));
    }
}
