//! Machine bodies: the structure in the built-in machine files, forward kinematics of the
//! bodies against hand-computed placements, and machine collisions (parry3d) against
//! closed-form answers: a trunnion tilt that drives the cradle into the spindle nose, a holder
//! lowered beside a tool into the table edge; the control raising the alarm at the right
//! line and position.

use glam::DVec3;
use talas::control::collide::{check_blocks, first_contact_along, machine_joints};
use talas::control::{Action, Control, ControlConfig, LiveStock, Mode, codes};
use talas::feed::path::JointVector;
use talas::gcode::{InterpretOptions, interpret};
use talas::machine::collision::{CollisionModel, tool_cylinders};
use talas::machine::{Link, Machine, MachineError, MachineJoints};
use talas::simulation::{DexelMode, DexelStock, StockShape};
use talas::tools::parse_tool_spec;

const TOOL: &str = "flat:d=10,flute=20,shank=10,length=50,holder=64x60";

fn tool_model(m: &Machine) -> CollisionModel {
    // d = 10 mm, 50 mm out of a 64 mm x 60 mm holder: gauge 110 mm.
    CollisionModel::new(m, &tool_cylinders(10.0, 10.0, 50.0, &[(64.0, 60.0)]), &[]).unwrap()
}

fn joints(x: f64, y: f64, z: f64, tilt_deg: f64, c_deg: f64) -> MachineJoints {
    MachineJoints {
        xyz: DVec3::new(x, y, z),
        tilt_rad: tilt_deg.to_radians(),
        rotary_rad: c_deg.to_radians(),
    }
}

#[test]
fn every_builtin_has_a_structure_whose_tool_tip_is_the_kinematic_tip() {
    for name in Machine::builtin_names() {
        let m = Machine::builtin(name).unwrap();
        let s = m.structure.as_ref().expect("bodies");
        assert!(s.bodies.len() >= 7, "{name}");
        for want in ["bed", "column", "table", "head", "spindle nose"] {
            assert!(
                s.bodies.iter().any(|b| b.name.contains(want)),
                "{name} has no {want}"
            );
        }
        if m.rotary_names().is_some() {
            assert!(s.bodies.iter().any(|b| b.link == Link::Tilt));
            assert!(s.bodies.iter().any(|b| b.link == Link::Rotary));
        }
        // The tip the head carries, seen from the part, is the forward kinematics' tip.
        for j in [
            joints(10.0, -20.0, 30.0, -25.0, 40.0),
            joints(-150.0, 90.0, -60.0, 20.0, -200.0),
        ] {
            let links = m.link_placements(&j, 110.0).unwrap();
            let pose = m.forward(&j);
            let tip_world = links.tool.apply(DVec3::ZERO);
            let tip_from_table = links.table.apply(pose.tip);
            assert!((tip_world - tip_from_table).length() < 1e-9, "{name}");
            let axis = links.table.rotation * pose.axis;
            assert!((axis - DVec3::Z).length() < 1e-12, "{name}");
        }
    }
}

#[test]
fn body_placements_match_hand_computed_positions() {
    // mill-3axis: the table (on Y then X) moves opposite to X and Y; the head rises by Z plus
    // the gauge length.
    let m = Machine::builtin("mill-3axis").unwrap();
    let l = m
        .link_placements(&joints(100.0, 50.0, -20.0, 0.0, 0.0), 110.0)
        .unwrap();
    assert_eq!(
        l.of(Link::Linear('X')).translation,
        DVec3::new(-100.0, -50.0, 0.0)
    );
    assert_eq!(
        l.of(Link::Linear('Y')).translation,
        DVec3::new(0.0, -50.0, 0.0)
    );
    assert_eq!(
        l.of(Link::Linear('Z')).translation,
        DVec3::new(0.0, 0.0, 90.0)
    );
    // trt-ac, A = −90° (direction −1: the table turns +90° about X around the tilt axis
    // 150 mm below the table top): the table-top centre goes to y = −150, z = −150.
    let m = Machine::builtin("trt-ac").unwrap();
    let l = m
        .link_placements(&joints(10.0, 20.0, 0.0, -90.0, 0.0), 0.0)
        .unwrap();
    let p = l.table.apply(DVec3::ZERO);
    assert!(
        (p - DVec3::new(-10.0, -170.0, -150.0)).length() < 1e-9,
        "{p}"
    );
    // C turns the table but not the cradle: a point on the table rim at +X, C = 90°
    // (direction −1: −90° about Z) goes to −Y.
    let l = m
        .link_placements(&joints(0.0, 0.0, 0.0, 0.0, 90.0), 0.0)
        .unwrap();
    assert!(
        (l.table.apply(DVec3::new(250.0, 0.0, 0.0)) - DVec3::new(0.0, -250.0, 0.0)).length() < 1e-9
    );
    assert!(
        (l.tilt.apply(DVec3::new(250.0, 0.0, 0.0)) - DVec3::new(250.0, 0.0, 0.0)).length() < 1e-9
    );
}

#[test]
fn nothing_touches_at_home_while_each_axis_sweeps_its_travel() {
    for name in Machine::builtin_names() {
        let m = Machine::builtin(name).unwrap();
        let model = tool_model(&m);
        let zmax = m.axis('Z').unwrap().max;
        // Z goes down to the table by design; every other axis sweeps with Z at its top.
        for a in m.axes.iter().filter(|a| a.name != 'Z') {
            let k = talas::feed::path::slot_of(a.name).unwrap();
            let at = |u: f64| {
                let mut p: JointVector = [0.0; 6];
                p[2] = zmax;
                p[k] = a.min + (a.max - a.min) * u;
                p
            };
            let hit = first_contact_along(&model, &m, at, (0.0, 1.0), &[]);
            assert!(hit.is_none(), "{name}: axis {} hits {hit:?}", a.name);
        }
    }
}

/// trt-ac with no tool, the spindle nose (radius 60 mm) centred at X = 280 mm, Y = −130 mm and
/// its face 255 mm above the tilt axis (Z = 105 mm). Tilting A towards −90° swings the cradle
/// plate (top 110 mm above the tilt axis, ±260 mm in Y, ±300 mm in X) up in −Y; the nose's
/// point nearest the C axis (y = −70 mm, 255 mm up) enters the plate's top face when
/// 70·sin θ + 255·cos θ = 110, θ the table's turn. Out at X = 220…340 mm the rotary table
/// (radius 250 mm) and the cheeks reach at most 191 mm above the tilt axis, and the housing
/// 30 mm above the nose stands above the plate's 282 mm reach: the nose meets the cradle first.
fn cradle_angle_deg() -> f64 {
    let r = (70.0f64.powi(2) + 255.0f64.powi(2)).sqrt();
    (70.0f64.atan2(255.0) + (110.0 / r).acos()).to_degrees()
}

#[test]
fn a_tilt_drives_the_cradle_into_the_spindle_nose_at_the_closed_form_angle() {
    let m = Machine::builtin("trt-ac").unwrap();
    let model = CollisionModel::new(&m, &[], &[]).unwrap();
    let prog = interpret(
        "G0 X280 Y-130 Z105\nG0 A-90\n",
        &InterpretOptions::default(),
    )
    .unwrap();
    let hit = check_blocks(&model, &m, &prog.blocks).expect("a collision");
    assert_eq!(hit.line, 2);
    assert_eq!(
        hit.contacts,
        [talas::machine::collision::Contact {
            bodies: ["spindle nose".into(), "cradle".into()]
        }]
    );
    let a = -hit.position[3].to_degrees();
    let want = cradle_angle_deg();
    assert!(
        (a - want).abs() < 1e-4,
        "first contact at A = −{a}°, closed form −{want}°"
    );
    // At A = −90° the plate's top stands 260 mm above the tilt axis under the nose.
    let names = |h: f64| {
        let j = joints(280.0, -130.0, h - 150.0, -90.0, 0.0);
        model
            .contacts(&m, &j)
            .into_iter()
            .map(|c| c.bodies[1].clone())
            .collect::<Vec<_>>()
    };
    assert!(names(261.0).is_empty());
    assert_eq!(names(259.0), ["cradle"]);
}

/// mill-3axis at Y = 200: the table (±180 mm in Y) ends 20 mm short of the tool's axis, so the
/// 10 mm tool passes it and the 64 mm holder, 50 mm above the tip, meets the table top
/// (100 mm below machine zero) when the tip reaches Z = −150.
#[test]
fn a_holder_lowered_beside_the_table_meets_its_edge_at_the_closed_form_depth() {
    let m = Machine::builtin("mill-3axis").unwrap();
    let model = tool_model(&m);
    let prog = interpret(
        "G0 X0 Y200 Z0\nG1 Z-250 F1000\n",
        &InterpretOptions::default(),
    )
    .unwrap();
    let hit = check_blocks(&model, &m, &prog.blocks).expect("a collision");
    assert_eq!(hit.line, 2);
    assert_eq!(
        hit.contacts[0].bodies,
        ["holder".to_string(), "table".into()]
    );
    assert!((hit.position[2] + 150.0).abs() < 1e-3, "{:?}", hit.position);
    // The same descent at Y = 150 brings the tool itself onto the table top at Z = −100.
    let prog = interpret(
        "G0 X0 Y150 Z0\nG1 Z-250 F1000\n",
        &InterpretOptions::default(),
    )
    .unwrap();
    let hit = check_blocks(&model, &m, &prog.blocks).expect("a collision");
    assert_eq!(hit.contacts[0].bodies, ["tool".to_string(), "table".into()]);
    assert!((hit.position[2] + 100.0).abs() < 1e-3, "{:?}", hit.position);
}

fn homed_control(machine: &str, stock: Option<LiveStock>) -> Control {
    let mut cfg = ControlConfig::new(Machine::builtin(machine).unwrap());
    cfg.stock = stock;
    let mut c = Control::new(cfg).unwrap();
    c.apply(Action::Home).unwrap();
    c.advance_until_idle(120.0);
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    c
}

fn small_stock() -> LiveStock {
    let stock = DexelStock::new(
        vec![StockShape::Box {
            min: DVec3::new(-60.0, -150.0, -100.0),
            max: DVec3::new(-20.0, -110.0, -70.0),
        }],
        2.0,
        DexelMode::Z,
        1 << 26,
    )
    .unwrap();
    LiveStock::new(stock, parse_tool_spec(TOOL).unwrap(), 2.0)
}

#[test]
fn the_control_stops_a_holder_running_into_the_table_with_an_alarm_at_the_contact() {
    let mut c = homed_control("mill-3axis", Some(small_stock()));
    for line in ["G0 X0 Y200 Z0", "G1 Z-250 F3000"] {
        c.apply(Action::Mdi(line.into())).unwrap();
        c.advance_until_idle(60.0);
    }
    let alarms = c.alarms();
    assert_eq!(alarms.len(), 1, "{alarms:?}");
    let a = &alarms[0];
    assert_eq!(a.code, codes::COLLISION_MACHINE);
    assert_eq!(a.bodies, ["holder", "table"]);
    assert_eq!(a.line, Some(2));
    let p = a.position.unwrap();
    assert!((p[2] + 150.0).abs() < 0.1 && p[1] == 200.0, "{p:?}");
    // The machine braked within its limits and stays blocked until reset; the alarm names
    // both the contact and where the axes came to rest (the DRO's position), and how far
    // apart they are (issue 35: "the DRO stops 1.7 mm past the reported riser contact").
    let z = c.snapshot().machine_position[2];
    assert!(z < -150.0 && z > -160.0, "stopped at Z = {z}");
    let a = &c.alarms()[0];
    assert!(
        a.text
            .contains(&format!("stopped at X0.000 Y200.000 Z{z:.3} mm")),
        "{}",
        a.text
    );
    let past = p[2] - z;
    assert!(
        a.text.contains(&format!("{past:.3} mm past the contact")),
        "{}",
        a.text
    );
    assert!(c.apply(Action::Mdi("G0 Z0".into())).is_err());
    c.apply(Action::Reset).unwrap();
    c.apply(Action::Mdi("G0 Z0".into())).unwrap();
    c.advance_until_idle(60.0);
    assert_eq!(c.alarms().len(), 0);
}

#[test]
fn the_control_raises_the_trunnion_collision_at_the_right_block_and_angle() {
    let mut c = homed_control("trt-ac", None);
    // No tool: the gauge length is 0 and the joints are the spindle nose.
    let theta = cradle_angle_deg();
    for line in ["G0 X280 Y-130 Z105", "G0 A-90"] {
        c.apply(Action::Mdi(line.into())).unwrap();
        c.advance_until_idle(60.0);
    }
    let a = &c.alarms()[0];
    assert_eq!(a.code, codes::COLLISION_MACHINE);
    assert_eq!(a.bodies, ["spindle nose", "cradle"]);
    assert_eq!(a.line, Some(2));
    let at = format!("A{:.3}°", -theta);
    assert!(a.text.contains(&at), "{} lacks {at}", a.text);
    let p = a.position.unwrap();
    assert!((p[0] - 280.0).abs() < 0.1 && (p[1] + 130.0).abs() < 0.1 && (p[2] - 105.0).abs() < 0.1);
    // 9.2° before the end at 150°/s the brake (333°/s², 3333°/s³) cannot stop short of it;
    // the machine stays blocked until reset.
    assert!(c.apply(Action::Mdi("G0 A0".into())).is_err());
}

#[test]
fn machine_files_with_bad_bodies_are_refused_naming_the_body() {
    let base = Machine::builtin("mill-3axis").unwrap();
    assert!(base.structure.is_some());
    let text = include_str!("../assets/machines/mill-3axis.json");
    let bad = text.replacen("\"link\": \"Y\"", "\"link\": \"Q\"", 1);
    let e = Machine::from_json(&bad).unwrap_err();
    assert!(
        matches!(&e, MachineError::Invalid(m) if m.contains("body 3 (\"saddle\")")),
        "{e}"
    );
    let bad = text.replacen(
        "\"box\": [[-260, -180, -330], [260, 180, -150]]",
        "\"box\": [[0, 0, 0], [0, 1, 1]]",
        1,
    );
    let e = Machine::from_json(&bad).unwrap_err();
    assert!(e.to_string().contains("zero extent"), "{e}");
    // Bodies are optional.
    let mut v: serde_json::Value = serde_json::from_str(text).unwrap();
    v.as_object_mut().unwrap().remove("structure");
    let m = Machine::from_json(&v.to_string()).unwrap();
    assert!(m.structure.is_none());
    assert!(CollisionModel::new(&m, &[], &[]).is_none());
    let _ = machine_joints(&m, &[0.0; 6]);
}

/// Every body's mesh is closed (each edge in exactly two triangles, opposite ways) with the
/// volume of its primitive: a box's extents' product, an n-gon prism's n/2·r²·sin(2π/n)·length.
#[test]
fn body_meshes_are_closed_with_the_primitive_volume() {
    use std::collections::HashMap;
    for name in Machine::builtin_names() {
        let m = Machine::builtin(name).unwrap();
        for b in &m.structure.as_ref().unwrap().bodies {
            let mesh = b.shape.mesh(24);
            let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
            let mut volume = 0.0;
            for t in &mesh.triangles {
                let p = t.map(|i| mesh.vertices[i as usize]);
                volume += p[0].dot(p[1].cross(p[2])) / 6.0;
                for k in 0..3 {
                    *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
                }
            }
            for (&(a, c), &n) in &edges {
                assert_eq!((n, edges.get(&(c, a))), (1, Some(&1)), "{name} {}", b.name);
            }
            let want = match b.shape {
                talas::machine::Shape::Box { min, max } => (max - min).element_product(),
                talas::machine::Shape::Cylinder { radius, length, .. } => {
                    12.0 * radius * radius * (std::f64::consts::TAU / 24.0).sin() * length
                }
            };
            assert!(
                (volume - want).abs() < 1e-6 * want,
                "{name} {}: {volume} vs {want}",
                b.name
            );
        }
    }
}

#[test]
fn the_stock_rests_on_a_riser_from_the_table_top_and_the_tool_meets_it() {
    use talas::control::collide::{riser_under, table_top_z};
    use talas::machine::Shape;
    // The mill's table top is 100 mm below machine zero (its table box ends at z = −100).
    let mill = Machine::builtin("mill-3axis").unwrap();
    assert_eq!(table_top_z(&mill), Some(-100.0));
    let (lo, hi) = (DVec3::new(-30.0, -30.0, -10.0), DVec3::new(30.0, 30.0, 0.0));
    let riser = riser_under(&mill, lo, hi).unwrap();
    assert_eq!(
        riser.shape,
        talas::machine::collision::TableShape::Solid(Shape::Box {
            min: DVec3::new(-30.0, -30.0, -100.0),
            max: DVec3::new(30.0, 30.0, -10.0),
        })
    );
    // The trunnion's rotary table top is z = 0: a stock standing on it needs no riser.
    let trt = Machine::builtin("trt-ac").unwrap();
    assert!(table_top_z(&trt).unwrap().abs() < 1e-9);
    assert!(
        riser_under(
            &trt,
            DVec3::new(-20.0, -20.0, 0.0),
            DVec3::new(20.0, 20.0, 30.0)
        )
        .is_none()
    );
    // A tool lowered through where the stock was meets the riser's top at Z = −10 mm.
    let model = CollisionModel::new(
        &mill,
        &tool_cylinders(10.0, 10.0, 50.0, &[(64.0, 60.0)]),
        &[riser],
    )
    .unwrap();
    let prog = interpret(
        "G0 X0 Y0 Z50\nG1 Z-50 F1000\n",
        &InterpretOptions::default(),
    )
    .unwrap();
    let hit = check_blocks(&model, &mill, &prog.blocks).expect("a collision");
    assert_eq!(hit.line, 2);
    assert_eq!(hit.contacts[0].bodies, ["tool".to_string(), "riser".into()]);
    assert!((hit.position[2] + 10.0).abs() < 1e-3, "{:?}", hit.position);
}
