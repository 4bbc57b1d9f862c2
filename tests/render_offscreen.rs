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

// ---------------------------------------------------------------------------------------------
// Pixel test: the default part through `talas render`'s own scene building, against a committed
// image.
// ---------------------------------------------------------------------------------------------

/// The committed reference (regenerate with `TALAS_BLESS=1 cargo test --test render_offscreen`).
const REFERENCE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/data/render/bicubic-hills-iso.png"
);
// The tolerance. Two conformant Vulkan rasterisers with the standard 4× MSAA sample positions
// cover the same samples; they differ by float rounding in the shading (a level or so) and by
// line rasterisation rules (edges and the triad's outline move by up to a pixel). The controls at
// the end of the test measure, on this 320×240 picture (lavapipe):
//   a third-of-a-pixel pan (harsher than the above; must pass):  0.09 % off, mean 0.37 levels;
//   the camera turned by 2° (must fail):                          0.44 % off, mean 1.00;
//   the part's colour 10 levels greyer (must fail):               13.6 % off, mean 0.93;
//   no part at all (must fail):                                    15.2 % off, mean 18.5.
// ("off": pixels with a channel more than CHANNEL_TOLERANCE from all of the reference's 3×3
// neighbourhood). Limits halfway (in ratio) between the pan and the nearest failure. The
// procedural ground grid is left out (`--no-grid`): its sub-pixel lines are antialiased with
// screen-space derivatives, which differ between GPUs and would dominate the comparison.

/// A pixel matches when every RGB channel is within this many levels of the reference pixel at
/// the same place or at one of its eight neighbours.
const CHANNEL_TOLERANCE: i32 = 8;
/// Fewest matching pixels (at most 0.2 % = 154 pixels off).
const MIN_MATCHING: f64 = 0.998;
/// Largest mean absolute channel difference at the same place (levels).
const MAX_MEAN_ABS: f64 = 0.6;

/// `talas render assets/bicubic-hills.stp --width 320 --height 240 --no-grid` (the embedded
/// default part's file; iso view fitted to the part, perspective, edges and triad on).
fn default_part_args() -> talas::cli::render::RenderArgs {
    talas::cli::render::RenderArgs {
        file: concat!(env!("CARGO_MANIFEST_DIR"), "/assets/bicubic-hills.stp").into(),
        path: None,
        width: 320,
        height: 240,
        output: "unused.png".into(),
        view: "iso".into(),
        colour_by: "none".into(),
        no_edges: false,
        no_grid: true,
        ortho: false,
    }
}

/// How far `actual` is from `reference`.
#[derive(Clone, Copy, Debug)]
struct Difference {
    /// Fraction of pixels within [`CHANNEL_TOLERANCE`] of the reference's 3×3 neighbourhood.
    matching: f64,
    /// Mean absolute RGB channel difference at the same place, levels.
    mean_abs: f64,
}

impl Difference {
    fn passes(self) -> bool {
        self.matching >= MIN_MATCHING && self.mean_abs <= MAX_MEAN_ABS
    }
}

fn difference(actual: &RgbaImage, reference: &RgbaImage) -> Difference {
    assert_eq!(
        (actual.width, actual.height),
        (reference.width, reference.height),
        "image sizes differ"
    );
    let (w, h) = (actual.width as i64, actual.height as i64);
    let at = |img: &RgbaImage, x: i64, y: i64| {
        img.pixel(x.clamp(0, w - 1) as u32, y.clamp(0, h - 1) as u32)
            .expect("inside")
    };
    let close = |a: [u8; 4], b: [u8; 4]| {
        (0..3).all(|c| (i32::from(a[c]) - i32::from(b[c])).abs() <= CHANNEL_TOLERANCE)
    };
    let (mut matching, mut sum) = (0_u64, 0_u64);
    for y in 0..h {
        for x in 0..w {
            let a = at(actual, x, y);
            let r = at(reference, x, y);
            sum += (0..3).map(|c| u64::from(a[c].abs_diff(r[c]))).sum::<u64>();
            let near =
                (-1..=1).any(|dy| (-1..=1).any(|dx| close(a, at(reference, x + dx, y + dy))));
            matching += u64::from(near);
        }
    }
    let n = (w * h) as f64;
    Difference {
        matching: matching as f64 / n,
        mean_abs: sum as f64 / (3.0 * n),
    }
}

fn read_png(path: &std::path::Path) -> RgbaImage {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("PNG header");
    let mut pixels = vec![0; reader.output_buffer_size().expect("PNG size")];
    let info = reader.next_frame(&mut pixels).expect("PNG data");
    assert_eq!(
        (info.color_type, info.bit_depth),
        (png::ColorType::Rgba, png::BitDepth::Eight),
        "{}: expected 8-bit RGBA",
        path.display()
    );
    pixels.truncate(info.buffer_size());
    RgbaImage {
        width: info.width,
        height: info.height,
        pixels,
    }
}

/// |actual − reference| per channel, ×4, opaque.
fn diff_image(actual: &RgbaImage, reference: &RgbaImage) -> RgbaImage {
    let pixels = actual
        .pixels
        .chunks_exact(4)
        .zip(reference.pixels.chunks_exact(4))
        .flat_map(|(a, r)| {
            let d = |c: usize| a[c].abs_diff(r[c]).saturating_mul(4);
            [d(0), d(1), d(2), 255]
        })
        .collect();
    RgbaImage {
        width: actual.width,
        height: actual.height,
        pixels,
    }
}

#[test]
fn the_default_part_renders_as_the_committed_image() {
    use talas::app::offscreen_render::{render_scene, write_png};
    let Some(mut r) = renderer() else { return };
    let prepared = render_scene(&default_part_args()).expect("scene of the default part");
    let (w, h) = (prepared.width, prepared.height);
    let actual = r.render(w, h, &prepared.scene).expect("render");
    let reference_path = std::path::Path::new(REFERENCE);
    if std::env::var_os("TALAS_BLESS").is_some_and(|v| v == "1") {
        if let Some(dir) = reference_path.parent() {
            std::fs::create_dir_all(dir).expect("reference folder");
        }
        write_png(&actual, reference_path).expect("write the reference");
        eprintln!("blessed: wrote {REFERENCE}");
        return;
    }
    let reference = read_png(reference_path);
    let d = difference(&actual, &reference);
    if !d.passes() {
        let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
        let (a, f) = (out.join("render-actual.png"), out.join("render-diff.png"));
        write_png(&actual, &a).expect("write the actual image");
        write_png(&diff_image(&actual, &reference), &f).expect("write the diff image");
        panic!(
            "the default part differs from {REFERENCE}: {:.2} % of pixels within {CHANNEL_TOLERANCE} \
             levels (need {:.1} %), mean |difference| {:.2} levels (at most {MAX_MEAN_ABS}); \
             actual: {}, diff (×4): {}; if the change is intended, rerun with TALAS_BLESS=1",
            d.matching * 100.0,
            MIN_MATCHING * 100.0,
            d.mean_abs,
            a.display(),
            f.display()
        );
    }
    eprintln!("default part vs reference: {d:?}");

    // The tolerance must let rasterisation differences through (another GPU's antialiasing and
    // line rules move edges by a fraction of a pixel: model them by a third-of-a-pixel pan) and
    // must catch a changed colour, camera or a missing mesh. Each control goes through the same
    // comparison as above.
    let mut variant = |change: &dyn Fn(&mut Scene)| {
        let mut scene = prepared.scene.clone();
        change(&mut scene);
        difference(&r.render(w, h, &scene).expect("render"), &reference)
    };
    let shifted = variant(&|s| s.camera.pan(glam::Vec2::new(0.33, -0.33), h as f32));
    let recoloured = variant(&|s| s.meshes[0].colour = [186, 186, 190, 255]);
    let turned = variant(&|s| s.camera.orbit(2.0_f32.to_radians(), 0.0));
    let empty = variant(&|s| s.meshes.clear());
    eprintln!("pan {shifted:?}\nrecoloured {recoloured:?}\nturned {turned:?}\nempty {empty:?}");
    assert!(
        shifted.passes(),
        "a third-of-a-pixel pan must pass: {shifted:?}"
    );
    assert!(
        !recoloured.passes(),
        "a greyer part must fail: {recoloured:?}"
    );
    assert!(
        !turned.passes(),
        "a camera turned by 2° must fail: {turned:?}"
    );
    assert!(!empty.passes(), "a missing part must fail: {empty:?}");
}

#[test]
fn the_tool_is_drawn_at_its_tip_along_its_axis_and_the_work_offset_is_marked() {
    use glam::DVec3;
    use talas::app::viewport::{ToolPose, ViewportState};
    use talas::tools::{Cutter, CutterKind};
    let Some(mut r) = renderer() else { return };
    let (w, h) = (240_u32, 240_u32);
    let cutter = Cutter::new(CutterKind::Ball, 10.0).expect("cutter");
    let (tip, axis) = (
        DVec3::new(30.0, -20.0, 5.0),
        DVec3::new(0.3, -0.2, 1.0).normalize(),
    );
    let mut state = ViewportState::default();
    state.options = plain_options();
    state.camera.set_view(StandardView::Front);
    state.camera.fit(
        BoundingSphere {
            centre: Vec3::new(0.0, 0.0, 30.0),
            radius: 60.0,
        },
        1.0,
    );
    let offset = DVec3::new(-30.0, 0.0, 0.0);
    state.work_offset = Some(glam::Mat4::from_translation(offset.as_vec3()));
    let empty = r.render(w, h, &state.scene(None)).expect("render");
    state.tool_pose = Some(ToolPose {
        tip,
        axis,
        cutter: cutter.clone(),
    });
    let scene = state.scene(None);
    let img = r.render(w, h, &scene).expect("render");
    let at = |p: DVec3| {
        let ndc = scene
            .camera
            .clip_from_world(1.0)
            .project_point3(p.as_vec3());
        (
            (ndc.x + 1.0) * 0.5 * w as f32,
            (1.0 - ndc.y) * 0.5 * h as f32,
        )
    };
    let to_px = |p: DVec3| {
        let (x, y) = at(p);
        (px(&img, x, y), px(&empty, x, y))
    };
    let tool_blue = |p: [u8; 4]| i32::from(p[2]) > i32::from(p[0]) + 40;
    // On the axis: the ball's centre, the middle of the flutes, the shank: the tool's metal,
    // where there was only background before.
    for along in [5.0, 20.0, cutter.overall_length - 2.0] {
        let (with, without) = to_px(tip + axis * along);
        assert!(
            tool_blue(with) && !tool_blue(without),
            "{along} mm up the axis: {with:?} (without the tool {without:?})"
        );
    }
    // Below the tip and beside the cutter: background.
    for p in [
        tip - axis * 4.0,
        tip + axis * 20.0 + axis.cross(DVec3::Y).normalize() * 9.0,
    ] {
        let (with, without) = to_px(p);
        assert_eq!(with, without, "at {p} the tool must not show");
    }
    // The marker's X axis (red) along +X from the work offset (20 mm long without a part):
    // a one-pixel line, so look one pixel around the projected point.
    let (x, y) = at(offset + DVec3::X * 10.0);
    let red = (-1..=1).find_map(|dy| {
        let p = px(&img, x, y + dy as f32);
        (i32::from(p[0]) > i32::from(p[1]) + 60).then_some(p)
    });
    assert!(red.is_some(), "no red marker axis near ({x}, {y})");
}
