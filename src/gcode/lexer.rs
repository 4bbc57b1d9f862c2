//! Lexer: one line of G-code text into words with their columns.
//!
//! A line is `[/] [N..] word* ` with comments `( ... )` anywhere and `;` to the end of the line.
//! A word is a letter followed by a number (`X-92.501`, `Y95.`, `G91.1`); spaces may separate
//! the letter from the number and the digits of the number (RS274NGC allows that).
//! Parameters (`#`) and expressions (`[`) are not supported and give an error.

use super::GcodeError;

/// Largest magnitude a number may have (1e12 mm is far beyond any machine; the bound keeps
/// every later computation finite).
const MAX_MAGNITUDE: f64 = 1e12;

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

/// Lex one line (`line` is 1-based, for error positions).
///
/// # Errors
/// [`GcodeError`] naming the line and column for an unclosed comment, a letter without a
/// number, a stray character, a parameter `#` or an expression `[`.
pub fn lex_line(text: &str, line: usize) -> Result<LexedLine, GcodeError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = LexedLine::default();
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
    while let Some(&c) = chars.get(i) {
        match c {
            c if c.is_whitespace() => i += 1,
            '(' => {
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
                            return Err(err(
                                start,
                                "comment '(' is not closed on this line".into(),
                            ));
                        }
                    }
                    j += 1;
                }
                out.comments.push(body);
                i = j + 1;
            }
            ';' => {
                out.comments
                    .push(chars.get(i + 1..).unwrap_or(&[]).iter().collect());
                break;
            }
            '#' => {
                return Err(err(
                    i,
                    "parameters ('#') are not supported by this interpreter".into(),
                ));
            }
            '[' => {
                return Err(err(
                    i,
                    "expressions ('[...]') are not supported by this interpreter".into(),
                ));
            }
            c if c.is_ascii_alphabetic()
                && chars.get(i + 1).is_some_and(char::is_ascii_alphabetic) =>
            {
                let column = i + 1;
                let mut name = String::new();
                while let Some(&k) = chars.get(i)
                    && (k.is_ascii_alphanumeric() || k == '_')
                {
                    name.push(k.to_ascii_uppercase());
                    i += 1;
                }
                out.keywords.push((name, column));
            }
            c if c.is_ascii_alphabetic() => {
                let column = i + 1;
                i += 1;
                let (value, next) = number(&chars, i).ok_or_else(|| {
                    err(
                        column - 1,
                        format!(
                            "letter '{}' is not followed by a number",
                            c.to_ascii_uppercase()
                        ),
                    )
                })?;
                i = next;
                out.words.push(Word {
                    letter: c.to_ascii_uppercase(),
                    value,
                    column,
                });
            }
            other => {
                return Err(err(i, format!("unexpected character {other:?}")));
            }
        }
    }
    Ok(out)
}

/// Read a number starting at `i` (blanks allowed inside); returns the value and the index after.
fn number(chars: &[char], mut i: usize) -> Option<(f64, usize)> {
    let mut text = String::new();
    let mut digits = 0usize;
    let mut dot = false;
    let skip_blanks = |i: &mut usize| {
        while chars.get(*i).is_some_and(|c| *c == ' ' || *c == '\t') {
            *i += 1;
        }
    };
    skip_blanks(&mut i);
    if let Some(&s) = chars.get(i)
        && (s == '+' || s == '-')
    {
        text.push(s);
        i += 1;
    }
    loop {
        skip_blanks(&mut i);
        match chars.get(i) {
            Some(&d) if d.is_ascii_digit() => {
                text.push(d);
                digits += 1;
            }
            Some('.') if !dot => {
                text.push('.');
                dot = true;
            }
            _ => break,
        }
        i += 1;
    }
    if digits == 0 || digits > 40 {
        return None;
    }
    let value: f64 = text.parse().ok()?;
    (value.abs() <= MAX_MAGNITUDE).then_some((value, i))
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
}
