//! Planning time of iso-scallop and two-way iso-parametric finishing on `bicubic-hills.stp`
//! with a 6 mm ball at h = 0.01 mm, ε = 0.005 mm (issue 4). Prints a table of cut length,
//! poses, time at feed and predicted max scallop per strategy once before timing.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use talas::import::step::read_step;
use talas::strategies::finish::face::FacePatch;
use talas::strategies::finish::plan::plan_finish;
use talas::strategies::finish::{FinishOptions, Pattern, Strategy};
use talas::tools::parse_tool_spec;

fn bench(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bicubic-hills.stp");
    let Ok(part) = read_step(&path) else {
        eprintln!("cannot read {}", path.display());
        return;
    };
    let Some(face) = part.faces.first() else {
        return;
    };
    let Ok(patch) = FacePatch::from_face(face) else {
        return;
    };
    let Ok(cutter) = parse_tool_spec("ball:d=6") else {
        return;
    };
    let opts = FinishOptions {
        scallop: 0.01,
        tolerance: 0.005,
        ..FinishOptions::default()
    };
    let strategies = [
        ("iso-scallop", Strategy::IsoScallop),
        (
            "iso-parametric zigzag",
            Strategy::IsoParametric {
                pattern: Pattern::Zigzag,
            },
        ),
    ];
    let mut group = c.benchmark_group("plan bicubic-hills ball d6 h0.01 e0.005");
    group.sample_size(10);
    for (name, s) in strategies {
        if let Ok(r) = plan_finish(patch, &cutter, "ball:d=6", s, &opts) {
            let m = r.toolpath.summary;
            eprintln!(
                "{name}: passes {}, poses {}, cut {:.1} mm, time {:.1} s, max scallop {:?}",
                r.passes.len(),
                m.pose_count,
                m.cut_length_mm,
                m.estimated_time_s,
                m.predicted_max_scallop_mm
            );
        }
        group.bench_function(name, |b| {
            b.iter(|| black_box(plan_finish(patch, &cutter, "ball:d=6", s, &opts).ok()));
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
