//! Reports: plots, tables and the report page.

pub mod compare;
pub mod figures;
pub mod page;
pub mod plot;

use std::path::PathBuf;

/// Why a report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Two cases have the same name, so their folders would collide.
    #[error("two cases are named `{0}`: their reports would overwrite each other")]
    DuplicateName(String),
    /// A folder or file could not be written.
    #[error("{path}: {source}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A plot could not be drawn.
    #[error("plot {path}: {message}")]
    Plot {
        /// The plot's file stem.
        path: PathBuf,
        /// What failed.
        message: String,
    },
}
