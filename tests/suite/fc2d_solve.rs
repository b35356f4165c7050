//! `floebench fc2d` and the solvers on Siconos' 2D frictional contact
//! problems (src/iterative/fc2d.rs): the bundled files converge to the
//! tolerance, the operator's residual is the dense formula's, NSGS, APGD and
//! Lemke agree where their laws coincide, the CSV has its columns, and bad
//! tolerances and malformed files are refused with a clear message.

use crate::common::{floebench, stdout_of_success, tempdir};
use floebench::iterative::{
    apgd, nsgs, project_cone, solve_fc2d, Delassus, Fc2dOperator, Fc2dSolver,
};
use floebench::model::fc2d::{read_fc2d, Fc2dProblem};
use std::path::PathBuf;

const FILES: [(&str, usize); 3] = [
    ("FrictionContactProblem00071.dat", 89),
    ("FrictionContactProblem00237.dat", 376),
    ("fc2d_granularflowonwall_00667_00000.dat", 667),
];

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/fc2d")
}

fn problem(name: &str) -> Fc2dProblem {
    read_fc2d(&data().join(name)).expect("a bundled file reads")
}

/// The natural-map residual of `r` from the dense `W` (the README's
/// formula, written out apart from the solvers' code).
fn dense_residual(p: &Fc2dProblem, r: &[[f64; 2]]) -> f64 {
    let m = 2 * p.contacts;
    let w = p.dense();
    let flat: Vec<f64> = r.iter().flat_map(|x| [x[0], x[1]]).collect();
    let mut sum = 0.0;
    for j in 0..p.contacts {
        let u: Vec<f64> = (2 * j..2 * j + 2)
            .map(|i| p.q[i] + (0..m).map(|k| w[i * m + k] * flat[k]).sum::<f64>())
            .collect();
        let mu = p.mu[j];
        let rho = 1.0 / w[2 * j * m + 2 * j];
        let x = [
            r[j][0] - rho * (u[0] + mu * u[1].abs()),
            r[j][1] - rho * u[1],
        ];
        let pr = project_cone(x, mu);
        sum += ((r[j][0] - pr[0]) / rho).powi(2) + ((r[j][1] - pr[1]) / rho).powi(2);
    }
    let qn = p.q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let qmax = p.q.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    sum.sqrt() / qn.max(1e-9 * qmax + 1e-12)
}

/// The rows of a `--csv` file, the header checked.
fn csv_rows(text: &str) -> Vec<Vec<String>> {
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("file,contacts,solver,iterations,residual,siconos_error,cpu_us")
    );
    lines
        .map(|l| l.split(',').map(String::from).collect::<Vec<_>>())
        .inspect(|r| assert_eq!(r.len(), 7, "{r:?}"))
        .collect()
}

#[test]
fn fc2d_nsgs_solves_the_bundled_files_to_the_tolerance() {
    let dir = tempdir();
    let csv = dir.path().join("nsgs.csv");
    let out = stdout_of_success(floebench().arg("fc2d").arg(data()).arg("--csv").arg(&csv));
    assert!(out.contains("3 of 3 files solved by nsgs"), "{out}");
    let rows = csv_rows(&std::fs::read_to_string(&csv).unwrap());
    assert_eq!(rows.len(), 3);
    for (row, (name, nc)) in rows.iter().zip(FILES) {
        assert_eq!(row[0], name);
        assert_eq!(row[1], nc.to_string());
        assert_eq!(row[2], "nsgs");
        let it: u64 = row[3].parse().unwrap();
        let res: f64 = row[4].parse().unwrap();
        let err: f64 = row[5].parse().unwrap();
        let cpu: f64 = row[6].parse().unwrap();
        assert!(
            it >= 1 && res <= 1e-6 && err.is_finite() && cpu >= 0.0,
            "{row:?}"
        );
    }
}

#[test]
fn fc2d_residual_of_the_operator_is_the_dense_formula() {
    for (name, nc) in FILES {
        let p = problem(name);
        let op = Fc2dOperator::new(&p);
        assert_eq!(op.len(), nc);
        let a = solve_fc2d(&p, &op, Fc2dSolver::Nsgs, 1e-6, 10_000).unwrap();
        assert!(a.converged);
        let (res, _) = op.measures(&a.r);
        let dense = dense_residual(&p, &a.r);
        assert!(res <= 1e-6, "{name}: {res}");
        assert!(
            (res - dense).abs() <= 1e-6 * dense + 1e-12,
            "{name}: operator {res}, dense {dense}"
        );
        // A spoiled answer is seen by both.
        let mut spoiled = a.r.clone();
        spoiled[0][0] = spoiled[0][0] * 2.0 + 1.0;
        assert!(op.measures(&spoiled).0 > 1e-3 && dense_residual(&p, &spoiled) > 1e-3);
    }
}

#[test]
fn fc2d_nsgs_and_apgd_agree_without_friction() {
    // Without friction the cone relaxation APGD solves is Coulomb's law:
    // the same velocities u = W r + q (unique: the QP's gradient).
    for (name, _) in FILES.iter().take(2) {
        let mut p = problem(name);
        p.mu.iter_mut().for_each(|m| *m = 0.0);
        let op = Fc2dOperator::new(&p);
        let mut rn = vec![[0.0; 2]; p.contacts];
        let (on, sn) = nsgs::solve(&op, &mut rn, 1e-9, 100_000, 1.0);
        let mut ra = vec![[0.0; 2]; p.contacts];
        let (oa, sa) = apgd::solve(&op, &mut ra, 1e-9, 100_000);
        assert!(on.converged && oa.converged, "{name}: {on:?} {oa:?}");
        let qn = p.q.iter().map(|x| x * x).sum::<f64>().sqrt();
        let diff = (0..p.contacts)
            .map(|j| {
                let (a, b) = (op.relative(j, &sn), op.relative(j, &sa));
                (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
            })
            .sum::<f64>()
            .sqrt();
        assert!(
            diff <= 1e-6 * qn,
            "{name}: ‖u_nsgs − u_apgd‖ = {diff}, ‖q‖ = {qn}"
        );
    }
}

#[test]
fn fc2d_lemke_and_nsgs_agree_on_the_small_file() {
    let name = FILES[0].0;
    let p = problem(name);
    let op = Fc2dOperator::new(&p);
    let l = solve_fc2d(&p, &op, Fc2dSolver::Lemke, 1e-6, 1).unwrap();
    assert!(l.converged);
    let (res, err) = op.measures(&l.r);
    assert!(res <= 1e-12 && err <= 1e-12, "{res} {err}");
    assert!(dense_residual(&p, &l.r) <= 1e-12);
    let n = solve_fc2d(&p, &op, Fc2dSolver::Nsgs, 1e-10, 100_000).unwrap();
    let (sl, sn) = (op.state(&l.r), op.state(&n.r));
    let qn = p.q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let diff = (0..p.contacts)
        .map(|j| {
            let (a, b) = (op.relative(j, &sl), op.relative(j, &sn));
            (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
        })
        .sum::<f64>()
        .sqrt();
    assert!(diff <= 1e-6 * qn, "‖u_lemke − u_nsgs‖ = {diff}, ‖q‖ = {qn}");
}

#[test]
fn fc2d_refuses_a_tolerance_that_is_not_positive_and_finite() {
    for t in ["0", "-1e-6", "NaN", "inf"] {
        let out = floebench()
            .args(["fc2d", &format!("--tolerance={t}")])
            .arg(data())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "--tolerance {t} accepted");
        assert!(
            err.contains("--tolerance") && err.lines().count() == 1,
            "{t}: {err}"
        );
    }
}

#[test]
fn fc2d_reports_a_malformed_file_and_solves_the_others() {
    let dir = tempdir();
    let good = FILES[0].0;
    std::fs::copy(data().join(good), dir.path().join(good)).unwrap();
    let text = std::fs::read_to_string(data().join(good)).unwrap();
    let bad = text.replacen("\n89\n", "\n8x9\n", 1);
    std::fs::write(dir.path().join("bad.dat"), bad).unwrap();
    let csv = dir.path().join("out.csv");
    let out = floebench()
        .arg("fc2d")
        .arg(dir.path())
        .arg("--csv")
        .arg(&csv)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1));
    assert!(err.contains("bad.dat:2: token \"8x9\""), "{err}");
    assert!(
        stdout.contains("1 of 2 files solved") && stdout.contains(good),
        "{stdout}"
    );
    let rows = csv_rows(&std::fs::read_to_string(&csv).unwrap());
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0][0], good);
}
