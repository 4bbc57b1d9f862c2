//! The controller families whose program syntax the interpreter reads.
//!
//! The motion words are ISO 6983 in all of them; what differs is the frame of the program,
//! block ends, a few keywords and which codes switch the tool-centre-point (TCP) mode on:
//!
//! | syntax | block end | units | TCP on / off | other |
//! |---|---|---|---|---|
//! | [`Syntax::Rs274`] (LinuxCNC, Fanuc, GRBL) | line end | G20/G21 | G43.4 / G49 | `%` tape lines |
//! | [`Syntax::Siemens`] (Sinumerik 840D) | line end | G70/G71, G700/G710 | `TRAORI` / `TRAFOOF` | `D` tool edge, `;` comments |
//! | [`Syntax::HeidenhainIso`] (TNC in ISO mode) | `*` | G70/G71 (also in the `%NAME G71` frame) | M128 / M129 | `%NAME G71 *` start and `N99999999 %NAME G71 *` end, `T1 G17 S..` tool call |

/// A controller family's program syntax.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Syntax {
    /// RS274NGC / ISO: LinuxCNC, Fanuc, GRBL.
    #[default]
    Rs274,
    /// Siemens Sinumerik 840D.
    Siemens,
    /// Heidenhain TNC, ISO programming.
    HeidenhainIso,
}

impl Syntax {
    /// The syntax of a post dialect or controller name (`linuxcnc`, `fanuc`, `grbl`, `rs274`,
    /// `siemens`, `sinumerik`, `heidenhain`, `heidenhain-iso`); `None` for an unknown name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        match name.trim().to_ascii_lowercase().as_str() {
            "rs274" | "rs274ngc" | "iso" | "linuxcnc" | "fanuc" | "grbl" => Some(Self::Rs274),
            "siemens" | "sinumerik" | "840d" => Some(Self::Siemens),
            "heidenhain" | "heidenhain-iso" | "tnc" => Some(Self::HeidenhainIso),
            _ => None,
        }
    }

    /// The syntax of a program, from its text, for a program whose syntax is not named:
    ///
    /// 1. Heidenhain ISO when the program frame `%NAME G70 *`/`%NAME G71 *` opens it, or when
    ///    more than half of its block lines end in `*`;
    /// 2. Sinumerik when a word only Sinumerik programs use appears outside comments: a
    ///    `G70`/`G71`/`G700`/`G710` unit code (lathe cycles in LinuxCNC and Fanuc, so never
    ///    in their milling programs), `TRAORI`/`TRAFOOF`, a `CYCLE..` call, `MCALL`, a
    ///    `%_N_..` file header, or a `T.. D..` tool call in a program commented with `;`
    ///    only (`;` comments alone do not decide: LinuxCNC and GRBL accept them too);
    /// 3. RS274 (LinuxCNC, Fanuc, GRBL) otherwise.
    ///
    /// The first 400 lines are read.
    #[must_use]
    pub fn detect(text: &str) -> Self {
        let mut star_lines = 0usize;
        let mut lines = 0usize;
        let mut semicolon_comments = false;
        let mut paren_comments = false;
        let mut tool_edge = false;
        for (i, line) in text.lines().take(400).enumerate() {
            let t = line.trim();
            let upper = t.to_ascii_uppercase();
            if i == 0 || lines == 0 {
                if upper.starts_with("%_N_") {
                    return Self::Siemens;
                }
                if upper.starts_with('%')
                    && upper.ends_with('*')
                    && (upper.contains(" G71") || upper.contains(" G70"))
                {
                    return Self::HeidenhainIso;
                }
            }
            if t.is_empty() {
                continue;
            }
            if t.starts_with(';') {
                semicolon_comments = true;
                continue;
            }
            if t.starts_with('(') {
                paren_comments = true;
                continue;
            }
            lines += 1;
            if t.ends_with('*') {
                star_lines += 1;
            }
            let (code, comment) = upper.split_once(';').unwrap_or((upper.as_str(), ""));
            semicolon_comments |= !comment.is_empty();
            let code = strip_parens(code, &mut paren_comments);
            if siemens_word(&code) {
                return Self::Siemens;
            }
            tool_edge |= has_word(&code, 'T') && has_word(&code, 'D');
        }
        if lines > 0 && star_lines * 2 > lines {
            Self::HeidenhainIso
        } else if tool_edge && semicolon_comments && !paren_comments {
            Self::Siemens
        } else {
            Self::Rs274
        }
    }

    /// The character that ends a block inside a line, if any (Heidenhain's `*`).
    #[must_use]
    pub fn block_end(self) -> Option<char> {
        match self {
            Self::HeidenhainIso => Some('*'),
            Self::Rs274 | Self::Siemens => None,
        }
    }

    /// G70/G71 select inch/metric (Siemens, Heidenhain) rather than being unknown codes.
    #[must_use]
    pub fn g70_g71_are_units(self) -> bool {
        !matches!(self, Self::Rs274)
    }
}

/// The line without its `( )` comments (noting that there were some).
fn strip_parens(code: &str, seen: &mut bool) -> String {
    let mut out = String::new();
    let mut depth = 0usize;
    for c in code.chars() {
        match c {
            '(' => {
                depth += 1;
                *seen = true;
            }
            ')' => depth = depth.saturating_sub(1),
            c if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

/// Whether the (upper-case, comment-free) line holds a word only Sinumerik programs use.
fn siemens_word(code: &str) -> bool {
    let tokens: Vec<&str> = code
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '.' || c == '_'))
        .filter(|t| !t.is_empty())
        .collect();
    tokens.iter().any(|t| {
        matches!(
            *t,
            "G70" | "G71" | "G700" | "G710" | "TRAORI" | "TRAFOOF" | "MCALL"
        ) || (t.starts_with("CYCLE") && t.len() > 5)
            || t.strip_prefix('N').is_some_and(|rest| {
                // `N10G71` written without a blank.
                rest.find('G').is_some_and(|g| {
                    rest.get(..g)
                        .is_some_and(|n| n.chars().all(|c| c.is_ascii_digit()))
                        && matches!(rest.get(g..), Some("G70" | "G71" | "G700" | "G710"))
                })
            })
    })
}

/// Whether the line has a word with this letter and a number.
fn has_word(code: &str, letter: char) -> bool {
    let chars: Vec<char> = code.chars().collect();
    chars.windows(2).enumerate().any(|(i, w)| {
        w.first() == Some(&letter)
            && w.get(1).is_some_and(char::is_ascii_digit)
            && (i == 0 || !chars.get(i - 1).is_some_and(char::is_ascii_alphabetic))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_detection() {
        assert_eq!(Syntax::from_name("Fanuc"), Some(Syntax::Rs274));
        assert_eq!(Syntax::from_name("heidenhain"), Some(Syntax::HeidenhainIso));
        assert_eq!(Syntax::from_name("siemens"), Some(Syntax::Siemens));
        assert_eq!(Syntax::from_name("mazak"), None);
        assert_eq!(
            Syntax::detect("%P G71 *\nN10 G01 X1 *\nN20 X2 *\n"),
            Syntax::HeidenhainIso
        );
        assert_eq!(Syntax::detect("N10 TRAORI\nN20 G1 X1\n"), Syntax::Siemens);
        assert_eq!(Syntax::detect("G1 X1 ; move\nG0 Z5\n"), Syntax::Rs274);
        // Talas's own Sinumerik output without TCP: G71 and `;` comments.
        assert_eq!(
            Syntax::detect("; PROGRAM TALAS\nN10 G17 G71 G40 G90 G94\nN20 G54\nN30 T1 D1\n"),
            Syntax::Siemens
        );
        assert_eq!(
            Syntax::detect("N10 T1 D1 ; edge\nN20 G1 X1 F100\n"),
            Syntax::Siemens
        );
        assert_eq!(
            Syntax::detect("N10 MCALL CYCLE81(10, 0, 2, -5)\n"),
            Syntax::Siemens
        );
        assert_eq!(
            Syntax::detect("%TALAS G71 *\n; PROGRAM\nN10 G17 *\n"),
            Syntax::HeidenhainIso
        );
        // LinuxCNC: parameters, O-words, G41 D1 with ( ) comments stay RS274.
        assert_eq!(
            Syntax::detect("(part)\n#1 = 2\nG41 D1 G1 X1 F100\no100 call\n(G71 in a comment)\n"),
            Syntax::Rs274
        );
    }
}
