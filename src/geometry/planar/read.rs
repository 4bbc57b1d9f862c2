//! Profile readers: CSV (`x, y[, bulge]` per row), DXF (LWPOLYLINE, LINE, ARC through the
//! `dxf` crate) and SVG path data (through `svgtypes`).
//!
//! Every error names the file and the row, line or entity. Arcs of more than a half circle are
//! split in two so every bulge stays within ±1. A profile whose last point repeats its first is
//! closed.

use glam::DVec2;
use std::path::Path;

use super::element::Element;
use super::{MAX_COORD_MM, Profile, ProfileError, Vertex};

/// The file formats a profile is read from and written to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProfileFormat {
    /// `x, y[, bulge]` per row.
    Csv,
    /// DXF (LWPOLYLINE, LINE, ARC).
    Dxf,
    /// SVG (the `d` of one `<path>`).
    Svg,
}

impl ProfileFormat {
    /// The format of a file name by its extension.
    #[must_use]
    pub fn of_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "csv" | "txt" | "xy" => Some(Self::Csv),
            "dxf" => Some(Self::Dxf),
            "svg" => Some(Self::Svg),
            _ => None,
        }
    }
}

/// Reads a profile file (format by extension; SVG curves flattened within `tolerance_mm`).
///
/// # Errors
/// [`ProfileError`] naming the file and place.
pub fn read_profile(path: &Path, tolerance_mm: f64) -> Result<Profile, ProfileError> {
    let file = path.display().to_string();
    let format = ProfileFormat::of_path(path).ok_or_else(|| {
        ProfileError::new(
            &file,
            "name",
            "unknown extension (expected .csv, .dxf or .svg)",
        )
    })?;
    let bytes = crate::storage::read_bounded(path, crate::storage::TEXT_LIMIT_BYTES)
        .map_err(|e| ProfileError::new(&file, "file", e.to_string()))?;
    let profile = match format {
        ProfileFormat::Dxf => parse_dxf(&bytes, &file)?,
        ProfileFormat::Csv | ProfileFormat::Svg => {
            let text = String::from_utf8(bytes).map_err(|e| {
                ProfileError::new(
                    &file,
                    format!("byte {}", e.utf8_error().valid_up_to()),
                    "not UTF-8 text",
                )
            })?;
            if format == ProfileFormat::Csv {
                parse_csv(&text, &file)?
            } else {
                parse_svg(&text, &file, tolerance_mm)?
            }
        }
    };
    profile.validate(&file)?;
    Ok(profile)
}

/// Adds the element from the last vertex to `b` with `bulge`, split in two when it sweeps more
/// than a half circle.
fn push_to(vertices: &mut Vec<Vertex>, b: DVec2, bulge: f64) {
    if let Some(last) = vertices.last_mut() {
        if bulge.abs() > 1.0 {
            let a = last.pos();
            let e = Element::from_bulge(a, b, bulge);
            let half = (bulge.atan() / 2.0).tan();
            last.bulge = half;
            let m = e.point_at(0.5);
            vertices.push(Vertex {
                x: m.x,
                y: m.y,
                bulge: half,
            });
        } else {
            last.bulge = bulge;
        }
    }
    vertices.push(Vertex::point(b.x, b.y));
}

/// [`push_to`] for the SVG reader.
pub(super) fn push_to_pub(vertices: &mut Vec<Vertex>, b: DVec2, bulge: f64) {
    push_to(vertices, b, bulge);
}

/// [`close_if_repeated`] (exact repeat) for the SVG reader.
pub(super) fn close_if_repeated_pub(vertices: &mut Vec<Vertex>) -> bool {
    close_if_repeated(vertices, 0.0)
}

/// Closes the profile when its last point repeats the first (within `eps`).
fn close_if_repeated(vertices: &mut Vec<Vertex>, eps: f64) -> bool {
    if vertices.len() < 4 {
        return false;
    }
    let (Some(first), Some(last)) = (vertices.first(), vertices.last()) else {
        return false;
    };
    if (first.pos() - last.pos()).length() <= eps {
        vertices.pop();
        true
    } else {
        false
    }
}

fn parse_number(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok()
}

/// Parses CSV: one point per row as `x, y` or `x, y, bulge` (comma, semicolon, tab or spaces
/// between); `#` starts a comment; a first row that is not numeric is a header.
///
/// # Errors
/// [`ProfileError`] naming the row (1-based line).
pub fn parse_csv(text: &str, file: &str) -> Result<Profile, ProfileError> {
    let mut vertices: Vec<Vertex> = Vec::new();
    let mut seen_data = false;
    for (k, raw) in text.lines().enumerate() {
        let row = k + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line
            .split([',', ';', '\t', ' '])
            .filter(|f| !f.trim().is_empty())
            .collect();
        let numbers: Vec<Option<f64>> = fields.iter().map(|f| parse_number(f)).collect();
        if !seen_data && numbers.iter().all(Option::is_none) {
            continue; // header
        }
        seen_data = true;
        let place = format!("row {row}");
        if vertices.len() >= super::MAX_PROFILE_POINTS {
            return Err(ProfileError::new(
                file,
                place,
                format!(
                    "more than {} points, the most a profile may have",
                    super::MAX_PROFILE_POINTS
                ),
            ));
        }
        if fields.len() < 2 || fields.len() > 3 {
            return Err(ProfileError::new(
                file,
                place,
                format!(
                    "expected x, y or x, y, bulge; found {} fields",
                    fields.len()
                ),
            ));
        }
        let mut vals = [0.0; 3];
        for (i, (f, n)) in fields.iter().zip(&numbers).enumerate() {
            let name = ["x", "y", "bulge"].get(i).copied().unwrap_or("?");
            let v = n.ok_or_else(|| {
                ProfileError::new(
                    file,
                    place.clone(),
                    format!("{name} {:?} is not a number", f.trim()),
                )
            })?;
            if !v.is_finite() {
                return Err(ProfileError::new(
                    file,
                    place,
                    format!("{name} is not finite"),
                ));
            }
            if let Some(slot) = vals.get_mut(i) {
                *slot = v;
            }
        }
        let [x, y, bulge] = vals;
        if x.abs() > MAX_COORD_MM || y.abs() > MAX_COORD_MM {
            return Err(ProfileError::new(
                file,
                place,
                format!("coordinate beyond ±{MAX_COORD_MM} mm"),
            ));
        }
        if bulge.abs() > 1.0 {
            return Err(ProfileError::new(
                file,
                place,
                format!("bulge {bulge} beyond ±1 (more than a half circle); split the arc"),
            ));
        }
        if let Some(prev) = vertices.last()
            && prev.x == x
            && prev.y == y
        {
            return Err(ProfileError::new(file, place, "repeats the previous point"));
        }
        vertices.push(Vertex { x, y, bulge });
    }
    let closed = close_if_repeated(&mut vertices, 0.0);
    Ok(Profile { vertices, closed })
}

/// Parses a DXF drawing: one LWPOLYLINE, or LINE and ARC entities that chain end to end.
///
/// # Errors
/// [`ProfileError`] naming the entity (1-based, in file order).
pub fn parse_dxf(bytes: &[u8], file: &str) -> Result<Profile, ProfileError> {
    let mut reader = std::io::Cursor::new(bytes);
    let drawing = dxf::Drawing::load(&mut reader)
        .map_err(|e| ProfileError::new(file, "drawing", e.to_string()))?;
    let mut polylines = Vec::new();
    let mut pieces: Vec<(usize, Element)> = Vec::new();
    for (k, ent) in drawing.entities().enumerate() {
        let n = k + 1;
        match &ent.specific {
            dxf::entities::EntityType::LwPolyline(pl) => polylines.push((n, pl.clone())),
            dxf::entities::EntityType::Line(l) => pieces.push((
                n,
                Element::Line {
                    a: DVec2::new(l.p1.x, l.p1.y),
                    b: DVec2::new(l.p2.x, l.p2.y),
                },
            )),
            dxf::entities::EntityType::Arc(a) => {
                if a.normal.z < 0.0 {
                    return Err(ProfileError::new(
                        file,
                        format!("entity {n}"),
                        "ARC with a downward normal (mirrored) is not supported",
                    ));
                }
                let c = DVec2::new(a.center.x, a.center.y);
                let s = a.start_angle.to_radians();
                let mut sweep = (a.end_angle - a.start_angle)
                    .to_radians()
                    .rem_euclid(std::f64::consts::TAU);
                if sweep == 0.0 {
                    sweep = std::f64::consts::TAU;
                }
                let p0 = c + DVec2::from_angle(s) * a.radius;
                let p1 = c + DVec2::from_angle(s + sweep) * a.radius;
                pieces.push((n, Element::from_bulge(p0, p1, (sweep / 4.0).tan())));
            }
            _ => {}
        }
    }
    match (polylines.len(), pieces.is_empty()) {
        (1, true) => {
            let (n, pl) = polylines.remove(0);
            lwpolyline(&pl, file, n)
        }
        (0, false) => chain(&pieces, file),
        (0, true) => Err(ProfileError::new(
            file,
            "drawing",
            "no LWPOLYLINE, LINE or ARC",
        )),
        _ => Err(ProfileError::new(
            file,
            "drawing",
            "more than one contour (one LWPOLYLINE, or LINE/ARC entities that chain into one)",
        )),
    }
}

fn lwpolyline(
    pl: &dxf::entities::LwPolyline,
    file: &str,
    n: usize,
) -> Result<Profile, ProfileError> {
    let mut vertices: Vec<Vertex> = Vec::new();
    for (i, v) in pl.vertices.iter().enumerate() {
        if !(v.x.is_finite() && v.y.is_finite() && v.bulge.is_finite()) {
            return Err(ProfileError::new(
                file,
                format!("entity {n}, vertex {}", i + 1),
                "non-finite number",
            ));
        }
        if vertices.is_empty() {
            vertices.push(Vertex::point(v.x, v.y));
        } else {
            let prev_bulge = vertices.last().map_or(0.0, |p| p.bulge);
            push_to(&mut vertices, DVec2::new(v.x, v.y), prev_bulge);
        }
        if let Some(last) = vertices.last_mut() {
            last.bulge = v.bulge;
        }
    }
    let closed = pl.is_closed();
    if closed && let Some(last) = vertices.last().copied() {
        // Split the closing element too when it sweeps more than a half circle.
        if last.bulge.abs() > 1.0
            && let Some(first) = vertices.first().copied()
        {
            if let Some(l) = vertices.last_mut() {
                l.bulge = 0.0;
            }
            push_to(&mut vertices, first.pos(), last.bulge);
            vertices.pop();
        }
    }
    Ok(Profile { vertices, closed })
}

/// Chains LINE and ARC entities end to end (reversing entities where needed).
fn chain(pieces: &[(usize, Element)], file: &str) -> Result<Profile, ProfileError> {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for (_, e) in pieces {
        lo = lo.min(e.start()).min(e.end());
        hi = hi.max(e.start()).max(e.end());
    }
    let eps = 1e-9 * (hi - lo).max_element().max(1.0);
    let same = |a: DVec2, b: DVec2| (a - b).length() <= eps;
    let reverse = |e: &Element| match *e {
        Element::Line { a, b } => Element::Line { a: b, b: a },
        Element::Arc {
            a, b, sweep_rad, ..
        } => Element::from_bulge(b, a, -(sweep_rad / 4.0).tan()),
    };
    // Start at a piece whose start no other piece touches (an open chain), else the first.
    let touches = |p: DVec2, skip: usize| {
        pieces
            .iter()
            .enumerate()
            .any(|(k, (_, e))| k != skip && (same(e.start(), p) || same(e.end(), p)))
    };
    let mut used = vec![false; pieces.len()];
    let mut order: Vec<Element> = Vec::new();
    let start = (0..pieces.len())
        .find_map(|k| {
            let (_, e) = pieces.get(k)?;
            if !touches(e.start(), k) {
                Some((k, *e))
            } else if !touches(e.end(), k) {
                Some((k, reverse(e)))
            } else {
                None
            }
        })
        .or_else(|| pieces.first().map(|(_, e)| (0, *e)));
    let Some((k0, e0)) = start else {
        return Err(ProfileError::new(file, "drawing", "no entities"));
    };
    if let Some(u) = used.get_mut(k0) {
        *u = true;
    }
    order.push(e0);
    while order.len() < pieces.len() {
        let end = order.last().map_or(DVec2::ZERO, Element::end);
        let next = pieces.iter().enumerate().find_map(|(k, (_, e))| {
            if used.get(k).copied().unwrap_or(true) {
                None
            } else if same(e.start(), end) {
                Some((k, *e))
            } else if same(e.end(), end) {
                Some((k, reverse(e)))
            } else {
                None
            }
        });
        let Some((k, e)) = next else {
            let first_unused = pieces
                .iter()
                .zip(&used)
                .find(|(_, u)| !**u)
                .map_or(0, |((n, _), _)| *n);
            return Err(ProfileError::new(
                file,
                format!("entity {first_unused}"),
                "does not connect to the chain of the other LINE/ARC entities (one contour per file)",
            ));
        };
        if let Some(u) = used.get_mut(k) {
            *u = true;
        }
        order.push(e);
    }
    let mut vertices = vec![];
    if let Some(first) = order.first() {
        vertices.push(Vertex::point(first.start().x, first.start().y));
    }
    for e in &order {
        let bulge = match *e {
            Element::Line { .. } => 0.0,
            Element::Arc { sweep_rad, .. } => (sweep_rad / 4.0).tan(),
        };
        push_to(&mut vertices, e.end(), bulge);
    }
    let closed = close_if_repeated(&mut vertices, eps);
    Ok(Profile { vertices, closed })
}

/// The `d` attributes of the `<path>` elements of an SVG document (or the text itself when it
/// holds no `<`: bare path data).
fn path_data(text: &str) -> Vec<(usize, String)> {
    if !text.contains('<') {
        return vec![(1, text.to_string())];
    }
    let mut out = Vec::new();
    let mut rest = text;
    let mut offset = 0;
    while let Some(i) = rest.find("<path") {
        let tag_start = offset + i;
        let after = &rest[i..];
        let tag_end = after.find('>').unwrap_or(after.len());
        let tag = &after[..tag_end];
        if let Some(d) = attribute(tag, "d") {
            let line = text[..tag_start].matches('\n').count() + 1;
            out.push((line, d));
        }
        offset = tag_start + tag_end.max(1);
        rest = &text[offset..];
    }
    out
}

fn attribute(tag: &str, name: &str) -> Option<String> {
    let mut search = 0;
    while let Some(i) = tag[search..].find(name) {
        let at = search + i;
        let before = tag[..at].chars().next_back();
        let rest = tag[at + name.len()..].trim_start();
        if before.is_some_and(char::is_whitespace)
            && let Some(r) = rest.strip_prefix('=')
        {
            let r = r.trim_start();
            let quote = r.chars().next()?;
            if quote == '"' || quote == '\'' {
                let body = &r[1..];
                let end = body.find(quote)?;
                return Some(body[..end].to_string());
            }
        }
        search = at + name.len();
    }
    None
}

/// Parses SVG path data (one `<path>` with one subpath, or bare path data). SVG's y axis points
/// down; the profile is mirrored to y up. Lines (M, L, H, V, Z) and circular arcs are exact;
/// cubic and quadratic Béziers are flattened within `tolerance_mm`; elliptical arcs are refused.
///
/// # Errors
/// [`ProfileError`] naming the line of the `<path>` and the segment number.
pub fn parse_svg(text: &str, file: &str, tolerance_mm: f64) -> Result<Profile, ProfileError> {
    // A tolerance far below any machine's resolution flattens each curve into up to 100 000
    // points (`--tolerance 1e-12` stalled `talas profile`): the bounds every tolerance has.
    crate::units::TOLERANCE_BOUNDS
        .check(&format!("tolerance {tolerance_mm} mm"), tolerance_mm)
        .map_err(|m| ProfileError::new(file, "tolerance", m))?;
    let paths = path_data(text);
    let [(line, d)] = paths.as_slice() else {
        return Err(ProfileError::new(
            file,
            "document",
            format!("expected one <path>, found {}", paths.len()),
        ));
    };
    super::read_svg::parse_path(d, file, *line, tolerance_mm)
}
