//! Load limits for `talas forces` from the tool library (`--tool-library FILE --tool NAME`),
//! the tool record of a tool path and the machine file's spindle power, used when the
//! `--max-*` flags are absent; bad limits are refused with the file and place.

mod common;

use common::{data, talas, talas_json, temp_file};
use serde_json::Value;

const PROGRAM: &str = "G21 G90 G94\nG0 Z5\nG0 X-20 Y0\nG1 Z-3 F600\nG1 X20\nG0 Z5\nM30\n";
const SPEC: &str = "flat:d=10,flute=20,flutes=2,helix=30,rake=10";

fn library() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/force/coefficients.toml"
    )
    .to_string()
}

/// The slot program's forces with `extra` arguments.
fn slot(extra: &[&str]) -> Value {
    let ngc = temp_file("force-limits", "slot.ngc", PROGRAM);
    let lib = library();
    let mut args = vec![
        "forces",
        ngc.to_str().unwrap(),
        "--coefficients",
        &lib,
        "--stock",
        "box:-10,-10,-10,10,10,0",
        "--rpm",
        "3000",
        "--json",
    ];
    args.extend_from_slice(extra);
    talas_json(&args)
}

fn slot_move(doc: &Value) -> &Value {
    doc["moves"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["line"] == 5)
        .unwrap()
}

fn flags(doc: &Value) -> Vec<String> {
    slot_move(doc)["limits_exceeded"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect()
}

#[test]
fn tool_library_limits_apply_when_flags_are_absent() {
    let tools = data("force/tools-limits.toml");
    let tools = tools.to_str().unwrap();
    let doc = slot(&["--tool-library", tools, "--tool", "slot mill d10 weak"]);
    assert_eq!(doc["limits"]["max_force_n"], 1.0);
    assert_eq!(doc["limits"]["max_torque_nm"], 100_000.0);
    assert_eq!(doc["limits"]["max_power_w"], Value::Null);
    assert_eq!(doc["limit_sources"]["force"], "tool");
    assert_eq!(doc["limit_sources"]["power"], "none");
    // A 3 mm deep slot of a D10 end mill carries far more than 1 N and far less than 10⁵ N·m.
    assert!(slot_move(&doc)["peak_resultant_n"].as_f64().unwrap() > 1.0);
    assert_eq!(flags(&doc), ["force"]);
    assert_eq!(doc["totals"]["moves_over_limits"], 1);

    // A flag wins over the tool's limit.
    let doc = slot(&[
        "--tool-library",
        tools,
        "--tool",
        "Slot mill D10 weak",
        "--max-force",
        "100000",
    ]);
    assert_eq!(doc["limit_sources"]["force"], "option");
    assert!(flags(&doc).is_empty());

    // Limits given beside the cutter in the entry.
    let doc = slot(&[
        "--tool-library",
        tools,
        "--tool",
        "Slot mill D10 entry limits",
    ]);
    assert_eq!(doc["limits"]["max_power_w"], 0.5);
    assert_eq!(doc["limit_sources"]["power"], "tool");
    assert_eq!(flags(&doc), ["power"]);
}

#[test]
fn the_machine_spindle_power_limits_the_power() {
    let tools = data("force/tools-limits.toml");
    let machine = data("force/mill-3axis-spindle.json");
    let (tools, machine) = (tools.to_str().unwrap(), machine.to_str().unwrap());
    // No tool power limit: the 1 W spindle is the limit.
    let doc = slot(&[
        "--tool-library",
        tools,
        "--tool",
        "Slot mill D10 no limits",
        "--machine",
        machine,
    ]);
    assert_eq!(doc["limits"]["max_power_w"], 1.0);
    assert_eq!(doc["limit_sources"]["power"], "machine spindle");
    assert_eq!(flags(&doc), ["power"]);
    // The tool's 0.5 W is lower than the spindle's 1 W.
    let doc = slot(&[
        "--tool-library",
        tools,
        "--tool",
        "Slot mill D10 entry limits",
        "--machine",
        machine,
    ]);
    assert_eq!(doc["limits"]["max_power_w"], 0.5);
    assert_eq!(doc["limit_sources"]["power"], "tool");
    // The built-in mill carries a 7.5 kW spindle; a slot at 3000 rpm stays far below it.
    let doc = slot(&["--tool", SPEC, "--machine", "mill-3axis"]);
    assert_eq!(doc["limits"]["max_power_w"], 7500.0);
    assert!(flags(&doc).is_empty());
    let mean_w = slot_move(&doc)["mean_power_w"].as_f64().unwrap();
    assert!(mean_w > 1.0 && mean_w < 7500.0, "{mean_w}");
}

#[test]
fn a_tool_path_brings_its_tools_limits() {
    let path = temp_file(
        "force-limits",
        "slot.json",
        &format!(
            r#"{{"units": "mm", "tool": {{"spec": "{SPEC}", "limits": {{"max_torque_nm": 0.01}}}},
              "poses": [
                {{"tip": [-20, 0, 5], "kind": "rapid"}},
                {{"tip": [-20, 0, -3], "kind": "plunge", "feed_mm_per_min": 600}},
                {{"tip": [20, 0, -3], "kind": "cut", "feed_mm_per_min": 600}}
              ]}}"#
        ),
    );
    let lib = library();
    let doc = talas_json(&[
        "forces",
        path.to_str().unwrap(),
        "--coefficients",
        &lib,
        "--stock",
        "box:-10,-10,-10,10,10,0",
        "--rpm",
        "3000",
        "--json",
    ]);
    assert_eq!(doc["limits"]["max_torque_nm"], 0.01);
    assert_eq!(doc["limit_sources"]["torque"], "tool");
    let cut = doc["moves"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["class"] == "cut")
        .unwrap();
    assert_eq!(cut["limits_exceeded"][0], "torque");
}

fn refused(args: &[&str]) -> String {
    let out = talas(args);
    assert_eq!(out.status.code(), Some(2), "{args:?}");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    err
}

#[test]
fn bad_limits_are_refused_with_the_place() {
    let ngc = temp_file("force-limits-bad", "slot.ngc", PROGRAM);
    let lib = library();
    let bad_tools = temp_file(
        "force-limits-bad",
        "tools.toml",
        "version = 1\n[[tools]]\nname = \"T\"\nspec = \"flat:d=10,flutes=2\"\nlimits = { max_force_n = -3 }\n",
    );
    let base = |tools: &str, tool: &str| {
        vec![
            "forces".to_string(),
            ngc.to_str().unwrap().to_string(),
            "--coefficients".into(),
            lib.clone(),
            "--stock".into(),
            "box:-10,-10,-10,10,10,0".into(),
            "--rpm".into(),
            "3000".into(),
            "--tool-library".into(),
            tools.to_string(),
            "--tool".into(),
            tool.to_string(),
        ]
    };
    let run = |v: Vec<String>| refused(&v.iter().map(String::as_str).collect::<Vec<_>>());
    let err = run(base(bad_tools.to_str().unwrap(), "T"));
    assert!(err.contains("tools.toml") && err.contains("line") && err.contains("max_force_n"));
    let good = data("force/tools-limits.toml");
    let err = run(base(good.to_str().unwrap(), "no such tool"));
    assert!(err.contains("no tool named 'no such tool'") && err.contains("Slot mill D10 weak"));
    let mut v = base(good.to_str().unwrap(), "Slot mill D10 weak");
    v.push("--max-torque=-1".into());
    assert!(run(v).contains("--max-torque"));
    let bad_machine = temp_file(
        "force-limits-bad",
        "m.json",
        &std::fs::read_to_string(data("force/mill-3axis-spindle.json"))
            .unwrap()
            .replace("\"spindle_power_w\": 1", "\"spindle_power_w\": -5"),
    );
    let mut v = base(good.to_str().unwrap(), "Slot mill D10 weak");
    v.extend(["--machine".into(), bad_machine.to_str().unwrap().into()]);
    assert!(run(v).contains("spindle_power_w"));
}

#[test]
fn limits_survive_the_tool_library_and_project_formats() {
    use talas::project::ToolEntry;
    #[derive(serde::Serialize, serde::Deserialize)]
    struct Tools {
        tools: Vec<ToolEntry>,
    }
    let text = std::fs::read_to_string(data("force/tools-limits.toml")).unwrap();
    let lib: Tools = toml::from_str(&text).unwrap();
    assert_eq!(lib.tools[0].cutter.limits.max_force_n, Some(1.0));
    assert_eq!(lib.tools[1].cutter.limits.max_power_w, Some(0.5));
    assert!(lib.tools[2].cutter.limits.is_empty());
    let back: Tools = toml::from_str(&toml::to_string(&lib).unwrap()).unwrap();
    assert_eq!(back.tools, lib.tools);
}
