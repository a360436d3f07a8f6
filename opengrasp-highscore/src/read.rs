//! Bounded reads: files, pipes, devices and standard input are read up to a limit, never
//! trusting a reported size (`/dev/zero` reports 0 bytes and never ends; a FIFO reports 0).

use std::io::Read;
use std::path::Path;

use super::error::{HighscoreError, Result};

/// Reads at most `limit` bytes of UTF-8 text from `reader`.
///
/// # Errors
/// [`HighscoreError::TooLarge`] as soon as more than `limit` bytes are available (at most
/// `limit + 1` bytes are read), [`HighscoreError::Io`] on read errors or invalid UTF-8
/// (`what` names the source in the error).
pub fn read_text_bounded(reader: impl Read, limit: usize, what: &Path) -> Result<String> {
    let io = |source| HighscoreError::Io { path: what.to_path_buf(), source };
    let mut buf = Vec::with_capacity(limit.min(64 * 1024));
    reader.take(limit as u64 + 1).read_to_end(&mut buf).map_err(io)?;
    if buf.len() > limit {
        return Err(HighscoreError::TooLarge { size: buf.len() as u64, limit: limit as u64 });
    }
    String::from_utf8(buf).map_err(|e| io(std::io::Error::new(std::io::ErrorKind::InvalidData, e)))
}

/// Reads a file (or a pipe, a device, `-` for standard input) of at most `limit` bytes.
///
/// # Errors
/// As [`read_text_bounded`]; [`HighscoreError::Io`] if the file cannot be opened.
pub fn read_file_bounded(path: &Path, limit: usize) -> Result<String> {
    if path == Path::new("-") {
        return read_text_bounded(std::io::stdin().lock(), limit, path);
    }
    let file = std::fs::File::open(path).map_err(|source| HighscoreError::Io { path: path.to_path_buf(), source })?;
    // A regular file that reports more than the limit is refused before reading it.
    if let Ok(meta) = file.metadata() {
        if meta.is_file() && meta.len() > limit as u64 {
            return Err(HighscoreError::TooLarge { size: meta.len(), limit: limit as u64 });
        }
    }
    read_text_bounded(file, limit, path)
}
