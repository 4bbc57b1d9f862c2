//! Part 21 grammar: the exchange structure, its sections, entity instances and parameters.
//!
//! Aggregates are parsed recursively, but never deeper than [`MAX_DEPTH`], so the stack stays
//! bounded whatever the input. Every error carries the line and, inside the DATA section, the
//! `#id` of the instance being read.

use std::collections::btree_map::Entry;

use super::lexer::{LexError, Lexer, Token, shown};
use super::text;
use super::{Exchange, Header, Instance, Param, Part21Error, Record};
use crate::diagnostics::Diagnostic;

/// Deepest nesting of aggregates and typed parameters accepted.
pub const MAX_DEPTH: usize = 64;

/// Most warnings listed for one file (a file with a problem on every line would otherwise
/// produce a list as long as itself).
pub const MAX_WARNINGS: usize = 200;

/// The parser state: a lexer with one token of look-ahead.
pub struct Parser<'a> {
    lexer: Lexer<'a>,
    peeked: Option<Option<(Token<'a>, usize)>>,
    /// Line of the last token consumed.
    line: usize,
    /// The instance being read.
    current: Option<u64>,
    /// The last token consumed was `;`.
    after_semicolon: bool,
    /// The lexer reported an error (it cannot be resumed).
    lex_failed: bool,
    diagnostics: Vec<Diagnostic>,
}

fn keyword_is(t: &Token<'_>, word: &str) -> bool {
    matches!(t, Token::Keyword(k) if k.eq_ignore_ascii_case(word.as_bytes()))
}

fn upper(bytes: &[u8]) -> String {
    // Keyword bytes are ASCII letters, digits, '_' and '-', so this is always UTF-8.
    let mut v = bytes.to_vec();
    v.make_ascii_uppercase();
    String::from_utf8(v).unwrap_or_default()
}

impl<'a> Parser<'a> {
    /// A parser over `bytes`.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self {
            lexer: Lexer::new(bytes),
            peeked: None,
            line: 1,
            current: None,
            after_semicolon: false,
            lex_failed: false,
            diagnostics: Vec::new(),
        }
    }

    fn error(&self, line: usize, message: impl Into<String>) -> Part21Error {
        Part21Error {
            line,
            id: self.current,
            message: message.into(),
        }
    }

    fn lex_error(&self, e: LexError) -> Part21Error {
        self.error(e.line, e.message)
    }

    fn warn(&mut self, line: usize, message: impl Into<String>) {
        if self.diagnostics.len() > MAX_WARNINGS {
            return;
        }
        if self.diagnostics.len() == MAX_WARNINGS {
            let note = format!("more than {MAX_WARNINGS} warnings; the rest are not listed");
            self.diagnostics
                .push(Diagnostic::warning(format!("line {line}"), note));
            return;
        }
        let place = match self.current {
            Some(id) => format!("line {line}, #{id}"),
            None => format!("line {line}"),
        };
        self.diagnostics.push(Diagnostic::warning(place, message));
    }

    fn peek(&mut self) -> Result<Option<(Token<'a>, usize)>, Part21Error> {
        if let Some(p) = self.peeked {
            return Ok(p);
        }
        let t = self.lexer.next_token().map_err(|e| {
            self.lex_failed = true;
            self.lex_error(e)
        })?;
        self.peeked = Some(t);
        Ok(t)
    }

    /// The next token; the end of input is an error naming `context`.
    fn next(&mut self, context: impl std::fmt::Display) -> Result<(Token<'a>, usize), Part21Error> {
        let t = self.peek()?;
        self.peeked = None;
        match t {
            Some((tok, line)) => {
                self.line = line;
                self.after_semicolon = tok == Token::Semicolon;
                Ok((tok, line))
            }
            None => Err(self.error(self.line, format!("unexpected end of file {context}"))),
        }
    }

    fn expect_semicolon(&mut self, after: impl std::fmt::Display) -> Result<(), Part21Error> {
        let last = self.line;
        match self.peek()? {
            Some((Token::Semicolon, _)) => {
                self.peeked = None;
                self.after_semicolon = true;
                Ok(())
            }
            Some((t, _)) => Err(self.error(
                last,
                format!("missing ';' after {after} (found {})", t.describe()),
            )),
            None => Err(self.error(
                self.line,
                format!("unexpected end of file: missing ';' after {after}"),
            )),
        }
    }

    /// Parses the whole exchange structure.
    pub fn exchange(mut self) -> Result<Exchange, Part21Error> {
        let mut ex = Exchange::default();
        match self.peek()? {
            None => return Err(self.error(1, "empty file (expected 'ISO-10303-21;')")),
            Some((t, line)) if !keyword_is(&t, "ISO-10303-21") => {
                return Err(self.error(
                    line,
                    format!(
                        "not a STEP file: expected 'ISO-10303-21;', found {}",
                        t.describe()
                    ),
                ));
            }
            Some(_) => {}
        }
        self.next("")?;
        self.expect_semicolon("'ISO-10303-21'")?;
        self.header(&mut ex.header)?;
        let mut data_sections = 0;
        loop {
            let Some((t, line)) = self.peek()? else {
                if data_sections == 0 {
                    return Err(self.error(self.line, "no DATA section"));
                }
                self.warn(self.line, "missing 'END-ISO-10303-21;' at end of file");
                break;
            };
            self.next("")?;
            if keyword_is(&t, "DATA") {
                self.data_section(&mut ex)?;
                data_sections += 1;
            } else if keyword_is(&t, "END-ISO-10303-21") {
                if data_sections == 0 {
                    return Err(self.error(line, "no DATA section before 'END-ISO-10303-21'"));
                }
                self.expect_semicolon("'END-ISO-10303-21'")?;
                if let Some((_, rest_line)) = self.peek().unwrap_or(None) {
                    self.warn(rest_line, "content after 'END-ISO-10303-21;' ignored");
                }
                break;
            } else if keyword_is(&t, "ANCHOR")
                || keyword_is(&t, "REFERENCE")
                || keyword_is(&t, "SIGNATURE")
            {
                self.warn(
                    line,
                    format!(
                        "{} section skipped (not supported)",
                        match t {
                            Token::Keyword(k) => shown(k),
                            _ => String::new(),
                        }
                    ),
                );
                self.skip_section(&t)?;
            } else {
                return Err(self.error(
                    line,
                    format!(
                        "expected 'DATA' or 'END-ISO-10303-21', found {}",
                        t.describe()
                    ),
                ));
            }
        }
        ex.diagnostics = self.diagnostics;
        Ok(ex)
    }

    fn skip_section(&mut self, _t: &Token<'a>) -> Result<(), Part21Error> {
        loop {
            let (t, _) = self.next("in a section without ENDSEC")?;
            if keyword_is(&t, "ENDSEC") {
                return self.expect_semicolon("'ENDSEC'");
            }
        }
    }

    fn header(&mut self, header: &mut Header) -> Result<(), Part21Error> {
        let (t, line) = self.next("where 'HEADER;' was expected")?;
        if !keyword_is(&t, "HEADER") {
            return Err(self.error(
                line,
                format!(
                    "missing HEADER section: expected 'HEADER;', found {}",
                    t.describe()
                ),
            ));
        }
        self.expect_semicolon("'HEADER'")?;
        loop {
            let (t, line) = self.next("in HEADER section (missing ENDSEC)")?;
            if keyword_is(&t, "ENDSEC") {
                return self.expect_semicolon("'ENDSEC'");
            }
            if keyword_is(&t, "DATA") {
                return Err(self.error(line, "'DATA' inside the HEADER section (missing ENDSEC)"));
            }
            let name = match t {
                Token::Keyword(k) | Token::UserKeyword(k) => upper(k),
                other => {
                    return Err(self.error(
                        line,
                        format!("expected a header entity, found {}", other.describe()),
                    ));
                }
            };
            let params = match self.header_entity(&name) {
                Ok(params) => params,
                Err(e) if !self.lex_failed => {
                    // Open CASCADE reads files with a malformed header entity (Tsh010.stp has an
                    // unbalanced parenthesis in FILE_DESCRIPTION): skip it with a warning.
                    self.warn(
                        e.line,
                        format!("header entity {name} skipped: {}", e.message),
                    );
                    while !self.after_semicolon {
                        self.next("in HEADER section (missing ENDSEC)")?;
                    }
                    continue;
                }
                Err(e) => return Err(e),
            };
            let strings = |p: Option<&Param>| -> Vec<String> {
                p.and_then(Param::as_list)
                    .map(|l| {
                        l.iter()
                            .filter_map(|s| s.as_str().map(str::to_owned))
                            .collect()
                    })
                    .unwrap_or_default()
            };
            let string =
                |p: Option<&Param>| p.and_then(Param::as_str).unwrap_or_default().to_owned();
            match name.as_str() {
                "FILE_DESCRIPTION" => header.description = strings(params.first()),
                "FILE_NAME" => {
                    header.name = string(params.first());
                    header.originating_system = string(params.get(5));
                }
                "FILE_SCHEMA" => header.schema = strings(params.first()),
                _ => {}
            }
        }
    }

    fn header_entity(&mut self, name: &str) -> Result<Vec<Param>, Part21Error> {
        self.after_semicolon = false;
        let params = self.param_list(name)?;
        self.expect_semicolon(format_args!("header entity {name}"))?;
        Ok(params)
    }

    fn data_section(&mut self, ex: &mut Exchange) -> Result<(), Part21Error> {
        // Edition 3: `DATA('name', ('SCHEMA'));`
        if let Some((Token::Open, _)) = self.peek()? {
            self.param_list("DATA")?;
        }
        self.expect_semicolon("'DATA'")?;
        loop {
            self.current = None;
            let (t, line) = self.next("in DATA section (missing ENDSEC; file truncated?)")?;
            match t {
                Token::InstanceName(id) => {
                    self.current = Some(id);
                    let instance = self.instance(id, line)?;
                    match ex.instances.entry(id) {
                        Entry::Occupied(first) => {
                            return Err(self.error(
                                line,
                                format!(
                                    "duplicate instance #{id} (first defined on line {})",
                                    first.get().line
                                ),
                            ));
                        }
                        Entry::Vacant(slot) => {
                            slot.insert(instance);
                        }
                    }
                }
                t if keyword_is(&t, "ENDSEC") => {
                    return self.expect_semicolon("'ENDSEC'");
                }
                t if keyword_is(&t, "END-ISO-10303-21") => {
                    return Err(self.error(
                        line,
                        "'END-ISO-10303-21' inside the DATA section (missing ENDSEC)",
                    ));
                }
                other => {
                    return Err(self.error(
                        line,
                        format!(
                            "expected an instance '#id = ...;', found {}",
                            other.describe()
                        ),
                    ));
                }
            }
        }
    }

    fn instance(&mut self, id: u64, line: usize) -> Result<Instance, Part21Error> {
        let (t, eq_line) = self.next("after the instance name")?;
        if t != Token::Equals {
            return Err(self.error(
                eq_line,
                format!("expected '=' after #{id}, found {}", t.describe()),
            ));
        }
        let (t, rec_line) = self.next("in an instance")?;
        let (records, complex) = match t {
            Token::Keyword(k) | Token::UserKeyword(k) => {
                let name = upper(k);
                let params = self.param_list(&name)?;
                (vec![Record { name, params }], false)
            }
            Token::Open => {
                let mut records = Vec::new();
                loop {
                    let (t, l) = self.next("in a complex instance")?;
                    match t {
                        Token::Close => break,
                        Token::Keyword(k) | Token::UserKeyword(k) => {
                            let name = upper(k);
                            let params = self.param_list(&name)?;
                            records.push(Record { name, params });
                        }
                        other => {
                            return Err(self.error(
                                l,
                                format!(
                                    "expected an entity name in the complex instance, found {}",
                                    other.describe()
                                ),
                            ));
                        }
                    }
                }
                if records.is_empty() {
                    return Err(self.error(rec_line, "complex instance has no records"));
                }
                (records, true)
            }
            other => {
                return Err(self.error(
                    rec_line,
                    format!("instance has no entity name (found {})", other.describe()),
                ));
            }
        };
        self.expect_semicolon(format_args!("instance #{id}"))?;
        Ok(Instance {
            id,
            line,
            records,
            complex,
        })
    }

    /// `( param, ... )` after an entity name.
    fn param_list(&mut self, name: &str) -> Result<Vec<Param>, Part21Error> {
        let (t, line) = self.next(format_args!("after entity name {name}"))?;
        if t != Token::Open {
            return Err(self.error(
                line,
                format!(
                    "expected '(' after entity name {name}, found {}",
                    t.describe()
                ),
            ));
        }
        self.params_until_close(0)
    }

    /// Parameters after an opening parenthesis, up to and including the closing one.
    fn params_until_close(&mut self, depth: usize) -> Result<Vec<Param>, Part21Error> {
        let mut params = Vec::new();
        if let Some((Token::Close, _)) = self.peek()? {
            self.peeked = None;
            return Ok(params);
        }
        loop {
            params.push(self.param(depth)?);
            let (t, line) = self.next("in a parameter list (unbalanced parentheses?)")?;
            match t {
                Token::Comma => {}
                Token::Close => return Ok(params),
                other => {
                    return Err(self.error(
                        line,
                        format!(
                            "expected ',' or ')' in a parameter list, found {}",
                            other.describe()
                        ),
                    ));
                }
            }
        }
    }

    fn param(&mut self, depth: usize) -> Result<Param, Part21Error> {
        let (t, line) = self.next("in a parameter list (unbalanced parentheses?)")?;
        Ok(match t {
            Token::Dollar => Param::Unset,
            Token::Star => Param::Derived,
            Token::Integer(i) => Param::Integer(i),
            Token::Real(r) => Param::Real(r),
            Token::InstanceName(id) => Param::Ref(id),
            Token::String(raw) => {
                let decoded = text::decode(raw);
                for note in decoded.notes {
                    self.warn(line, note);
                }
                Param::String(decoded.text)
            }
            Token::Binary(b) => Param::Binary(String::from_utf8_lossy(b).into_owned()),
            Token::Enum(e) => Param::Enum(upper(e)),
            Token::Open => {
                if depth + 1 >= MAX_DEPTH {
                    return Err(self.error(
                        line,
                        format!("aggregates nested deeper than {MAX_DEPTH} levels"),
                    ));
                }
                Param::List(self.params_until_close(depth + 1)?)
            }
            Token::Keyword(k) | Token::UserKeyword(k) => self.typed(k, line, depth)?,
            Token::Dot => {
                // `.LENGTH_MEASURE(1.E-7).`: a typed parameter wrapped in dots by a bad writer.
                let (t, l) = self.next("in a parameter list")?;
                let Token::Keyword(k) = t else {
                    return Err(self.error(line, "stray '.' in a parameter list"));
                };
                let p = self.typed(k, l, depth)?;
                let (t, l) = self.next("in a parameter list")?;
                if t != Token::Dot {
                    return Err(self.error(l, "stray '.' before a typed parameter"));
                }
                self.warn(
                    line,
                    "typed parameter wrapped in '.' as if an enumeration; dots ignored",
                );
                p
            }
            other => {
                return Err(self.error(
                    line,
                    format!("expected a parameter, found {}", other.describe()),
                ));
            }
        })
    }

    /// `NAME(value)` after its keyword.
    fn typed(&mut self, k: &[u8], line: usize, depth: usize) -> Result<Param, Part21Error> {
        let name = upper(k);
        if depth + 1 >= MAX_DEPTH {
            return Err(self.error(
                line,
                format!("parameters nested deeper than {MAX_DEPTH} levels"),
            ));
        }
        let (t, l) = self.next(format_args!("after typed parameter {name}"))?;
        if t != Token::Open {
            return Err(self.error(
                l,
                format!(
                    "expected '(' after typed parameter name {name}, found {}",
                    t.describe()
                ),
            ));
        }
        let mut inner = self.params_until_close(depth + 1)?;
        if inner.len() != 1 {
            return Err(self.error(
                l,
                format!(
                    "typed parameter {name} must hold exactly one value, found {}",
                    inner.len()
                ),
            ));
        }
        let value = inner.pop().unwrap_or(Param::Unset);
        Ok(Param::Typed(name, Box::new(value)))
    }
}
