//! `talas speeds --material NAME --tool SPEC --ae MM --ap MM [--tool-material carbide|hss]
//! [--max-rpm N] [--mode up|down] [--machine NAME] [--json]`: spindle speed and feeds from the
//! cutting-data library ([`crate::force::cutting_data`]), with radial chip thinning, and the
//! force model's torque, power, peak force and tool deflection against the tool's and the
//! machine's limits. `talas speeds --list` prints the library.

use std::fmt::Write as _;
use std::path::Path;

use serde_json::{Value, json};

use crate::force::Mode;
use crate::force::cutting_data::{
    self, Case, Limits, MATERIALS, ToolMaterial, check_load, recommend,
};
use crate::import::ImportError;
use crate::machine::Machine;
use crate::tools::parse_tool_spec;

/// Options of `talas speeds`.
#[derive(Debug, clap::Args)]
pub struct SpeedsArgs {
    /// Work material: `6061`, `7075`, `1045`, `4140`, `304`, `ti64`, `brass`, `acetal` (or a
    /// name containing one: `Al6061-T6`, `AISI 304`, `Ti-6Al-4V`, `POM`).
    #[arg(long, value_name = "NAME", required_unless_present = "list")]
    pub material: Option<String>,
    /// The tool: e.g. `flat:d=10,flutes=3,helix=35,length=40` (flutes needed for the load
    /// check; `length` is the stick-out for the deflection).
    #[arg(long, value_name = "SPEC", required_unless_present = "list")]
    pub tool: Option<String>,
    /// Cutting-edge material: `carbide` or `hss`.
    #[arg(long, value_name = "KIND", default_value = "carbide")]
    pub tool_material: String,
    /// Radial depth of cut (width) a_e, mm (default: half the diameter).
    #[arg(long, value_name = "MM")]
    pub ae: Option<f64>,
    /// Axial depth of cut a_p, mm (default: the diameter).
    #[arg(long, value_name = "MM")]
    pub ap: Option<f64>,
    /// The machine's top spindle speed, rpm.
    #[arg(long, value_name = "N")]
    pub max_rpm: Option<f64>,
    /// `down` (climb, default) or `up` (conventional); a full-width cut is a slot.
    #[arg(long, value_name = "MODE", default_value = "down")]
    pub mode: String,
    /// Machine (`talas machines`) or machine JSON whose spindle power limits the cut.
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub machine: Option<String>,
    /// List the library instead.
    #[arg(long)]
    pub list: bool,
    /// Print JSON instead of the summary.
    #[arg(long)]
    pub json: bool,
}

fn opt(name: &str, msg: String) -> ImportError {
    ImportError::new(Path::new(name), None, msg)
}

/// Run `talas speeds`.
///
/// # Errors
/// An [`ImportError`] naming the option that is wrong.
pub fn speeds(args: &SpeedsArgs) -> Result<Value, ImportError> {
    if args.list {
        return Ok(json!({ "materials": MATERIALS }));
    }
    let name = args.material.as_deref().unwrap_or_default();
    let material = cutting_data::material(name).ok_or_else(|| {
        let keys: Vec<_> = MATERIALS.iter().map(|m| m.key).collect();
        opt(
            "--material",
            format!("unknown material '{name}' (known: {})", keys.join(", ")),
        )
    })?;
    let tool_material = ToolMaterial::parse(&args.tool_material).ok_or_else(|| {
        opt(
            "--tool-material",
            format!("must be carbide or hss, got '{}'", args.tool_material),
        )
    })?;
    let spec = args.tool.as_deref().unwrap_or_default();
    let cutter = parse_tool_spec(spec).map_err(|e| opt("--tool", e.to_string()))?;
    let mode = match Mode::parse(&args.mode) {
        Some(m @ (Mode::Up | Mode::Down)) => m,
        _ => {
            return Err(opt(
                "--mode",
                format!("must be up or down, got '{}'", args.mode),
            ));
        }
    };
    let machine = match &args.machine {
        Some(m) => Some(Machine::resolve(m).map_err(|e| opt("--machine", e.to_string()))?),
        None => None,
    };
    let case = Case {
        material,
        tool_material,
        diameter_mm: cutter.diameter,
        flutes: cutter.flutes.map_or(2, |f| f.count),
        radial_mm: args.ae.unwrap_or(0.5 * cutter.diameter),
        axial_mm: args.ap.unwrap_or(cutter.diameter),
        max_rpm: args.max_rpm,
    };
    let s = recommend(&case).map_err(|e| opt("--ae/--ap", e.to_string()))?;
    let limits = Limits {
        spindle_power_w: machine.as_ref().and_then(|m| m.spindle_power_w),
        max_force_n: cutter.limits.max_force_n,
        max_torque_nm: cutter.limits.max_torque_nm,
        max_power_w: cutter.limits.max_power_w,
    };
    let (load, load_error) = if cutter.flutes.is_some() {
        match check_load(&case, &cutter, &s, mode, &limits) {
            Ok(l) => (Some(l), None),
            Err(e) => (None, Some(e.to_string())),
        }
    } else {
        (
            None,
            Some("the tool SPEC gives no flutes=N: no load check".to_string()),
        )
    };
    Ok(json!({
        "material": material.name,
        "tool_material": tool_material.name(),
        "tool": spec,
        "radial_depth_mm": case.radial_mm,
        "axial_depth_mm": case.axial_mm,
        "flutes": case.flutes,
        "speeds": s,
        "load": load,
        "load_error": load_error,
    }))
}

/// The human summary of the JSON document.
#[must_use]
pub fn human(doc: &Value) -> String {
    let mut out = String::new();
    if let Some(list) = doc["materials"].as_array() {
        let _ = writeln!(
            out,
            "{:<8} {:<36} {:>13} {:>10} {:>13} {:>6}",
            "key", "material", "v_c carbide", "v_c HSS", "f_z D10", "k_c1.1"
        );
        for m in list {
            let _ = writeln!(
                out,
                "{:<8} {:<36} {:>7.0} m/min {:>4.0} m/min {:>7.3} mm/z {:>6.0} N/mm²",
                m["key"].as_str().unwrap_or_default(),
                m["name"].as_str().unwrap_or_default(),
                m["vc_carbide_m_min"].as_f64().unwrap_or(f64::NAN),
                m["vc_hss_m_min"].as_f64().unwrap_or(f64::NAN),
                m["chip_load_mm"][2].as_f64().unwrap_or(f64::NAN),
                m["kc11_n_mm2"].as_f64().unwrap_or(f64::NAN),
            );
        }
        return out;
    }
    let n = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    let s = &doc["speeds"];
    let _ = writeln!(
        out,
        "{} with {} {}: a_e {:.3} mm, a_p {:.3} mm",
        doc["material"].as_str().unwrap_or_default(),
        doc["tool_material"].as_str().unwrap_or_default(),
        doc["tool"].as_str().unwrap_or_default(),
        n(&doc["radial_depth_mm"]),
        n(&doc["axial_depth_mm"])
    );
    let _ = writeln!(
        out,
        "spindle {:.0} rpm (v_c {:.1} m/min), feed {:.0} mm/min ({:.4} mm/tooth, chip \
         thinning ×{:.3}), ramp {:.0} mm/min, plunge {:.0} mm/min, removal {:.2} cm³/min",
        n(&s["spindle_rpm"]),
        n(&s["cutting_speed_m_min"]),
        n(&s["feed_mm_min"]),
        n(&s["feed_per_tooth_mm"]),
        n(&s["chip_thinning"]),
        n(&s["ramp_feed_mm_min"]),
        n(&s["plunge_feed_mm_min"]),
        n(&s["removal_cm3_min"])
    );
    for src in s["sources"].as_array().into_iter().flatten() {
        let _ = writeln!(
            out,
            "  {}: {}",
            src["quantity"].as_str().unwrap_or_default(),
            src["from"].as_str().unwrap_or_default()
        );
    }
    let l = &doc["load"];
    if l.is_object() {
        let _ = writeln!(
            out,
            "load: torque mean {:.3} N·m, peak {:.3} N·m; power {:.0} W; peak force {:.0} N; \
             deflection {}",
            n(&l["mean_torque_nm"]),
            n(&l["peak_torque_nm"]),
            n(&l["mean_power_w"]),
            n(&l["peak_force_n"]),
            l["deflection_mm"]
                .as_f64()
                .map_or("not modelled".into(), |d| format!("{d:.4} mm"))
        );
        for f in l["flags"].as_array().into_iter().flatten() {
            let _ = writeln!(out, "  warning: {}", f.as_str().unwrap_or_default());
        }
    }
    if let Some(e) = doc["load_error"].as_str() {
        let _ = writeln!(out, "load: {e}");
    }
    out
}
