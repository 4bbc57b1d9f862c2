//! Cutting-force disk evaluations per second: one evaluation is one flute in one axial disk at
//! one rotation angle (engagement clipping plus 4-point Gauss–Legendre along the disk), the
//! unit the 10⁶/s goal counts. Cases: a flat end mill in a half-immersion up-milling
//! cut (Table 8.4's D = 12 mm test) and a ball end mill in a 3 mm down-milling cut.

use std::f64::consts::TAU;
use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use talas::force::disks::DiskForces;
use talas::force::{Coefficients, EndMill, LinearCoefficients, Mode, Profile, StraightCut};

fn bench_disks(c: &mut Criterion) {
    let k = Coefficients::Linear(LinearCoefficients {
        ktc: 1500.0,
        krc: 20.0,
        kac: 0.0,
        kte: 2.0,
        kre: 4.0,
        kae: 0.0,
    });
    let cases = [
        (
            "flat_d12_up_half",
            EndMill::new(Profile::Flat, 12.0, 2, 30f64.to_radians(), 0.0).expect("mill"),
            StraightCut {
                radial_depth: 6.0,
                axial_depth: 18.0,
                feed_per_tooth: 0.08,
                mode: Mode::Up,
            },
        ),
        (
            "ball_d10_down_3mm",
            EndMill::new(Profile::Ball, 10.0, 3, 30f64.to_radians(), 0.0).expect("mill"),
            StraightCut {
                radial_depth: 3.0,
                axial_depth: 8.0,
                feed_per_tooth: 0.05,
                mode: Mode::Down,
            },
        ),
    ];
    let mut group = c.benchmark_group("force_disk_evaluations");
    for (name, mill, cut) in &cases {
        let eng = cut.engagement(mill, 0.5).expect("engagement");
        let model = DiskForces::new(mill, &k, &eng);
        let steps = 360;
        let evaluations = (steps * model.len() * mill.flutes()) as u64;
        group.throughput(Throughput::Elements(evaluations));
        group.bench_function(*name, |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for s in 0..steps {
                    let phi = TAU * s as f64 / steps as f64;
                    for i in 0..model.len() {
                        for j in 0..mill.flutes() {
                            acc += model.disk_load(i, j, black_box(phi)).force.fy;
                        }
                    }
                }
                black_box(acc)
            });
        });
    }
    group.finish();
}

criterion_group!(benches, bench_disks);
criterion_main!(benches);
