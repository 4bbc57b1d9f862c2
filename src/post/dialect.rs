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
    /// Write arcs as G2/G3 (false: every arc as lines within the post tolerance).
    pub arcs: bool,
    /// Clockwise arc code.
    pub arc_cw: String,
    /// Counter-clockwise arc code.
    pub arc_ccw: String,
    /// Plane codes arcs may be written in, of `G17` (XY), `G18` (ZX), `G19` (YZ); an arc in
    /// another plane is written as lines.
    pub arc_planes: Vec<String>,
    /// How an arc's centre is written: `ijk` (incremental I J K) or `radius` (R, negative
    /// beyond 180°).
    pub arc_centre: ArcCentre,
    /// Largest arc radius written as an arc, mm (larger: lines).
    pub arc_max_radius_mm: f64,
    /// Largest sweep of one arc block, degrees (longer arcs are split; at most 360, and 150
    /// with `radius` centres, where R is ill-conditioned near 180°).
    pub arc_max_sweep_deg: f64,
    /// Helices (arcs rising along the plane normal) allowed as arcs.
    pub helix: bool,
    /// How canned cycles are written.
    pub cycles: CycleStyle,
    /// Dwell at the bottom of an RS274 cycle (`P`) in milliseconds rather than seconds
    /// (Fanuc).
    pub cycle_dwell_ms: bool,
    /// Dwell block template, with `{seconds}` or `{ms}`.
    pub dwell: String,
    /// Spindle counter-clockwise (tapping out), clockwise, and stop codes.
    pub spindle_reverse: String,
    /// Spindle clockwise.
    pub spindle_forward: String,
    /// Spindle stop.
    pub spindle_stop: String,
    /// Blocks between two operations of one program before the tool change (optional stop,
    /// coolant and spindle off).
    pub between_operations: Vec<String>,
    /// How a 3+2 setup's tilted work plane is written (`explicit`: rotary words and rotated
    /// coordinates; `g68_2`, `cycle800`, `plane_spatial`: the control's own plane).
    pub work_plane: super::workplane::WorkPlaneStyle,
}

/// How an arc's centre is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ArcCentre {
    /// Incremental I J K from the start point (RS274 default, Siemens).
    Ijk,
    /// Signed radius R (negative for arcs beyond 180°).
    Radius,
}

/// How a dialect writes canned cycles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CycleStyle {
    /// G73, G81–G86, G89 with G98/G99 and G80 (LinuxCNC, Fanuc).
    Rs274,
    /// CYCLE81–CYCLE85 calls (Sinumerik 840D).
    Siemens,
    /// Cycles 200, 201, 203, 207 defined in ISO (`G200 Q200=…`) and called with `G79`
    /// (Heidenhain TNC in DIN/ISO).
    HeidenhainIso,
    /// Expanded into rapids, feeds, dwells and spindle switches (GRBL).
    Expand,
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
        d.check_numbers(file)?;
        super::probe::check_reads_back(&d, file)?;
        Ok(d)
    }

    /// Every number of the dialect within its bounds, every code and template one line.
    fn check_numbers(&self, file: &str) -> Result<(), PostError> {
        let bad = |field: &str, value: String, bounds: &str| {
            Err(PostError::Dialect(format!(
                "{file}: {field} = {value} is out of bounds ({bounds})"
            )))
        };
        let decimals = [
            ("decimals_linear", self.decimals_linear, 1, 6),
            ("decimals_angle", self.decimals_angle, 1, 6),
            ("decimals_feed", self.decimals_feed, 0, 4),
            ("decimals_inverse_time", self.decimals_inverse_time, 1, 6),
        ];
        for (field, v, lo, hi) in decimals {
            if !(lo..=hi).contains(&v) {
                let why = if field == "decimals_linear" && v == 0 {
                    ": 0 rounds every coordinate to 1 mm"
                } else {
                    ""
                };
                return bad(
                    field,
                    v.to_string(),
                    &format!("{lo} to {hi} decimal places{why}"),
                );
            }
        }
        if !(1..=1000).contains(&self.line_number_step) {
            return bad(
                "line_number_step",
                self.line_number_step.to_string(),
                "1 to 1000",
            );
        }
        if self.line_number_start > 99_999_000 {
            return bad(
                "line_number_start",
                self.line_number_start.to_string(),
                "0 to 99999000",
            );
        }
        if !(self.arc_max_radius_mm > 0.0 && self.arc_max_radius_mm <= 1e6) {
            return bad(
                "arc_max_radius_mm",
                self.arc_max_radius_mm.to_string(),
                "more than 0 and at most 1e6 mm",
            );
        }
        if !(self.arc_max_sweep_deg >= 1.0 && self.arc_max_sweep_deg <= 360.0) {
            return bad(
                "arc_max_sweep_deg",
                self.arc_max_sweep_deg.to_string(),
                "1 to 360 degrees",
            );
        }
        if let Some(p) = self
            .arc_planes
            .iter()
            .find(|p| !matches!(p.as_str(), "G17" | "G18" | "G19"))
        {
            return bad("arc_planes", format!("{p:?}"), "G17, G18 or G19");
        }
        let codes = [
            ("rapid", &self.rapid),
            ("linear", &self.linear),
            ("feed_per_minute", &self.feed_per_minute),
            ("inverse_time", &self.inverse_time),
            ("arc_cw", &self.arc_cw),
            ("arc_ccw", &self.arc_ccw),
            ("dwell", &self.dwell),
            ("spindle_reverse", &self.spindle_reverse),
            ("spindle_forward", &self.spindle_forward),
            ("spindle_stop", &self.spindle_stop),
        ];
        for (field, code) in codes {
            if code.trim().is_empty() || code.chars().any(char::is_control) {
                return bad(field, format!("{code:?}"), "a code on one line");
            }
        }
        let templates = [
            ("header", &self.header),
            ("header_comments", &self.header_comments),
            ("setup", &self.setup),
            ("tool_change", &self.tool_change),
            ("spindle_on", &self.spindle_on),
            ("coolant_on", &self.coolant_on),
            ("tcp_on", &self.tcp_on),
            ("tcp_off", &self.tcp_off),
            ("footer", &self.footer),
            ("trailer", &self.trailer),
            ("between_operations", &self.between_operations),
        ];
        for (field, lines) in templates {
            if let Some(l) = lines.iter().find(|l| l.chars().any(char::is_control)) {
                return bad(field, format!("{l:?}"), "lines without control characters");
            }
        }
        let marks = [
            ("comment_open", &self.comment_open),
            ("comment_close", &self.comment_close),
            ("block_end", &self.block_end),
        ];
        for (field, m) in marks {
            if m.chars().any(char::is_control) {
                return bad(field, format!("{m:?}"), "no control characters");
            }
        }
        Ok(())
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
        match crate::storage::read_text_bounded(path, crate::storage::TEXT_LIMIT_BYTES) {
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
        // Loaded dialects have at most 6 places; a hand-built one is clamped, never a panic.
        let decimals = decimals.min(17);
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
        let scale = 10f64.powi(decimals.min(17) as i32);
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
