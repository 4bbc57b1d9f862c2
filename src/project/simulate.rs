//! Material removal for a computed operation, as the workstation shows it: the project's stock
//! (or a box 2 mm around the part when none is defined) on a Z-dexel grid sized to a ray budget,
//! the operation's path swept through it, and the signed deviation of the cut stock's top from
//! the part at every vertex of the stock's height-field mesh (+ material left, − gouge), measured
//! by [`crate::simulation::top_deviation`] as `talas simulate --part` measures it; and
//! [`StockLeftover`], the cut stock's top as a height field that measures the layer left over a
//! part point (rest finishing from the stock).

use std::sync::Arc;

use glam::DVec3;

use super::Stock;
use super::results::{InProcessStock, STOCK_MAX_RAYS, stock_resolution_mm};
use crate::diagnostics::Progress;
use crate::geometry::mesh::TriMesh;
use crate::simulation::{
    DexelMode, DexelStock, SimError, SimOptions, SimReport, StepOptions, StockShape, plan_toolpath,
    simulate, top_deviation,
};
use crate::toolpath::Toolpath;
use crate::tools::Cutter;

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

/// Operation `index` simulated as the result store cuts it: its posted run
/// ([`super::results::operation_moves`]) into the in-process stock before it
/// ([`super::Results::stock_before`], the earlier operations' runs), measured against the part.
/// The stock after it is the store's, so the simulation, rest finishing and forces see one.
///
/// # Errors
/// The operation's or an earlier one's [`super::pipeline::ComputeError`], or the measure's
/// [`SimError`] as text.
pub fn simulate_in_process(
    store: &super::Results,
    project: &super::Project,
    part: &crate::import::Workpiece,
    index: usize,
    progress: &Progress,
) -> Result<Simulated, String> {
    let after = store
        .stock_after(project, part, index, progress)
        .map_err(|e| e.to_string())?;
    let reports = after.last_cut.iter().cloned().collect();
    measured(&after.dexels, &part.mesh, reports, progress).map_err(|e| e.to_string())
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

/// The simulated stock's top as a height field, to measure the layer earlier operations left
/// on the part (rest finishing from the stock).
pub struct StockLeftover {
    stock: Arc<InProcessStock>,
}

impl StockLeftover {
    /// The in-process stock's top.
    #[must_use]
    pub fn of(stock: Arc<InProcessStock>) -> Self {
        Self { stock }
    }

    /// Cut `paths` (tool paths, not posted runs) in order into the project's stock (or the
    /// part's box + 2 mm) on the engine's one grid ([`stock_resolution_mm`]).
    ///
    /// # Errors
    /// As [`simulate_toolpaths`].
    pub fn simulate(
        stock: &Stock,
        part: &TriMesh,
        paths: &[(Toolpath, Cutter)],
        progress: &Progress,
    ) -> Result<Self, SimError> {
        let (mut dexels, resolution) = stock_grid(stock, part, &SimulationSettings::default())?;
        let mut last_cut = None;
        for (toolpath, cutter) in paths {
            last_cut = Some(cut_path(
                &mut dexels,
                resolution,
                toolpath,
                cutter,
                progress,
            )?);
        }
        Ok(Self::of(Arc::new(InProcessStock {
            dexels,
            last_cut,
            from_posted_runs: false,
            notes: Vec::new(),
        })))
    }

    /// Dexel spacing, mm.
    #[must_use]
    pub fn resolution_mm(&self) -> f64 {
        self.stock.resolution_mm()
    }

    /// The stock's top at (x, y), interpolated bilinearly between the four nearest Z rays, mm;
    /// −∞ where one of them holds no material or lies outside the grid.
    #[must_use]
    pub fn top(&self, x: f64, y: f64) -> f64 {
        let Some(fam) = self.stock.dexels.families.first() else {
            return f64::NEG_INFINITY;
        };
        let u = (x - fam.origin.x) / fam.spacing - 0.5;
        let v = (y - fam.origin.y) / fam.spacing - 0.5;
        let (i0, j0) = (u.floor(), v.floor());
        let (fu, fv) = (u - i0, v - j0);
        #[allow(clippy::cast_precision_loss)]
        let (nu, nv) = (fam.nu as f64, fam.nv as f64);
        let at = |i: f64, j: f64| -> f64 {
            if i < 0.0 || j < 0.0 || i >= nu || j >= nv {
                return f64::NEG_INFINITY;
            }
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let (i, j) = (i as usize, j as usize);
            fam.dexels
                .get(j * fam.nu + i)
                .and_then(|d| d.intervals().last())
                .map_or(f64::NEG_INFINITY, |iv| fam.point(i, j, f64::from(iv[1])).z)
        };
        let z = [
            at(i0, j0),
            at(i0 + 1.0, j0),
            at(i0, j0 + 1.0),
            at(i0 + 1.0, j0 + 1.0),
        ];
        if z.iter().any(|z| !z.is_finite()) {
            return f64::NEG_INFINITY;
        }
        (z[0] * (1.0 - fu) + z[1] * fu) * (1.0 - fv) + (z[2] * (1.0 - fu) + z[3] * fu) * fv
    }

    /// Thickness of the layer over the part point `c` along its unit normal `n`, mm: how far
    /// along `n` the first point above the interpolated top lies (half-spacing steps, then
    /// bisection to 1e-5 mm); 0 where the top lies below `c`, at most `max_mm`.
    #[must_use]
    pub fn thickness(&self, c: DVec3, n: DVec3, max_mm: f64) -> f64 {
        let inside = |t: f64| {
            let q = c + n * t;
            self.top(q.x, q.y) > q.z
        };
        if !inside(0.0) {
            return 0.0;
        }
        let dt = 0.5 * self.stock.resolution_mm();
        let mut a = 0.0;
        while a < max_mm {
            let b = (a + dt).min(max_mm);
            if !inside(b) {
                let mut hi = b;
                while hi - a > 1e-5 {
                    let m = 0.5 * (a + hi);
                    if inside(m) { a = m } else { hi = m }
                }
                return a;
            }
            a = b;
        }
        max_mm
    }
}
