//! Atomic file writes.

use std::fs::{self, File};
use std::io::{self, BufWriter};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes a file atomically: `write` fills a temporary file in the same directory, which is
/// flushed, fsynced and renamed over `path` (then the directory is fsynced, best effort).
/// If anything fails, the temporary file is removed and the old file at `path` (if any) is
/// left untouched.
///
/// # Errors
/// [`Error::Io`] for the first failing step (including an error returned by `write`).
pub fn write_atomic(path: &Path, write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>) -> Result<()> {
    let io_err = |source| Error::Io { path: path.to_path_buf(), source };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| io_err(io::Error::new(io::ErrorKind::InvalidInput, "the path has no file name")))?;
    let tmp = dir.join(format!(
        ".{}.tmp.{}.{}",
        name.to_string_lossy(),
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let result = (|| {
        let file = File::create(&tmp)?;
        let mut w = BufWriter::new(file);
        write(&mut w)?;
        let file = w.into_inner().map_err(io::IntoInnerError::into_error)?;
        file.sync_all()?;
        drop(file);
        fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = fs::remove_file(&tmp);
        return Err(io_err(e));
    }
    // Persist the rename itself; not possible on every platform, hence best effort.
    if let Ok(d) = File::open(&dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// Checks, before any work is done, that `path` can be written: its directory exists and a
/// file can be created in it (a probe file is created and removed; an existing `path` is left
/// untouched). A run's `--out` is checked this way so a bad path never throws a run away.
///
/// # Errors
/// [`Error::Io`] naming `path` and why it cannot be written.
pub fn check_writable(path: &Path) -> Result<()> {
    let io_err = |source| Error::Io { path: path.to_path_buf(), source };
    if path.is_dir() {
        return Err(io_err(io::Error::new(io::ErrorKind::IsADirectory, "is a directory, not a file")));
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let probe =
        dir.join(format!(".opengrasp-probe.{}.{}", std::process::id(), TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)));
    File::create(&probe).map_err(io_err)?;
    let _ = fs::remove_file(&probe);
    Ok(())
}
