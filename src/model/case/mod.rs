//! Case files, version 1: parsing and validation.
//!
//! The contract is `docs/case-format.md`.
//! Every rule is checked here, and every error names the file, the line and
//! the key, or the floe's index. Loading either returns a whole [`Scenario`]
//! or an error: nothing is written anywhere before a case has loaded.
//!
//! This file holds the entry points, the error and its location helpers;
//! `spec.rs` is the file as written (serde), `messages.rs` makes the
//! parser's messages name their table and key, `build.rs` turns it into a
//! [`Scenario`] table by table (`environment.rs` the `[environment]` table
//! and its velocity fields, `fields.rs` the `[[field]]` tables),
//! `overlap.rs` checks that no bodies overlap at t = 0.

mod build;
mod environment;
mod fields;
mod messages;
mod overlap;
mod spec;
mod warnings;

pub(crate) use messages::closest;

pub use spec::FieldSpec;
pub use warnings::{EXTENT_FACTOR, SIZE_SPAN};

use super::limits;
use super::settings::TableSpec;
use super::Scenario;
use crate::geometry::Vec2;
use build::build;
use spec::CaseFile;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// A case file that cannot be loaded: where, and what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}{}: {message}", file.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct CaseError {
    /// The case file.
    pub file: PathBuf,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// What is wrong, naming the key or the floe.
    pub message: String,
}

// ---------------------------------------------------------------------------
// Error location helpers.

struct Ctx<'a> {
    file: &'a Path,
    text: &'a str,
}

impl Ctx<'_> {
    fn line_of(&self, offset: usize) -> usize {
        let end = offset.min(self.text.len());
        self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    }

    fn err(&self, span: Option<Range<usize>>, message: impl Into<String>) -> CaseError {
        CaseError {
            file: self.file.to_path_buf(),
            line: span.map(|s| self.line_of(s.start)),
            message: message.into(),
        }
    }

    /// A TOML syntax or type error at its line; a duplicate key or table is
    /// named (the parser's own message does not say which), any other says
    /// where it is ([`Ctx::explain`]: the table, the key, the closest known
    /// name).
    fn toml_err(&self, e: &toml::de::Error) -> CaseError {
        let span = e.span();
        let message = e.message().trim_end();
        let named = span
            .as_ref()
            .filter(|_| message.starts_with("duplicate key"))
            .and_then(|s| self.text.get(s.clone()))
            .map(|written| {
                written
                    .split('=')
                    .next()
                    .unwrap_or(written)
                    .trim()
                    .trim_matches(|c| c == '[' || c == ']')
                    .trim()
            })
            .filter(|key| !key.is_empty());
        match named {
            Some(key) => self.err(
                span,
                format!("{message} `{key}` (each key and table is written once)"),
            ),
            None => {
                let message = self.explain(span.as_ref().map(|s| s.start), message);
                self.err(span, message)
            }
        }
    }

    /// `r`, or its message as the error at the line of `key` inside `span`:
    /// the one way a refused value (a [`crate::model::limits::Limit`]'s
    /// check) becomes a located error.
    fn at<T>(&self, span: &Range<usize>, key: &str, r: Result<T, String>) -> Result<T, CaseError> {
        r.map_err(|m| self.key_err(span, key, m))
    }

    /// The key written at the start of the line holding `offset`
    /// (`polygon` for `polygon = [[0, 0], …]`), if any.
    fn key_at(&self, offset: usize) -> Option<&str> {
        let offset = offset.min(self.text.len());
        let start = self.text[..offset].rfind('\n').map_or(0, |i| i + 1);
        let line = self.text[start..].lines().next().unwrap_or("");
        let (key, _) = line.split_once('=')?;
        let key = key.trim();
        let bare = !key.is_empty()
            && key
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        bare.then_some(key)
    }

    /// The line where `key` is written inside `span`, if it can be found.
    fn key_line(&self, span: &Range<usize>, key: &str) -> Option<usize> {
        // A table's span may cover only its header: search on to the next header.
        let start = span.start.min(self.text.len());
        let end = span.end.min(self.text.len()).max(start);
        let mut offset = start;
        for (k, line) in self.text[start..].split_inclusive('\n').enumerate() {
            let header = line.trim_start().starts_with('[');
            if k > 0 && header && offset >= end {
                break;
            }
            if contains_key(line, key) {
                return Some(self.line_of(offset));
            }
            offset += line.len();
        }
        None
    }

    /// The error at the line where `key` is written inside `span`, or at the
    /// start of `span` when it cannot be found.
    fn key_err(&self, span: &Range<usize>, key: &str, message: impl Into<String>) -> CaseError {
        CaseError {
            file: self.file.to_path_buf(),
            line: Some(
                self.key_line(span, key)
                    .unwrap_or_else(|| self.line_of(span.start)),
            ),
            message: message.into(),
        }
    }
}

fn contains_key(line: &str, key: &str) -> bool {
    let code = line.split('#').next().unwrap_or("");
    let mut rest = code;
    while let Some(pos) = rest.find(key) {
        let before_ok = rest[..pos]
            .chars()
            .last()
            .is_none_or(|c| !(c.is_ascii_alphanumeric() || c == '_'));
        let after = rest[pos + key.len()..].trim_start();
        if before_ok && after.starts_with('=') {
            return true;
        }
        rest = &rest[pos + key.len()..];
    }
    false
}

// ---------------------------------------------------------------------------

/// Reads and validates a case file; each `[formulation.<name>]` table is
/// checked by the parser in `tables` that has its name (an unknown table is
/// an error). [`crate::formulation::load_case`] passes the registry's.
pub fn load_case_with(path: &Path, tables: &[TableSpec]) -> Result<Scenario, CaseError> {
    // The size first: the file is read whole.
    if let Ok(meta) = std::fs::metadata(path) {
        check_size(path, meta.len())?;
    }
    let text = std::fs::read_to_string(path).map_err(|e| CaseError {
        file: path.to_path_buf(),
        line: None,
        message: format!("cannot read the case file: {e}"),
    })?;
    parse_case_with(&text, path, tables)
}

/// Parses and validates case text; `file` is used in messages (and, for
/// future keys holding paths, as the base of relative paths); `tables` as in
/// [`load_case_with`].
pub fn parse_case_with(
    text: &str,
    file: &Path,
    tables: &[TableSpec],
) -> Result<Scenario, CaseError> {
    check_size(file, text.len() as u64)?;
    let ctx = Ctx { file, text };
    // Syntax first, then the version, before any typed rule.
    let raw: toml::Table = toml::from_str(text).map_err(|e| ctx.toml_err(&e))?;
    check_version(&ctx, &raw)?;
    environment::check_field_keys(&ctx)?;
    let case: CaseFile = toml::from_str(text).map_err(|e| ctx.toml_err(&e))?;
    build(&ctx, case, tables)
}

/// A case file of `bytes` within [`limits::FILE_BYTES`].
fn check_size(file: &Path, bytes: u64) -> Result<(), CaseError> {
    limits::FILE_BYTES
        .check_integer("the case file's size", i128::from(bytes))
        .map(|_| ())
        .map_err(|message| CaseError {
            file: file.to_path_buf(),
            line: None,
            message,
        })
}

fn check_version(ctx: &Ctx, raw: &toml::Table) -> Result<(), CaseError> {
    let header = raw.get("case").and_then(|v| v.as_table()).ok_or_else(|| {
        ctx.err(
            None,
            "missing [case] table (with version = 1, name, duration, output_interval)",
        )
    })?;
    let whole = 0..ctx.text.len();
    match header.get("version") {
        None => Err(ctx.err(
            None,
            "missing key `version` in [case]; this reader knows version = 1",
        )),
        Some(toml::Value::Integer(1)) => Ok(()),
        Some(v) => Err(ctx.key_err(
            &whole,
            "version",
            format!("[case] version = {v} is not supported; this reader knows version = 1"),
        )),
    }
}

/// A point of the file (`[x, y]`) as a vector.
fn vec2(v: [f64; 2]) -> Vec2 {
    Vec2::new(v[0], v[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_lines_are_found_inside_inline_tables() {
        assert!(contains_key("air = { density = 1.3 }", "density"));
        assert!(!contains_key("# density = 1", "density"));
        assert!(!contains_key("xdensity = 1", "density"));
    }
}
