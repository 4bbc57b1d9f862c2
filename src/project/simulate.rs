//! Material removal for a computed operation, as the workstation shows it: the project's stock
//! (or a box 2 mm around the part when none is defined) on a Z-dexel grid sized to a ray budget,
//! the operation's path swept through it, and the signed deviation of the cut stock's top from
//! the part at every vertex of the stock's height-field mesh (+ material left, − gouge), measured
//! by [`crate::simulation::top_deviation`] as `talas simulate --part` measures it; and the
//! engine's one grid rule ([`stock_resolution_mm`]). The in-process stock, the layer it leaves
//! over the part and the operation simulated on it are in the result store (`results`).

use super::Stock;
use crate::diagnostics::Progress;
use crate::geometry::Aabb;
use crate::geometry::mesh::TriMesh;
use crate::simulation::{
    DexelMode, DexelStock, SimError, SimOptions, SimReport, StepOptions, StockShape, plan_toolpath,
    simulate, top_deviation,
};
use crate::toolpath::Toolpath;
use crate::tools::Cutter;

/// Most Z rays of the in-process stock ([`stock_resolution_mm`]; the engine's one rule, see [`super::results`]).
pub const STOCK_MAX_RAYS: usize = 1_000_000;

/// The engine's one dexel-spacing rule for a stock whose bounds are `bounds`: the finest
/// spacing that keeps its Z grid within `max_rays` rays, rounded up to two significant digits
/// (0.01 mm at the finest), mm.
#[must_use]
pub fn stock_resolution_mm(bounds: &Aabb, max_rays: usize) -> f64 {
    let area = (bounds.max.x - bounds.min.x).max(0.0) * (bounds.max.y - bounds.min.y).max(0.0);
    #[allow(clippy::cast_precision_loss)]
    let r = (area / max_rays.max(1) as f64).sqrt();
    if !(r.is_finite() && r > 0.0) {
        return 0.01;
    }
    let scale = 10f64.powf(r.log10().floor() - 1.0);
    ((r / scale).ceil() * scale).max(0.01)
}

/// How finely to simulate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulationSettings {
    /// Dexel spacing, mm (`None`: the finest that keeps the Z grid within `max_rays`).
    pub resolution_mm: Option<f64>,
    /// Most Z rays when the resolution is chosen automatically.
    pub max_rays: usize,
    /// Memory the stock may take, bytes.
    pub memory_limit_bytes: u64,
}

impl Default for SimulationSettings {
    fn default() -> Self {
        Self {
            resolution_mm: None,
            max_rays: STOCK_MAX_RAYS,
            memory_limit_bytes: 2 << 30,
        }
    }
}

/// A simulated operation.
#[derive(Clone, Debug)]
pub struct Simulated {
    /// The removal's report over all paths (volumes, collisions of shank and holder, time).
    pub report: SimReport,
    /// One report per path, in order.
    pub reports: Vec<SimReport>,
    /// Dexel spacing used, mm.
    pub resolution_mm: f64,
    /// The cut stock's top as a mesh (one vertex per Z ray holding material), mm.
    pub stock_mesh: TriMesh,
    /// Signed distance of each `stock_mesh` vertex from the part, mm: positive where material
    /// is left (scallops, uncut margins), negative where the part was cut into.
    pub deviation_mm: Vec<f64>,
    /// Deepest cut into the part, mm (≥ 0).
    pub max_gouge_mm: f64,
    /// 99th percentile of the material left over the part (vertices whose closest part point
    /// is straight below them), mm.
    pub remaining_p99_mm: f64,
}

/// Simulate `toolpath` cut by `cutter` in `stock` and measure the result against `part`.
///
/// # Errors
/// [`SimError`] for a bad stock, resolution or cutter, too little memory, or a cancel.
pub fn simulate_toolpath(
    stock: &Stock,
    part: &TriMesh,
    toolpath: &Toolpath,
    cutter: &Cutter,
    settings: &SimulationSettings,
    progress: &Progress,
) -> Result<Simulated, SimError> {
    simulate_toolpaths(stock, part, &[(toolpath, cutter)], settings, progress)
}

/// Simulate several paths, in order, on one stock (roughing, then finishing, …) and measure the
/// result against `part`. [`Simulated::reports`] has one report per path; [`Simulated::report`]
/// sums them (volumes from the first stock to the last, every collision).
///
/// # Errors
/// As [`simulate_toolpath`]; [`SimError::Options`] when `paths` is empty.
pub fn simulate_toolpaths(
    stock: &Stock,
    part: &TriMesh,
    paths: &[(&Toolpath, &Cutter)],
    settings: &SimulationSettings,
    progress: &Progress,
) -> Result<Simulated, SimError> {
    if paths.is_empty() {
        return Err(SimError::Options("no tool path to simulate".into()));
    }
    let (mut dexels, resolution) = stock_grid(stock, part, settings)?;
    let mut reports = Vec::with_capacity(paths.len());
    for (toolpath, cutter) in paths {
        reports.push(cut_path(
            &mut dexels,
            resolution,
            toolpath,
            cutter,
            progress,
        )?);
    }
    measured(&dexels, part, reports, progress)
}

/// Cut one whole tool path into the stock, stepped for the grid's spacing `resolution`, mm.
pub(super) fn cut_path(
    dexels: &mut DexelStock,
    resolution: f64,
    toolpath: &Toolpath,
    cutter: &Cutter,
    progress: &Progress,
) -> Result<SimReport, SimError> {
    let step = StepOptions::for_resolution(resolution, cutter.flute_length);
    let plan = plan_toolpath(toolpath, &step)?;
    simulate(dexels, cutter, &plan, &SimOptions::default(), progress)
}

/// The project's stock (or the part's box + 2 mm) on a Z-dexel grid, and its spacing, mm.
pub(super) fn stock_grid(
    stock: &Stock,
    part: &TriMesh,
    settings: &SimulationSettings,
) -> Result<(DexelStock, f64), SimError> {
    let shape = StockShape::of(stock, &part.bbox());
    let resolution = settings
        .resolution_mm
        .unwrap_or_else(|| stock_resolution_mm(&shape.bounds(), settings.max_rays));
    let dexels = DexelStock::new(
        vec![shape],
        resolution,
        DexelMode::Z,
        settings.memory_limit_bytes,
    )?;
    Ok((dexels, resolution))
}

/// The cut stock's mesh and deviation from `part`, with the reports of the paths cut.
pub(super) fn measured(
    dexels: &DexelStock,
    part: &TriMesh,
    reports: Vec<SimReport>,
    progress: &Progress,
) -> Result<Simulated, SimError> {
    let report = merged(&reports);
    let stock_mesh = dexels.height_field_mesh();
    let top = top_deviation(dexels, part, progress)?;
    Ok(Simulated {
        report,
        reports,
        resolution_mm: dexels.resolution_mm,
        stock_mesh,
        deviation_mm: top.values_mm,
        max_gouge_mm: top.max_gouge_mm,
        remaining_p99_mm: top.remaining_p99_mm,
    })
}

/// The reports of consecutive runs on one stock as one: the first run's initial volume, the last
/// run's final volume and memory, the sums of the rest, every collision.
fn merged(reports: &[SimReport]) -> SimReport {
    let mut out = reports.first().cloned().unwrap_or(SimReport {
        initial_volume_mm3: 0.0,
        final_volume_mm3: 0.0,
        removed_volume_mm3: 0.0,
        collisions: Vec::new(),
        moves: 0,
        steps: 0,
        time_s: 0.0,
        memory_bytes: 0,
    });
    for r in reports.iter().skip(1) {
        out.final_volume_mm3 = r.final_volume_mm3;
        out.memory_bytes = r.memory_bytes;
        out.removed_volume_mm3 += r.removed_volume_mm3;
        out.collisions.extend(r.collisions.iter().copied());
        out.moves += r.moves;
        out.steps += r.steps;
        out.time_s += r.time_s;
    }
    out
}
