//! LinuxCNC tool tables (`.tbl`): one tool a line,
//!
//! ```text
//! T1 P1 D6.0 Z+25.0 ;6 mm flat end mill
//! T2 P2 X0.5 Z30 D10 ;comment
//! ```
//!
//! `T` tool number (required), `P` pocket, `X Y Z` length offsets, `D` diameter, `A B C U V W`
//! (rotary and secondary offsets: accepted, must be 0 here), `I J Q` (lathe angles and
//! orientation: ignored); `;` starts the comment. Blank lines and lines that are only a
//! comment are skipped.
//!
//! The values are in the machine's length unit, which LinuxCNC takes from its INI file:
//! [`LengthUnit`] says which. Note that `rs274` run without an INI file reads every table in
//! inches (its stand-alone canon reports inches as the machine unit), so a `D6.0` there is a
//! 152.4 mm tool.

use std::collections::BTreeMap;

use glam::DVec3;

use super::GcodeError;
use crate::units::MM_PER_INCH;

/// The length unit of a tool table.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LengthUnit {
    /// Millimetres (a metric machine).
    #[default]
    Mm,
    /// Inches (an imperial machine, or `rs274` without an INI file).
    Inch,
}

impl LengthUnit {
    /// Millimetres per unit.
    #[must_use]
    pub fn mm(self) -> f64 {
        match self {
            Self::Mm => 1.0,
            Self::Inch => MM_PER_INCH,
        }
    }
}

/// One tool of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolEntry {
    /// Tool number (`T`).
    pub number: u32,
    /// Pocket (`P`; the tool number when absent).
    pub pocket: u32,
    /// Length offsets `X Y Z`, mm.
    pub offset_mm: DVec3,
    /// Diameter `D`, mm (may be negative: compensation then swaps sides, as in LinuxCNC).
    pub diameter_mm: f64,
    /// The text after `;`.
    pub comment: String,
}

/// A tool table: tools by number.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolTable {
    tools: BTreeMap<u32, ToolEntry>,
}

impl ToolTable {
    /// Read a table whose values are in `unit`.
    ///
    /// # Errors
    /// A [`GcodeError`] naming the line and column of a word that is not a letter and a
    /// number, a missing `T`, a tool listed twice or a non-zero rotary offset.
    pub fn parse(text: &str, unit: LengthUnit) -> Result<Self, GcodeError> {
        let mut tools = BTreeMap::new();
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let (body, comment) = raw.split_once(';').unwrap_or((raw, ""));
            if body.trim().is_empty() {
                continue;
            }
            let entry = parse_entry(body, line, unit, comment.trim())?;
            let number = entry.number;
            if tools.insert(number, entry).is_some() {
                return Err(GcodeError {
                    line,
                    column: 1,
                    message: format!("tool T{number} is listed twice"),
                });
            }
        }
        Ok(Self { tools })
    }

    /// The entry of tool `number`.
    #[must_use]
    pub fn get(&self, number: u32) -> Option<&ToolEntry> {
        self.tools.get(&number)
    }

    /// The tools in number order.
    pub fn tools(&self) -> impl Iterator<Item = &ToolEntry> {
        self.tools.values()
    }
}

fn parse_entry(
    body: &str,
    line: usize,
    unit: LengthUnit,
    comment: &str,
) -> Result<ToolEntry, GcodeError> {
    let err = |column: usize, message: String| GcodeError {
        line,
        column,
        message,
    };
    let mut number = None;
    let mut pocket = None;
    let mut offset = [0.0; 3];
    let mut diameter = 0.0;
    let mut words = Vec::new();
    let mut start: Option<usize> = None;
    for (i, ch) in body.char_indices() {
        if ch.is_whitespace() {
            if let Some(s0) = start.take() {
                words.push((s0, body.get(s0..i).unwrap_or("")));
            }
        } else if start.is_none() {
            start = Some(i);
        }
    }
    if let Some(s0) = start {
        words.push((s0, body.get(s0..).unwrap_or("")));
    }
    for (at, word) in words {
        let col = body.get(..at).map_or(1, |b| b.chars().count() + 1);
        let mut chars = word.chars();
        let letter = chars.next().map(|c| c.to_ascii_uppercase()).unwrap_or(' ');
        let value: f64 = chars
            .as_str()
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite() && v.abs() < 1e9)
            .ok_or_else(|| err(col, format!("'{word}' is not a letter and a number")))?;
        let whole = || {
            (value >= 0.0 && value.fract() == 0.0 && value <= f64::from(u32::MAX))
                .then_some(value as u32)
                .ok_or_else(|| err(col, format!("{letter} must be a non-negative integer")))
        };
        match letter {
            'T' => number = Some(whole()?),
            'P' => pocket = Some(whole()?),
            'X' => offset[0] = value * unit.mm(),
            'Y' => offset[1] = value * unit.mm(),
            'Z' => offset[2] = value * unit.mm(),
            'D' => diameter = value * unit.mm(),
            'A' | 'B' | 'C' | 'U' | 'V' | 'W' => {
                if value != 0.0 {
                    return Err(err(
                        col,
                        format!("tool offset {letter} is not supported (only X, Y, Z lengths)"),
                    ));
                }
            }
            'I' | 'J' | 'Q' => {}
            _ => return Err(err(col, format!("unknown tool table word '{word}'"))),
        }
    }
    let number = number.ok_or_else(|| err(1, "tool line without a T number".into()))?;
    Ok(ToolEntry {
        number,
        pocket: pocket.unwrap_or(number),
        offset_mm: DVec3::from_array(offset),
        diameter_mm: diameter,
        comment: comment.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_linuxcnc_lines_in_either_unit() {
        let text = "T1 P1 D6.0 Z+25.0 ;six mm\n\n; only a comment\nt2 p5 d0.25 z1 x-0.5\n";
        let t = ToolTable::parse(text, LengthUnit::Mm).unwrap();
        let t1 = t.get(1).unwrap();
        assert_eq!(
            (t1.diameter_mm, t1.offset_mm.z, t1.comment.as_str()),
            (6.0, 25.0, "six mm")
        );
        let t = ToolTable::parse(text, LengthUnit::Inch).unwrap();
        let t2 = t.get(2).unwrap();
        assert_eq!((t2.pocket, t2.diameter_mm, t2.offset_mm.z), (5, 6.35, 25.4));
        assert!((t2.offset_mm.x + 12.7).abs() < 1e-12);
        let e = ToolTable::parse("T1 D6\nT1 D3", LengthUnit::Mm).unwrap_err();
        assert_eq!(e.line, 2);
        let e = ToolTable::parse("T3 Dx", LengthUnit::Mm).unwrap_err();
        assert_eq!((e.line, e.column), (1, 4));
        assert!(ToolTable::parse("P1 D3", LengthUnit::Mm).is_err());
    }
}
