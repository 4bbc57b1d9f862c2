//! The playback bar under the viewport: play and pause the active tool path on its clock (time at
//! feed), scrub, step pose by pose, choose the speed; the path is drawn up to the current pose and
//! the tool stands there.

use super::super::command::{Command, PlaybackCommand};
use super::super::widgets::duration_text;
use super::super::widgets::grouped;

/// The playback speeds offered, × real time at feed.
pub const SPEEDS: [f64; 7] = [1.0, 2.0, 5.0, 10.0, 50.0, 200.0, 1000.0];

/// What the playback bar shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaybackView {
    /// Clock time, s (`None`: the whole path is shown).
    pub t_s: Option<f64>,
    /// Duration of the path at feed, s.
    pub duration_s: f64,
    /// Is the clock running?
    pub playing: bool,
    /// Speed, × real time.
    pub speed: f64,
    /// The pose reached at `t_s`.
    pub pose: usize,
    /// Number of poses.
    pub poses: usize,
    /// The clock is the jerk-limited plan of the posted program (else the programmed feeds).
    pub planned: bool,
}

/// The playback bar.
pub fn playback_ui(ui: &mut egui::Ui, view: &PlaybackView, commands: &mut Vec<Command>) {
    ui.horizontal(|ui| {
        if view.playing {
            if ui.button("Pause").on_hover_text("Pause (Space)").clicked() {
                commands.push(Command::Playback(PlaybackCommand::Pause));
            }
        } else if ui.button("Play").on_hover_text("Play (Space)").clicked() {
            commands.push(Command::Playback(PlaybackCommand::Play));
        }
        if ui.button("<").on_hover_text("Back one pose (,)").clicked() {
            commands.push(Command::Playback(PlaybackCommand::Step(-1)));
        }
        if ui
            .button(">")
            .on_hover_text("Forward one pose (.)")
            .clicked()
        {
            commands.push(Command::Playback(PlaybackCommand::Step(1)));
        }
        if ui
            .add_enabled(view.t_s.is_some(), egui::Button::new("All"))
            .on_hover_text("Show the whole path")
            .clicked()
        {
            commands.push(Command::Playback(PlaybackCommand::Reset));
        }
        let mut t = view.t_s.unwrap_or(view.duration_s);
        let width = (ui.available_width() - 520.0).max(80.0);
        ui.spacing_mut().slider_width = width;
        let r = ui.add(
            egui::Slider::new(&mut t, 0.0..=view.duration_s.max(1e-9))
                .show_value(false)
                .trailing_fill(true),
        );
        if r.changed() {
            commands.push(Command::Playback(PlaybackCommand::Seek(t)));
        }
        ui.label(
            egui::RichText::new(format!(
                "{} / {}",
                duration_text(t),
                duration_text(view.duration_s)
            ))
            .monospace(),
        )
        .on_hover_text(if view.planned {
            "Planned time: the jerk-limited motion of the posted program"
        } else {
            "Time at the programmed feeds (post the operation for the planned time)"
        });
        ui.label(
            egui::RichText::new(format!(
                "pose {} / {}",
                grouped((view.pose + 1).min(view.poses)),
                grouped(view.poses)
            ))
            .monospace()
            .weak(),
        );
        if ui
            .add_enabled(view.t_s.is_some(), egui::Button::new("Stock here"))
            .on_hover_text("Simulate the stock up to this pose (after the earlier operations)")
            .clicked()
        {
            commands.push(Command::SimulateToPlayback);
        }
        let mut speed = view.speed;
        egui::ComboBox::from_id_salt("playback speed")
            .selected_text(format!("×{}", view.speed))
            .width(64.0)
            .show_ui(ui, |ui| {
                for s in SPEEDS {
                    ui.selectable_value(&mut speed, s, format!("×{s}"));
                }
            });
        if speed != view.speed {
            commands.push(Command::Playback(PlaybackCommand::Speed(speed)));
        }
    });
}
