//! Drop-cutter throughput (points per second) on `bicubic-hills.stl` for ball, flat, bull-nose and
//! cone cutters over a 100×100 grid, and raster finishing planning time on the same part (and on
//! `pocket-fillets.stl`), with the plan's passes, cut length and predicted scallop printed once
//! before timing. `benches/dropcutter_ocl.py` compares heights and times with OpenCAMLib's
//! BatchDropCutter on the same machine.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use talas::geometry::DVec2;
use talas::geometry::bvh::MeshBvh;
use talas::import::stl::{StlOptions, read_stl};
use talas::strategies::raster::{RasterOptions, raster};
use talas::toolpath::ToolRecord;
use talas::tools::dropcutter::drop_cutter;
use talas::tools::parse_tool_spec;

fn dropcutter(c: &mut Criterion) {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bicubic-hills.stl");
    let stl = read_stl(&file, &StlOptions::default()).expect("test mesh reads");
    let bvh = MeshBvh::new(&stl.mesh).expect("test mesh has triangles");
    let bb = bvh.bbox();
    let n = 100usize;
    let pts: Vec<DVec2> = (0..n * n)
        .map(|k| {
            let (i, j) = ((k % n) as f64, (k / n) as f64);
            DVec2::new(
                bb.min.x + (bb.max.x - bb.min.x) * i / (n - 1) as f64,
                bb.min.y + (bb.max.y - bb.min.y) * j / (n - 1) as f64,
            )
        })
        .collect();
    let mut g = c.benchmark_group("dropcutter");
    g.sample_size(10);
    g.throughput(Throughput::Elements(pts.len() as u64));
    for spec in [
        "ball:d=6",
        "flat:d=10",
        "bull:d=10,r=2",
        "cone:d=10,angle=45",
    ] {
        let cutter = parse_tool_spec(spec).expect("valid spec");
        g.bench_function(format!("bicubic-hills {spec}"), |b| {
            b.iter(|| black_box(drop_cutter(&bvh, &stl.mesh, &cutter, &pts)));
        });
    }
    g.finish();
}

/// Raster finishing of the whole of bicubic-hills and pocket-fillets with a Ø6 ball (scallop
/// 0.02 and 0.05 mm, chord 0.01 mm, passes along +X): planning time, drop-cutter included.
fn raster_planning(c: &mut Criterion) {
    let tool = ToolRecord {
        spec: "ball:d=6".into(),
        cutter: parse_tool_spec("ball:d=6").expect("valid spec"),
    };
    let mut g = c.benchmark_group("raster");
    g.sample_size(10);
    for (part, h) in [
        ("bicubic-hills", 0.02),
        ("bicubic-hills", 0.05),
        ("pocket-fillets", 0.05),
    ] {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/data/{part}.stl"));
        let stl = read_stl(&file, &StlOptions::default()).expect("test mesh reads");
        let bvh = MeshBvh::new(&stl.mesh).expect("test mesh has triangles");
        let opts = RasterOptions {
            scallop_mm: h,
            chord_tol_mm: 0.01,
            ..RasterOptions::default()
        };
        if let Ok(plan) = raster(&stl.mesh, &bvh, &tool, &opts) {
            let m = &plan.toolpath.summary;
            eprintln!(
                "raster {part} h {h}: passes {}, poses {}, cut {:.0} mm, predicted max scallop {:.4} mm",
                plan.passes, m.pose_count, m.cut_length_mm, plan.max_predicted_scallop_mm
            );
        }
        g.bench_function(format!("{part} ball:d=6 h={h}"), |b| {
            b.iter(|| black_box(raster(&stl.mesh, &bvh, &tool, &opts)));
        });
    }
    g.finish();
}

criterion_group!(benches, dropcutter, raster_planning);
criterion_main!(benches);
