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

    /// A guess from the program text: Heidenhain when blocks end in `*`, Siemens when a
    /// Sinumerik keyword (`TRAORI`, `TRAFOOF`) or an `N.. D..` tool edge appears, else RS274.
    #[must_use]
    pub fn detect(text: &str) -> Self {
        let mut star_lines = 0usize;
        let mut lines = 0usize;
        for line in text.lines().take(400) {
            let t = line.trim();
            if t.is_empty() || t.starts_with(';') || t.starts_with('(') {
                continue;
            }
            lines += 1;
            if t.ends_with('*') {
                star_lines += 1;
            }
            let upper = t.to_ascii_uppercase();
            if upper.contains("TRAORI") || upper.contains("TRAFOOF") {
                return Self::Siemens;
            }
        }
        if lines > 0 && star_lines * 2 > lines {
            Self::HeidenhainIso
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
    }
}
