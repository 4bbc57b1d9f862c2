//! The panel's keyboard, as LinuxCNC AXIS: arrows jog X and Y, Page Up/Down Z, `[`/`]` the
//! first rotary axis, Home homes, Escape stops, F1 is the e-stop. A jog key starts a
//! continuous jog when pressed and stops it when released (JOG), or moves one increment per
//! press (INC); auto-repeat is ignored, so nothing queues.

use egui::Key;

use super::OperatorPanel;
use crate::control::Action;

/// The key table shown on the panel: keys and what they do.
pub const KEY_HELP: &[(&str, &str)] = &[
    ("← →", "X − / +"),
    ("↓ ↑", "Y − / +"),
    ("PgDn PgUp", "Z − / +"),
    ("[ ]", "rotary − / +"),
    ("Home", "home all"),
    ("Esc", "stop"),
    ("F1", "e-stop"),
];

impl OperatorPanel {
    /// The jog axis and direction of `key`, if it is a jog key.
    fn jog_key(&self, key: Key) -> Option<(char, f64)> {
        let rotary = self
            .control
            .as_ref()
            .and_then(|c| c.machine().axes.iter().find(|a| a.is_rotary()))
            .map(|a| a.name);
        match key {
            Key::ArrowLeft => Some(('X', -1.0)),
            Key::ArrowRight => Some(('X', 1.0)),
            Key::ArrowDown => Some(('Y', -1.0)),
            Key::ArrowUp => Some(('Y', 1.0)),
            Key::PageDown => Some(('Z', -1.0)),
            Key::PageUp => Some(('Z', 1.0)),
            Key::OpenBracket => rotary.map(|r| (r, -1.0)),
            Key::CloseBracket => rotary.map(|r| (r, 1.0)),
            _ => None,
        }
    }

    /// Act on this frame's keys, while the pointer is over the panel and no text field has
    /// the keyboard (a jog key's release acts always).
    pub(super) fn keys(&mut self, ui: &egui::Ui) {
        let over = match (self.panel_rect, ui.ctx().pointer_hover_pos()) {
            (Some(r), Some(p)) => r.contains(p),
            _ => false,
        };
        let keys: Vec<(Key, bool, bool)> = ui.input(|i| {
            i.events
                .iter()
                .filter_map(|e| match e {
                    egui::Event::Key {
                        key,
                        pressed,
                        repeat,
                        ..
                    } => Some((*key, *pressed, *repeat)),
                    _ => None,
                })
                .collect()
        });
        // A release always ends the held jog, wherever the pointer went meanwhile.
        let listening = over && !ui.ctx().egui_wants_keyboard_input();
        for (key, pressed, repeat) in keys {
            if repeat || (pressed && !listening) {
                continue;
            }
            self.key(key, pressed);
        }
    }

    fn key(&mut self, key: Key, pressed: bool) {
        if let Some((axis, direction)) = self.jog_key(key) {
            if pressed {
                self.jog_press(axis, direction);
            } else if self.jog_held == Some((axis, direction)) {
                self.release_jog();
            }
            return;
        }
        if !pressed {
            return;
        }
        match key {
            Key::Home => {
                self.act(Action::Home);
                if self.message.is_none() {
                    self.mode = super::PanelMode::Ref;
                }
            }
            Key::Escape => {
                self.jog_held = None;
                self.act(Action::Stop);
            }
            Key::F1 => {
                self.jog_held = None;
                self.act(Action::EStop);
            }
            _ => {}
        }
    }
}
