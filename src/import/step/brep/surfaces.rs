//! Face surfaces: `PLANE`, `CYLINDRICAL_SURFACE`, `CONICAL_SURFACE`, `SPHERICAL_SURFACE`,
//! `TOROIDAL_SURFACE`, `SURFACE_OF_REVOLUTION`, `SURFACE_OF_LINEAR_EXTRUSION`, B-spline surfaces
//! (with knots, Bézier, uniform, quasi-uniform, rational complex instances) and
//! `RECTANGULAR_TRIMMED_SURFACE` (its basis surface). Anything else is
//! [`ErrorKind::Unsupported`].

use std::f64::consts::FRAC_PI_2;

use super::curves::curve;
use super::entities::Entity;
use super::points::Geo;
use super::splines::{KnotSpec, check_weights, degree, knot_vector};
use super::{BrepError, ErrorKind};
use crate::geometry::nurbs::BSplineSurface;
use crate::geometry::surface::{
    Cone, Cylinder, Extrusion, Plane, Revolution, Sphere, SurfaceGeom, Torus,
};

/// Deepest chain of basis surfaces followed.
const MAX_SURFACE_DEPTH: usize = 8;

/// The surface `#id` referred to by `from`, in mm.
pub(super) fn surface(
    geo: &Geo<'_, '_>,
    from: Entity<'_>,
    id: u64,
    depth: usize,
) -> Result<SurfaceGeom, BrepError> {
    let e = geo.entity(from, id)?;
    if depth > MAX_SURFACE_DEPTH {
        return Err(e.error(
            ErrorKind::Cycle,
            "surface definitions nest too deeply (self reference?)",
        ));
    }
    if e.has("PLANE") {
        let frame = geo.placement(e, e.args("PLANE")?.reference(1, "position")?)?;
        return Ok(SurfaceGeom::Plane(Plane { frame }));
    }
    if e.has("CYLINDRICAL_SURFACE") {
        let a = e.args("CYLINDRICAL_SURFACE")?;
        let frame = geo.placement(e, a.reference(1, "position")?)?;
        let radius = geo.positive_length(e, a.real(2, "radius")?, "radius")?;
        return Ok(SurfaceGeom::Cylinder(Cylinder { frame, radius }));
    }
    if e.has("CONICAL_SURFACE") {
        let a = e.args("CONICAL_SURFACE")?;
        let frame = geo.placement(e, a.reference(1, "position")?)?;
        let radius = geo.length(a.real(2, "radius")?);
        let semi_angle = a.real(3, "semi_angle")? * geo.units.angle_rad;
        if !(radius >= 0.0 && radius.is_finite()) {
            return Err(e.error(
                ErrorKind::InvalidGeometry,
                "cone radius must not be negative",
            ));
        }
        if !(semi_angle.abs() > 0.0 && semi_angle.abs() < FRAC_PI_2) {
            return Err(e.error(
                ErrorKind::InvalidGeometry,
                format!("cone semi-angle {semi_angle} rad is outside (0, π/2)"),
            ));
        }
        return Ok(SurfaceGeom::Cone(Cone {
            frame,
            radius,
            semi_angle,
        }));
    }
    if e.has("SPHERICAL_SURFACE") {
        let a = e.args("SPHERICAL_SURFACE")?;
        let frame = geo.placement(e, a.reference(1, "position")?)?;
        let radius = geo.positive_length(e, a.real(2, "radius")?, "radius")?;
        return Ok(SurfaceGeom::Sphere(Sphere { frame, radius }));
    }
    if let Ok(a) = e.args_any(&["TOROIDAL_SURFACE", "DEGENERATE_TOROIDAL_SURFACE"]) {
        let frame = geo.placement(e, a.reference(1, "position")?)?;
        let major_radius = geo.length(a.real(2, "major_radius")?);
        let minor_radius = geo.positive_length(e, a.real(3, "minor_radius")?, "minor radius")?;
        if !(major_radius >= 0.0 && major_radius.is_finite()) {
            return Err(e.error(
                ErrorKind::InvalidGeometry,
                "torus major radius must not be negative",
            ));
        }
        return Ok(SurfaceGeom::Torus(Torus {
            frame,
            major_radius,
            minor_radius,
        }));
    }
    if e.has("SURFACE_OF_REVOLUTION") {
        let a = e.args("SURFACE_OF_REVOLUTION")?;
        let meridian = curve(geo, e, a.reference(1, "swept_curve")?, depth + 1)?;
        let (axis_origin, axis_dir) = geo.axis1(e, a.reference(2, "axis_position")?)?;
        return Ok(SurfaceGeom::Revolution(Revolution {
            meridian: Box::new(meridian),
            axis_origin,
            axis_dir,
        }));
    }
    if e.has("SURFACE_OF_LINEAR_EXTRUSION") {
        let a = e.args("SURFACE_OF_LINEAR_EXTRUSION")?;
        let profile = curve(geo, e, a.reference(1, "swept_curve")?, depth + 1)?;
        let dir = geo.vector_dir(e, a.reference(2, "extrusion_axis")?)?;
        return Ok(SurfaceGeom::Extrusion(Extrusion {
            profile: Box::new(profile),
            dir,
        }));
    }
    if e.has("RECTANGULAR_TRIMMED_SURFACE") {
        let basis = e
            .args("RECTANGULAR_TRIMMED_SURFACE")?
            .reference(1, "basis_surface")?;
        return surface(geo, e, basis, depth + 1);
    }
    if let Some(s) = bspline_surface(geo, e)? {
        return Ok(SurfaceGeom::BSpline(s));
    }
    let is_surface = e
        .inst
        .records
        .iter()
        .any(|r| r.name.contains("SURFACE") && !r.name.contains("CURVE"));
    Err(if is_surface {
        e.error(
            ErrorKind::Unsupported,
            format!("unsupported surface type {}", e.type_name()),
        )
    } else {
        e.error(
            ErrorKind::WrongType,
            format!("expected a surface, found {}", e.type_name()),
        )
    })
}

/// Degrees, control-point grid and knot forms of a B-spline surface entity.
struct SurfaceArgs {
    deg_u: i64,
    deg_v: i64,
    grid: Vec<Vec<u64>>,
    spec_u: KnotSpec,
    spec_v: KnotSpec,
}

fn surface_args(e: Entity<'_>) -> Result<Option<SurfaceArgs>, BrepError> {
    if e.has("B_SPLINE_SURFACE") {
        // Complex instance: B_SPLINE_SURFACE(u_degree, v_degree, points, form, u_closed, v_closed,
        // self_intersect) plus the knot form.
        let a = e.args("B_SPLINE_SURFACE")?;
        let (spec_u, spec_v) = if e.has("B_SPLINE_SURFACE_WITH_KNOTS") {
            let k = e.args("B_SPLINE_SURFACE_WITH_KNOTS")?;
            (
                KnotSpec::Explicit {
                    mults: k.ints(0, "u_multiplicities")?,
                    knots: k.reals(2, "u_knots")?,
                },
                KnotSpec::Explicit {
                    mults: k.ints(1, "v_multiplicities")?,
                    knots: k.reals(3, "v_knots")?,
                },
            )
        } else if e.has("BEZIER_SURFACE") {
            (KnotSpec::Bezier, KnotSpec::Bezier)
        } else if e.has("QUASI_UNIFORM_SURFACE") {
            (KnotSpec::QuasiUniform, KnotSpec::QuasiUniform)
        } else if e.has("UNIFORM_SURFACE") {
            (KnotSpec::Uniform, KnotSpec::Uniform)
        } else {
            return Err(e.error(
                ErrorKind::Unsupported,
                "B_SPLINE_SURFACE without a knot form",
            ));
        };
        return Ok(Some(SurfaceArgs {
            deg_u: a.int(0, "u_degree")?,
            deg_v: a.int(1, "v_degree")?,
            grid: a.ref_grid(2, "control_points_list")?,
            spec_u,
            spec_v,
        }));
    }
    if let Ok(k) = e.args("B_SPLINE_SURFACE_WITH_KNOTS") {
        return Ok(Some(SurfaceArgs {
            deg_u: k.int(1, "u_degree")?,
            deg_v: k.int(2, "v_degree")?,
            grid: k.ref_grid(3, "control_points_list")?,
            spec_u: KnotSpec::Explicit {
                mults: k.ints(8, "u_multiplicities")?,
                knots: k.reals(10, "u_knots")?,
            },
            spec_v: KnotSpec::Explicit {
                mults: k.ints(9, "v_multiplicities")?,
                knots: k.reals(11, "v_knots")?,
            },
        }));
    }
    if let Ok(a) = e.args_any(&["BEZIER_SURFACE", "UNIFORM_SURFACE", "QUASI_UNIFORM_SURFACE"]) {
        let spec = match a.rec.name.as_str() {
            "BEZIER_SURFACE" => KnotSpec::Bezier,
            "UNIFORM_SURFACE" => KnotSpec::Uniform,
            _ => KnotSpec::QuasiUniform,
        };
        return Ok(Some(SurfaceArgs {
            deg_u: a.int(1, "u_degree")?,
            deg_v: a.int(2, "v_degree")?,
            grid: a.ref_grid(3, "control_points_list")?,
            spec_u: spec.clone(),
            spec_v: spec,
        }));
    }
    Ok(None)
}

/// A B-spline surface in any of its forms; `None` when `e` is not one.
fn bspline_surface(geo: &Geo<'_, '_>, e: Entity<'_>) -> Result<Option<BSplineSurface>, BrepError> {
    let Some(s) = surface_args(e)? else {
        return Ok(None);
    };
    let bad = |m: String| e.error(ErrorKind::InvalidGeometry, m);
    let degree_u = degree(s.deg_u).map_err(bad)?;
    let degree_v = degree(s.deg_v).map_err(bad)?;
    let n_u = s.grid.len();
    let n_v = s.grid.first().map_or(0, Vec::len);
    if s.grid.iter().any(|row| row.len() != n_v) {
        return Err(bad("control point rows differ in length".into()));
    }
    let knots_u = knot_vector(&s.spec_u, n_u, degree_u).map_err(|m| bad(format!("u: {m}")))?;
    let knots_v = knot_vector(&s.spec_v, n_v, degree_v).map_err(|m| bad(format!("v: {m}")))?;
    let poles = s
        .grid
        .iter()
        .flatten()
        .map(|&id| geo.point(e, id))
        .collect::<Result<Vec<_>, _>>()?;
    let weights = if e.has("RATIONAL_B_SPLINE_SURFACE") {
        let rows = e
            .args("RATIONAL_B_SPLINE_SURFACE")?
            .real_grid(0, "weights_data")?;
        if rows.len() != n_u || rows.iter().any(|r| r.len() != n_v) {
            return Err(bad(format!(
                "weights grid does not match the {n_u}×{n_v} control points"
            )));
        }
        let w: Vec<f64> = rows.into_iter().flatten().collect();
        check_weights(&w, n_u * n_v).map_err(bad)?;
        Some(w)
    } else {
        None
    };
    BSplineSurface::new(
        degree_u, degree_v, knots_u, knots_v, n_u, n_v, poles, weights,
    )
    .map(Some)
    .map_err(|err| bad(err.to_string()))
}
