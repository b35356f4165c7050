//! The `[formulation.<name>]` tables of a case file, kept as written and
//! read by the formulation that owns each (see
//! [`crate::formulation::Entry::settings`]).
//!
//! A table keeps the line of each key, so a formulation's parser reports a
//! bad value at the file and line where it is written. The case loader
//! validates every table with its owner's parser before a case is accepted;
//! an unknown table or key is an error. Each formulation declares the
//! [`Limit`] of every number it reads; the [`SettingsReader`] checks it (and
//! the number of steps a step gives over the case's duration), so the range
//! checks are here, once.

use super::limits::{check_count, Limit, STEPS};
use super::CaseError;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// One `[formulation.<name>]` table as written, with the line of each key.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SettingsTable {
    /// The table's name (`moreau` for `[formulation.moreau]`).
    pub name: String,
    /// The keys and values as written.
    pub values: toml::Table,
    #[serde(skip)]
    file: PathBuf,
    #[serde(skip)]
    line: Option<usize>,
    #[serde(skip)]
    key_lines: BTreeMap<String, usize>,
    #[serde(skip)]
    duration: Option<f64>,
    /// How messages name the table (`[formulation.moreau]`, `[fracture]`).
    #[serde(skip)]
    header: String,
}

/// The parser of one table: checks it and reports errors with their line.
#[derive(Debug, Clone, Copy)]
pub struct TableSpec {
    /// The table's name (`moreau` for `[formulation.moreau]`).
    pub name: &'static str,
    /// Checks the table (every key known, every value in range).
    pub validate: fn(&SettingsTable) -> Result<(), CaseError>,
    /// The limits of its numbers (docs/case-format.md, "Limits").
    pub limits: &'static [Limit],
}

impl SettingsTable {
    /// A table read from `file`, header at `line`, with the line of each
    /// key, in a case of `duration` (s: it bounds the number of steps).
    pub fn new(
        name: &str,
        values: toml::Table,
        file: PathBuf,
        line: Option<usize>,
        key_lines: BTreeMap<String, usize>,
        duration: Option<f64>,
    ) -> SettingsTable {
        SettingsTable {
            name: name.to_string(),
            values,
            file,
            line,
            key_lines,
            duration,
            header: format!("[formulation.{name}]"),
        }
    }

    /// The same table named `header` in messages (e.g. `[fracture]`, a
    /// table outside `[formulation.*]` read with the same reader).
    pub fn with_header(mut self, header: &str) -> SettingsTable {
        self.header = header.to_string();
        self
    }

    /// An empty table (a case that does not write it: every default).
    pub fn empty(name: &str) -> SettingsTable {
        SettingsTable::new(
            name,
            toml::Table::new(),
            PathBuf::new(),
            None,
            BTreeMap::new(),
            None,
        )
    }

    /// The error `message` at the line of `key` (or of the table).
    pub fn error(&self, key: Option<&str>, message: impl Into<String>) -> CaseError {
        CaseError {
            file: self.file.clone(),
            line: key
                .and_then(|k| self.key_lines.get(k).copied())
                .or(self.line),
            message: format!("{} {}", self.header, message.into()),
        }
    }

    /// A reader that takes the keys one by one and, at
    /// [`SettingsReader::finish`], refuses any key it was not asked for.
    pub fn read(&self) -> SettingsReader<'_> {
        SettingsReader {
            table: self,
            asked: Vec::new(),
        }
    }
}

/// Reads typed values from a [`SettingsTable`].
#[derive(Debug)]
pub struct SettingsReader<'a> {
    table: &'a SettingsTable,
    asked: Vec<&'static str>,
}

impl SettingsReader<'_> {
    /// The error `message` at the line of `key` (or of the table), for a
    /// refusal that depends on several keys.
    pub fn error(&self, key: &str, message: impl Into<String>) -> CaseError {
        self.table.error(Some(key), message)
    }

    fn number(&mut self, key: &'static str) -> Result<Option<f64>, CaseError> {
        self.asked.push(key);
        match self.table.values.get(key) {
            None => Ok(None),
            Some(toml::Value::Float(v)) => Ok(Some(*v)),
            Some(toml::Value::Integer(v)) => Ok(Some(*v as f64)),
            Some(other) => Err(self
                .table
                .error(Some(key), format!("{key} = {other} must be a number"))),
        }
    }

    /// A number within `limit` (its key is `limit.key`).
    pub fn bounded(&mut self, limit: &Limit) -> Result<Option<f64>, CaseError> {
        let key = limit.key;
        match self.number(key)? {
            Some(v) => limit
                .check(key, v)
                .map(Some)
                .map_err(|m| self.table.error(Some(key), m)),
            None => Ok(None),
        }
    }

    /// A step (s) within `limit` that also gives at most
    /// [`super::limits::STEPS`] steps over the case's duration.
    pub fn step(&mut self, limit: &Limit) -> Result<Option<f64>, CaseError> {
        let h = self.bounded(limit)?;
        if let (Some(h), Some(duration)) = (h, self.table.duration) {
            check_count(&STEPS, limit.key, h, duration)
                .map_err(|m| self.table.error(Some(limit.key), m))?;
        }
        Ok(h)
    }

    /// An integer within `limit` (its key is `limit.key`).
    pub fn integer(&mut self, limit: &Limit) -> Result<Option<i64>, CaseError> {
        let key = limit.key;
        self.asked.push(key);
        match self.table.values.get(key) {
            None => Ok(None),
            Some(toml::Value::Integer(v)) => limit
                .check_integer(key, i128::from(*v))
                .map(|_| Some(*v))
                .map_err(|m| self.table.error(Some(key), m)),
            Some(other) => Err(self
                .table
                .error(Some(key), format!("{key} = {other} must be an integer"))),
        }
    }

    /// A boolean (`true` or `false`).
    pub fn boolean(&mut self, key: &'static str) -> Result<Option<bool>, CaseError> {
        self.asked.push(key);
        match self.table.values.get(key) {
            None => Ok(None),
            Some(toml::Value::Boolean(b)) => Ok(Some(*b)),
            Some(other) => Err(self
                .table
                .error(Some(key), format!("{key} = {other} must be true or false"))),
        }
    }

    /// A choice among the names `T` parses (its error lists them).
    pub fn choice<T: std::str::FromStr<Err = String>>(
        &mut self,
        key: &'static str,
    ) -> Result<Option<T>, CaseError> {
        self.asked.push(key);
        match self.table.values.get(key) {
            None => Ok(None),
            Some(toml::Value::String(s)) => s
                .parse::<T>()
                .map(Some)
                .map_err(|e| self.table.error(Some(key), e)),
            Some(other) => Err(self
                .table
                .error(Some(key), format!("{key} = {other} must be a string"))),
        }
    }

    /// Refuses every key that was not asked for.
    pub fn finish(self) -> Result<(), CaseError> {
        match self
            .table
            .values
            .keys()
            .find(|k| !self.asked.contains(&k.as_str()))
        {
            None => Ok(()),
            Some(k) => Err(self.table.error(
                Some(k),
                format!("unknown key `{k}`; known: {}", self.asked.join(", ")),
            )),
        }
    }
}
