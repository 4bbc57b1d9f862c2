//! Part 21 string literals: `''` escapes and the control directives `\\`, `\X\hh`,
//! `\X2\...\X0\`, `\X4\...\X0\`, `\S\c` and `\P?\`, decoded to Rust text.
//!
//! Tolerance: a backslash that does not start a valid directive is kept as written (writers put
//! Windows paths in strings); raw bytes that are not UTF-8 are decoded lossily. Both give a note.
//! Line breaks inside a literal are not part of the value (ISO 10303-21 §6.4.3.5) and are dropped.

/// A decoded string and what was tolerated on the way.
#[derive(Debug, Default, PartialEq)]
pub struct Decoded {
    /// The value.
    pub text: String,
    /// Problems tolerated (one sentence each), empty for a clean literal.
    pub notes: Vec<String>,
}

/// Decodes the raw bytes between the quotes of a string literal.
pub fn decode(raw: &[u8]) -> Decoded {
    // Fast path: nothing to decode.
    if !raw
        .iter()
        .any(|&b| matches!(b, b'\'' | b'\\' | b'\n' | b'\r'))
    {
        return match std::str::from_utf8(raw) {
            Ok(s) => Decoded {
                text: s.to_owned(),
                notes: Vec::new(),
            },
            Err(_) => Decoded {
                text: String::from_utf8_lossy(raw).into_owned(),
                notes: vec!["string holds bytes that are not UTF-8; decoded lossily".to_owned()],
            },
        };
    }
    let mut out = Decoded::default();
    // Unicode text decoded so far, and a run of raw bytes still to be UTF-8 checked.
    let mut pending: Vec<u8> = Vec::new();
    let mut i = 0;
    while let Some(&b) = raw.get(i) {
        match b {
            b'\'' => {
                // `''` inside a literal stands for one quote; the lexer guarantees the pair.
                pending.push(b'\'');
                i += if raw.get(i + 1) == Some(&b'\'') { 2 } else { 1 };
            }
            b'\n' | b'\r' => i += 1,
            b'\\' => match directive(raw, i) {
                Some((chars, len)) => {
                    flush(&mut pending, &mut out);
                    out.text.extend(chars);
                    i += len;
                }
                None => {
                    if !out.notes.iter().any(|n| n.starts_with("backslash")) {
                        out.notes.push(
                            "backslash not starting a valid control directive kept as written"
                                .to_owned(),
                        );
                    }
                    pending.push(b'\\');
                    i += 1;
                }
            },
            _ => {
                pending.push(b);
                i += 1;
            }
        }
    }
    flush(&mut pending, &mut out);
    out
}

fn flush(pending: &mut Vec<u8>, out: &mut Decoded) {
    if pending.is_empty() {
        return;
    }
    match std::str::from_utf8(pending) {
        Ok(s) => out.text.push_str(s),
        Err(_) => {
            out.text.push_str(&String::from_utf8_lossy(pending));
            if !out.notes.iter().any(|n| n.contains("UTF-8")) {
                out.notes
                    .push("string holds bytes that are not UTF-8; decoded lossily".to_owned());
            }
        }
    }
    pending.clear();
}

fn hex_value(bytes: &[u8]) -> Option<u32> {
    bytes.iter().try_fold(0_u32, |acc, &b| {
        Some(acc * 16 + char::from(b).to_digit(16)?)
    })
}

/// The directive starting at `raw[i] == '\\'`: the characters it stands for and its length.
fn directive(raw: &[u8], i: usize) -> Option<(Vec<char>, usize)> {
    let rest = raw.get(i..)?;
    if rest.starts_with(b"\\\\") {
        return Some((vec!['\\'], 2));
    }
    if rest.starts_with(b"\\S\\") {
        // \S\c: the character c + 128 of the current code page (taken as ISO 8859-1).
        let c = *rest.get(3)?;
        if !(0x20..0x7F).contains(&c) {
            return None;
        }
        return Some((vec![char::from(c + 128)], 4));
    }
    if rest.starts_with(b"\\P") && rest.get(3) == Some(&b'\\') {
        // \P?\ selects an ISO 8859 part for later \S\ directives; we decode all as part 1.
        return rest
            .get(2)
            .filter(|c| c.is_ascii_uppercase())
            .map(|_| (Vec::new(), 4));
    }
    if rest.starts_with(b"\\X\\") {
        let v = hex_value(rest.get(3..5)?)?;
        return Some((vec![char::from_u32(v)?], 5));
    }
    let (width, header) = if rest.starts_with(b"\\X2\\") {
        (4, 4)
    } else if rest.starts_with(b"\\X4\\") {
        (8, 4)
    } else {
        return None;
    };
    let body = rest.get(header..)?;
    // The hex digits, then the terminator right after them (scanning only the digits keeps the
    // whole decoding linear, however many unterminated directives a string holds).
    let end = body
        .iter()
        .position(|b| !b.is_ascii_hexdigit())
        .unwrap_or(body.len());
    if !body.get(end..).is_some_and(|t| t.starts_with(b"\\X0\\")) {
        return None;
    }
    let hex = body.get(..end)?;
    if hex.is_empty() || hex.len() % width != 0 {
        return None;
    }
    let units: Option<Vec<u32>> = hex.chunks(width).map(hex_value).collect();
    let units = units?;
    let chars = if width == 4 {
        let u16s: Vec<u16> = units.iter().map(|&u| u as u16).collect();
        char::decode_utf16(u16s)
            .collect::<Result<Vec<char>, _>>()
            .ok()?
    } else {
        units
            .into_iter()
            .map(char::from_u32)
            .collect::<Option<Vec<char>>>()?
    };
    Some((chars, header + end + 4))
}

#[cfg(test)]
mod tests {
    use super::decode;

    fn text(raw: &str) -> String {
        decode(raw.as_bytes()).text
    }

    #[test]
    fn plain_and_quotes() {
        assert_eq!(text("abc"), "abc");
        assert_eq!(text("it''s"), "it's");
        assert_eq!(text("''''"), "''");
    }

    #[test]
    fn directives() {
        assert_eq!(text(r"a\\b"), r"a\b");
        assert_eq!(text(r"\X\E9t\X\E9"), "été");
        assert_eq!(text(r"\X2\00E9004C\X0\x"), "éLx");
        assert_eq!(text(r"\X2\D83DDE00\X0\"), "\u{1F600}");
        assert_eq!(text(r"\X4\0001F600\X0\"), "\u{1F600}");
        assert_eq!(text(r"\S\i"), "é");
        assert_eq!(text(r"\PA\\S\i"), "é");
    }

    #[test]
    fn tolerated() {
        let d = decode(br"C:\temp\x");
        assert_eq!(d.text, r"C:\temp\x");
        assert_eq!(d.notes.len(), 1);
        let d = decode(b"caf\xE9");
        assert_eq!(d.text, "caf\u{FFFD}");
        assert_eq!(d.notes.len(), 1);
        assert_eq!(text("ab\r\ncd"), "abcd");
        assert_eq!(text("h\u{e9}"), "h\u{e9}");
        // Unpaired surrogate: not a directive, kept as written.
        assert_eq!(text(r"\X2\D83D\X0\"), r"\X2\D83D\X0\");
    }
}
