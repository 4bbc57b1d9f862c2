//! The operator panel: the virtual control of [`crate::control`] driven from a window laid out
//! as a machine's control panel.
//!
//! - `layout`: the panel's widgets (mode selector, axis and direction buttons, increment
//!   selector, handwheel, overrides, cycle buttons, DRO, active codes, MDI line with history,
//!   program view, alarms).
//! - `keys`: the keyboard, as LinuxCNC AXIS: arrows X/Y, Page Up/Down Z, `[`/`]` the first
//!   rotary, Home homes, Escape stops, F1 e-stop. Keys act while the pointer is over the panel
//!   and no text field has the keyboard.
//!
//! The control is built for the workstation's machine (`project.machine`) with the project's
//! stock (dexel, at [`STOCK_RESOLUTION_MM`]) and the active operation's tool, so jogging into
//! the stock cuts it. The part's coordinates are taken as machine coordinates; the setup's
//! program origin is the work offset it names. Each frame advances the control by the frame's
//! time × the clock factor (at most [`MAX_FRAME_S`] of real time), and asks for the next frame
//! while anything moves; the time one `advance` took is shown.

mod camera;
mod feature;
mod keys;
mod layout;
pub mod machine_view;

use std::path::PathBuf;
use std::time::Instant;

use glam::DVec3;

use super::file_chooser::{ChooserPurpose, FileChooser, FileType};
use crate::control::{Action, Control, ControlConfig, LiveStock, Mode, Snapshot};
use crate::machine::Machine;
use crate::simulation::{DexelMode, DexelStock, StockShape};
use crate::tools::Cutter;

/// Dexel spacing of the panel's stock, mm (coarse, so that cutting stays interactive).
pub const STOCK_RESOLUTION_MM: f64 = 0.5;
/// Longest real frame time the control advances by, s (a stalled frame does not jump).
pub const MAX_FRAME_S: f64 = 0.1;
/// Memory the panel's stock may take, bytes.
const STOCK_MEMORY_BYTES: u64 = 1 << 28;

const GCODE_FILES: &[FileType] = &[
    (
        "G-code (.ngc, .nc, .tap, .mpf, .gcode)",
        &["ngc", "nc", "tap", "mpf", "gcode"],
    ),
    ("All files", &[]),
];

/// What the workstation lends the panel each frame.
#[derive(Clone, Debug, Default)]
pub struct PanelSource<'a> {
    /// Machine name or machine file (`project.machine`).
    pub machine: String,
    /// The project's stock shape (part coordinates = machine coordinates, mm).
    pub stock: Option<StockShape>,
    /// The tool in the spindle.
    pub cutter: Option<Cutter>,
    /// Work offset number (1 = G54 … 6 = G59) and its origin, mm.
    pub work_offset: (u8, [f64; 3]),
    /// The active operation's posted program: name and text.
    pub posted: Option<(&'a str, &'a str)>,
    /// The setup whose workholding sits on the table (the active operation's).
    pub setup: Option<SetupSource<'a>>,
}

/// What places a setup's workholding on the control's table: the project, the setup, the part
/// (its faces orient the setup, its box sizes the stock) and the folder body files are read
/// from.
#[derive(Clone, Copy)]
pub struct SetupSource<'a> {
    /// The project.
    pub project: &'a crate::project::Project,
    /// Index of the setup.
    pub index: usize,
    /// The part.
    pub part: &'a crate::import::Workpiece,
    /// The project's folder.
    pub base: &'a std::path::Path,
}

impl std::fmt::Debug for SetupSource<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SetupSource")
            .field("index", &self.index)
            .field("base", &self.base)
            .finish_non_exhaustive()
    }
}

/// The panel's mode selector: the control's modes, JOG split into continuous and incremental.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PanelMode {
    /// Homing.
    Ref,
    /// Continuous jog while a key or button is held.
    Jog,
    /// Incremental jog, one increment per press.
    Inc,
    /// Handwheel.
    Mpg,
    /// Manual data input.
    Mdi,
    /// Program run.
    Auto,
}

impl PanelMode {
    /// All modes, in the selector's order.
    pub const ALL: [Self; 6] = [
        Self::Ref,
        Self::Jog,
        Self::Inc,
        Self::Mpg,
        Self::Mdi,
        Self::Auto,
    ];

    /// The label on the selector.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Ref => "REF",
            Self::Jog => "JOG",
            Self::Inc => "INC",
            Self::Mpg => "MPG",
            Self::Mdi => "MDI",
            Self::Auto => "AUTO",
        }
    }

    fn control_mode(self) -> Mode {
        match self {
            Self::Ref => Mode::Ref,
            Self::Jog | Self::Inc => Mode::Jog,
            Self::Mpg => Mode::Mpg,
            Self::Mdi => Mode::Mdi,
            Self::Auto => Mode::Auto,
        }
    }
}

/// The operator panel's state.
pub struct OperatorPanel {
    /// The window is shown.
    pub open: bool,
    control: Option<Control>,
    /// The machine the control was built for.
    built_for: Option<String>,
    /// Why the control could not be built, or the last refused action.
    message: Option<String>,
    mode: PanelMode,
    mdi: String,
    history: Vec<String>,
    program_name: String,
    program: Vec<String>,
    /// The continuous jog running from a held button or key.
    jog_held: Option<(char, f64)>,
    /// The axis button held down for it.
    jog_button: Option<(char, f64)>,
    /// Jog feed, mm/min (deg/min on rotaries).
    jog_feed: f64,
    /// Line to run the program from (1-based).
    run_from: usize,
    /// Handwheel axis and its turned angle not yet a whole detent, rad.
    wheel_axis: char,
    wheel_rest_rad: f32,
    /// Angle of the handwheel as drawn, rad.
    wheel_angle_rad: f32,
    /// Simulated seconds per real second.
    clock: f64,
    single_block: bool,
    optional_stop: bool,
    block_delete: bool,
    /// Wall time of the last frame's `advance`, s.
    advance_s: f64,
    last_line: Option<usize>,
    chooser: Option<FileChooser>,
    panel_rect: Option<egui::Rect>,
    /// A machine camera preset to carry out (`camera.rs`).
    camera_request: Option<crate::render::StandardView>,
    /// The machine's meshes drawn in the viewport while the panel is open.
    machine_view: machine_view::MachineView,
}

impl Default for OperatorPanel {
    fn default() -> Self {
        Self::new()
    }
}

impl OperatorPanel {
    /// A closed panel; its control is built when first shown.
    #[must_use]
    pub fn new() -> Self {
        Self {
            open: false,
            control: None,
            built_for: None,
            message: None,
            mode: PanelMode::Jog,
            mdi: String::new(),
            history: Vec::new(),
            program_name: String::new(),
            program: Vec::new(),
            jog_held: None,
            jog_button: None,
            jog_feed: 1000.0,
            run_from: 1,
            wheel_axis: 'X',
            wheel_rest_rad: 0.0,
            wheel_angle_rad: 0.0,
            clock: 1.0,
            single_block: false,
            optional_stop: false,
            block_delete: false,
            advance_s: 0.0,
            last_line: None,
            chooser: None,
            panel_rect: None,
            camera_request: None,
            machine_view: machine_view::MachineView::default(),
        }
    }

    /// The control (after the panel built it).
    #[must_use]
    pub fn control(&self) -> Option<&Control> {
        self.control.as_ref()
    }

    /// The control, to change (after the panel built it).
    pub fn control_mut(&mut self) -> Option<&mut Control> {
        self.control.as_mut()
    }

    /// The mode selected on the panel.
    #[must_use]
    pub fn mode(&self) -> PanelMode {
        self.mode
    }

    /// The MDI line as typed.
    #[must_use]
    pub fn mdi_line(&self) -> &str {
        &self.mdi
    }

    /// The message shown (a refused action, a control that could not be built).
    #[must_use]
    pub fn message(&self) -> Option<&str> {
        self.message.as_deref()
    }

    /// Simulated seconds per real second (1 … 100).
    pub fn set_clock(&mut self, factor: f64) {
        self.clock = factor.clamp(1.0, 100.0);
    }

    /// Build the control for `source` (machine, stock, tool, work offset), replacing the one
    /// there was.
    pub fn build(&mut self, source: &PanelSource<'_>) {
        self.jog_held = None;
        self.built_for = Some(source.machine.clone());
        match build_control(source) {
            Ok(c) => {
                self.wheel_axis = c.machine().axes.first().map_or('X', |a| a.name);
                self.control = Some(c);
                self.message = None;
                self.mode = PanelMode::Jog;
            }
            Err(e) => {
                self.control = None;
                self.message = Some(e);
            }
        }
    }

    /// Draw the panel in its window while it is open.
    pub fn window(&mut self, ctx: &egui::Context, source: &PanelSource<'_>) {
        if !self.open {
            return;
        }
        let mut open = self.open;
        egui::Window::new("Operator panel · virtual control")
            .id(egui::Id::unique("talas operator panel"))
            .open(&mut open)
            .default_pos([60.0, 60.0])
            .default_size([1180.0, 800.0])
            .resizable(true)
            .show(ctx, |ui| self.ui(ui, source));
        self.open = open;
        if !self.open {
            self.release_jog();
        }
    }

    /// The panel's contents: advance the control by the frame's time, then draw and act.
    pub fn ui(&mut self, ui: &mut egui::Ui, source: &PanelSource<'_>) {
        if self.built_for.as_deref() != Some(source.machine.as_str()) {
            self.build(source);
        }
        self.advance(ui);
        let Some(snap) = self.control.as_ref().map(Control::snapshot) else {
            ui.colored_label(
                ui.visuals().error_fg_color,
                self.message.as_deref().unwrap_or("No control"),
            );
            if ui.button("Retry").clicked() {
                self.build(source);
            }
            return;
        };
        let rect = ui
            .scope(|ui| self.panel_ui(ui, &snap, source))
            .response
            .rect;
        self.panel_rect = Some(rect);
        self.keys(ui);
        self.chooser_ui(ui.ctx());
        if self.control.as_ref().is_some_and(|c| !c.is_idle()) || self.jog_held.is_some() {
            ui.ctx().request_repaint();
        }
    }

    /// Advance the control by this frame's time × the clock factor, timing the call.
    fn advance(&mut self, ui: &egui::Ui) {
        let dt = f64::from(ui.input(|i| i.stable_dt)).clamp(0.0, MAX_FRAME_S) * self.clock;
        let Some(c) = &mut self.control else { return };
        if c.is_idle() || dt <= 0.0 {
            return;
        }
        let t0 = Instant::now();
        c.advance(dt);
        self.advance_s = t0.elapsed().as_secs_f64();
    }

    /// Apply `action`; a refusal is shown as the panel's message.
    fn act(&mut self, action: Action) {
        let Some(c) = &mut self.control else { return };
        match c.apply(action) {
            Ok(()) => self.message = None,
            Err(e) => self.message = Some(e.to_string()),
        }
    }

    /// Select a panel mode (the control refuses while something moves).
    fn select_mode(&mut self, mode: PanelMode) {
        let before = self.message.clone();
        self.act(Action::SetMode(mode.control_mode()));
        if self
            .control
            .as_ref()
            .is_some_and(|c| c.snapshot().mode == mode.control_mode())
        {
            self.mode = mode;
        } else if self.message.is_none() {
            self.message = before;
        }
    }

    /// Start a continuous jog (JOG) or one increment (INC) of `axis` in `direction`.
    fn jog_press(&mut self, axis: char, direction: f64) {
        match self.mode {
            PanelMode::Jog if self.jog_held.is_none() => {
                self.jog_held = Some((axis, direction));
                self.act(Action::JogStart { axis, direction });
            }
            PanelMode::Inc => self.act(Action::JogIncrement { axis, direction }),
            PanelMode::Mpg => self.wheel_axis = axis,
            _ => {}
        }
    }

    /// End the continuous jog of a released button or key.
    fn release_jog(&mut self) {
        if self.jog_held.take().is_some() {
            self.act(Action::JogStop);
        }
    }

    /// Send the MDI line and keep it in the history.
    fn send_mdi(&mut self) {
        let line = self.mdi.trim().to_string();
        if line.is_empty() {
            return;
        }
        self.act(Action::Mdi(line.clone()));
        self.history.retain(|h| *h != line);
        self.history.push(line);
        self.mdi.clear();
    }

    /// Load `text` as the AUTO program.
    fn load_program(&mut self, name: String, text: String) {
        self.program = text.lines().map(str::to_string).collect();
        self.program_name.clone_from(&name);
        self.last_line = None;
        self.act(Action::LoadProgram { name, text });
    }

    fn choose_file(&mut self) {
        let purpose = ChooserPurpose::Feature {
            title: "Load a G-code program",
            types: GCODE_FILES,
            save: false,
        };
        self.chooser = Some(FileChooser::new(purpose, std::env::current_dir().ok(), &[]));
    }

    fn chooser_ui(&mut self, ctx: &egui::Context) {
        let Some(chooser) = &mut self.chooser else {
            return;
        };
        let Some(outcome) = chooser.ui(ctx) else {
            return;
        };
        self.chooser = None;
        if let Some(path) = outcome {
            self.load_file(&path);
        }
    }

    fn load_file(&mut self, path: &PathBuf) {
        match std::fs::read_to_string(path) {
            Ok(text) => self.load_program(path.display().to_string(), text),
            Err(e) => self.message = Some(format!("{}: {e}", path.display())),
        }
    }
}

/// The control for `source`: its machine, stock, tool and work offset.
fn build_control(source: &PanelSource<'_>) -> Result<Control, String> {
    let machine = Machine::resolve(&source.machine).map_err(|e| e.to_string())?;
    let mut cfg = ControlConfig::new(machine);
    let (n, origin) = source.work_offset;
    let slot = usize::from(n.clamp(1, 6) - 1);
    cfg.work_offsets[slot] = DVec3::from(origin);
    if let (Some(shape), Some(cutter)) = (&source.stock, &source.cutter) {
        let stock = DexelStock::new(
            vec![shape.clone()],
            STOCK_RESOLUTION_MM,
            DexelMode::Z,
            STOCK_MEMORY_BYTES,
        )
        .map_err(|e| format!("stock: {e}"))?;
        // The stock rests on a riser block on the table (tested against the head and tool).
        let b = &stock.bounds;
        cfg.fixtures.extend(crate::control::collide::riser_under(
            &cfg.machine,
            b.min,
            b.max,
        ));
        cfg.stock = Some(LiveStock::new(stock, cutter.clone(), STOCK_RESOLUTION_MM));
    }
    // The setup's vise, plate or bodies on the table: the same meshes planning and the job's
    // simulation test, so AUTO stops at the jaw on the line planning names.
    if let Some(s) = &source.setup {
        let placements = crate::project::setups::placements(s.project, Some(s.part))?;
        cfg.fixtures.extend(
            crate::project::job_sim::control_fixtures(
                s.project,
                s.index,
                &placements,
                &s.part.mesh.bbox(),
                s.base,
                DVec3::from(origin),
            )
            .map_err(|e| format!("workholding of setup {}: {e}", s.index + 1))?,
        );
    }
    let mut control = Control::new(cfg).map_err(|e| e.to_string())?;
    // The stock is cut on a worker thread, so frames stay short while AUTO cuts. The frame
    // waits for the worker when it falls behind (not the simulated clock): with the cutting's
    // tiles kept between pieces a ×100 frame costs about 2 ms, and a paced clock capped the
    // panel at about 6 simulated seconds per second whatever the factor (0.4 s/s before).
    control.start_cutting_worker();
    control.pace_motion_by_cutting(false);
    Ok(control)
}

/// The unit of `axis`'s numbers: mm, or ° for a rotary axis.
fn unit_of(control: &Control, axis: char) -> &'static str {
    match control.machine().axis(axis) {
        Some(a) if a.is_rotary() => "°",
        _ => "mm",
    }
}

/// The snapshot's value of `axis` in `values`.
fn value_of(snap: &Snapshot, values: &[f64], axis: char) -> f64 {
    snap.axes
        .iter()
        .position(|&a| a == axis)
        .and_then(|i| values.get(i).copied())
        .unwrap_or(0.0)
}
