//! The layer rule, checked: an engine module may use only modules of lower layers (plus the
//! same-layer uses listed in `SAME_LAYER`), never a GUI crate; `render` never names an engine
//! module; only `app` sees both. ARCHITECTURE.md holds the same table: keep them in step.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

/// (module, layer). `cli` sits above the engine; `render`/`app` are the GUI.
const LAYERS: &[(&str, u32)] = &[
    ("units", 0),
    ("diagnostics", 0),
    ("storage", 0),
    ("geometry", 0),
    ("import", 1),
    ("tools", 1),
    ("machine", 1),
    ("gcode", 1),
    ("toolpath", 2),
    ("strategies", 3),
    ("checks", 3),
    ("reduce", 3),
    ("post", 4),
    ("feed", 4),
    ("simulation", 4),
    ("force", 4),
    ("profile", 4),
    ("project", 5),
    ("control", 5),
    ("cli", 6),
    ("render", 7),
    ("app", 8),
];

/// Allowed uses inside one layer: (user, used).
const SAME_LAYER: &[(&str, &str)] = &[
    ("diagnostics", "units"),
    ("geometry", "units"),
    ("geometry", "diagnostics"),
    ("strategies", "checks"),
    ("force", "simulation"),
    ("profile", "post"),
];

const GUI_CRATES: &[&str] = &[
    "egui",
    "eframe",
    "egui_wgpu",
    "wgpu",
    "winit",
    "rfd",
    "egui_kittest",
    "egui_plot",
    "egui_file",
];

fn layer_of(module: &str) -> Option<u32> {
    LAYERS.iter().find(|(m, _)| *m == module).map(|(_, l)| *l)
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<_> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The top-level module a source file belongs to (`src/geometry/nurbs.rs` → `geometry`).
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).ok()?;
    let first = rel.components().next()?.as_os_str().to_str()?;
    let name = first.strip_suffix(".rs").unwrap_or(first);
    match name {
        "lib" | "main" => None,
        other => Some(other.to_string()),
    }
}

/// Strip `//` comments so doc text does not count as a use.
fn code_only(text: &str) -> String {
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// `crate::X` (and `talas::X`) module names used in `code`.
fn crate_uses(code: &str) -> BTreeSet<String> {
    let mut used = BTreeSet::new();
    for prefix in ["crate::", "talas::"] {
        for (i, _) in code.match_indices(prefix) {
            let before = code[..i].chars().next_back();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                continue;
            }
            let rest = &code[i + prefix.len()..];
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                used.insert(name);
            }
        }
        // `use crate::{a, b}` groups.
        for (i, _) in code.match_indices(&format!("{prefix}{{")) {
            let rest = &code[i + prefix.len() + 1..];
            let group: String = rest.chars().take_while(|c| *c != '}').collect();
            for item in group.split(',') {
                let name: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    used.insert(name);
                }
            }
        }
    }
    used
}

fn gui_crates_named(code: &str) -> Vec<&'static str> {
    GUI_CRATES
        .iter()
        .copied()
        .filter(|c| {
            code.match_indices(&format!("{c}::")).any(|(i, _)| {
                let before = code[..i].chars().next_back();
                !before.is_some_and(|ch| ch.is_alphanumeric() || ch == '_' || ch == ':')
            })
        })
        .collect()
}

fn violations() -> Vec<String> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    assert!(files.len() > 5, "no sources found under {}", src.display());
    let mut bad = Vec::new();
    for file in files {
        let Some(module) = module_of(&src, &file) else {
            continue;
        };
        let Some(layer) = layer_of(&module) else {
            bad.push(format!(
                "{}: module `{module}` is not in the layer table",
                file.display()
            ));
            continue;
        };
        let code = code_only(&fs::read_to_string(&file).unwrap_or_default());
        if module != "app" && module != "render" {
            for c in gui_crates_named(&code) {
                bad.push(format!(
                    "{}: engine module `{module}` names GUI crate `{c}`",
                    file.display()
                ));
            }
        }
        for used in crate_uses(&code) {
            if used == module {
                continue;
            }
            let Some(used_layer) = layer_of(&used) else {
                continue;
            };
            let ok = match module.as_str() {
                "app" => true,
                "render" => false,
                _ => {
                    used_layer < layer
                        || (used_layer == layer
                            && SAME_LAYER.contains(&(module.as_str(), used.as_str())))
                }
            };
            if !ok || (module != "app" && (used == "render" || used == "app")) {
                bad.push(format!(
                    "{}: `{module}` (L{layer}) uses `{used}` (L{used_layer})",
                    file.display()
                ));
            }
        }
    }
    bad
}

#[test]
fn engine_modules_respect_layers_and_never_name_gui_crates() {
    let bad = violations();
    assert!(bad.is_empty(), "layer violations:\n{}", bad.join("\n"));
}

#[test]
fn the_checker_catches_violations() {
    // The checker itself must be able to fail: feed it known-bad code.
    assert!(crate_uses("use crate::app::x; fn f() { crate::geometry::y(); }").contains("app"));
    assert!(crate_uses("use crate::{import, geometry::mesh};").contains("import"));
    assert!(!crate_uses("// no use here\nlet s = mycrate::x;").contains("x"));
    assert_eq!(
        gui_crates_named("let c = egui::Context::default();"),
        vec!["egui"]
    );
    assert!(gui_crates_named("let c = my_egui::Context::default();").is_empty());
    assert!(layer_of("geometry") < layer_of("import"));
}

#[test]
fn architecture_md_lists_every_engine_module() {
    let text = fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md"))
        .unwrap_or_default();
    for (m, _) in LAYERS {
        assert!(
            text.contains(&format!("`{m}`")),
            "ARCHITECTURE.md does not mention `{m}`"
        );
    }
}
