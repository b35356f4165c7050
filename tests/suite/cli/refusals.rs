//! What the commands refuse before running: one grammar for formulations
//! and jobs, free drift through contacts, dumps a formulation does not
//! write, output paths that are not folders, unknown formulations.

use super::cli;
use crate::common::{case_path, tempdir};

#[test]
fn one_grammar_for_formulations_and_jobs() {
    let dir = tempdir();
    let md = dir.path().join("t.md");
    // check takes -f like run and compare, with spaces after the commas.
    let (ok, stdout, stderr) = cli(&[
        "check".as_ref(),
        case_path("head_on").as_os_str(),
        "-f".as_ref(),
        "event-driven, moreau".as_ref(),
        "--quiet".as_ref(),
        "--markdown".as_ref(),
        md.as_os_str(),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("moreau") && !stdout.contains("rapier"),
        "{stdout}"
    );
    let (ok, _, stderr) = cli(&[
        "compare".as_ref(),
        case_path("head_on").as_os_str(),
        "-j".as_ref(),
        "0".as_ref(),
    ]);
    assert!(!ok && stderr.contains("-j"), "{stderr}");
    // check takes -j as compare does.
    let (ok, _, stderr) = cli(&[
        "check".as_ref(),
        case_path("head_on").as_os_str(),
        "-f".as_ref(),
        "event-driven".as_ref(),
        "-j".as_ref(),
        "1".as_ref(),
        "--quiet".as_ref(),
    ]);
    assert!(ok, "{stderr}");
    let (ok, _, stderr) = cli(&[
        "check".as_ref(),
        case_path("head_on").as_os_str(),
        "-j".as_ref(),
        "0".as_ref(),
    ]);
    assert!(!ok && stderr.contains("-j"), "{stderr}");
}

#[test]
fn run_refuses_what_would_mislead_before_running() {
    let dir = tempdir();
    let out = dir.path().join("o");
    let head_on = case_path("head_on");
    // free-drift through a case with contacts: refused unless asked.
    let (ok, _, stderr) = cli(&[
        "run".as_ref(),
        case_path("bouncing_floe").as_os_str(),
        "-f".as_ref(),
        "free-drift".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(!ok && stderr.contains("--allow-contacts"), "{stderr}");
    assert!(!out.exists());
    let (ok, _, stderr) = cli(&[
        "run".as_ref(),
        case_path("bouncing_floe").as_os_str(),
        "-f".as_ref(),
        "free-drift".as_ref(),
        "--allow-contacts".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(ok, "{stderr}");
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains("\"ignored\""),
        "the summary says contacts were ignored"
    );
    // --dump-lcp: a formulation that dumps nothing, and a used folder.
    let dumps = dir.path().join("d");
    for f in ["rapier", "moreau-cone", "free-drift"] {
        let (ok, _, stderr) = cli(&[
            "run".as_ref(),
            head_on.as_os_str(),
            "-f".as_ref(),
            f.as_ref(),
            "--dump-lcp".as_ref(),
            dumps.as_os_str(),
            "--quiet".as_ref(),
        ]);
        assert!(
            !ok && stderr.contains("writes no LCP dumps"),
            "{f}: {stderr}"
        );
    }
    std::fs::create_dir_all(&dumps).unwrap();
    std::fs::write(dumps.join("000000.json"), "{}").unwrap();
    let (ok, _, stderr) = cli(&[
        "run".as_ref(),
        head_on.as_os_str(),
        "--dump-lcp".as_ref(),
        dumps.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(!ok && stderr.contains("not an empty folder"), "{stderr}");
    // An output path that is a file: compare says so before any run.
    let file = dir.path().join("notes.txt");
    std::fs::write(&file, "x").unwrap();
    let (ok, _, stderr) = cli(&[
        "compare".as_ref(),
        head_on.as_os_str(),
        "-o".as_ref(),
        file.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(!ok && stderr.contains("is not a folder"), "{stderr}");
    assert!(
        !stderr.contains("runs at a time"),
        "refused before loading: {stderr}"
    );
}

#[test]
fn compare_and_check_refuse_free_drift_through_contacts_as_run_does() {
    // Issue 40: `run -f free-drift` refused a case with contacts, `compare`
    // ran it (the floes passed through the coast). One rule for all three.
    let dir = tempdir();
    let out = dir.path().join("r");
    let bouncing = case_path("bouncing_floe");
    for cmd in ["compare", "check"] {
        let mut args: Vec<&std::ffi::OsStr> = vec![
            cmd.as_ref(),
            bouncing.as_os_str(),
            "-f".as_ref(),
            "event-driven,free-drift".as_ref(),
            "--quiet".as_ref(),
        ];
        if cmd == "compare" {
            args.extend(["-o".as_ref(), out.as_os_str()]);
        }
        let (ok, _, stderr) = cli(&args);
        assert!(
            !ok && stderr.contains("free-drift ignores contacts")
                && stderr.contains("--allow-contacts"),
            "{cmd}: {stderr}"
        );
        assert!(
            !stderr.contains("runs at a time"),
            "refused before any run: {stderr}"
        );
    }
    assert!(!out.exists(), "no report for a refused comparison");
    let (ok, stdout, stderr) = cli(&[
        "compare".as_ref(),
        bouncing.as_os_str(),
        "-f".as_ref(),
        "free-drift".as_ref(),
        "--allow-contacts".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("bouncing_floe"), "{stdout}");
}

#[test]
fn an_unknown_formulation_is_named_without_blaming_a_case() {
    for cmd in ["compare", "check"] {
        let (ok, _, stderr) = cli(&[
            cmd.as_ref(),
            case_path("head_on").as_os_str(),
            "-f".as_ref(),
            "rapeir".as_ref(),
            "--quiet".as_ref(),
        ]);
        assert!(!ok);
        assert!(
            stderr.contains(
                "error: -f: unknown formulation `rapeir` (did you mean `rapier`?); known: event-driven"
            ),
            "{cmd}: {stderr}"
        );
        assert!(!stderr.contains("head_on.toml"), "{cmd}: {stderr}");
    }
    // run too, with its one formulation: the case keys' did-you-mean.
    let (ok, _, stderr) = cli(&[
        "run".as_ref(),
        case_path("head_on").as_os_str(),
        "-f".as_ref(),
        "event_driven".as_ref(),
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("unknown formulation `event_driven` (did you mean `event-driven`?)"),
        "{stderr}"
    );
    // A name far from every formulation gets no guess.
    let (ok, _, stderr) = cli(&[
        "run".as_ref(),
        case_path("head_on").as_os_str(),
        "--formulation".as_ref(),
        "xyzzy-quux".as_ref(),
    ]);
    assert!(!ok && !stderr.contains("did you mean"), "{stderr}");
}

#[test]
fn every_option_of_every_help_is_in_docs_commands() {
    // The help and docs/commands.md describe the same options: each long
    // option a command's --help lists is named in docs/commands.md.
    let docs = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/commands.md"),
    )
    .unwrap();
    let commands = [
        "validate",
        "run",
        "compare",
        "check",
        "lcp",
        "sweep",
        "percussion-1d",
        "percussion-2d",
    ];
    let mut missing = Vec::new();
    for cmd in commands {
        let (ok, help, stderr) = cli(&[cmd.as_ref(), "--help".as_ref()]);
        assert!(ok, "{stderr}");
        for line in help.lines() {
            // `  -o, --out <OUT>`: the docs may name it by either form.
            let line = line.trim_start();
            let short = line
                .strip_prefix('-')
                .filter(|rest| rest.get(1..3) == Some(", "))
                .and_then(|rest| rest.get(..1))
                .map(|c| format!("-{c} "));
            for word in line.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-')) {
                let Some(name) = word.strip_prefix("--") else {
                    continue;
                };
                let named = docs.contains(&format!("--{name}"))
                    || short.as_ref().is_some_and(|s| docs.contains(s.as_str()));
                if !name.is_empty() && name != "help" && !named {
                    missing.push(format!("{cmd} --{name}"));
                }
            }
        }
    }
    missing.dedup();
    assert!(missing.is_empty(), "not in docs/commands.md: {missing:?}");
    // The names the help shows.
    let (_, help, _) = cli(&["run".as_ref(), "--help".as_ref()]);
    assert!(help.contains("-f, --formulation <NAME>"), "{help}");
    assert!(
        help.contains("docs/output-format.md") && !help.contains("README"),
        "{help}"
    );
    let (_, help, _) = cli(&["--help".as_ref()]);
    assert!(
        help.contains("floebench compare cases/head_on.toml")
            && help.contains("floebench validate cases/"),
        "{help}"
    );
    let (_, help, _) = cli(&["lcp".as_ref(), "--help".as_ref()]);
    assert!(help.contains("small-unpolished-below"), "{help}");
    let (_, help, _) = cli(&["check".as_ref(), "--help".as_ref()]);
    assert!(help.contains("-j, --jobs"), "{help}");
}
