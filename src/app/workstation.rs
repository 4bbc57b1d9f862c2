//! The workstation: owns the document, the viewport state, the log and the background jobs; lays
//! out the panels each frame; applies the commands they return in one place.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use super::command::Command;
use super::document::{Document, Selection};
use super::document_loader::{LoadError, LoadedPart, load_default_part, load_part};
use super::file_dialog::{DialogOutcome, OpenDialog};
use super::job::{Job, JobPoll};
use super::message_log::MessageLog;
use super::panels::grouped;
use super::panels::log_panel::log_ui;
use super::panels::menu_bar::{ViewFlags, menu_bar_ui, shortcuts};
use super::panels::project_tree::project_tree_ui;
use super::panels::properties::properties_ui;
use super::panels::status_bar::{StatusInfo, status_bar_ui};
use super::recent_files::RecentFiles;
use super::theme;
use super::viewport::{ViewportState, viewport_ui};
use crate::diagnostics::Severity;
use crate::render::DataId;

type LoadJob = Job<Result<LoadedPart, LoadError>>;

/// The workstation application.
pub struct Workstation {
    document: Option<Document>,
    viewport: ViewportState,
    log: MessageLog,
    load_job: Option<LoadJob>,
    dialog: OpenDialog,
    recent: RecentFiles,
    started: Instant,
    next_data_id: DataId,
    render_problems: Option<Arc<Mutex<Vec<String>>>>,
    ctx: egui::Context,
}

impl Workstation {
    /// A workstation on `ctx`, drawing through `render_state` when eframe runs on wgpu, opening
    /// `file` at once when given.
    #[must_use]
    pub fn new(
        ctx: &egui::Context,
        render_state: Option<&egui_wgpu::RenderState>,
        file: Option<PathBuf>,
        recent: RecentFiles,
    ) -> Self {
        theme::apply(ctx);
        let mut ws = Self {
            document: None,
            viewport: ViewportState::default(),
            log: MessageLog::default(),
            load_job: None,
            dialog: OpenDialog::default(),
            recent,
            started: Instant::now(),
            next_data_id: 1,
            render_problems: render_state.map(super::viewport::bridge::install),
            ctx: ctx.clone(),
        };
        match render_state {
            Some(rs) => {
                let info = rs.adapter.get_info();
                ws.log_info(format!(
                    "Graphics: {} ({:?}, {:?})",
                    info.name, info.backend, info.device_type
                ));
            }
            None => ws.log.push(
                0.0,
                Severity::Error,
                "No wgpu renderer: the 3D viewport is unavailable",
            ),
        }
        ws.apply(file.map_or(Command::OpenDefaultPart, Command::Open));
        ws
    }

    /// The open document.
    #[must_use]
    pub fn document(&self) -> Option<&Document> {
        self.document.as_ref()
    }

    /// The log.
    #[must_use]
    pub fn log(&self) -> &MessageLog {
        &self.log
    }

    /// Is a file being loaded?
    #[must_use]
    pub fn is_loading(&self) -> bool {
        self.load_job.is_some()
    }

    fn now_s(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    fn log_info(&mut self, text: impl Into<String>) {
        let t = self.now_s();
        self.log.push(t, Severity::Info, text);
    }

    /// Apply one command. The only place where the document and the workstation state change.
    pub fn apply(&mut self, command: Command) {
        match command {
            Command::OpenDialog => {
                let start = self
                    .document
                    .as_ref()
                    .and_then(|d| d.part.path.parent().map(Path::to_path_buf));
                let ctx = self.ctx.clone();
                self.dialog.open(start, move || ctx.request_repaint());
            }
            Command::Open(path) => self.start_load(path),
            Command::OpenDefaultPart => self.start_default_load(),
            Command::CancelJob => {
                if let Some(job) = self.load_job.take() {
                    job.cancel();
                    let t = self.now_s();
                    self.log
                        .push(t, Severity::Warning, format!("{} cancelled", job.label));
                }
            }
            Command::Quit => self.ctx.send_viewport_cmd(egui::ViewportCommand::Close),
            Command::FitAll => self.viewport.fit(self.document.as_ref()),
            Command::StandardView(v) => self.viewport.set_view(v, self.document.as_ref()),
            Command::SetProjection(p) => self.viewport.set_projection(p),
            Command::SetEdges(on) => self.viewport.show_edges = on,
            Command::SetGrid(on) => self.viewport.options.grid = on,
            Command::Select(selection) => {
                if let Some(doc) = &mut self.document {
                    doc.selection = match selection {
                        Selection::Face(i) if i >= doc.part.faces.len() => Selection::Part,
                        s => s,
                    };
                }
            }
            Command::ClearLog => self.log.entries.clear(),
        }
    }

    fn start_load(&mut self, path: PathBuf) {
        if let Some(old) = self.load_job.take() {
            old.cancel();
        }
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        self.log_info(format!("Opening {}", path.display()));
        let ctx = self.ctx.clone();
        let worker_path = path;
        self.load_job = Some(Job::spawn(
            format!("Opening {name}"),
            move |progress| load_part(&worker_path, progress),
            move || ctx.request_repaint(),
        ));
    }

    fn start_default_load(&mut self) {
        if let Some(old) = self.load_job.take() {
            old.cancel();
        }
        self.log_info("Opening the default part (bicubic-hills, embedded)");
        let ctx = self.ctx.clone();
        self.load_job = Some(Job::spawn(
            "Opening the default part",
            load_default_part,
            move || ctx.request_repaint(),
        ));
    }

    /// Collect finished work: the load job, the file dialog, renderer problems.
    fn poll_background(&mut self) {
        if let Some(job) = &self.load_job {
            match job.poll() {
                JobPoll::Running => self.ctx.request_repaint_after(Duration::from_millis(100)),
                JobPoll::Done(result) => {
                    let elapsed = job.started.elapsed().as_secs_f64();
                    self.load_job = None;
                    self.finish_load(result, elapsed);
                }
                JobPoll::Lost => {
                    self.load_job = None;
                    let t = self.now_s();
                    self.log.notify(
                        t,
                        Severity::Error,
                        "Loading failed: the import worker stopped unexpectedly",
                    );
                }
            }
        }
        if self.dialog.is_waiting() {
            self.ctx.request_repaint_after(Duration::from_millis(250));
        }
        match self.dialog.poll() {
            DialogOutcome::Picked(path) => self.apply(Command::Open(path)),
            DialogOutcome::Unavailable => {
                self.log_info(
                    "The system file dialog did not open (no XDG desktop portal?): type the path instead",
                );
            }
            DialogOutcome::Waiting | DialogOutcome::Cancelled => {}
        }
        let problems: Vec<String> = self
            .render_problems
            .as_ref()
            .and_then(|p| p.lock().ok().map(|mut l| std::mem::take(&mut *l)))
            .unwrap_or_default();
        for p in problems {
            let t = self.now_s();
            self.log.push(t, Severity::Error, format!("Viewport: {p}"));
        }
        let now = self.now_s();
        self.log.expire(now);
        if !self.log.toasts.is_empty() {
            self.ctx.request_repaint_after(Duration::from_millis(250));
        }
    }

    fn finish_load(&mut self, result: Result<LoadedPart, LoadError>, elapsed_s: f64) {
        let t = self.now_s();
        match result {
            Ok(part) => {
                for d in &part.diagnostics {
                    self.log
                        .push(t, d.severity, format!("{}: {d}", part.path.display()));
                }
                let summary = format!(
                    "Opened {} ({}, {} triangles) in {elapsed_s:.2} s",
                    part.path.display(),
                    part.format,
                    grouped(part.mesh.triangles.len())
                );
                // The embedded default part has no file to reopen.
                if part.path.is_file()
                    && let Some(e) = self.recent.add(&part.path)
                {
                    self.log.push(t, Severity::Warning, e);
                }
                let id = self.next_data_id;
                self.next_data_id += 2;
                self.document = Some(Document::new(part, id));
                self.viewport.fit_requested = true;
                self.log.push(t, Severity::Info, summary);
            }
            Err(LoadError::Cancelled) => self.log.push(t, Severity::Warning, "Loading cancelled"),
            Err(e) => {
                let kept = if self.document.is_some() {
                    " (the open part is unchanged)"
                } else {
                    ""
                };
                self.log
                    .notify(t, Severity::Error, format!("Could not open {e}{kept}"));
            }
        }
    }

    fn status(&self) -> StatusInfo {
        StatusInfo {
            cursor_mm: self.viewport.hover_point,
            job: self.load_job.as_ref().map(|j| {
                (
                    j.label.clone(),
                    j.progress.fraction(),
                    j.started.elapsed().as_secs_f64(),
                )
            }),
            document: self.document.as_ref().map(|d| {
                format!(
                    "{} · {} triangles",
                    d.part.name,
                    grouped(d.part.mesh.triangles.len())
                )
            }),
        }
    }

    /// Lay out one frame and apply what it asked for.
    pub fn frame_ui(&mut self, ui: &mut egui::Ui) {
        self.poll_background();
        let mut commands = Vec::new();
        let ctx = ui.ctx().clone();
        shortcuts(&ctx, &mut commands);
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .collect()
        });
        if let Some(path) = dropped.into_iter().next() {
            commands.push(Command::Open(path));
        }

        let flags = ViewFlags {
            projection: self.viewport.camera.projection,
            edges: self.viewport.show_edges,
            grid: self.viewport.options.grid,
        };
        egui::Panel::top("menu bar")
            .show(ui, |ui| menu_bar_ui(ui, &self.recent, flags, &mut commands));
        let status = self.status();
        egui::Panel::bottom("status bar")
            .exact_size(26.0)
            .show(ui, |ui| status_bar_ui(ui, &status, &mut commands));
        egui::Panel::bottom("log")
            .resizable(true)
            .default_size(150.0)
            .size_range(60.0..=500.0)
            .show(ui, |ui| {
                log_ui(ui, &self.log, &mut commands);
            });
        egui::Panel::left("project tree")
            .resizable(true)
            .default_size(250.0)
            .size_range(160.0..=500.0)
            .show(ui, |ui| {
                project_tree_ui(ui, self.document.as_ref(), &mut commands);
            });
        egui::Panel::right("properties")
            .resizable(true)
            .default_size(290.0)
            .size_range(180.0..=520.0)
            .show(ui, |ui| {
                properties_ui(ui, self.document.as_ref());
            });
        egui::CentralPanel::no_frame().show(ui, |ui| {
            let rect = ui.available_rect_before_wrap();
            viewport_ui(
                ui,
                &mut self.viewport,
                self.document.as_ref(),
                &mut commands,
            );
            overlays_ui(
                ui,
                rect,
                &self.log,
                ctx.input(|i| !i.raw.hovered_files.is_empty()),
            );
        });
        self.path_field_ui(&ctx, &mut commands);
        for c in commands {
            self.apply(c);
        }
    }

    /// The path field, when there is no native dialog.
    fn path_field_ui(&mut self, ctx: &egui::Context, commands: &mut Vec<Command>) {
        if !self.dialog.path_field_open {
            return;
        }
        let mut open = true;
        let mut submit = false;
        egui::Window::new("Open part")
            .collapsible(false)
            .resizable(false)
            .open(&mut open)
            .show(ctx, |ui| {
                ui.label("Path of a STEP (.stp, .step) or STL file:");
                let edit = ui.add(
                    egui::TextEdit::singleline(&mut self.dialog.path_text)
                        .desired_width(420.0)
                        .hint_text("/path/to/part.stp"),
                );
                if std::mem::take(&mut self.dialog.focus_path_field) {
                    edit.request_focus();
                }
                if edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
                    submit = true;
                }
                ui.horizontal(|ui| {
                    if ui.button("Open").clicked() {
                        submit = true;
                    }
                    if ui.button("Cancel").clicked() {
                        self.dialog.path_field_open = false;
                    }
                });
            });
        if submit && !self.dialog.path_text.trim().is_empty() {
            commands.push(Command::Open(PathBuf::from(self.dialog.path_text.trim())));
            self.dialog.path_field_open = false;
        }
        if !open {
            self.dialog.path_field_open = false;
        }
    }
}

/// Notifications and the drop hint over the viewport.
fn overlays_ui(ui: &mut egui::Ui, rect: egui::Rect, log: &MessageLog, files_hovered: bool) {
    if files_hovered {
        ui.painter()
            .rect_filled(rect, 0.0, egui::Color32::from_black_alpha(140));
        ui.painter().text(
            rect.center(),
            egui::Align2::CENTER_CENTER,
            "Drop a STEP or STL file to open it",
            egui::FontId::proportional(22.0),
            egui::Color32::WHITE,
        );
    }
    let mut y = rect.top() + 12.0;
    for toast in log.toasts.iter().rev().take(4) {
        let colour = match toast.severity {
            Severity::Error => theme::ERROR,
            Severity::Warning => theme::WARNING,
            Severity::Info => theme::ACCENT,
        };
        let area = egui::Area::new(egui::Id::unique(("toast", toast.until_s.to_bits())))
            .fixed_pos(egui::pos2(rect.right() - 12.0, y))
            .pivot(egui::Align2::RIGHT_TOP)
            .order(egui::Order::Foreground)
            .interactable(false);
        let response = area.show(ui.ctx(), |ui| {
            egui::Frame::popup(ui.style())
                .stroke(egui::Stroke::new(1.0, colour))
                .show(ui, |ui| {
                    ui.set_max_width(440.0);
                    let title = match toast.severity {
                        Severity::Error => "Error",
                        Severity::Warning => "Warning",
                        Severity::Info => "Note",
                    };
                    ui.label(egui::RichText::new(title).strong().color(colour));
                    ui.add(egui::Label::new(&toast.text).wrap());
                });
        });
        y += response.response.rect.height() + 8.0;
    }
}

impl eframe::App for Workstation {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame_ui(ui);
    }

    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        egui::Color32::from_rgb(30, 32, 36).to_normalized_gamma_f32()
    }
}
