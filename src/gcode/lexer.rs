//! Lexer: one line of G-code text into words with their columns.
//!
//! A line is `[/] [N..] item*` with comments `( ... )` anywhere and `;` to the end of the line,
//! or an O-word line (`o100 sub`, `o<name> call [1] [2]`, `o3 if [#1 GT 0]`, see
//! [`super::oword`]). An item is a word, a letter followed by a value (`X-92.501`, `Y95.`,
//! `G91.1`, `X#1`, `Z[#<depth> - 1]`, `XSIN[30]`), or a parameter assignment (`#1 = 5`,
//! `#<depth> = [#1 * 2]`); the values are RS274NGC expressions ([`super::expr`]). Spaces may
//! separate the letter from the number and the digits of the number (RS274NGC allows that).
//! Two or more letters in a row that do not start a function are a keyword (Sinumerik's
//! `TRAORI`); the interpreter decides which it knows.
//!
//! [`lex_line`] reads plain ISO words only: there, parameters (`#`) and expressions (`[`) are
//! refused, as before the interpreter read them.

use super::GcodeError;
use super::expr::{
    Expr, MAX_MAGNITUDE, NoParams, ParamName, ParamSource, Reader, eval, param_index,
};
use super::oword::{OLine, parse_oline};

/// One word of a block: a letter and its number, with the 1-based column of the letter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Word {
    /// The letter, upper case.
    pub letter: char,
    /// The number as written.
    pub value: f64,
    /// 1-based column (in characters) of the letter.
    pub column: usize,
}

/// A lexed line.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LexedLine {
    /// `/` block delete at the start of the line.
    pub block_delete: bool,
    /// A `%` tape marker line (the rest of the line is kept as a comment).
    pub percent: bool,
    /// The words in order.
    pub words: Vec<Word>,
    /// Comment texts (without delimiters).
    pub comments: Vec<String>,
    /// Keywords (two or more letters, e.g. Sinumerik's `TRAORI`), upper case, with the
    /// 1-based column of their first letter. The interpreter decides which it knows.
    pub keywords: Vec<(String, usize)>,
}

/// One item of a parsed line.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Item {
    /// A letter and its value.
    Word {
        letter: char,
        value: Expr,
        column: usize,
    },
    /// `#target = value`.
    Assign {
        target: ParamName,
        value: Expr,
        column: usize,
    },
}

/// A line parsed but not evaluated: its values are expressions, read when the line runs.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct ParsedLine {
    pub(super) block_delete: bool,
    pub(super) percent: bool,
    pub(super) items: Vec<Item>,
    pub(super) comments: Vec<String>,
    pub(super) keywords: Vec<(String, usize)>,
    /// An O-word line (`o100 sub`, `o100 if [..]`, ...).
    pub(super) oword: Option<OLine>,
}

/// A parameter to set after the line is read, with the column of its `#`.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Target {
    Numbered(usize),
    Named(String),
}

/// The evaluated words and assignments of a line.
pub(super) struct Evaluated {
    pub(super) words: Vec<Word>,
    pub(super) assignments: Vec<(Target, f64, usize)>,
}

impl ParsedLine {
    /// Move every column right by `offset` (a piece of a line split at block ends).
    pub(super) fn shift(&mut self, offset: usize) {
        for item in &mut self.items {
            match item {
                Item::Word { column, .. } | Item::Assign { column, .. } => *column += offset,
            }
        }
        for (_, c) in &mut self.keywords {
            *c += offset;
        }
        if let Some(o) = &mut self.oword {
            o.column += offset;
        }
    }

    /// Nothing to execute: no words, assignments, keywords or O-word.
    pub(super) fn is_empty(&self) -> bool {
        self.items.is_empty() && self.keywords.is_empty() && self.oword.is_none()
    }

    /// Read the values with the parameters as they are before the line: every value on a
    /// line sees the parameters the lines before it left (RS274NGC sets a line's parameters
    /// after the whole line is read).
    ///
    /// # Errors
    /// A [`GcodeError`] at the column of the word whose value cannot be computed.
    pub(super) fn evaluate(
        &self,
        line: usize,
        params: &dyn ParamSource,
    ) -> Result<Evaluated, GcodeError> {
        let err = |column: usize, message: String| GcodeError {
            line,
            column,
            message,
        };
        let mut out = Evaluated {
            words: Vec::with_capacity(self.items.len()),
            assignments: Vec::new(),
        };
        for item in &self.items {
            match item {
                Item::Word {
                    letter,
                    value,
                    column,
                } => {
                    let v =
                        eval(value, params).map_err(|m| err(*column, format!("{letter}: {m}")))?;
                    if v.abs() > MAX_MAGNITUDE {
                        return Err(err(*column, format!("{letter} value {v} is too large")));
                    }
                    out.words.push(Word {
                        letter: *letter,
                        value: v,
                        column: *column,
                    });
                }
                Item::Assign {
                    target,
                    value,
                    column,
                } => {
                    let t = match target {
                        ParamName::Named(n) => Target::Named(n.clone()),
                        ParamName::Numbered(i) => Target::Numbered(
                            eval(i, params)
                                .and_then(param_index)
                                .map_err(|m| err(*column, m))?,
                        ),
                    };
                    let v = eval(value, params).map_err(|m| err(*column, m))?;
                    out.assignments.push((t, v, *column));
                }
            }
        }
        Ok(out)
    }
}

/// Lex one line of plain ISO words (`line` is 1-based, for error positions).
///
/// # Errors
/// [`GcodeError`] naming the line and column for an unclosed comment, a letter without a
/// number, a stray character, a parameter `#` or an expression `[`.
pub fn lex_line(text: &str, line: usize) -> Result<LexedLine, GcodeError> {
    let parsed = parse_line(text, line, true)?;
    let words = parsed.evaluate(line, &NoParams)?.words;
    Ok(LexedLine {
        block_delete: parsed.block_delete,
        percent: parsed.percent,
        words,
        comments: parsed.comments,
        keywords: parsed.keywords,
    })
}

/// Parse one line. `plain`: refuse parameters, expressions and O-word lines (see
/// [`lex_line`]).
///
/// # Errors
/// [`GcodeError`] naming the line and column for an unclosed comment, a letter without a
/// value, a malformed expression, a stray character.
pub(super) fn parse_line(text: &str, line: usize, plain: bool) -> Result<ParsedLine, GcodeError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = ParsedLine::default();
    let mut i = 0;
    let err = |i: usize, message: String| GcodeError {
        line,
        column: i + 1,
        message,
    };
    // Leading blanks, then block delete or a tape marker.
    while chars.get(i).is_some_and(|c| c.is_whitespace()) {
        i += 1;
    }
    match chars.get(i) {
        Some('/') => {
            out.block_delete = true;
            i += 1;
        }
        Some('%') => {
            // Tape marker; some dialects put a program number or name after it (`%123`).
            out.percent = true;
            out.comments
                .push(chars.get(i + 1..).unwrap_or(&[]).iter().collect());
            return Ok(out);
        }
        _ => {}
    }
    if !plain && let Some((oline, n_word, rest)) = parse_oline(&chars, i, line)? {
        if let Some((value, column)) = n_word {
            out.items.push(Item::Word {
                letter: 'N',
                value: Expr::Number(value),
                column,
            });
        }
        out.oword = Some(oline);
        i = rest;
        // After an O-word only comments may follow.
        while let Some(&c) = chars.get(i) {
            match c {
                c if c.is_whitespace() => i += 1,
                '(' => i = comment(&chars, i, &mut out, &err)?,
                ';' => {
                    out.comments
                        .push(chars.get(i + 1..).unwrap_or(&[]).iter().collect());
                    break;
                }
                other => {
                    return Err(err(
                        i,
                        format!("unexpected {other:?} after the O-word (only comments may follow)"),
                    ));
                }
            }
        }
        return Ok(out);
    }
    while let Some(&c) = chars.get(i) {
        match c {
            c if c.is_whitespace() => i += 1,
            '(' => i = comment(&chars, i, &mut out, &err)?,
            ';' => {
                out.comments
                    .push(chars.get(i + 1..).unwrap_or(&[]).iter().collect());
                break;
            }
            '#' if plain => {
                return Err(err(
                    i,
                    "parameters ('#') are not supported by this interpreter".into(),
                ));
            }
            '[' if plain => {
                return Err(err(
                    i,
                    "expressions ('[...]') are not supported by this interpreter".into(),
                ));
            }
            '#' => {
                let column = i + 1;
                let mut r = Reader::new(&chars, i + 1);
                let target = r.param_name().map_err(|(at, m)| err(at, m))?;
                if r.peek() != Some('=') {
                    return Err(err(
                        r.at,
                        "a parameter at the start of an item must be set: #n = value".into(),
                    ));
                }
                r.at += 1;
                while chars.get(r.at).is_some_and(|c| c.is_whitespace()) {
                    r.at += 1;
                }
                let value = r.value().map_err(|(at, m)| err(at, m))?;
                i = r.at;
                out.items.push(Item::Assign {
                    target,
                    value,
                    column,
                });
            }
            c if c.is_ascii_alphabetic() => {
                i = letter(&chars, i, plain, &mut out, &err)?;
            }
            other => {
                return Err(err(i, format!("unexpected character {other:?}")));
            }
        }
    }
    Ok(out)
}

/// A comment `( ... )` starting at `i`; returns the index after it.
fn comment(
    chars: &[char],
    i: usize,
    out: &mut ParsedLine,
    err: &impl Fn(usize, String) -> GcodeError,
) -> Result<usize, GcodeError> {
    let start = i;
    let mut j = i + 1;
    let mut body = String::new();
    loop {
        match chars.get(j) {
            Some(')') => break,
            Some('(') => {
                return Err(err(j, "nested comment '(' inside a comment".into()));
            }
            Some(&ch) => body.push(ch),
            None => {
                return Err(err(start, "comment '(' is not closed on this line".into()));
            }
        }
        j += 1;
    }
    out.comments.push(body);
    Ok(j + 1)
}

/// A word or a keyword starting with the letter at `i`; returns the index after it.
fn letter(
    chars: &[char],
    i: usize,
    plain: bool,
    out: &mut ParsedLine,
    err: &impl Fn(usize, String) -> GcodeError,
) -> Result<usize, GcodeError> {
    let c = chars.get(i).copied().unwrap_or(' ');
    let column = i + 1;
    let mut r = Reader::new(chars, i + 1);
    let next = r.peek();
    let function = !plain && r.function_ahead().is_some();
    let adjacent_letter = chars.get(i + 1).is_some_and(char::is_ascii_alphabetic);
    if adjacent_letter && !function {
        let mut name = String::new();
        let mut j = i;
        while let Some(&k) = chars.get(j)
            && (k.is_ascii_alphanumeric() || k == '_')
        {
            name.push(k.to_ascii_uppercase());
            j += 1;
        }
        // A Sinumerik call's arguments, `CYCLE81(10, 0, 2, -7)` or `MSG("text")`, written right
        // after the name: kept with it (the interpreter reads them), not taken for a comment.
        if chars.get(j) == Some(&'(') {
            let open = j;
            let mut quoted = false;
            loop {
                match chars.get(j) {
                    Some('"') => quoted = !quoted,
                    Some(')') if !quoted => break,
                    Some(&k) if j > open && k == '(' && !quoted => {
                        return Err(err(j, format!("nested '(' in the arguments of {name}")));
                    }
                    Some(_) => {}
                    None => {
                        return Err(err(
                            open,
                            format!("the arguments of {name} are not closed ')' on this line"),
                        ));
                    }
                }
                j += 1;
            }
            name.extend(chars.get(open..=j).unwrap_or_default());
            j += 1;
        }
        out.keywords.push((name, column));
        return Ok(j);
    }
    let no_value = || {
        err(
            column - 1,
            format!(
                "letter '{}' is not followed by a number",
                c.to_ascii_uppercase()
            ),
        )
    };
    match next {
        Some('#') if plain => {
            return Err(err(
                r.at,
                "parameters ('#') are not supported by this interpreter".into(),
            ));
        }
        Some('[') if plain => {
            return Err(err(
                r.at,
                "expressions ('[...]') are not supported by this interpreter".into(),
            ));
        }
        _ => {}
    }
    let start = r.at;
    let parsed = if plain {
        r.number().map(Expr::Number)
    } else {
        r.value()
    };
    let value = parsed.map_err(|(at, m)| if at <= start { no_value() } else { err(at, m) })?;
    out.items.push(Item::Word {
        letter: c.to_ascii_uppercase(),
        value,
        column,
    });
    Ok(r.at)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_without_spaces_and_comments() {
        let l = lex_line("N310 G2X-92.501Y95.R12.499 (corner) ; tail", 3).unwrap();
        let letters: String = l.words.iter().map(|w| w.letter).collect();
        assert_eq!(letters, "NGXYR");
        assert_eq!(l.words[2].value, -92.501);
        assert_eq!(l.words[3].value, 95.0);
        assert_eq!(l.words[2].column, 8);
        assert_eq!(l.comments, vec!["corner".to_string(), " tail".to_string()]);
    }

    #[test]
    fn keywords_are_collected_with_columns() {
        let l = lex_line("N170 TRAFOOF", 1).unwrap();
        assert_eq!(l.keywords, vec![("TRAFOOF".to_string(), 6)]);
        assert_eq!(l.words.len(), 1);
    }

    #[test]
    fn errors_carry_columns() {
        let e = lex_line("G1 X", 7).unwrap_err();
        assert_eq!((e.line, e.column), (7, 4));
        let e = lex_line("G1 (open", 2).unwrap_err();
        assert_eq!(e.column, 4);
        let e = lex_line("#1=3", 1).unwrap_err();
        assert_eq!(e.column, 1);
    }

    #[test]
    fn expressions_parameters_and_functions() {
        let p = parse_line("#1=2 G1 X[#1*2] Ysin[30] Z-#1 #<d> = -1.5", 4, false).unwrap();
        let e = p.evaluate(4, &NoParams).unwrap();
        let values: Vec<(char, f64)> = e.words.iter().map(|w| (w.letter, w.value)).collect();
        assert_eq!(values[0], ('G', 1.0));
        assert_eq!(values[1], ('X', 0.0)); // #1 is still 0 while the line is read
        assert!((values[2].1 - 0.5).abs() < 1e-12);
        assert_eq!(values[3], ('Z', -0.0));
        assert_eq!(e.assignments.len(), 2);
        assert_eq!(e.assignments[0].0, Target::Numbered(1));
        assert_eq!(e.assignments[1], (Target::Named("d".into()), -1.5, 31));
        let e = parse_line("G1 X[1 + ]", 2, false).unwrap_err();
        assert_eq!((e.line, e.column), (2, 10));
    }
}
