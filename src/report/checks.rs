//! The tables of check outcomes ([`crate::analysis::check`]): aligned plain
//! text for the terminal (`floebench check`), Markdown (`--markdown`, the
//! report page), with numbers rounded by [`super::format::fmt_num`], and
//! `checks.csv`, with every number at full precision.

use super::format::{fmt_apart, fmt_num};
use crate::analysis::check::{claimed_failures, verdict, CheckOutcome};
use std::fmt::Write as _;

/// The cells of one outcome, in the order of [`TABLE_HEADER`]: the measured
/// value printed apart from the value it is judged against (the tolerance,
/// or the expected answer), by [`fmt_apart`].
pub fn table_cells(o: &CheckOutcome) -> [String; 9] {
    let (measured, expected, tolerance) = match o.expected {
        Some(x) => {
            let (m, e) = fmt_apart(o.measured, x);
            (m, e, fmt_num(o.tolerance))
        }
        None => {
            let (m, t) = fmt_apart(o.measured, o.tolerance);
            (m, "-".into(), t)
        }
    };
    [
        o.case.clone(),
        o.check.clone(),
        o.formulation.clone(),
        measured,
        expected,
        tolerance,
        o.unit.clone(),
        verdict(o).into(),
        o.note.clone(),
    ]
}

/// The columns of the check tables.
pub const TABLE_HEADER: [&str; 9] = [
    "case",
    "check",
    "formulation",
    "measured",
    "expected",
    "tolerance",
    "unit",
    "result",
    "note",
];

/// The outcomes as an aligned plain-text table, one line each, then a count
/// of passes, known failures and claimed failures.
pub fn format_table(rows: &[CheckOutcome]) -> String {
    let mut table = vec![TABLE_HEADER.map(String::from).to_vec()];
    table.extend(rows.iter().map(|o| table_cells(o).to_vec()));
    let mut out = super::format::aligned_table(&table);
    out.push_str(&totals(rows));
    out.push('\n');
    out
}

/// The count of `rows`: `N checks: P pass, K fail (known, not claimed), C
/// FAIL (claimed)`, the one summary line of `check` and of the report page.
pub fn totals(rows: &[CheckOutcome]) -> String {
    let known = rows.iter().filter(|o| !o.pass && !o.claimed).count();
    format!(
        "{} checks: {} pass, {} fail (known, not claimed), {} FAIL (claimed)",
        rows.len(),
        rows.iter().filter(|o| o.pass).count(),
        known,
        claimed_failures(rows)
    )
}

/// The outcomes as a Markdown table, for the report page.
pub fn markdown_table(rows: &[CheckOutcome]) -> String {
    let esc = |s: &str| s.replace('|', "\\|");
    let mut out = format!(
        "| {} |\n|{}\n",
        TABLE_HEADER.join(" | "),
        " --- |".repeat(9)
    );
    for o in rows {
        let c = table_cells(o);
        let c: Vec<String> = c.iter().map(|s| esc(s)).collect();
        out.push_str(&format!("| {} |\n", c.join(" | ")));
    }
    out
}

/// `checks.csv`: one row per check outcome.
pub fn checks_csv(rows: &[CheckOutcome]) -> String {
    let mut s =
        String::from("case,formulation,check,measured,expected,tolerance,unit,pass,claimed,note\n");
    for o in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},\"{}\"",
            o.case,
            o.formulation,
            o.check,
            o.measured,
            o.expected.map_or(String::new(), |e| e.to_string()),
            o.tolerance,
            o.unit,
            o.pass,
            o.claimed,
            o.note.replace('"', "'")
        );
    }
    s
}
