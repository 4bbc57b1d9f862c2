//! Planning time of 5-axis finishing on real parts with the whole part as check and the
//! tilt-away on (30°, 2°/mm): a trimmed face (`Schenkel.stp` sphere face 291), a fillet
//! (`pocket-fillets.stp` floor fillet face 13, a 5 mm quarter cylinder) and a 20-face group
//! (the 20 largest non-planar faces of `Schenkel.stp`). Ball Ø6, iso-scallop, h = 0.05 mm,
//! ε = 0.01 mm, exact check on. Prints poses, spans left out, whole-part hits and the wall
//! time of each case (best and median of `N` runs).
//!
//! `cargo run --release --no-default-features --example finish_times -- [N]`

use std::path::{Path, PathBuf};
use std::time::Instant;

use talas::checks::part::PartCheck;
use talas::geometry::brep::Part;
use talas::geometry::surface::SurfaceGeom;
use talas::geometry::tessellate::{TessellationOptions, tessellate_part};
use talas::geometry::trim::TrimRegion;
use talas::import::step::read_step;
use talas::import::{OpenOptions, Workpiece};
use talas::strategies::finish::face::FacePatch;
use talas::strategies::finish::group::plan_group;
use talas::strategies::finish::plan::plan_finish_in;
use talas::strategies::finish::tiltaway::{PartContext, TiltAway};
use talas::strategies::finish::{FinishOptions, Strategy};
use talas::tools::{Cutter, parse_tool_spec};

const SPEC: &str = "ball:d=6";

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn opts() -> FinishOptions {
    FinishOptions {
        scallop: 0.05,
        tolerance: 0.01,
        exact_check: true,
        ..FinishOptions::default()
    }
}

/// One plan of `faces` (one face: `plan_finish_in`, more: `plan_group`): (poses, left out, hits).
fn plan(
    wp: &Workpiece,
    part: &Part,
    faces: &[usize],
    cutter: &Cutter,
) -> Result<(usize, usize, usize), String> {
    let bvh = wp.bvh().map_err(|e| e.to_string())?;
    let context = PartContext {
        check: PartCheck::of_workpiece(wp, &bvh, faces),
        tilt: Some(TiltAway::default()),
    };
    if let [face] = faces {
        let region = TrimRegion::of_face(&part.faces[*face], part, 0.002)?;
        let patch = FacePatch::trimmed(part, *face, &region).map_err(|e| e.to_string())?;
        let r = plan_finish_in(
            patch,
            cutter,
            SPEC,
            Strategy::IsoScallop,
            &opts(),
            Some(&context),
        )
        .map_err(|e| e.to_string())?;
        Ok((r.toolpath.poses.len(), r.left_out.len(), r.part_hits.len()))
    } else {
        let r = plan_group(
            part,
            faces,
            cutter,
            SPEC,
            Strategy::IsoScallop,
            &opts(),
            Some(&context),
        )
        .map_err(|(f, e)| format!("face {f}: {e}"))?;
        Ok((r.toolpath.poses.len(), r.left_out.len(), r.part_hits.len()))
    }
}

fn time(
    name: &str,
    file: &str,
    faces: &[usize],
    cutter: &Cutter,
    runs: usize,
) -> Result<(), String> {
    let part = read_step(&data(file)).map_err(|e| e.to_string())?;
    let wp = Workpiece::from_part(&data(file), part.clone(), &OpenOptions::default());
    let mut times = Vec::new();
    let mut last = (0, 0, 0);
    for _ in 0..runs {
        let t0 = Instant::now();
        last = plan(&wp, &part, faces, cutter)?;
        times.push(t0.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    println!(
        "{name}: {} faces, {} poses, {} spans left out, {} whole-part hits; best {:.2} s, median {:.2} s ({runs} runs)",
        faces.len(),
        last.0,
        last.1,
        last.2,
        times[0],
        times[times.len() / 2]
    );
    Ok(())
}

/// The `n` largest non-planar faces of `part`, by tessellated area.
fn largest_curved(part: &Part, n: usize) -> Vec<usize> {
    let mesh = tessellate_part(part, &TessellationOptions::default());
    let mut faces: Vec<(usize, f64)> = (0..part.faces.len())
        .filter(|&i| !matches!(part.faces[i].surface, SurfaceGeom::Plane(_)))
        .filter_map(|i| mesh.faces.get(i).map(|f| (i, f.area_mm2)))
        .collect();
    faces.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    faces.into_iter().take(n).map(|(i, _)| i).collect()
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(3)
        .max(1);
    let Ok(cutter) = parse_tool_spec(SPEC) else {
        eprintln!("bad tool spec {SPEC}");
        std::process::exit(2);
    };
    let schenkel = "real/freecad/Schenkel.stp";
    let group = match read_step(&data(schenkel)) {
        Ok(p) => largest_curved(&p, 20),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let cases: [(&str, &str, Vec<usize>); 3] = [
        ("trimmed sphere face (Schenkel 291)", schenkel, vec![291]),
        ("fillet (pocket-fillets 13)", "pocket-fillets.stp", vec![13]),
        ("20-face group (Schenkel)", schenkel, group),
    ];
    for (name, file, faces) in &cases {
        if let Err(e) = time(name, file, faces, &cutter, runs) {
            eprintln!("{file}: {e}");
            std::process::exit(2);
        }
    }
}
