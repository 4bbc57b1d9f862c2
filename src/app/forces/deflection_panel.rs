//! The deflection of the tool at the pose it stands at (picked, hovered or played back): for
//! the heaviest engaged piece of the move into that pose,
//! [`crate::project::forces::pose_deflection`] gives the tool's deflection along the depth of
//! cut at the rotation of the largest resultant force, and the wall (form) error the flutes
//! leave along the depth. Both are plotted in µm against the height above the tool tip in mm,
//! with the beam the tool is taken as: a cantilever clamped at the holder face (the tool's
//! length out of the holder), the fluted part a round bar of 0.8·D, the shank above it, carbide
//! (E = 600 GPa), the rigid tool's forces applied per disk, static (no runout, no dynamics).

use egui::Color32;
use egui_plot::{Legend, Line, Plot};

use crate::force::deflection::{BeamSpec, CARBIDE_E, FLUTE_DIAMETER_RATIO};
use crate::force::path::ModeCoefficients;
use crate::project::forces::{ForceTimeline, PoseDeflection, pose_deflection};
use crate::tools::Cutter;

/// Heights of a profile.
pub const PROFILE_POINTS: usize = 41;

/// The beam the tool is taken as: its own diameters and flute length, its length out of the
/// holder as the overhang, carbide, the fluted section at 0.8·D.
#[must_use]
pub fn beam_of(cutter: &Cutter) -> BeamSpec {
    BeamSpec {
        diameter: cutter.diameter,
        flute_length: cutter.flute_length,
        shank_diameter: cutter.shank_diameter,
        overhang: cutter.overall_length,
        youngs_modulus: CARBIDE_E,
        flute_diameter_ratio: FLUTE_DIAMETER_RATIO,
    }
}

/// The stated beam assumptions, with the tool's numbers and units.
#[must_use]
pub fn assumptions(beam: &BeamSpec) -> String {
    format!(
        "Tool as a cantilever clamped at the holder face: overhang {:.1} mm; fluted part {:.1} mm \
         long as a round bar of {:.2} × D = {:.2} mm; shank Ø {:.2} mm; E = {:.0} GPa (carbide). \
         Forces of the rigid tool at the rotation of the largest resultant, applied per 0.5 mm \
         disk; static (no runout, no dynamics, no holder or spindle compliance).",
        beam.overhang,
        beam.flute_length,
        beam.flute_diameter_ratio,
        beam.flute_diameter_ratio * beam.diameter,
        beam.shank_diameter,
        beam.youngs_modulus / 1000.0,
    )
}

/// The profile of `pose` (cached by the caller per pose).
///
/// # Errors
/// The engine's message.
pub fn compute(
    timeline: &ForceTimeline,
    pose: usize,
    cutter: &Cutter,
    coefficients: &ModeCoefficients,
) -> Result<Option<PoseDeflection>, String> {
    pose_deflection(
        timeline,
        pose,
        cutter,
        coefficients,
        &beam_of(cutter),
        PROFILE_POINTS,
    )
    .map_err(|e| e.to_string())
}

/// Draw the profile (or why there is none).
pub fn ui(
    ui: &mut egui::Ui,
    pose: Option<usize>,
    profile: Option<&Result<Option<PoseDeflection>, String>>,
) {
    let Some(pose) = pose else {
        ui.label("Pick a pose (click the path or the plot) to see the tool's deflection there.");
        return;
    };
    let d = match profile {
        Some(Ok(Some(d))) => d,
        Some(Ok(None)) => {
            ui.label(format!("Pose {pose}: the move into it cuts no material."));
            return;
        }
        Some(Err(e)) => {
            ui.colored_label(ui.visuals().warn_fg_color, format!("Deflection: {e}"));
            return;
        }
        None => return,
    };
    let tip = d.deflection.first().copied();
    let wall_max = d
        .wall
        .iter()
        .map(|p| p.error_um)
        .fold(0.0f64, |a, e| if e.abs() > a.abs() { e } else { a });
    ui.label(format!(
        "Pose {pose} · {} milling · depth {:.2} mm · at φ = {:.0}°: tip deflection {:.1} µm \
         (feed {:.1} µm, normal {:.1} µm) · largest wall error {:.1} µm ({})",
        d.mode.name(),
        d.depth_mm,
        d.phi_rad.to_degrees(),
        tip.map_or(0.0, |p| p.dx_um.hypot(p.dy_um)),
        tip.map_or(0.0, |p| p.dx_um),
        tip.map_or(0.0, |p| p.dy_um),
        wall_max,
        if wall_max < 0.0 {
            "overcut"
        } else {
            "undercut"
        },
    ));
    ui.label(egui::RichText::new(assumptions(&d.beam)).small().weak());
    let height = ui.available_height().clamp(140.0, 220.0);
    ui.columns(2, |cols| {
        let defl = |f: fn(&crate::force::deflection::DeflectionPoint) -> f64| -> Vec<[f64; 2]> {
            d.deflection.iter().map(|p| [f(p), p.z_mm]).collect()
        };
        Plot::new("talas_force_deflection")
            .height(height)
            .legend(Legend::default())
            .x_axis_label("deflection (µm)")
            .y_axis_label("height above tip (mm)")
            .include_x(0.0)
            .include_y(0.0)
            .show(&mut cols[0], |p| {
                p.line(Line::new("|δ|", defl(|q| q.dx_um.hypot(q.dy_um))).color(Color32::WHITE));
                p.line(
                    Line::new("δ feed", defl(|q| q.dx_um)).color(Color32::from_rgb(235, 90, 80)),
                );
                p.line(
                    Line::new("δ normal", defl(|q| q.dy_um))
                        .color(Color32::from_rgb(110, 200, 110)),
                );
            });
        let wall: Vec<[f64; 2]> = d.wall.iter().map(|p| [p.error_um, p.z_mm]).collect();
        Plot::new("talas_force_wall")
            .height(height)
            .legend(Legend::default())
            .x_axis_label("wall error (µm; − overcut, + undercut)")
            .y_axis_label("height above tip (mm)")
            .include_x(0.0)
            .include_y(0.0)
            .show(&mut cols[1], |p| {
                p.line(Line::new("wall error", wall).color(Color32::from_rgb(232, 180, 60)));
            });
    });
}
