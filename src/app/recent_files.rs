//! The recent-files list, kept in `$XDG_CONFIG_HOME/talas/recent-files.txt` (one path a line,
//! newest first). Reading or writing it never fails loudly: a missing list is an empty one.

use std::path::{Path, PathBuf};

/// How many recent files are kept.
pub const MAX_RECENT: usize = 10;

/// Recently opened files, newest first.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RecentFiles {
    /// The paths.
    pub paths: Vec<PathBuf>,
    store: Option<PathBuf>,
}

impl RecentFiles {
    /// Load the list from the user's config folder (or an empty list).
    #[must_use]
    pub fn load() -> Self {
        let store = config_dir().map(|d| d.join("talas").join("recent-files.txt"));
        let paths = store
            .as_deref()
            .and_then(|p| std::fs::read_to_string(p).ok())
            .map(|text| {
                text.lines()
                    .filter(|l| !l.trim().is_empty())
                    .map(PathBuf::from)
                    .take(MAX_RECENT)
                    .collect()
            })
            .unwrap_or_default();
        Self { paths, store }
    }

    /// A list that is never saved (tests).
    #[must_use]
    pub fn in_memory() -> Self {
        Self::default()
    }

    /// Put `path` first; returns an error message when the list could not be saved.
    pub fn add(&mut self, path: &Path) -> Option<String> {
        let path = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        self.paths.retain(|p| *p != path);
        self.paths.insert(0, path);
        self.paths.truncate(MAX_RECENT);
        self.save()
    }

    fn save(&self) -> Option<String> {
        let store = self.store.as_ref()?;
        let text: String = self
            .paths
            .iter()
            .map(|p| format!("{}\n", p.display()))
            .collect();
        let write = || -> std::io::Result<()> {
            if let Some(dir) = store.parent() {
                std::fs::create_dir_all(dir)?;
            }
            crate::storage::write_atomic(store, text.as_bytes())
        };
        write().err().map(|e| {
            format!(
                "could not save the recent-files list {}: {e}",
                store.display()
            )
        })
    }
}

fn config_dir() -> Option<PathBuf> {
    std::env::var_os("XDG_CONFIG_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("HOME")
                .filter(|v| !v.is_empty())
                .map(|h| PathBuf::from(h).join(".config"))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn newest_first_without_duplicates() {
        let mut r = RecentFiles::in_memory();
        for name in ["/a.stp", "/b.stp", "/a.stp"] {
            assert_eq!(r.add(Path::new(name)), None);
        }
        assert_eq!(
            r.paths,
            vec![PathBuf::from("/a.stp"), PathBuf::from("/b.stp")]
        );
        for i in 0..20 {
            r.add(Path::new(&format!("/{i}.stl")));
        }
        assert_eq!(r.paths.len(), MAX_RECENT);
    }
}
