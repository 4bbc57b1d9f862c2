//! The job's stock simulated setup after setup: each setup's tool paths (setup frame, from
//! [`super::job::plan_in_setup`]) cut in order into that setup's starting stock, and a setup
//! whose stock is [`SetupStock::Previous`] starts from what the previous setup left: the cut
//! stock's closed column mesh ([`DexelStock::closed_mesh`], watertight, its volume the dexels'
//! material) moved through the part's motion between the two frames
//! ([`setups::motion_between`]) and ray-cast into a new Z-dexel grid at the previous spacing
//! (the mesh's bounding-volume hierarchy answers each ray, [`StockShape::mesh`]).
//!
//! The same run tests the tool assembly against the setup's workholding with the one check
//! planning uses ([`crate::checks::collide::first_hit`], [`workholding_hits`]), along the moves
//! the simulation cuts ([`MovePlan`], whose `block` is the pose reached, or the program line
//! for a posted program), so the pose a jaw is hit at is the one planning names.

use std::path::Path;

use super::Project;
use super::setups::{self, Placement, SetupStock, transform_mesh};
use super::simulate::{Simulated, SimulationSettings, measured, stock_resolution_mm};
use crate::checks::collide::{Hit, Obstacle, assembly, first_hit};
use crate::diagnostics::Progress;
use crate::geometry::Aabb;
use crate::geometry::mesh::TriMesh;
use crate::import::Workpiece;
use crate::simulation::{
    DexelMode, DexelStock, MovePlan, SimOptions, SimReport, StepOptions, StockShape, plan_toolpath,
    simulate,
};
use crate::toolpath::Toolpath;

/// Largest step along a move between two collision tests against the workholding, mm.
pub const COLLISION_STEP_MM: f64 = 0.25;

/// A contact of the tool assembly with a setup's workholding, on one operation's moves.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkholdingHit {
    /// The block of the move where the contact is: the tool-path pose reached (or, on a
    /// program's plan, the 1-based line).
    pub block: usize,
    /// The check's own record (its `index` counts the placements tested).
    pub hit: Hit,
}

/// One setup simulated.
#[derive(Clone, Debug)]
pub struct SetupSimulation {
    /// Setup index.
    pub setup: usize,
    /// Whether it started from the previous setup's cut stock.
    pub carried: bool,
    /// Dexel spacing, mm.
    pub resolution_mm: f64,
    /// Triangles of the carried stock mesh (0 when not carried).
    pub carried_triangles: usize,
    /// Volume of the carried stock mesh itself (divergence theorem), mm³ (0 when not carried).
    pub carried_mesh_volume_mm3: f64,
    /// Material at the start (the dexels'), mm³.
    pub start_volume_mm3: f64,
    /// Material at the end, mm³.
    pub end_volume_mm3: f64,
    /// Removed by this setup's paths, mm³.
    pub removed_volume_mm3: f64,
    /// Contacts of shank or holder with the stock the simulation saw.
    pub stock_collisions: usize,
    /// Deepest cut into the part (setup frame), mm; 0 without paths.
    pub max_gouge_mm: f64,
    /// Per operation (path), the first contact with the workholding.
    pub workholding: Vec<Option<WorkholdingHit>>,
    /// The stock at the end (setup frame).
    pub stock: DexelStock,
    /// The cut stock's top and its signed deviation from the part (setup frame), as the
    /// single-operation simulation measures it; `None` for a setup without paths.
    pub measured: Option<Simulated>,
}

/// The workholding obstacles of setup `index` in its frame.
///
/// # Errors
/// As [`setups::workholding_meshes`], or a mesh the check cannot take.
pub fn obstacles(
    project: &Project,
    index: usize,
    placements: &[Placement],
    part_bounds: &Aabb,
    base: &Path,
) -> Result<Vec<Obstacle>, String> {
    let meshes = setups::workholding_meshes(project, index, placements, part_bounds, base)?;
    project.setups[index]
        .workholding
        .iter()
        .zip(&meshes)
        .map(|(w, m)| Obstacle::new(w.kind_name(), m))
        .collect()
}

/// The workholding of setup `index` as the virtual control's table extras: each item's mesh
/// moved from the setup frame (the program's frame) into table coordinates by the work
/// offset's origin `offset_mm` (table = program + offset, the rotaries at zero), so the
/// control's AUTO run tests the same jaws planning and the simulation test
/// ([`crate::machine::collision::TableShape::Mesh`]).
///
/// # Errors
/// As [`setups::workholding_meshes`], or an item whose mesh is empty, named.
pub fn control_fixtures(
    project: &Project,
    index: usize,
    placements: &[Placement],
    part_bounds: &Aabb,
    base: &Path,
    offset_mm: glam::DVec3,
) -> Result<Vec<crate::machine::collision::TableExtra>, String> {
    let meshes = setups::workholding_meshes(project, index, placements, part_bounds, base)?;
    project.setups[index]
        .workholding
        .iter()
        .zip(meshes)
        .map(|(w, m)| {
            let mesh = crate::machine::BodyMesh {
                vertices: m.positions.iter().map(|&p| p + offset_mm).collect(),
                triangles: m.triangles,
            };
            crate::machine::collision::TableExtra::mesh(w.kind_name(), mesh)
                .ok_or_else(|| format!("{}: an empty or broken mesh", w.kind_name()))
        })
        .collect()
}

/// The first contact of each tool path (setup frame) with the obstacles, as planning sees
/// it: along the poses; the block is the pose index.
#[must_use]
pub fn workholding_hits(paths: &[Toolpath], obstacles: &[Obstacle]) -> Vec<Option<WorkholdingHit>> {
    paths
        .iter()
        .map(|tp| {
            let moves: Vec<_> = tp.poses.iter().map(|p| (p.tip, p.axis)).collect();
            first_hit(
                &assembly(&tp.tool.cutter),
                obstacles,
                &moves,
                COLLISION_STEP_MM,
            )
            .map(|hit| WorkholdingHit {
                block: hit.index,
                hit,
            })
        })
        .collect()
}

/// The first contact of `cutter`'s assembly with the obstacles along the moves of `plan`
/// (the first move's start, then each move's end): the block is the move's (pose or line).
#[must_use]
pub fn workholding_hit_on_plan(
    cutter: &crate::tools::Cutter,
    obstacles: &[Obstacle],
    plan: &MovePlan,
) -> Option<WorkholdingHit> {
    let first = plan.moves.first()?;
    let mut poses = vec![(first.start.tip, first.start.axis)];
    poses.extend(plan.moves.iter().map(|m| (m.end.tip, m.end.axis)));
    let hit = first_hit(&assembly(cutter), obstacles, &poses, COLLISION_STEP_MM)?;
    let block = match hit.index {
        0 => first.block.saturating_sub(1),
        k => plan.moves[k - 1].block,
    };
    Some(WorkholdingHit { block, hit })
}

/// The starting stock of a setup that does not carry: its solid, a box when the solid is
/// its own bounding box (every box stock in an axis-aligned frame), else the mesh.
fn fresh_shape(solid: TriMesh) -> Result<StockShape, String> {
    let b = solid.bbox();
    let size = b.max - b.min;
    let box_volume = size.x * size.y * size.z;
    if (solid.signed_volume() - box_volume).abs() <= 1e-9 * box_volume.max(1.0) {
        Ok(StockShape::Box {
            min: b.min,
            max: b.max,
        })
    } else {
        StockShape::mesh(solid).map_err(|e| format!("stock: {e}"))
    }
}

/// Simulate setups `0..paths.len()` in order: `paths[s]` are setup `s`'s tool paths in its
/// frame (its operations in order). A setup whose stock is the previous one's starts from
/// what that setup left; the others from their own starting solid
/// ([`setups::stock_solid`]). Each setup's paths are tested against its workholding
/// (bodies read relative to `base`).
///
/// # Errors
/// A message naming the setup: its stock, frame or workholding cannot be built, or the
/// simulation fails (memory, a bad tool, a cancel).
pub fn simulate_job(
    project: &Project,
    part: &Workpiece,
    base: &Path,
    paths: &[Vec<Toolpath>],
    settings: &SimulationSettings,
    progress: &Progress,
) -> Result<Vec<SetupSimulation>, String> {
    let placements = setups::placements(project, Some(part))?;
    let bounds = part.mesh.bbox();
    let mut out: Vec<SetupSimulation> = Vec::with_capacity(paths.len());
    for (s, setup_paths) in paths.iter().enumerate() {
        let setup = project
            .setups
            .get(s)
            .ok_or_else(|| format!("no setup {} (there are {})", s + 1, project.setups.len()))?;
        let named = |e: String| format!("setup {} ('{}'): {e}", s + 1, setup.name);
        let here = placements[s];
        let previous = if setup.stock == SetupStock::Previous {
            out.last()
        } else {
            None
        };
        let (mut dexels, carried_triangles, carried_mesh_volume_mm3) = match previous {
            Some(prev) => {
                let mesh = prev.stock.closed_mesh();
                let (r, t) = setups::motion_between(&placements[s - 1], &here);
                let moved = transform_mesh(&mesh, r, t);
                let (n, v) = (moved.triangles.len(), moved.signed_volume());
                let shape = StockShape::mesh(moved).map_err(|e| named(format!("carried {e}")))?;
                let dexels = DexelStock::new(
                    vec![shape],
                    prev.resolution_mm,
                    DexelMode::Z,
                    settings.memory_limit_bytes,
                )
                .map_err(|e| named(e.to_string()))?;
                (dexels, n, v)
            }
            None => {
                let solid = setups::stock_solid(project, s, &placements, &bounds).map_err(named)?;
                let shape = fresh_shape(solid).map_err(named)?;
                let resolution = settings
                    .resolution_mm
                    .unwrap_or_else(|| stock_resolution_mm(&shape.bounds(), settings.max_rays));
                let dexels = DexelStock::new(
                    vec![shape],
                    resolution,
                    DexelMode::Z,
                    settings.memory_limit_bytes,
                )
                .map_err(|e| named(e.to_string()))?;
                (dexels, 0, 0.0)
            }
        };
        let start = dexels.volume_mm3();
        let obstacles = obstacles(project, s, &placements, &bounds, base).map_err(named)?;
        let mut reports: Vec<SimReport> = Vec::new();
        let mut workholding = Vec::new();
        for tp in setup_paths {
            let cutter = &tp.tool.cutter;
            let step = StepOptions::for_resolution(dexels.resolution_mm, cutter.flute_length);
            let plan = plan_toolpath(tp, &step).map_err(|e| named(e.to_string()))?;
            workholding.push(workholding_hit_on_plan(cutter, &obstacles, &plan));
            reports.push(
                simulate(&mut dexels, cutter, &plan, &SimOptions::default(), progress)
                    .map_err(|e| named(e.to_string()))?,
            );
        }
        let (stock_collisions, max_gouge_mm, measured) = if reports.is_empty() {
            (0, 0.0, None)
        } else {
            let mesh = transform_mesh(&part.mesh, here.rotation, -(here.rotation * here.origin));
            let m =
                measured(&dexels, &mesh, reports, progress).map_err(|e| named(e.to_string()))?;
            (m.report.collisions.len(), m.max_gouge_mm, Some(m))
        };
        let end = dexels.volume_mm3();
        out.push(SetupSimulation {
            setup: s,
            carried: previous.is_some(),
            resolution_mm: dexels.resolution_mm,
            carried_triangles,
            carried_mesh_volume_mm3,
            start_volume_mm3: start,
            end_volume_mm3: end,
            removed_volume_mm3: start - end,
            stock_collisions,
            max_gouge_mm,
            workholding,
            stock: dexels,
            measured,
        });
    }
    Ok(out)
}

/// The whole job simulated as `talas job --simulate` runs it: every setup's operations planned
/// in its frame ([`super::job::plan_in_setup`]) and linked over the stock the paths before them
/// leave ([`super::job::link_setup`]), then [`simulate_job`]. Progress runs over the planning
/// (the first half) and is checked between operations.
///
/// # Errors
/// The first operation that cannot be planned, named with its setup; a setup that cannot be
/// linked or simulated; "cancelled".
pub fn simulate_whole_job(
    project: &Project,
    part: &Workpiece,
    base: &Path,
    settings: &SimulationSettings,
    progress: &Progress,
) -> Result<Vec<SetupSimulation>, String> {
    let total = project.operations.len().max(1) as f64;
    let mut done = 0usize;
    let mut paths = Vec::with_capacity(project.setups.len());
    for (s, setup) in project.setups.iter().enumerate() {
        let named = |e: String| format!("setup {} ('{}'): {e}", s + 1, setup.name);
        let mut planned = Vec::with_capacity(setup.operations.len());
        for &op in &setup.operations {
            progress.check().map_err(|_| "cancelled".to_string())?;
            let c = super::job::plan_in_setup(project, op, part, &Progress::new())
                .map_err(|e| named(format!("operation {}: {e}", op + 1)))?;
            planned.push(c.toolpath);
            done += 1;
            progress.set(0.5 * done as f64 / total);
        }
        if !planned.is_empty() {
            let (linked, _) =
                super::job::link_setup(project, s, part, &planned, false, &Progress::new())
                    .map_err(named)?;
            planned = linked.into_iter().map(|l| l.toolpath).collect();
        }
        paths.push(planned);
    }
    simulate_job(project, part, base, &paths, settings, progress)
}
