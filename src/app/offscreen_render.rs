//! `talas render`: a part (and a tool path) drawn offscreen by the workstation's renderer and
//! written as PNG. The engine data becomes a [`Scene`] here, as in the viewport; the renderer
//! never sees an engine type.

use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Vec3};

use super::document::Document;
use super::document_loader::load_part;
use super::scalar_field::{ScalarField, curvature_field, mapping_for};
use super::toolpaths::move_colour;
use crate::cli::render::RenderArgs;
use crate::cli::{EXIT_BAD_INPUT, EXIT_INTERNAL};
use crate::diagnostics::Progress;
use crate::render::{
    BoundingSphere, Camera, DisplayOptions, LineData, LineInstance, MeshInstance, Projection,
    Rgba8, RgbaImage, Scene, StandardView, render_to_image,
};
use crate::toolpath::Toolpath;

/// Colour of the part (sRGB), as in the viewport.
const PART_COLOUR: Rgba8 = [176, 186, 200, 255];

/// The tool path's tip polyline, each segment coloured by the kind of its end pose.
#[must_use]
pub fn toolpath_lines(path: &Toolpath) -> LineData {
    let mut lines = LineData::default();
    for pair in path.poses.windows(2) {
        let [a, b] = [&pair[0], &pair[1]];
        let Ok(i) = u32::try_from(lines.positions.len()) else {
            break;
        };
        let colour = move_colour(b.kind);
        lines.positions.push(a.tip.as_vec3().to_array());
        lines.positions.push(b.tip.as_vec3().to_array());
        lines.colours.extend([colour, colour]);
        lines.indices.extend([i, i + 1]);
    }
    lines
}

fn parse_view(name: &str) -> Result<StandardView, String> {
    match name.to_ascii_lowercase().as_str() {
        "iso" => Ok(StandardView::Iso),
        "top" => Ok(StandardView::Top),
        "front" => Ok(StandardView::Front),
        "right" => Ok(StandardView::Right),
        "back" => Ok(StandardView::Back),
        "left" => Ok(StandardView::Left),
        "bottom" => Ok(StandardView::Bottom),
        other => Err(format!(
            "--view {other}: expected iso, top, front, right, back, left or bottom"
        )),
    }
}

fn parse_field(name: &str) -> Result<Option<ScalarField>, String> {
    match name.to_ascii_lowercase().as_str() {
        "none" => Ok(None),
        "k-min" | "kmin" => Ok(Some(ScalarField::KMin)),
        "k-max" | "kmax" => Ok(Some(ScalarField::KMax)),
        "mean" => Ok(Some(ScalarField::Mean)),
        other => Err(format!(
            "--colour-by {other}: expected none, k-min, k-max or mean"
        )),
    }
}

/// What [`render`] drew.
#[derive(Clone, Debug)]
pub struct RenderOutcome {
    /// The picture.
    pub image: RgbaImage,
    /// Triangles of the part.
    pub triangles: usize,
    /// Tool-path segments drawn.
    pub path_segments: usize,
    /// The colour-map range of the field shown: (field, min, max).
    pub field_range: Option<(ScalarField, f32, f32)>,
}

/// Why `talas render` failed: bad input (exit 2) or the renderer (exit 1).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RenderFailure {
    /// A bad file or option.
    Input(String),
    /// No adapter, or the device failed.
    Renderer(String),
}

/// The scene `talas render` draws, before it is drawn: what [`render`] hands to the renderer.
#[derive(Clone, Debug)]
pub struct RenderScene {
    /// The scene (camera fitted to the part for the image's aspect).
    pub scene: Scene,
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Triangles of the part.
    pub triangles: usize,
    /// Tool-path segments drawn.
    pub path_segments: usize,
    /// The colour-map range of the field shown: (field, min, max).
    pub field_range: Option<(ScalarField, f32, f32)>,
}

/// Load the part (and the tool path) of `args` and draw them.
///
/// # Errors
/// [`RenderFailure::Input`] for unreadable or malformed files and bad options,
/// [`RenderFailure::Renderer`] when nothing can draw.
pub fn render(args: &RenderArgs) -> Result<RenderOutcome, RenderFailure> {
    let prepared = render_scene(args)?;
    let image = render_to_image(prepared.width, prepared.height, &prepared.scene)
        .map_err(|e| RenderFailure::Renderer(e.to_string()))?;
    Ok(RenderOutcome {
        image,
        triangles: prepared.triangles,
        path_segments: prepared.path_segments,
        field_range: prepared.field_range,
    })
}

/// Load the part (and the tool path) of `args` and build the scene [`render`] draws.
///
/// # Errors
/// As [`render`], except that nothing is drawn yet.
pub fn render_scene(args: &RenderArgs) -> Result<RenderScene, RenderFailure> {
    let input = RenderFailure::Input;
    args.check_size().map_err(input)?;
    let view = parse_view(&args.view).map_err(input)?;
    let field = parse_field(&args.colour_by).map_err(input)?;
    let part =
        load_part(&args.file, &Progress::new()).map_err(|e| RenderFailure::Input(e.to_string()))?;
    let toolpath = match &args.path {
        Some(p) => Some(Toolpath::load(p).map_err(|e| RenderFailure::Input(e.to_string()))?),
        None => None,
    };
    let mut doc = Document::new(part, 1);
    let mut field_range = None;
    let mut part_mesh = MeshInstance {
        id: doc.ids[0],
        data: Arc::clone(&doc.render_mesh),
        world_from_mesh: Mat4::IDENTITY,
        colour: PART_COLOUR,
        scalar_map: None,
    };
    if let Some(f) = field {
        if !super::scalar_field::has_surfaces(&doc.part) {
            return Err(RenderFailure::Input(format!(
                "{}: --colour-by needs a STEP part (exact surfaces)",
                args.file.display()
            )));
        }
        let curvature = curvature_field(&doc.part, &Progress::new())
            .map_err(|()| RenderFailure::Renderer("curvature evaluation stopped".into()))?;
        let values = curvature.values(f);
        let mapping = mapping_for(values);
        let mut data = (*doc.render_mesh).clone();
        data.scalars = values.to_vec();
        part_mesh.id = 3;
        part_mesh.data = Arc::new(data);
        part_mesh.scalar_map = Some(mapping);
        field_range = Some((f, mapping.min, mapping.max));
        doc.curvature = Some(curvature);
    }
    let mut lines = Vec::new();
    if !args.no_edges {
        lines.push(LineInstance {
            id: doc.ids[1],
            data: Arc::clone(&doc.render_edges),
            world_from_lines: Mat4::IDENTITY,
            draw_segments: None,
        });
    }
    let path_lines = toolpath.as_ref().map(toolpath_lines);
    let path_segments = path_lines.as_ref().map_or(0, LineData::segment_count);
    if let Some(l) = path_lines {
        lines.push(LineInstance {
            id: 4,
            data: Arc::new(l),
            world_from_lines: Mat4::IDENTITY,
            draw_segments: None,
        });
    }
    let mut scene = Scene {
        camera: Camera::default(),
        meshes: vec![part_mesh],
        lines,
        options: DisplayOptions {
            grid: !args.no_grid,
            ..DisplayOptions::default()
        },
    };
    let (lo, hi) = scene
        .bounds()
        .unwrap_or((Vec3::splat(-50.0), Vec3::splat(50.0)));
    scene.options.grid_z = lo.z;
    scene.options.grid_spacing = DisplayOptions::grid_spacing_for((hi - lo).max_element());
    let sphere = BoundingSphere::from_box(lo, hi);
    scene.camera.set_view(view);
    scene.camera.projection = if args.ortho {
        Projection::Orthographic
    } else {
        Projection::Perspective
    };
    scene.camera.scene = sphere;
    scene
        .camera
        .fit(sphere, args.width as f32 / args.height as f32);
    Ok(RenderScene {
        scene,
        width: args.width,
        height: args.height,
        triangles: doc.part.mesh().triangles.len(),
        path_segments,
        field_range,
    })
}

/// Write `image` as an 8-bit RGBA PNG at `path`, atomically.
///
/// # Errors
/// The encoder's or the file system's message, naming the file.
pub fn write_png(image: &RgbaImage, path: &Path) -> Result<(), String> {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, image.width, image.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder
            .write_header()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        writer
            .write_image_data(&image.pixels)
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    crate::storage::write_atomic(path, &bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// `talas render`: draw, write the PNG, print a one-line summary; returns the exit code.
#[must_use]
pub fn run(args: &RenderArgs) -> i32 {
    let outcome = match render(args) {
        Ok(o) => o,
        Err(RenderFailure::Input(e)) => {
            eprintln!("talas: {e}");
            return EXIT_BAD_INPUT;
        }
        Err(RenderFailure::Renderer(e)) => {
            eprintln!("talas: render: {e}");
            return EXIT_INTERNAL;
        }
    };
    if let Err(e) = write_png(&outcome.image, &args.output) {
        eprintln!("talas: {e}");
        return EXIT_BAD_INPUT;
    }
    let field = outcome.field_range.map_or_else(String::new, |(f, lo, hi)| {
        format!(", {} from {lo:.4} to {hi:.4} {}", f.name(), f.unit())
    });
    println!(
        "{}: {}×{} px, {} triangles, {} path segments{field}",
        args.output.display(),
        outcome.image.width,
        outcome.image.height,
        outcome.triangles,
        outcome.path_segments
    );
    0
}

/// A setup-sheet picture drawn by the offscreen renderer: the bodies (setup frame) shaded, the
/// stock box's edges and the work offset's axes, seen from the sheet's direction (eye at +X,
/// −Y, +Z), orthographic, on the sheet's light background; registered with
/// [`crate::project::sheet::set_drawer`] by the binary.
///
/// # Errors
/// No adapter, or the device failed.
pub fn sheet_picture(
    bodies: &[crate::project::sheet::Body<'_>],
    stock: Option<&crate::geometry::Aabb>,
    width: u32,
    height: u32,
) -> Result<crate::project::sheet::Picture, String> {
    use crate::project::sheet::{self, AXIS_COLOURS, BACKGROUND, BOX_EDGES, STOCK_EDGE};
    let (w, h) = (width.clamp(16, 4096), height.clamp(16, 4096));
    let rgba = |c: [u8; 3]| [c[0], c[1], c[2], 255];
    let meshes: Vec<MeshInstance> = bodies
        .iter()
        .zip(10_u64..)
        .map(|(b, id)| MeshInstance {
            id,
            data: Arc::new(crate::render::MeshData::flat(
                &b.mesh.positions,
                &b.mesh.triangles,
            )),
            world_from_mesh: Mat4::IDENTITY,
            colour: rgba(b.colour),
            scalar_map: None,
        })
        .collect();
    let mut lines = LineData::default();
    let mut segment = |a: glam::DVec3, b: glam::DVec3, c: [u8; 3]| {
        let Ok(i) = u32::try_from(lines.positions.len()) else {
            return;
        };
        lines.positions.push(a.as_vec3().to_array());
        lines.positions.push(b.as_vec3().to_array());
        lines.colours.extend([rgba(c), rgba(c)]);
        lines.indices.extend([i, i + 1]);
    };
    if let Some(s) = stock {
        let c = sheet::corners(s);
        for (i, j) in BOX_EDGES {
            segment(c[i], c[j], STOCK_EDGE);
        }
    }
    let axis_len = sheet::axis_length(bodies, stock);
    let axes = [glam::DVec3::X, glam::DVec3::Y, glam::DVec3::Z];
    for (k, a) in axes.into_iter().enumerate() {
        segment(glam::DVec3::ZERO, a * axis_len, AXIS_COLOURS[k]);
    }
    let mut scene = Scene {
        camera: Camera::default(),
        meshes,
        lines: vec![LineInstance {
            id: 9,
            data: Arc::new(lines),
            world_from_lines: Mat4::IDENTITY,
            draw_segments: None,
        }],
        options: DisplayOptions {
            background_top: rgba(BACKGROUND),
            background_bottom: rgba(BACKGROUND),
            grid: false,
            triad: false,
            ..DisplayOptions::default()
        },
    };
    let (lo, hi) = scene
        .bounds()
        .unwrap_or((Vec3::splat(-50.0), Vec3::splat(50.0)));
    let sphere = BoundingSphere::from_box(lo, hi);
    let aspect = w as f32 / h as f32;
    scene.camera.set_view(StandardView::Iso);
    scene.camera.projection = Projection::Orthographic;
    scene.camera.scene = sphere;
    scene.camera.fit(sphere, aspect);
    // Fit the orthographic view to what is drawn (the sphere leaves wide margins), as the
    // software drawing does: 6 % margins around the projected extent.
    let (right, up) = (scene.camera.right(), scene.camera.up());
    let mut lo2 = [f32::INFINITY; 2];
    let mut hi2 = [f32::NEG_INFINITY; 2];
    let points = bodies
        .iter()
        .flat_map(|b| b.mesh.positions.iter().map(|p| p.as_vec3()))
        .chain(scene.lines[0].data.positions.iter().map(|&p| Vec3::from(p)));
    for p in points {
        for (k, v) in [p.dot(right), p.dot(up)].into_iter().enumerate() {
            lo2[k] = lo2[k].min(v);
            hi2[k] = hi2[k].max(v);
        }
    }
    if lo2[0] < hi2[0] && lo2[1] < hi2[1] {
        let t = scene.camera.target;
        let mid = [0.5 * (lo2[0] + hi2[0]), 0.5 * (lo2[1] + hi2[1])];
        scene.camera.target = t + right * (mid[0] - t.dot(right)) + up * (mid[1] - t.dot(up));
        let half_h = (0.5 * (hi2[1] - lo2[1])).max(0.5 * (hi2[0] - lo2[0]) / aspect) / 0.88;
        scene.camera.distance = half_h / (scene.camera.fov_y_rad * 0.5).tan();
    }
    let mut renderer = crate::render::OffscreenRenderer::new().map_err(|e| e.to_string())?;
    let image = renderer.render(w, h, &scene).map_err(|e| e.to_string())?;
    // Where the origin and the axis tips fall (for the sheet's labels).
    let clip = scene.camera.clip_from_world(aspect);
    let to_px = |p: glam::DVec3| {
        let c = clip * p.as_vec3().extend(1.0);
        let (x, y) = (c.x / c.w, c.y / c.w);
        [
            f64::from((x + 1.0) * 0.5 * w as f32),
            f64::from((1.0 - y) * 0.5 * h as f32),
        ]
    };
    let mut axes_px = [to_px(glam::DVec3::ZERO); 4];
    for (k, a) in axes.into_iter().enumerate() {
        axes_px[k + 1] = to_px(a * axis_len);
    }
    let rgb: Vec<[u8; 3]> = image
        .pixels
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    let covered_px = rgb.iter().filter(|p| **p != BACKGROUND).count();
    Ok(sheet::Picture {
        width: w,
        height: h,
        png: sheet::encode_png(&rgb, w as usize, h as usize),
        axes_px,
        covered_px,
        renderer: format!(
            "the offscreen renderer ({})",
            renderer.gpu.adapter_description
        ),
    })
}
