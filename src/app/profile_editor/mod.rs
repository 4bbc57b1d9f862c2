//! The profile editor: a 2D section profile typed into a point table or clicked on a canvas,
//! the path of a ball-ended electrode (or ball end mill) of radius R along it, and the gouges
//! of the per-point method, all from [`crate::profile`].
//!
//! - [`rows`]: the point table as typed text and the input rules, a message per bad row.
//! - [`canvas`]: the view (zoom, pan, grid, snap), the drawing and the mouse.
//! - `panel`: the table, the results and the list of flags (a click centres the view on one),
//!   the G-code settings.
//! - `files`: import and export of profiles (CSV, DXF, SVG) and of the G-code.
//!
//! Every change (a typed cell, a moved point, a new radius) starts the computation on a worker
//! thread; the last finished result stays on screen until the next one arrives, so dragging a
//! point or the radius slider updates the path live without holding up the frame.

pub mod canvas;
mod feature;
mod files;
mod panel;
pub mod rows;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use glam::DVec2;

use super::file_chooser::FileChooser;
use super::job::{Job, JobSlot};
use crate::profile::{
    ProfileError, ProfileOptions, ProfilePlane, ProfileResult, Side, compute_opt,
};
use canvas::{CanvasAction, Drawn, View};
use rows::{Checked, Row, check_rows};

/// The result of one computation and how long it took, s.
type Outcome = (Result<ProfileResult, ProfileError>, f64);

/// A finished computation.
#[derive(Debug)]
pub struct Computed {
    /// The edit it was made for.
    revision: u64,
    /// The result, or why there is none.
    pub outcome: Result<ProfileResult, ProfileError>,
    /// Computing time, s.
    pub elapsed_s: f64,
}

/// What a file chooser of the editor is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FileAction {
    Import,
    ExportProfile,
    ExportGcode,
}

/// G-code settings.
#[derive(Clone, Debug, PartialEq)]
struct GcodeSettings {
    dialect: String,
    plane: ProfilePlane,
    feed_mm_per_min: f64,
}

/// The profile editor's state.
pub struct ProfileEditor {
    /// The window is shown.
    pub open: bool,
    rows: Vec<Row>,
    closed: bool,
    function_rule: bool,
    side: Side,
    radius_mm: f64,
    checked: Checked,
    revision: u64,
    computed: Option<Computed>,
    job: JobSlot<Outcome, u64>,
    view: View,
    canvas_rect: Option<egui::Rect>,
    snap: bool,
    electrodes: bool,
    naive: bool,
    selected_row: Option<usize>,
    selected_flag: Option<usize>,
    dragging: Option<usize>,
    gcode: GcodeSettings,
    chooser: Option<(FileAction, FileChooser)>,
    /// The last import or export: what was done, or why not.
    note: Option<Result<String, String>>,
    file: Option<PathBuf>,
}

impl Default for ProfileEditor {
    fn default() -> Self {
        Self::new()
    }
}

/// The profile the editor opens with: flats, a hill, a V notch and a narrow slot (y = f(x)).
const EXAMPLE: [(f64, f64); 14] = [
    (-12.0, 3.0),
    (-10.0, 3.0),
    (-8.0, 4.5),
    (-6.0, 5.0),
    (-4.0, 4.5),
    (-2.0, 3.0),
    (0.0, 3.0),
    (1.5, 0.5),
    (3.0, 3.0),
    (5.0, 3.0),
    (6.0, 0.8),
    (6.8, 0.8),
    (7.8, 3.0),
    (10.0, 3.0),
];

impl ProfileEditor {
    /// The editor on the example profile (closed window), electrode radius 1.5 mm.
    #[must_use]
    pub fn new() -> Self {
        let rows = EXAMPLE
            .iter()
            .map(|&(x, y)| Row::at(DVec2::new(x, y)))
            .collect();
        let mut ed = Self {
            open: false,
            rows,
            closed: false,
            function_rule: true,
            side: Side::Above,
            radius_mm: 1.5,
            checked: Checked::default(),
            revision: 0,
            computed: None,
            job: JobSlot::default(),
            view: View::default(),
            canvas_rect: None,
            snap: true,
            electrodes: true,
            naive: true,
            selected_row: None,
            selected_flag: None,
            dragging: None,
            gcode: GcodeSettings {
                dialect: "linuxcnc".into(),
                plane: ProfilePlane::G18,
                feed_mm_per_min: 100.0,
            },
            chooser: None,
            note: None,
            file: None,
        };
        ed.changed();
        ed
    }

    /// The editor with an empty table.
    #[must_use]
    pub fn empty() -> Self {
        let mut ed = Self::new();
        ed.set_rows(Vec::new());
        ed
    }

    /// The rows of the point table.
    #[must_use]
    pub fn rows(&self) -> &[Row] {
        &self.rows
    }

    /// Replace the table.
    pub fn set_rows(&mut self, rows: Vec<Row>) {
        self.rows = rows;
        self.selected_row = None;
        self.view.fit = true;
        self.changed();
    }

    /// The table as checked by the input rules.
    #[must_use]
    pub fn checked(&self) -> &Checked {
        &self.checked
    }

    /// Electrode radius, mm.
    #[must_use]
    pub fn radius_mm(&self) -> f64 {
        self.radius_mm
    }

    /// Set the electrode radius, mm (values outside (0, 10⁶] mm are refused by the engine and
    /// reported).
    pub fn set_radius_mm(&mut self, r: f64) {
        self.radius_mm = r;
        self.changed();
    }

    /// The last finished computation (possibly for an earlier edit while one runs).
    #[must_use]
    pub fn computed(&self) -> Option<&Computed> {
        self.computed.as_ref()
    }

    /// The last finished result, when it succeeded.
    #[must_use]
    pub fn result(&self) -> Option<&ProfileResult> {
        self.computed.as_ref().and_then(|c| c.outcome.as_ref().ok())
    }

    /// Is the shown result behind the table (a computation running or due)?
    #[must_use]
    pub fn is_computing(&self) -> bool {
        self.job.is_running()
            || (self.checked.profile.is_some()
                && self
                    .computed
                    .as_ref()
                    .is_none_or(|c| c.revision != self.revision))
    }

    /// Is the shown result the one for the table as it is?
    #[must_use]
    pub fn is_current(&self) -> bool {
        self.computed
            .as_ref()
            .is_some_and(|c| c.revision == self.revision)
    }

    /// The view of the canvas.
    #[must_use]
    pub fn view(&self) -> &View {
        &self.view
    }

    /// Where world point `p` (mm) is on the screen, once the canvas has been drawn.
    #[must_use]
    pub fn screen_of(&self, p: DVec2) -> Option<egui::Pos2> {
        self.canvas_rect.map(|r| self.view.to_screen(r, p))
    }

    /// The selected row (0-based).
    #[must_use]
    pub fn selected_row(&self) -> Option<usize> {
        self.selected_row
    }

    /// The flag picked in the list.
    #[must_use]
    pub fn selected_flag(&self) -> Option<usize> {
        self.selected_flag
    }

    /// The last import or export message.
    #[must_use]
    pub fn note(&self) -> Option<&Result<String, String>> {
        self.note.as_ref()
    }

    /// The table, the closure or the rule changed: check the rows again and recompute.
    fn changed(&mut self) {
        self.checked = check_rows(&self.rows, self.closed, self.function_rule);
        self.revision += 1;
        self.selected_flag = None;
        if self.selected_row.is_some_and(|r| r >= self.rows.len()) {
            self.selected_row = None;
        }
    }

    /// Collect a finished computation and start the next one when the table has moved on
    /// (one at a time: edits made meanwhile are folded into the next).
    fn poll(&mut self, ctx: &egui::Context) {
        if self.job.is_running() {
            let Some(done) = self.job.poll() else {
                ctx.request_repaint_after(Duration::from_millis(15));
                return;
            };
            self.computed = Some(match done.result {
                Some((outcome, elapsed_s)) => Computed {
                    revision: done.key,
                    outcome,
                    elapsed_s,
                },
                None => Computed {
                    revision: done.key,
                    outcome: Err(ProfileError {
                        file: "profile".into(),
                        place: "computation".into(),
                        message: "the worker stopped without a result".into(),
                    }),
                    elapsed_s: 0.0,
                },
            });
        }
        if self
            .computed
            .as_ref()
            .is_some_and(|c| c.revision == self.revision)
        {
            return;
        }
        let Some(profile) = self.checked.profile.clone() else {
            // Nothing to compute until the rows are fixed; the old result is not shown.
            self.computed = None;
            return;
        };
        let opts = ProfileOptions::new(self.radius_mm, self.side);
        let job = Job::start("Profile path", ctx, move |_| {
            let t = Instant::now();
            let r = compute_opt(&profile, &opts);
            (r, t.elapsed().as_secs_f64())
        });
        self.job.start(self.revision, job);
        ctx.request_repaint_after(Duration::from_millis(15));
    }

    /// Step the background computation until the shown result is current (tests, scripts);
    /// false when it takes longer than `timeout`.
    pub fn wait(&mut self, ctx: &egui::Context, timeout: Duration) -> bool {
        let start = Instant::now();
        while self.is_computing() {
            if start.elapsed() > timeout {
                return false;
            }
            self.poll(ctx);
            std::thread::sleep(Duration::from_millis(2));
        }
        true
    }

    /// The window (when open) and its file chooser.
    pub fn window(&mut self, ctx: &egui::Context) {
        if !self.open {
            return;
        }
        let mut open = self.open;
        egui::Window::new("Profile editor · ball electrode (EDM)")
            .id(egui::Id::unique("talas profile editor"))
            .open(&mut open)
            .default_pos([30.0, 40.0])
            .default_size([1480.0, 860.0])
            .min_size([700.0, 420.0])
            .resizable(true)
            .show(ctx, |ui| self.ui(ui));
        self.open = open;
    }

    /// The editor's contents.
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        self.poll(&ctx);
        self.toolbar_ui(ui);
        ui.separator();
        ui.horizontal_top(|ui| {
            let h = ui.available_height();
            ui.allocate_ui_with_layout(
                egui::vec2(400.0, h),
                egui::Layout::top_down(egui::Align::Min),
                |ui| {
                    ui.set_width(400.0);
                    ui.set_min_height(h);
                    self.panel_ui(ui);
                },
            );
            ui.separator();
            self.canvas(ui);
        });
        self.keys(ui);
        self.files_ui(&ctx);
    }

    fn canvas(&mut self, ui: &mut egui::Ui) {
        let rect = ui.available_rect_before_wrap();
        self.canvas_rect = Some(rect);
        let action = {
            let drawn = Drawn {
                points: &self.checked.points,
                closed: self.closed,
                result: self.computed.as_ref().and_then(|c| c.outcome.as_ref().ok()),
                electrodes: self.electrodes,
                naive: self.naive,
                selected_row: self.selected_row,
                selected_flag: self.selected_flag,
            };
            canvas::canvas_ui(ui, &mut self.view, self.snap, &drawn, &mut self.dragging)
        };
        if let Some(a) = action {
            self.act(a);
        }
    }

    /// Apply a canvas action to the table.
    fn act(&mut self, action: CanvasAction) {
        match action {
            CanvasAction::Append(p) => {
                self.rows.push(Row::at(p));
                self.selected_row = Some(self.rows.len() - 1);
            }
            CanvasAction::Insert(row, p) => {
                let at = row.min(self.rows.len());
                self.rows.insert(at, Row::at(p));
                self.selected_row = Some(at);
            }
            CanvasAction::Move(row, p) => {
                if let Some(r) = self.rows.get_mut(row) {
                    let bulge = std::mem::take(&mut r.bulge);
                    *r = Row {
                        bulge,
                        ..Row::at(p)
                    };
                }
                self.selected_row = Some(row);
            }
            CanvasAction::Delete(row) => self.delete_row(row),
            CanvasAction::Select(row) => {
                self.selected_row = Some(row);
                return;
            }
        }
        self.changed();
    }

    fn delete_row(&mut self, row: usize) {
        if row < self.rows.len() {
            self.rows.remove(row);
            self.selected_row = None;
        }
    }

    /// Delete removes the selected point (unless a text field has the keys).
    fn keys(&mut self, ui: &egui::Ui) {
        if ui.ctx().text_edit_focused() || !ui.ui_contains_pointer() {
            return;
        }
        let delete = ui.input_mut(|i| {
            i.consume_key(egui::Modifiers::NONE, egui::Key::Delete)
                | i.consume_key(egui::Modifiers::NONE, egui::Key::Backspace)
        });
        if delete && let Some(row) = self.selected_row {
            self.delete_row(row);
            self.changed();
        }
    }

    /// Centre the view on flag `k` of the shown result and select it.
    pub fn pick_flag(&mut self, k: usize) {
        if let Some(f) = self.result().and_then(|r| r.flags.get(k)).copied() {
            self.view.centre = f.deepest;
            self.selected_flag = Some(k);
            self.selected_row = Some(f.point_index);
        }
    }

    fn toolbar_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            if ui
                .button("Import…")
                .on_hover_text("A profile: CSV, DXF or SVG")
                .clicked()
            {
                self.choose(FileAction::Import);
            }
            if ui.button("Export profile…").clicked() {
                self.choose(FileAction::ExportProfile);
            }
            let can_post = self.is_current() && self.result().is_some_and(|r| !r.paths.is_empty());
            if ui
                .add_enabled(can_post, egui::Button::new("Export G-code…"))
                .on_disabled_hover_text("Needs a computed path")
                .clicked()
            {
                self.choose(FileAction::ExportGcode);
            }
            ui.separator();
            if ui.button("Clear").clicked() {
                self.set_rows(Vec::new());
            }
            if ui.button("Fit view").clicked() {
                self.view.fit = true;
            }
            ui.checkbox(&mut self.snap, "Snap to grid");
            ui.checkbox(&mut self.electrodes, "Electrode");
            ui.checkbox(&mut self.naive, "Per-point path");
            ui.separator();
            let mut again = false;
            again |= ui
                .checkbox(&mut self.closed, "Closed")
                .on_hover_text("The last point joins the first")
                .changed();
            again |= ui
                .checkbox(&mut self.function_rule, "Rule y = f(x)")
                .on_hover_text(
                    "The per-point method's input rule: x runs one way and never repeats \
                     (no vertical walls). Off: any open or closed contour.",
                )
                .changed();
            if again {
                self.changed();
            }
        });
        self.radius_ui(ui);
        match &self.note {
            Some(Ok(text)) => {
                ui.weak(text);
            }
            Some(Err(text)) => {
                ui.colored_label(super::theme::ERROR, text);
            }
            None => {}
        }
    }

    fn radius_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let label = ui.label("Electrode radius R");
            let mut r = self.radius_mm;
            let typed = super::number_field::NumberField::new("profile radius", &mut r)
                .unit("mm")
                .range(1e-6..=1e6)
                .decimals(6)
                .labelled_by(label.id)
                .show(ui);
            let top = self
                .checked
                .profile
                .as_ref()
                .map_or(20.0, |p| p.extent_mm().max(1.0))
                .max(r);
            let low = r.min(0.01);
            let slid = ui
                .add(
                    egui::Slider::new(&mut r, low..=top)
                        .logarithmic(true)
                        .suffix(" mm")
                        .show_value(false),
                )
                .on_hover_text("Drag: the path follows live")
                .changed();
            if (typed || slid) && r != self.radius_mm {
                self.set_radius_mm(r);
            }
            ui.separator();
            ui.label("Free side");
            let before = self.side;
            egui::ComboBox::from_id_salt("profile side")
                .selected_text(side_name(self.side))
                .show_ui(ui, |ui| {
                    for s in [
                        Side::Above,
                        Side::Left,
                        Side::Right,
                        Side::Outside,
                        Side::Inside,
                    ] {
                        ui.selectable_value(&mut self.side, s, side_name(s));
                    }
                });
            if before != self.side {
                self.changed();
            }
        });
    }
}

fn side_name(s: Side) -> &'static str {
    match s {
        Side::Above => "above (outside if closed)",
        Side::Left => "left of travel",
        Side::Right => "right of travel",
        Side::Outside => "outside",
        Side::Inside => "inside",
    }
}
