//! The project document (L5): the part reference, stock, tool library, machine, operations and
//! view, saved as TOML ([`mod@file`]), changed only through [`Edit`]s so that every change can be
//! undone ([`History`]).
//!
//! The document holds plain data: paths, numbers and validated [`Cutter`]s. It never holds the
//! loaded mesh; the workstation loads the part the document references.

mod computed;
pub mod cutting;
mod edit;
pub mod file;
pub mod finish_group;
pub mod force_schedule;
pub mod forces;
mod history;
pub mod job;
pub mod job_sim;
pub mod keyframes;
pub mod op_common;
pub mod op_contour;
pub mod op_face;
pub mod op_holes;
pub mod op_pocket;
pub mod op_regions;
pub mod operation;
mod part;
pub mod pipeline;
pub mod posting;
pub mod rapids;
pub mod reach;
pub mod results;
pub mod run;
pub mod saved_paths;
pub mod setups;
pub mod sheet;
pub mod simulate;
pub mod tool_library;
pub mod workholding;

pub use crate::geometry::stock::{DEFAULT_MARGIN_MM, Stock};
pub use edit::{Edit, EditError};
pub use file::ProjectError;
pub use history::History;
pub use operation::{FINISH_3AXIS_CLEARANCE_MM, Operation, OperationKind};
pub use part::{PartRef, PartStatus, content_hash};
pub use results::{InProcessStock, Results};
pub use run::{LineSpan, MachiningRun, RunError, RunMotion};
pub use setups::{Frame, Orientation, Placement, Setup, SetupStock, Tilt};
pub use workholding::Workholding;

use crate::tools::Cutter;

/// The name of the one setup of a new project or of an old project file.
pub const FIRST_SETUP_NAME: &str = "Setup 1";

/// The document format version written by this build; [`Project::load`] refuses newer files and
/// migrates older ones.
pub const PROJECT_VERSION: u32 = 1;

/// One tool of the library: a name the user chose and the validated cutter.
///
/// Read generously (tool libraries and projects from other programs): `spec = "ball:d=6"` alone
/// defines the cutter; `cutter` may give only `kind` and `diameter` (the rest takes
/// [`Cutter::new`]'s defaults); when both are given they must agree; `name` defaults to the
/// spec.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "ToolEntryFile")]
pub struct ToolEntry {
    /// Name shown in the tree (free text).
    pub name: String,
    /// The cutter (sizes validated by [`Cutter::validate`] before an edit is applied).
    pub cutter: Cutter,
}

/// A tool entry as written by hand or by another program.
#[derive(serde::Deserialize)]
struct ToolEntryFile {
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    spec: Option<String>,
    #[serde(default)]
    cutter: Option<crate::toolpath::ToolFile>,
    /// Load limits given beside the cutter (those the cutter gives win).
    #[serde(default)]
    limits: Option<crate::tools::ToolLimits>,
}

impl TryFrom<ToolEntryFile> for ToolEntry {
    type Error = String;

    fn try_from(f: ToolEntryFile) -> Result<Self, String> {
        let mut tool = f.cutter.unwrap_or_default();
        if f.spec.is_some() {
            tool.spec = f.spec;
        }
        if let Some(l) = f.limits {
            let mut merged = tool.limits.unwrap_or_default();
            merged.max_force_n = merged.max_force_n.or(l.max_force_n);
            merged.max_torque_nm = merged.max_torque_nm.or(l.max_torque_nm);
            merged.max_power_w = merged.max_power_w.or(l.max_power_w);
            tool.limits = Some(merged);
        }
        let record = tool.record()?;
        Ok(Self {
            name: f.name.unwrap_or_else(|| record.spec.clone()),
            cutter: record.cutter,
        })
    }
}

/// The single setup of a version-1 project file (a work offset and a program origin, a
/// translation only), read from old files and folded into [`Project::setups`] by
/// [`Project::from_toml`]; never written.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LegacySetup {
    /// Work offset number: 1 = G54 … 6 = G59.
    #[serde(default = "first_offset")]
    pub work_offset: u8,
    /// The program origin in part coordinates, mm (program = part − origin).
    #[serde(default)]
    pub origin_mm: [f64; 3],
}

fn first_offset() -> u8 {
    1
}

/// How programs are posted: the dialect and tool-centre-point output (the machine is
/// [`Project::machine`], the work offset [`Frame::work_offset`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PostConfig {
    /// Dialect name (`linuxcnc`, `fanuc`, `siemens`, `heidenhain`, `grbl`) or a dialect file.
    pub dialect: String,
    /// Tool-centre-point output (G43.4 / TRAORI / M128) on 5-axis machines.
    pub tcp: bool,
    /// Spindle speed, rpm.
    #[serde(default = "default_rpm")]
    pub spindle_rpm: f64,
}

fn default_rpm() -> f64 {
    10_000.0
}

impl PostConfig {
    /// Check the values (the dialect is resolved by [`Project::check`]).
    ///
    /// # Errors
    /// What is wrong, in words.
    pub fn validate(&self) -> Result<(), String> {
        if self.dialect.trim().is_empty() {
            return Err("the dialect name is empty".into());
        }
        if !(self.spindle_rpm.is_finite() && (0.0..=1e6).contains(&self.spindle_rpm)) {
            return Err(format!(
                "spindle speed must be between 0 and 1 000 000 rpm, got {}",
                self.spindle_rpm
            ));
        }
        Ok(())
    }
}

impl Default for PostConfig {
    fn default() -> Self {
        Self {
            dialect: "linuxcnc".into(),
            tcp: false,
            spindle_rpm: default_rpm(),
        }
    }
}

/// The camera as plain numbers (mm, rad), so a reopened project shows the same view.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ViewState {
    /// The point the camera orbits, mm.
    pub target_mm: [f64; 3],
    /// Distance from the target to the eye, mm.
    pub distance_mm: f64,
    /// Azimuth of the eye about +Z, rad.
    pub yaw_rad: f64,
    /// Elevation of the eye, rad.
    pub pitch_rad: f64,
    /// Orthographic (true) or perspective projection.
    pub orthographic: bool,
}

impl Default for ViewState {
    fn default() -> Self {
        Self {
            target_mm: [0.0; 3],
            distance_mm: 200.0,
            yaw_rad: -std::f64::consts::FRAC_PI_4,
            pitch_rad: 0.6,
            orthographic: false,
        }
    }
}

/// The project document.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Project {
    /// Format version ([`PROJECT_VERSION`] when written by this build; 1 when missing).
    #[serde(default = "first_version")]
    pub version: u32,
    /// Project name (shown in the title bar; "Untitled" when missing).
    #[serde(default = "untitled")]
    pub name: String,
    /// The part; `None` is the embedded default part.
    #[serde(default)]
    pub part: Option<PartRef>,
    /// Stock (raw material).
    #[serde(default)]
    pub stock: Stock,
    /// The stock's material, for feeds and speeds from the cutting-data library (`None`: the
    /// operations' feeds are all typed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<cutting::WorkMaterial>,
    /// The tool library.
    #[serde(default)]
    pub tools: Vec<ToolEntry>,
    /// Index of the selected tool in [`Project::tools`].
    #[serde(default)]
    pub selected_tool: Option<usize>,
    /// The job: the setups in machining order, each with its frame, stock, workholding and
    /// operations (never empty once read or made).
    #[serde(default)]
    pub setups: Vec<Setup>,
    /// The old single setup, read from version-1 files only (folded into
    /// [`Project::setups`] when read; `None` otherwise, never written).
    #[serde(default, rename = "setup", skip_serializing)]
    pub legacy_setup: Option<LegacySetup>,
    /// Posting: dialect and options.
    #[serde(default)]
    pub post: PostConfig,
    /// Machine name (one of [`crate::machine::Machine::builtin_names`]) or a machine file path
    /// (`mill-3axis` when missing).
    #[serde(default = "default_machine")]
    pub machine: String,
    /// Operations, in machining order.
    #[serde(default)]
    pub operations: Vec<Operation>,
    /// The camera.
    #[serde(default)]
    pub view: ViewState,
}

fn first_version() -> u32 {
    1
}

fn untitled() -> String {
    "Untitled".into()
}

fn default_machine() -> String {
    "mill-3axis".into()
}

impl Default for Project {
    /// A new project: the embedded default part, no stock, a 6 mm ball end mill selected, the
    /// 3-axis mill.
    fn default() -> Self {
        let tools = crate::tools::parse_tool_spec("ball:d=6")
            .map(|cutter| ToolEntry {
                name: "Ball end mill Ø6".into(),
                cutter,
            })
            .into_iter()
            .collect::<Vec<_>>();
        Self {
            version: PROJECT_VERSION,
            name: "Untitled".into(),
            part: None,
            stock: Stock::None,
            material: None,
            setups: vec![Setup::named(FIRST_SETUP_NAME)],
            legacy_setup: None,
            post: PostConfig::default(),
            selected_tool: if tools.is_empty() { None } else { Some(0) },
            tools,
            machine: crate::machine::Machine::builtin_names()
                .first()
                .map_or_else(|| "mill-3axis".to_string(), |n| (*n).to_string()),
            operations: Vec::new(),
            view: ViewState::default(),
        }
    }
}

impl Project {
    /// The selected tool, if any.
    #[must_use]
    pub fn selected_tool(&self) -> Option<&ToolEntry> {
        self.selected_tool.and_then(|i| self.tools.get(i))
    }

    /// The first setup (the project's only one in files of today's format), or the default
    /// setup when a project made in code has none.
    #[must_use]
    pub fn first_setup(&self) -> Setup {
        self.setups
            .first()
            .cloned()
            .unwrap_or_else(|| Setup::named(FIRST_SETUP_NAME))
    }

    /// The setup holding operation `op` (the first setup when none holds it).
    #[must_use]
    pub fn setup_of_operation(&self, op: usize) -> Setup {
        setups::setup_of(self, op)
            .and_then(|i| self.setups.get(i).cloned())
            .unwrap_or_else(|| self.first_setup())
    }

    /// Fold an old file's single setup into [`Project::setups`]: when there are no setups,
    /// one setup holding every operation in order, its work offset and origin from the old
    /// `setup` (G54 at the part origin when missing).
    ///
    /// # Errors
    /// When the file gives both the old `setup` and `setups`. Operations that no setup names
    /// go, in order, to the last setup.
    pub fn migrate_setups(&mut self) -> Result<(), String> {
        let legacy = self.legacy_setup.take();
        if self.setups.is_empty() {
            let mut s = Setup::named(FIRST_SETUP_NAME);
            if let Some(l) = legacy {
                s.frame.work_offset = l.work_offset;
                s.frame.origin_mm = l.origin_mm;
            }
            s.operations = (0..self.operations.len()).collect();
            self.setups.push(s);
        } else if legacy.is_some() {
            return Err(
                "the file gives both the old `[setup]` and `[[setups]]`: keep only `[[setups]]`"
                    .into(),
            );
        }
        // Read generously: operations no setup names go, in order, to the last setup.
        let owned: Vec<usize> = self
            .setups
            .iter()
            .flat_map(|s| s.operations.iter().copied())
            .collect();
        let free: Vec<usize> = (0..self.operations.len())
            .filter(|i| !owned.contains(i))
            .collect();
        if let Some(last) = self.setups.last_mut() {
            last.operations.extend(free);
        }
        Ok(())
    }
}
