//! What a case that loads is warned of, and what `validate` refuses for a
//! formulation (issue 55): a floe of another size, a run of days, output
//! times off a fixed step's grid, and the default lattice spacing of
//! narrow bars.

use crate::common::{cases_dir, floebench, scenario, tempdir};
use floebench::formulation::{build, check_formulations, parse_case, FormulationOptions};
use floebench::run::{RunOptions, Runner};
use std::path::Path;

/// A square floe of side `side` (m) with its lower-left corner at `x0`
/// (m, on y = 0).
fn square(x0: f64, side: f64) -> String {
    format!(
        "\n[[floe]]\npolygon = [[{x0:?}, 0.0], [{:?}, 0.0], [{:?}, {side:?}], [{x0:?}, {side:?}]]\nthickness = 1.0\n",
        x0 + side,
        x0 + side,
    )
}

/// `n` 10 m floes in a row, and `extra` appended.
fn row(n: u32, duration: f64, interval: f64, extra: &str) -> String {
    let mut text = format!(
        "[case]\nversion = 1\nname = \"row\"\nduration = {duration:?}\noutput_interval = {interval:?}\n\n[contact]\nrestitution = 0.5\nfriction = 0.3\n"
    );
    for k in 0..n {
        text += &square(20.0 * f64::from(k), 10.0);
    }
    text + extra
}

#[test]
fn a_giant_floe_is_warned_of_and_does_not_move_the_median_scale() {
    let plain = scenario(&row(3, 10.0, 1.0, ""));
    assert!(
        plain.source.warnings.is_empty(),
        "{:?}",
        plain.source.warnings
    );
    let d = plain.median_floe_diameter();
    // A floe of 1e6 m (a unit mistake), far from the others.
    let giant = square(-2.0e6, 1.0e6);
    let text = row(3, 10.0, 1.0, &giant);
    let scn = scenario(&text);
    // The scale is the median: the three small floes' diameter exactly.
    assert_eq!(scn.median_floe_diameter(), d);
    let mean = scn.floes.iter().map(|f| f.diameter()).sum::<f64>() / 4.0;
    assert!(mean > 1e4 * d, "the mean would be dominated: {mean}");
    // One warning, at the giant's [[floe]] line, naming it and both rules.
    let w = &scn.source.warnings;
    assert_eq!(w.len(), 1, "{w:?}");
    // The 0-based index of its polygon is the 1-based line of its header.
    let line = text.lines().position(|l| l.contains("-2000000")).unwrap();
    assert_eq!(w[0].line, Some(line));
    let shown = w[0].to_string();
    for part in [
        "inline.toml:",
        "floe 3 ([[floe]] #3)",
        "median floe diameter d_med",
        "the bounding box of the other floes",
    ] {
        assert!(shown.contains(part), "{shown} lacks {part}");
    }
}

#[test]
fn no_bundled_case_is_warned_of() {
    let cases = floebench::run::batch::load_cases(&[cases_dir(), cases_dir().join("fields")])
        .unwrap_or_else(|e| panic!("{e}"));
    for (path, scn) in &cases {
        assert!(
            scn.source.warnings.is_empty(),
            "{}: {:?}",
            path.display(),
            scn.source.warnings
        );
    }
}

#[test]
fn a_run_of_days_is_warned_of_at_its_duration_and_validate_prints_it() {
    // 20 floes over 1e8 s (the longest duration): 1e5 s of CPU by the
    // rough estimate.
    let text = row(20, 1e8, 1e7, "");
    let scn = scenario(&text);
    let w = &scn.source.warnings;
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].line, Some(4));
    assert!(w[0].message.contains("more than a day"), "{}", w[0]);
    assert!(w[0].message.contains("rough"), "{}", w[0]);
    // Half of it is not warned of.
    assert!(scenario(&row(10, 1e8, 1e7, "")).source.warnings.is_empty());
    // `validate` lists it on stderr and still passes.
    let dir = tempdir();
    let file = dir.path().join("days.toml");
    std::fs::write(&file, &text).unwrap();
    let out = floebench().arg("validate").arg(&file).output().unwrap();
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!("warning: {}:4: [case] duration", file.display())),
        "{err}"
    );
}

#[test]
fn validate_refuses_the_output_interval_a_fixed_step_refuses_naming_file_and_line() {
    let dir = tempdir();
    // A floe against an obstacle: every formulation but free-drift applies.
    let obstacle =
        "\n[[obstacle]]\npolygon = [[70.0, -10.0], [80.0, -10.0], [80.0, 20.0], [70.0, 20.0]]\n";
    let text = row(3, 3.0, 0.3, obstacle);
    let file = dir.path().join("interval.toml");
    std::fs::write(&file, &text).unwrap();
    // The case's own rules accept it, and event-driven runs it.
    let scn = parse_case(&text, &file).unwrap();
    build("event-driven", &scn, &FormulationOptions::default()).unwrap();
    // moreau's default step (1 s) does not divide 0.3 s: refused at the
    // output_interval line, with a step that would do.
    let e = check_formulations(&scn).unwrap_err();
    assert_eq!(e.file, file);
    assert_eq!(e.line, Some(5));
    assert!(
        e.message.contains("[formulation.moreau] step, the default"),
        "{e}"
    );
    assert!(e.message.contains("step = 0.1 would do"), "{e}");
    // The builder refuses with the same located message.
    let built = build("moreau", &scn, &FormulationOptions::default())
        .err()
        .unwrap();
    assert_eq!(built, e.to_string());
    // `validate` fails on it.
    let out = floebench().arg("validate").arg(&file).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains(&format!("{}:5:", file.display())));
    // A written step is named at its own line.
    let text = text + "\n[formulation.moreau]\nstep = 0.25\n";
    let scn = parse_case(&text, &file).unwrap();
    let e = check_formulations(&scn).unwrap_err();
    let step_line = text.lines().position(|l| l.starts_with("step")).unwrap() + 1;
    assert_eq!(e.line, Some(step_line), "{e}");
    assert!(e.message.contains("step = 0.05 would do"), "{e}");
}

/// Two bars of 100 m and 200 m, 10 m wide, with lattice impacts and
/// `spacing` lines appended.
fn two_bars(spacing: &str) -> String {
    format!(
        "[case]\nversion = 1\nname = \"two_bars\"\nduration = 2.0\noutput_interval = 1.0\n\n[contact]\nrestitution = 0.5\nfriction = 0.3\n\n[[floe]]\npolygon = [[0.0, 0.0], [100.0, 0.0], [100.0, 10.0], [0.0, 10.0]]\nthickness = 1.0\nvelocity = [2.0, 0.0]\n\n[[floe]]\npolygon = [[101.0, 0.0], [301.0, 0.0], [301.0, 10.0], [101.0, 10.0]]\nthickness = 1.0\n\n[fracture]\nmodel = \"lattice\"\nimpact = \"lattice\"\n{spacing}"
    )
}

#[test]
fn the_default_lattice_spacing_fits_two_narrow_bars_and_a_refused_one_says_what_would_do() {
    let scn = parse_case(&two_bars(""), Path::new("bars.toml")).unwrap_or_else(|e| panic!("{e}"));
    check_formulations(&scn).unwrap();
    // The 200 m bar's default (√A/8 = 5.59 m) is cut to half its width.
    let s = floebench::fracture::strike::lattice_spacing(
        &scn.fracture,
        scn.floes[1].area,
        &scn.floes[1].shape,
    );
    assert_eq!(s, 5.0);
    // The 100 m bar keeps √A/8 = 3.95 m: the rule changes no spacing that passed.
    let s0 = floebench::fracture::strike::lattice_spacing(
        &scn.fracture,
        scn.floes[0].area,
        &scn.floes[0].shape,
    );
    assert_eq!(s0, 0.125 * scn.floes[0].area.sqrt());
    // It runs a short time.
    let mut f = build("event-driven", &scn, &FormulationOptions::default()).unwrap();
    let r = Runner::new(RunOptions::default()).run(&scn, "event-driven", f.formulation.as_mut());
    assert_eq!(r.summary.t_reached, 2.0, "{:?}", r.summary.end);
    // An explicit spacing of 6 m is refused at its line with the value that would do.
    let text = two_bars("spacing = 6.0\n");
    let e = parse_case(&text, Path::new("bars.toml")).unwrap_err();
    assert_eq!(e.line, Some(text.lines().count()));
    assert!(e.message.contains("spacing <= 5 m would do"), "{e}");
}
