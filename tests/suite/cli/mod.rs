//! The command line: `validate`, `show`, `run` (outputs, dumps, plots), `lcp`.
//!
//! This file holds what the submodules share: `cli`, which runs the binary
//! and returns its status and output. The tests are in the submodules, one
//! topic each.

mod lcp;
mod refusals;
mod reports;
mod run;
mod show;
mod signals;
mod validate;

use crate::common::floebench;

/// Runs `floebench` with `args`; (success, stdout, stderr).
fn cli(args: &[&std::ffi::OsStr]) -> (bool, String, String) {
    let out = floebench().args(args).output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
