//! The panel's widgets, in three columns as on a control: the DRO, codes and alarms; the
//! machine controls (axis buttons, increments, handwheel, overrides, cycle buttons, keys); the
//! MDI line and the program.

use std::f32::consts::TAU;

use egui::{Color32, RichText, Sense, Stroke, vec2};

use super::keys::KEY_HELP;
use super::{OperatorPanel, PanelMode, PanelSource, unit_of, value_of};
use crate::control::{Action, OverrideKind, RunState, Snapshot, Spindle};

/// Detents per handwheel turn.
const DETENTS_PER_TURN: f32 = 100.0;
/// Increments offered (mm on linear axes, ° on rotaries) and their handwheel scale.
const INCREMENTS: [(f64, &str); 4] = [
    (0.001, "0.001 (×1)"),
    (0.01, "0.01 (×10)"),
    (0.1, "0.1 (×100)"),
    (1.0, "1"),
];
const CLOCKS: [f64; 3] = [1.0, 10.0, 100.0];
const GREEN: Color32 = Color32::from_rgb(40, 150, 60);
const RED: Color32 = Color32::from_rgb(200, 30, 30);

impl OperatorPanel {
    pub(super) fn panel_ui(
        &mut self,
        ui: &mut egui::Ui,
        snap: &Snapshot,
        source: &PanelSource<'_>,
    ) {
        self.top_bar(ui, snap, source);
        ui.separator();
        ui.columns(3, |cols| {
            self.dro_ui(&mut cols[0], snap);
            self.controls_ui(&mut cols[1], snap);
            self.mdi_ui(&mut cols[2]);
            cols[2].separator();
            self.program_ui(&mut cols[2], snap, source);
        });
    }

    fn top_bar(&mut self, ui: &mut egui::Ui, snap: &Snapshot, source: &PanelSource<'_>) {
        ui.horizontal_wrapped(|ui| {
            if ui
                .button("Power on")
                .on_hover_text(
                    "Rebuild the control from the project now (machine, stock, tool, work offset)",
                )
                .clicked()
            {
                self.build(source);
                return;
            }
            ui.label("Mode");
            for m in PanelMode::ALL {
                let text = RichText::new(m.label()).strong();
                if ui.selectable_label(self.mode == m, text).clicked() && self.mode != m {
                    self.select_mode(m);
                }
            }
            ui.separator();
            ui.label("Clock");
            for f in CLOCKS {
                if ui
                    .selectable_label(self.clock == f, format!("×{f:.0}"))
                    .on_hover_text("Simulated seconds per real second")
                    .clicked()
                {
                    self.clock = f;
                }
            }
            ui.separator();
            ui.label(format!("{:?}", snap.state));
            ui.label(format!("t = {:.3} s", snap.time_s));
            ui.label(format!("advance {:.3} ms/frame", self.advance_s * 1e3))
                .on_hover_text("Wall time the last frame's Control::advance took");
            ui.separator();
            self.camera_buttons(ui);
        });
        if let Some(m) = &self.message {
            ui.colored_label(ui.visuals().warn_fg_color, m);
        }
    }

    fn dro_ui(&mut self, ui: &mut egui::Ui, snap: &Snapshot) {
        let Some(c) = &self.control else { return };
        ui.heading("Position");
        egui::Grid::new("talas op dro")
            .striped(true)
            .spacing(vec2(14.0, 4.0))
            .show(ui, |ui| {
                for h in ["Axis", "Machine", "Work", "To go", ""] {
                    ui.label(RichText::new(h).strong());
                }
                ui.end_row();
                for (i, &a) in snap.axes.iter().enumerate() {
                    let u = unit_of(c, a);
                    let big = |v: f64| RichText::new(format!("{v:9.3} {u}")).monospace().size(17.0);
                    ui.label(RichText::new(a.to_string()).monospace().size(17.0).strong());
                    ui.label(big(value_of(snap, &snap.machine_position, a)));
                    ui.label(big(value_of(snap, &snap.work_position, a)));
                    ui.label(big(value_of(snap, &snap.distance_to_go, a)));
                    let homed = snap.homed.get(i).copied().unwrap_or(false);
                    ui.label(if homed { "homed" } else { "not homed" });
                    ui.end_row();
                }
            });
        ui.add_space(6.0);
        ui.label(format!(
            "Feed {:.0} mm/min (programmed {:.0} mm/min)",
            snap.feed_actual_mm_per_min, snap.feed_programmed_mm_per_min
        ));
        ui.label(format!(
            "Spindle {:.0} rpm (programmed {:.0} rpm)",
            snap.spindle_actual_rpm, snap.spindle_programmed_rpm
        ));
        ui.label(format!(
            "Increment {} mm / °   Removed {:.1} mm³",
            snap.increment, snap.removed_volume_mm3
        ));
        if let Some(c) = &snap.cycle {
            // The canned cycle's move under way: which hole, which peck, how deep.
            ui.label(RichText::new(format!("Cycle: {}", c.describe())).strong());
        }
        ui.separator();
        ui.label(RichText::new("Active codes").strong());
        ui.label(RichText::new(snap.active_codes.join(" ")).monospace());
        ui.separator();
        alarms_ui(ui, snap);
    }

    fn controls_ui(&mut self, ui: &mut egui::Ui, snap: &Snapshot) {
        ui.horizontal(|ui| {
            if ui.button("Home all").on_hover_text("Home (key)").clicked() {
                self.mode = PanelMode::Ref;
                self.act(Action::Home);
            }
            ui.label("Jog feed");
            let r = ui.add(
                egui::DragValue::new(&mut self.jog_feed)
                    .range(1.0..=20000.0)
                    .suffix(" mm/min"),
            );
            if r.changed() {
                self.act(Action::JogFeed(self.jog_feed));
            }
        });
        self.axis_buttons(ui);
        ui.horizontal_wrapped(|ui| {
            ui.label("Increment (mm / °)");
            for (inc, label) in INCREMENTS {
                if ui
                    .selectable_label((snap.increment - inc).abs() < 1e-12, label)
                    .clicked()
                {
                    self.act(Action::SetIncrement(inc));
                }
            }
        });
        self.handwheel_ui(ui, snap);
        self.overrides_ui(ui, snap);
        ui.separator();
        self.cycle_ui(ui, snap);
        ui.separator();
        ui.label(RichText::new("Keys").strong());
        egui::Grid::new("talas op keys").show(ui, |ui| {
            for (k, what) in KEY_HELP {
                ui.label(RichText::new(*k).monospace());
                ui.label(*what);
                ui.end_row();
            }
        });
    }

    /// A − and a + button per axis (and the tool axis `T` on 5-axis machines): held (JOG)
    /// they jog, clicked (INC) they move one increment, in MPG they select the handwheel's
    /// axis.
    fn axis_buttons(&mut self, ui: &mut egui::Ui) {
        let Some(axes) = self.control.as_ref().map(|c| {
            let mut axes: Vec<char> = c.machine().axes.iter().map(|a| a.name).collect();
            // The 5-axis machines also jog along the tool axis (pseudo-axis T).
            if c.machine().rotary_names().is_some() {
                axes.push(crate::control::tool_axis::TOOL_AXIS);
            }
            axes
        }) else {
            return;
        };
        egui::Grid::new("talas op axes").show(ui, |ui| {
            for a in axes {
                for dir in [-1.0, 1.0] {
                    let sign = if dir < 0.0 { '−' } else { '+' };
                    let r = ui.add(
                        egui::Button::new(RichText::new(format!("{a}{sign}")).size(16.0))
                            .min_size(vec2(52.0, 30.0))
                            .sense(Sense::click_and_drag()),
                    );
                    self.axis_button(&r, a, dir);
                }
                ui.end_row();
            }
        });
    }

    fn axis_button(&mut self, r: &egui::Response, axis: char, dir: f64) {
        let down = r.is_pointer_button_down_on();
        match self.mode {
            PanelMode::Jog => {
                if down && self.jog_held.is_none() {
                    self.jog_press(axis, dir);
                    self.jog_button = self.jog_held;
                } else if !down && self.jog_button == Some((axis, dir)) {
                    self.jog_button = None;
                    self.release_jog();
                }
            }
            _ if r.clicked() => self.jog_press(axis, dir),
            _ => {}
        }
    }

    /// The handwheel: dragged round or turned with the mouse wheel, in detents.
    fn handwheel_ui(&mut self, ui: &mut egui::Ui, snap: &Snapshot) {
        ui.horizontal(|ui| {
            let (rect, r) = ui.allocate_exact_size(vec2(120.0, 120.0), Sense::drag());
            let c = rect.center();
            let detent = TAU / DETENTS_PER_TURN;
            if r.dragged()
                && let Some(p) = r.interact_pointer_pos()
            {
                let prev = p - r.drag_delta();
                let a1 = (p - c).angle();
                let a0 = (prev - c).angle();
                let mut d = a1 - a0;
                if d > TAU / 2.0 {
                    d -= TAU;
                } else if d < -TAU / 2.0 {
                    d += TAU;
                }
                self.wheel_rest_rad += d;
            }
            if r.hovered() {
                let notches: f32 = ui.input(|i| {
                    i.events
                        .iter()
                        .filter_map(|e| match e {
                            egui::Event::MouseWheel { delta, .. } if delta.y != 0.0 => {
                                Some(delta.y.signum())
                            }
                            _ => None,
                        })
                        .sum()
                });
                self.wheel_rest_rad += detent * notches;
            }
            let n = (self.wheel_rest_rad / detent).trunc();
            if n != 0.0 {
                self.wheel_rest_rad -= n * detent;
                self.turn_wheel(n as i32);
            }
            draw_wheel(ui, rect, self.wheel_angle_rad, self.mode == PanelMode::Mpg);
            ui.vertical(|ui| {
                ui.label(RichText::new("Handwheel").strong());
                ui.label(format!("{} detents/turn", DETENTS_PER_TURN));
                ui.label(format!("{} mm or ° per detent", snap.increment));
                for a in snap.axes.clone() {
                    ui.radio_value(&mut self.wheel_axis, a, format!("axis {a}"));
                }
            });
        });
    }

    /// Turn the handwheel by `detents` (MPG mode only).
    pub(super) fn turn_wheel(&mut self, detents: i32) {
        if self.mode != PanelMode::Mpg {
            self.message = Some("Select MPG to move an axis with the handwheel".into());
            return;
        }
        self.wheel_angle_rad += detents as f32 * TAU / DETENTS_PER_TURN;
        let axis = self.wheel_axis;
        self.act(Action::Mpg { axis, detents });
    }

    fn overrides_ui(&mut self, ui: &mut egui::Ui, snap: &Snapshot) {
        let [mut feed, rapid, mut spindle] = snap.overrides_pct;
        egui::Grid::new("talas op overrides").show(ui, |ui| {
            ui.label("Feed override");
            if ui
                .add(egui::Slider::new(&mut feed, 0.0..=150.0).suffix(" %"))
                .changed()
            {
                self.act(Action::Override(OverrideKind::Feed, feed));
            }
            ui.end_row();
            ui.label("Rapid override");
            ui.horizontal(|ui| {
                for v in [0.0, 25.0, 50.0, 100.0] {
                    if ui
                        .selectable_label((rapid - v).abs() < 1e-9, format!("{v:.0} %"))
                        .clicked()
                    {
                        self.act(Action::Override(OverrideKind::Rapid, v));
                    }
                }
            });
            ui.end_row();
            ui.label("Spindle override");
            if ui
                .add(egui::Slider::new(&mut spindle, 50.0..=120.0).suffix(" %"))
                .changed()
            {
                self.act(Action::Override(OverrideKind::Spindle, spindle));
            }
            ui.end_row();
        });
    }

    fn cycle_ui(&mut self, ui: &mut egui::Ui, snap: &Snapshot) {
        ui.horizontal_wrapped(|ui| {
            let big = |t: &str, fill: Color32| {
                egui::Button::new(RichText::new(t).strong().color(Color32::WHITE))
                    .fill(fill)
                    .min_size(vec2(84.0, 34.0))
            };
            if ui.add(big("Cycle start", GREEN)).clicked() {
                let a = if snap.state == RunState::Held {
                    Action::Resume
                } else {
                    Action::CycleStart
                };
                self.act(a);
            }
            if ui
                .add(big("Feed hold", Color32::from_rgb(190, 140, 20)))
                .clicked()
            {
                self.act(Action::FeedHold);
            }
            if ui.button("Stop").clicked() {
                self.jog_held = None;
                self.act(Action::Stop);
            }
            if ui.button("Reset").clicked() {
                self.jog_held = None;
                self.act(Action::Reset);
            }
            if ui.add(big("E-STOP", RED)).on_hover_text("F1").clicked() {
                self.jog_held = None;
                self.act(Action::EStop);
            }
        });
        ui.horizontal_wrapped(|ui| {
            ui.label("Spindle");
            for (t, s) in [
                ("CW", Spindle::Cw),
                ("Stop", Spindle::Stop),
                ("CCW", Spindle::Ccw),
            ] {
                if ui.button(t).clicked() {
                    self.act(Action::Spindle(s));
                }
            }
        });
        ui.horizontal_wrapped(|ui| {
            if ui
                .checkbox(&mut self.single_block, "Single block")
                .changed()
            {
                self.act(Action::SingleBlock(self.single_block));
            }
            if ui
                .checkbox(&mut self.optional_stop, "Optional stop M1")
                .changed()
            {
                self.act(Action::OptionalStop(self.optional_stop));
            }
            if ui
                .checkbox(&mut self.block_delete, "Block delete /")
                .changed()
            {
                self.act(Action::BlockDelete(self.block_delete));
            }
        });
    }

    fn mdi_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("MDI line");
        ui.horizontal(|ui| {
            let r = ui.add(
                egui::TextEdit::singleline(&mut self.mdi)
                    .id(egui::Id::unique("talas op mdi"))
                    .hint_text("G-code line, Enter runs it")
                    .desired_width(220.0)
                    .font(egui::TextStyle::Monospace),
            );
            let enter = r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            if ui.button("Send").clicked() || enter {
                self.send_mdi();
            }
        });
        ui.label(RichText::new("History (click to recall)").small());
        let mut recall = None;
        for h in self.history.iter().rev().take(8) {
            if ui
                .selectable_label(false, RichText::new(h).monospace())
                .clicked()
            {
                recall = Some(h.clone());
            }
        }
        if let Some(h) = recall {
            self.mdi = h;
        }
    }

    fn program_ui(&mut self, ui: &mut egui::Ui, snap: &Snapshot, source: &PanelSource<'_>) {
        ui.heading("Program");
        ui.horizontal_wrapped(|ui| {
            let posted = source.posted;
            let hover = posted.as_ref().map_or_else(
                || "Post the active operation first".to_string(),
                |(n, _)| format!("Load '{n}' into AUTO"),
            );
            if ui
                .add_enabled(posted.is_some(), egui::Button::new("Load posted program"))
                .on_hover_text(hover)
                .on_disabled_hover_text("Post the active operation first")
                .clicked()
                && let Some((name, text)) = posted
            {
                self.load_program(name.to_string(), text.to_string());
            }
            if ui.button("Open G-code file…").clicked() {
                self.choose_file();
            }
        });
        ui.horizontal(|ui| {
            ui.add(egui::DragValue::new(&mut self.run_from).range(1..=self.program.len().max(1)));
            if ui.button("Run from line").clicked() {
                self.act(Action::RunFromLine(self.run_from));
            }
        });
        ui.label(format!(
            "{} · {} lines",
            if self.program_name.is_empty() {
                "none loaded"
            } else {
                &self.program_name
            },
            self.program.len()
        ));
        self.program_lines(ui, snap);
    }

    /// The program's lines, the current one highlighted and kept in view.
    fn program_lines(&mut self, ui: &mut egui::Ui, snap: &Snapshot) {
        let current = if snap.mode == crate::control::Mode::Auto {
            snap.line
        } else {
            None
        };
        let row_h = ui.text_style_height(&egui::TextStyle::Monospace) + ui.spacing().item_spacing.y;
        let mut area = egui::ScrollArea::vertical()
            .id_salt("talas op program")
            .max_height(ui.available_height().max(120.0))
            .auto_shrink([false, false]);
        if current != self.last_line {
            self.last_line = current;
            if let Some(l) = current {
                area = area.vertical_scroll_offset(row_h * (l.saturating_sub(5)) as f32);
            }
        }
        area.show_rows(ui, row_h, self.program.len(), |ui, range| {
            for i in range {
                let text = RichText::new(format!("{:>5}  {}", i + 1, self.program[i])).monospace();
                if current == Some(i + 1) {
                    ui.label(
                        text.background_color(ui.visuals().selection.bg_fill)
                            .strong(),
                    );
                } else {
                    ui.label(text);
                }
            }
        });
    }
}

fn alarms_ui(ui: &mut egui::Ui, snap: &Snapshot) {
    ui.label(RichText::new(format!("Alarms ({})", snap.alarms.len())).strong());
    if snap.alarms.is_empty() {
        ui.label("No alarms");
    }
    for a in &snap.alarms {
        ui.colored_label(
            ui.visuals().error_fg_color,
            format!("A{:03} at {:.3} s: {}", a.code, a.t_s, a.text),
        );
    }
}

/// The handwheel: a disc with a tick per detent, turned by `angle`, and its grip.
fn draw_wheel(ui: &egui::Ui, rect: egui::Rect, angle: f32, active: bool) {
    let p = ui.painter();
    let c = rect.center();
    let r = rect.width() * 0.5 - 2.0;
    let fg = if active {
        ui.visuals().strong_text_color()
    } else {
        ui.visuals().weak_text_color()
    };
    p.circle(c, r, ui.visuals().extreme_bg_color, Stroke::new(1.5, fg));
    for k in 0..DETENTS_PER_TURN as usize {
        let a = angle + k as f32 * TAU / DETENTS_PER_TURN;
        let d = vec2(a.cos(), a.sin());
        let inner = if k % 10 == 0 { r - 10.0 } else { r - 5.0 };
        p.line_segment([c + d * inner, c + d * r], Stroke::new(1.0, fg));
    }
    let g = vec2(angle.cos(), angle.sin()) * (r * 0.55);
    p.circle_filled(c + g, 9.0, fg);
    p.circle_stroke(c, r * 0.3, Stroke::new(1.0, fg));
}
