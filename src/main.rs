//! The `floebench` command line: parse arguments, call the library. The
//! commands, their arguments and what they print are in [`cli`].

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    if let Err(e) = floebench::run::interrupt::install() {
        eprintln!("warning: Ctrl-C will not end runs cleanly: {e}");
    }
    cli.command.run()
}
