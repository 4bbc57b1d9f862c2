//! Forces along a tool path or program. Every fed move is cut into pieces of at most
//! [`PathOptions::sample_spacing_mm`]; at each piece's midpoint the engagement (per axial disk,
//! the entry and exit angles) is read from the material as it is before the move
//! ([`super::stock::engagement_at`]), one revolution is sampled at the move's feed per tooth
//! `f_t = F / (n·N)`, and the piece's forces are turned into the machine frame (x̂ along the
//! horizontal feed, ŷ = ẑ × x̂). Then the move is removed from the material
//! ([`Workpiece::cut_move`]) and the next move is read.
//!
//! Per move: peak (signed value of largest magnitude) and time-weighted mean of F_x, F_y, F_z
//! in the machine frame, the resultant, torque and spindle power, the immersion of each disk
//! at the move's heaviest piece, and the limits exceeded. Moves the side-cutting model does not
//! cover are marked and left without forces: rapids, plunges (no horizontal feed: the bottom
//! edges cut) and tilted tool axes.

use glam::DVec3;

use super::cut::{Engagement, Mode};
use super::mill::EndMill;
use super::revolution::{RevolutionOptions, revolution};
use super::stock::{Material, SampleOptions, engagement_at};
use super::{Coefficients, Force, ForceError};

/// Material that a move can be removed from: the stock simulation behind the force model.
pub trait Workpiece: Material {
    /// Remove move `index` (of the moves the forces are computed for) from the material.
    ///
    /// # Errors
    /// [`ForceError::Input`] when the removal fails (the message says why).
    fn cut_move(&mut self, index: usize) -> Result<(), ForceError>;
}

/// One straight piece of a move with a fixed tool axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathStep {
    /// Tip at the start, mm.
    pub from: DVec3,
    /// Tip at the end, mm.
    pub to: DVec3,
    /// Unit tool axis.
    pub axis: DVec3,
}

/// One move of the path (a G-code block or the way to a tool-path pose).
#[derive(Clone, Debug, PartialEq)]
pub struct PathMove {
    /// G-code line or tool-path pose index.
    pub block: usize,
    /// A rapid move.
    pub rapid: bool,
    /// Programmed feed, mm/min (0 when unknown).
    pub feed_mm_per_min: f64,
    /// Spindle speed, rev/min (0 when stopped or unknown).
    pub spindle_rpm: f64,
    /// The move as straight steps (arcs as chords).
    pub steps: Vec<PathStep>,
}

impl PathMove {
    /// Length of the move, mm.
    #[must_use]
    pub fn length_mm(&self) -> f64 {
        self.steps.iter().map(|s| s.from.distance(s.to)).sum()
    }
}

/// Coefficients per milling mode (the library may hold one set per mode).
#[derive(Clone, Debug, PartialEq)]
pub struct ModeCoefficients {
    /// For pieces cutting mostly on the up-milling side (φ < π/2).
    pub up: Coefficients,
    /// For pieces cutting mostly on the down-milling side.
    pub down: Coefficients,
    /// For pieces engaged from φ = 0 to π (slots).
    pub slot: Coefficients,
}

impl ModeCoefficients {
    /// The set for `mode`.
    #[must_use]
    pub fn get(&self, mode: Mode) -> &Coefficients {
        match mode {
            Mode::Up => &self.up,
            Mode::Down => &self.down,
            Mode::Slot => &self.slot,
        }
    }
}

/// Limits to flag (none: not checked).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Limits {
    /// Largest resultant force, N.
    pub max_force_n: Option<f64>,
    /// Largest cutting torque, N·m.
    pub max_torque_nm: Option<f64>,
    /// Largest spindle power, W.
    pub max_power_w: Option<f64>,
}

/// How the path is sampled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathOptions {
    /// Longest piece of a move, mm.
    pub sample_spacing_mm: f64,
    /// At most this many pieces per move (a longer move gets longer pieces).
    pub max_pieces_per_move: usize,
    /// Disk height and angular step of the engagement query.
    pub sample: SampleOptions,
    /// Rotation steps per revolution.
    pub revolution_steps: usize,
    /// Flute length above the tip that can cut, mm.
    pub flute_length_mm: f64,
    /// Limits to flag.
    pub limits: Limits,
}

impl Default for PathOptions {
    fn default() -> Self {
        Self {
            sample_spacing_mm: 0.5,
            max_pieces_per_move: 400,
            sample: SampleOptions::default(),
            revolution_steps: 360,
            flute_length_mm: 30.0,
            limits: Limits::default(),
        }
    }
}

/// What the model did with a move.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MoveClass {
    /// Fed, horizontal feed, in material somewhere.
    Cut,
    /// Fed but never in material.
    Air,
    /// Rapid: no forces computed.
    Rapid,
    /// No horizontal feed (plunge or zero-length): bottom-edge forces are not modelled.
    Plunge,
    /// Tool axis not vertical: not modelled.
    Tilted,
}

/// One disk's immersion: the first entry and last exit angle of its engaged arcs.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct DiskImmersion {
    /// Bottom of the disk above the tip, mm.
    pub z0_mm: f64,
    /// Top of the disk above the tip, mm.
    pub z1_mm: f64,
    /// Entry angle (clockwise from the left normal of the feed), degrees.
    pub entry_deg: f64,
    /// Exit angle, degrees.
    pub exit_deg: f64,
    /// Number of separate engaged arcs.
    pub arcs: usize,
}

/// The forces of one piece of a move.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// Index of the move.
    pub move_index: usize,
    /// Start of the piece, mm.
    pub from: DVec3,
    /// End of the piece, mm.
    pub to: DVec3,
    /// The engagement at the piece's midpoint (empty disks: in air).
    pub engagement: Engagement,
    /// Milling mode the coefficients were chosen for (none in air).
    pub mode: Option<Mode>,
    /// Spindle speed, rev/min.
    pub spindle_rpm: f64,
    /// Mean force over a revolution, machine frame, N.
    pub mean: Force,
    /// Signed peaks over a revolution, machine frame, N.
    pub peak: Force,
    /// Largest resultant, N.
    pub peak_resultant_n: f64,
    /// Mean torque, N·m.
    pub mean_torque_nm: f64,
    /// Largest torque, N·m.
    pub peak_torque_nm: f64,
}

impl Piece {
    /// Length, mm.
    #[must_use]
    pub fn length_mm(&self) -> f64 {
        self.from.distance(self.to)
    }

    /// Whether any disk is engaged.
    #[must_use]
    pub fn engaged(&self) -> bool {
        self.engagement.disks.iter().any(|d| !d.arcs.is_empty())
    }
}

/// The forces of one move.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MoveForces {
    /// Index of the move.
    pub move_index: usize,
    /// G-code line or tool-path pose index.
    pub block: usize,
    /// What the model did with it.
    pub class: MoveClass,
    /// Length, mm.
    pub length_mm: f64,
    /// Time at the programmed feed, s.
    pub time_s: f64,
    /// Feed per tooth, mm (0 when not cutting).
    pub feed_per_tooth_mm: f64,
    /// Time-weighted mean force, machine frame, N.
    pub mean: Force,
    /// Signed peak force, machine frame, N.
    pub peak: Force,
    /// Time-weighted mean resultant of the per-piece mean forces, N.
    pub mean_resultant_n: f64,
    /// Largest resultant, N.
    pub peak_resultant_n: f64,
    /// Time-weighted mean torque, N·m.
    pub mean_torque_nm: f64,
    /// Largest torque, N·m.
    pub peak_torque_nm: f64,
    /// Mean spindle power, W.
    pub mean_power_w: f64,
    /// Largest spindle power, W.
    pub peak_power_w: f64,
    /// Axial depth engaged (top of the highest engaged disk), mm.
    pub axial_depth_mm: f64,
    /// Immersion per disk at the piece of largest resultant.
    pub immersion: Vec<DiskImmersion>,
    /// Limits exceeded (`force`, `torque`, `power`).
    pub limits_exceeded: Vec<&'static str>,
}

/// Totals over the path.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Totals {
    /// Moves in material.
    pub cutting_moves: usize,
    /// Time in material at the programmed feeds, s.
    pub cutting_time_s: f64,
    /// Largest resultant, N, and the block where it occurs.
    pub peak_resultant_n: f64,
    /// Block of the largest resultant.
    pub peak_resultant_block: usize,
    /// Largest torque, N·m.
    pub peak_torque_nm: f64,
    /// Largest spindle power, W.
    pub peak_power_w: f64,
    /// Mean spindle power over the cutting time, W.
    pub mean_power_w: f64,
    /// Cutting energy, J.
    pub energy_j: f64,
    /// Moves exceeding a limit.
    pub moves_over_limits: usize,
    /// Moves not modelled (plunges, tilted axes).
    pub moves_not_modelled: usize,
}

/// Forces along a whole path.
#[derive(Clone, Debug, PartialEq)]
pub struct PathForces {
    /// Per move.
    pub moves: Vec<MoveForces>,
    /// Per piece, in order (only of fed, modelled moves).
    pub pieces: Vec<Piece>,
    /// Totals.
    pub totals: Totals,
}

/// Milling mode of an engagement: slot when some disk is engaged near both φ = 0 and φ = π,
/// else up or down by which half holds more engaged angle (None in air).
#[must_use]
pub fn classify(engagement: &Engagement, tolerance: f64) -> Option<Mode> {
    let (mut up, mut down, mut slot) = (0.0, 0.0, false);
    let half = std::f64::consts::FRAC_PI_2;
    for d in &engagement.disks {
        let a = d.arcs.as_slice();
        let (Some(first), Some(last)) = (a.first(), a.last()) else {
            continue;
        };
        slot |= first.0 <= tolerance && last.1 >= std::f64::consts::PI - tolerance;
        for &(s, e) in a {
            up += (e.min(half) - s).max(0.0);
            down += (e - s.max(half)).max(0.0);
        }
    }
    if up + down <= 0.0 {
        None
    } else if slot {
        Some(Mode::Slot)
    } else if up >= down {
        Some(Mode::Up)
    } else {
        Some(Mode::Down)
    }
}

/// The force of the feed frame (x along `x_dir`, y = ẑ × x) in the machine frame.
fn to_machine(f: Force, x_dir: DVec3) -> Force {
    let y = DVec3::Z.cross(x_dir);
    let v = x_dir * f.fx + y * f.fy + DVec3::Z * f.fz;
    Force {
        fx: v.x,
        fy: v.y,
        fz: v.z,
    }
}

fn signed_max(a: f64, b: f64) -> f64 {
    if b.abs() > a.abs() { b } else { a }
}

/// The forces of one engagement over a revolution, machine frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PieceResult {
    /// Mean force, N.
    pub mean: Force,
    /// Signed peaks per component, N.
    pub peak: Force,
    /// Largest resultant, N.
    pub peak_resultant_n: f64,
    /// Mean torque, N·m.
    pub mean_torque_nm: f64,
    /// Largest torque, N·m.
    pub peak_torque_nm: f64,
}

/// Forces of one engagement at its feed per tooth, in the machine frame (x̂ = `x_dir`).
///
/// # Errors
/// As [`revolution`].
pub fn piece_forces(
    mill: &EndMill,
    coefficients: &Coefficients,
    engagement: &Engagement,
    x_dir: DVec3,
    steps: usize,
) -> Result<PieceResult, ForceError> {
    let rev = revolution(
        mill,
        coefficients,
        engagement,
        &RevolutionOptions {
            steps,
            spindle_rpm: None,
        },
    )?;
    let mut peak = Force::default();
    for s in &rev.samples {
        let m = to_machine(s.force, x_dir);
        peak = Force {
            fx: signed_max(peak.fx, m.fx),
            fy: signed_max(peak.fy, m.fy),
            fz: signed_max(peak.fz, m.fz),
        };
    }
    Ok(PieceResult {
        mean: to_machine(rev.mean, x_dir),
        peak,
        peak_resultant_n: rev.peak_resultant_n,
        mean_torque_nm: rev.mean_torque_nm,
        peak_torque_nm: rev.peak_torque_nm,
    })
}

fn check_options(o: &PathOptions) -> Result<(), ForceError> {
    super::check_range("sample spacing", o.sample_spacing_mm, 1e-3, 1000.0, "mm")?;
    super::check_range("flute length", o.flute_length_mm, 1e-3, 2000.0, "mm")?;
    if !(1..=100_000).contains(&o.max_pieces_per_move) {
        return Err(ForceError::Input(
            "pieces per move must be 1 to 100000".into(),
        ));
    }
    Ok(())
}

/// The straight pieces of a move: each step cut into pieces no longer than `spacing`.
fn split_move(m: &PathMove, spacing: f64, max_pieces: usize) -> Vec<(DVec3, DVec3)> {
    let len = m.length_mm();
    // A count: bounded by max_pieces.
    #[allow(clippy::cast_precision_loss)]
    let spacing = spacing.max(len / max_pieces as f64);
    let mut out = Vec::new();
    for s in &m.steps {
        let l = s.from.distance(s.to);
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let n = (l / spacing).ceil().clamp(1.0, 1e6) as usize;
        for k in 0..n {
            let (a, b) = (k as f64 / n as f64, (k + 1) as f64 / n as f64);
            out.push((s.from.lerp(s.to, a), s.from.lerp(s.to, b)));
        }
    }
    out
}

/// The class of a move before looking at the material.
fn pre_class(m: &PathMove) -> Option<MoveClass> {
    if m.rapid {
        return Some(MoveClass::Rapid);
    }
    if m.steps
        .iter()
        .any(|s| (s.axis - DVec3::Z).length_squared() > 1e-18)
    {
        return Some(MoveClass::Tilted);
    }
    let horizontal: f64 = m
        .steps
        .iter()
        .map(|s| (s.to - s.from).truncate().length())
        .sum();
    (horizontal <= 1e-9).then_some(MoveClass::Plunge)
}

/// Evaluator with a one-entry cache (consecutive pieces of a steady cut share an engagement).
struct Evaluator<'a> {
    mill: &'a EndMill,
    coefficients: &'a ModeCoefficients,
    steps: usize,
    last: Option<(Engagement, DVec3, Mode, PieceResult)>,
}

impl Evaluator<'_> {
    fn eval(
        &mut self,
        e: &Engagement,
        x_dir: DVec3,
    ) -> Result<Option<(Mode, PieceResult)>, ForceError> {
        let Some(mode) = classify(e, 2.0 * std::f64::consts::PI / 180.0) else {
            return Ok(None);
        };
        if let Some((le, lx, lm, r)) = &self.last
            && le == e
            && *lx == x_dir
            && *lm == mode
        {
            return Ok(Some((mode, *r)));
        }
        let r = piece_forces(self.mill, self.coefficients.get(mode), e, x_dir, self.steps)?;
        self.last = Some((e.clone(), x_dir, mode, r));
        Ok(Some((mode, r)))
    }
}

/// Forces along `moves`, reading and cutting `workpiece` move by move.
///
/// # Errors
/// [`ForceError::Move`] for a fed move in material without a spindle speed or feed,
/// [`ForceError::Input`] for bad options or a failed removal.
pub fn path_forces(
    workpiece: &mut impl Workpiece,
    mill: &EndMill,
    coefficients: &ModeCoefficients,
    moves: &[PathMove],
    options: &PathOptions,
) -> Result<PathForces, ForceError> {
    check_options(options)?;
    let mut out = PathForces {
        moves: Vec::with_capacity(moves.len()),
        pieces: Vec::new(),
        totals: Totals::default(),
    };
    let mut eval = Evaluator {
        mill,
        coefficients,
        steps: options.revolution_steps,
        last: None,
    };
    for (index, m) in moves.iter().enumerate() {
        let mf = match pre_class(m) {
            Some(class) => empty_move(index, m, class),
            None => move_forces(&mut *workpiece, &mut eval, index, m, options, &mut out)?,
        };
        out.moves.push(mf);
        workpiece.cut_move(index)?;
    }
    out.totals = totals(&out.moves);
    Ok(out)
}

fn empty_move(index: usize, m: &PathMove, class: MoveClass) -> MoveForces {
    let length_mm = m.length_mm();
    MoveForces {
        move_index: index,
        block: m.block,
        class,
        length_mm,
        time_s: move_time(m, length_mm),
        feed_per_tooth_mm: 0.0,
        mean: Force::default(),
        peak: Force::default(),
        mean_resultant_n: 0.0,
        peak_resultant_n: 0.0,
        mean_torque_nm: 0.0,
        peak_torque_nm: 0.0,
        mean_power_w: 0.0,
        peak_power_w: 0.0,
        axial_depth_mm: 0.0,
        immersion: Vec::new(),
        limits_exceeded: Vec::new(),
    }
}

fn move_time(m: &PathMove, length_mm: f64) -> f64 {
    if m.feed_mm_per_min > 0.0 {
        length_mm / m.feed_mm_per_min * 60.0
    } else {
        0.0
    }
}

/// The immersion of each disk of `e`.
#[must_use]
pub fn immersion(e: &Engagement) -> Vec<DiskImmersion> {
    e.disks
        .iter()
        .map(|d| {
            let a = d.arcs.as_slice();
            DiskImmersion {
                z0_mm: d.z0,
                z1_mm: d.z1,
                entry_deg: a.first().map_or(0.0, |x| x.0.to_degrees()),
                exit_deg: a.last().map_or(0.0, |x| x.1.to_degrees()),
                arcs: a.len(),
            }
        })
        .collect()
}

fn move_forces(
    material: &mut impl Workpiece,
    eval: &mut Evaluator<'_>,
    index: usize,
    m: &PathMove,
    options: &PathOptions,
    out: &mut PathForces,
) -> Result<MoveForces, ForceError> {
    let mut mf = empty_move(index, m, MoveClass::Air);
    let teeth = eval.mill.flutes() as f64;
    let ft = if m.spindle_rpm > 0.0 {
        m.feed_mm_per_min / (m.spindle_rpm * teeth)
    } else {
        0.0
    };
    let omega = m.spindle_rpm * std::f64::consts::TAU / 60.0;
    let (mut wsum, mut mean, mut mres, mut mtorque) = (0.0, Force::default(), 0.0, 0.0);
    let mut best = -1.0;
    for (a, b) in split_move(m, options.sample_spacing_mm, options.max_pieces_per_move) {
        let dir = (b - a).truncate();
        let Some(x_dir) = dir.try_normalize().map(|d| d.extend(0.0)) else {
            continue;
        };
        let mid = a.lerp(b, 0.5);
        let mut e = engagement_at(
            &*material,
            eval.mill,
            mid,
            x_dir,
            options.flute_length_mm,
            ft.max(1e-9),
            &options.sample,
        )?;
        let engaged = e.disks.iter().any(|d| !d.arcs.is_empty());
        if engaged && !(ft > 0.0) {
            return Err(ForceError::Move {
                block: m.block,
                message: "the move cuts material without a feed and a spindle speed (give F \
                          and S in the program, or --rpm)"
                    .into(),
            });
        }
        e.feed_per_tooth = ft;
        let result = if engaged { eval.eval(&e, x_dir)? } else { None };
        let (mode, r) = match result {
            Some((mode, r)) => (Some(mode), r),
            None => (None, PieceResult::default()),
        };
        let (pm, pp, pr, mt, pt) = (
            r.mean,
            r.peak,
            r.peak_resultant_n,
            r.mean_torque_nm,
            r.peak_torque_nm,
        );
        let w = a.distance(b);
        wsum += w;
        mean += Force {
            fx: pm.fx * w,
            fy: pm.fy * w,
            fz: pm.fz * w,
        };
        mres += pm.resultant() * w;
        mtorque += mt * w;
        if mode.is_some() {
            mf.class = MoveClass::Cut;
            mf.peak = Force {
                fx: signed_max(mf.peak.fx, pp.fx),
                fy: signed_max(mf.peak.fy, pp.fy),
                fz: signed_max(mf.peak.fz, pp.fz),
            };
            mf.peak_torque_nm = mf.peak_torque_nm.max(pt);
            mf.axial_depth_mm = e
                .disks
                .iter()
                .rev()
                .find(|d| !d.arcs.is_empty())
                .map_or(mf.axial_depth_mm, |d| d.z1.max(mf.axial_depth_mm));
            if pr > best {
                best = pr;
                mf.peak_resultant_n = pr;
                mf.immersion = immersion(&e);
            }
        }
        out.pieces.push(Piece {
            move_index: index,
            from: a,
            to: b,
            engagement: e,
            mode,
            spindle_rpm: m.spindle_rpm,
            mean: pm,
            peak: pp,
            peak_resultant_n: pr,
            mean_torque_nm: mt,
            peak_torque_nm: pt,
        });
    }
    if wsum > 0.0 {
        mf.mean = Force {
            fx: mean.fx / wsum,
            fy: mean.fy / wsum,
            fz: mean.fz / wsum,
        };
        mf.mean_resultant_n = mres / wsum;
        mf.mean_torque_nm = mtorque / wsum;
    }
    if mf.class == MoveClass::Cut {
        mf.feed_per_tooth_mm = ft;
        mf.mean_power_w = mf.mean_torque_nm * omega;
        mf.peak_power_w = mf.peak_torque_nm * omega;
        mf.limits_exceeded = exceeded(&mf, &options.limits);
    }
    Ok(mf)
}

fn exceeded(m: &MoveForces, l: &Limits) -> Vec<&'static str> {
    let mut v = Vec::new();
    if l.max_force_n.is_some_and(|x| m.peak_resultant_n > x) {
        v.push("force");
    }
    if l.max_torque_nm.is_some_and(|x| m.peak_torque_nm > x) {
        v.push("torque");
    }
    if l.max_power_w.is_some_and(|x| m.peak_power_w > x) {
        v.push("power");
    }
    v
}

fn totals(moves: &[MoveForces]) -> Totals {
    let mut t = Totals::default();
    for m in moves {
        match m.class {
            MoveClass::Cut => {
                t.cutting_moves += 1;
                t.cutting_time_s += m.time_s;
                t.energy_j += m.mean_power_w * m.time_s;
                if m.peak_resultant_n > t.peak_resultant_n {
                    t.peak_resultant_n = m.peak_resultant_n;
                    t.peak_resultant_block = m.block;
                }
                t.peak_torque_nm = t.peak_torque_nm.max(m.peak_torque_nm);
                t.peak_power_w = t.peak_power_w.max(m.peak_power_w);
                t.moves_over_limits += usize::from(!m.limits_exceeded.is_empty());
            }
            MoveClass::Plunge | MoveClass::Tilted => t.moves_not_modelled += 1,
            MoveClass::Air | MoveClass::Rapid => {}
        }
    }
    if t.cutting_time_s > 0.0 {
        t.mean_power_w = t.energy_j / t.cutting_time_s;
    }
    t
}
