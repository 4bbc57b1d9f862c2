//! Waterline contours for the OpenCAMLib comparison (`benches/waterline_ocl.py`), or a timing
//! run on its own.
//!
//! `cargo bench --no-default-features --bench waterline -- STL SPEC SAMPLING Z1,Z2,... OUT.csv`
//! writes every contour point as `level,loop,x,y,z` and prints the planning time (BVH build
//! plus all levels) in seconds as `time_s=T`. Without arguments it times a ball d=6 on
//! `tests/data/bicubic-hills.stl` at ten levels.

use std::io::Write;
use std::time::Instant;

use talas::geometry::bvh::MeshBvh;
use talas::import::stl::{StlOptions, read_stl};
use talas::strategies::waterline::contours_at;
use talas::tools::parse_tool_spec;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).filter(|a| a != "--bench").collect();
    let (stl, spec, sampling, levels, out) = if args.len() >= 5 {
        let levels: Result<Vec<f64>, _> = args[3].split(',').map(str::parse::<f64>).collect();
        (
            args[0].clone(),
            args[1].clone(),
            args[2].parse::<f64>()?,
            levels?,
            Some(args[4].clone()),
        )
    } else {
        let z: Vec<f64> = (0..10).map(|k| 1.0 + 1.5 * f64::from(k)).collect();
        ("tests/data/bicubic-hills.stl".into(), "ball:d=6".into(), 0.1, z, None)
    };
    let mesh = read_stl(std::path::Path::new(&stl), &StlOptions::default())?.mesh;
    let cutter = parse_tool_spec(&spec)?;
    let t0 = Instant::now();
    let bvh = MeshBvh::new(&mesh)?;
    let all: Vec<_> = levels
        .iter()
        .map(|&z| contours_at(&mesh, &bvh, &cutter, z, sampling))
        .collect();
    let dt = t0.elapsed().as_secs_f64();
    let points: usize = all.iter().flatten().map(Vec::len).sum();
    println!("time_s={dt:.4} levels={} points={points}", levels.len());
    if let Some(out) = out {
        let mut f = std::io::BufWriter::new(std::fs::File::create(out)?);
        for (k, loops) in all.iter().enumerate() {
            for (l, lp) in loops.iter().enumerate() {
                for p in lp {
                    writeln!(f, "{k},{l},{:.12},{:.12},{:.12}", p.tip.x, p.tip.y, p.tip.z)?;
                }
            }
        }
    }
    Ok(())
}
