//! Reports: everything that turns runs and their analysis into files and
//! text for people. Nothing below this layer prints a table or draws a plot.
//!
//! - [`compare`]: writes a comparison (`floebench compare`): each case's
//!   folder (data files, run files, plots), then `index.md` and `index.html`;
//! - [`folder`]: which case folders of an output folder a report owns (it
//!   replaces no other);
//! - [`verdict`]: the verdict sentences on a case;
//! - `tables` (private): the tables of the report page (headline, runs,
//!   pairs, checks);
//! - [`case_view`]: the picture of a case before it runs (`floebench
//!   show`): floes, obstacles, wind, current and velocities, a scale bar;
//! - [`checks`]: the tables of check outcomes (`floebench check`): plain
//!   text, Markdown, `checks.csv`;
//! - [`figures`]: which plots a comparison draws, from its data;
//! - `lattice_energy` (private): the energy split of the impacts resolved
//!   in the floes' lattices, against time;
//! - [`crack`]: the crack figure of a percussion (the lattice with its
//!   broken bonds), for the report and `percussion-2d --plot`;
//! - [`page`]: the page's document model, rendered as Markdown and HTML;
//! - `parameters` (private): the case's and the runs' parameters on the page;
//! - [`provenance`]: version, commit, machine and date of a report;
//! - [`plot`]: the charts (plotters, DejaVu Sans embedded): lines, stacked
//!   bars, plan views, snapshot grids;
//! - [`sweep`]: writes a sweep's report (`floebench sweep`): `sweep.csv`,
//!   `orders.csv`, the work–precision and error-against-setting plots, the page;
//! - [`format`](mod@format): the one rounding rule of the numbers printed for
//!   people ([`format::fmt_num`]).

pub mod case_view;
pub mod checks;
pub mod compare;
pub mod crack;
pub mod figures;
pub mod folder;
pub mod format;
mod lattice_energy;
pub mod page;
mod parameters;
pub mod plot;
pub mod provenance;
pub mod sweep;
mod tables;
pub mod verdict;

use std::path::PathBuf;

/// Why a report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Two cases have the same name, so their folders would collide.
    #[error("two cases are named `{0}`: their reports would overwrite each other")]
    DuplicateName(String),
    /// The output path exists and is not a folder.
    #[error("{0} exists and is not a folder")]
    NotAFolder(PathBuf),
    /// A case's folder exists and was not written by a report into this
    /// output folder ([`folder`]).
    #[error("{0} exists and is not a case folder of a report in this output folder (another report, or your files): choose another output folder, or move it")]
    NotOurs(PathBuf),
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

/// The error of a chart that could not be drawn at `stem` (its files'
/// path without extension).
fn plot_err(stem: &std::path::Path) -> impl FnOnce(plot::PlotError) -> ReportError + '_ {
    move |e| ReportError::Plot {
        path: stem.to_path_buf(),
        message: e.to_string(),
    }
}
