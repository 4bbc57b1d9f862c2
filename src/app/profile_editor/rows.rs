//! The point table as typed text, checked row by row before anything is computed.
//!
//! The input rules: x and y are numbers within ±[`MAX_COORD_MM`] mm, the bulge (empty for a
//! line) lies within ±1, a point does not repeat the point before it (a zero-length element),
//! and, under the rule "y = f(x)" of the per-point method, x runs one way without repeating (a
//! repeated x is a vertical wall that method cannot handle). Every broken rule is a message on
//! its row; the profile is built only when no row has an error.

use glam::DVec2;

use crate::app::number_field::format_number;
use crate::profile::{MAX_COORD_MM, Profile, Vertex};

/// One row of the table, as typed.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Row {
    /// x, mm.
    pub x: String,
    /// y, mm.
    pub y: String,
    /// Bulge of the element to the next point (empty: a line).
    pub bulge: String,
}

impl Row {
    /// A row holding a point (and a bulge when it is not zero).
    #[must_use]
    pub fn from_vertex(v: &Vertex) -> Self {
        Self {
            x: format_number(v.x, 6),
            y: format_number(v.y, 6),
            bulge: if v.bulge == 0.0 {
                String::new()
            } else {
                format_number(v.bulge, 9)
            },
        }
    }

    /// A row for the point `p` (a line to the next point).
    #[must_use]
    pub fn at(p: DVec2) -> Self {
        Self {
            x: format_number(p.x, 6),
            y: format_number(p.y, 6),
            bulge: String::new(),
        }
    }
}

/// How bad a message is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    /// The row cannot be used; nothing is computed until it is fixed.
    Error,
    /// Worth knowing; the profile is still computed.
    Warning,
}

/// A message about one row (0-based).
#[derive(Clone, Debug, PartialEq)]
pub struct RowMessage {
    /// The row, 0-based.
    pub row: usize,
    /// Error or warning.
    pub level: Level,
    /// What is wrong, with units.
    pub text: String,
}

/// What the table holds once checked.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Checked {
    /// Every row whose x and y are usable: (row, point, bulge).
    pub points: Vec<(usize, DVec2, f64)>,
    /// Messages per row, in row order.
    pub messages: Vec<RowMessage>,
    /// A message about the table as a whole (too few points, a closed contour under y = f(x)).
    pub profile_message: Option<String>,
    /// The profile, when no row has an error (vertex i is row i).
    pub profile: Option<Profile>,
}

impl Checked {
    /// The messages of row `row`.
    pub fn row_messages(&self, row: usize) -> impl Iterator<Item = &RowMessage> {
        self.messages.iter().filter(move |m| m.row == row)
    }

    /// Does any row have an error?
    #[must_use]
    pub fn has_errors(&self) -> bool {
        self.messages.iter().any(|m| m.level == Level::Error)
    }
}

fn mm(v: f64) -> String {
    format!("{} mm", format_number(v, 6))
}

/// Reads cell `name` of a row: a number (an `mm` suffix is allowed) within ±`limit`.
fn cell(text: &str, name: &str, limit: f64, unit: &str) -> Result<f64, String> {
    let t = text.trim();
    if t.is_empty() {
        return Err(format!("{name} is empty"));
    }
    let t = t.strip_suffix("mm").unwrap_or(t).trim();
    let v: f64 = t
        .parse()
        .map_err(|_| format!("{name} '{}' is not a number", text.trim()))?;
    if !v.is_finite() {
        return Err(format!("{name} '{}' is not a finite number", text.trim()));
    }
    if v.abs() > limit {
        return Err(format!(
            "{name} = {}{unit} lies beyond ±{}{unit}",
            format_number(v, 6),
            format_number(limit, 6)
        ));
    }
    Ok(v)
}

/// Checks every row (see the module documentation). `closed`: the last point joins the first;
/// `function_of_x`: apply the rule y = f(x).
#[must_use]
pub fn check_rows(rows: &[Row], closed: bool, function_of_x: bool) -> Checked {
    let mut out = Checked::default();
    let error = |out: &mut Checked, row: usize, text: String| {
        out.messages.push(RowMessage {
            row,
            level: Level::Error,
            text,
        });
    };
    for (i, r) in rows.iter().enumerate() {
        let x = cell(&r.x, "x", MAX_COORD_MM, " mm");
        let y = cell(&r.y, "y", MAX_COORD_MM, " mm");
        let bulge = if r.bulge.trim().is_empty() {
            Ok(0.0)
        } else {
            cell(&r.bulge, "bulge", 1.0, "").map_err(|e| {
                if e.contains("beyond") {
                    format!("{e} (more than a half circle: split the arc)")
                } else {
                    e
                }
            })
        };
        let mut ok = true;
        for e in [x.as_ref().err(), y.as_ref().err(), bulge.as_ref().err()]
            .into_iter()
            .flatten()
        {
            error(&mut out, i, e.clone());
            ok = false;
        }
        if let (true, Ok(x), Ok(y), Ok(b)) = (ok, x, y, bulge) {
            out.points.push((i, DVec2::new(x, y), b));
        }
    }
    repeated_points(&mut out, closed);
    if function_of_x {
        if closed {
            out.profile_message = Some(
                "a closed contour is not a function y = f(x): turn the rule off to offset it"
                    .into(),
            );
        } else {
            function_rule(&mut out);
        }
    }
    out.messages.sort_by_key(|m| m.row);
    let need = if closed { 3 } else { 2 };
    if out.points.len() < need && out.profile_message.is_none() {
        out.profile_message = Some(format!(
            "a {} profile needs at least {need} points; {} usable",
            if closed { "closed" } else { "open" },
            out.points.len()
        ));
    }
    if !out.has_errors() && out.profile_message.is_none() {
        build(&mut out, rows.len(), closed);
    }
    out
}

/// A point that repeats the point before it (the last and the first of a closed profile too).
fn repeated_points(out: &mut Checked, closed: bool) {
    let n = out.points.len();
    let pairs = if closed && n > 2 {
        n
    } else {
        n.saturating_sub(1)
    };
    let mut found = Vec::new();
    for k in 0..pairs {
        let (Some(&(ra, a, _)), Some(&(rb, b, _))) =
            (out.points.get(k), out.points.get((k + 1) % n))
        else {
            continue;
        };
        if a == b {
            found.push(RowMessage {
                row: rb,
                level: Level::Error,
                text: format!(
                    "repeats the point of row {} ({}, {}): a zero-length element",
                    ra + 1,
                    mm(a.x),
                    mm(a.y)
                ),
            });
        }
    }
    out.messages.extend(found);
}

/// The rule y = f(x): x runs one way (the way of the first two points) and never repeats.
fn function_rule(out: &mut Checked) {
    let mut found = Vec::new();
    let mut dir = 0.0_f64;
    for w in out.points.windows(2) {
        let [(ra, a, _), (rb, b, _)] = w else {
            continue;
        };
        let dx = b.x - a.x;
        if dx == 0.0 {
            found.push(RowMessage {
                row: *rb,
                level: Level::Error,
                text: format!(
                    "x = {} repeats row {}: a vertical wall, which y = f(x) cannot hold",
                    mm(b.x),
                    ra + 1
                ),
            });
        } else if dir == 0.0 {
            dir = dx.signum();
        } else if dx.signum() != dir {
            found.push(RowMessage {
                row: *rb,
                level: Level::Error,
                text: format!(
                    "x = {} goes back past row {} (x = {}): y = f(x) needs x to run one way",
                    mm(b.x),
                    ra + 1,
                    mm(a.x)
                ),
            });
        }
    }
    out.messages.extend(found);
}

/// The profile of a table without errors, checked once more by the engine (which names a
/// vertex; vertex i is row i).
fn build(out: &mut Checked, rows: usize, closed: bool) {
    let profile = Profile {
        vertices: out
            .points
            .iter()
            .map(|&(_, p, bulge)| Vertex {
                x: p.x,
                y: p.y,
                bulge,
            })
            .collect(),
        closed,
    };
    match profile.validate("table") {
        Ok(()) => out.profile = Some(profile),
        Err(e) => {
            let row = e
                .place
                .strip_prefix("vertex ")
                .and_then(|n| n.parse::<usize>().ok())
                .map(|n| n.saturating_sub(1).min(rows.saturating_sub(1)));
            match row {
                Some(row) => out.messages.push(RowMessage {
                    row,
                    level: Level::Error,
                    text: e.message,
                }),
                None => out.profile_message = Some(e.message),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(cells: &[(&str, &str)]) -> Vec<Row> {
        cells
            .iter()
            .map(|(x, y)| Row {
                x: (*x).into(),
                y: (*y).into(),
                bulge: String::new(),
            })
            .collect()
    }

    #[test]
    fn a_clean_table_gives_the_profile() {
        let c = check_rows(
            &rows(&[("0", "0"), ("1", "2 mm"), ("3", "-1")]),
            false,
            true,
        );
        assert!(c.messages.is_empty(), "{:?}", c.messages);
        let p = c.profile.expect("profile");
        assert_eq!(p.vertices.len(), 3);
        assert_eq!(p.vertices[1].y, 2.0);
    }

    #[test]
    fn each_broken_rule_is_a_message_on_its_row_and_blocks_the_profile() {
        let c = check_rows(
            &rows(&[
                ("0", "0"),
                ("abc", "1"),
                ("2", ""),
                ("2", "1"),
                ("2", "3"),
                ("1", "0"),
                ("5", "1e9"),
            ]),
            false,
            true,
        );
        let texts: Vec<(usize, &str)> = c
            .messages
            .iter()
            .map(|m| (m.row, m.text.as_str()))
            .collect();
        assert!(c.profile.is_none());
        assert!(texts.contains(&(1, "x 'abc' is not a number")), "{texts:?}");
        assert!(texts.contains(&(2, "y is empty")), "{texts:?}");
        assert!(
            texts
                .iter()
                .any(|(r, t)| *r == 4 && t.contains("repeats row 4: a vertical wall")),
            "{texts:?}"
        );
        assert!(
            texts
                .iter()
                .any(|(r, t)| *r == 5 && t.contains("goes back past row 5")),
            "{texts:?}"
        );
        assert!(
            texts
                .iter()
                .any(|(r, t)| *r == 6 && t.contains("beyond ±1000000 mm")),
            "{texts:?}"
        );
        // Without the rule a wall is fine.
        let c = check_rows(&rows(&[("0", "0"), ("0", "1"), ("1", "1")]), false, false);
        assert!(c.profile.is_some(), "{:?}", c.messages);
    }

    #[test]
    fn repeated_points_bulges_and_too_few_points_are_reported() {
        let mut r = rows(&[("0", "0"), ("0", "0"), ("1", "1")]);
        let c = check_rows(&r, false, false);
        assert_eq!(c.messages.len(), 1);
        assert_eq!(c.messages[0].row, 1);
        assert!(c.messages[0].text.contains("zero-length"));
        r[1] = Row {
            x: "0.5".into(),
            y: "0".into(),
            bulge: "1.5".into(),
        };
        let c = check_rows(&r, false, false);
        assert!(
            c.messages[0].text.contains("half circle"),
            "{:?}",
            c.messages
        );
        let c = check_rows(&rows(&[("0", "0")]), false, false);
        assert!(c.profile_message.is_some_and(|m| m.contains("at least 2")));
        let c = check_rows(&rows(&[("0", "0"), ("1", "0"), ("0", "1")]), true, true);
        assert!(
            c.profile_message
                .is_some_and(|m| m.contains("closed contour"))
        );
        let c = check_rows(&rows(&[("0", "0"), ("1", "0"), ("0", "1")]), true, false);
        assert!(c.profile.is_some_and(|p| p.closed));
    }
}
