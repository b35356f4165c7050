//! The `[formulation.<name>]` tables of a case file, kept as written and
//! read by the formulation that owns each (see
//! [`crate::formulation::Entry::settings`]).
//!
//! A table keeps the line of each key, so a formulation's parser reports a
//! bad value at the file and line where it is written. The case loader
//! validates every table with its owner's parser before a case is accepted;
//! an unknown table or key is an error.

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
}

/// The parser of one table: checks it and reports errors with their line.
#[derive(Debug, Clone, Copy)]
pub struct TableSpec {
    /// The table's name (`moreau` for `[formulation.moreau]`).
    pub name: &'static str,
    /// Checks the table (every key known, every value in range).
    pub validate: fn(&SettingsTable) -> Result<(), CaseError>,
}

impl SettingsTable {
    /// A table read from `file`, header at `line`, with the line of each key.
    pub fn new(
        name: &str,
        values: toml::Table,
        file: PathBuf,
        line: Option<usize>,
        key_lines: BTreeMap<String, usize>,
    ) -> SettingsTable {
        SettingsTable {
            name: name.to_string(),
            values,
            file,
            line,
            key_lines,
        }
    }

    /// An empty table (a case that does not write it: every default).
    pub fn empty(name: &str) -> SettingsTable {
        SettingsTable::new(
            name,
            toml::Table::new(),
            PathBuf::new(),
            None,
            BTreeMap::new(),
        )
    }

    /// The error `message` at the line of `key` (or of the table).
    pub fn error(&self, key: Option<&str>, message: impl Into<String>) -> CaseError {
        CaseError {
            file: self.file.clone(),
            line: key
                .and_then(|k| self.key_lines.get(k).copied())
                .or(self.line),
            message: format!("[formulation.{}] {}", self.name, message.into()),
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

    /// A number that must be finite and > 0.
    pub fn positive(&mut self, key: &'static str) -> Result<Option<f64>, CaseError> {
        match self.number(key)? {
            Some(v) if !(v.is_finite() && v > 0.0) => Err(self
                .table
                .error(Some(key), format!("{key} = {v} must be finite and > 0"))),
            v => Ok(v),
        }
    }

    /// A number in [0, 1].
    pub fn unit_interval(&mut self, key: &'static str) -> Result<Option<f64>, CaseError> {
        match self.number(key)? {
            Some(v) if !(0.0..=1.0).contains(&v) => Err(self
                .table
                .error(Some(key), format!("{key} = {v} must be in [0, 1]"))),
            v => Ok(v),
        }
    }

    /// An integer ≥ `min`.
    pub fn integer_at_least(
        &mut self,
        key: &'static str,
        min: i64,
    ) -> Result<Option<i64>, CaseError> {
        self.asked.push(key);
        match self.table.values.get(key) {
            None => Ok(None),
            Some(toml::Value::Integer(v)) if *v >= min => Ok(Some(*v)),
            Some(toml::Value::Integer(_)) => Err(self
                .table
                .error(Some(key), format!("{key} must be >= {min}"))),
            Some(other) => Err(self.table.error(
                Some(key),
                format!("{key} = {other} must be an integer >= {min}"),
            )),
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
