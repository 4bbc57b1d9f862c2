//! Dialects: everything a shop changes about the text of a program (codes, number formats,
//! header and footer templates) lives in a JSON file (`assets/posts/*.json`, embedded; any
//! other file can be loaded by path).
//!
//! A dialect file needs only a `name` and what differs from LinuxCNC's
//! (`assets/posts/linuxcnc.json`): every field it leaves out takes LinuxCNC's value. Unknown
//! fields are refused (a misspelt key would otherwise change nothing without a word).
//!
//! Template lines may use `{program}`, `{machine}`, `{dialect}`, `{tool}`, `{tool_spec}`,
//! `{rpm}`, `{work_offset}`. A line beginning with `!` is written as it stands: no line number, no block end.

use super::PostError;

/// A G-code dialect (see the module docs and `assets/posts/linuxcnc.json`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dialect {
    /// Short name (`linuxcnc`).
    pub name: String,
    /// One line for people.
    pub description: String,
    /// Rotary axes allowed (false: 3-axis machines only).
    pub five_axis: bool,
    /// Text before a comment.
    pub comment_open: String,
    /// Text after a comment.
    pub comment_close: String,
    /// Text after every block (`" *"` for Heidenhain).
    pub block_end: String,
    /// Number blocks by default.
    pub line_numbers: bool,
    /// First line number.
    pub line_number_start: u32,
    /// Line number increment.
    pub line_number_step: u32,
    /// Decimal places of X Y Z (mm).
    pub decimals_linear: usize,
    /// Decimal places of rotary axes (degrees).
    pub decimals_angle: usize,
    /// Decimal places of F in mm/min.
    pub decimals_feed: usize,
    /// Decimal places of F in inverse time (1/min).
    pub decimals_inverse_time: usize,
    /// Drop trailing zeros (`10.5` rather than `10.5000`).
    pub strip_trailing_zeros: bool,
    /// Keep the point of whole numbers (`10.`), as Fanuc reads `10` as 10 µm-units otherwise.
    pub keep_decimal_point: bool,
    /// Rapid move code.
    pub rapid: String,
    /// Linear feed move code.
    pub linear: String,
    /// Feed per minute mode.
    pub feed_per_minute: String,
    /// Inverse-time feed mode.
    pub inverse_time: String,
    /// Lines before everything (tape marks, program number).
    pub header: Vec<String>,
    /// Comment lines after the header.
    pub header_comments: Vec<String>,
    /// Modal setup blocks (plane, units, offsets).
    pub setup: Vec<String>,
    /// Tool change and length compensation.
    pub tool_change: Vec<String>,
    /// Spindle start.
    pub spindle_on: Vec<String>,
    /// Coolant on.
    pub coolant_on: Vec<String>,
    /// Tool-centre-point mode on (empty: not supported).
    pub tcp_on: Vec<String>,
    /// Tool-centre-point mode off.
    pub tcp_off: Vec<String>,
    /// Blocks after the final retract.
    pub footer: Vec<String>,
    /// Lines after everything.
    pub trailer: Vec<String>,
}

const BUILTIN: [(&str, &str); 5] = [
    ("linuxcnc", include_str!("../../assets/posts/linuxcnc.json")),
    ("fanuc", include_str!("../../assets/posts/fanuc.json")),
    ("siemens", include_str!("../../assets/posts/siemens.json")),
    (
        "heidenhain",
        include_str!("../../assets/posts/heidenhain.json"),
    ),
    ("grbl", include_str!("../../assets/posts/grbl.json")),
];

impl Dialect {
    /// Names of the embedded dialects.
    #[must_use]
    pub fn builtin_names() -> Vec<&'static str> {
        BUILTIN.iter().map(|(n, _)| *n).collect()
    }

    /// An embedded dialect by name.
    ///
    /// # Errors
    /// [`PostError::Dialect`] for unknown names.
    pub fn builtin(name: &str) -> Result<Self, PostError> {
        let (_, text) = BUILTIN.iter().find(|(n, _)| *n == name).ok_or_else(|| {
            PostError::Dialect(format!(
                "unknown dialect {name:?} (built in: {})",
                Self::builtin_names().join(", ")
            ))
        })?;
        Self::from_json(text, name)
    }

    /// A dialect from JSON text (`file` names it in errors).
    ///
    /// # Errors
    /// [`PostError::Dialect`] naming the file, line and column.
    pub fn from_json(text: &str, file: &str) -> Result<Self, PostError> {
        let syntax = |e: serde_json::Error| {
            PostError::Dialect(format!(
                "{file}: line {}, column {}: {}",
                e.line(),
                e.column(),
                crate::toolpath::strip_position(&e.to_string())
            ))
        };
        let given: serde_json::Value = serde_json::from_str(text).map_err(syntax)?;
        let serde_json::Value::Object(given) = given else {
            return Err(PostError::Dialect(format!(
                "{file}: a dialect file is one JSON object"
            )));
        };
        if !given.contains_key("name") {
            return Err(PostError::Dialect(format!(
                "{file}: a dialect needs a \"name\""
            )));
        }
        // Every field the file leaves out is the LinuxCNC dialect's.
        let mut merged: serde_json::Map<String, serde_json::Value> =
            serde_json::from_str(BUILTIN[0].1).map_err(syntax)?;
        merged.extend(given);
        let d: Self = serde_json::from_value(serde_json::Value::Object(merged)).map_err(|e| {
            // Read the file alone for the line and column of a wrong value or key (its
            // "missing field" errors are not errors here).
            match serde_json::from_str::<Self>(text) {
                Err(positioned) if !positioned.to_string().starts_with("missing field") => {
                    syntax(positioned)
                }
                _ => PostError::Dialect(format!("{file}: {e}")),
            }
        })?;
        if d.decimals_linear > 9 || d.decimals_angle > 9 || d.decimals_feed > 9 {
            return Err(PostError::Dialect(format!(
                "{file}: at most 9 decimal places"
            )));
        }
        if d.line_number_step == 0 {
            return Err(PostError::Dialect(format!(
                "{file}: line_number_step must be positive"
            )));
        }
        Ok(d)
    }

    /// A built-in name, or else a path to a dialect file.
    ///
    /// # Errors
    /// [`PostError::Dialect`] when neither works.
    pub fn resolve(name_or_file: &str) -> Result<Self, PostError> {
        if let Ok(d) = Self::builtin(name_or_file) {
            return Ok(d);
        }
        let path = std::path::Path::new(name_or_file);
        match std::fs::read_to_string(path) {
            Ok(text) => Self::from_json(&text, name_or_file),
            Err(_) => Self::builtin(name_or_file),
        }
    }

    /// The controller supports a tool-centre-point mode.
    #[must_use]
    pub fn supports_tcp(&self) -> bool {
        !self.tcp_on.is_empty()
    }

    /// A number with `decimals` places in this dialect's style (never `-0`).
    #[must_use]
    pub fn number(&self, v: f64, decimals: usize) -> String {
        let mut s = format!("{v:.decimals$}");
        if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
            s.remove(0);
        }
        if self.strip_trailing_zeros && s.contains('.') {
            while s.ends_with('0') {
                s.pop();
            }
            if s.ends_with('.') && !self.keep_decimal_point {
                s.pop();
            }
        } else if self.keep_decimal_point && !s.contains('.') {
            s.push('.');
        }
        s
    }

    /// A value rounded as [`Dialect::number`] writes it.
    #[must_use]
    pub fn rounded(v: f64, decimals: usize) -> f64 {
        let scale = 10f64.powi(decimals as i32);
        (v * scale).round() / scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_loads() {
        for name in Dialect::builtin_names() {
            let d = Dialect::builtin(name).unwrap();
            assert_eq!(d.name, name);
        }
        assert!(Dialect::builtin("haas").is_err());
    }

    #[test]
    fn number_formats() {
        let lcnc = Dialect::builtin("linuxcnc").unwrap();
        assert_eq!(lcnc.number(10.0, 4), "10");
        assert_eq!(lcnc.number(-0.00001, 4), "0");
        assert_eq!(lcnc.number(1.23456, 4), "1.2346");
        let fanuc = Dialect::builtin("fanuc").unwrap();
        assert_eq!(fanuc.number(10.0, 4), "10.");
        assert_eq!(fanuc.number(-2.5, 4), "-2.5");
    }

    #[test]
    fn bad_files_name_the_place() {
        let e = Dialect::from_json("{\n \"name\": 3 }", "x.json").unwrap_err();
        assert!(e.to_string().contains("x.json: line 2"), "{e}");
    }
}
