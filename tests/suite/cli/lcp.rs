//! `lcp`: the switch of the small-problem refinement of `--time`.

use super::cli;
use crate::common::tempdir;

#[test]
fn lcp_time_switches_the_small_problem_refinement() {
    // `lcp DIR --time` (default `--unpolished-below 1e-13`) keeps the
    // small candidates within 1e-13 unrefined; `--unpolished-below 0`
    // refines every candidate: the same pivots on every dump, and residuals
    // at least as small. The old name of the switch is still read. A
    // negative value is refused by name.
    let dir = tempdir();
    let dumps = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/lcp");
    let rows = |extra: &[&str], name: &str| {
        let csv = dir.path().join(name);
        let mut args: Vec<&std::ffi::OsStr> = vec!["lcp".as_ref(), dumps.as_os_str()];
        args.extend(["--time", "--repeat", "1", "--csv"].map(std::ffi::OsStr::new));
        args.push(csv.as_os_str());
        args.extend(extra.iter().map(std::ffi::OsStr::new));
        let (ok, _, stderr) = cli(&args);
        assert!(ok, "{stderr}");
        let text = std::fs::read_to_string(&csv).unwrap();
        text.lines()
            .skip(1)
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                let n: usize = f[1].parse().unwrap();
                let pivots: usize = f[3].parse().unwrap();
                let residual: f64 = f[6].parse().unwrap();
                (f[0].to_string(), n, pivots, residual)
            })
            .collect::<Vec<_>>()
    };
    let small = rows(&[], "small.csv");
    assert_eq!(
        small,
        rows(&["--small-unpolished-below", "1e-13"], "old_name.csv")
    );
    let refined = rows(&["--unpolished-below", "0"], "refined.csv");
    assert_eq!(small.len(), refined.len());
    let mut differ = 0;
    for (a, b) in small.iter().zip(&refined) {
        assert_eq!((&a.0, a.1, a.2), (&b.0, b.1, b.2));
        assert!(b.3 <= a.3, "{}: refined {:e} above {:e}", a.0, b.3, a.3);
        if a.1 > 40 {
            assert_eq!(a.3, b.3, "{}: above 40 unknowns nothing changes", a.0);
        } else if a.3 != b.3 {
            differ += 1;
            assert!(a.3 <= 1e-13, "{}: {:e}", a.0, a.3);
        }
    }
    assert!(differ > 0, "the switch changed no residual");
    let (ok, _, stderr) = cli(&[
        "lcp".as_ref(),
        dumps.as_os_str(),
        "--time".as_ref(),
        "--unpolished-below=-1".as_ref(),
    ]);
    assert!(!ok);
    assert!(stderr.contains("--unpolished-below"), "{stderr}");
}
