//! `talas inspect FILE [--samples N] [--tolerance MM] [--json]`: a part summary (faces, area,
//! bounding box, triangles, closedness and volume), optionally with the surface evaluated on an
//! N×N grid of every B-spline face's own parameter domain.

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use crate::diagnostics::{Diagnostic, Severity};
use crate::geometry::brep::Face;
use crate::geometry::mesh::TriMesh;
use crate::geometry::surface::SurfaceGeom;
use crate::geometry::tessellate::{PartMesh, TessellationOptions, tessellate_part};
use crate::geometry::{Aabb, DVec3};
use crate::import::ImportError;
use crate::import::step::read_step;
use crate::import::stl::{StlOptions, read_stl};

/// Options of `talas inspect`.
#[derive(Debug, clap::Args)]
pub struct InspectArgs {
    /// The part: STEP (.stp/.step) or STL (.stl).
    pub file: PathBuf,
    /// Evaluate every B-spline face on an N×N grid of its parameter domain (N ≥ 2): rows of
    /// u, v, point (mm), unit normal and principal curvatures (1/mm). The normal is the face's
    /// outward normal: the surface normal S_u × S_v, reversed on a face whose same_sense is .F.;
    /// the curvatures are signed with respect to it (negative where the face bends away from its
    /// normal, as on a convex solid).
    #[arg(long, value_name = "N")]
    pub samples: Option<usize>,
    /// Chord tolerance of the tessellation, mm [default: 0.01, or 1e-4 of the part's size when
    /// smaller].
    #[arg(long, value_name = "MM")]
    pub tolerance: Option<f64>,
    /// Print one JSON document instead of the human summary.
    #[arg(long)]
    pub json: bool,
}

/// The finest chord tolerance `--tolerance` accepts, mm.
const MIN_TOLERANCE_MM: f64 = 1e-4;

/// What `inspect` found, as JSON (the contract's shape).
///
/// # Errors
/// The import error (file and place) when the file cannot be read.
pub fn inspect(args: &InspectArgs) -> Result<Value, ImportError> {
    if let Some(n) = args.samples
        && !(2..=1000).contains(&n)
    {
        return Err(ImportError::new(
            &args.file,
            None,
            format!("--samples must be between 2 and 1000, got {n}"),
        ));
    }
    if let Some(t) = args
        .tolerance
        .filter(|t| !(MIN_TOLERANCE_MM..=100.0).contains(t))
    {
        return Err(ImportError::new(
            &args.file,
            None,
            format!(
                "--tolerance must be between {MIN_TOLERANCE_MM} mm (0.1 µm, far below any \
                 machine's resolution) and 100 mm, got {t}"
            ),
        ));
    }
    if is_stl(&args.file) {
        inspect_stl(&args.file)
    } else {
        inspect_step(args)
    }
}

fn is_stl(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("stl"))
}

fn inspect_step(args: &InspectArgs) -> Result<Value, ImportError> {
    let part = read_step(&args.file)?;
    let opts = args.tolerance.map_or_else(
        || TessellationOptions::for_size(part.rough_bbox().diagonal()),
        TessellationOptions::with_chord_tol,
    );
    let pm = tessellate_part(&part, &opts);
    let faces: Vec<Value> = part
        .faces
        .iter()
        .enumerate()
        .map(|(i, f)| face_json(i, f, &pm, args.samples))
        .collect();
    let mut diagnostics: Vec<Diagnostic> = part.diagnostics.clone();
    diagnostics.extend(pm.diagnostics.iter().cloned());
    let mut doc = mesh_summary(&pm.mesh);
    doc["file"] = json!(args.file.display().to_string());
    doc["format"] = json!("step");
    doc["name"] = json!(part.name);
    doc["faces"] = Value::Array(faces);
    doc["area_mm2"] = json!(pm.area_mm2());
    doc["mesh_area_mm2"] = json!(pm.faces.iter().map(|f| f.mesh_area_mm2).sum::<f64>());
    doc["bodies"] = json!(
        pm.bodies
            .iter()
            .map(|b| json!({
                "shell": b.shell,
                "id": b.source_id,
                "faces": b.faces,
                "closed": b.closed,
                "volume_mm3": b.volume_mm3,
            }))
            .collect::<Vec<_>>()
    );
    // The volume enclosed by the exact faces when every body closes (the triangles' own
    // volume is short of it by about the chord tolerance times the area).
    doc["mesh_volume_mm3"] = doc["volume_mm3"].clone();
    doc["volume_mm3"] = match pm.volume_mm3() {
        Some(v) => json!(v),
        None if pm.bodies.is_empty() => doc["mesh_volume_mm3"].clone(),
        None => Value::Null,
    };
    doc["shells"] = json!(
        part.shells
            .iter()
            .map(|s| json!({"faces": s.faces.len(), "closed": s.closed, "id": s.source_id}))
            .collect::<Vec<_>>()
    );
    doc["tolerance_mm"] = json!(opts.chord_tol_mm);
    doc["diagnostics"] = diagnostics_json(&diagnostics);
    Ok(doc)
}

fn inspect_stl(path: &Path) -> Result<Value, ImportError> {
    let stl = read_stl(path, &StlOptions::default())?;
    let mut doc = mesh_summary(&stl.mesh);
    doc["file"] = json!(path.display().to_string());
    doc["format"] = json!(format!(
        "stl-{}",
        format!("{:?}", stl.format).to_lowercase()
    ));
    doc["name"] = json!(stl.name);
    doc["faces"] = json!([]);
    doc["facets"] = json!(stl.facet_count);
    doc["degenerate_facets"] = json!(stl.degenerate_facets.len());
    doc["area_mm2"] = json!(stl.mesh.area());
    doc["diagnostics"] = diagnostics_json(&stl.diagnostics);
    Ok(doc)
}

/// Triangle count, bounding box, closedness and (when closed) volume of a mesh.
fn mesh_summary(mesh: &TriMesh) -> Value {
    let bbox = mesh.bbox();
    let mut welded = mesh.clone();
    welded.weld(1e-9 * bbox.diagonal().max(1.0));
    let closed = !welded.triangles.is_empty() && welded.is_closed();
    json!({
        "triangles": mesh.triangles.len(),
        "bbox": bbox_json(&bbox),
        "closed": closed,
        "volume_mm3": if closed { json!(welded.signed_volume().abs()) } else { Value::Null },
    })
}

fn bbox_json(b: &Aabb) -> Value {
    if b.is_empty() {
        Value::Null
    } else {
        json!({"min": [b.min.x, b.min.y, b.min.z], "max": [b.max.x, b.max.y, b.max.z]})
    }
}

fn finite_or_null(x: f64) -> Value {
    if x.is_finite() { json!(x) } else { Value::Null }
}

fn face_json(index: usize, face: &Face, pm: &PartMesh, samples: Option<usize>) -> Value {
    let s = &face.surface;
    let d = s.domain();
    let (degree, poles, rational) = match s {
        SurfaceGeom::BSpline(b) => (
            json!([b.degree_u, b.degree_v]),
            json!([b.n_u, b.n_v]),
            b.weights.is_some(),
        ),
        _ => (Value::Null, Value::Null, false),
    };
    let range = pm.faces.get(index);
    let mut v = json!({
        "index": index,
        "id": face.source_id,
        "kind": s.kind(),
        "degree": degree,
        "poles": poles,
        "rational": rational,
        "domain": [[finite_or_null(d.u.t0), finite_or_null(d.u.t1)], [finite_or_null(d.v.t0), finite_or_null(d.v.t1)]],
        "same_sense": face.same_sense,
        "area_mm2": range.map_or(0.0, |r| r.area_mm2),
        "triangles": range.map_or(0, |r| r.count),
    });
    if let (Some(n), SurfaceGeom::BSpline(_)) = (samples, s) {
        v["samples"] = Value::Array(sample_grid(s, n, face.same_sense));
    }
    v
}

/// `[u, v, x, y, z, nx, ny, nz, k_min, k_max]` on an N×N grid (i over u outer, j over v inner).
/// The normal is the face's outward normal: `S_u × S_v` when `same_sense`, else reversed; the
/// curvatures are signed with respect to it (Open CASCADE's `BRepLProp_SLProps` on the oriented
/// face gives the same), so on a `.F.` face both the normal and the curvatures change sign (and
/// the minimum and maximum swap) against the bare surface's.
#[must_use]
pub fn sample_grid(s: &SurfaceGeom, n: usize, same_sense: bool) -> Vec<Value> {
    let sign = if same_sense { 1.0 } else { -1.0 };
    let d = s.domain();
    let mut rows = Vec::with_capacity(n * n);
    for i in 0..n {
        let u = d.u.t0 + d.u.len() * i as f64 / (n - 1) as f64;
        for j in 0..n {
            let v = d.v.t0 + d.v.len() * j as f64 / (n - 1) as f64;
            let der = s.derivs(u, v);
            let nrm = sign * der.normal().unwrap_or(DVec3::ZERO);
            let (kmin, kmax) = der.principal().map_or((f64::NAN, f64::NAN), |p| {
                if same_sense {
                    (p.k_min, p.k_max)
                } else {
                    (-p.k_max, -p.k_min)
                }
            });
            let row = [
                u, v, der.p.x, der.p.y, der.p.z, nrm.x, nrm.y, nrm.z, kmin, kmax,
            ];
            rows.push(Value::Array(
                row.iter().map(|&x| finite_or_null(x)).collect(),
            ));
        }
    }
    rows
}

fn diagnostics_json(ds: &[Diagnostic]) -> Value {
    Value::Array(
        ds.iter()
            .map(|d| json!({"severity": d.severity, "place": d.place, "message": d.message}))
            .collect(),
    )
}

/// The human summary of an inspect result.
#[must_use]
pub fn human(doc: &Value) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let f = |v: &Value| {
        v.as_f64()
            .map_or_else(|| "-".to_string(), |x| format!("{x:.4}"))
    };
    let _ = writeln!(
        s,
        "{} ({})",
        doc["file"].as_str().unwrap_or(""),
        doc["format"].as_str().unwrap_or("")
    );
    if let Some(faces) = doc["faces"].as_array().filter(|a| !a.is_empty()) {
        let _ = writeln!(s, "faces: {}", faces.len());
        let mut kinds: std::collections::BTreeMap<&str, usize> = std::collections::BTreeMap::new();
        for face in faces {
            *kinds
                .entry(face["kind"].as_str().unwrap_or("?"))
                .or_default() += 1;
        }
        let _ = writeln!(
            s,
            "  by kind: {}",
            kinds
                .iter()
                .map(|(k, n)| format!("{n} {k}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        for face in faces.iter().take(50) {
            let extra = if face["kind"] == "bspline" {
                format!(
                    " degree {} poles {}{}",
                    face["degree"],
                    face["poles"],
                    if face["rational"] == true {
                        " rational"
                    } else {
                        ""
                    }
                )
            } else {
                String::new()
            };
            let _ = writeln!(
                s,
                "  [{}] #{} {}{} area {} mm²{}",
                face["index"],
                face["id"],
                face["kind"].as_str().unwrap_or("?"),
                extra,
                f(&face["area_mm2"]),
                if face["same_sense"] == false {
                    " (reversed)"
                } else {
                    ""
                }
            );
        }
        if faces.len() > 50 {
            let _ = writeln!(s, "  ... {} more", faces.len() - 50);
        }
    }
    if let Some(n) = doc["facets"].as_u64() {
        let _ = writeln!(s, "facets: {n} (degenerate: {})", doc["degenerate_facets"]);
    }
    let _ = writeln!(s, "area: {} mm²", f(&doc["area_mm2"]));
    if let Some(b) = doc["bbox"].as_object() {
        let p = |v: &Value| {
            v.as_array()
                .map(|a| a.iter().map(f).collect::<Vec<_>>().join(", "))
                .unwrap_or_default()
        };
        let _ = writeln!(
            s,
            "bounding box: ({}) – ({}) mm",
            p(&b["min"]),
            p(&b["max"])
        );
    }
    let _ = writeln!(s, "triangles: {}", doc["triangles"]);
    let _ = writeln!(
        s,
        "closed: {}{}",
        doc["closed"],
        doc["volume_mm3"]
            .as_f64()
            .map(|v| format!(", volume {v:.4} mm³"))
            .unwrap_or_default()
    );
    if let Some(bodies) = doc["bodies"].as_array().filter(|b| b.len() > 1) {
        for (k, b) in bodies.iter().enumerate() {
            let _ = writeln!(
                s,
                "  body {} (shell #{}, {} faces): {}",
                k + 1,
                b["id"],
                b["faces"],
                b["volume_mm3"].as_f64().map_or_else(
                    || "not closed".to_string(),
                    |v| format!("volume {v:.4} mm³")
                )
            );
        }
    }
    if let Some(ds) = doc["diagnostics"].as_array() {
        for d in ds {
            let _ = writeln!(
                s,
                "{}: {}{}",
                d["severity"].as_str().unwrap_or(""),
                d["place"]
                    .as_str()
                    .map(|p| format!("{p}: "))
                    .unwrap_or_default(),
                d["message"].as_str().unwrap_or("")
            );
        }
    }
    s
}

/// Does this diagnostic list carry errors?
#[must_use]
pub fn has_errors(ds: &[Diagnostic]) -> bool {
    ds.iter().any(|d| d.severity == Severity::Error)
}
