//! Geometry kernel and import benchmarks: STEP import of pocket-fillets.stp (parse + B-rep, and
//! with tessellation), surface evaluations per second (point + derivatives to second order),
//! closest-point queries per second. Compare import time with Open CASCADE via
//! `benches/occt_import.py` run on the same machine (see benches/README.md).

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use talas::geometry::DVec3;
use talas::geometry::surface::SurfaceGeom;
use talas::geometry::tessellate::{TessellationOptions, tessellate_part};
use talas::import::step::read_step;

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn first_surface(file: &str) -> SurfaceGeom {
    let part = read_step(&data(file)).expect("test part reads");
    part.faces.into_iter().next().expect("one face").surface
}

fn import(c: &mut Criterion) {
    let file = std::env::var_os("TALAS_BENCH_STEP")
        .map_or_else(|| data("pocket-fillets.stp"), std::path::PathBuf::from);
    let mut g = c.benchmark_group("step_import");
    g.sample_size(20);
    g.bench_function("read_step", |b| {
        b.iter(|| black_box(read_step(&file).expect("reads")))
    });
    g.bench_function("read_step + tessellate 0.01 mm", |b| {
        b.iter(|| {
            let part = read_step(&file).expect("reads");
            black_box(tessellate_part(&part, &TessellationOptions::default()))
        });
    });
    g.finish();
}

fn evaluation(c: &mut Criterion) {
    let mut g = c.benchmark_group("surface_eval");
    for file in ["bicubic-hills.stp", "rational-trough.stp"] {
        let s = first_surface(file);
        let d = s.domain();
        let n = 64usize;
        g.throughput(Throughput::Elements((n * n) as u64));
        g.bench_function(format!("{file} derivs 2nd order"), |b| {
            b.iter(|| {
                let mut acc = DVec3::ZERO;
                for i in 0..n {
                    for j in 0..n {
                        let der = s.derivs(
                            d.u.lerp(i as f64 / (n - 1) as f64),
                            d.v.lerp(j as f64 / (n - 1) as f64),
                        );
                        acc += der.p + der.suu;
                    }
                }
                black_box(acc)
            });
        });
    }
    g.finish();
}

fn closest_point(c: &mut Criterion) {
    let mut g = c.benchmark_group("closest_point");
    g.sample_size(20);
    for file in ["bicubic-hills.stp", "rational-trough.stp"] {
        let s = first_surface(file);
        let d = s.domain();
        // Query points 2 mm off the surface along its normal on a 16×16 grid.
        let queries: Vec<DVec3> = (0..16)
            .flat_map(|i| (0..16).map(move |j| (i, j)))
            .map(|(i, j)| {
                let der = s.derivs(
                    d.u.lerp((i as f64 + 0.5) / 16.0),
                    d.v.lerp((j as f64 + 0.5) / 16.0),
                );
                der.p + der.normal().unwrap_or(DVec3::Z) * 2.0
            })
            .collect();
        g.throughput(Throughput::Elements(queries.len() as u64));
        g.bench_function(format!("{file} closest_point (no hint)"), |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for q in &queries {
                    acc += s.closest_point(*q, d, None).distance;
                }
                black_box(acc)
            });
        });
    }
    g.finish();
}

criterion_group!(benches, import, evaluation, closest_point);
criterion_main!(benches);
