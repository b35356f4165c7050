//! Atomic file writes, for every output the project writes: each file is
//! written to a temporary name in its folder and renamed into place, so a
//! reader never sees a half-written file.

use std::io;
use std::path::Path;

/// Writes `contents` to `path` atomically (temporary file, then rename);
/// on failure the temporary file is removed.
pub fn write_atomic(path: &Path, contents: &[u8]) -> io::Result<()> {
    write_atomic_with(path, |tmp| std::fs::write(tmp, contents))
}

/// Writes `path` atomically with `write`, which creates the file at the
/// temporary path it is given (a writer that opens the file itself, such
/// as NetCDF's); then renames it into place. On failure the temporary file
/// is removed.
pub fn write_atomic_with<W>(path: &Path, write: W) -> io::Result<()>
where
    W: FnOnce(&Path) -> io::Result<()>,
{
    let dir = path.parent().unwrap_or_else(|| Path::new("."));
    std::fs::create_dir_all(dir)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let done = write(&tmp).and_then(|()| std::fs::rename(&tmp, path));
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done
}
