//! ASCII STL:
//!
//! ```text
//! solid NAME
//!   facet normal ni nj nk
//!     outer loop
//!       vertex x y z      (three times)
//!     endloop
//!   endfacet
//! endsolid NAME
//! ```
//!
//! Keywords are matched in any case and white space is free. Several solids in one file are read
//! as one mesh; a missing final `endsolid` is a warning, anything else out of place an error.

use std::path::Path;

use super::{RawFacets, shown};
use crate::diagnostics::Diagnostic;
use crate::geometry::DVec3;
use crate::import::ImportError;

/// Words of the text with their 1-based line numbers.
struct Words<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    words: std::str::SplitWhitespace<'a>,
    /// Line of the word last returned (or of the last line read, at the end).
    line: usize,
}

impl<'a> Words<'a> {
    fn new(text: &'a str) -> Self {
        Self {
            lines: text.lines().enumerate(),
            words: "".split_whitespace(),
            line: 1,
        }
    }

    /// The next word, `None` at the end of the text.
    fn next_word(&mut self) -> Option<&'a str> {
        loop {
            if let Some(w) = self.words.next() {
                return Some(w);
            }
            let (i, l) = self.lines.next()?;
            self.line = i + 1;
            self.words = l.split_whitespace();
        }
    }

    /// The rest of the current line, words joined by single spaces.
    fn rest_of_line(&mut self) -> String {
        self.words.by_ref().collect::<Vec<_>>().join(" ")
    }
}

/// The parser: words in, facets out, errors at a line.
struct Parser<'a> {
    words: Words<'a>,
    file: &'a Path,
}

impl<'a> Parser<'a> {
    fn error(&self, message: impl Into<String>) -> ImportError {
        ImportError::new(
            self.file,
            Some(format!("line {}", self.words.line)),
            message,
        )
    }

    /// The next word, or an error saying what was expected instead of the end of the file.
    fn word(&mut self, expected: &str) -> Result<&'a str, ImportError> {
        self.words
            .next_word()
            .ok_or_else(|| self.error(format!("unexpected end of file, expected {expected}")))
    }

    /// Require the keyword `kw` (any case).
    fn keyword(&mut self, kw: &str) -> Result<(), ImportError> {
        let w = self.word(&format!("\"{kw}\""))?;
        if w.eq_ignore_ascii_case(kw) {
            Ok(())
        } else {
            Err(self.error(format!("expected \"{kw}\", found \"{}\"", shown(w))))
        }
    }

    /// A finite number.
    fn number(&mut self, what: &str) -> Result<f64, ImportError> {
        let w = self.word(what)?;
        match w.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            Ok(_) => Err(self.error(format!("{what} \"{}\" is not finite", shown(w)))),
            Err(_) => Err(self.error(format!("expected {what}, found \"{}\"", shown(w)))),
        }
    }

    /// Three finite numbers.
    fn point(&mut self, what: &str) -> Result<DVec3, ImportError> {
        Ok(DVec3::new(
            self.number(what)?,
            self.number(what)?,
            self.number(what)?,
        ))
    }

    /// One facet, after its `facet` keyword: `[normal n n n] outer loop vertex… endloop endfacet`.
    fn facet(&mut self, raw: &mut RawFacets) -> Result<(), ImportError> {
        let k = raw.corners.len();
        let mut w = self.word("\"normal\" or \"outer\"")?;
        let mut normal = DVec3::ZERO;
        if w.eq_ignore_ascii_case("normal") {
            normal = self.point("a normal component")?;
            w = self.word("\"outer\"")?;
        }
        if !w.eq_ignore_ascii_case("outer") {
            return Err(self.error(format!(
                "facet {k}: expected \"outer\", found \"{}\"",
                shown(w)
            )));
        }
        self.keyword("loop")?;
        let mut corners = [DVec3::ZERO; 3];
        let mut n = 0_usize;
        loop {
            let w = self.word("\"vertex\" or \"endloop\"")?;
            if w.eq_ignore_ascii_case("endloop") {
                break;
            }
            if !w.eq_ignore_ascii_case("vertex") {
                return Err(self.error(format!(
                    "facet {k}: expected \"vertex\" or \"endloop\", found \"{}\"",
                    shown(w)
                )));
            }
            let p = self.point("a vertex coordinate")?;
            let Some(slot) = corners.get_mut(n) else {
                return Err(self.error(format!("facet {k} has more than 3 vertices")));
            };
            *slot = p;
            n += 1;
        }
        if n != 3 {
            return Err(self.error(format!("facet {k} has {n} vertices, an STL facet has 3")));
        }
        self.keyword("endfacet")?;
        raw.corners.push(corners);
        raw.normals.push(normal);
        Ok(())
    }

    /// The whole file.
    fn solids(&mut self) -> Result<RawFacets, ImportError> {
        let mut raw = RawFacets::default();
        self.keyword("solid")?;
        raw.name = self.words.rest_of_line();
        loop {
            let Some(w) = self.words.next_word() else {
                raw.diagnostics.push(Diagnostic::warning(
                    Some(format!("line {}", self.words.line)),
                    "file ends without \"endsolid\"",
                ));
                return Ok(raw);
            };
            if w.eq_ignore_ascii_case("facet") {
                self.facet(&mut raw)?;
            } else if w.eq_ignore_ascii_case("endsolid") {
                self.words.rest_of_line();
                match self.words.next_word() {
                    None => return Ok(raw),
                    Some(s) if s.eq_ignore_ascii_case("solid") => {
                        self.words.rest_of_line();
                    }
                    Some(s) => {
                        return Err(self.error(format!(
                            "expected \"solid\" or the end of the file, found \"{}\"",
                            shown(s)
                        )));
                    }
                }
            } else {
                return Err(self.error(format!(
                    "expected \"facet\" or \"endsolid\", found \"{}\"",
                    shown(w)
                )));
            }
        }
    }
}

/// Parse an ASCII STL (must be UTF-8; a leading byte-order mark is skipped).
pub(super) fn parse(bytes: &[u8], file: &Path) -> Result<RawFacets, ImportError> {
    let (bom, bytes) = match bytes.strip_prefix(b"\xEF\xBB\xBF") {
        Some(rest) => (3, rest),
        None => (0, bytes),
    };
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let at = e.valid_up_to();
        let line = 1 + bytes
            .get(..at)
            .unwrap_or(bytes)
            .iter()
            .filter(|&&c| c == b'\n')
            .count();
        ImportError::new(
            file,
            Some(format!("line {line}")),
            format!("not valid UTF-8 text (byte {})", at + bom),
        )
    })?;
    Parser {
        words: Words::new(text),
        file,
    }
    .solids()
}
