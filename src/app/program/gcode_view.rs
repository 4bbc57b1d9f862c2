//! The G-code pane: the posted program with line numbers and syntax colouring, a selected
//! line (synced with the viewport by the caller), and a search box.
//!
//! Only the visible rows are laid out ([`egui::ScrollArea::show_rows`]), and a line is
//! tokenized the first time it is shown, so a program of a million lines scrolls as fast as a
//! short one.

mod syntax;

pub use syntax::{Token, TokenKind, tokenize};

use super::super::theme;
use egui::text::{LayoutJob, TextFormat};
use egui::{Color32, FontId, Sense};

/// What the user did in the pane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GcodeEvent {
    /// A line was clicked, or stepped to with the Up/Down arrows (0-based); it is now the
    /// selected line.
    LineClicked(usize),
}

/// State of the G-code pane.
pub struct GcodeView {
    text: String,
    /// Byte offset of the start of every line (a line ends before the next start's `\n`).
    line_starts: Vec<usize>,
    /// Tokens of every line, computed when the line is first drawn.
    tokens: Vec<Option<Box<[Token]>>>,
    selected: Option<usize>,
    search: String,
    /// The line to bring into view on the next frame.
    pending_scroll: Option<usize>,
    /// Rows drawn in the last frame.
    visible: std::ops::Range<usize>,
    /// "not found" after a search without a match.
    search_failed: bool,
}

impl Default for GcodeView {
    fn default() -> Self {
        Self::new(String::new())
    }
}

impl GcodeView {
    /// A pane showing `text` (the lines are split once, here).
    #[must_use]
    pub fn new(text: String) -> Self {
        let line_starts = line_starts(&text);
        let n = line_starts.len();
        Self {
            text,
            line_starts,
            tokens: vec![None; n],
            selected: None,
            search: String::new(),
            pending_scroll: None,
            visible: 0..0,
            search_failed: false,
        }
    }

    /// Replace the program (the selection and search text are kept if they still fit).
    pub fn set_text(&mut self, text: String) {
        let selected = self.selected;
        let search = std::mem::take(&mut self.search);
        *self = Self::new(text);
        self.search = search;
        self.selected = selected.filter(|&l| l < self.line_count());
    }

    /// The whole program text.
    #[must_use]
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Number of lines (a final newline does not start another line).
    #[must_use]
    pub fn line_count(&self) -> usize {
        self.line_starts.len()
    }

    /// Line `i` (0-based) without its line break.
    #[must_use]
    pub fn line(&self, i: usize) -> Option<&str> {
        let start = *self.line_starts.get(i)?;
        let end = self
            .line_starts
            .get(i + 1)
            .map_or(self.text.len(), |&next| next.saturating_sub(1));
        let line = self.text.get(start..end)?;
        let line = line.strip_suffix('\n').unwrap_or(line);
        Some(line.strip_suffix('\r').unwrap_or(line))
    }

    /// The selected line (0-based).
    #[must_use]
    pub fn selected_line(&self) -> Option<usize> {
        self.selected
    }

    /// Select a line (or none) without scrolling.
    pub fn select_line(&mut self, line: Option<usize>) {
        self.selected = line.filter(|&l| l < self.line_count());
    }

    /// The rows drawn in the last frame (0-based lines).
    #[must_use]
    pub fn visible_lines(&self) -> std::ops::Range<usize> {
        self.visible.clone()
    }

    /// Select `line` and bring it into view on the next frame (when the user picks a path
    /// point in the viewport).
    pub fn scroll_to_line(&mut self, line: usize) {
        if line < self.line_count() {
            self.selected = Some(line);
            self.pending_scroll = Some(line);
        }
    }

    /// The search text.
    #[must_use]
    pub fn search_text(&self) -> &str {
        &self.search
    }

    /// Set the search text.
    pub fn set_search_text(&mut self, text: &str) {
        text.clone_into(&mut self.search);
        self.search_failed = false;
    }

    /// Select and scroll to the next line (after the selected one, wrapping) that holds the
    /// search text, ignoring ASCII case. Returns the line, `None` when there is no match.
    pub fn find_next(&mut self) -> Option<usize> {
        let from = self.selected.map_or(0, |l| l + 1);
        let found = find_line(&self.text, &self.line_starts, &self.search, from);
        self.search_failed = found.is_none();
        if let Some(l) = found {
            self.scroll_to_line(l);
        }
        found
    }

    /// The tokens of line `i`, tokenizing it on first use.
    fn tokens_of(&mut self, i: usize) -> &[Token] {
        if self.tokens.get(i).is_some_and(Option::is_none) {
            let t: Box<[Token]> = self.line(i).map(tokenize).unwrap_or_default().into();
            if let Some(slot) = self.tokens.get_mut(i) {
                *slot = Some(t);
            }
        }
        self.tokens
            .get(i)
            .and_then(Option::as_deref)
            .unwrap_or_default()
    }

    /// Draw the pane: header (lines, size, search), then the lines.
    pub fn ui(&mut self, ui: &mut egui::Ui) -> Option<GcodeEvent> {
        self.header_ui(ui);
        ui.separator();
        self.lines_ui(ui)
    }

    fn header_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.label(egui::RichText::new("G-CODE").small().strong().weak());
            ui.label(format!(
                "{} lines · {}",
                super::super::widgets::grouped(self.line_count()),
                size_text(self.text.len())
            ));
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                let next = ui.small_button("Next").on_hover_text("Find the next match");
                let edit = ui.add(
                    egui::TextEdit::singleline(&mut self.search)
                        .hint_text("Search")
                        .desired_width(140.0),
                );
                if edit.changed() {
                    self.search_failed = false;
                }
                let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                if (next.clicked() || enter) && !self.search.is_empty() {
                    self.find_next();
                    if enter {
                        edit.request_focus();
                    }
                }
                if self.search_failed {
                    ui.colored_label(theme::WARNING, "not found");
                }
            });
        });
    }

    fn lines_ui(&mut self, ui: &mut egui::Ui) -> Option<GcodeEvent> {
        let font = egui::TextStyle::Monospace.resolve(ui.style());
        let row_height = ui.fonts_mut(|f| f.row_height(&font)) + 2.0;
        let digits = self.line_count().max(1).to_string().len();
        let mut event = self.step_with_keys(ui);
        let mut scroll = egui::ScrollArea::both()
            .id_salt("gcode_view")
            .auto_shrink([false, false]);
        if let Some(line) = self.pending_scroll.take()
            && !(self.visible.start + 1 < line && line + 2 < self.visible.end)
        {
            // Centre the line when it is not already well inside the view.
            let shown = self.visible.len().max(1) as f32;
            let top = line as f32 - shown / 2.0;
            scroll = scroll.vertical_scroll_offset((top * row_height).max(0.0));
        }
        let colours = Palette::new(ui.visuals());
        ui.scope(|ui| {
            ui.spacing_mut().item_spacing.y = 0.0;
            scroll.show_rows(ui, row_height, self.line_count(), |ui, rows| {
                self.visible = rows.clone();
                for i in rows {
                    let job = self.layout(i, digits, &font, &colours);
                    let width = ui.available_width().max(job_width_hint(&job, &font));
                    let (rect, response) =
                        ui.allocate_exact_size(egui::vec2(width, row_height), Sense::click());
                    if self.selected == Some(i) {
                        ui.painter().rect_filled(rect, 0.0, colours.selection);
                    } else if response.hovered() {
                        ui.painter().rect_filled(rect, 0.0, colours.hover);
                    }
                    let galley = ui.painter().layout_job(job);
                    ui.painter()
                        .galley(rect.min + egui::vec2(2.0, 1.0), galley, colours.plain);
                    if response.clicked() {
                        self.selected = Some(i);
                        event = Some(GcodeEvent::LineClicked(i));
                    }
                }
            });
        });
        event
    }

    /// Up/Down arrows (pointer over the pane, no text field focused) step the selection.
    fn step_with_keys(&mut self, ui: &egui::Ui) -> Option<GcodeEvent> {
        let over = ui.rect_contains_pointer(ui.available_rect_before_wrap());
        if !over || ui.ctx().egui_wants_keyboard_input() {
            return None;
        }
        let (up, down) = ui.input(|i| {
            (
                i.key_pressed(egui::Key::ArrowUp),
                i.key_pressed(egui::Key::ArrowDown),
            )
        });
        let last = self.line_count().saturating_sub(1);
        let line = match (self.selected, up, down) {
            (Some(l), true, false) => l.saturating_sub(1),
            (Some(l), false, true) => (l + 1).min(last),
            (None, true, false) | (None, false, true) => self.visible.start.min(last),
            _ => return None,
        };
        self.scroll_to_line(line);
        Some(GcodeEvent::LineClicked(line))
    }

    /// The coloured text of row `i`: the gutter, then the tokens.
    fn layout(&mut self, i: usize, digits: usize, font: &FontId, colours: &Palette) -> LayoutJob {
        let mut job = LayoutJob::default();
        let format = |color: Color32| TextFormat {
            font_id: font.clone(),
            color,
            ..TextFormat::default()
        };
        job.append(
            &format!("{:>digits$}  ", i + 1),
            0.0,
            format(colours.gutter),
        );
        let tokens = self.tokens_of(i).to_vec();
        let line = self.line(i).unwrap_or_default();
        let mut at = 0usize;
        for t in &tokens {
            if let Some(gap) = line.get(at..t.start).filter(|g| !g.is_empty()) {
                job.append(gap, 0.0, format(colours.plain));
            }
            if let Some(s) = line.get(t.start..t.end) {
                job.append(s, 0.0, format(colours.colour(t.kind)));
            }
            at = t.end;
        }
        if let Some(rest) = line.get(at..).filter(|r| !r.is_empty()) {
            job.append(rest, 0.0, format(colours.plain));
        }
        job
    }
}

/// An estimate of a row's width (monospace), so the horizontal scroll range fits long lines.
fn job_width_hint(job: &LayoutJob, font: &FontId) -> f32 {
    job.text.chars().count() as f32 * font.size * 0.62 + 8.0
}

/// Colours of the token kinds, on the workstation's dark theme.
struct Palette {
    plain: Color32,
    gutter: Color32,
    selection: Color32,
    hover: Color32,
    g: Color32,
    m: Color32,
    axis: Color32,
    feed: Color32,
    line_number: Color32,
    comment: Color32,
    keyword: Color32,
    word: Color32,
}

impl Palette {
    fn new(v: &egui::Visuals) -> Self {
        Self {
            plain: v.text_color(),
            gutter: v.weak_text_color(),
            selection: theme::ACCENT.gamma_multiply(0.35),
            hover: v.widgets.hovered.weak_bg_fill.gamma_multiply(0.5),
            g: theme::ACCENT,
            m: Color32::from_rgb(200, 130, 230),
            axis: Color32::from_rgb(120, 200, 140),
            feed: theme::WARNING,
            line_number: v.weak_text_color(),
            comment: Color32::from_rgb(120, 125, 135),
            keyword: Color32::from_rgb(230, 120, 110),
            word: Color32::from_rgb(110, 195, 210),
        }
    }

    fn colour(&self, kind: TokenKind) -> Color32 {
        match kind {
            TokenKind::LineNumber => self.line_number,
            TokenKind::GCode => self.g,
            TokenKind::MCode => self.m,
            TokenKind::Axis => self.axis,
            TokenKind::FeedSpeedTool => self.feed,
            TokenKind::Comment => self.comment,
            TokenKind::Keyword => self.keyword,
            TokenKind::Word => self.word,
        }
    }
}

/// Byte offsets where the lines of `text` start (one line for an empty text; a final newline
/// does not start another).
fn line_starts(text: &str) -> Vec<usize> {
    let mut starts = vec![0];
    starts.extend(
        text.bytes()
            .enumerate()
            .filter(|&(_, b)| b == b'\n')
            .map(|(i, _)| i + 1)
            .filter(|&s| s < text.len()),
    );
    starts
}

/// The first line at or after `from` (wrapping to the start) that holds `needle`, ignoring
/// ASCII case.
fn find_line(text: &str, starts: &[usize], needle: &str, from: usize) -> Option<usize> {
    if needle.is_empty() {
        return None;
    }
    let offset = starts.get(from).copied().unwrap_or(text.len());
    let hay = text.as_bytes();
    let n = needle.as_bytes();
    let find = |range: std::ops::Range<usize>| {
        hay.get(range.clone())?
            .windows(n.len())
            .position(|w| w.eq_ignore_ascii_case(n))
            .map(|p| p + range.start)
    };
    let at = find(offset..hay.len()).or_else(|| find(0..hay.len()))?;
    Some(starts.partition_point(|&s| s <= at).saturating_sub(1))
}

/// `812 B`, `12.4 kB`, `3.2 MB`.
fn size_text(bytes: usize) -> String {
    let b = bytes as f64;
    if b < 1e3 {
        format!("{bytes} B")
    } else if b < 1e6 {
        format!("{:.1} kB", b / 1e3)
    } else {
        format!("{:.1} MB", b / 1e6)
    }
}

#[cfg(test)]
mod tests;
