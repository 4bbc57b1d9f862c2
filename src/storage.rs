//! Storage: writing files so that a failure never loses work. A save goes to a temporary file in
//! the same folder, is flushed to disk, then renamed over the target; a reader sees the old file
//! or the new one, never half of either. Every saver in Talas (projects, tool paths, posted
//! G-code, STL, recent files, CSV samples) goes through [`write_atomic`] or [`AtomicFile`].
//!
//! A symbolic link is followed, not replaced: the file it points to is rewritten in its own
//! folder and the link stays. An existing file keeps its permission bits.
//!
//! Only a regular file (or a path that does not exist yet) is replaced atomically. A device, a
//! FIFO or a socket (`-o /dev/null`, `-o /dev/stdout`, a named pipe) is written directly, as a
//! shell user expects: renaming a file over it would destroy the device node (as root) or
//! leave the reader at the other end of the pipe with nothing. `-` is standard output.

use std::io::Write;
use std::path::{Path, PathBuf};

/// The most bytes read from a settings or text file (project, tool or coefficient library,
/// dialect, machine, point or loop CSV, profile).
pub const TEXT_LIMIT_BYTES: u64 = 64 << 20;
/// The most bytes read from a G-code program or a tool path.
pub const PROGRAM_LIMIT_BYTES: u64 = 512 << 20;
/// The most bytes read from a part (STEP, STL).
pub const PART_LIMIT_BYTES: u64 = 2 << 30;

/// The most lines read from a G-code program (`feed`, `simulate`, `interpret`, `control`,
/// `forces`): a posted program of 4 million blocks plans in about 3 GB; a 5-million-line file
/// aborted `feed` on allocation under a 2 GiB limit, where this gives an error naming the file.
pub const PROGRAM_LINE_LIMIT: usize = 4_000_000;

/// `Ok` when `text` has at most `limit` lines (counted without allocating); else
/// `InvalidData` naming the limit.
///
/// # Errors
/// `InvalidData` "more than N lines, the most read from a file of this kind".
pub fn check_line_count(text: &str, limit: usize) -> std::io::Result<()> {
    let lines = text.lines().take(limit.saturating_add(1)).count();
    if lines > limit {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("more than {limit} lines, the most read from a file of this kind"),
        ));
    }
    Ok(())
}

/// [`read_text_bounded`] for a G-code program: at most [`PROGRAM_LIMIT_BYTES`] and
/// [`PROGRAM_LINE_LIMIT`] lines.
///
/// # Errors
/// As [`read_text_bounded`] and [`check_line_count`].
pub fn read_program_text(path: &Path) -> std::io::Result<String> {
    let text = read_text_bounded(path, PROGRAM_LIMIT_BYTES)?;
    check_line_count(&text, PROGRAM_LINE_LIMIT)?;
    Ok(text)
}

/// Read `path` whole, refusing more than `limit` bytes (`/dev/zero`, a runaway pipe or a file
/// far larger than any of its kind would otherwise take all the memory).
///
/// # Errors
/// The I/O error, or `InvalidData` naming the limit.
pub fn read_bounded(path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let file = std::fs::File::open(path)?;
    let hint = file.metadata().map_or(0, |m| m.len()).min(limit);
    let mut bytes = Vec::with_capacity(usize::try_from(hint).unwrap_or(0));
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "larger than {} MiB, the most read from a file of this kind",
                limit >> 20
            ),
        ));
    }
    Ok(bytes)
}

/// [`read_bounded`] as UTF-8 text.
///
/// # Errors
/// As [`read_bounded`], or `InvalidData` when the bytes are not UTF-8.
pub fn read_text_bounded(path: &Path, limit: u64) -> std::io::Result<String> {
    String::from_utf8(read_bounded(path, limit)?).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("not UTF-8 text: {e}"),
        )
    })
}

/// Write `bytes` to `path` through a temporary file in the same folder, flushed before the
/// rename; the temporary file is removed when anything fails.
///
/// # Errors
/// The I/O error; `path` is then untouched.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut file = AtomicFile::create(path)?;
    file.write_all(bytes)?;
    file.commit()
}

/// A file written in pieces and put in place atomically by [`AtomicFile::commit`]; dropped
/// without a commit (an error on the way), it leaves the target untouched and removes its
/// temporary file. Use it for output too large to build in memory first.
pub struct AtomicFile {
    target: PathBuf,
    dir: PathBuf,
    tmp: PathBuf,
    file: Option<std::io::BufWriter<std::fs::File>>,
    renamed: bool,
}

impl AtomicFile {
    /// Start writing `path` (through a temporary file beside the link's target).
    ///
    /// # Errors
    /// The I/O error of creating the temporary file; `path` is untouched.
    pub fn create(path: &Path) -> std::io::Result<Self> {
        if let Some(direct) = direct_target(path) {
            let file = std::fs::OpenOptions::new().write(true).open(&direct)?;
            return Ok(Self {
                target: direct,
                dir: PathBuf::new(),
                tmp: PathBuf::new(),
                file: Some(std::io::BufWriter::new(file)),
                renamed: true,
            });
        }
        let target = resolve_links(path)?;
        let (dir, tmp) = temporary_beside(&target)?;
        let file = std::fs::File::create(&tmp)?;
        if let Ok(meta) = std::fs::metadata(&target) {
            // Keep the permission bits of the file being replaced.
            let _ = file.set_permissions(meta.permissions());
        }
        Ok(Self {
            target,
            dir,
            tmp,
            file: Some(std::io::BufWriter::new(file)),
            renamed: false,
        })
    }

    /// Flush, sync and rename over the target.
    ///
    /// # Errors
    /// The I/O error; the target is then untouched and the temporary file removed.
    pub fn commit(mut self) -> std::io::Result<()> {
        let Some(w) = self.file.take() else {
            return Err(std::io::Error::other("already committed"));
        };
        let f = w
            .into_inner()
            .map_err(std::io::IntoInnerError::into_error)?;
        if self.tmp.as_os_str().is_empty() {
            // Written directly (a device or a pipe): nothing to sync or rename.
            return Ok(());
        }
        f.sync_all()?;
        drop(f);
        std::fs::rename(&self.tmp, &self.target)?;
        self.renamed = true;
        // Make the rename itself durable (best effort: not every platform can open a folder).
        if let Ok(d) = std::fs::File::open(&self.dir) {
            let _ = d.sync_all();
        }
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.file {
            Some(f) => f.write(buf),
            None => Err(std::io::Error::other("already committed")),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match &mut self.file {
            Some(f) => f.flush(),
            None => Ok(()),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        drop(self.file.take());
        if !self.renamed {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// The path to write directly instead of replacing: standard output for `-`, or `path` itself
/// when it (through its links) is something other than a regular file or a folder (a device,
/// FIFO or socket). `None` for a regular file or a path that does not exist.
fn direct_target(path: &Path) -> Option<PathBuf> {
    if path == Path::new("-") {
        return Some(PathBuf::from("/dev/stdout"));
    }
    let meta = std::fs::metadata(path).ok()?;
    (!meta.is_file() && !meta.is_dir()).then(|| path.to_path_buf())
}

/// Follow symbolic links (up to 32) to the file a save must replace.
fn resolve_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut target = path.to_path_buf();
    for _ in 0..32 {
        match std::fs::symlink_metadata(&target) {
            Ok(m) if m.file_type().is_symlink() => {
                let link = std::fs::read_link(&target)?;
                target = match target.parent() {
                    Some(dir) if link.is_relative() => dir.join(link),
                    _ => link,
                };
            }
            _ => return Ok(target),
        }
    }
    Err(std::io::Error::other("too many levels of symbolic links"))
}

/// The folder of `path` and a temporary file name in it unique to this process and thread.
fn temporary_beside(path: &Path) -> std::io::Result<(PathBuf, PathBuf)> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let Some(name) = path.file_name() else {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a file path",
        ));
    };
    // Process and thread in the name, so concurrent savers never share a temporary file.
    let thread: String = format!("{:?}", std::thread::current().id())
        .chars()
        .filter(char::is_ascii_digit)
        .collect();
    let tmp = dir.join(format!(
        ".{}.{}-{thread}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    Ok((dir, tmp))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_the_file_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("talas-storage-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.txt");
        write_atomic(&p, b"old").unwrap();
        write_atomic(&p, b"new").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        // A failed save (target is a non-empty folder) keeps what was there.
        let sub = dir.join("sub");
        std::fs::create_dir_all(sub.join("x")).unwrap();
        assert!(write_atomic(&sub, b"z").is_err());
        assert!(sub.join("x").is_dir());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        assert!(write_atomic(Path::new("/"), b"z").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// `/dev/zero` and a file past the limit are refused with the limit named, not read until
    /// the memory runs out; a file within it reads whole.
    #[cfg(unix)]
    #[test]
    fn reads_are_bounded() {
        let e = read_bounded(Path::new("/dev/zero"), 1 << 20).unwrap_err();
        assert!(e.to_string().contains("larger than 1 MiB"), "{e}");
        let dir = std::env::temp_dir().join(format!("talas-storage-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.txt");
        std::fs::write(&p, vec![b'x'; 4096]).unwrap();
        assert_eq!(read_bounded(&p, 4096).unwrap().len(), 4096);
        assert!(read_bounded(&p, 4095).is_err());
        assert_eq!(read_text_bounded(&p, 1 << 20).unwrap().len(), 4096);
        std::fs::write(&p, [0xff, 0xfe]).unwrap();
        assert!(read_text_bounded(&p, 1 << 20).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// `-o /dev/null`, a link to it and a FIFO are written directly: /dev/null stays a
    /// character device (the atomic rename would have replaced it with a regular file, as
    /// root), a reader at the FIFO gets the bytes, and no temporary file is left beside them.
    #[cfg(unix)]
    #[test]
    fn devices_and_pipes_are_written_not_replaced() {
        use std::os::unix::fs::FileTypeExt;
        let null = Path::new("/dev/null");
        write_atomic(null, b"nothing").unwrap();
        assert!(
            std::fs::metadata(null)
                .unwrap()
                .file_type()
                .is_char_device()
        );
        let dir = std::env::temp_dir().join(format!("talas-storage-dev-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let link = dir.join("null.ngc");
        std::os::unix::fs::symlink(null, &link).unwrap();
        write_atomic(&link, b"nothing").unwrap();
        assert!(
            std::fs::metadata(null)
                .unwrap()
                .file_type()
                .is_char_device()
        );
        let fifo = dir.join("pipe.ngc");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let reader = {
                let fifo = fifo.clone();
                std::thread::spawn(move || std::fs::read(fifo).unwrap())
            };
            write_atomic(&fifo, b"G0 X1\n").unwrap();
            assert_eq!(reader.join().unwrap(), b"G0 X1\n");
            assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
        }
        // Nothing else appeared in the folder (no temporary files).
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert!(names.len() <= 2, "{names:?}");
        assert_eq!(
            direct_target(Path::new("-")),
            Some(PathBuf::from("/dev/stdout"))
        );
        assert_eq!(direct_target(&dir.join("new.ngc")), None);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_link_stays_a_link_and_the_mode_is_kept() {
        use std::os::unix::fs::PermissionsExt;
        let dir = std::env::temp_dir().join(format!("talas-storage-link-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("real")).unwrap();
        let real = dir.join("real/a.ngc");
        std::fs::write(&real, "old").unwrap();
        std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o640)).unwrap();
        let link = dir.join("a.ngc");
        std::os::unix::fs::symlink("real/a.ngc", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
        let mode = std::fs::metadata(&real).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o640);
        // Written in pieces; dropped without commit, the old file stays.
        let mut f = AtomicFile::create(&real).unwrap();
        f.write_all(b"half").unwrap();
        drop(f);
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
        assert_eq!(std::fs::read_dir(dir.join("real")).unwrap().count(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
