//! The engine's result store (L5): each operation's computed path, and the in-process stock
//! before each operation, kept under a [`Digest`] of exactly the inputs the computation reads,
//! so a result is fresh only while all of them are unchanged — in the workstation and the
//! command line alike.
//!
//! ```text
//! Project + Workpiece ─pipeline::digests─▶ Keys { part, operation k, stock before k }
//!   get_or_compute(k) ─(digest k known?)─▶ Arc<Computed>      else pipeline ─▶ store
//!   stock_before(k)   ─(digest known?)───▶ Arc<InProcessStock> else stock_before(k−1)
//!                        ─ posted run of operation k−1 (RunMotion::move_plan, kinematics) ─▶ cut
//! ```
//!
//! **One stock.** The stock before operation k is the project's stock cut by the *posted run*
//! of operations 0…k−1 in order: each path is posted as the project posts it
//! ([`super::posting::run_operation`]), its interpreted program turned into tool poses through
//! the machine's kinematics ([`super::RunMotion::move_plan`]) and cut once; the result is
//! memoised and shared by rest machining, the forces and the simulation. Where a path cannot be
//! posted or planned (a 5-axis path on a 3-axis machine), its tool path is cut instead and the
//! stock carries a warning saying so.
//!
//! **One resolution rule** ([`stock_resolution_mm`]): the finest dexel spacing that keeps the
//! stock's Z grid within [`STOCK_MAX_RAYS`] rays, rounded up to two significant digits. The
//! stock is shared by every reader, so its grid cannot depend on any one reader's tool (the
//! rest finishing's 0.1·R, the forces' clamp); a ray budget bounds its memory and cutting time
//! whatever the part's size, and the rounding keeps the grid reproducible.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use glam::DVec3;

use super::computed::{ComputeError, Computed};
use super::rapids::Linked;
pub use super::simulate::{STOCK_MAX_RAYS, stock_resolution_mm};
use super::simulate::{Simulated, SimulationSettings, cut_path, measured, stock_grid};
use super::{Project, Stock, pipeline};
use crate::diagnostics::{Diagnostic, Progress};
use crate::geometry::mesh::TriMesh;
use crate::import::Workpiece;
use crate::simulation::SimError;
use crate::simulation::{
    DexelMode, DexelStock, MovePlan, SimOptions, SimReport, StepOptions, StockShape, plan_toolpath,
    simulate,
};
use crate::toolpath::Toolpath;
use crate::tools::Cutter;

/// Corner tolerance the in-process stock's runs are planned with, mm (the workstation's
/// program view uses the same; it changes only the run's timing, not the cut geometry).
pub const RUN_CORNER_TOLERANCE_MM: f64 = 0.01;

/// A 64-bit digest of a computation's inputs (FNV-1a over their serialised form, finished by
/// a 64-bit mix).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Digest(pub u64);

impl std::fmt::Display for Digest {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:016x}", self.0)
    }
}

/// Builds a [`Digest`] from labelled parts (the label keeps `("a", "bc")` apart from
/// `("ab", "c")`).
#[derive(Clone, Debug)]
pub struct DigestBuilder(u64);

impl Default for DigestBuilder {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

impl DigestBuilder {
    /// A builder for the inputs of `what` (a name kept apart from every other kind).
    #[must_use]
    pub fn new(what: &str) -> Self {
        let mut b = Self::default();
        b.bytes(what.as_bytes());
        b
    }

    fn byte(&mut self, v: u8) {
        self.0 ^= u64::from(v);
        self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
    }

    fn word(&mut self, v: u64) {
        for b in v.to_le_bytes() {
            self.byte(b);
        }
    }

    /// Add raw bytes (their length first).
    pub fn bytes(&mut self, bytes: &[u8]) {
        self.word(bytes.len() as u64);
        for &b in bytes {
            self.byte(b);
        }
    }

    /// Add a labelled value by its JSON form (or the error serialising it gave).
    pub fn json<T: serde::Serialize + ?Sized>(&mut self, label: &str, value: &T) {
        self.bytes(label.as_bytes());
        match serde_json::to_vec(value) {
            Ok(v) => self.bytes(&v),
            Err(e) => self.bytes(format!("unserialisable: {e}").as_bytes()),
        }
    }

    /// Add a labelled text.
    pub fn text(&mut self, label: &str, text: &str) {
        self.bytes(label.as_bytes());
        self.bytes(text.as_bytes());
    }

    /// Add a labelled digest.
    pub fn digest(&mut self, label: &str, d: Digest) {
        self.bytes(label.as_bytes());
        self.word(d.0);
    }

    /// The digest (FNV-1a state finished by the splitmix64 mix).
    #[must_use]
    pub fn finish(&self) -> Digest {
        let mut z = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        Digest(z ^ (z >> 31))
    }
}

/// The digest of a part's identity and content: its source, format, the tessellated mesh
/// (positions and triangles) and the face of every triangle (a changed B-rep changes them).
#[must_use]
pub fn part_digest(part: &Workpiece) -> Digest {
    let mut b = DigestBuilder::new("part");
    b.text("source", &part.source.to_string_lossy());
    b.text("format", &format!("{:?}", part.format));
    b.word(part.mesh.positions.len() as u64);
    for p in &part.mesh.positions {
        for v in p.to_array() {
            b.word(v.to_bits());
        }
    }
    b.word(part.mesh.triangles.len() as u64);
    for t in &part.mesh.triangles {
        for v in t {
            b.word(u64::from(*v));
        }
    }
    for f in &part.face_of_triangle {
        b.word(u64::from(*f));
    }
    b.word(part.surfaces.len() as u64);
    b.word(u64::from(part.part.is_some()));
    b.finish()
}

/// The digests of every result of a project on a part: the part's, each operation's path and
/// the stock before each operation (one more than there are operations: the last is the stock
/// after them all). Built by [`pipeline::digests`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Keys {
    /// The part's ([`part_digest`]).
    pub part: Digest,
    /// Operation k's path.
    pub operations: Vec<Digest>,
    /// The stock before operation k (k = 0: the project's stock).
    pub stocks: Vec<Digest>,
}

/// The stock the operations before one operation leave, as a dexel stock on the engine's one
/// grid ([`stock_resolution_mm`]).
#[derive(Clone, Debug)]
pub struct InProcessStock {
    /// The cut stock (Z dexels).
    pub dexels: DexelStock,
    /// The report of cutting the operation just before (`None` for the raw stock).
    pub last_cut: Option<SimReport>,
    /// Whether every path was cut from its posted run (false where one fell back to its tool
    /// path: `notes` says which and why).
    pub from_posted_runs: bool,
    /// Notes on how the stock was made (fallbacks to the tool path, the move plans' warnings).
    pub notes: Vec<Diagnostic>,
}

impl InProcessStock {
    /// Dexel spacing, mm.
    #[must_use]
    pub fn resolution_mm(&self) -> f64 {
        self.dexels.resolution_mm
    }

    /// The stock's volume, mm³.
    #[must_use]
    pub fn volume_mm3(&self) -> f64 {
        self.dexels.volume_mm3()
    }
}

#[derive(Default)]
struct Inner {
    paths: Vec<Option<(Digest, Arc<Computed>)>>,
    stocks: Vec<Option<(Digest, Arc<InProcessStock>)>>,
    /// Operation k's linked path, under (its path's digest, the stock-before digest).
    linked: Vec<Option<LinkedSlot>>,
}

/// A linked path under (its operation's digest, the stock-before digest).
type LinkedSlot = ((Digest, Digest), Arc<Linked>);

fn slot<T>(v: &mut Vec<Option<T>>, k: usize) -> &mut Option<T> {
    if v.len() <= k {
        v.resize_with(k + 1, || None);
    }
    &mut v[k]
}

/// The engine's result store: computed paths and in-process stocks, each kept under the
/// digest of its inputs (one slot per operation index, so a changed input replaces the old
/// result). Shareable between threads; computations run outside its lock.
#[derive(Default)]
pub struct Results {
    inner: Mutex<Inner>,
    computations: AtomicUsize,
    stock_cuts: AtomicUsize,
}

impl std::fmt::Debug for Results {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Results")
            .field("computations", &self.computations())
            .field("stock_cuts", &self.stock_cuts())
            .finish_non_exhaustive()
    }
}

impl Results {
    /// An empty store.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    fn lock(&self) -> MutexGuard<'_, Inner> {
        // A panic while holding the lock leaves plain data: keep using it.
        self.inner
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// How many operations this store has planned (each call of the strategy counts once).
    #[must_use]
    pub fn computations(&self) -> usize {
        self.computations.load(Ordering::Relaxed)
    }

    /// How many operations' runs this store has cut into an in-process stock.
    #[must_use]
    pub fn stock_cuts(&self) -> usize {
        self.stock_cuts.load(Ordering::Relaxed)
    }

    /// The digests of `project`'s results on `part` ([`pipeline::digests`]).
    #[must_use]
    pub fn keys(project: &Project, part: &Workpiece) -> Keys {
        pipeline::digests_in(
            project,
            part_digest(part),
            super::op_regions::part_folder(part),
        )
    }

    /// Operation `index`'s path if the store holds it fresh (computed from the inputs the
    /// project and part give now).
    #[must_use]
    pub fn fresh(&self, keys: &Keys, index: usize) -> Option<Arc<Computed>> {
        let want = *keys.operations.get(index)?;
        match self.lock().paths.get(index) {
            Some(Some((d, c))) if *d == want => Some(Arc::clone(c)),
            _ => None,
        }
    }

    /// Keep `computed` as operation `index`'s path under `keys` (a path computed elsewhere,
    /// or rewritten, e.g. by feed scheduling).
    pub fn insert(&self, keys: &Keys, index: usize, computed: Computed) -> Option<Arc<Computed>> {
        let d = *keys.operations.get(index)?;
        let c = Arc::new(computed);
        *slot(&mut self.lock().paths, index) = Some((d, Arc::clone(&c)));
        Some(c)
    }

    /// Operation `index`'s path: the stored one when fresh, else planned now (a rest
    /// finishing from the stock reads [`Results::stock_before`], itself from this store).
    ///
    /// # Errors
    /// [`ComputeError`] naming the operation and what is wrong, or the cancel.
    pub fn get_or_compute(
        &self,
        project: &Project,
        part: &Workpiece,
        index: usize,
        progress: &Progress,
    ) -> Result<Arc<Computed>, ComputeError> {
        let keys = Self::keys(project, part);
        self.get_or_compute_keyed(project, part, &keys, index, progress)
    }

    /// [`Results::get_or_compute`] with the keys already built.
    ///
    /// # Errors
    /// As [`Results::get_or_compute`].
    pub fn get_or_compute_keyed(
        &self,
        project: &Project,
        part: &Workpiece,
        keys: &Keys,
        index: usize,
        progress: &Progress,
    ) -> Result<Arc<Computed>, ComputeError> {
        if index >= project.operations.len() || index >= keys.operations.len() {
            return Err(ComputeError::NoOperation {
                index,
                count: project.operations.len(),
            });
        }
        if let Some(c) = self.fresh(keys, index) {
            return Ok(c);
        }
        let computed = pipeline::compute_in(project, index, part, self, keys, progress)?;
        self.computations.fetch_add(1, Ordering::Relaxed);
        self.insert(keys, index, computed)
            .ok_or(ComputeError::NoOperation {
                index,
                count: project.operations.len(),
            })
    }

    /// The in-process stock before operation `index` (`index` = the number of operations:
    /// after them all): the project's stock cut by the posted runs of the operations before
    /// it, each cut once and memoised.
    ///
    /// # Errors
    /// An earlier operation's [`ComputeError`], or [`ComputeError::Plan`] naming the operation
    /// whose run could not be cut.
    pub fn stock_before(
        &self,
        project: &Project,
        part: &Workpiece,
        index: usize,
        progress: &Progress,
    ) -> Result<Arc<InProcessStock>, ComputeError> {
        let keys = Self::keys(project, part);
        self.stock_before_keyed(project, part, &keys, index, progress)
    }

    /// The in-process stock once operation `index` has run ([`Results::stock_before`] of
    /// `index + 1`).
    ///
    /// # Errors
    /// As [`Results::stock_before`].
    pub fn stock_after(
        &self,
        project: &Project,
        part: &Workpiece,
        index: usize,
        progress: &Progress,
    ) -> Result<Arc<InProcessStock>, ComputeError> {
        self.stock_before(project, part, index + 1, progress)
    }

    fn fresh_stock(&self, keys: &Keys, k: usize) -> Option<Arc<InProcessStock>> {
        let want = *keys.stocks.get(k)?;
        match self.lock().stocks.get(k) {
            Some(Some((d, s))) if *d == want => Some(Arc::clone(s)),
            _ => None,
        }
    }

    /// [`Results::stock_before`] with the keys already built.
    ///
    /// # Errors
    /// As [`Results::stock_before`].
    pub fn stock_before_keyed(
        &self,
        project: &Project,
        part: &Workpiece,
        keys: &Keys,
        index: usize,
        progress: &Progress,
    ) -> Result<Arc<InProcessStock>, ComputeError> {
        let n = project.operations.len();
        if index > n || index >= keys.stocks.len() {
            return Err(ComputeError::NoOperation { index, count: n });
        }
        // The latest fresh stock at or before `index`, else the raw one.
        let mut start = index;
        let mut stock = loop {
            if let Some(s) = self.fresh_stock(keys, start) {
                break s;
            }
            if start == 0 {
                let raw = Arc::new(raw_stock(project, part)?);
                *slot(&mut self.lock().stocks, 0) = Some((keys.stocks[0], Arc::clone(&raw)));
                break raw;
            }
            start -= 1;
        };
        for k in start..index {
            if progress.is_cancelled() {
                return Err(ComputeError::Cancelled);
            }
            let computed = self.get_or_compute_keyed(project, part, keys, k, progress)?;
            let linked = self.linked_over(keys, k, &computed, &stock);
            let next = Arc::new(cut_operation(project, k, &linked, &stock, progress)?);
            self.stock_cuts.fetch_add(1, Ordering::Relaxed);
            *slot(&mut self.lock().stocks, k + 1) = Some((keys.stocks[k + 1], Arc::clone(&next)));
            stock = next;
        }
        Ok(stock)
    }

    /// Operation `index`'s linked path: its stored path ([`Results::get_or_compute`]) with
    /// the rapids lifted over the in-process stock before it ([`Results::stock_before`]) by
    /// [`super::rapids::link`]; what is posted, run and cut into the stock after it. Kept under
    /// (the path's digest, the stock-before digest), so it is fresh exactly while both are,
    /// and the path's own digest does not depend on the earlier operations' stock.
    ///
    /// # Errors
    /// As [`Results::get_or_compute`] and [`Results::stock_before`].
    pub fn linked(
        &self,
        project: &Project,
        part: &Workpiece,
        index: usize,
        progress: &Progress,
    ) -> Result<Arc<Linked>, ComputeError> {
        let keys = Self::keys(project, part);
        self.linked_keyed(project, part, &keys, index, progress)
    }

    /// [`Results::linked`] with the keys already built.
    ///
    /// # Errors
    /// As [`Results::linked`].
    pub fn linked_keyed(
        &self,
        project: &Project,
        part: &Workpiece,
        keys: &Keys,
        index: usize,
        progress: &Progress,
    ) -> Result<Arc<Linked>, ComputeError> {
        let computed = self.get_or_compute_keyed(project, part, keys, index, progress)?;
        if let Some(l) = self.fresh_linked(keys, index) {
            return Ok(l);
        }
        let stock = self.stock_before_keyed(project, part, keys, index, progress)?;
        Ok(self.linked_over(keys, index, &computed, &stock))
    }

    /// Operation `index`'s machining run as the project posts it ([`super::posting::run_operation`])
    /// of its linked path ([`Results::linked`]), as tool number = its library index + 1.
    ///
    /// # Errors
    /// As [`Results::linked`]; the post's error as [`ComputeError::Plan`].
    pub fn run_operation(
        &self,
        project: &Project,
        part: &Workpiece,
        index: usize,
        corner_tolerance_mm: f64,
        progress: &Progress,
    ) -> Result<super::MachiningRun, ComputeError> {
        let linked = self.linked(project, part, index, progress)?;
        let op = &project.operations[index];
        let tool_number = u32::try_from(op.tool() + 1).unwrap_or(1);
        super::posting::run_operation(
            project,
            index,
            &linked.toolpath,
            tool_number,
            corner_tolerance_mm,
        )
        .map_err(|e| ComputeError::Plan {
            operation: op.name().to_string(),
            message: e.to_string(),
        })
    }

    fn fresh_linked(&self, keys: &Keys, k: usize) -> Option<Arc<Linked>> {
        let want = (*keys.operations.get(k)?, *keys.stocks.get(k)?);
        match self.lock().linked.get(k) {
            Some(Some((d, l))) if *d == want => Some(Arc::clone(l)),
            _ => None,
        }
    }

    /// Operation `k`'s linked path over `stock` (the stock before it under `keys`), memoised.
    fn linked_over(
        &self,
        keys: &Keys,
        k: usize,
        computed: &Computed,
        stock: &InProcessStock,
    ) -> Arc<Linked> {
        if let Some(l) = self.fresh_linked(keys, k) {
            return l;
        }
        let l = Arc::new(super::rapids::link(&computed.toolpath, &stock.dexels));
        if let (Some(&d), Some(&s)) = (keys.operations.get(k), keys.stocks.get(k)) {
            *slot(&mut self.lock().linked, k) = Some(((d, s), Arc::clone(&l)));
        }
        l
    }
}

/// The project's stock (the part's box + 2 mm when none is set) on the one grid.
fn raw_stock(project: &Project, part: &Workpiece) -> Result<InProcessStock, ComputeError> {
    let shape = StockShape::of(&project.stock, &part.mesh.bbox());
    let resolution = stock_resolution_mm(&shape.bounds(), STOCK_MAX_RAYS);
    let dexels = DexelStock::new(
        vec![shape],
        resolution,
        DexelMode::Z,
        crate::simulation::DEFAULT_MEMORY_LIMIT_BYTES,
    )
    .map_err(|e| ComputeError::Plan {
        operation: "stock".into(),
        message: format!("the project's stock cannot be built: {e}"),
    })?;
    Ok(InProcessStock {
        dexels,
        last_cut: None,
        from_posted_runs: true,
        notes: Vec::new(),
    })
}

/// The moves of operation `index`'s posted run of `toolpath` (its linked path,
/// [`Results::linked`], in part coordinates) in part coordinates, without the lead-in from
/// wherever the machine stood ([`super::MachiningRun::commanded_move_plan`]), or (with a note
/// saying why) of the tool path itself where it cannot be posted or planned.
///
/// # Errors
/// The move plan's error, as text.
pub fn operation_moves(
    project: &Project,
    index: usize,
    toolpath: &Toolpath,
    step: &StepOptions,
) -> Result<(MovePlan, Option<Diagnostic>), String> {
    let op = project
        .operations
        .get(index)
        .ok_or_else(|| format!("no operation number {index}"))?;
    let tool_number = u32::try_from(op.tool() + 1).unwrap_or(1);
    let fallback = |why: String| -> Result<(MovePlan, Option<Diagnostic>), String> {
        let plan = plan_toolpath(toolpath, step).map_err(|e| e.to_string())?;
        Ok((
            plan,
            Some(Diagnostic::warning(
                format!("operation '{}'", op.name()),
                format!("its tool path was cut instead of its posted run: {why}"),
            )),
        ))
    };
    let run = match super::posting::run_operation(
        project,
        index,
        toolpath,
        tool_number,
        RUN_CORNER_TOLERANCE_MM,
    ) {
        Ok(run) => run,
        Err(e) => return fallback(e.to_string()),
    };
    if let Err(e) = &run.motion {
        return fallback(e.to_string());
    }
    let (setup, machine) = match super::posting::resolve_operation(project, index) {
        Ok((s, m, _)) => (s, m),
        Err(e) => return fallback(e.to_string()),
    };
    let mut plan = run.commanded_move_plan(&machine, step)?;
    // The run is posted in the operation's setup frame (`posting::run_operation`): program =
    // R·(part − origin), so part = Rᵀ·program + origin.
    let placement = match super::setups::Placement::of(&setup, None) {
        Ok(p) => p,
        Err(e) => return fallback(format!("setup '{}': {e}", setup.name)),
    };
    to_part(&mut plan, placement.rotation.transpose(), placement.origin);
    Ok((plan, None))
}

/// `plan` taken from program coordinates back into part coordinates: `rotation · p + by` for
/// points, `rotation · a` for tool axes.
fn to_part(plan: &mut MovePlan, rotation: glam::DMat3, by: DVec3) {
    for m in &mut plan.moves {
        for pose in [&mut m.start, &mut m.end] {
            pose.tip = rotation * pose.tip + by;
            pose.axis = rotation * pose.axis;
        }
    }
    for s in &mut plan.steps {
        s.from = rotation * s.from + by;
        s.to = rotation * s.to + by;
        s.axis = rotation * s.axis;
    }
}

/// `before` cut by operation `index`'s posted run of its linked path.
fn cut_operation(
    project: &Project,
    index: usize,
    linked: &Linked,
    before: &InProcessStock,
    progress: &Progress,
) -> Result<InProcessStock, ComputeError> {
    let op = &project.operations[index];
    let err = |message: String| ComputeError::Plan {
        operation: op.name().to_string(),
        message: format!("cutting its run into the in-process stock: {message}"),
    };
    let cutter: &Cutter = &project
        .tools
        .get(op.tool())
        .ok_or_else(|| ComputeError::NoTool {
            operation: op.name().to_string(),
            tool: op.tool(),
        })?
        .cutter;
    let step = StepOptions::for_resolution(before.resolution_mm(), cutter.flute_length);
    let (plan, note) = operation_moves(project, index, &linked.toolpath, &step).map_err(err)?;
    let mut dexels = before.dexels.clone();
    let quiet = Progress::new();
    let report = simulate(&mut dexels, cutter, &plan, &SimOptions::default(), &quiet)
        .map_err(|e| err(e.to_string()))?;
    if progress.is_cancelled() {
        return Err(ComputeError::Cancelled);
    }
    let mut notes = before.notes.clone();
    notes.extend(note.iter().cloned());
    notes.extend(linked.diagnostics.iter().map(|d| Diagnostic {
        place: Some(format!("operation '{}'", op.name())),
        ..d.clone()
    }));
    Ok(InProcessStock {
        dexels,
        last_cut: Some(report),
        from_posted_runs: before.from_posted_runs && note.is_none(),
        notes,
    })
}

/// Operation `index` simulated as the result store cuts it: its posted run
/// ([`operation_moves`]) into the in-process stock before it
/// ([`Results::stock_before`], the earlier operations' runs), measured against the part.
/// The stock after it is the store's, so the simulation, rest finishing and forces see one.
///
/// # Errors
/// The operation's or an earlier one's [`super::pipeline::ComputeError`], or the measure's
/// [`SimError`] as text.
pub fn simulate_in_process(
    store: &Results,
    project: &Project,
    part: &Workpiece,
    index: usize,
    progress: &Progress,
) -> Result<Simulated, String> {
    let after = store
        .stock_after(project, part, index, progress)
        .map_err(|e| e.to_string())?;
    let reports = after.last_cut.iter().cloned().collect();
    measured(&after.dexels, &part.mesh, reports, progress).map_err(|e| e.to_string())
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
    /// As [`super::simulate::simulate_toolpaths`].
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
