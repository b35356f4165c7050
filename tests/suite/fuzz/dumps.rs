//! LCP-dump mutants: the strict dump reader, then the LCP driver, whose
//! solved answers are checked here.

use super::{corpus, fuzz, one_line};
use crate::common::{guarded, lcp_violation, Defect};
use floebench::lcp::{residual, solve, LcpDump, SolveOptions};
use std::path::Path;

/// One dump mutant: the strict reader, then the driver; a solved answer
/// must pass its residual check.
fn check_dump(text: String, _pick: u64) -> Result<String, Defect> {
    let read = guarded("the dump reader", || {
        LcpDump::from_json(&text, Path::new("mutant.json"))
    })?;
    let dump = match read {
        Err(e) => {
            one_line("the dump reader's error", &e.to_string())?;
            return Ok("rejected by the reader".into());
        }
        Ok(d) => d,
    };
    let lcp = match dump.to_lcp() {
        Err(e) => {
            one_line("the LCP's error", &e.to_string())?;
            return Ok("rejected: not an LCP".into());
        }
        Ok(l) => l,
    };
    let opts = SolveOptions::default();
    let sol = guarded("solve", || solve(&lcp, &opts))?;
    if !sol.status.is_solved() {
        return Ok("solve failed (counted)".into());
    }
    let r = residual(&lcp.m, &lcp.q, &sol.z);
    if r.is_nan() || r > opts.tolerance {
        return Err(format!(
            "false solve: {} with residual {r} above {}",
            sol.status, opts.tolerance
        ));
    }
    // An independent check: M z + q computed naively, relative to the
    // magnitudes (a residual of 1e-10 relative to |q|_2 is within 1e-8 of
    // them for these sizes, rounding included).
    if let Some(v) = lcp_violation(&lcp.m, &lcp.q, &sol.z, 1e-8) {
        return Err(format!("false solve: {}: {v}", sol.status));
    }
    Ok(format!("solved ({})", sol.status))
}

#[test]
fn mutated_lcp_dumps_never_panic_and_no_false_solve() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/lcp");
    let texts = corpus(&[dir], "json");
    fuzz("LCP dumps", "lcp", &texts, true, check_dump);
}
