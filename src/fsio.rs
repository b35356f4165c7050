//! Atomic file writes, for every output the project writes: each file is
//! written to a temporary name in its folder and renamed into place, so a
//! reader never sees a half-written file; [`probe_folder`] checks, before
//! any work, that an output folder can be written.

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

/// Checks, before any work, that files can be written into the folder
/// `dir`: creates it (and its parents) when missing, writes a small probe
/// file there and removes it. The error is the OS's (a parent that is a
/// file, no permission, a read-only file system), so a command can refuse
/// an output folder at once rather than after hours of simulation.
pub fn probe_folder(dir: &Path) -> io::Result<()> {
    if let Some(file) = dir.ancestors().find(|a| a.is_file()) {
        return Err(io::Error::other(format!(
            "{} is a file, not a folder",
            file.display()
        )));
    }
    std::fs::create_dir_all(dir)?;
    let probe = dir.join(format!(".floebench-probe{}", std::process::id()));
    std::fs::write(&probe, b"probe")?;
    std::fs::remove_file(&probe)
}

/// [`probe_folder`] on the folder that will hold the file `path` (its
/// parent, or the current folder); also an error when `path` is a folder.
pub fn probe_file(path: &Path) -> io::Result<()> {
    if path.is_dir() {
        return Err(io::Error::other("is a folder, not a file"));
    }
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => probe_folder(p),
        _ => probe_folder(Path::new(".")),
    }
}
