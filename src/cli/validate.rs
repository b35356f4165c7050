//! `floebench validate`: load case files and describe them.

use super::{describe, plural, print_warnings, Outcome};
use floebench::formulation::validate_case;
use std::path::PathBuf;
use std::process::ExitCode;

/// The arguments of `floebench validate`.
#[derive(clap::Args)]
pub struct Args {
    /// Case files (.toml) or folders (their *.toml files, not subfolders).
    #[arg(required = true)]
    cases: Vec<PathBuf>,
}

/// Describes every case file on stdout and names every bad one on stderr,
/// with the warnings of every good one (`warning: <file>:<line>: …`);
/// fails when one is bad.
pub fn run(args: Args) -> Outcome {
    let files = floebench::run::batch::case_files(&args.cases).map_err(|e| e.to_string())?;
    let mut bad = 0;
    for path in &files {
        match validate_case(path) {
            Ok(scn) => {
                println!("ok  {}", describe(&scn));
                print_warnings(&scn);
            }
            Err(e) => {
                eprintln!("error: {e}");
                bad += 1;
            }
        }
    }
    if bad > 0 {
        eprintln!("{} of {} bad", plural(bad, "case file"), files.len());
        Ok(ExitCode::FAILURE)
    } else {
        Ok(ExitCode::SUCCESS)
    }
}
