//! Planning time of 5-axis finishing on real trimmed faces of `Schenkel.stp` (issue 14): the
//! sphere face 291 (the workstation's Face 292), the cylinder face 144 and the cone face 79,
//! with a 6 mm ball at h = 0.01 mm, ε = 0.01 mm, iso-scallop, iso-planar and two-way
//! iso-parametric, each on the face's trimmed region. Prints passes, poses and predicted
//! scallop once per case before timing.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use talas::geometry::trim::TrimRegion;
use talas::import::step::read_step;
use talas::strategies::finish::face::FacePatch;
use talas::strategies::finish::plan::plan_finish;
use talas::strategies::finish::{FinishOptions, Pattern, Strategy};
use talas::tools::parse_tool_spec;

fn bench(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/real/freecad/Schenkel.stp");
    let Ok(part) = read_step(&path) else {
        eprintln!("cannot read {}", path.display());
        return;
    };
    let Ok(cutter) = parse_tool_spec("ball:d=6") else {
        return;
    };
    let opts = FinishOptions {
        scallop: 0.01,
        tolerance: 0.01,
        ..FinishOptions::default()
    };
    let strategies = [
        ("iso-scallop", Strategy::IsoScallop),
        ("iso-planar", Strategy::IsoPlanar { angle: 0.0 }),
        (
            "iso-parametric",
            Strategy::IsoParametric {
                pattern: Pattern::Zigzag,
            },
        ),
    ];
    let mut group = c.benchmark_group("plan Schenkel trimmed faces ball d6 h0.01");
    group.sample_size(10);
    for index in [291usize, 144, 79] {
        let Some(face) = part.faces.get(index) else {
            continue;
        };
        let Ok(region) = TrimRegion::of_face(face, &part, 0.002) else {
            eprintln!("face {index}: no region");
            continue;
        };
        let Ok(patch) = FacePatch::trimmed(&part, index, &region) else {
            continue;
        };
        for (name, s) in strategies {
            match plan_finish(patch, &cutter, "ball:d=6", s, &opts) {
                Ok(r) => {
                    let m = r.toolpath.summary;
                    eprintln!(
                        "face {index} {name}: passes {}, poses {}, cut {:.1} mm, max scallop {:?} mm",
                        r.passes.len(),
                        m.pose_count,
                        m.cut_length_mm,
                        m.predicted_max_scallop_mm
                    );
                }
                Err(e) => eprintln!("face {index} {name}: {e}"),
            }
            group.bench_function(format!("face {index} {name}"), |b| {
                b.iter(|| black_box(plan_finish(patch, &cutter, "ball:d=6", s, &opts).ok()));
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
