//! Viewport frame time with large data: a 2-million-triangle height field and a 1-million-point
//! tool path above it, rendered offscreen at 1600 × 1000 with 4× MSAA through the workstation's
//! renderer. Prints the upload time and the mean, median and worst ms/frame.
//!
//! `cargo run --release --example viewport_frame_time [FRAMES]`

#[cfg(feature = "gui")]
fn main() {
    measure::run();
}

#[cfg(not(feature = "gui"))]
fn main() {
    eprintln!("viewport_frame_time needs the `gui` feature");
}

/// The measurement (needs the renderer, feature `gui`).
#[cfg(feature = "gui")]
mod measure {
    use std::f32::consts::TAU;
    use std::sync::Arc;
    use std::time::Instant;

    use glam::{Mat4, Vec3};
    use talas::render::{
        BoundingSphere, Camera, DisplayOptions, LineData, LineInstance, MeshData, MeshInstance,
        OffscreenRenderer, Scene,
    };

    /// Height of the test surface (mm) at (x, y).
    fn height(x: f32, y: f32) -> f32 {
        6.0 * (x * TAU / 80.0).sin() * (y * TAU / 60.0).cos() + 2.0 * (x * TAU / 17.0).sin()
    }

    /// An n × n-quad height field over 200 × 200 mm (2 n² triangles).
    fn height_field(n: u32) -> MeshData {
        let mut m = MeshData::default();
        let step = 200.0 / n as f32;
        for i in 0..=n {
            for j in 0..=n {
                let (x, y) = (i as f32 * step - 100.0, j as f32 * step - 100.0);
                let e = 1e-2;
                let dx = (height(x + e, y) - height(x - e, y)) / (2.0 * e);
                let dy = (height(x, y + e) - height(x, y - e)) / (2.0 * e);
                m.positions.push([x, y, height(x, y)]);
                m.normals
                    .push(Vec3::new(-dx, -dy, 1.0).normalize().to_array());
            }
        }
        let row = n + 1;
        for i in 0..n {
            for j in 0..n {
                let a = i * row + j;
                m.indices
                    .extend_from_slice(&[a, a + row, a + row + 1, a, a + row + 1, a + 1]);
            }
        }
        m
    }

    /// A zig-zag raster path of `points` points 1 mm above the surface.
    fn raster_path(points: u32) -> LineData {
        let passes = 200;
        let per_pass = points / passes;
        let mut positions = Vec::with_capacity(points as usize);
        let mut colours = Vec::with_capacity(points as usize);
        for p in 0..passes {
            let y = -100.0 + 200.0 * p as f32 / (passes - 1) as f32;
            for k in 0..per_pass {
                let t = k as f32 / (per_pass - 1) as f32;
                let x = if p % 2 == 0 {
                    -100.0 + 200.0 * t
                } else {
                    100.0 - 200.0 * t
                };
                positions.push([x, y, height(x, y) + 1.0]);
                colours.push([60, 200, 255, 255]);
            }
        }
        LineData::polyline(positions, colours)
    }

    pub fn run() {
        let frames: usize = std::env::args()
            .nth(1)
            .and_then(|a| a.parse().ok())
            .unwrap_or(20);
        let (w, h) = (1600_u32, 1000_u32);
        let mut renderer = match OffscreenRenderer::new() {
            Ok(r) => r,
            Err(e) => {
                eprintln!("viewport_frame_time: {e}");
                std::process::exit(1);
            }
        };
        let t = Instant::now();
        let mesh = Arc::new(height_field(1000));
        let path = Arc::new(raster_path(1_000_000));
        println!(
            "adapter: {} ({}x MSAA); data: {} triangles, {} path points, built in {:.0} ms",
            renderer.gpu.adapter_description,
            renderer.gpu.samples,
            mesh.triangle_count(),
            path.positions.len(),
            t.elapsed().as_secs_f64() * 1e3
        );
        let mut camera = Camera::default();
        camera.fit(
            BoundingSphere {
                centre: Vec3::ZERO,
                radius: 145.0,
            },
            w as f32 / h as f32,
        );
        let mut scene = Scene {
            camera,
            meshes: vec![MeshInstance {
                id: 1,
                data: mesh,
                world_from_mesh: Mat4::IDENTITY,
                colour: [176, 186, 200, 255],
                scalar_map: None,
            }],
            lines: vec![LineInstance {
                id: 2,
                data: path,
                world_from_lines: Mat4::IDENTITY,
                draw_segments: None,
            }],
            options: DisplayOptions {
                grid_z: -10.0,
                ..DisplayOptions::default()
            },
        };
        let t = Instant::now();
        if let Err(e) = renderer.draw(w, h, &scene) {
            eprintln!("viewport_frame_time: {e}");
            std::process::exit(1);
        }
        println!(
            "first frame (upload + draw): {:.1} ms",
            t.elapsed().as_secs_f64() * 1e3
        );
        let all = (scene.meshes.clone(), scene.lines.clone());
        for (label, meshes, lines) in [
            ("mesh + path", all.0.clone(), all.1.clone()),
            ("mesh only", all.0.clone(), Vec::new()),
            ("path only", Vec::new(), all.1.clone()),
        ] {
            scene.meshes = meshes;
            scene.lines = lines;
            let mut times = Vec::with_capacity(frames);
            for _ in 0..frames {
                scene.camera.orbit(0.02, 0.0);
                let t = Instant::now();
                if let Err(e) = renderer.draw(w, h, &scene) {
                    eprintln!("viewport_frame_time: {e}");
                    std::process::exit(1);
                }
                times.push(t.elapsed().as_secs_f64() * 1e3);
            }
            times.sort_by(f64::total_cmp);
            let mean = times.iter().sum::<f64>() / times.len().max(1) as f64;
            let median = times.get(times.len() / 2).copied().unwrap_or(0.0);
            let worst = times.last().copied().unwrap_or(0.0);
            println!(
                "{label:>12}: {w}x{h}, {frames} frames: mean {mean:.1} ms/frame, median {median:.1}, worst {worst:.1}"
            );
        }
    }
}
