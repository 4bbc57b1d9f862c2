//! The library against cases worked by hand from the formulas (the numbers below were computed
//! outside Talas: n = 1000·v_c/(π·D); f_z from the table, interpolated; chip thinning
//! 1/√(1 − (1 − 2a_e/D)²); v_f = f_z·z·n; and for a flat end mill the mean power
//! P = K_t(h_a)·a_e·a_p·v_f/60 000 W with h_a = f_z·(1 − cos φ_e)/φ_e and
//! K_t = k_c1.1·h_a^−m_c, the closed form of the mean tangential force over a revolution).

use super::*;
use crate::tools::parse_tool_spec;

fn close(what: &str, got: f64, want: f64) {
    let rel = ((got - want) / want).abs();
    assert!(
        rel < 1e-3,
        "{what}: got {got}, want {want} ({:.4} %)",
        rel * 100.0
    );
}

struct Hand {
    material: &'static str,
    tool: ToolMaterial,
    d: f64,
    z: u32,
    ae: f64,
    ap: f64,
    max_rpm: Option<f64>,
    rpm: f64,
    fz: f64,
    feed: f64,
    power_w: f64,
    torque_nm: f64,
}

const HAND: [Hand; 5] = [
    Hand {
        material: "6061",
        tool: ToolMaterial::Carbide,
        d: 10.0,
        z: 3,
        ae: 5.0,
        ap: 10.0,
        max_rpm: None,
        rpm: 9549.296586,
        fz: 0.08,
        feed: 2291.831181,
        power_w: 2814.2125,
        torque_nm: 2.814213,
    },
    Hand {
        material: "4140",
        tool: ToolMaterial::Carbide,
        d: 12.0,
        z: 4,
        ae: 1.2,
        ap: 18.0,
        max_rpm: Some(8000.0),
        rpm: 3183.098862,
        fz: 0.075,
        feed: 954.929659,
        power_w: 1715.6275,
        torque_nm: 5.146883,
    },
    Hand {
        material: "6061",
        tool: ToolMaterial::Carbide,
        d: 3.0,
        z: 2,
        ae: 0.75,
        ap: 3.0,
        max_rpm: Some(24_000.0),
        rpm: 24_000.0,
        fz: 0.028868,
        feed: 1385.640646,
        power_w: 106.1554,
        torque_nm: 0.042238,
    },
    Hand {
        material: "304",
        tool: ToolMaterial::Hss,
        d: 8.0,
        z: 4,
        ae: 4.0,
        ap: 8.0,
        max_rpm: None,
        rpm: 596.831037,
        fz: 0.024,
        feed: 57.295780,
        power_w: 154.4121,
        torque_nm: 2.470594,
    },
    Hand {
        material: "ti64",
        tool: ToolMaterial::Carbide,
        d: 10.0,
        z: 4,
        ae: 0.5,
        ap: 20.0,
        max_rpm: None,
        rpm: 1591.549431,
        fz: 0.080296,
        feed: 511.177073,
        power_w: 301.2560,
        torque_nm: 1.807536,
    },
];

#[test]
fn speeds_feeds_and_power_agree_with_the_hand_worked_cases() {
    for h in &HAND {
        let m = material(h.material).expect("material");
        let case = Case {
            material: m,
            tool_material: h.tool,
            diameter_mm: h.d,
            flutes: h.z,
            radial_mm: h.ae,
            axial_mm: h.ap,
            max_rpm: h.max_rpm,
        };
        let s = recommend(&case).expect("recommend");
        let tag = format!("{} D{} ae{}", h.material, h.d, h.ae);
        close(&format!("{tag} rpm"), s.spindle_rpm, h.rpm);
        close(&format!("{tag} fz"), s.feed_per_tooth_mm, h.fz);
        close(&format!("{tag} feed"), s.feed_mm_min, h.feed);
        close(&format!("{tag} ramp"), s.ramp_feed_mm_min, 0.5 * h.feed);
        let spec = format!(
            "flat:d={},flute={},shank={},length={},flutes={},helix=30",
            h.d,
            (h.ap + 2.0).max(2.0 * h.d),
            h.d,
            3.0 * h.d + h.ap,
            h.z
        );
        let cutter = parse_tool_spec(&spec).expect("tool");
        let load = check_load(&case, &cutter, &s, Mode::Up, &Limits::default()).expect("load");
        close(&format!("{tag} power"), load.mean_power_w, h.power_w);
        close(&format!("{tag} torque"), load.mean_torque_nm, h.torque_nm);
        // Climb milling removes the same chip: the same mean power.
        let climb = check_load(&case, &cutter, &s, Mode::Down, &Limits::default()).expect("load");
        close(&format!("{tag} climb power"), climb.mean_power_w, h.power_w);
        assert!(load.peak_force_n > 0.0 && load.deflection_mm.is_some_and(|d| d > 0.0));
    }
}

#[test]
fn chip_thinning_at_five_to_fifty_percent() {
    for (r, want) in [
        (0.05, 2.294157338705618),
        (0.10, 1.666666666666667),
        (0.25, 1.1547005383792517),
        (0.50, 1.0),
        (0.80, 1.0),
    ] {
        close(
            &format!("a_e/D = {r}"),
            chip_thinning_factor(r * 12.0, 12.0),
            want,
        );
    }
    assert!((chip_thinning_factor(1e-4, 12.0) - MAX_CHIP_THINNING).abs() < 1e-12);
    // The thinned feed restores the table's chip as the largest chip thickness.
    let m = material("7075").expect("7075");
    for r in [0.05, 0.1, 0.25] {
        let s = recommend(&Case {
            material: m,
            tool_material: ToolMaterial::Carbide,
            diameter_mm: 12.0,
            flutes: 3,
            radial_mm: r * 12.0,
            axial_mm: 12.0,
            max_rpm: None,
        })
        .expect("recommend");
        close("largest chip", s.max_chip_mm, s.table_chip_load_mm);
    }
}

#[test]
fn every_material_of_the_issue_is_in_the_library_with_sane_numbers() {
    for key in [
        "Al6061",
        "7075-T6",
        "1045",
        "4140",
        "stainless 304",
        "Ti-6Al-4V",
        "brass",
        "acetal",
    ] {
        let m = material(key).unwrap_or_else(|| panic!("{key} missing"));
        assert!(m.vc_carbide_m_min > m.vc_hss_m_min, "{key}");
        assert!(m.chip_load_mm.windows(2).all(|w| w[1] >= w[0]), "{key}");
        assert!(m.kc11_n_mm2 > 0.0 && (0.1..0.4).contains(&m.mc), "{key}");
        for d in [1.0, 3.0, 7.0, 20.0, 40.0] {
            let f = m.chip_load_mm(d, ToolMaterial::Carbide);
            assert!(f > 0.0 && f <= 0.2, "{key} D{d}: {f}");
        }
    }
    assert!(material("unobtainium").is_none() && material("").is_none());
    // Interpolation between tabulated diameters: 304 at D = 8 is halfway from 6 to 10.
    let m = material("304").expect("304");
    close("304 D8", m.chip_load_mm(8.0, ToolMaterial::Carbide), 0.03);
}

#[test]
fn limits_are_flagged_and_bad_input_is_refused() {
    let m = material("4140").expect("4140");
    let case = Case {
        material: m,
        tool_material: ToolMaterial::Carbide,
        diameter_mm: 16.0,
        flutes: 4,
        radial_mm: 16.0,
        axial_mm: 16.0,
        max_rpm: None,
    };
    let s = recommend(&case).expect("recommend");
    let cutter =
        parse_tool_spec("flat:d=16,flute=40,shank=16,length=90,flutes=4,helix=35").expect("tool");
    let limits = Limits {
        spindle_power_w: Some(1500.0),
        max_torque_nm: Some(5.0),
        ..Limits::default()
    };
    let load = check_load(&case, &cutter, &s, Mode::Up, &limits).expect("load");
    assert!(load.mean_power_w > 1500.0, "{load:?}");
    assert!(
        load.flags.iter().any(|f| f.contains("spindle")),
        "{:?}",
        load.flags
    );
    assert!(
        load.flags.iter().any(|f| f.contains("torque")),
        "{:?}",
        load.flags
    );
    assert!(
        load.flags.iter().any(|f| f.contains("deflection")),
        "{:?}",
        load.flags
    );
    for bad in [
        Case {
            radial_mm: 20.0,
            ..case
        },
        Case {
            diameter_mm: f64::NAN,
            ..case
        },
        Case { flutes: 0, ..case },
        Case {
            max_rpm: Some(-1.0),
            ..case
        },
    ] {
        assert!(recommend(&bad).is_err());
    }
    // A cone has no end-mill force model: an error, not a panic.
    let cone = parse_tool_spec("cone:d=10,angle=45").expect("cone");
    assert!(check_load(&case, &cone, &s, Mode::Up, &limits).is_err());
}

#[test]
fn every_number_says_where_it_came_from() {
    let m = material("6061").expect("6061");
    let s = recommend(&Case {
        material: m,
        tool_material: ToolMaterial::Carbide,
        diameter_mm: 3.0,
        flutes: 2,
        radial_mm: 0.3,
        axial_mm: 3.0,
        max_rpm: Some(24_000.0),
    })
    .expect("recommend");
    let q: Vec<_> = s.sources.iter().map(|s| s.quantity).collect();
    for want in ["spindle speed", "chip load", "feed per tooth", "feed"] {
        assert!(q.contains(&want), "{q:?}");
    }
    assert!(s.sources[0].from.contains("capped"), "{:?}", s.sources[0]);
}
