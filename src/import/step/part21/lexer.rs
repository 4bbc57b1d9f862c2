//! Part 21 tokens: splits the byte stream into keywords, instance names, literals and
//! punctuation, skipping whitespace and `/* */` comments, and counting lines.
//!
//! Tokens borrow from the input; nothing is allocated per token. Numbers are converted here so
//! that an out-of-range literal is reported at its own line.

/// Longest string literal accepted, in bytes between the quotes (as written, before decoding).
///
/// ISO 10303-21 edition 3 bounds a string at 32 767 characters; Open CASCADE refuses a file
/// holding a 32 768-byte literal (`Ad001.stp` of the adversarial corpus), and so do we.
pub const MAX_STRING_BYTES: usize = 32_767;

/// One token.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Token<'a> {
    /// A standard keyword (`CARTESIAN_POINT`, `HEADER`, `END-ISO-10303-21`), as written.
    Keyword(&'a [u8]),
    /// A user-defined keyword `!NAME` (without the `!`).
    UserKeyword(&'a [u8]),
    /// An entity instance name `#123`.
    InstanceName(u64),
    /// An integer literal.
    Integer(i64),
    /// A real literal (finite).
    Real(f64),
    /// A string literal: the raw bytes between the quotes, `''` and `\` directives not decoded.
    String(&'a [u8]),
    /// A binary literal: the characters between the double quotes.
    Binary(&'a [u8]),
    /// An enumeration `.NAME.` (the name without dots).
    Enum(&'a [u8]),
    /// A lone `.` that does not start an enumeration or a number.
    Dot,
    /// `(`
    Open,
    /// `)`
    Close,
    /// `,`
    Comma,
    /// `;`
    Semicolon,
    /// `=`
    Equals,
    /// `$`
    Dollar,
    /// `*`
    Star,
}

impl Token<'_> {
    /// A short description of the token for error messages.
    pub fn describe(&self) -> String {
        match self {
            Token::Keyword(k) => format!("keyword '{}'", shown(k)),
            Token::UserKeyword(k) => format!("user keyword '!{}'", shown(k)),
            Token::InstanceName(n) => format!("instance name '#{n}'"),
            Token::Integer(i) => format!("integer {i}"),
            Token::Real(r) => format!("real {r}"),
            Token::String(_) => "a string".to_owned(),
            Token::Binary(_) => "a binary literal".to_owned(),
            Token::Enum(e) => format!("enumeration '.{}.'", shown(e)),
            Token::Dot => "'.'".to_owned(),
            Token::Open => "'('".to_owned(),
            Token::Close => "')'".to_owned(),
            Token::Comma => "','".to_owned(),
            Token::Semicolon => "';'".to_owned(),
            Token::Equals => "'='".to_owned(),
            Token::Dollar => "'$'".to_owned(),
            Token::Star => "'*'".to_owned(),
        }
    }
}

/// Bytes shown in a message: ASCII as is, at most 40 of them.
pub fn shown(bytes: &[u8]) -> String {
    let cut = bytes.get(..40).unwrap_or(bytes);
    let mut s: String = cut
        .iter()
        .map(|&b| if b.is_ascii_graphic() { b as char } else { '?' })
        .collect();
    if cut.len() < bytes.len() {
        s.push_str("...");
    }
    s
}

/// A lexical error: line and message (the parser adds the instance id).
#[derive(Clone, Debug, PartialEq)]
pub struct LexError {
    /// 1-based line.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// The tokenizer.
pub struct Lexer<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
}

fn is_keyword_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_'
}

fn is_keyword_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b == b'-'
}

impl<'a> Lexer<'a> {
    /// A lexer at the start of `bytes` (a UTF-8 byte-order mark is skipped).
    pub fn new(bytes: &'a [u8]) -> Self {
        let pos = if bytes.starts_with(&[0xEF, 0xBB, 0xBF]) {
            3
        } else {
            0
        };
        Self {
            bytes,
            pos,
            line: 1,
        }
    }

    fn peek_byte(&self, ahead: usize) -> Option<u8> {
        self.bytes.get(self.pos + ahead).copied()
    }

    fn err(&self, line: usize, message: impl Into<String>) -> LexError {
        LexError {
            line,
            message: message.into(),
        }
    }

    /// Counts a line break at `pos` (`\n`, or `\r` not followed by `\n`).
    fn count_newline(&mut self, b: u8, next: Option<u8>) {
        if b == b'\n' || (b == b'\r' && next != Some(b'\n')) {
            self.line += 1;
        }
    }

    /// Skips whitespace and comments.
    fn skip_blank(&mut self) -> Result<(), LexError> {
        while let Some(b) = self.peek_byte(0) {
            match b {
                b' ' | b'\t' | b'\n' | b'\r' | 0x0B | 0x0C => {
                    self.count_newline(b, self.peek_byte(1));
                    self.pos += 1;
                }
                b'/' if self.peek_byte(1) == Some(b'*') => {
                    let start_line = self.line;
                    self.pos += 2;
                    loop {
                        match self.peek_byte(0) {
                            None => return Err(self.err(start_line, "unterminated comment '/*'")),
                            Some(b'*') if self.peek_byte(1) == Some(b'/') => {
                                self.pos += 2;
                                break;
                            }
                            Some(c) => {
                                self.count_newline(c, self.peek_byte(1));
                                self.pos += 1;
                            }
                        }
                    }
                }
                _ => break,
            }
        }
        Ok(())
    }

    /// The next token with its 1-based line, or `None` at the end of the input.
    pub fn next_token(&mut self) -> Result<Option<(Token<'a>, usize)>, LexError> {
        self.skip_blank()?;
        let line = self.line;
        let Some(b) = self.peek_byte(0) else {
            return Ok(None);
        };
        let token = match b {
            b'(' => self.single(Token::Open),
            b')' => self.single(Token::Close),
            b',' => self.single(Token::Comma),
            b';' => self.single(Token::Semicolon),
            b'=' => self.single(Token::Equals),
            b'$' => self.single(Token::Dollar),
            b'*' => self.single(Token::Star),
            b'\'' => self.string(line)?,
            b'"' => self.binary(line)?,
            b'#' => self.instance_name(line)?,
            b'!' => {
                self.pos += 1;
                match self.peek_byte(0) {
                    Some(c) if is_keyword_start(c) => Token::UserKeyword(self.keyword_bytes()),
                    _ => {
                        return Err(
                            self.err(line, "'!' not followed by a user-defined keyword name")
                        );
                    }
                }
            }
            b'.' => match self.peek_byte(1) {
                Some(c) if c.is_ascii_digit() => self.number(line)?,
                Some(c) if is_keyword_start(c) => self.enumeration(line)?,
                _ => self.single(Token::Dot),
            },
            b'+' | b'-' | b'0'..=b'9' => self.number(line)?,
            c if is_keyword_start(c) => Token::Keyword(self.keyword_bytes()),
            c => {
                let what = if c.is_ascii_graphic() {
                    format!("unexpected character '{}'", c as char)
                } else {
                    format!("unexpected byte 0x{c:02X} (not Part 21 text)")
                };
                return Err(self.err(line, what));
            }
        };
        Ok(Some((token, line)))
    }

    fn single(&mut self, t: Token<'a>) -> Token<'a> {
        self.pos += 1;
        t
    }

    fn keyword_bytes(&mut self) -> &'a [u8] {
        let start = self.pos;
        while self.peek_byte(0).is_some_and(is_keyword_byte) {
            self.pos += 1;
        }
        self.bytes.get(start..self.pos).unwrap_or_default()
    }

    /// `.NAME.`; or a lone `.` when the name is followed by `(` (`.LENGTH_MEASURE(1.E-7).`,
    /// a typed parameter wrapped in dots, which the parser tolerates).
    fn enumeration(&mut self, line: usize) -> Result<Token<'a>, LexError> {
        let start = self.pos + 1;
        let mut end = start;
        while self
            .bytes
            .get(end)
            .is_some_and(|&c| c.is_ascii_alphanumeric() || c == b'_')
        {
            end += 1;
        }
        let name = self.bytes.get(start..end).unwrap_or_default();
        match self.bytes.get(end) {
            Some(b'.') => {
                self.pos = end + 1;
                Ok(Token::Enum(name))
            }
            Some(b'(') => {
                self.pos += 1;
                Ok(Token::Dot)
            }
            _ => Err(self.err(
                line,
                format!("enumeration '.{}' has no closing '.'", shown(name)),
            )),
        }
    }

    fn instance_name(&mut self, line: usize) -> Result<Token<'a>, LexError> {
        self.pos += 1;
        let start = self.pos;
        while self.peek_byte(0).is_some_and(|c| c.is_ascii_digit()) {
            self.pos += 1;
        }
        let digits = self.bytes.get(start..self.pos).unwrap_or_default();
        if digits.is_empty() {
            let rest = self.bytes.get(start..).unwrap_or_default();
            let word: Vec<u8> = rest
                .iter()
                .copied()
                .take_while(|&c| is_keyword_byte(c))
                .take(40)
                .collect();
            return Err(match rest.first() {
                Some(b'-') => self.err(line, format!("negative instance name '#{}'", shown(&word))),
                _ => self.err(
                    line,
                    format!("bad instance name '#{}' (expected digits)", shown(&word)),
                ),
            });
        }
        if self.peek_byte(0).is_some_and(is_keyword_start) {
            let mut end = self.pos;
            while self.bytes.get(end).is_some_and(|&c| is_keyword_byte(c)) {
                end += 1;
            }
            let word = self.bytes.get(start..end).unwrap_or_default();
            return Err(self.err(line, format!("bad instance name '#{}'", shown(word))));
        }
        let value = parse_u64(digits).ok_or_else(|| {
            self.err(
                line,
                format!("instance name '#{}' out of range", shown(digits)),
            )
        })?;
        Ok(Token::InstanceName(value))
    }

    fn number(&mut self, line: usize) -> Result<Token<'a>, LexError> {
        let start = self.pos;
        if matches!(self.peek_byte(0), Some(b'+' | b'-')) {
            self.pos += 1;
        }
        let int_start = self.pos;
        self.skip_digits();
        let int_digits = self.pos - int_start;
        let mut real = false;
        let mut frac_digits = 0;
        if self.peek_byte(0) == Some(b'.') {
            real = true;
            self.pos += 1;
            let f = self.pos;
            self.skip_digits();
            frac_digits = self.pos - f;
        }
        if int_digits + frac_digits == 0 {
            return Err(self.malformed_number(start, line));
        }
        if matches!(self.peek_byte(0), Some(b'E' | b'e')) {
            real = true;
            self.pos += 1;
            if matches!(self.peek_byte(0), Some(b'+' | b'-')) {
                self.pos += 1;
            }
            let e = self.pos;
            self.skip_digits();
            if self.pos == e {
                return Err(self.err(line, "malformed number: exponent has no digits"));
            }
        }
        let text = self.bytes.get(start..self.pos).unwrap_or_default();
        if self
            .peek_byte(0)
            .is_some_and(|c| is_keyword_byte(c) || c == b'.' || c == b'#')
        {
            return Err(self.malformed_number(start, line));
        }
        // The text is ASCII digits, signs, '.', 'E': always valid UTF-8.
        let s = std::str::from_utf8(text).unwrap_or_default();
        if real {
            match s.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(Token::Real(v)),
                _ => Err(self.err(line, format!("real '{}' out of range", shown(text)))),
            }
        } else {
            s.parse::<i64>()
                .map(Token::Integer)
                .map_err(|_| self.err(line, format!("integer '{}' out of range", shown(text))))
        }
    }

    /// The error for a number starting at `start`, showing the whole word it is part of.
    fn malformed_number(&self, start: usize, line: usize) -> LexError {
        let mut end = start + 1;
        while self
            .bytes
            .get(end)
            .is_some_and(|&c| is_keyword_byte(c) || c == b'.' || c == b'+')
        {
            end += 1;
        }
        let whole = self.bytes.get(start..end).unwrap_or_default();
        self.err(line, format!("malformed number '{}'", shown(whole)))
    }

    fn skip_digits(&mut self) {
        while self.peek_byte(0).is_some_and(|c| c.is_ascii_digit()) {
            self.pos += 1;
        }
    }

    fn string(&mut self, line: usize) -> Result<Token<'a>, LexError> {
        self.pos += 1;
        let start = self.pos;
        loop {
            let Some(rel) = self.bytes.get(self.pos..).and_then(|r| {
                r.iter()
                    .position(|&c| c == b'\'' || c == b'\n' || c == b'\r')
            }) else {
                return Err(self.err(line, "unterminated string"));
            };
            self.pos += rel;
            if self.pos - start > MAX_STRING_BYTES {
                return Err(self.err(
                    line,
                    format!("string literal longer than {MAX_STRING_BYTES} bytes"),
                ));
            }
            match self.peek_byte(0) {
                Some(b'\'') if self.peek_byte(1) == Some(b'\'') => self.pos += 2,
                Some(b'\'') => break,
                Some(c) => {
                    self.count_newline(c, self.peek_byte(1));
                    self.pos += 1;
                }
                None => return Err(self.err(line, "unterminated string")),
            }
        }
        let content = self.bytes.get(start..self.pos).unwrap_or_default();
        if content.len() > MAX_STRING_BYTES {
            return Err(self.err(
                line,
                format!("string literal longer than {MAX_STRING_BYTES} bytes"),
            ));
        }
        self.pos += 1;
        Ok(Token::String(content))
    }

    fn binary(&mut self, line: usize) -> Result<Token<'a>, LexError> {
        self.pos += 1;
        let start = self.pos;
        while self.peek_byte(0).is_some_and(|c| c.is_ascii_hexdigit()) {
            self.pos += 1;
        }
        match self.peek_byte(0) {
            Some(b'"') => {}
            None => return Err(self.err(line, "unterminated binary literal")),
            Some(_) => {
                return Err(self.err(
                    self.line,
                    "binary literal holds a character that is not a hex digit",
                ));
            }
        }
        let content = self.bytes.get(start..self.pos).unwrap_or_default();
        self.pos += 1;
        if !content.first().is_some_and(|c| matches!(c, b'0'..=b'3')) {
            return Err(self.err(
                line,
                "binary literal must start with a digit 0-3 (count of unused bits)",
            ));
        }
        Ok(Token::Binary(content))
    }
}

fn parse_u64(digits: &[u8]) -> Option<u64> {
    digits.iter().try_fold(0_u64, |acc, &d| {
        acc.checked_mul(10)?.checked_add(u64::from(d - b'0'))
    })
}
