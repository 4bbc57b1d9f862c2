//! Binary STL: an 80-byte header, a little-endian `u32` facet count, then 50 bytes a facet
//! (normal, three vertices as 12 `f32`, and a `u16` attribute).

use std::path::Path;

use super::RawFacets;
use crate::diagnostics::Diagnostic;
use crate::geometry::DVec3;
use crate::import::ImportError;

/// Header length, bytes.
pub(super) const HEADER_LEN: usize = 80;
/// Header plus facet count, bytes.
pub(super) const PREAMBLE_LEN: usize = 84;
/// One facet, bytes.
pub(super) const FACET_LEN: usize = 50;

/// The facet count the header claims, when the file is long enough to have one.
pub(super) fn count(bytes: &[u8]) -> Option<u32> {
    let b: [u8; 4] = bytes.get(HEADER_LEN..PREAMBLE_LEN)?.try_into().ok()?;
    Some(u32::from_le_bytes(b))
}

/// The file length the header's facet count implies (`84 + 50 · count`).
pub(super) fn expected_len(bytes: &[u8]) -> Option<u64> {
    count(bytes).map(|n| PREAMBLE_LEN as u64 + FACET_LEN as u64 * u64::from(n))
}

/// The little-endian `f32` at `off`.
fn f32_at(bytes: &[u8], off: usize) -> Option<f32> {
    let b: [u8; 4] = bytes.get(off..off.checked_add(4)?)?.try_into().ok()?;
    Some(f32::from_le_bytes(b))
}

/// The point (three `f32`) at `off`.
fn vec_at(bytes: &[u8], off: usize) -> Option<[f32; 3]> {
    Some([
        f32_at(bytes, off)?,
        f32_at(bytes, off + 4)?,
        f32_at(bytes, off + 8)?,
    ])
}

/// The header's printable text, trimmed (empty when it holds none).
fn header_name(bytes: &[u8]) -> String {
    let header = bytes.get(..HEADER_LEN).unwrap_or(bytes);
    let end = header.iter().position(|&c| c == 0).unwrap_or(header.len());
    let text: String = header
        .iter()
        .take(end)
        .map(|&c| {
            if c.is_ascii_graphic() {
                char::from(c)
            } else {
                ' '
            }
        })
        .collect();
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Parse a binary STL. The length must match the header's count, except that fewer than 50
/// stray bytes after the last facet are ignored with a warning.
pub(super) fn parse(bytes: &[u8], file: &Path) -> Result<RawFacets, ImportError> {
    let len = bytes.len();
    let (Some(count), Some(expected)) = (count(bytes), expected_len(bytes)) else {
        return Err(ImportError::new(
            file,
            Some(format!("byte {len}")),
            format!(
                "file is {len} bytes: too short for a binary STL (84-byte header and count) and \
                 it does not start with \"solid\" as an ASCII STL does"
            ),
        ));
    };
    let room = (len - PREAMBLE_LEN) / FACET_LEN;
    let mut diagnostics = Vec::new();
    if (len as u64) < expected {
        let at = PREAMBLE_LEN + FACET_LEN * room;
        return Err(ImportError::new(
            file,
            Some(format!("facet {room}, byte {at}")),
            format!(
                "truncated binary STL: the header claims {count} facets ({expected} bytes) but \
                 the file has {len} bytes, ending inside facet {room}"
            ),
        ));
    }
    let extra = len as u64 - expected;
    if extra >= FACET_LEN as u64 {
        return Err(ImportError::new(
            file,
            Some(format!("byte {expected}")),
            format!(
                "facet count mismatch: the header claims {count} facets ({expected} bytes) but \
                 the file has {len} bytes, room for {room} facets"
            ),
        ));
    }
    if extra > 0 {
        diagnostics.push(Diagnostic::warning(
            Some(format!("byte {expected}")),
            format!("{extra} stray bytes after the last facet ignored"),
        ));
    }
    // Here `room == count`: the length check bounds the count by the file size, so these
    // allocations are justified by bytes actually present.
    let n = room;
    let mut corners = Vec::with_capacity(n);
    let mut normals = Vec::with_capacity(n);
    let mut bad_normals = 0_usize;
    for k in 0..n {
        let off = PREAMBLE_LEN + FACET_LEN * k;
        let truncated = || {
            ImportError::new(
                file,
                Some(format!("facet {k}, byte {off}")),
                "facet runs past the end of the file",
            )
        };
        let normal = vec_at(bytes, off).ok_or_else(truncated)?;
        let mut c = [DVec3::ZERO; 3];
        for (j, corner) in c.iter_mut().enumerate() {
            let at = off + 12 + 12 * j;
            let v = vec_at(bytes, at).ok_or_else(truncated)?;
            if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                let what = if x.is_nan() { "NaN" } else { "infinite" };
                return Err(ImportError::new(
                    file,
                    Some(format!("facet {k}, byte {}", at + 4 * i)),
                    format!("vertex {j} has a {what} coordinate"),
                ));
            }
            *corner = DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
        }
        let nv = DVec3::new(
            f64::from(normal[0]),
            f64::from(normal[1]),
            f64::from(normal[2]),
        );
        if nv.is_finite() {
            normals.push(nv);
        } else {
            bad_normals += 1;
            normals.push(DVec3::ZERO);
        }
        corners.push(c);
    }
    if bad_normals > 0 {
        diagnostics.push(Diagnostic::warning(
            None,
            format!("{bad_normals} facets store a non-finite normal; the vertex winding is used"),
        ));
    }
    Ok(RawFacets {
        corners,
        normals,
        name: header_name(bytes),
        diagnostics,
    })
}
