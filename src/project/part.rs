//! The part reference: a path plus a content hash, so that a moved or changed file is noticed.

use std::path::{Path, PathBuf};

/// Where the project's part lives and what its content was when it was referenced.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct PartRef {
    /// Path of the part file (as the user opened it).
    pub path: PathBuf,
    /// FNV-1a 64-bit hash of the file's bytes, 16 hex digits ([`content_hash`]); empty when a
    /// project written by hand or by another program leaves it out (nothing to compare then).
    #[serde(default)]
    pub content_hash: String,
    /// File size in bytes (0 when left out).
    #[serde(default)]
    pub size_bytes: u64,
}

/// What a [`PartRef`] finds on disk now.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PartStatus {
    /// The file is there with the same content.
    Unchanged,
    /// The file is there but its content differs.
    Changed,
    /// The file cannot be read (moved, deleted, no permission): the reason.
    Missing(String),
}

/// FNV-1a 64-bit hash of `bytes`, as 16 lower-case hex digits.
#[must_use]
pub fn content_hash(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

impl PartRef {
    /// Reference the file at `path` (reads it once to hash it).
    ///
    /// # Errors
    /// The I/O error's text, naming the file, when it cannot be read.
    pub fn from_file(path: &Path) -> Result<Self, String> {
        let bytes = crate::storage::read_bounded(path, crate::storage::PART_LIMIT_BYTES)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(Self::from_bytes(path, &bytes))
    }

    /// Reference `path` whose content is `bytes` (already read by the caller).
    #[must_use]
    pub fn from_bytes(path: &Path, bytes: &[u8]) -> Self {
        Self {
            path: path.to_path_buf(),
            content_hash: content_hash(bytes),
            size_bytes: bytes.len() as u64,
        }
    }

    /// Compare the file on disk now with the reference.
    #[must_use]
    pub fn status(&self) -> PartStatus {
        match crate::storage::read_bounded(&self.path, crate::storage::PART_LIMIT_BYTES) {
            Ok(bytes)
                if self.content_hash.is_empty() || content_hash(&bytes) == self.content_hash =>
            {
                PartStatus::Unchanged
            }
            Ok(_) => PartStatus::Changed,
            Err(e) => PartStatus::Missing(format!("{}: {e}", self.path.display())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_part_written_without_hash_or_size_reads_and_is_not_called_changed() {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/plate-hole.stp");
        let text = format!("path = {:?}\n", file.display().to_string());
        let r: PartRef = toml::from_str(&text).expect("hash and size are optional");
        assert!(r.content_hash.is_empty());
        assert_eq!(r.size_bytes, 0);
        assert_eq!(r.status(), PartStatus::Unchanged);
        // A hash that is given is still checked.
        let wrong = PartRef {
            content_hash: "0000000000000000".into(),
            ..r
        };
        assert_eq!(wrong.status(), PartStatus::Changed);
    }
}
