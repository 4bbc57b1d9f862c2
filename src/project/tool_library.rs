//! The user's tool library on disk (`tools.toml`), engine side: reading it and saving it so that
//! two workstations sharing one library never lose each other's tools.
//!
//! A plain save is last-writer-wins: workstation A adds a tool and saves, workstation B (which
//! read the file before A's save) adds another and saves, and A's tool is gone without a word
//! (issue 36). [`ToolLibrary::save_merged`] is a three-way merge instead: it re-reads the file,
//! compares it and this workstation's library with the library as this workstation last read or
//! wrote it (the *base*), and writes the union, keyed by tool name:
//!
//! - a tool added, edited or removed on one side only keeps that change;
//! - a tool changed alike on both sides is that tool;
//! - a tool changed differently on both sides (or edited on one and removed on the other) is a
//!   conflict: nothing is written and the error names the tool and the file.
//!
//! The default tool follows the side that changed it (by name, since indices shift). The merged
//! library is returned: it is the base of the next save.

use std::collections::BTreeMap;
use std::path::Path;

use crate::project::ToolEntry;
use crate::tools::CutterKind;

/// The library format version written by this build.
pub const TOOL_LIBRARY_VERSION: u32 = 1;

/// A tool library: what a new project starts with.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ToolLibrary {
    /// Format version (1 when missing).
    #[serde(default = "first_version")]
    pub version: u32,
    /// Index of the tool a new project selects (`None`: the first ball end mill, if any).
    #[serde(default)]
    pub default_tool: Option<usize>,
    /// The tools.
    #[serde(default)]
    pub tools: Vec<ToolEntry>,
}

fn first_version() -> u32 {
    1
}

impl Default for ToolLibrary {
    fn default() -> Self {
        Self {
            version: TOOL_LIBRARY_VERSION,
            default_tool: None,
            tools: Vec::new(),
        }
    }
}

/// The key of each tool: its name, and `#k` after the k-th repeat of a name (k ≥ 2).
fn keys(lib: &ToolLibrary) -> Vec<String> {
    let mut seen: BTreeMap<&str, usize> = BTreeMap::new();
    lib.tools
        .iter()
        .map(|t| {
            let n = seen.entry(t.name.as_str()).or_insert(0);
            *n += 1;
            if *n == 1 {
                t.name.clone()
            } else {
                format!("{}#{n}", t.name)
            }
        })
        .collect()
}

fn by_key(lib: &ToolLibrary) -> BTreeMap<String, &ToolEntry> {
    keys(lib).into_iter().zip(&lib.tools).collect()
}

fn default_key(lib: &ToolLibrary) -> Option<String> {
    lib.default_tool.and_then(|i| keys(lib).get(i).cloned())
}

impl ToolLibrary {
    /// Parse library TOML; `source` names the file in errors.
    ///
    /// # Errors
    /// A one-line message naming `source`: TOML syntax (with line), a newer version, an invalid
    /// tool size.
    pub fn from_toml(text: &str, source: &Path) -> Result<Self, String> {
        let lib: Self = toml::from_str(text).map_err(|e| {
            let line = e.span().map_or(1, |s| {
                text.get(..s.start).unwrap_or("").matches('\n').count() + 1
            });
            format!("{}:{line}: {}", source.display(), e.message().trim())
        })?;
        if lib.version > TOOL_LIBRARY_VERSION {
            return Err(format!(
                "{}: tool library version {} is newer than this Talas understands ({TOOL_LIBRARY_VERSION})",
                source.display(),
                lib.version
            ));
        }
        for (i, t) in lib.tools.iter().enumerate() {
            t.cutter
                .validate()
                .map_err(|e| format!("{}: tool {} ('{}'): {e}", source.display(), i + 1, t.name))?;
        }
        Ok(lib)
    }

    /// The library at `path`: `Ok(None)` when the file does not exist.
    ///
    /// # Errors
    /// The read or parse error, naming the file.
    pub fn load(path: &Path) -> Result<Option<Self>, String> {
        match crate::storage::read_text_bounded(path, crate::storage::TEXT_LIMIT_BYTES) {
            Ok(text) => Self::from_toml(&text, path).map(Some),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(format!("{}: {e}", path.display())),
        }
    }

    /// Write the library to `path` atomically (creating the folder), replacing what is there.
    ///
    /// # Errors
    /// The I/O or encoding error, naming the file.
    pub fn save(&self, path: &Path) -> Result<(), String> {
        let text = toml::to_string_pretty(self).map_err(|e| format!("{}: {e}", path.display()))?;
        if let Some(dir) = path.parent()
            && !dir.as_os_str().is_empty()
        {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let header = "# Talas tool library (lengths in mm, cone half_angle in rad)\n\n";
        crate::storage::write_atomic(path, format!("{header}{text}").as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Save this library to `path`, merged with what another workstation may have written
    /// there since this one read `base` (see the module's text). Returns the library written,
    /// the base of the next save.
    ///
    /// # Errors
    /// A conflict naming the tool and the file (nothing is written then), or the read, parse or
    /// write error naming the file.
    pub fn save_merged(&self, base: &Self, path: &Path) -> Result<Self, String> {
        let disk = Self::load(path)?.unwrap_or_else(|| base.clone());
        let merged = self.merge(base, &disk).map_err(|tool| {
            format!(
                "{}: tool '{tool}' was changed here and, differently, by another workstation \
                 since this one read the library; nothing was saved (reopen the tool library to \
                 see the other change, then make yours again)",
                path.display()
            )
        })?;
        merged.save(path)?;
        Ok(merged)
    }

    /// The three-way merge of `self` (this side) and `other` (the file now) over `base`.
    ///
    /// # Errors
    /// The key (name) of the first tool both sides changed differently.
    pub fn merge(&self, base: &Self, other: &Self) -> Result<Self, String> {
        if other == base {
            return Ok(self.clone());
        }
        if self == base || self == other {
            return Ok(other.clone());
        }
        let (b, m, o) = (by_key(base), by_key(self), by_key(other));
        // Order: this side's tools, then the other side's new ones in their order.
        let mut order: Vec<String> = keys(self);
        for k in keys(other) {
            if !m.contains_key(&k) && !b.contains_key(&k) {
                order.push(k);
            }
        }
        // Tools the other side kept but this side removed come back only when edited there;
        // they sit where the other side has them, after this side's.
        for k in keys(other) {
            if !order.contains(&k) {
                order.push(k);
            }
        }
        let mut tools = Vec::new();
        let mut kept_keys = Vec::new();
        for k in order {
            let (bt, mt, ot) = (b.get(&k), m.get(&k), o.get(&k));
            let pick = if mt == ot || bt == ot {
                mt
            } else if bt == mt {
                ot
            } else {
                return Err(k);
            };
            if let Some(t) = pick {
                tools.push((*t).clone());
                kept_keys.push(k);
            }
        }
        let (bd, md, od) = (default_key(base), default_key(self), default_key(other));
        let default = if md == bd { od } else { md };
        let default_tool = default.and_then(|d| kept_keys.iter().position(|k| *k == d));
        Ok(Self {
            version: TOOL_LIBRARY_VERSION,
            default_tool,
            tools,
        })
    }

    /// The tool a new project selects: `default_tool` when valid, else the first ball end mill,
    /// else the first tool.
    #[must_use]
    pub fn default_selection(&self) -> Option<usize> {
        self.default_tool
            .filter(|&i| i < self.tools.len())
            .or_else(|| {
                self.tools
                    .iter()
                    .position(|t| t.cutter.kind == CutterKind::Ball)
            })
            .or(if self.tools.is_empty() { None } else { Some(0) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::parse_tool_spec;

    fn tool(name: &str, spec: &str) -> ToolEntry {
        ToolEntry {
            name: name.into(),
            cutter: parse_tool_spec(spec).expect("spec"),
        }
    }

    fn names(lib: &ToolLibrary) -> Vec<&str> {
        lib.tools.iter().map(|t| t.name.as_str()).collect()
    }

    fn shared_file(name: &str) -> std::path::PathBuf {
        let dir =
            std::env::temp_dir().join(format!("talas-toolmerge-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir.join("tools.toml")
    }

    /// Two workstations read one library; each adds a tool and saves: both tools are in the
    /// file (a plain save keeps only the last writer's), and a third reader sees both.
    #[test]
    fn two_writers_adding_tools_keep_both() {
        let path = shared_file("add");
        let start = ToolLibrary {
            default_tool: Some(0),
            tools: vec![tool("Ball 6", "ball:d=6"), tool("Flat 10", "flat:d=10")],
            ..ToolLibrary::default()
        };
        start.save(&path).expect("first save");
        // Both read the same file.
        let base_a = ToolLibrary::load(&path).expect("read").expect("there");
        let base_b = base_a.clone();
        let mut a = base_a.clone();
        a.tools.push(tool("Bull 8", "bull:d=8,r=1"));
        let mut b = base_b.clone();
        b.tools.push(tool("Cone 10", "cone:d=10,angle=45"));
        a.save_merged(&base_a, &path).expect("A saves");
        // The last-writer-wins save this replaces drops A's tool.
        let plain_path = path.with_file_name("plain.toml");
        std::fs::copy(&path, &plain_path).unwrap();
        b.save(&plain_path).expect("plain save");
        let plain = ToolLibrary::load(&plain_path)
            .expect("read")
            .expect("there");
        assert!(!names(&plain).contains(&"Bull 8"));
        let written = b.save_merged(&base_b, &path).expect("B saves");
        let on_disk = ToolLibrary::load(&path).expect("read").expect("there");
        assert_eq!(written, on_disk);
        assert_eq!(names(&on_disk), ["Ball 6", "Flat 10", "Cone 10", "Bull 8"]);
        assert_eq!(on_disk.default_tool, Some(0));
        // A's next save, over what it wrote, keeps B's tool too.
        let base_a2 = a.clone();
        let mut a2 = a.clone();
        a2.tools.retain(|t| t.name != "Flat 10");
        a2.save_merged(&base_a2, &path).expect("A saves again");
        let on_disk = ToolLibrary::load(&path).expect("read").expect("there");
        assert_eq!(names(&on_disk), ["Ball 6", "Bull 8", "Cone 10"]);
        let _ = std::fs::remove_dir_all(path.parent().unwrap());
    }

    /// Edits of different tools merge; edits of one tool that differ are refused with the
    /// tool's name and the file, and the file is left as the other writer wrote it.
    #[test]
    fn conflicting_edits_are_refused_naming_the_tool() {
        let path = shared_file("edit");
        let start = ToolLibrary {
            tools: vec![tool("Ball 6", "ball:d=6"), tool("Flat 10", "flat:d=10")],
            ..ToolLibrary::default()
        };
        start.save(&path).expect("first save");
        let base = ToolLibrary::load(&path).expect("read").expect("there");
        let mut a = base.clone();
        a.tools[0] = tool("Ball 6", "ball:d=6,flute=30");
        a.default_tool = Some(1);
        let mut b = base.clone();
        b.tools[1] = tool("Flat 10", "flat:d=10,flute=40");
        a.save_merged(&base, &path).expect("A saves");
        let merged = b.save_merged(&base, &path).expect("other tools merge");
        assert!((merged.tools[0].cutter.flute_length - 30.0).abs() < 1e-12);
        assert!((merged.tools[1].cutter.flute_length - 40.0).abs() < 1e-12);
        assert_eq!(merged.default_tool, Some(1), "A's default kept");
        // Both change the ball, differently.
        let base = merged.clone();
        let mut a = base.clone();
        a.tools[0] = tool("Ball 6", "ball:d=6,flute=20");
        let mut b = base.clone();
        b.tools[0] = tool("Ball 6", "ball:d=6,flute=25");
        a.save_merged(&base, &path).expect("A saves");
        let before = std::fs::read_to_string(&path).unwrap();
        let e = b.save_merged(&base, &path).expect_err("a conflict");
        assert!(e.contains("'Ball 6'") && e.contains("tools.toml"), "{e}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), before);
        // An edit against a removal is a conflict too.
        let base = ToolLibrary::load(&path).expect("read").expect("there");
        let mut a = base.clone();
        a.tools.remove(1);
        let mut b = base.clone();
        b.tools[1] = tool("Flat 10", "flat:d=10,flute=50");
        a.save_merged(&base, &path).expect("A removes");
        let e = b
            .save_merged(&base, &path)
            .expect_err("edit against removal");
        assert!(e.contains("'Flat 10'"), "{e}");
        let _ = std::fs::remove_dir_all(path.parent().unwrap());
    }
}
