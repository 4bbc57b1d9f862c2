//! `talas control --machine NAME_OR_FILE [--stock SHAPE] [--resolution MM] [--tool SPEC]
//! [--program FILE.ngc] [--tool-table FILE.tbl] --script SCRIPT.txt [--json]`: the virtual
//! control run headless from a script, one operator action per line. The program runs as
//! `talas interpret --machine` reads it (one interpretation: canned cycles, cutter
//! compensation with the tool table's radii, subroutines, loops).
//!
//! Script actions (`#` starts a comment): `home`, `mode ref|jog|mpg|mdi|auto`,
//! `jog AXIS ±DIST`, `jog-continuous AXIS +|- SECONDS`, `increment MM`, `mpg AXIS STEPS`,
//! `mdi LINE`, `override feed|rapid|spindle PCT`, `cycle-start`, `run-from LINE`, `hold`, `resume`, `stop`,
//! `reset`, `estop`, `wait SECONDS`, `wait-idle`, `spindle cw|ccw|stop`,
//! `single-block on|off`, `optional-stop on|off`, `block-delete on|off`, `jog-feed MM_PER_MIN`.
//! `home`, `jog`, `jog-continuous`, `mpg` and `mdi` return when the machine is at rest;
//! `cycle-start` and `resume` return at once (the program runs while later lines wait or
//! hold); after the last line the control runs until it is at rest.

use std::path::{Path, PathBuf};

use serde_json::{Map, Value, json};

use crate::control::{
    Action, Control, ControlConfig, LiveStock, Mode, OverrideKind, Snapshot, Spindle,
};
use crate::import::ImportError;
use crate::machine::Machine;
use crate::simulation::{DEFAULT_MEMORY_LIMIT_BYTES, DexelMode, DexelStock};
use crate::tools::parse_tool_spec;

/// Options of `talas control`.
#[derive(Debug, clap::Args)]
pub struct ControlArgs {
    /// Machine name (`talas machines`) or machine JSON file.
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub machine: String,
    /// Stock to cut (repeatable, union): `box:X0,Y0,Z0,X1,Y1,Z1`,
    /// `cylinder:CX,CY,R,Z0,Z1` (centre, radius, bottom and top) or `mesh:FILE.stl`, mm, machine
    /// coordinates. Needs `--tool`.
    #[arg(long, value_name = "SHAPE")]
    pub stock: Vec<String>,
    /// Dexel spacing of the stock, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.5)]
    pub resolution: f64,
    /// The tool in the spindle (`flat:d=6`, `ball:d=6`, ...).
    #[arg(long, value_name = "SPEC")]
    pub tool: Option<String>,
    /// A G-code program loaded for AUTO.
    #[arg(long, value_name = "FILE.ngc")]
    pub program: Option<PathBuf>,
    /// The tool table (G43 lengths, G41/G42 radii) for MDI and AUTO.
    #[command(flatten)]
    pub table: super::interpret::ToolTableArgs,
    /// The operator actions, one per line.
    #[arg(long, value_name = "SCRIPT.txt")]
    pub script: PathBuf,
    /// Print one JSON document instead of the human summary.
    #[arg(long)]
    pub json: bool,
}

/// Longest simulated time any one action (or the run after the last line) may take, s.
const MAX_WAIT_S: f64 = 1e5;

/// One parsed script line.
struct Step {
    line: usize,
    text: String,
    actions: Vec<Action>,
    /// Simulated seconds to run after the actions (`wait`, held jog keys).
    then_wait: f64,
    /// Further actions after that wait (`jog-continuous` releases its key).
    after: Vec<Action>,
    /// Run until the machine is at rest at the end.
    until_idle: bool,
}

fn number(tok: Option<&str>, what: &str, lo: f64, hi: f64) -> Result<f64, String> {
    let t = tok.ok_or_else(|| format!("missing {what}"))?;
    let v: f64 = t
        .parse()
        .map_err(|_| format!("{what} '{t}' is not a number"))?;
    if !(v >= lo && v <= hi) {
        return Err(format!("{what} {v} must lie in [{lo}, {hi}]"));
    }
    Ok(v)
}

fn axis(tok: Option<&str>) -> Result<char, String> {
    let t = tok.ok_or("missing axis letter")?;
    let mut c = t.chars();
    match (c.next(), c.next()) {
        (Some(a), None) if "XYZABCT".contains(a.to_ascii_uppercase()) => Ok(a.to_ascii_uppercase()),
        _ => Err(format!(
            "'{t}' is not an axis letter (X Y Z A B C, or T for the tool axis)"
        )),
    }
}

fn switch(tok: Option<&str>) -> Result<bool, String> {
    match tok {
        Some("on") => Ok(true),
        Some("off") => Ok(false),
        other => Err(format!("expected on or off, got {other:?}")),
    }
}

/// Parse one script line (comment and blank lines give `None`).
fn parse_line(raw: &str, line: usize) -> Result<Option<Step>, String> {
    let text = raw.split('#').next().unwrap_or("").trim();
    if text.is_empty() {
        return Ok(None);
    }
    let mut words = text.split_whitespace();
    let verb = words.next().unwrap_or("").to_ascii_lowercase();
    let mut step = Step {
        line,
        text: text.to_string(),
        actions: Vec::new(),
        then_wait: 0.0,
        after: Vec::new(),
        until_idle: false,
    };
    let one = |a: Action| vec![a];
    match verb.as_str() {
        "home" => {
            step.actions = one(Action::Home);
            step.until_idle = true;
        }
        "mode" => {
            let m = match words.next().map(str::to_ascii_lowercase).as_deref() {
                Some("ref") => Mode::Ref,
                Some("jog") => Mode::Jog,
                Some("mpg") => Mode::Mpg,
                Some("mdi") => Mode::Mdi,
                Some("auto") => Mode::Auto,
                other => return Err(format!("unknown mode {other:?} (ref, jog, mpg, mdi, auto)")),
            };
            step.actions = one(Action::SetMode(m));
        }
        "jog" => {
            let axis = axis(words.next())?;
            let distance = number(words.next(), "jog distance", -1e4, 1e4)?;
            step.actions = one(Action::JogDistance { axis, distance });
            step.until_idle = true;
        }
        "jog-continuous" => {
            let axis = axis(words.next())?;
            let direction = match words.next() {
                Some("+") => 1.0,
                Some("-") => -1.0,
                other => return Err(format!("jog direction must be + or -, got {other:?}")),
            };
            step.then_wait = number(words.next(), "seconds held", 0.0, MAX_WAIT_S)?;
            step.actions = one(Action::JogStart { axis, direction });
            step.after = one(Action::JogStop);
            step.until_idle = true;
        }
        "increment" => {
            step.actions = one(Action::SetIncrement(number(
                words.next(),
                "increment",
                1e-6,
                1000.0,
            )?));
        }
        "mpg" => {
            let axis = axis(words.next())?;
            let n = number(words.next(), "detent count", -1e6, 1e6)?;
            if n.fract() != 0.0 {
                return Err(format!("detent count {n} must be a whole number"));
            }
            #[allow(clippy::cast_possible_truncation)]
            let detents = n as i32;
            step.actions = one(Action::Mpg { axis, detents });
            step.until_idle = true;
        }
        "mdi" => {
            let rest = text.get(3..).unwrap_or("").trim();
            if rest.is_empty() {
                return Err("mdi needs a G-code line".into());
            }
            step.actions = one(Action::Mdi(rest.to_string()));
            step.until_idle = true;
        }
        "override" => {
            let kind = match words.next() {
                Some("feed") => OverrideKind::Feed,
                Some("rapid") => OverrideKind::Rapid,
                Some("spindle") => OverrideKind::Spindle,
                other => {
                    return Err(format!(
                        "override must be feed, rapid or spindle, got {other:?}"
                    ));
                }
            };
            step.actions = one(Action::Override(
                kind,
                number(words.next(), "override percent", 0.0, 1000.0)?,
            ));
        }
        "cycle-start" => step.actions = one(Action::CycleStart),
        "run-from" => {
            let n = number(words.next(), "line", 1.0, 1e9)?;
            if n.fract() != 0.0 {
                return Err(format!("line {n} must be a whole number"));
            }
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let n = n as usize;
            step.actions = one(Action::RunFromLine(n));
        }
        "hold" => step.actions = one(Action::FeedHold),
        "resume" => step.actions = one(Action::Resume),
        "stop" => step.actions = one(Action::Stop),
        "reset" => step.actions = one(Action::Reset),
        "estop" => step.actions = one(Action::EStop),
        "wait" => step.then_wait = number(words.next(), "wait seconds", 0.0, MAX_WAIT_S)?,
        "wait-idle" => step.until_idle = true,
        "spindle" => {
            let s = match words.next() {
                Some("cw") => Spindle::Cw,
                Some("ccw") => Spindle::Ccw,
                Some("stop") => Spindle::Stop,
                other => return Err(format!("spindle cw, ccw or stop, got {other:?}")),
            };
            step.actions = one(Action::Spindle(s));
        }
        "single-block" => step.actions = one(Action::SingleBlock(switch(words.next())?)),
        "optional-stop" => step.actions = one(Action::OptionalStop(switch(words.next())?)),
        "block-delete" => step.actions = one(Action::BlockDelete(switch(words.next())?)),
        "jog-feed" => {
            step.actions = one(Action::JogFeed(number(
                words.next(),
                "jog feed",
                1e-3,
                1e6,
            )?));
        }
        other => return Err(format!("unknown action '{other}'")),
    }
    if verb != "mdi"
        && let Some(extra) = words.next()
    {
        return Err(format!("unexpected '{extra}' after the action"));
    }
    Ok(Some(step))
}

/// The most lines a control script may have.
pub const MAX_SCRIPT_LINES: usize = 100_000;

fn build_control(args: &ControlArgs) -> Result<Control, ImportError> {
    let machine = Machine::resolve(&args.machine)
        .map_err(|e| ImportError::new(Path::new(&args.machine), None, e.to_string()))?;
    let mut cfg = ControlConfig::new(machine);
    cfg.tool_table = args.table.read()?;
    if !args.stock.is_empty() {
        let spec = args.tool.as_deref().ok_or_else(|| {
            ImportError::new(
                Path::new("--tool"),
                None,
                "a stock needs --tool SPEC to cut it",
            )
        })?;
        let cutter = parse_tool_spec(spec)
            .map_err(|e| ImportError::new(Path::new("--tool"), None, e.to_string()))?;
        let shapes = args
            .stock
            .iter()
            .map(|s| super::simulate::parse_stock(s, None))
            .collect::<Result<Vec<_>, _>>()?;
        let mode = if cfg.machine.rotary_names().is_some() {
            DexelMode::Tri
        } else {
            DexelMode::Z
        };
        let stock = DexelStock::new(shapes, args.resolution, mode, DEFAULT_MEMORY_LIMIT_BYTES)
            .map_err(|e| ImportError::new(Path::new("--stock"), None, e.to_string()))?;
        cfg.stock = Some(LiveStock::new(stock, cutter, args.resolution));
    }
    let mut control = Control::new(cfg)
        .map_err(|e| ImportError::new(Path::new(&args.machine), None, e.to_string()))?;
    if let Some(p) = &args.program {
        let text = crate::storage::read_program_text(p)
            .map_err(|e| ImportError::new(p, None, format!("cannot read file: {e}")))?;
        control
            .apply(Action::LoadProgram {
                name: p.display().to_string(),
                text,
            })
            .map_err(|e| ImportError::new(p, None, e.to_string()))?;
        // A program AUTO could not read is an error of the command (exit 2), not an alarm
        // in an otherwise successful run.
        control
            .check_program()
            .map_err(|e| ImportError::new(p, None, e.to_string()))?;
    }
    Ok(control)
}

/// Run the script and build the JSON document.
///
/// # Errors
/// An [`ImportError`] naming the file and place for bad input (machine, stock, tool, program,
/// a script line that is not an action).
pub fn control(args: &ControlArgs) -> Result<Value, ImportError> {
    let script = crate::storage::read_text_bounded(&args.script, crate::storage::TEXT_LIMIT_BYTES)
        .and_then(|t| crate::storage::check_line_count(&t, MAX_SCRIPT_LINES).map(|()| t))
        .map_err(|e| ImportError::new(&args.script, None, format!("cannot read file: {e}")))?;
    let mut steps = Vec::new();
    for (i, raw) in script.lines().enumerate() {
        match parse_line(raw, i + 1) {
            Ok(Some(s)) => steps.push(s),
            Ok(None) => {}
            Err(msg) => {
                return Err(ImportError::new(
                    &args.script,
                    Some(format!("line {}", i + 1)),
                    msg,
                ));
            }
        }
    }
    let mut c = build_control(args)?;
    let mut actions = Vec::new();
    for step in &steps {
        let before = c.alarms().len();
        let mut refused: Option<String> = None;
        let mut apply = |c: &mut Control, list: &[Action]| {
            for a in list {
                if let Err(e) = c.apply(a.clone()) {
                    refused.get_or_insert(e.to_string());
                }
            }
        };
        apply(&mut c, &step.actions);
        c.advance(step.then_wait);
        apply(&mut c, &step.after);
        if step.until_idle {
            c.advance_until_idle(MAX_WAIT_S);
        }
        let alarm = c.alarms().get(before).map(alarm_json);
        let now = c.snapshot();
        actions.push(json!({
            "line": step.line,
            "action": step.text,
            "t_s": c.time_s(),
            "program_line": now.line,
            "cycle": now.cycle,
            "alarm": alarm,
            "refused": refused,
        }));
    }
    c.advance_until_idle(MAX_WAIT_S);
    c.flush_cutting();
    let snap = c.snapshot();
    Ok(document(&c, &snap, actions))
}

fn alarm_json(a: &crate::control::Alarm) -> Value {
    json!({
        "code": a.code,
        "text": a.text,
        "axis": a.axis.map(String::from),
        "bodies": a.bodies,
        "position": a.position,
        "line": a.line,
        "t_s": a.t_s,
    })
}

fn document(c: &Control, snap: &Snapshot, actions: Vec<Value>) -> Value {
    let per_axis = |v: &[f64]| -> Value {
        let mut m = Map::new();
        for (a, x) in snap.axes.iter().zip(v) {
            m.insert(a.to_string(), json!(x));
        }
        Value::Object(m)
    };
    let mut peaks = Map::new();
    for p in c.peaks() {
        peaks.insert(
            p.axis.to_string(),
            json!({"velocity": p.velocity, "acceleration": p.acceleration, "jerk": p.jerk}),
        );
    }
    json!({
        "units": "mm, deg, s (peaks per s, s², s³)",
        "machine": c.machine().name,
        "mode": snap.mode,
        "state": snap.state,
        "machine_position": per_axis(&snap.machine_position),
        "work_position": per_axis(&snap.work_position),
        "homed": snap.axes.iter().zip(&snap.homed).map(|(a, h)| (a.to_string(), json!(h))).collect::<Map<_, _>>(),
        "time_s": snap.time_s,
        "active_codes": snap.active_codes,
        "alarms": snap.alarms.iter().map(alarm_json).collect::<Vec<_>>(),
        "removed_volume_mm3": snap.removed_volume_mm3,
        "peaks": peaks,
        "actions": actions,
    })
}

/// Human summary.
#[must_use]
pub fn human(doc: &Value) -> String {
    let mut s = String::new();
    let axes = |k: &str| {
        doc.get(k)
            .and_then(Value::as_object)
            .map(|m| {
                m.iter()
                    .map(|(a, v)| format!("{a} {:.4}", v.as_f64().unwrap_or(f64::NAN)))
                    .collect::<Vec<_>>()
                    .join("  ")
            })
            .unwrap_or_default()
    };
    s.push_str(&format!(
        "machine: {}  (mm, deg)\n",
        axes("machine_position")
    ));
    s.push_str(&format!("work:    {}\n", axes("work_position")));
    s.push_str(&format!(
        "time {:.3} s, removed {:.3} mm³, state {}\n",
        doc.get("time_s").and_then(Value::as_f64).unwrap_or(0.0),
        doc.get("removed_volume_mm3")
            .and_then(Value::as_f64)
            .unwrap_or(0.0),
        doc.get("state").and_then(Value::as_str).unwrap_or("?"),
    ));
    for a in doc
        .get("alarms")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
    {
        s.push_str(&format!(
            "alarm {}: {}\n",
            a.get("code").and_then(Value::as_u64).unwrap_or(0),
            a.get("text").and_then(Value::as_str).unwrap_or("")
        ));
    }
    for a in doc
        .get("actions")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
    {
        if let Some(r) = a.get("refused").and_then(Value::as_str) {
            s.push_str(&format!(
                "script line {}: refused: {r}\n",
                a.get("line").and_then(Value::as_u64).unwrap_or(0)
            ));
        }
    }
    s
}
