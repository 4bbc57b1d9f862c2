//! The workstation's frame: the title and dropped files, the panels (menu bar, status bar,
//! log dock, project tree, properties, playback), the 3D view with the features' scene parts
//! and steering, and the floating windows.

use super::*;

impl Workstation {
    /// Lay out one frame and apply what it asked for.
    pub fn frame_ui(&mut self, ui: &mut egui::Ui) {
        self.poll_background();
        let dt = ui.ctx().input(|i| f64::from(i.stable_dt));
        self.tick_playback(dt);
        let mut commands = Vec::new();
        let ctx = ui.ctx().clone();
        self.run.ctx = ctx.clone();
        self.on_close_request(&ctx);
        shortcuts(&ctx, &self.actions, &mut commands);
        self.title_and_drops(&ctx, &mut commands);
        self.panels_ui(ui, &mut commands);
        self.central_ui(ui, &ctx, &mut commands);
        self.windows_ui(&ctx, &mut commands);
        for c in commands {
            self.apply(c);
        }
    }

    /// Keep the window title current; a dropped file is opened.
    fn title_and_drops(&mut self, ctx: &egui::Context, commands: &mut Vec<Command>) {
        let title = self.saved.session.title();
        if title != self.run.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.run.title = title;
        }
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .collect()
        });
        if let Some(path) = dropped.into_iter().next() {
            commands.push(Command::Open(path));
        }
    }

    /// The menu bar, the status bar, the log dock, the project tree, the properties and the
    /// playback bar.
    fn panels_ui(&mut self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        let flags = ViewFlags {
            projection: self.viewport.camera.projection,
            edges: self.viewport.show_edges,
            grid: self.viewport.options.grid,
            orient_to_setup: self.viewport.orient_to_setup,
            scalar_field: self.viewport.scalar_field,
            fields_available: self
                .document
                .as_ref()
                .is_some_and(|d| has_surfaces(&d.part)),
            path_colouring: self.ops.colouring,
            all_paths: self.ops.show_all,
            axis_vectors: self.ops.show_axes,
            has_faces: self
                .document
                .as_ref()
                .is_some_and(|d| !d.part.faces.is_empty()),
        };
        let undo = UndoLabels {
            undo: self.saved.session.history.undo_label(),
            redo: self.saved.session.history.redo_label(),
        };
        let toggles: Vec<_> = self.features.iter().flat_map(|f| f.toggles()).collect();
        egui::Panel::top("menu bar").show(ui, |ui| {
            menu_bar_ui(
                ui,
                &self.actions,
                &self.saved.recent,
                flags,
                &toggles,
                undo,
                commands,
            );
        });
        let status = self.status();
        egui::Panel::bottom("status bar")
            .exact_size(26.0)
            .show(ui, |ui| status_bar_ui(ui, &status, commands));
        egui::Panel::bottom("log")
            .resizable(true)
            .default_size(190.0)
            .size_range(60.0..=700.0)
            .show(ui, |ui| self.dock_ui(ui, commands));
        egui::Panel::left("project tree")
            .resizable(true)
            .default_size(250.0)
            .size_range(160.0..=500.0)
            .show(ui, |ui| {
                project_tree_ui(
                    ui,
                    self.document.as_ref(),
                    &self.saved.session.project,
                    self.focus,
                    commands,
                );
            });
        let mut forms = std::mem::take(&mut self.forms);
        let operation = match self.focus {
            Focus::Operation(i) => Some(i),
            _ => None,
        };
        // The features' sections of the operation editor (the stock simulation's).
        let view = self.feature_view();
        let features = &self.features;
        let sections = |ui: &mut egui::Ui, commands: &mut Vec<Command>| {
            if let Some(i) = operation {
                for f in features {
                    f.operation_ui(ui, i, &view, commands);
                }
            }
        };
        egui::Panel::right("properties")
            .resizable(true)
            .default_size(290.0)
            .size_range(180.0..=520.0)
            .show(ui, |ui| {
                let operation = operation.map(|i| self.operation_view(i, &sections));
                let view = PropertiesView {
                    focus: self.focus,
                    document: self.document.as_ref(),
                    project: &self.saved.session.project,
                    pick: self.pick.as_ref(),
                    operation,
                };
                properties_ui(ui, &view, &mut forms, commands);
            });
        self.forms = forms;
        if let Some(view) = self.playback_view() {
            egui::Panel::bottom("playback")
                .exact_size(30.0)
                .show(ui, |ui| playback_ui(ui, &view, commands));
        }
    }

    /// The 3D view: part, paths, tool, stock or reduced surface, the machine and the features'
    /// scene parts, with the overlays.
    fn central_ui(&mut self, ui: &mut egui::Ui, ctx: &egui::Context, commands: &mut Vec<Command>) {
        let (paths, legend) = self.path_instances();
        let mut viewport = std::mem::take(&mut self.viewport);
        // The tool stands at the pose under the pointer in a plot, else the picked one, else the
        // playback's (playback clears the pick); the marker at program zero.
        viewport.tool_pose = self.active_result().and_then(|r| {
            let i = self.tool_pose_index()?;
            let p = r.toolpath().poses.get(i)?;
            Some(crate::app::viewport::ToolPose {
                tip: p.tip,
                axis: p.axis,
                cutter: r.cutter.clone(),
            })
        });
        // The first setup's origin until the job feature steers the active setup's frame in.
        viewport.work_offset = Some(glam::Mat4::from_translation(
            glam::DVec3::from_array(self.saved.session.project.first_setup().frame.origin_mm)
                .as_vec3(),
        ));
        // The features' steering (the operator panel's machine, its camera and tool; the active
        // setup's frame).
        viewport.machine_shown = false;
        let machine_meshes: Vec<_> = self
            .features
            .iter_mut()
            .flat_map(|f| f.steer_view(&mut viewport, &self.run.feature_ids))
            .collect();
        let mut scene = SceneParts::default();
        for f in &self.features {
            let parts = f.scene();
            scene.meshes.extend(parts.meshes);
            scene.lines.extend(parts.lines);
            scene.instead_of_part = scene.instead_of_part.or(parts.instead_of_part);
            scene.path_legend = parts.path_legend.or(scene.path_legend);
            scene.hide_paths |= parts.hide_paths;
        }
        egui::CentralPanel::no_frame().show(ui, |ui| {
            let rect = ui.available_rect_before_wrap();
            let up_to = self.playback_pose();
            // Over a feature's surface (the simulated stock) the path would hide it: it is drawn
            // only while playing back.
            let paths = if scene.hide_paths && up_to.is_none() {
                Vec::new()
            } else {
                paths
            };
            // A feature's surface (the reduced one, the simulated stock) replaces the part.
            let shown = scene.instead_of_part;
            let mut extras = ViewportExtras {
                hide_part: shown.is_some(),
                stock_legend: shown.as_ref().map(|r| (r.legend.clone(), r.mapping)),
                meshes: shown
                    .into_iter()
                    .map(|r| r.mesh)
                    .chain(machine_meshes)
                    .collect(),
                paths,
                path_legend: legend,
                path_legend_mark: None,
                pick_path: self
                    .active_result()
                    .filter(|_| {
                        self.ops
                            .active
                            .is_none_or(|a| !self.ops.hidden.contains(&a))
                    })
                    .map(|r| (r.toolpath(), up_to)),
            };
            extras.meshes.extend(scene.meshes);
            extras.paths.extend(scene.lines);
            if let Some(l) = scene.path_legend {
                (extras.path_legend, extras.path_legend_mark) =
                    (Some((l.title, l.mapping)), l.mark);
            }
            viewport_ui(ui, &mut viewport, self.document.as_ref(), extras, commands);
            overlays_ui(
                ui,
                rect,
                &self.log,
                ctx.input(|i| !i.raw.hovered_files.is_empty()),
            );
        });
        self.viewport = viewport;
    }

    /// The floating windows: comparison, the features', file chooser and the questions
    /// (unsaved changes, recovery).
    fn windows_ui(&mut self, ctx: &egui::Context, commands: &mut Vec<Command>) {
        self.compare_ui(ctx, commands);
        let mut features = std::mem::take(&mut self.features);
        let view = self.feature_view();
        for f in &mut features {
            f.ui(ctx, &view, commands);
        }
        self.features = features;
        self.gather_lent();
        self.chooser_ui(ctx);
        self.unsaved_ui(ctx);
        if let Some(recovery) = &self.run.recovery
            && let Some(answer) = recovery_ui(
                ctx,
                recovery,
                self.run
                    .recovery_project
                    .as_deref()
                    .or(self.saved.session.path.as_deref()),
            )
        {
            commands.push(answer);
        }
    }
}
