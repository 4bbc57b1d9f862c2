//! Tokens of one G-code line for colouring, dialect-agnostic: RS274NGC/Fanuc words (`N10`,
//! `G01`, `X-1.5`, `F1200`), comments in parentheses or after `;`, Siemens keywords and
//! assignments (`TRAORI`, `X=10`, `MSG("...")`), Heidenhain ISO (`M128`, `X+10`, `*`) and
//! plain language (`5 L X+10 FMAX`, `FUNCTION TCPM`).

/// What a token is, for its colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TokenKind {
    /// `N` word, or the bare number opening a Heidenhain plain-language block.
    LineNumber,
    /// `G` word.
    GCode,
    /// `M` word.
    MCode,
    /// Axis word: `X Y Z A B C U V W`.
    Axis,
    /// Feed, spindle speed or tool: `F S T`.
    FeedSpeedTool,
    /// Comment (parentheses, or from `;` to the end of the line) or a quoted string.
    Comment,
    /// A name of two or more letters: `TRAORI`, `CYCLE800`, `FMAX`, `TCPM`.
    Keyword,
    /// Any other letter word: `I J K R H D P Q L O E` with its value.
    Word,
}

/// A token: its kind and byte range in the line. Text between tokens (spaces, operators,
/// block-end marks) is plain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Token {
    /// Kind of the token.
    pub kind: TokenKind,
    /// Byte offset of the first character.
    pub start: usize,
    /// Byte offset after the last character.
    pub end: usize,
}

/// The tokens of one line, in order, not overlapping.
#[must_use]
pub fn tokenize(line: &str) -> Vec<Token> {
    let b = line.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0usize;
    let push = |tokens: &mut Vec<Token>, kind, start, end| {
        if end > start {
            tokens.push(Token { kind, start, end });
        }
    };
    // A Heidenhain plain-language block opens with its number, without `N`.
    let lead = b.iter().take_while(|c| c.is_ascii_whitespace()).count();
    let digits = b
        .iter()
        .skip(lead)
        .take_while(|c| c.is_ascii_digit())
        .count();
    if digits > 0 {
        push(&mut tokens, TokenKind::LineNumber, lead, lead + digits);
        i = lead + digits;
    }
    // A `(` right after a name opens its arguments (Siemens `CYCLE800(...)`, `MSG("...")`),
    // not a comment.
    let mut call_at = None;
    while let Some(&c) = b.get(i) {
        match c {
            b'(' if call_at == Some(i) => i += 1,
            b'(' => {
                let end = b
                    .iter()
                    .skip(i)
                    .position(|&x| x == b')')
                    .map_or(b.len(), |p| i + p + 1);
                push(&mut tokens, TokenKind::Comment, i, end);
                i = end;
            }
            b';' => {
                push(&mut tokens, TokenKind::Comment, i, b.len());
                i = b.len();
            }
            b'"' => {
                let end = b
                    .iter()
                    .skip(i + 1)
                    .position(|&x| x == b'"')
                    .map_or(b.len(), |p| i + 1 + p + 1);
                push(&mut tokens, TokenKind::Comment, i, end);
                i = end;
            }
            c if c.is_ascii_alphabetic() || c == b'_' => {
                let letters = b
                    .iter()
                    .skip(i)
                    .take_while(|x| x.is_ascii_alphabetic() || **x == b'_')
                    .count();
                if letters >= 2 {
                    let end = i + b
                        .iter()
                        .skip(i)
                        .take_while(|x| x.is_ascii_alphanumeric() || **x == b'_')
                        .count();
                    push(&mut tokens, TokenKind::Keyword, i, end);
                    call_at = Some(end);
                    i = end;
                } else {
                    let end = word_end(b, i + 1);
                    push(&mut tokens, letter_kind(c), i, end);
                    i = end;
                }
            }
            _ => {
                // Plain: spaces, operators, `*`, `%`, numbers not after a letter. Skip one
                // whole character (the line may hold UTF-8 in comments only, but be safe).
                i += line
                    .get(i..)
                    .and_then(|s| s.chars().next())
                    .map_or(1, char::len_utf8);
            }
        }
    }
    tokens
}

/// The end of a word's value after its letter: optional `=`, a sign and a number
/// (`X=10`, `X+10`, `G01`, `G43.4`, `F.5`).
fn word_end(b: &[u8], mut i: usize) -> usize {
    if b.get(i) == Some(&b'=') {
        i += 1;
    }
    if matches!(b.get(i), Some(b'+' | b'-')) && b.get(i + 1).is_some_and(|c| is_number_char(*c)) {
        i += 1;
    }
    while b.get(i).is_some_and(|c| is_number_char(*c)) {
        i += 1;
    }
    i
}

fn is_number_char(c: u8) -> bool {
    c.is_ascii_digit() || c == b'.'
}

fn letter_kind(letter: u8) -> TokenKind {
    match letter.to_ascii_uppercase() {
        b'N' => TokenKind::LineNumber,
        b'G' => TokenKind::GCode,
        b'M' => TokenKind::MCode,
        b'X' | b'Y' | b'Z' | b'A' | b'B' | b'C' | b'U' | b'V' | b'W' => TokenKind::Axis,
        b'F' | b'S' | b'T' => TokenKind::FeedSpeedTool,
        _ => TokenKind::Word,
    }
}
