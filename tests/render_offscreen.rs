//! Offscreen rendering on whatever adapter exists (lavapipe in CI). Skips, with a note on stderr,
//! when there is no adapter.
#![cfg(feature = "gui")]

use std::f32::consts::{PI, TAU};
use std::sync::Arc;

use glam::{Mat4, Vec3};
use talas::render::{
    BoundingSphere, Camera, ColourMap, DisplayOptions, LineData, LineInstance, MeshData,
    MeshInstance, OffscreenRenderer, RenderError, RgbaImage, ScalarMapping, Scene, StandardView,
};

fn renderer() -> Option<OffscreenRenderer> {
    match OffscreenRenderer::new() {
        Ok(r) => Some(r),
        Err(RenderError::NoAdapter(e)) => {
            eprintln!("skipped: no graphics adapter ({e})");
            None
        }
        Err(e) => panic!("device failed: {e}"),
    }
}

/// A UV sphere of `radius` at the origin with exact normals.
fn sphere(radius: f32, rings: u32, segments: u32) -> MeshData {
    let mut m = MeshData::default();
    for i in 0..=rings {
        let theta = PI * i as f32 / rings as f32;
        for j in 0..=segments {
            let phi = TAU * j as f32 / segments as f32;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            m.positions.push((n * radius).to_array());
            m.normals.push(n.to_array());
            m.scalars.push(n.z);
        }
    }
    let row = segments + 1;
    for i in 0..rings {
        for j in 0..segments {
            let (a, b) = (i * row + j, (i + 1) * row + j);
            m.indices.extend_from_slice(&[a, b, b + 1, a, b + 1, a + 1]);
        }
    }
    m
}

fn plain_options() -> DisplayOptions {
    DisplayOptions {
        grid: false,
        triad: false,
        ..DisplayOptions::default()
    }
}

fn scene_with(mesh: MeshData, scalar_map: Option<ScalarMapping>, aspect: f32) -> Scene {
    let mut camera = Camera::default();
    camera.set_view(StandardView::Front);
    camera.fit(
        BoundingSphere {
            centre: Vec3::ZERO,
            radius: 10.0,
        },
        aspect,
    );
    Scene {
        camera,
        meshes: vec![MeshInstance {
            id: 1,
            data: Arc::new(mesh),
            world_from_mesh: Mat4::IDENTITY,
            colour: [200, 200, 200, 255],
            scalar_map,
        }],
        lines: Vec::new(),
        options: plain_options(),
    }
}

fn linear(p: [u8; 4]) -> Vec3 {
    let f = |v: u8| {
        let s = f32::from(v) / 255.0;
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    };
    Vec3::new(f(p[0]), f(p[1]), f(p[2]))
}

fn luminance(p: [u8; 4]) -> f32 {
    0.2126 * f32::from(p[0]) + 0.7152 * f32::from(p[1]) + 0.0722 * f32::from(p[2])
}

fn px(img: &RgbaImage, x: f32, y: f32) -> [u8; 4] {
    img.pixel(x.round() as u32, y.round() as u32)
        .expect("inside the image")
}

#[test]
fn a_sphere_is_lit_in_the_middle_and_its_silhouette_is_where_projection_puts_it() {
    let Some(mut r) = renderer() else { return };
    let (w, h) = (320_u32, 240_u32);
    let scene = scene_with(sphere(10.0, 48, 96), None, w as f32 / h as f32);
    let img = r.render(w, h, &scene).expect("render");
    assert_eq!(img.pixels.len(), (w * h * 4) as usize);

    let (cx, cy) = (w as f32 / 2.0, h as f32 / 2.0);
    let centre = px(&img, cx, cy);
    // Facing the headlight: base 200 grey (sRGB) lit at roughly full strength.
    assert!(luminance(centre) > 150.0, "centre {centre:?}");
    // The top-right corner shows the background gradient's top colour (58, 64, 76).
    let corner = px(&img, w as f32 - 2.0, 1.0);
    for (c, bg) in corner.iter().zip([58_u8, 64, 76]) {
        assert!(
            (i32::from(*c) - i32::from(bg)).abs() <= 3,
            "corner {corner:?}"
        );
    }
    // Closed form: a sphere of radius r at distance d subtends asin(r/d); its silhouette lies
    // at tan(asin(r/d)) / tan(fov/2) of the half height from the centre.
    let c = &scene.camera;
    let d = c.distance;
    let radius_px = (10.0 / d).asin().tan() / (c.fov_y_rad / 2.0).tan() * (h as f32 / 2.0);
    // The background is a vertical gradient: compare with the left edge of the same row.
    let background = |y: f32| luminance(px(&img, 2.0, y));
    for (dx, dy) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
        let (xi, yi) = (cx + dx * radius_px * 0.93, cy + dy * radius_px * 0.93);
        let (xo, yo) = (cx + dx * radius_px * 1.07, cy + dy * radius_px * 1.07);
        let (inside, outside) = (px(&img, xi, yi), px(&img, xo, yo));
        assert!(
            (luminance(inside) - background(yi)).abs() > 8.0,
            "inside {inside:?}"
        );
        assert!(
            (luminance(outside) - background(yo)).abs() < 3.0,
            "outside {outside:?}"
        );
    }
    // Centre brighter than the limb (Lambert falls off toward the silhouette).
    assert!(luminance(centre) > luminance(px(&img, cx + radius_px * 0.93, cy)));
}

#[test]
fn scalars_use_the_colour_map_and_lines_draw_over_surfaces() {
    let Some(mut r) = renderer() else { return };
    let (w, h) = (200_u32, 200_u32);
    // Scalar = n.z, mapped over [-1, 1] through viridis.
    let map = ScalarMapping {
        map: ColourMap::Viridis,
        min: -1.0,
        max: 1.0,
    };
    let mut scene = scene_with(sphere(10.0, 48, 96), Some(map), 1.0);
    let red = [255, 0, 0, 255];
    scene.lines.push(LineInstance {
        id: 2,
        data: Arc::new(LineData::polyline(
            vec![[-20.0, -12.0, 0.0], [20.0, -12.0, 0.0]],
            vec![red; 2],
        )),
        world_from_lines: Mat4::IDENTITY,
        draw_segments: None,
    });
    // The clip planes must take in the line too.
    scene.camera.scene = BoundingSphere {
        centre: Vec3::ZERO,
        radius: 25.0,
    };
    let img = r.render(w, h, &scene).expect("render");
    // At a pixel on the sphere, the scalar is n.z of the surface point the view ray hits; the
    // colour must be the map's colour there, up to the lighting's brightness: compare the
    // direction of the linear RGB vectors.
    for y in [52.0_f32, 148.0] {
        let ndc = glam::Vec2::new(0.0, 1.0 - 2.0 * y / h as f32);
        let (origin, dir) = scene.camera.ray(ndc, 1.0);
        // |origin + t dir| = 10, nearest root.
        let b = origin.dot(dir);
        let c = origin.length_squared() - 100.0;
        let t = -b - (b * b - c).sqrt();
        let n = (origin + dir * t) / 10.0;
        let expected = ColourMap::Viridis.sample((n.z + 1.0) / 2.0);
        let got = px(&img, 100.0, y);
        let e = linear([expected[0], expected[1], expected[2], 255]).normalize();
        let g = linear(got).normalize();
        assert!(
            e.dot(g) > 0.995,
            "at row {y}: got {got:?}, map colour {expected:?} (n.z = {})",
            n.z
        );
    }
    // The red line passes in front of the sphere (y = -12 is in front of its centre, the
    // camera looks along +Y) at mid-height.
    let line_row = (0..h).find(|&y| {
        img.pixel(100, y).is_some_and(|p| {
            i32::from(p[0]) > i32::from(p[1]) + 60 && i32::from(p[0]) > i32::from(p[2]) + 60
        })
    });
    assert!(
        line_row.is_some_and(|y| (y as i32 - 100).abs() <= 2),
        "line at {line_row:?}"
    );
}

#[test]
fn a_mesh_drawn_again_over_itself_shows_the_later_colour() {
    // The viewport highlights a selected face by drawing its triangles again in another colour.
    let Some(mut r) = renderer() else { return };
    let quad = MeshData {
        positions: vec![
            [-5.0, 0.0, -5.0],
            [5.0, 0.0, -5.0],
            [5.0, 0.0, 5.0],
            [-5.0, 0.0, 5.0],
        ],
        normals: vec![[0.0, -1.0, 0.0]; 4],
        scalars: Vec::new(),
        indices: vec![0, 1, 2, 0, 2, 3],
    };
    let mut scene = scene_with(quad.clone(), None, 1.0);
    scene.meshes.push(MeshInstance {
        id: 7,
        data: Arc::new(quad),
        world_from_mesh: Mat4::IDENTITY,
        colour: [255, 160, 40, 255],
        scalar_map: None,
    });
    let img = r.render(100, 100, &scene).expect("render");
    let p = px(&img, 50.0, 50.0);
    assert!(
        p[0] > p[2] + 80,
        "centre {p:?} should be the highlight's orange"
    );
}
