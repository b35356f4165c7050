//! The plan file as written (the serde layer: `PlanFile`, `SweepSpec`,
//! `FormulationSpec`), where its errors point (`At`), and the lexical
//! form of the case paths it names (`lexical`); read by `parse.rs` and
//! `grid.rs`.

use crate::model::CaseError;
use crate::sweep::start::StartSpec;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

// ---------------------------------------------------------------------------
// The file as written.

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PlanFile {
    pub(super) sweep: Spanned<SweepSpec>,
    #[serde(default)]
    pub(super) formulation: Vec<Spanned<FormulationSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SweepSpec {
    #[allow(dead_code)] // checked on the raw table before typed parsing
    version: i64,
    pub(super) name: Option<Spanned<String>>,
    pub(super) cases: Spanned<Vec<Spanned<String>>>,
    pub(super) reference: Spanned<toml::Value>,
    pub(super) measures: Option<Spanned<Vec<Spanned<String>>>>,
    pub(super) start: Option<Spanned<StartSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FormulationSpec {
    pub(super) name: Spanned<String>,
    pub(super) cases: Option<Vec<Spanned<String>>>,
    #[serde(default)]
    pub(super) grid: BTreeMap<String, Spanned<Vec<Spanned<toml::Value>>>>,
}

/// Where errors point: the plan file and its text.
pub(super) struct At<'a> {
    pub(super) file: &'a Path,
    pub(super) text: &'a str,
}

impl At<'_> {
    fn line(&self, span: &Range<usize>) -> usize {
        let end = span.start.min(self.text.len());
        1 + self.text[..end].matches('\n').count()
    }

    pub(super) fn err(&self, span: Option<&Range<usize>>, message: impl Into<String>) -> CaseError {
        CaseError {
            file: self.file.to_path_buf(),
            line: span.map(|s| self.line(s)),
            message: message.into(),
        }
    }
}

/// `path` with its `.` and `dir/..` components taken out, without reading
/// the file system (so messages name `cases/x.toml`, not
/// `plans/../cases/x.toml`).
pub(super) fn lexical(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}
