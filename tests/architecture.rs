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
    ("features", 1),
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
    ("geometry", "storage"),
    ("strategies", "checks"),
    ("force", "simulation"),
    ("profile", "post"),
    ("gcode", "machine"),
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

/// The engine layers (L0…L5) of a markdown layer table, `| Lk | `a`, `b` | … |`, in `text` (a
/// doc comment's `//! ` prefix is ignored): for each layer, the module names of its second
/// column.
fn layer_table(text: &str) -> std::collections::BTreeMap<u32, BTreeSet<String>> {
    let mut table = std::collections::BTreeMap::new();
    for line in text.lines() {
        let line = line.trim_start_matches("//!").trim();
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let Some(layer) = cells.get(1).and_then(|c| c.strip_prefix('L')) else {
            continue;
        };
        let (Ok(layer), Some(modules)) = (layer.parse::<u32>(), cells.get(2)) else {
            continue;
        };
        let names = modules
            .split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect();
        table.insert(layer, names);
    }
    table
}

/// The layer tables of ARCHITECTURE.md and of the crate docs in src/lib.rs say what `LAYERS`
/// says, layer by layer.
#[test]
fn the_layer_tables_in_the_docs_match_the_checked_layers() {
    let mut expected = std::collections::BTreeMap::<u32, BTreeSet<String>>::new();
    for (m, l) in LAYERS.iter().filter(|(_, l)| *l <= 5) {
        expected.entry(*l).or_default().insert((*m).to_string());
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for doc in ["ARCHITECTURE.md", "src/lib.rs"] {
        let text = fs::read_to_string(root.join(doc)).unwrap_or_default();
        assert_eq!(layer_table(&text), expected, "the layer table of {doc}");
    }
    let sample =
        "//! | L1 | [`import`], [`tools`] |\n| L2 | `toolpath` | CL poses |\n| CLI | `cli` |";
    let parsed = layer_table(sample);
    assert_eq!(parsed.len(), 2);
    assert_eq!(parsed[&1].len(), 2);
    assert!(parsed[&2].contains("toolpath"));
}

/// The same-layer uses ARCHITECTURE.md allows ("`a` → `b`" in its "Same-layer uses allowed"
/// line) are exactly `SAME_LAYER`.
#[test]
fn the_same_layer_uses_in_architecture_md_are_the_checked_ones() {
    let text = fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md"))
        .unwrap_or_default();
    let line = text
        .lines()
        .find(|l| l.starts_with("Same-layer uses allowed:"))
        .expect("ARCHITECTURE.md has a \"Same-layer uses allowed:\" line");
    let mut listed = BTreeSet::new();
    // "`user` → `used`, `used2`; …": each clause up to ';' names one user and its used modules.
    for clause in line.split(';') {
        let Some((user, used)) = clause.split_once('→') else {
            continue;
        };
        let Some(user) = user.split('`').rev().nth(1) else {
            continue;
        };
        let used_part = used.split('(').next().unwrap_or_default();
        for used in used_part.split('`').skip(1).step_by(2) {
            listed.insert((user.to_string(), used.to_string()));
        }
    }
    let checked: BTreeSet<(String, String)> = SAME_LAYER
        .iter()
        .map(|(a, b)| ((*a).to_string(), (*b).to_string()))
        .collect();
    assert_eq!(listed, checked);
}

/// The one-way data walk drawn in ARCHITECTURE.md names the engine's types in order (file →
/// Workpiece → Toolpath → MachiningRun → TimedPath → stock / forces / virtual control), and
/// each of those types exists where the drawing says.
#[test]
fn the_data_walk_in_architecture_md_names_existing_types_in_order() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = fs::read_to_string(root.join("ARCHITECTURE.md")).unwrap_or_default();
    let walk = text
        .split("## Pipeline: the one-way data walk")
        .nth(1)
        .and_then(|t| t.split("```").nth(1))
        .expect("ARCHITECTURE.md draws the data walk in a code block");
    let stages = [
        ("file", None),
        (
            "Workpiece",
            Some(("src/import/workpiece.rs", "pub struct Workpiece")),
        ),
        (
            "Toolpath",
            Some(("src/toolpath/mod.rs", "pub struct Toolpath")),
        ),
        (
            "MachiningRun",
            Some(("src/project/run.rs", "pub struct MachiningRun")),
        ),
        (
            "TimedPath",
            Some(("src/feed/timed_path.rs", "pub struct TimedPath")),
        ),
        ("simulation", None),
        ("force model", None),
        ("virtual control", None),
    ];
    let mut from = 0;
    for (name, def) in stages {
        let at = walk[from..]
            .find(name)
            .unwrap_or_else(|| panic!("the data walk does not name {name} after byte {from}"));
        from += at + name.len();
        if let Some((file, decl)) = def {
            let code = fs::read_to_string(root.join(file)).unwrap_or_default();
            assert!(code.contains(decl), "{file} has no `{decl}`");
        }
    }
}

/// The code of a file without its `#[cfg(test)]` module (whose `super` is the file itself).
fn without_test_module(code: &str) -> &str {
    code.find("#[cfg(test)]\nmod ").map_or(code, |i| &code[..i])
}

/// Names `name` as a path's first segment after `prefix` (e.g. `super::` + `plan`) or in a
/// `prefix{…}` group.
fn path_heads(code: &str, prefix: &str) -> BTreeSet<String> {
    let ident = |s: &str| -> String {
        s.trim()
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut heads = BTreeSet::new();
    for (i, _) in code.match_indices(prefix) {
        let before = code[..i].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        let rest = &code[i + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let group: String = group.chars().take_while(|c| *c != '}').collect();
            heads.extend(group.split(',').map(ident).filter(|n| !n.is_empty()));
        } else {
            let name = ident(rest);
            if !name.is_empty() {
                heads.insert(name);
            }
        }
    }
    heads
}

/// The `use` graph among the files of one folder: node `mod` is the folder's own module file
/// (`dir/mod.rs` or `dir.rs`), the others are its child modules (files and sub-folders). A child
/// uses a sibling through `super::sibling` or `crate::…::dir::sibling`, the folder's module
/// through `super::Item`; the module file uses a child through `child::` or `self::child`.
fn sibling_graph(src: &Path, dir: &Path) -> std::collections::BTreeMap<String, BTreeSet<String>> {
    let mut children = BTreeSet::new();
    let Ok(entries) = fs::read_dir(dir) else {
        return Default::default();
    };
    for p in entries.filter_map(Result::ok).map(|e| e.path()) {
        let stem = p.file_stem().and_then(|s| s.to_str()).unwrap_or("");
        let is_rs = p.extension().is_some_and(|e| e == "rs");
        if (is_rs && stem != "mod")
            || (p.is_dir()
                && (p.join("mod.rs").exists() || dir.join(format!("{stem}.rs")).exists()))
        {
            children.insert(stem.to_string());
        }
    }
    let rel = dir.strip_prefix(src).unwrap_or(dir);
    let module_path = format!(
        "crate::{}::",
        rel.components()
            .filter_map(|c| c.as_os_str().to_str())
            .collect::<Vec<_>>()
            .join("::")
    );
    let read = |p: &Path| {
        without_test_module(&code_only(&fs::read_to_string(p).unwrap_or_default())).to_string()
    };
    let mut graph = std::collections::BTreeMap::new();
    for child in &children {
        let file = dir.join(format!("{child}.rs"));
        let file = if file.exists() {
            file
        } else {
            dir.join(child).join("mod.rs")
        };
        let code = read(&file);
        let mut uses = BTreeSet::new();
        for head in path_heads(&code, "super::")
            .into_iter()
            .chain(path_heads(&code, &module_path))
        {
            if children.contains(&head) {
                uses.insert(head);
            } else if !["*", "super", "self", "crate"].contains(&head.as_str()) {
                uses.insert("mod".to_string());
            }
        }
        uses.remove(child);
        graph.insert(child.clone(), uses);
    }
    let own = [dir.join("mod.rs"), dir.with_extension("rs")]
        .into_iter()
        .find(|p| p.exists());
    if let Some(own) = own {
        let code = read(&own);
        let mut uses = BTreeSet::new();
        for c in &children {
            if !path_heads(&code, &format!("{c}::")).is_empty()
                || code.contains(&format!("self::{c}::"))
            {
                uses.insert(c.clone());
            }
        }
        graph.insert("mod".to_string(), uses);
    }
    graph
}

/// The import circles (strongly connected sets of two or more files) in a folder's graph.
fn circles(graph: &std::collections::BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    let reaches = |from: &str| -> BTreeSet<String> {
        let mut seen = BTreeSet::new();
        let mut stack = vec![from.to_string()];
        while let Some(n) = stack.pop() {
            for m in graph.get(&n).into_iter().flatten() {
                if seen.insert(m.clone()) {
                    stack.push(m.clone());
                }
            }
        }
        seen
    };
    let reach: std::collections::BTreeMap<&String, BTreeSet<String>> =
        graph.keys().map(|k| (k, reaches(k))).collect();
    let mut done = BTreeSet::new();
    let mut out = Vec::new();
    for (a, ra) in &reach {
        if done.contains(*a) || !ra.contains(*a) {
            continue;
        }
        let circle: Vec<String> = ra
            .iter()
            .filter(|b| reach.get(b).is_some_and(|rb| rb.contains(*a)))
            .cloned()
            .collect();
        done.extend(circle.iter().cloned());
        if circle.len() > 1 {
            out.push(circle);
        }
    }
    out
}

fn folders(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for p in entries.filter_map(Result::ok).map(|e| e.path()) {
        if p.is_dir() {
            out.push(p.clone());
            folders(&p, out);
        }
    }
}

/// Import circles among the child files of a folder (its `mod.rs` aside) that exist and are
/// tolerated, as (folder, files). A new circle fails the test: break it, or (if it has to be)
/// list it here.
const KNOWN_CIRCLES: &[(&str, &[&str])] = &[
    ("app", &["command", "face_group", "viewport"]),
    ("app", &["forces", "workstation"]),
    ("checks", &["footprint", "gouge"]),
    ("cli", &["forces", "forces_path"]),
    ("cli", &["plan", "plan_25d", "plan_group", "plan_mesh"]),
    ("feed", &["blend", "path"]),
    ("force", &["closed_form", "disks"]),
    ("force", &["path", "stock"]),
    ("gcode", &["interpreter", "motion"]),
    ("import/step/brep", &["assembly", "representation"]),
    ("geometry/planar", &["read", "read_svg"]),
    // The store plans through the pipeline; a rest from the stock reads the store's stock.
    ("project", &["pipeline", "results"]),
    ("simulation", &["batch", "engine"]),
    ("strategies/raster", &["envelope", "passes"]),
];

/// Folders whose files, their `mod.rs` included, use each other one way only.
const NO_CIRCLE_AT_ALL: &[&str] = &["geometry/zmap", "strategies/finish", "strategies/zmap"];

#[test]
fn no_import_circles_among_the_files_of_a_folder() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut dirs = vec![src.clone()];
    folders(&src, &mut dirs);
    dirs.sort();
    let mut bad = Vec::new();
    for d in &dirs {
        let name = d
            .strip_prefix(&src)
            .unwrap_or(d)
            .to_string_lossy()
            .replace('\\', "/");
        let mut g = sibling_graph(&src, d);
        if NO_CIRCLE_AT_ALL.contains(&name.as_str()) {
            bad.extend(
                circles(&g)
                    .into_iter()
                    .map(|c| format!("{name}: {} (mod.rs counted)", c.join(" "))),
            );
        }
        g.remove("mod");
        for c in circles(&g) {
            let known = KNOWN_CIRCLES.iter().any(|(f, files)| {
                *f == name && files.iter().copied().eq(c.iter().map(String::as_str))
            });
            if !known {
                bad.push(format!("{name}: {}", c.join(" ")));
            }
        }
    }
    for f in NO_CIRCLE_AT_ALL {
        assert!(src.join(f).is_dir(), "{f} is not a folder of src");
    }
    assert!(
        bad.is_empty(),
        "import circles among sibling files:\n{}",
        bad.join("\n")
    );
}

#[test]
fn the_circle_checker_finds_circles() {
    let g: std::collections::BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec!["a"]),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.into_iter().map(String::from).collect()))
    .collect();
    assert_eq!(circles(&g), vec![vec!["a", "b", "c"]]);
    let heads = path_heads(
        "use super::{setup::Setup, pass};\nlet x = super::plan::f();",
        "super::",
    );
    assert_eq!(
        heads.into_iter().collect::<Vec<_>>(),
        ["pass", "plan", "setup"]
    );
    assert!(path_heads("use a::super::x;", "super::").is_empty());
    let code = "fn f() {}\n#[cfg(test)]\nmod tests {\n use super::x;\n}";
    assert!(!without_test_module(code).contains("super"));
}

/// The registered workstation features, `(module, type)`, from the `features!` list in
/// src/app/mod.rs (one `module::Type,` line each).
fn registered_features(mod_rs: &str) -> Vec<(String, String)> {
    let Some(start) = mod_rs.find("\nfeatures! {") else {
        return Vec::new();
    };
    let body = &mod_rs[start + "\nfeatures! {".len()..];
    let body = &body[..body.find('}').unwrap_or(body.len())];
    code_only(body)
        .split(',')
        .filter_map(|entry| {
            let (module, ty) = entry.trim().split_once("::")?;
            Some((module.trim().to_string(), ty.trim().to_string()))
        })
        .collect()
}

/// The names of `features` that `code` uses: a feature's module as a path segment
/// (`reduction::`, `super::reduction::`, `crate::app::reduction::`, but not an engine module of
/// the same name such as `crate::project::reduction::`) or its type
/// as a word (`DataReduction`). Doc links count: they tie the file to the feature too.
fn feature_names_in(code: &str, features: &[&(String, String)]) -> Vec<String> {
    let word_char = |c: char| c.is_alphanumeric() || c == '_';
    let mut found = Vec::new();
    for (module, ty) in features {
        let as_path = format!("{module}::");
        // `forces::`, `super::forces::`, `app::forces::`; not an engine module of the same
        // name deeper in a path (`crate::forces::`, `project::forces::`).
        let names_module = code.match_indices(&as_path).any(|(i, _)| {
            let before = &code[..i];
            !before.ends_with(word_char)
                && (!before.ends_with("::")
                    || ["super::", "self::", "app::"]
                        .iter()
                        .any(|p| before.ends_with(p)))
        });
        let names_type = code.match_indices(ty.as_str()).any(|(i, _)| {
            !code[..i].ends_with(word_char) && !code[i + ty.len()..].starts_with(word_char)
        });
        if names_module {
            found.push(as_path);
        }
        if names_type {
            found.push(ty.clone());
        }
    }
    found
}

/// Files of src/app that must name a registered feature, and why (none so far).
const FEATURE_NAMING_EXCEPTIONS: &[(&str, &str)] = &[];

/// A workstation feature is its own folder plus one line of the `features!` list: no shared
/// file of src/app (and no other feature) names a feature's module or type, so adding or
/// removing one touches nothing else. Run: `cargo test --no-default-features --test architecture`.
#[test]
fn no_shared_file_of_the_workstation_names_a_feature() {
    let app = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/app");
    let mod_rs = fs::read_to_string(app.join("mod.rs")).expect("src/app/mod.rs");
    let features = registered_features(&mod_rs);
    assert!(
        features.len() >= 5,
        "the features! list in src/app/mod.rs was not found: {features:?}"
    );
    let mut files = Vec::new();
    rust_files(&app, &mut files);
    let mut bad = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&app).expect("under src/app");
        let owner = rel
            .components()
            .next()
            .and_then(|c| c.as_os_str().to_str())
            .map(|first| first.strip_suffix(".rs").unwrap_or(first).to_string());
        let others: Vec<_> = features
            .iter()
            .filter(|(m, _)| Some(m) != owner.as_ref())
            .collect();
        let mut text = fs::read_to_string(file).expect("readable");
        if rel == Path::new("mod.rs") {
            // The registration list itself.
            let start = text.find("\nfeatures! {").expect("the list");
            let end = start + text[start..].find('}').expect("its end");
            text.replace_range(start..=end, "");
        }
        let rel = rel.to_string_lossy().replace('\\', "/");
        if FEATURE_NAMING_EXCEPTIONS.iter().any(|(f, _)| *f == rel) {
            continue;
        }
        let names = feature_names_in(&text, &others);
        if !names.is_empty() {
            bad.push(format!("src/app/{rel}: {}", names.join(", ")));
        }
    }
    assert!(
        bad.is_empty(),
        "shared workstation files naming a feature (reach it through the Feature trait, \
         FeatureView, Command::Feature / FeatureFile instead):\n{}",
        bad.join("\n")
    );
}

#[test]
fn the_feature_name_checker_finds_names() {
    let list = "x\nfeatures! {\n    reduction::DataReduction,\n    // a comment\n    forces::ForcesWindow,\n}\n";
    let features = registered_features(list);
    assert_eq!(
        features,
        vec![
            ("reduction".to_string(), "DataReduction".to_string()),
            ("forces".to_string(), "ForcesWindow".to_string())
        ]
    );
    let all: Vec<_> = features.iter().collect();
    assert_eq!(
        feature_names_in("use super::super::reduction::window;", &all),
        vec!["reduction::"]
    );
    assert_eq!(
        feature_names_in("let f = crate::app::forces::x();", &all),
        vec!["forces::"]
    );
    assert_eq!(
        feature_names_in("/// [`ForcesWindow`] draws", &all),
        vec!["ForcesWindow"]
    );
    // The engine's module of the same name, longer names and plain words do not count.
    assert!(
        feature_names_in(
            "use crate::forces::x; crate::project::forces::y(); let data_reduction = 1;\n\
             // the reduction\nMyForcesWindow",
            &all
        )
        .is_empty()
    );
}
