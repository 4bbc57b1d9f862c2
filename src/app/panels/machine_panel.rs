//! The machine panel: choose a built-in machine (or ask for a file), see its axes with travel
//! and velocity/acceleration/jerk limits, its kinematics and a schematic of it, and set the
//! post options (dialect, tool-centre-point output, work offset). Returns
//! [`MachinePanelEvent`]s; the caller turns them into project edits.

mod schematic;

pub use schematic::{SchematicView, draw_schematic};

use crate::machine::{KinematicsKind, Machine};
use crate::post::Dialect;

/// Post settings chosen in the panel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PostSettings {
    /// Dialect name (one of [`Dialect::builtin_names`]).
    pub dialect: String,
    /// Tool-centre-point output.
    pub tcp: bool,
    /// Work offset number 54..=59 (G54..G59).
    pub work_offset: u8,
}

impl Default for PostSettings {
    fn default() -> Self {
        Self {
            dialect: "linuxcnc".into(),
            tcp: false,
            work_offset: 54,
        }
    }
}

/// What the user did in the panel.
#[derive(Clone, Debug, PartialEq)]
pub enum MachinePanelEvent {
    /// A built-in machine was chosen (already shown by the panel), with the post settings
    /// made valid for it (a 3-axis machine falls back to a 3-axis dialect, TCP off).
    MachineChosen {
        /// Built-in machine name.
        name: String,
        /// The settings now shown.
        settings: PostSettings,
    },
    /// The user asked to open a machine file (show the file dialog, then call
    /// [`MachinePanel::set_machine`]).
    OpenMachineFile,
    /// The post settings changed (the panel keeps them valid for the machine).
    PostSettingsChanged(PostSettings),
}

/// One row of the axis table, in display units (mm or deg).
#[derive(Clone, Debug, PartialEq)]
pub struct AxisRow {
    /// Axis letter.
    pub axis: char,
    /// Rotary axis: values in degrees.
    pub rotary: bool,
    /// Travel (min, max).
    pub travel: (f64, f64),
    /// Velocity limit per s.
    pub velocity: f64,
    /// Acceleration limit per s².
    pub acceleration: f64,
    /// Jerk limit per s³.
    pub jerk: f64,
    /// Rotation direction (+1 or −1).
    pub direction: f64,
}

/// The axis table of a machine in display units.
#[must_use]
pub fn axis_rows(machine: &Machine) -> Vec<AxisRow> {
    machine
        .axes
        .iter()
        .map(|a| {
            let k = if a.is_rotary() {
                180.0 / std::f64::consts::PI
            } else {
                1.0
            };
            AxisRow {
                axis: a.name,
                rotary: a.is_rotary(),
                travel: (a.min * k, a.max * k),
                velocity: a.velocity * k,
                acceleration: a.acceleration * k,
                jerk: a.jerk * k,
                direction: a.direction,
            }
        })
        .collect()
}

/// A phrase for a kinematic arrangement.
#[must_use]
pub fn kinematics_label(kind: KinematicsKind) -> &'static str {
    match kind {
        KinematicsKind::ThreeAxis => "3-axis mill (xyz)",
        KinematicsKind::TableAc => "table-tilting A/C trunnion (xyzac-trt)",
        KinematicsKind::TableBc => "table-tilting B/C trunnion (xyzbc-trt)",
    }
}

/// The dialects that can post for `machine` (3-axis dialects only for 3-axis machines).
#[must_use]
pub fn dialects_for(machine: &Machine) -> Vec<&'static str> {
    let five = machine.kinematics != KinematicsKind::ThreeAxis;
    Dialect::builtin_names()
        .into_iter()
        .filter(|n| Dialect::builtin(n).is_ok_and(|d| !five || d.five_axis))
        .collect()
}

/// Can `dialect` write tool-centre-point output for `machine`?
#[must_use]
pub fn tcp_possible(machine: &Machine, dialect: &str) -> bool {
    machine.kinematics != KinematicsKind::ThreeAxis
        && Dialect::builtin(dialect).is_ok_and(|d| d.five_axis && d.supports_tcp())
}

/// State of the machine panel.
pub struct MachinePanel {
    machine: Machine,
    settings: PostSettings,
    view: SchematicView,
}

impl MachinePanel {
    /// A panel showing `machine` with `settings` (made valid for the machine).
    #[must_use]
    pub fn new(machine: Machine, settings: PostSettings) -> Self {
        let mut panel = Self {
            machine,
            settings,
            view: SchematicView::default(),
        };
        panel.settings = panel.valid(panel.settings.clone());
        panel
    }

    /// The machine shown.
    #[must_use]
    pub fn machine(&self) -> &Machine {
        &self.machine
    }

    /// The post settings.
    #[must_use]
    pub fn settings(&self) -> &PostSettings {
        &self.settings
    }

    /// Show another machine (from a file, or after an undo); the settings are made valid for
    /// it. Returns the settings when that changed them.
    pub fn set_machine(&mut self, machine: Machine) -> Option<PostSettings> {
        self.machine = machine;
        let valid = self.valid(self.settings.clone());
        (valid != self.settings).then(|| {
            self.settings = valid.clone();
            valid
        })
    }

    /// Draw the tilt axis at `deg` in the schematic (clamped to its travel).
    pub fn set_preview_tilt(&mut self, deg: f64) {
        let range = self
            .machine
            .rotary_names()
            .and_then(|(t, _)| self.machine.axis(t))
            .map_or((0.0, 0.0), |a| (a.min.to_degrees(), a.max.to_degrees()));
        self.view.tilt_deg = if deg.is_finite() {
            deg.clamp(range.0, range.1)
        } else {
            0.0
        };
    }

    /// Replace the settings (made valid for the machine).
    pub fn set_settings(&mut self, settings: PostSettings) {
        self.settings = self.valid(settings);
    }

    /// `s` with a dialect that fits the machine, TCP only where possible, offset in 54..=59.
    fn valid(&self, mut s: PostSettings) -> PostSettings {
        let dialects = dialects_for(&self.machine);
        if !dialects.contains(&s.dialect.as_str())
            && let Some(first) = dialects.first()
        {
            s.dialect = (*first).to_string();
        }
        s.tcp &= tcp_possible(&self.machine, &s.dialect);
        s.work_offset = s.work_offset.clamp(54, 59);
        s
    }

    /// Draw the panel.
    pub fn ui(&mut self, ui: &mut egui::Ui) -> Option<MachinePanelEvent> {
        let mut event = None;
        ui.horizontal(|ui| {
            egui::ComboBox::new("machine_choice", "Machine")
                .selected_text(self.machine.name.clone())
                .show_ui(ui, |ui| {
                    for name in Machine::builtin_names() {
                        if ui
                            .selectable_label(self.machine.name == name, name)
                            .clicked()
                            && let Ok(m) = Machine::builtin(name)
                        {
                            self.set_machine(m);
                            event = Some(MachinePanelEvent::MachineChosen {
                                name: name.to_string(),
                                settings: self.settings.clone(),
                            });
                        }
                    }
                });
            if ui.button("File…").clicked() {
                event = Some(MachinePanelEvent::OpenMachineFile);
            }
        });
        ui.label(egui::RichText::new(&self.machine.description).weak());
        ui.label(kinematics_label(self.machine.kinematics));
        self.axis_table(ui);
        if let Some(e) = self.post_options_ui(ui) {
            event = event.or(Some(e));
        }
        ui.separator();
        if let Some((t, _)) = self.machine.rotary_names() {
            let range = self
                .machine
                .axis(t)
                .map_or(-90.0..=90.0, |a| a.min.to_degrees()..=a.max.to_degrees());
            ui.horizontal(|ui| {
                ui.add(
                    egui::Slider::new(&mut self.view.tilt_deg, range).text(format!(
                        "{t} (deg) · side view along {}",
                        if t == 'A' { 'X' } else { 'Y' }
                    )),
                );
            });
        }
        let size = egui::vec2(
            ui.available_width(),
            ui.available_height().clamp(120.0, 360.0),
        );
        let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
        draw_schematic(ui.painter(), rect, &self.machine, &self.view, ui.visuals());
        event
    }

    fn axis_table(&self, ui: &mut egui::Ui) {
        egui::Grid::new("machine_axes")
            .striped(true)
            .num_columns(6)
            .show(ui, |ui| {
                for h in ["axis", "travel", "velocity", "acceleration", "jerk", "dir"] {
                    ui.label(egui::RichText::new(h).strong());
                }
                ui.end_row();
                for r in axis_rows(&self.machine) {
                    let u = if r.rotary { "deg" } else { "mm" };
                    ui.label(r.axis.to_string());
                    ui.label(format!("{:.0} … {:.0} {u}", r.travel.0, r.travel.1));
                    ui.label(format!("{:.0} {u}/s", r.velocity));
                    ui.label(format!("{:.0} {u}/s²", r.acceleration));
                    ui.label(format!("{:.0} {u}/s³", r.jerk));
                    ui.label(if r.direction < 0.0 { "−" } else { "+" });
                    ui.end_row();
                }
            });
        if self.machine.kinematics != KinematicsKind::ThreeAxis {
            let p = self.machine.rot_point_mm;
            let o = self.machine.tilt_offset_mm;
            ui.label(format!(
                "C centre ({:.1}, {:.1}, {:.1}) mm · tilt axis offset ({:.1}, {:.1}, {:.1}) mm",
                p.x, p.y, p.z, o.x, o.y, o.z
            ));
        }
    }

    fn post_options_ui(&mut self, ui: &mut egui::Ui) -> Option<MachinePanelEvent> {
        let before = self.settings.clone();
        let mut s = before.clone();
        ui.separator();
        ui.horizontal(|ui| {
            egui::ComboBox::new("post_dialect", "Dialect")
                .selected_text(s.dialect.clone())
                .show_ui(ui, |ui| {
                    for name in dialects_for(&self.machine) {
                        ui.selectable_value(&mut s.dialect, name.to_string(), name);
                    }
                });
            egui::ComboBox::new("post_work_offset", "Work offset")
                .selected_text(format!("G{}", s.work_offset))
                .show_ui(ui, |ui| {
                    for g in 54..=59u8 {
                        ui.selectable_value(&mut s.work_offset, g, format!("G{g}"));
                    }
                });
        });
        let possible = tcp_possible(&self.machine, &s.dialect);
        ui.add_enabled(
            possible,
            egui::Checkbox::new(&mut s.tcp, "Tool-centre-point output"),
        )
        .on_disabled_hover_text("needs a 5-axis machine and a dialect with TCP");
        let s = self.valid(s);
        if s == before {
            None
        } else {
            self.settings = s.clone();
            Some(MachinePanelEvent::PostSettingsChanged(s))
        }
    }
}

#[cfg(test)]
mod tests;
