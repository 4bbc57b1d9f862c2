//! The setup sheet of a job (`talas job PROJECT --sheet OUT.html`): one self-contained HTML
//! file (no scripts, no outside files: pictures embedded as PNG data) with the job's tools and,
//! per setup, a picture of the part, stock and workholding as they lie in the setup's frame
//! with the work offset's axes marked, the setup's machine, work offset, tool axis, stock size
//! and workholding, and per operation its strategy, tool, feeds and speeds, heights and times.
//!
//! The pictures are drawn by the workstation's offscreen renderer (wgpu) where the binary has
//! it (the `gui` feature registers it with [`set_drawer`]) and a graphics adapter answers;
//! otherwise, and in an engine build, here in software (a depth-buffered flat-shaded isometric
//! view from the same direction with the same colours). Each picture says which drew it. Either
//! way the same job on the same machine gives the same bytes.

use std::fmt::Write as _;

use glam::DVec3;

use crate::geometry::Aabb;
use crate::geometry::mesh::TriMesh;

/// One body drawn in a picture, in the setup frame (mm), with its colour (sRGB).
pub struct Body<'a> {
    /// The triangles.
    pub mesh: &'a TriMesh,
    /// Its colour.
    pub colour: [u8; 3],
}

/// A drawn picture: the PNG and where the work offset's origin and axis tips fall in it.
#[derive(Clone, Debug, PartialEq)]
pub struct Picture {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// The PNG file's bytes (8-bit RGB).
    pub png: Vec<u8>,
    /// Pixel positions of the origin and of the X, Y and Z axis tips.
    pub axes_px: [[f64; 2]; 4],
    /// Pixels covered by a body (for a check that something was drawn).
    pub covered_px: usize,
    /// What drew it (`the offscreen renderer (ADAPTER)`, `software`, with why).
    pub renderer: String,
}

/// A picture drawer for the sheet: bodies (setup frame), the stock box, width, height.
pub type Drawer = fn(&[Body<'_>], Option<&Aabb>, u32, u32) -> Result<Picture, String>;

static DRAWER: std::sync::OnceLock<Drawer> = std::sync::OnceLock::new();

/// Register the drawer [`picture`] tries first (the binary's offscreen renderer); `false`
/// when one was registered already.
pub fn set_drawer(drawer: Drawer) -> bool {
    DRAWER.set(drawer).is_ok()
}

/// The picture of `bodies` and the `stock` box with the work offset's axes: by the registered
/// drawer when there is one and it draws, else in software ([`draw`]), saying why.
#[must_use]
pub fn picture(bodies: &[Body<'_>], stock: Option<&Aabb>, width: u32, height: u32) -> Picture {
    let Some(drawer) = DRAWER.get() else {
        return draw(bodies, stock, width, height);
    };
    match drawer(bodies, stock, width, height) {
        Ok(p) => p,
        Err(e) => {
            let mut p = draw(bodies, stock, width, height);
            p.renderer = format!("software (the offscreen renderer could not draw: {e})");
            p
        }
    }
}

/// Length of the drawn work-offset axes for `bodies` and `stock`: 0.3 × the largest extent,
/// within 5–200 mm.
#[must_use]
pub fn axis_length(bodies: &[Body<'_>], stock: Option<&Aabb>) -> f64 {
    let mut extent = 0.0_f64;
    for b in bodies {
        let bb = b.mesh.bbox();
        extent = extent.max((bb.max - bb.min).max_element());
    }
    if let Some(s) = stock {
        extent = extent.max((s.max - s.min).max_element());
    }
    (0.3 * extent).clamp(5.0, 200.0)
}

/// The view direction of the pictures: from the front, right and above (eye at +X, −Y, +Z).
#[must_use]
pub fn view_basis() -> (DVec3, DVec3, DVec3) {
    let forward = DVec3::new(-1.0, 1.0, -1.0).normalize();
    let right = forward.cross(DVec3::Z).normalize();
    let up = right.cross(forward);
    (right, up, forward)
}

/// Background colour of the pictures (sRGB).
pub const BACKGROUND: [u8; 3] = [250, 250, 247];
/// Colour of the stock box's edges (sRGB).
pub const STOCK_EDGE: [u8; 3] = [170, 120, 40];
/// Colours of the X, Y and Z axes (sRGB).
pub const AXIS_COLOURS: [[u8; 3]; 3] = [[210, 40, 40], [30, 150, 40], [40, 70, 210]];

/// Draw `bodies`, the `stock` box's edges and the work offset's axes (at the origin of the
/// setup frame) in a `width` × `height` picture, the view fitted to all of them.
#[must_use]
pub fn draw(bodies: &[Body<'_>], stock: Option<&Aabb>, width: u32, height: u32) -> Picture {
    let (w, h) = (
        width.clamp(16, 4096) as usize,
        height.clamp(16, 4096) as usize,
    );
    let (right, up, forward) = view_basis();
    // Fit the view to every vertex, the stock and the axes.
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    let mut grow = |p: DVec3| {
        let q = [p.dot(right), p.dot(up)];
        for k in 0..2 {
            if q[k].is_finite() {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
    };
    for b in bodies {
        for &p in &b.mesh.positions {
            grow(p);
        }
    }
    if let Some(s) = stock {
        for c in corners(s) {
            grow(c);
        }
    }
    let axis_len = axis_length(bodies, stock);
    grow(DVec3::ZERO);
    for a in [DVec3::X, DVec3::Y, DVec3::Z] {
        grow(a * axis_len);
    }
    if !(lo[0] < hi[0]) || !(lo[1] < hi[1]) {
        lo = [-1.0, -1.0];
        hi = [1.0, 1.0];
    }
    let margin = 0.06;
    let scale = ((w as f64 * (1.0 - 2.0 * margin)) / (hi[0] - lo[0]))
        .min((h as f64 * (1.0 - 2.0 * margin)) / (hi[1] - lo[1]));
    let cx = 0.5 * (lo[0] + hi[0]);
    let cy = 0.5 * (lo[1] + hi[1]);
    let to_px = |p: DVec3| -> [f64; 3] {
        [
            w as f64 * 0.5 + (p.dot(right) - cx) * scale,
            h as f64 * 0.5 - (p.dot(up) - cy) * scale,
            p.dot(forward),
        ]
    };
    let mut rgb = vec![BACKGROUND; w * h];
    let mut depth = vec![f64::INFINITY; w * h];
    let light = (-forward + 0.6 * up + 0.3 * right).normalize();
    for b in bodies {
        let m = b.mesh;
        for t in &m.triangles {
            let [Some(&a), Some(&bb), Some(&c)] = t.map(|i| m.positions.get(i as usize)) else {
                continue;
            };
            let n = (bb - a).cross(c - a);
            let len = n.length();
            if !(len > 0.0) {
                continue;
            }
            let shade = 0.35 + 0.65 * (n / len).dot(light).abs();
            let colour = b
                .colour
                .map(|v| (f64::from(v) * shade).round().clamp(0.0, 255.0) as u8);
            fill_triangle(
                [to_px(a), to_px(bb), to_px(c)],
                colour,
                w,
                h,
                &mut rgb,
                &mut depth,
            );
        }
    }
    if let Some(s) = stock {
        let c = corners(s);
        for (i, j) in BOX_EDGES {
            let (p, q) = (to_px(c[i]), to_px(c[j]));
            line(&mut rgb, w, h, [p[0], p[1]], [q[0], q[1]], STOCK_EDGE, 1);
        }
    }
    let o = to_px(DVec3::ZERO);
    let mut axes_px = [[o[0], o[1]]; 4];
    for (k, a) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
        let t = to_px(a * axis_len);
        line(
            &mut rgb,
            w,
            h,
            [o[0], o[1]],
            [t[0], t[1]],
            AXIS_COLOURS[k],
            2,
        );
        axes_px[k + 1] = [t[0], t[1]];
    }
    Picture {
        width: w as u32,
        height: h as u32,
        png: encode_png(&rgb, w, h),
        axes_px,
        covered_px: depth.iter().filter(|d| d.is_finite()).count(),
        renderer: "software".into(),
    }
}

/// The 8 corners of a box, bit k of the index choosing max on axis k.
#[must_use]
pub fn corners(b: &Aabb) -> [DVec3; 8] {
    std::array::from_fn(|i| {
        DVec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        )
    })
}

/// The 12 edges of a box as corner pairs (see [`corners`]).
pub const BOX_EDGES: [(usize, usize); 12] = [
    (0, 1),
    (2, 3),
    (4, 5),
    (6, 7),
    (0, 2),
    (1, 3),
    (4, 6),
    (5, 7),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// Fill one projected triangle (pixel x, y and depth per corner) where it is nearer than the
/// depth buffer.
fn fill_triangle(
    p: [[f64; 3]; 3],
    colour: [u8; 3],
    w: usize,
    h: usize,
    rgb: &mut [[u8; 3]],
    depth: &mut [f64],
) {
    let area =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
    if !area.is_finite() || area.abs() < 1e-12 {
        return;
    }
    let x0 = p
        .iter()
        .map(|q| q[0])
        .fold(f64::INFINITY, f64::min)
        .floor()
        .max(0.0);
    let x1 = p
        .iter()
        .map(|q| q[0])
        .fold(f64::NEG_INFINITY, f64::max)
        .ceil()
        .min(w as f64 - 1.0);
    let y0 = p
        .iter()
        .map(|q| q[1])
        .fold(f64::INFINITY, f64::min)
        .floor()
        .max(0.0);
    let y1 = p
        .iter()
        .map(|q| q[1])
        .fold(f64::NEG_INFINITY, f64::max)
        .ceil()
        .min(h as f64 - 1.0);
    if x0 > x1 || y0 > y1 {
        return;
    }
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    for y in y0 as usize..=y1 as usize {
        for x in x0 as usize..=x1 as usize {
            let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
            let e = |a: [f64; 3], b: [f64; 3]| {
                (b[0] - a[0]) * (py - a[1]) - (px - a[0]) * (b[1] - a[1])
            };
            let l0 = e(p[1], p[2]) / area;
            let l1 = e(p[2], p[0]) / area;
            let l2 = 1.0 - l0 - l1;
            if l0 < 0.0 || l1 < 0.0 || l2 < 0.0 {
                continue;
            }
            let z = l0 * p[0][2] + l1 * p[1][2] + l2 * p[2][2];
            let k = y * w + x;
            if z < depth[k] {
                depth[k] = z;
                rgb[k] = colour;
            }
        }
    }
}

/// A line `thick` pixels wide drawn over everything.
fn line(
    rgb: &mut [[u8; 3]],
    w: usize,
    h: usize,
    a: [f64; 2],
    b: [f64; 2],
    colour: [u8; 3],
    thick: i64,
) {
    let n = ((b[0] - a[0]).abs().max((b[1] - a[1]).abs()).ceil() as usize).clamp(1, 20_000);
    for k in 0..=n {
        let t = k as f64 / n as f64;
        let (x, y) = (a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t);
        for dy in 0..thick {
            for dx in 0..thick {
                #[allow(clippy::cast_possible_truncation)]
                let (xi, yi) = (x.floor() as i64 + dx, y.floor() as i64 + dy);
                if xi >= 0 && yi >= 0 && (xi as usize) < w && (yi as usize) < h {
                    rgb[yi as usize * w + xi as usize] = colour;
                }
            }
        }
    }
}

/// An 8-bit RGB PNG of `rgb` (row-major, `w` × `h`).
#[must_use]
pub fn encode_png(rgb: &[[u8; 3]], w: usize, h: usize) -> Vec<u8> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, w as u32, h as u32);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let data: Vec<u8> = rgb.iter().flatten().copied().collect();
    if let Ok(mut writer) = encoder.write_header() {
        // Writing into a Vec cannot fail but for a size the header already accepted.
        let _ = writer.write_image_data(&data);
    }
    bytes
}

/// Standard base64 (RFC 4648, with padding) of `bytes`, for the embedded pictures.
#[must_use]
pub fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                out.push(A[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// A tool of the sheet's tool list.
#[derive(Clone, Debug, PartialEq)]
pub struct SheetTool {
    /// Tool number (T).
    pub number: usize,
    /// Its name in the project.
    pub name: String,
    /// Its spec (`ball:d=6,...`).
    pub spec: String,
    /// Cutting diameter, mm.
    pub diameter_mm: f64,
    /// Flute length, mm.
    pub flute_mm: f64,
    /// Stick-out from the holder (overall length), mm.
    pub stick_out_mm: f64,
    /// The holder, described.
    pub holder: String,
}

/// One operation's row.
#[derive(Clone, Debug, PartialEq)]
pub struct SheetOperation {
    /// Number in the project (from 1).
    pub number: usize,
    /// Name.
    pub name: String,
    /// Strategy.
    pub strategy: String,
    /// Tool number.
    pub tool: usize,
    /// Cutting feed, mm/min.
    pub feed_mm_per_min: f64,
    /// Plunge feed, mm/min, where it has its own.
    pub plunge_mm_per_min: Option<f64>,
    /// Spindle speed, rpm.
    pub spindle_rpm: f64,
    /// Clearance and retract heights, as the operation gives them.
    pub heights: String,
    /// Where its feeds and speeds come from (the cutting data for the material, or typed).
    pub speeds_from: String,
    /// Time at the programmed feeds, s.
    pub time_at_feed_s: f64,
    /// Jerk-limited cycle time of its posted run, s (or why there is none).
    pub cycle_time_s: Result<f64, String>,
    /// Warnings of the plan.
    pub warnings: Vec<String>,
}

/// One setup's page.
pub struct SheetSetup {
    /// Number (from 1).
    pub number: usize,
    /// Name.
    pub name: String,
    /// Machine.
    pub machine: String,
    /// Work offset (G54 …).
    pub work_offset: String,
    /// Tool axis in the setup frame.
    pub tool_axis: [f64; 3],
    /// Stock box size, mm, and what it is.
    pub stock_size_mm: [f64; 3],
    /// The stock, described (box, cylinder, from the previous setup).
    pub stock: String,
    /// The workholding, each described.
    pub workholding: Vec<String>,
    /// The picture.
    pub picture: Picture,
    /// The operations in machining order.
    pub operations: Vec<SheetOperation>,
}

/// The whole sheet.
pub struct Sheet {
    /// Project name.
    pub project: String,
    /// The part file.
    pub part: String,
    /// The work material and the tools' material, described (`None`: not set).
    pub material: Option<String>,
    /// The tools used.
    pub tools: Vec<SheetTool>,
    /// The setups.
    pub setups: Vec<SheetSetup>,
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `s` seconds as "1 h 02 min", "3 min 05 s" or "12.3 s".
#[must_use]
pub fn duration(s: f64) -> String {
    if !s.is_finite() || s < 0.0 {
        return "—".into();
    }
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let whole = s.round() as u64;
    if s < 60.0 {
        format!("{s:.1} s")
    } else if whole < 3600 {
        format!("{} min {:02} s", whole / 60, whole % 60)
    } else {
        format!("{} h {:02} min", whole / 3600, (whole % 3600) / 60)
    }
}

/// The sheet as one HTML document.
#[must_use]
pub fn html(sheet: &Sheet) -> String {
    let mut o = String::new();
    let _ = write!(
        o,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>Setup sheet: {p}</title><style>\
         body{{font-family:sans-serif;margin:24px;color:#222}}\
         h1{{font-size:22px;margin:0 0 4px}}h2{{font-size:18px;margin:24px 0 8px;border-bottom:2px solid #444}}\
         table{{border-collapse:collapse;font-size:13px;margin:6px 0}}\
         th,td{{border:1px solid #bbb;padding:3px 7px;text-align:left;vertical-align:top}}\
         th{{background:#eee}}td.n{{text-align:right;font-variant-numeric:tabular-nums}}\
         .row{{display:flex;gap:18px;align-items:flex-start}}.warn{{color:#a05000}}\
         section{{page-break-inside:avoid}}\
         </style></head><body>\n<h1>Setup sheet: {p}</h1>\n<p>Part: {part} · Material: {m} · {n} setups · {t} tools</p>\n",
        p = esc(&sheet.project),
        part = esc(&sheet.part),
        m = esc(sheet.material.as_deref().unwrap_or("not set")),
        n = sheet.setups.len(),
        t = sheet.tools.len()
    );
    o.push_str("<h2>Tools</h2>\n<table><tr><th>T</th><th>Name</th><th>Spec</th><th>Ø mm</th><th>Flute mm</th><th>Stick-out mm</th><th>Holder</th></tr>\n");
    for t in &sheet.tools {
        let _ = writeln!(
            o,
            "<tr><td class=\"n\">T{}</td><td>{}</td><td>{}</td><td class=\"n\">{:.3}</td><td class=\"n\">{:.1}</td><td class=\"n\">{:.1}</td><td>{}</td></tr>",
            t.number,
            esc(&t.name),
            esc(&t.spec),
            t.diameter_mm,
            t.flute_mm,
            t.stick_out_mm,
            esc(&t.holder)
        );
    }
    o.push_str("</table>\n");
    for s in &sheet.setups {
        let p = &s.picture;
        let _ = write!(
            o,
            "<section><h2>Setup {}: {}</h2>\n<div class=\"row\"><svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\
             <image width=\"{w}\" height=\"{h}\" href=\"data:image/png;base64,{}\"/>",
            s.number,
            esc(&s.name),
            base64(&p.png),
            w = p.width,
            h = p.height
        );
        for (k, label) in ["X", "Y", "Z"].iter().enumerate() {
            let [x, y] = p.axes_px[k + 1];
            let c = AXIS_COLOURS[k];
            let _ = write!(
                o,
                "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"15\" font-weight=\"bold\" fill=\"rgb({},{},{})\">{label}</text>",
                x + 4.0,
                y - 4.0,
                c[0],
                c[1],
                c[2]
            );
        }
        let [ox, oy] = p.axes_px[0];
        let _ = writeln!(
            o,
            "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"13\" fill=\"#222\">{}</text></svg>",
            ox + 6.0,
            oy + 16.0,
            esc(&s.work_offset)
        );
        let total_feed: f64 = s.operations.iter().map(|op| op.time_at_feed_s).sum();
        let total_cycle: Result<f64, String> =
            s.operations.iter().map(|op| op.cycle_time_s.clone()).sum();
        let _ = writeln!(
            o,
            "<table><tr><th>Machine</th><td>{}</td></tr><tr><th>Work offset</th><td>{} (origin at the marked axes)</td></tr>\
             <tr><th>Tool axis</th><td>{:.4}, {:.4}, {:.4}</td></tr>\
             <tr><th>Stock</th><td>{} · {:.2} × {:.2} × {:.2} mm</td></tr><tr><th>Workholding</th><td>{}</td></tr>\
             <tr><th>Time at feed</th><td>{}</td></tr><tr><th>Cycle time</th><td>{}</td></tr>\
             <tr><th>Picture</th><td>drawn by {}</td></tr></table></div>",
            esc(&s.machine),
            esc(&s.work_offset),
            s.tool_axis[0],
            s.tool_axis[1],
            s.tool_axis[2],
            esc(&s.stock),
            s.stock_size_mm[0],
            s.stock_size_mm[1],
            s.stock_size_mm[2],
            if s.workholding.is_empty() {
                "none".to_string()
            } else {
                esc(&s.workholding.join("; "))
            },
            duration(total_feed),
            total_cycle.map_or_else(|e| format!("— ({})", esc(&e)), duration),
            esc(&p.renderer)
        );
        o.push_str("<table><tr><th>#</th><th>Operation</th><th>Strategy</th><th>Tool</th><th>Feed mm/min</th><th>Plunge mm/min</th><th>Spindle rpm</th><th>Heights</th><th>Time at feed</th><th>Cycle time</th><th>Notes</th></tr>\n");
        for op in &s.operations {
            let notes: Vec<String> =
                std::iter::once(format!("<div>Speeds {}</div>", esc(&op.speeds_from)))
                    .chain(
                        op.warnings
                            .iter()
                            .map(|w| format!("<div class=\"warn\">{}</div>", esc(w))),
                    )
                    .collect();
            let _ = writeln!(
                o,
                "<tr><td class=\"n\">{}</td><td>{}</td><td>{}</td><td>T{}</td><td class=\"n\">{:.0}</td><td class=\"n\">{}</td><td class=\"n\">{:.0}</td><td>{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td><td>{}</td></tr>",
                op.number,
                esc(&op.name),
                esc(&op.strategy),
                op.tool,
                op.feed_mm_per_min,
                op.plunge_mm_per_min
                    .map_or_else(|| "—".into(), |f| format!("{f:.0}")),
                op.spindle_rpm,
                esc(&op.heights),
                duration(op.time_at_feed_s),
                op.cycle_time_s
                    .as_ref()
                    .map_or_else(|e| format!("— ({})", esc(e)), |t| duration(*t)),
                notes.join("")
            );
        }
        o.push_str("</table></section>\n");
    }
    o.push_str("</body></html>\n");
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc_4648_vectors() {
        for (raw, enc) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(raw.as_bytes()), enc);
        }
    }

    /// A unit cube seen from the front, right and above covers the hexagon of its projection:
    /// area √3 · s² in pixels (s the pixel scale), within the rim's pixels.
    #[test]
    fn a_cube_covers_its_projected_hexagon() {
        let b = Aabb {
            min: DVec3::splat(0.0),
            max: DVec3::splat(10.0),
        };
        let c = corners(&b);
        let quads = [
            [0, 1, 3, 2],
            [4, 6, 7, 5],
            [0, 4, 5, 1],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 5, 7, 3],
        ];
        let mut tris = Vec::new();
        for q in quads {
            tris.push([q[0], q[1], q[2]]);
            tris.push([q[0], q[2], q[3]]);
        }
        let mesh = TriMesh::new(c.to_vec(), tris);
        let body = Body {
            mesh: &mesh,
            colour: [200, 200, 200],
        };
        let pic = draw(&[body], None, 400, 400);
        assert!(pic.png.starts_with(b"\x89PNG\r\n\x1a\n"));
        // The picture's scale from the axes drawn: the X axis (length 5 mm here: 0.3·10
        // clamped to 5) projects to 5·|x·right|... measured instead from the origin to the X
        // tip, whose screen length is 5·sqrt(2/3) mm times the scale.
        let [o, x] = [pic.axes_px[0], pic.axes_px[1]];
        let s = (x[0] - o[0]).hypot(x[1] - o[1]) / (5.0 * (2.0_f64 / 3.0).sqrt());
        let hexagon = 3.0_f64.sqrt() * (10.0 * s).powi(2);
        let rim = 6.0 * 10.0 * s * (2.0_f64 / 3.0).sqrt();
        let covered = pic.covered_px as f64;
        assert!(
            (covered - hexagon).abs() < rim,
            "covered {covered} px against the hexagon's {hexagon:.0} ± {rim:.0}"
        );
        // The same input gives the same bytes.
        let again = draw(
            &[Body {
                mesh: &mesh,
                colour: [200, 200, 200],
            }],
            None,
            400,
            400,
        );
        assert_eq!(again.png, pic.png);
    }

    #[test]
    fn durations_read_naturally() {
        assert_eq!(duration(12.34), "12.3 s");
        assert_eq!(duration(185.0), "3 min 05 s");
        assert_eq!(duration(3725.0), "1 h 02 min");
    }
}
