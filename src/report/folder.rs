//! Which folders of a report's output folder the report owns.
//!
//! `compare -o DIR` writes one folder per case into `DIR`, replacing a case
//! folder of the same name. It must never replace a folder it did not write:
//! another report (a case named `sample` compared into `reports/` must not
//! touch `reports/sample/`, the committed sample report), or anything else a
//! user keeps there. So every report lists the case folders it wrote in
//! `DIR/.floebench-report.json` ([`MANIFEST`]), and a case folder may be
//! replaced only if it is listed there, or if it is a case folder of a
//! report older than this list (it holds `summary.json` and `metrics.csv`
//! and is not itself a report: no `index.md`).
//!
//! [`check`] is called before any run (so a mistake costs nothing) and again
//! by the writer; [`record`] lists the folders after the page is written.
//! A comparison of other cases into the same folder would leave the
//! earlier report's case folders beside a page that does not show them:
//! [`earlier`] names them before any run, so the command can refuse, and
//! only when the user says so (`compare --replace`) does [`remove_stale`]
//! remove them after the new page is written, so the folder holds exactly
//! what its page shows. Nothing is ever removed without that word.

use super::ReportError;
use crate::fsio::write_atomic;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The file, in a report's output folder, listing the case folders the
/// report wrote.
pub const MANIFEST: &str = ".floebench-report.json";

#[derive(Debug, Default, serde::Serialize, serde::Deserialize)]
struct Manifest {
    /// The case folders (names, relative to the output folder).
    cases: BTreeSet<String>,
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> ReportError + '_ {
    move |source| ReportError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The case folders `out` lists as its own (none when it has no list).
fn owned(out: &Path) -> Result<BTreeSet<String>, ReportError> {
    let path = out.join(MANIFEST);
    match std::fs::read(&path) {
        Ok(bytes) => serde_json::from_slice::<Manifest>(&bytes)
            .map(|m| m.cases)
            .map_err(|e| ReportError::Io {
                path,
                source: std::io::Error::other(format!(
                    "not a floebench report list ({e}); remove it or choose another output folder"
                )),
            }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(BTreeSet::new()),
        Err(e) => Err(io_err(&path)(e)),
    }
}

/// A case folder written by a report older than the list.
fn is_unlisted_case_folder(dir: &Path) -> bool {
    dir.join("summary.json").is_file()
        && dir.join("metrics.csv").is_file()
        && !dir.join("index.md").exists()
}

/// Checks that a report of the cases `names` may be written into `out`:
/// `out` is a folder or does not exist, no two cases share a name, and
/// every existing `out/<name>` is a case folder this report may replace (see
/// the module doc). Nothing is written.
pub fn check(out: &Path, names: &[&str]) -> Result<(), ReportError> {
    let mut sorted: Vec<&str> = names.to_vec();
    sorted.sort_unstable();
    if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
        return Err(ReportError::DuplicateName(w[0].to_string()));
    }
    if !out.exists() {
        return Ok(());
    }
    if !out.is_dir() {
        return Err(ReportError::NotAFolder(out.to_path_buf()));
    }
    let owned = owned(out)?;
    for name in names {
        let dir = out.join(name);
        if dir.exists() && !(owned.contains(*name) || is_unlisted_case_folder(&dir)) {
            return Err(ReportError::NotOurs(dir));
        }
    }
    Ok(())
}

/// The case folders of an earlier report into `out` (listed in its
/// [`MANIFEST`] and still there) that are not among `names`, sorted: the
/// folders [`remove_stale`] would remove after a report of `names`.
pub fn earlier(out: &Path, names: &[&str]) -> Result<Vec<String>, ReportError> {
    if !out.is_dir() {
        return Ok(Vec::new());
    }
    Ok(owned(out)?
        .into_iter()
        .filter(|n| !names.contains(&n.as_str()) && out.join(n).is_dir())
        .collect())
}

/// Lists `names` (with the folders listed before that still exist) as the
/// case folders of `out`.
pub fn record(out: &Path, names: &[&str]) -> Result<(), ReportError> {
    let mut cases: BTreeSet<String> = owned(out)?
        .into_iter()
        .filter(|n| out.join(n).is_dir())
        .collect();
    cases.extend(names.iter().map(|n| n.to_string()));
    write_list(out, cases)
}

fn write_list(out: &Path, cases: BTreeSet<String>) -> Result<(), ReportError> {
    let path = out.join(MANIFEST);
    let bytes = serde_json::to_vec_pretty(&Manifest { cases })
        .map_err(|e| io_err(&path)(std::io::Error::other(e)))?;
    write_atomic(&path, &bytes).map_err(io_err(&path))
}

/// Removes the case folders `out` lists that are not among `names` (a
/// report of other cases into the same folder, called only when the user
/// asked for it: `compare --replace`); returns them.
pub fn remove_stale(out: &Path, names: &[&str]) -> Result<Vec<PathBuf>, ReportError> {
    let listed = owned(out)?;
    let mut removed = Vec::new();
    let mut kept = BTreeSet::new();
    for name in listed {
        let dir = out.join(&name);
        if names.contains(&name.as_str()) {
            kept.insert(name);
        } else if dir.is_dir() {
            std::fs::remove_dir_all(&dir).map_err(io_err(&dir))?;
            removed.push(dir);
        }
    }
    write_list(out, kept)?;
    Ok(removed)
}
