//! `floebench show` (the picture of a case before it runs) and
//! `run --plot` (a run's figures).

use crate::common::{bad_case, case_path, floebench, stdout_of_success, tempdir};

/// The bytes every PNG file starts with.
const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// Whether `path` is a PNG file larger than its header.
fn is_png(path: &std::path::Path) -> bool {
    std::fs::read(path).is_ok_and(|b| b.len() > 1000 && b.starts_with(PNG_SIGNATURE))
}

#[test]
fn show_draws_a_bundled_case_with_a_field_and_its_default_name() {
    let dir = tempdir();
    // The default name: <case name>.png in the current folder.
    let stdout = stdout_of_success(
        floebench()
            .current_dir(dir.path())
            .arg("show")
            .arg(case_path("narrow_channel")),
    );
    let png = dir.path().join("narrow_channel.png");
    assert!(is_png(&png), "no PNG at {}", png.display());
    assert!(stdout.contains("wrote narrow_channel.png"));
    // Only the PNG (no SVG, no temporary file left).
    let files: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(files.len(), 1, "{files:?}");
    // -o names it; a vortex current (arrows on a grid) draws too.
    let named = dir.path().join("sub").join("v.png");
    stdout_of_success(
        floebench()
            .arg("show")
            .arg(case_path("vortex_field"))
            .arg("-o")
            .arg(&named),
    );
    assert!(is_png(&named));
}

#[test]
fn show_refuses_a_bad_case_as_validate_does_and_writes_nothing() {
    let dir = tempdir();
    let bad = bad_case("clockwise");
    let out = floebench()
        .current_dir(dir.path())
        .arg("show")
        .arg(&bad)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("clockwise.toml:14") && err.contains("[[floe]] #0"),
        "{err}"
    );
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    // An output that is not a PNG is refused before anything is drawn.
    let out = floebench()
        .arg("show")
        .arg(case_path("head_on"))
        .arg("-o")
        .arg(dir.path().join("head_on.svg"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn run_plot_draws_the_energies_and_snapshots_into_the_run_folder() {
    let dir = tempdir();
    stdout_of_success(
        floebench()
            .arg("run")
            .arg(case_path("head_on"))
            .args(["-f", "moreau", "--plot", "-q", "-o"])
            .arg(dir.path()),
    );
    for stem in ["kinetic", "dissipated", "snapshots"] {
        assert!(
            is_png(&dir.path().join(format!("{stem}.png"))),
            "{stem}.png"
        );
        assert!(
            dir.path().join(format!("{stem}.svg")).is_file(),
            "{stem}.svg"
        );
    }
    // Without --plot, no figure.
    let plain = tempdir();
    stdout_of_success(
        floebench()
            .arg("run")
            .arg(case_path("head_on"))
            .args(["-f", "moreau", "-q", "-o"])
            .arg(plain.path()),
    );
    assert!(!plain.path().join("snapshots.png").exists());
}
