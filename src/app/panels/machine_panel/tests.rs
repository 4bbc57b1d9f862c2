use super::*;

/// The table against the machine file as written (assets/machines/trt-ac.json, degrees).
#[test]
fn axis_rows_are_in_the_file_units() {
    let m = Machine::builtin("trt-ac").unwrap();
    let rows = axis_rows(&m);
    let names: String = rows.iter().map(|r| r.axis).collect();
    assert_eq!(names, "XYZAC");
    let a = rows.iter().find(|r| r.axis == 'A').unwrap();
    assert!(a.rotary);
    assert!(
        (a.travel.0 + 120.0).abs() < 1e-9 && (a.travel.1 - 30.0).abs() < 1e-9,
        "{a:?}"
    );
    assert!((a.velocity - 150.0).abs() < 1e-6 && (a.jerk - 3333.3).abs() < 1e-3);
    assert!((a.direction + 1.0).abs() < f64::EPSILON);
    let z = rows.iter().find(|r| r.axis == 'Z').unwrap();
    assert!(!z.rotary && (z.travel.0 + 500.0).abs() < 1e-9 && (z.velocity - 833.0).abs() < 1e-9);
}

#[test]
fn settings_follow_the_machine() {
    let trt = Machine::builtin("trt-ac").unwrap();
    let mill = Machine::builtin("mill-3axis").unwrap();
    assert!(!dialects_for(&trt).contains(&"grbl"));
    assert!(dialects_for(&mill).contains(&"grbl"));
    assert!(tcp_possible(&trt, "linuxcnc") && !tcp_possible(&mill, "linuxcnc"));
    assert!(!tcp_possible(&trt, "grbl"));
    let mut p = MachinePanel::new(
        mill,
        PostSettings {
            dialect: "grbl".into(),
            tcp: true,
            work_offset: 60,
        },
    );
    assert_eq!(
        p.settings(),
        &PostSettings {
            dialect: "grbl".into(),
            tcp: false,
            work_offset: 59
        }
    );
    // grbl cannot post for the trunnion: the panel falls back to a 5-axis dialect.
    let changed = p.set_machine(trt).unwrap();
    assert_ne!(changed.dialect, "grbl");
    assert!(Dialect::builtin(&changed.dialect).unwrap().five_axis);
    assert_eq!(
        kinematics_label(p.machine().kinematics),
        "table-tilting A/C trunnion (xyzac-trt)"
    );
}

/// Headless: every built-in machine draws (table, schematic at the tilt limits).
#[test]
fn every_machine_draws() {
    for name in Machine::builtin_names() {
        let m = Machine::builtin(name).unwrap();
        let mut h = egui_kittest::Harness::builder()
            .with_size(egui::vec2(520.0, 700.0))
            .build_ui_state(
                |ui, p: &mut MachinePanel| {
                    let _ = p.ui(ui);
                },
                MachinePanel::new(m, PostSettings::default()),
            );
        h.run_steps(2);
        h.state_mut().view.tilt_deg = -120.0;
        h.run_steps(1);
        let _ = h.root();
        assert_eq!(h.state().machine().name, name);
    }
}
