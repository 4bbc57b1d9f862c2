//! The tool library: the list of tools (in the project tree, with add, duplicate and delete) and
//! the editor of one tool (in the properties panel). Sizes are typed in [`NumberField`]s, the
//! name and holder as text, and applied when the field loses focus (Enter, Tab or a click
//! elsewhere): one undo step per field. An invalid value (out of range, or a tool that is not
//! valid, such as a corner radius above the tool radius) is shown in red with the reason and is
//! not applied. The load limits (force N, torque N·m, power W, each optional) are typed as text
//! and range-checked as the engine checks them. Every change is a
//! [`Command::Edit`].

use super::super::command::Command;
use super::super::number_field::NumberField;
use super::super::state::Focus;
use super::super::theme;
use crate::project::{Edit, Project, ToolEntry};
use crate::tools::{Cutter, CutterKind, HolderSection, parse_tool_spec};

/// The kinds a new tool can have: (button label, spec of the default size).
pub const NEW_TOOLS: [(&str, &str); 4] = [
    ("Ball", "ball:d=6"),
    ("Flat", "flat:d=10"),
    ("Bull-nose", "bull:d=10,r=2"),
    ("Cone", "cone:d=10,angle=45"),
];

/// Name of a cutter kind, for labels.
#[must_use]
pub fn kind_name(kind: CutterKind) -> &'static str {
    match kind {
        CutterKind::Ball => "Ball end mill",
        CutterKind::Flat => "Flat end mill",
        CutterKind::BullNose { .. } => "Bull-nose end mill",
        CutterKind::Cone { .. } => "Cone (taper) tool",
    }
}

/// The tool rows of the project tree, with add, duplicate and delete buttons.
pub fn tool_list_ui(
    ui: &mut egui::Ui,
    project: &Project,
    focus: Focus,
    commands: &mut Vec<Command>,
) {
    for (i, tool) in project.tools.iter().enumerate() {
        let in_use = if project.selected_tool == Some(i) {
            "  (in use)"
        } else {
            ""
        };
        if ui
            .selectable_label(
                focus == Focus::Tool(i),
                format!("T{} {}{in_use}", i + 1, tool.name),
            )
            .on_hover_text(format!(
                "{} Ø{} mm{}",
                kind_name(tool.cutter.kind),
                tool.cutter.diameter,
                if in_use.is_empty() {
                    ""
                } else {
                    " (selected tool)"
                }
            ))
            .clicked()
        {
            commands.push(Command::Inspect(Focus::Tool(i)));
        }
    }
    ui.horizontal_wrapped(|ui| {
        for (label, spec) in NEW_TOOLS {
            if ui
                .small_button(format!("+ {label}"))
                .on_hover_text(format!("Add a {label} tool ({spec})"))
                .clicked()
                && let Ok(cutter) = parse_tool_spec(spec)
            {
                let index = project.tools.len();
                commands.push(Command::Edit(Edit::AddTool {
                    index,
                    tool: ToolEntry {
                        name: format!("{label} Ø{}", cutter.diameter),
                        cutter,
                    },
                }));
                commands.push(Command::Inspect(Focus::Tool(index)));
            }
        }
    });
    if let Focus::Tool(i) = focus
        && i < project.tools.len()
    {
        ui.horizontal(|ui| {
            if ui.small_button("Duplicate").clicked()
                && let Ok(e) = Edit::duplicate_tool(project, i)
            {
                commands.push(Command::Edit(e));
                commands.push(Command::Inspect(Focus::Tool(i + 1)));
            }
            if ui.small_button("Delete").clicked() {
                commands.push(Command::Edit(Edit::RemoveTool { index: i }));
                commands.push(Command::Inspect(Focus::Selection));
            }
        });
    }
}

/// The text fields of the tool being edited (the numbers are [`NumberField`]s).
#[derive(Clone, Debug, Default)]
pub struct ToolForm {
    /// The tool the texts were filled from (index and value).
    source: Option<(usize, ToolEntry)>,
    name: String,
    holder: String,
    /// The load limits as typed: force (N), torque (N·m), power (W); empty for none.
    limits: [String; 3],
    /// Why the last typed value was refused.
    pub error: Option<String>,
}

/// Sizes accepted for a tool, mm.
const TOOL_SIZE_MM: std::ops::RangeInclusive<f64> = 0.01..=1000.0;

fn number(text: &str, what: &str) -> Result<f64, String> {
    text.trim()
        .trim_end_matches("mm")
        .trim_end_matches('°')
        .trim()
        .parse::<f64>()
        .map_err(|_| format!("{what}: '{}' is not a number", text.trim()))
}

/// `20×30, 40×20`: holder sections (diameter × length, mm) from the bottom up.
fn holder_text(holder: &[HolderSection]) -> String {
    holder
        .iter()
        .map(|h| format!("{}×{}", h.diameter, h.length))
        .collect::<Vec<_>>()
        .join(", ")
}

fn parse_holder(text: &str) -> Result<Vec<HolderSection>, String> {
    text.split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            let (d, l) = s
                .split_once(['×', 'x', 'X', '*'])
                .ok_or_else(|| format!("holder: '{s}' is not diameter×length"))?;
            Ok(HolderSection {
                diameter: number(d, "holder diameter")?,
                length: number(l, "holder length")?,
            })
        })
        .collect()
}

/// Round away binary noise for display (a half-angle of 45° read back from radians).
fn tidy(v: f64) -> String {
    format!("{}", (v * 1e9).round() / 1e9)
}

impl ToolForm {
    fn fill(&mut self, index: usize, tool: &ToolEntry) {
        self.name.clone_from(&tool.name);
        self.holder = holder_text(&tool.cutter.holder);
        let l = tool.cutter.limits;
        self.limits = [l.max_force_n, l.max_torque_nm, l.max_power_w]
            .map(|v| v.map_or_else(String::new, tidy));
        self.error = None;
        self.source = Some((index, tool.clone()));
    }
}

/// The numeric fields of `cutter` (label, value in internal units, unit, × scale), each typed in
/// a [`NumberField`].
fn size_fields(cutter: &mut Cutter) -> Vec<(&'static str, &mut f64, &'static str, f64)> {
    let mut out = vec![("Diameter", &mut cutter.diameter, "mm", 1.0)];
    match &mut cutter.kind {
        CutterKind::BullNose { corner_radius } => {
            out.push(("Corner radius", corner_radius, "mm", 1.0));
        }
        CutterKind::Cone { half_angle } => {
            out.push(("Half-angle", half_angle, "°", 1f64.to_degrees()));
        }
        _ => {}
    }
    out.push(("Flute length", &mut cutter.flute_length, "mm", 1.0));
    out.push(("Shank diameter", &mut cutter.shank_diameter, "mm", 1.0));
    out.push(("Overall length", &mut cutter.overall_length, "mm", 1.0));
    out
}

/// `tool` (its sizes as typed) with the name and holder of `form`, if it is a valid tool; else
/// why not.
fn complete_tool(mut tool: ToolEntry, form: &ToolForm) -> Result<ToolEntry, String> {
    tool.name = form.name.trim().to_string();
    if tool.name.is_empty() {
        return Err("name: empty".into());
    }
    tool.cutter.holder = parse_holder(&form.holder)?;
    let [force, torque, power] = &form.limits;
    let limit = |text: &str, what: &str, unit: &str| -> Result<Option<f64>, String> {
        let t = text.trim().trim_end_matches(unit).trim();
        if t.is_empty() {
            return Ok(None);
        }
        t.parse::<f64>()
            .map(Some)
            .map_err(|_| format!("{what}: '{t}' is not a number"))
    };
    tool.cutter.limits = crate::tools::ToolLimits {
        max_force_n: limit(force, "max force", "N")?,
        max_torque_nm: limit(torque, "max torque", "N·m")?,
        max_power_w: limit(power, "max power", "W")?,
    };
    tool.cutter.validate().map_err(|e| e.to_string())?;
    Ok(tool)
}

/// The load-limit fields (force N, torque N·m, power W; empty for none), checked by the
/// cutting-force window; true when one lost focus.
fn limits_ui(ui: &mut egui::Ui, index: usize, form: &mut ToolForm) -> bool {
    let mut commit = false;
    ui.label("Load limits (empty: none)")
        .on_hover_text("Checked by the Cutting forces window: moves above a limit are flagged");
    egui::Grid::new(("tool limits", index))
        .num_columns(2)
        .spacing([8.0, 4.0])
        .show(ui, |ui| {
            let labels = ["Max force (N)", "Max torque (N·m)", "Max power (W)"];
            for (label, text) in labels.into_iter().zip(form.limits.iter_mut()) {
                let l = ui.label(label);
                let r = ui
                    .add(
                        egui::TextEdit::singleline(text)
                            .desired_width(90.0)
                            .id_salt(("tool limit", label)),
                    )
                    .labelled_by(l.id);
                commit |= r.lost_focus();
                ui.end_row();
            }
        });
    commit
}

/// The same tool with another cutting-end kind, sizes kept where they still fit.
fn with_kind(tool: &ToolEntry, kind: CutterKind) -> Option<ToolEntry> {
    let mut cutter = Cutter::new(kind, tool.cutter.diameter).ok()?;
    cutter.holder.clone_from(&tool.cutter.holder);
    cutter.shank_diameter = tool.cutter.shank_diameter;
    cutter.flute_length = tool.cutter.flute_length.max(cutter.profile_height());
    cutter.overall_length = tool.cutter.overall_length.max(cutter.flute_length);
    cutter.validate().ok()?;
    Some(ToolEntry {
        name: tool.name.clone(),
        cutter,
    })
}

/// The editor of tool `index` (properties panel).
pub fn tool_editor_ui(
    ui: &mut egui::Ui,
    project: &Project,
    index: usize,
    form: &mut ToolForm,
    commands: &mut Vec<Command>,
) {
    let Some(tool) = project.tools.get(index) else {
        ui.weak("No such tool.");
        return;
    };
    if form.source.as_ref() != Some(&(index, tool.clone())) {
        form.fill(index, tool);
    }
    ui.heading(format!("Tool T{}", index + 1));
    let d = tool.cutter.diameter;
    let mut kind = tool.cutter.kind;
    ui.horizontal(|ui| {
        let label = ui.label("Kind");
        egui::ComboBox::from_id_salt("tool kind")
            .selected_text(kind_name(kind))
            .show_ui(ui, |ui| {
                for k in [
                    CutterKind::Ball,
                    CutterKind::Flat,
                    CutterKind::BullNose {
                        corner_radius: 0.25 * d,
                    },
                    CutterKind::Cone {
                        half_angle: std::f64::consts::FRAC_PI_4,
                    },
                ] {
                    let same = std::mem::discriminant(&k) == std::mem::discriminant(&kind);
                    if ui.selectable_label(same, kind_name(k)).clicked() && !same {
                        kind = k;
                    }
                }
            })
            .response
            .labelled_by(label.id);
    });
    if kind != tool.cutter.kind
        && let Some(new) = with_kind(tool, kind)
    {
        commands.push(Command::Edit(Edit::SetTool { index, tool: new }));
    }
    let mut next = tool.clone();
    let mut commit = false;
    ui.horizontal(|ui| {
        let l = ui.label("Name");
        let r = ui
            .add(
                egui::TextEdit::singleline(&mut form.name)
                    .desired_width(f32::INFINITY)
                    .id_salt("tool name"),
            )
            .labelled_by(l.id);
        commit |= r.lost_focus();
    });
    egui::Grid::new(("tool editor", index))
        .num_columns(2)
        .spacing([8.0, 4.0])
        .striped(true)
        .show(ui, |ui| {
            for (label, value, unit, scale) in size_fields(&mut next.cutter) {
                let l = ui.label(label);
                let range = if unit == "°" {
                    0.1..=89.9
                } else {
                    TOOL_SIZE_MM
                };
                commit |= NumberField::new(("tool field", label), value)
                    .labelled_by(l.id)
                    .scale(scale)
                    .range(range)
                    .decimals(4)
                    .unit(unit)
                    .show(ui);
                ui.end_row();
            }
        });
    ui.horizontal(|ui| {
        let l = ui.label("Holder (Ø×length, mm)");
        let r = ui
            .add(
                egui::TextEdit::singleline(&mut form.holder)
                    .desired_width(f32::INFINITY)
                    .id_salt("tool holder"),
            )
            .labelled_by(l.id)
            .on_hover_text("Sections from the bottom up, e.g. 20×30, 40×20");
        commit |= r.lost_focus();
    });
    commit |= limits_ui(ui, index, form);
    if commit {
        match complete_tool(next, form) {
            Ok(new) if new != *tool => {
                form.error = None;
                commands.push(Command::Edit(Edit::SetTool { index, tool: new }));
            }
            Ok(_) => form.error = None,
            Err(e) => form.error = Some(e),
        }
    }
    if let Some(e) = &form.error {
        ui.colored_label(theme::ERROR, format!("Not applied: {e}"));
    }
    ui.add_space(6.0);
    let c = &tool.cutter;
    ui.weak(format!(
        "Profile height {} mm · stick-out {} mm",
        tidy(c.profile_height()),
        tidy(c.overall_length)
    ));
    ui.add_space(6.0);
    if project.selected_tool == Some(index) {
        ui.label("The project's selected tool");
    } else if ui.button("Use this tool").clicked() {
        commands.push(Command::Edit(Edit::SelectTool(Some(index))));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holder_text_reads_back_and_errors_name_the_field() {
        let h = parse_holder("20×30, 40x20").expect("two sections");
        assert_eq!(h.len(), 2);
        assert!((h[1].diameter - 40.0).abs() < 1e-12 && (h[1].length - 20.0).abs() < 1e-12);
        assert_eq!(parse_holder(&holder_text(&h)), Ok(h));
        assert!(parse_holder("20").is_err_and(|e| e.contains("holder")));
        assert!(number("abc", "diameter").is_err_and(|e| e.starts_with("diameter")));
        assert_eq!(number(" 6 mm", "d"), Ok(6.0));
    }
}
