//! Where a scenario was written: its case file, the lines of its keys and
//! floes, and the warnings its loading found. A loaded [`super::Scenario`]
//! keeps them so that a check made after loading (a formulation's settings
//! against the case's times, [`crate::formulation::load_case`]) still names
//! the file and the line, and so that every command that loads a case can
//! print its warnings.

use super::CaseError;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A doubt about a case that does not stop it loading (a floe far larger
/// than the others, a run of days). Every command that loads the case
/// prints it on stderr as `warning: <file>:<line>: <message>`; `validate`
/// lists it under the case.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseWarning {
    /// The case file.
    pub file: PathBuf,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// What is doubtful, naming the key or the floe, and why.
    pub message: String,
}

impl std::fmt::Display for CaseWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        write!(f, ": {}", self.message)
    }
}

/// The case file of a scenario, the lines of what it wrote, and the
/// warnings found while loading it. Empty for a scenario not read from a
/// file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CaseSource {
    /// The case file.
    pub file: PathBuf,
    /// The line of each key of `[case]` that is written (`duration`,
    /// `output_interval`, …), and of the `[case]` header itself under
    /// `case`.
    pub case_lines: BTreeMap<String, usize>,
    /// The line of each key of the other tables that a refusal after
    /// loading may name, as `table.key` (`fracture.model`,
    /// `fracture.impact`).
    pub key_lines: BTreeMap<String, usize>,
    /// The line of the table each initial floe comes from (its `[[floe]]`
    /// or its `[[field]]`), by floe index.
    pub floe_lines: Vec<Option<usize>>,
    /// The warnings of the case, in the order found.
    pub warnings: Vec<CaseWarning>,
}

impl CaseSource {
    /// The line of `[case]` key `key` (or of the `[case]` header when it is
    /// not written).
    pub fn case_line(&self, key: &str) -> Option<usize> {
        self.case_lines
            .get(key)
            .or_else(|| self.case_lines.get("case"))
            .copied()
    }

    /// An error at the line of `[case]` key `key`.
    pub fn case_error(&self, key: &str, message: impl Into<String>) -> CaseError {
        CaseError {
            file: self.file.clone(),
            line: self.case_line(key),
            message: message.into(),
        }
    }

    /// An error at the line of `key` (`table.key`, [`CaseSource::key_lines`];
    /// no line when it is not written).
    pub fn key_error(&self, key: &str, message: impl Into<String>) -> CaseError {
        CaseError {
            file: self.file.clone(),
            line: self.key_lines.get(key).copied(),
            message: message.into(),
        }
    }

    /// Records a warning at `line`.
    pub fn warn(&mut self, line: Option<usize>, message: impl Into<String>) {
        self.warnings.push(CaseWarning {
            file: self.file.clone(),
            line,
            message: message.into(),
        });
    }
}
