//! `floebench show`: the picture of a case before it runs.

use super::Outcome;
use floebench::formulation::load_case;
use std::path::PathBuf;
use std::process::ExitCode;

/// The arguments of `floebench show`.
#[derive(clap::Args)]
pub struct Args {
    /// The case file (.toml).
    case: PathBuf,
    /// The picture to write, a PNG file [default: <case name>.png in the
    /// current folder].
    #[arg(short, long, value_name = "PNG")]
    out: Option<PathBuf>,
}

/// Loads the case as `run` does (a bad case is refused as `validate`
/// refuses it, naming file, line and key, and nothing is written), draws
/// it ([`floebench::report::case_view`]) and prints the path written.
pub fn run(args: Args) -> Outcome {
    if let Some(out) = &args.out {
        let png = out
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if !png {
            return Err(format!(
                "-o {}: the picture is a PNG file: name it *.png",
                out.display()
            ));
        }
    }
    let scn = load_case(&args.case).map_err(|e| e.to_string())?;
    let out = args
        .out
        .unwrap_or_else(|| PathBuf::from(format!("{}.png", scn.name)));
    if out.is_dir() {
        return Err(format!("-o {}: is a folder", out.display()));
    }
    let path = floebench::report::case_view::draw(&scn, &out).map_err(|e| e.to_string())?;
    println!("wrote {}", path.display());
    Ok(ExitCode::SUCCESS)
}
