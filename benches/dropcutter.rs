//! Drop-cutter throughput (points per second) on `bicubic-hills.stl` for ball, flat, bull-nose and
//! cone cutters over a 100×100 grid, and raster finishing planning time on the same part. `benches/dropcutter_ocl.py` compares heights and times with
//! OpenCAMLib's BatchDropCutter on the same machine.

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

/// Raster finishing of the whole of bicubic-hills with a Ø6 ball (scallop 0.02 mm, chord
/// 0.01 mm): planning time, drop-cutter included.
fn raster_planning(c: &mut Criterion) {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bicubic-hills.stl");
    let stl = read_stl(&file, &StlOptions::default()).expect("test mesh reads");
    let bvh = MeshBvh::new(&stl.mesh).expect("test mesh has triangles");
    let tool = ToolRecord {
        spec: "ball:d=6".into(),
        cutter: parse_tool_spec("ball:d=6").expect("valid spec"),
    };
    let opts = RasterOptions {
        scallop_mm: 0.02,
        chord_tol_mm: 0.01,
        ..RasterOptions::default()
    };
    let mut g = c.benchmark_group("raster");
    g.sample_size(10);
    g.bench_function("bicubic-hills ball:d=6 h=0.02", |b| {
        b.iter(|| black_box(raster(&stl.mesh, &bvh, &tool, &opts)));
    });
    g.finish();
}

criterion_group!(benches, dropcutter, raster_planning);
criterion_main!(benches);
