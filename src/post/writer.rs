//! The program text: blocks with line numbers, modal words written only when they change.

use super::{Dialect, PostOptions, Target};
use crate::machine::{KinematicsKind, Machine};
use crate::toolpath::{MoveKind, Toolpath};

/// Feed modes (modal).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FeedMode {
    PerMinute,
    InverseTime,
}

/// Builds the program text.
pub(super) struct Writer<'a> {
    d: &'a Dialect,
    machine: &'a Machine,
    toolpath: &'a Toolpath,
    options: &'a PostOptions,
    numbered: bool,
    next_number: u64,
    lines: Vec<String>,
    /// For each line, the tool-path pose whose motion it writes.
    pose_of_line: Vec<Option<usize>>,
    /// For each line, the operation it belongs to.
    op_of_line: Vec<usize>,
    /// The operation the blocks written now belong to.
    current_op: usize,
    /// The pose the blocks written now belong to (set by [`Self::motion`]).
    current_pose: Option<usize>,
    /// Last written X Y Z, tilt, rotary words (formatted values).
    last: [Option<String>; 5],
    last_motion: Option<String>,
    feed_mode: FeedMode,
    last_feed: Option<String>,
    /// Last written plane code (`G17`, `G18`, `G19`); `None` before the first arc or cycle.
    last_plane: Option<String>,
    /// The tilted work plane while blocks are written in its coordinates.
    plane_on: Option<PlaneOn>,
    /// The last machine X Y Z written (tracked under a tilted plane).
    machine_last: glam::DVec3,
    /// The blocks that cancel the active plane.
    plane_off_blocks: Vec<String>,
}

/// An active tilted work plane: program point `s` is at plane point `wᵀ·s`, and machine
/// point `m` is program point `mᵀ·(m − t)` at the plane's rotary angles.
#[derive(Clone, Copy, Debug)]
struct PlaneOn {
    w: glam::DMat3,
    m: glam::DMat3,
    t: glam::DVec3,
}

impl<'a> Writer<'a> {
    pub(super) fn new(
        d: &'a Dialect,
        machine: &'a Machine,
        toolpath: &'a Toolpath,
        options: &'a PostOptions,
    ) -> Self {
        Self {
            d,
            machine,
            toolpath,
            options,
            numbered: options.line_numbers.unwrap_or(d.line_numbers),
            next_number: u64::from(d.line_number_start),
            lines: Vec::new(),
            pose_of_line: Vec::new(),
            op_of_line: Vec::new(),
            current_op: 0,
            current_pose: None,
            last: Default::default(),
            last_motion: None,
            feed_mode: FeedMode::PerMinute,
            last_feed: None,
            last_plane: None,
            plane_on: None,
            machine_last: glam::DVec3::ZERO,
            plane_off_blocks: Vec::new(),
        }
    }

    /// Blocks are written in a tilted work plane's coordinates.
    pub(super) fn tilted(&self) -> bool {
        self.plane_on.is_some()
    }

    /// Plane coordinates of machine point `m`.
    fn plane_point(p: &PlaneOn, m: glam::DVec3) -> glam::DVec3 {
        p.w.transpose() * (p.m.transpose() * (m - p.t))
    }

    /// Under a tilted plane: a rapid to machine point `m` (the plane words that change).
    fn machine_rapid(&mut self, m: glam::DVec3) {
        let Some(p) = self.plane_on else { return };
        let q = Self::plane_point(&p, m);
        let dl = self.d.decimals_linear;
        let values = [
            self.d.number(q.x, dl),
            self.d.number(q.y, dl),
            self.d.number(q.z, dl),
            String::new(),
            String::new(),
        ];
        let words = self.axis_words(&values, [true, true, true, false, false]);
        self.machine_last = m;
        if !words.is_empty() {
            let code = self.motion_code(&self.d.rapid.clone());
            self.block(&join(code, &words));
        }
    }

    /// A rapid along machine Z to `z` (the safe retract), in the plane's words when tilted.
    fn z_retract(&mut self, z: f64, only_if_moved: bool) {
        let d = self.d;
        let zs = d.number(z, d.decimals_linear);
        if self.plane_on.is_some() {
            let m = glam::DVec3::new(self.machine_last.x, self.machine_last.y, z);
            self.machine_rapid(m);
            return;
        }
        if only_if_moved && self.last[2].as_deref() == Some(zs.as_str()) {
            return;
        }
        let code = self.motion_code(&d.rapid);
        self.block(&join(code, &[format!("Z{zs}")]));
        self.last[2] = Some(zs);
        self.machine_last.z = z;
    }

    /// Set the options' tilted work plane in the dialect's words, the tool turned onto it at
    /// target `t`'s rotary angles (none for an explicit dialect or no plane).
    fn plane_start(&mut self, t: &Target) -> bool {
        let Some(w) = self.options.work_plane else {
            return false;
        };
        let Some((on, off, r)) =
            super::workplane::blocks(self.d, self.d.work_plane, &w, t.joints.tilt_rad)
        else {
            return false;
        };
        self.blocks(&on);
        let (m, tr) = self.machine.machine_from_table(&t.joints);
        let values = self.values(t);
        // The rotary axes are where the control turned them: never written under the plane.
        for i in [3usize, 4] {
            if let (Some(slot), Some(v)) = (self.last.get_mut(i), values.get(i)) {
                *slot = Some(v.clone());
            }
        }
        // Plane words are written afresh.
        for slot in self.last.iter_mut().take(3) {
            *slot = None;
        }
        self.last_motion = None;
        self.plane_on = Some(PlaneOn { w: r, m, t: tr });
        self.plane_off_blocks = off;
        true
    }

    /// Cancel the tilted plane (its blocks), back to machine words.
    fn plane_stop(&mut self) {
        if self.plane_on.take().is_some() {
            let off = std::mem::take(&mut self.plane_off_blocks);
            self.blocks(&off);
            for slot in self.last.iter_mut().take(3) {
                *slot = None;
            }
            self.last_motion = None;
        }
    }

    fn fill(&self, template: &str) -> String {
        template
            .replace("{program}", &self.options.program_name)
            .replace("{machine}", &inert(&self.machine.name))
            .replace("{dialect}", &inert(&self.d.name))
            .replace("{tool_spec}", &inert(&self.toolpath.tool.spec))
            .replace("{tool}", &self.options.tool_number.to_string())
            .replace("{rpm}", &format!("{:.0}", self.options.spindle_rpm))
            .replace("{work_offset}", &self.options.work_offset)
    }

    /// One output line, tagged with the current pose.
    fn push_line(&mut self, line: String) {
        self.lines.push(line);
        self.pose_of_line.push(self.current_pose);
        self.op_of_line.push(self.current_op);
    }

    /// One block (numbered, with the block end) or a raw `!` line.
    fn block(&mut self, text: &str) {
        if let Some(raw) = text.strip_prefix('!') {
            let line = self.fill(raw);
            self.push_line(line);
            return;
        }
        let body = self.fill(text);
        let line = if self.numbered {
            let n = self.next_number;
            self.next_number += u64::from(self.d.line_number_step);
            format!("N{n} {body}{}", self.d.block_end)
        } else {
            format!("{body}{}", self.d.block_end)
        };
        self.push_line(line);
    }

    fn blocks(&mut self, templates: &[String]) {
        for t in templates {
            self.block(t);
            self.note_plane(t);
        }
    }

    /// With a setup plane ([`PostOptions::setup_plane`]), the last plane word a template
    /// names is the plane in force.
    fn note_plane(&mut self, template: &str) {
        if self.options.setup_plane.is_none() {
            return;
        }
        let body = self.fill(template);
        if let Some(code) = body
            .split_whitespace()
            .rfind(|w| matches!(*w, "G17" | "G18" | "G19"))
        {
            self.last_plane = Some(code.to_string());
        }
    }

    /// The dialect's setup blocks, their `G17` replaced by the setup plane's code (written
    /// after them when none names `G17`).
    fn setup_blocks(&mut self) {
        let d = self.d;
        let Some(plane) = self.options.setup_plane else {
            self.blocks(&d.setup);
            return;
        };
        let code = plane_code(plane);
        let mut named = false;
        for t in &d.setup {
            if t.contains("G17") {
                named = true;
                self.blocks(&[t.replace("G17", code)]);
            } else {
                self.blocks(std::slice::from_ref(t));
            }
        }
        if !named {
            self.blocks(&[code.to_string()]);
        }
    }

    fn comment(&mut self, text: &str) {
        // Comment text may not hold the closing mark or a newline.
        let clean: String = self
            .fill(text)
            .chars()
            .map(|c| match c {
                '(' | ')' | '\n' | '\r' | ';' => ' ',
                c => c,
            })
            .collect();
        let line = format!("{}{}{}", self.d.comment_open, clean, self.d.comment_close);
        self.push_line(line);
    }

    fn five_axis(&self) -> bool {
        self.machine.kinematics != KinematicsKind::ThreeAxis
    }

    fn letters(&self) -> [char; 5] {
        let (t, c) = self.machine.rotary_names().unwrap_or(('A', 'C'));
        ['X', 'Y', 'Z', t, c]
    }

    fn values(&self, t: &Target) -> [String; 5] {
        let (dl, da) = (self.d.decimals_linear, self.d.decimals_angle);
        let xyz = match &self.plane_on {
            Some(p) => Self::plane_point(p, t.joints.xyz),
            None => t.joints.xyz,
        };
        [
            self.d.number(xyz.x, dl),
            self.d.number(xyz.y, dl),
            self.d.number(xyz.z, dl),
            self.d.number(t.joints.tilt_rad.to_degrees(), da),
            self.d.number(t.joints.rotary_rad.to_degrees(), da),
        ]
    }

    /// Axis words of the selected axes that differ from the last written ones (and remember
    /// them).
    fn axis_words(&mut self, values: &[String; 5], select: [bool; 5]) -> Vec<String> {
        let letters = self.letters();
        let mut words = Vec::new();
        for i in 0..5 {
            let (Some(v), Some(&l), Some(&on)) = (values.get(i), letters.get(i), select.get(i))
            else {
                continue;
            };
            if !on || (i >= 3 && !self.five_axis()) {
                continue;
            }
            if let Some(slot) = self.last.get_mut(i)
                && slot.as_deref() != Some(v.as_str())
            {
                words.push(format!("{l}{v}"));
                *slot = Some(v.clone());
            }
        }
        words
    }

    fn rapid_words(&mut self, t: &Target, select: [bool; 5]) {
        if self.plane_on.is_some() {
            let pick = |i: usize, v: f64, last: f64| if select[i] { v } else { last };
            let (m, l) = (t.joints.xyz, self.machine_last);
            let target = glam::DVec3::new(pick(0, m.x, l.x), pick(1, m.y, l.y), pick(2, m.z, l.z));
            self.machine_rapid(target);
            return;
        }
        for (i, (on, v)) in select
            .iter()
            .zip(t.joints.xyz.to_array())
            .enumerate()
            .take(3)
        {
            if *on {
                let mut a = self.machine_last.to_array();
                if let Some(slot) = a.get_mut(i) {
                    *slot = v;
                }
                self.machine_last = glam::DVec3::from_array(a);
            }
        }
        let values = self.values(t);
        let words = self.axis_words(&values, select);
        if !words.is_empty() {
            let code = self.motion_code(&self.d.rapid.clone());
            self.block(&join(code, &words));
        }
    }

    fn motion_code(&mut self, code: &str) -> Option<String> {
        if self.last_motion.as_deref() == Some(code) {
            None
        } else {
            self.last_motion = Some(code.to_string());
            Some(code.to_string())
        }
    }

    /// Header, setup, tool change, TCP, spindle, coolant, safe retract.
    pub(super) fn preamble(&mut self) {
        let d = self.d;
        self.blocks(&d.header);
        for c in &d.header_comments {
            self.comment(c);
        }
        let options = self.options;
        for c in &options.comments {
            self.comment(c);
        }
        self.setup_blocks();
        self.tool_blocks();
        self.z_retract(self.options.clearance_z_mm, false);
    }

    /// Tool change, TCP, spindle and coolant of the current operation.
    fn tool_blocks(&mut self) {
        let d = self.d;
        self.blocks(&d.tool_change);
        if self.options.tcp {
            self.blocks(&d.tcp_on);
        }
        if self.options.spindle_rpm > 0.0 {
            self.blocks(&d.spindle_on);
        }
        if self.options.coolant {
            self.blocks(&d.coolant_on);
        }
    }

    /// Between operations: retract, TCP off, feed per minute, the dialect's blocks between
    /// operations (optional stop, coolant and spindle off), then the next operation's tool
    /// change, spindle and coolant and a retract; every axis word is written again after it.
    pub(super) fn next_operation(
        &mut self,
        index: usize,
        toolpath: &'a Toolpath,
        options: &'a PostOptions,
    ) {
        let d = self.d;
        self.z_retract(self.options.clearance_z_mm, true);
        // A tilted plane is cancelled before the tool change.
        self.plane_stop();
        if self.options.tcp {
            self.blocks(&d.tcp_off);
        }
        if self.feed_mode == FeedMode::InverseTime {
            self.block(&d.feed_per_minute);
            self.feed_mode = FeedMode::PerMinute;
        }
        self.blocks(&d.between_operations);
        self.current_op = index;
        self.toolpath = toolpath;
        self.options = options;
        self.comment(&format!(
            "OPERATION {} TOOL T{} {}",
            index + 1,
            options.tool_number,
            inert(&toolpath.tool.spec)
        ));
        self.tool_blocks();
        self.last = Default::default();
        self.last_motion = None;
        self.last_feed = None;
        self.z_retract(options.clearance_z_mm, false);
    }

    /// At clearance: rotaries first, then X Y.
    pub(super) fn approach(&mut self, t: &Target) {
        // A 3+2 setup in a dialect with its own plane: set it (the control turns the axes).
        if self.plane_on.is_none() && !self.plane_start(t) {
            self.rapid_words(t, [false, false, false, true, true]);
        }
        self.rapid_words(t, [true, true, false, false, false]);
    }

    /// A safe move to `t` (at tool-path pose `pose`): retract to the clearance, turn the
    /// rotaries, position X Y, feed in (only the feed-in is tagged with the pose).
    pub(super) fn reposition(&mut self, t: &Target, feed: f64, pose: usize) {
        self.z_retract(self.options.clearance_z_mm, false);
        self.approach(t);
        self.motion(t, MoveKind::Plunge, feed, 0.0, pose);
    }

    /// A rapid to `t` that turns the rotaries (tagged with tool-path pose `pose`): up to the
    /// clearance height unless already there, rotaries, X Y, then down to `t`'s Z.
    pub(super) fn turn_at_clearance(&mut self, t: &Target, pose: usize) {
        self.z_retract(self.options.clearance_z_mm, true);
        self.current_pose = Some(pose);
        self.approach(t);
        self.rapid_words(t, [false, false, true, false, false]);
        self.current_pose = None;
    }

    /// The block reaching `t` by a move of `kind` (tip travel `tip_len` mm), on the way to the
    /// tool-path pose `pose`.
    pub(super) fn motion(
        &mut self,
        t: &Target,
        kind: MoveKind,
        feed: f64,
        tip_len: f64,
        pose: usize,
    ) {
        self.current_pose = Some(pose);
        self.motion_block(t, kind, feed, tip_len);
        self.current_pose = None;
    }

    fn motion_block(&mut self, t: &Target, kind: MoveKind, feed: f64, tip_len: f64) {
        let values = self.values(t);
        if kind == MoveKind::Rapid {
            self.rapid_words(t, [true; 5]);
            return;
        }
        // Per rotary word: its travel (deg) and the least minutes its axis needs for it at the
        // machine's velocity limit.
        let letters = self.letters();
        let rotary: Vec<(f64, f64)> = [3usize, 4]
            .iter()
            .filter_map(|&i| {
                let new: f64 = values.get(i)?.parse().ok()?;
                let old: f64 = self.last.get(i)?.as_deref()?.parse().ok()?;
                let deg = (new - old).abs();
                let deg_per_min = self
                    .machine
                    .axis(*letters.get(i)?)
                    .map(|a| a.velocity.to_degrees() * 60.0)
                    .filter(|v| *v > 0.0 && v.is_finite());
                Some((deg, deg_per_min.map_or(0.0, |v| deg / v)))
            })
            .collect();
        let rotary_deg = rotary.iter().map(|r| r.0).fold(0.0, f64::max);
        let rotary_minutes = rotary.iter().map(|r| r.1).fold(0.0, f64::max);
        let words = self.axis_words(&values, [true; 5]);
        self.machine_last = t.joints.xyz;
        if words.is_empty() {
            return;
        }
        let d = self.d;
        let mut modal = Vec::new();
        let inverse = rotary_deg > 0.0 && !self.options.tcp && self.five_axis();
        let feed_word = if inverse {
            // Minutes of the move: the tip's travel over the part at the feed, but no less than
            // the rotary axes need at their velocity limits. (It once read the rotary travel in
            // degrees at the feed as deg/min, which halved the real feed wherever the table
            // turned: 70 % of the blocks of an iso-scallop path on trt-ac.)
            let minutes = (tip_len / feed).max(rotary_minutes).max(1e-9);
            if self.feed_mode != FeedMode::InverseTime {
                modal.push(d.inverse_time.clone());
                self.feed_mode = FeedMode::InverseTime;
            }
            self.last_feed = None;
            Some(format!(
                "F{}",
                d.number(1.0 / minutes, d.decimals_inverse_time)
            ))
        } else {
            if self.feed_mode != FeedMode::PerMinute {
                modal.push(d.feed_per_minute.clone());
                self.feed_mode = FeedMode::PerMinute;
                self.last_feed = None;
            }
            let f = d.number(feed, d.decimals_feed);
            if self.last_feed.as_deref() == Some(f.as_str()) {
                None
            } else {
                self.last_feed = Some(f.clone());
                Some(format!("F{f}"))
            }
        };
        if let Some(code) = self.motion_code(&d.linear) {
            modal.push(code);
        }
        let mut all = modal;
        all.extend(words);
        all.extend(feed_word);
        self.block(&all.join(" "));
    }

    /// Safe retract, rotaries home, footer, trailer.
    pub(super) fn postamble(&mut self) {
        let d = self.d;
        self.z_retract(self.options.clearance_z_mm, true);
        self.plane_stop();
        if self.options.tcp {
            self.blocks(&d.tcp_off);
        }
        if self.five_axis() {
            let (t, c) = self.machine.rotary_names().unwrap_or(('A', 'C'));
            let code = self.motion_code(&d.rapid);
            self.block(&join(code, &[format!("{t}0"), format!("{c}0")]));
        }
        if self.feed_mode == FeedMode::InverseTime {
            self.block(&d.feed_per_minute);
        }
        self.blocks(&d.footer);
        self.blocks(&d.trailer);
    }

    /// The text, one block per line, ending with a newline, the pose and operation of every
    /// line.
    pub(super) fn finish(self) -> (String, Vec<Option<usize>>, Vec<usize>) {
        let mut s = self.lines.join("\n");
        s.push('\n');
        (s, self.pose_of_line, self.op_of_line)
    }
}

impl Writer<'_> {
    /// One block tagged with tool-path pose `pose` (a raw `!` line as it stands).
    pub(super) fn tagged_block(&mut self, text: &str, pose: Option<usize>) {
        self.current_pose = pose;
        self.block(text);
        self.current_pose = None;
    }

    /// The plane code when it differs from the last one written (and remember it).
    pub(super) fn plane_word(&mut self, code: &str) -> Option<String> {
        if self.last_plane.as_deref() == Some(code) {
            None
        } else {
            self.last_plane = Some(code.to_string());
            Some(code.to_string())
        }
    }

    /// Back to feed per minute when needed, and the F word when the feed changes.
    pub(super) fn per_minute_words(&mut self, feed: f64) -> (Option<String>, Option<String>) {
        let d = self.d;
        let mode = if self.feed_mode == FeedMode::PerMinute {
            None
        } else {
            self.feed_mode = FeedMode::PerMinute;
            self.last_feed = None;
            Some(d.feed_per_minute.clone())
        };
        let f = d.number(feed, d.decimals_feed);
        if self.last_feed.as_deref() == Some(f.as_str()) {
            (mode, None)
        } else {
            self.last_feed = Some(f.clone());
            (mode, Some(format!("F{f}")))
        }
    }

    /// The last written X Y Z as numbers, when all three have been written.
    pub(super) fn last_xyz(&self) -> Option<glam::DVec3> {
        let v = |i: usize| -> Option<f64> { self.last.get(i)?.as_deref()?.parse().ok() };
        Some(glam::DVec3::new(v(0)?, v(1)?, v(2)?))
    }

    /// The machine is at `p` (mm) after a block that did not go through the axis words (a
    /// cycle), and its motion mode is unknown.
    pub(super) fn moved_to(&mut self, p: glam::DVec3) {
        self.machine_last = p;
        let dl = self.d.decimals_linear;
        for (slot, v) in self.last.iter_mut().zip(p.to_array()) {
            *slot = Some(self.d.number(v, dl));
        }
        self.last_motion = None;
    }

    /// The next feed move writes its F word again (a cycle set the feed itself).
    pub(super) fn forget_feed(&mut self) {
        self.last_feed = None;
    }

    /// A G2/G3 block from the last written point to `end` about `centre` (machine mm) in
    /// `plane`, sweeping `sweep_rad` (> 0) in the sense `ccw` about the plane's normal; all
    /// three end words are written. Returns false (writing nothing) when the start is unknown.
    #[expect(
        clippy::too_many_arguments,
        reason = "the arc's geometry, its feed and the pose it belongs to"
    )]
    pub(super) fn arc(
        &mut self,
        plane: crate::gcode::Plane,
        ccw: bool,
        end: glam::DVec3,
        centre: glam::DVec3,
        sweep_rad: f64,
        feed: f64,
        pose: usize,
    ) -> bool {
        let Some(start) = self.last_xyz() else {
            return false;
        };
        let d = self.d;
        let dl = d.decimals_linear;
        let code = plane_code(plane);
        let mut words: Vec<String> = Vec::new();
        words.extend(self.plane_word(code));
        let (mode, feed_word) = self.per_minute_words(feed);
        words.extend(mode);
        let motion = if ccw {
            d.arc_ccw.clone()
        } else {
            d.arc_cw.clone()
        };
        words.extend(self.motion_code(&motion));
        let values = [
            d.number(end.x, dl),
            d.number(end.y, dl),
            d.number(end.z, dl),
        ];
        for (l, v) in ['X', 'Y', 'Z'].iter().zip(&values) {
            words.push(format!("{l}{v}"));
        }
        let (iu, iv, _) = plane.axes();
        let (c, s) = (centre.to_array(), start.to_array());
        match d.arc_centre {
            super::ArcCentre::Ijk => {
                let mut idx = [iu, iv];
                idx.sort_unstable();
                for i in idx {
                    let (Some(&ci), Some(&si), Some(l)) =
                        (c.get(i), s.get(i), ['I', 'J', 'K'].get(i))
                    else {
                        continue;
                    };
                    // From the written start to the centre rounded as the end is: the centre
                    // read back is the rounded centre.
                    let off = super::Dialect::rounded(ci, dl) - si;
                    words.push(format!("{l}{}", d.number(off, dl)));
                }
            }
            super::ArcCentre::Radius => {
                let (cu, cv) = (
                    c.get(iu).copied().unwrap_or(0.0),
                    c.get(iv).copied().unwrap_or(0.0),
                );
                let (su, sv) = (
                    s.get(iu).copied().unwrap_or(0.0),
                    s.get(iv).copied().unwrap_or(0.0),
                );
                let r = (cu - su).hypot(cv - sv);
                let r = if sweep_rad > std::f64::consts::PI {
                    -r
                } else {
                    r
                };
                words.push(format!("R{}", d.number(r, dl)));
            }
        }
        words.extend(feed_word);
        for (slot, v) in self.last.iter_mut().zip(values) {
            *slot = Some(v);
        }
        self.tagged_block(&words.join(" "), Some(pose));
        true
    }
}

/// The plane's code.
pub(super) fn plane_code(plane: crate::gcode::Plane) -> &'static str {
    match plane {
        crate::gcode::Plane::Xy => "G17",
        crate::gcode::Plane::Zx => "G18",
        crate::gcode::Plane::Yz => "G19",
    }
}

fn join(code: Option<String>, words: &[String]) -> String {
    code.into_iter()
        .chain(words.iter().cloned())
        .collect::<Vec<_>>()
        .join(" ")
}

/// A name from a file (machine, dialect, tool spec) made inert inside a comment or header: no
/// control character (a newline would start a block), no comment or block delimiter.
fn inert(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_control() || matches!(c, '(' | ')' | ';' | '*' | '%') {
                '_'
            } else {
                c
            }
        })
        .collect()
}
