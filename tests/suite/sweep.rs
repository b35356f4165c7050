//! `floebench sweep`: the observed orders that theory predicts, measured by
//! the sweep itself on small plans of the bundled cases; resuming; an
//! interrupted point; the tasks of a cluster job against the local run;
//! bad plans.

use crate::common::{
    bouncing_expected, case_path, case_text, floebench, interrupt_after, scenario, tempdir,
};
use floebench::analysis::check::wind_acceleration;
use floebench::sweep::execute::{run_local, run_task, ExecOptions, Executed};
use floebench::sweep::orders::{Order, Span};
use floebench::sweep::plan::{load_plan, parse_plan, Plan};
use floebench::sweep::points::{points, tasks};
use floebench::sweep::{collect, slurm};
use std::path::{Path, PathBuf};

/// A plan of `cases` (bundled names) with `body` after `[sweep]`'s
/// `cases` line, written into `dir`.
fn plan_file(dir: &Path, cases: &[&str], body: &str) -> PathBuf {
    let list: Vec<String> = cases
        .iter()
        .map(|c| format!("{:?}", case_path(c).display().to_string()))
        .collect();
    let text = format!(
        "[sweep]\nversion = 1\nname = \"t\"\ncases = [{}]\n{body}\n",
        list.join(", ")
    );
    let path = dir.join("plan.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn load(path: &Path) -> Plan {
    load_plan(path).unwrap_or_else(|e| panic!("{e}"))
}

/// Runs every point of the plan at `path` into `out`; returns what was done
/// and the observed orders.
fn sweep(path: &Path, out: &Path) -> (Executed, Vec<Order>) {
    let plan = load(path);
    let pts = points(&plan);
    let done = run_local(
        &plan,
        &pts,
        out,
        ExecOptions {
            jobs: 2,
            progress: false,
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let orders = collect(&plan, pts, out).orders();
    (done, orders)
}

/// The orders of `metric` along `key`, in increasing value.
fn along<'a>(orders: &'a [Order], metric: &str, key: &str, span: Span) -> Vec<&'a Order> {
    orders
        .iter()
        .filter(|o| o.metric == metric && o.key == key && o.span == span)
        .collect()
}

#[test]
fn rapier_free_drift_position_error_is_first_order_in_its_step() {
    let dir = tempdir();
    let path = plan_file(
        dir.path(),
        &["free_drift"],
        "reference = \"event-driven\"\nmeasures = [\"position\"]\n\n\
         [[formulation]]\nname = \"rapier\"\ngrid = { step = [0.4, 0.2, 0.1, 0.05] }",
    );
    let (done, orders) = sweep(&path, &dir.path().join("out"));
    assert_eq!((done.run, done.skipped, done.references), (4, 0, 1));
    let p = along(&orders, "position", "step", Span::Successive);
    assert_eq!(p.len(), 3, "{orders:?}");
    for o in p {
        eprintln!(
            "rapier free drift: h {} -> {}: position error {:.4e} -> {:.4e}, order {:.5}",
            o.s_from, o.s_to, o.e_from, o.e_to, o.order
        );
        // Symplectic Euler under the drag: e = C h + O(h^2), so the order
        // of a halving moves from 1 by O(h/T) (T the drag time, 430 s):
        // measured 1.0002 at most.
        assert!((o.order - 1.0).abs() < 0.01, "{o:?}");
    }
}

#[test]
fn moreau_sliding_distance_error_is_second_order_in_h() {
    let dir = tempdir();
    let path = plan_file(
        dir.path(),
        &["sliding_floe"],
        "reference = \"exact\"\nmeasures = [\"check:sliding_distance\"]\n\n\
         [[formulation]]\nname = \"moreau\"\ngrid = { step = [1.0, 0.5, 0.25, 0.125] }",
    );
    let out = dir.path().join("out");
    let (done, orders) = sweep(&path, &out);
    assert_eq!((done.run, done.references), (4, 0));
    // The error is 1/2 mu a h^2 f (1 - f) (f: the fractional part of
    // t_stop / h, see tests/suite/moreau/closed_forms.rs): at most mu a h^2 / 8, second
    // order, with a factor f (1 - f) that changes from one h to the next, so
    // single halvings measure 3.37, 1.18, 1.46 and the order over the three
    // halvings 2.00.
    let all = along(&orders, "check:sliding_distance", "step", Span::Successive);
    assert_eq!(all.len(), 3, "{orders:?}");
    let overall = along(&orders, "check:sliding_distance", "step", Span::Overall);
    assert_eq!(overall.len(), 1);
    eprintln!(
        "moreau sliding distance: successive orders {:?}, overall {:.4}",
        all.iter().map(|o| o.order).collect::<Vec<_>>(),
        overall[0].order
    );
    assert!((overall[0].order - 2.0).abs() < 0.05, "{:?}", overall[0]);
    let scn = scenario(&case_text("sliding_floe"));
    let (a, mu, v0) = (wind_acceleration(&scn, 0), scn.contact.friction, 0.05);
    let dist = v0 * v0 / (2.0 * mu * a);
    for o in all {
        for (h, e) in [(o.s_from, o.e_from), (o.s_to, o.e_to)] {
            // The sweep's error is relative to the distance.
            assert!(
                e * dist <= mu * a * h * h / 8.0 * (1.0 + 1e-9),
                "h = {h}: {e}"
            );
        }
    }
}

#[test]
fn event_driven_first_impact_error_is_linear_in_the_contact_distance() {
    let dir = tempdir();
    let path = plan_file(
        dir.path(),
        &["bouncing_floe"],
        "reference = \"exact\"\nmeasures = [\"first_event\"]\n\n\
         [[formulation]]\nname = \"event-driven\"\ngrid = { \"contact.distance\" = [0.02, 0.01, 0.005] }",
    );
    let (_, orders) = sweep(&path, &dir.path().join("out"));
    let p = along(&orders, "first_event", "contact.distance", Span::Successive);
    assert_eq!(p.len(), 2, "{orders:?}");
    let b = bouncing_expected(&scenario(&case_text("bouncing_floe")));
    for o in p {
        eprintln!(
            "event-driven first impact: delta {} -> {}: error {:.4e} -> {:.4e} (x t1: {:.4} s, delta/(10 v1) = {:.4} s), order {:.4}",
            o.s_from,
            o.s_to,
            o.e_from,
            o.e_to,
            o.e_from * b.t1,
            0.1 * o.s_from / b.v1,
            o.order
        );
        // The impact is located at a gap of delta / 10, to 1e-3 delta: early
        // by delta / (10 v1) to 1 %, plus what the floe's acceleration over
        // that last tenth changes (measured: +0.01 % at 0.005 m, +1.01 % at
        // 0.01 m); the bound allows 1.5 %.
        for (d, e) in [(o.s_from, o.e_from), (o.s_to, o.e_to)] {
            let early = e * b.t1;
            assert!(
                early >= 0.0985 * d / b.v1 && early <= 0.1015 * d / b.v1,
                "delta = {d}: {early} s against delta/(10 v1) = {} s",
                0.1 * d / b.v1
            );
        }
        assert!((o.order - 1.0).abs() < 0.02, "{o:?}");
    }
}

#[test]
fn a_resumed_sweep_recomputes_nothing_and_a_removed_point_is_run_again() {
    let dir = tempdir();
    let path = plan_file(
        dir.path(),
        &["head_on", "bouncing_floe"],
        "reference = \"event-driven\"\n\n[[formulation]]\nname = \"moreau\"\ngrid = { step = [0.5, 0.25] }",
    );
    let out = dir.path().join("out");
    let args = |extra: &[&str]| {
        let mut a: Vec<String> = vec![
            "sweep".into(),
            path.display().to_string(),
            "-o".into(),
            out.display().to_string(),
            "--quiet".into(),
        ];
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let run = |extra: &[&str]| {
        let o = floebench().args(args(extra)).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let first = run(&[]);
    assert!(
        first.contains("sweep: 4 points run, 0 skipped (already finished), 2 reference runs"),
        "{first}"
    );
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert!(csv
        .starts_with("case,formulation,settings,metric,value,unit\nhead_on,moreau,step=0.5,cpu,"));
    // The page and its plots.
    let page = std::fs::read_to_string(out.join("index.md")).unwrap();
    for case in ["head_on", "bouncing_floe"] {
        for stem in ["work_precision", "setting_step"] {
            for ext in ["png", "svg"] {
                let f = format!("{case}/{stem}.{ext}");
                assert!(out.join(&f).is_file(), "{f}");
            }
            assert!(page.contains(&format!("{case}/{stem}.png")), "{page}");
        }
    }
    assert!(page.contains("4 of 4 points finished"), "{page}");
    let file = out.join("points").join("head_on__moreau__step=0.5.json");
    let written = std::fs::metadata(&file).unwrap().modified().unwrap();
    let again = run(&[]);
    assert!(
        again.contains("sweep: 0 points run, 4 skipped (already finished), 0 reference runs"),
        "{again}"
    );
    assert_eq!(
        std::fs::metadata(&file).unwrap().modified().unwrap(),
        written
    );
    assert_eq!(std::fs::read_to_string(out.join("sweep.csv")).unwrap(), csv);
    std::fs::remove_file(&file).unwrap();
    let third = run(&[]);
    assert!(
        third.contains("sweep: 1 point run, 3 skipped (already finished), 0 reference runs"),
        "{third}"
    );
}

#[test]
fn an_interrupted_point_leaves_no_result_file() {
    let dir = tempdir();
    let path = plan_file(
        dir.path(),
        &["head_on", "fields/field_200_coast"],
        "reference = \"exact\"\n\n[[formulation]]\nname = \"event-driven\"",
    );
    let out = dir.path().join("out");
    // The field's point runs after head_on's (one at a time): interrupted
    // 1.5 s into it.
    let (code, seen) = interrupt_after(
        &[
            "sweep".as_ref(),
            path.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
            "-j".as_ref(),
            "1".as_ref(),
        ],
        "head_on / event-driven",
        std::time::Duration::from_millis(1500),
        libc::SIGINT,
    );
    assert_eq!(code, Some(130), "{seen}");
    assert!(seen.contains("interrupted"), "{seen}");
    let points = out.join("points");
    assert!(points
        .join("head_on__event-driven__defaults.json")
        .is_file());
    let files: Vec<String> = std::fs::read_dir(&points)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        files,
        ["head_on__event-driven__defaults.json"],
        "no partial or temporary file"
    );
    let page = std::fs::read_to_string(out.join("index.md")).unwrap();
    assert!(page.contains("1 of 2 points finished"), "{page}");
}

#[test]
fn the_tasks_of_a_cluster_job_give_the_local_sweep_csv_but_for_cpu_times() {
    let dir = tempdir();
    let path = plan_file(
        dir.path(),
        &["head_on", "sliding_floe"],
        "reference = \"event-driven\"\n\n\
         [[formulation]]\nname = \"rapier\"\ngrid = { iterations = [2, 4] }\n\n\
         [[formulation]]\nname = \"event-driven\"\ngrid = { \"integrator.tolerance\" = [1e-8, 1e-10], \"contact.distance\" = [0.01, 0.005] }",
    );
    let plan = load(&path);
    let pts = points(&plan);
    let (local, cluster) = (dir.path().join("local"), dir.path().join("cluster"));
    sweep(&path, &local);
    let written = slurm::write_slurm(
        &plan,
        &pts,
        &cluster,
        &dir.path().join("slurm"),
        Path::new(env!("CARGO_BIN_EXE_floebench")),
        &slurm::SlurmOptions {
            chunk: 3,
            ..slurm::SlurmOptions::default()
        },
    )
    .unwrap();
    // 2 references, then 12 points in chunks of 3.
    assert_eq!((written.tasks, written.references), (6, 2));
    let script = std::fs::read_to_string(dir.path().join("slurm/sweep.sbatch")).unwrap();
    assert!(
        script.contains("--task \"$SLURM_ARRAY_TASK_ID\""),
        "{script}"
    );
    assert!(script.contains("#SBATCH --cpus-per-task=1"), "{script}");
    let submit = std::fs::read_to_string(dir.path().join("slurm/submit.sh")).unwrap();
    assert!(
        submit.contains("--array=0-1") && submit.contains("--dependency=afterok:"),
        "{submit}"
    );
    assert!(submit.contains("--array=2-5"), "{submit}");
    // The tasks in reverse order: each point task runs its case's reference
    // itself when its task has not run yet.
    for k in (0..written.tasks).rev() {
        let task = slurm::manifest_task(&plan, &pts, &cluster, k).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(task, tasks(&plan, &pts, 3)[k]);
        run_task(&plan, &pts, &cluster, &task).unwrap_or_else(|e| panic!("{e}"));
    }
    assert!(slurm::manifest_task(&plan, &pts, &cluster, 6).is_err());
    let csv = |out: &Path| {
        let c = collect(&plan, points(&plan), out);
        assert!(c.missing().is_empty());
        floebench::report::sweep::sweep_csv(&c)
            .lines()
            .filter(|l| !l.contains(",cpu,"))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    let (a, b) = (csv(&local), csv(&cluster));
    assert!(a.len() > 40, "{a:?}");
    assert_eq!(a, b);
}

#[test]
fn a_manifest_of_another_plan_is_refused() {
    let dir = tempdir();
    let body = "reference = \"exact\"\n\n[[formulation]]\nname = \"moreau\"\ngrid = { step = [0.5, 0.25] }";
    let path = plan_file(dir.path(), &["head_on"], body);
    let out = dir.path().join("out");
    let plan = load(&path);
    slurm::write_slurm(
        &plan,
        &points(&plan),
        &out,
        &dir.path().join("slurm"),
        Path::new("floebench"),
        &slurm::SlurmOptions::default(),
    )
    .unwrap();
    let other = plan_file(dir.path(), &["head_on"], &body.replace("0.25", "0.125"));
    let plan = load(&other);
    let e = slurm::manifest_task(&plan, &points(&plan), &out, 0).unwrap_err();
    assert!(
        e.to_string()
            .contains("written for another version of the plan"),
        "{e}"
    );
}

/// The bad plans of `tests/cases/bad_plans/` and the line and words of their error.
const BAD_PLANS: &[(&str, Option<usize>, &str)] = &[
    ("version_2", Some(3), "version = 2 is not supported"),
    ("missing_sweep", None, "missing [sweep] table"),
    ("unknown_key", Some(4), "unknown field `case`"),
    ("no_cases", Some(4), "[sweep] cases is empty"),
    (
        "missing_case_file",
        Some(6),
        "cases/no_such_case.toml: cannot read the case file",
    ),
    (
        "unknown_reference",
        Some(5),
        "[sweep] reference: unknown formulation `rapeir`",
    ),
    (
        "reference_ignores_contacts",
        Some(5),
        "free-drift does not apply to",
    ),
    ("unknown_measure", Some(6), "unknown measure `velocity`"),
    (
        "exact_position",
        Some(6),
        "`position` needs a reference run",
    ),
    ("no_formulation", Some(2), "no [[formulation]] table"),
    (
        "unknown_formulation",
        Some(12),
        "[[formulation]] #1: name: unknown formulation `moreua`",
    ),
    (
        "unknown_grid_key",
        Some(9),
        "[formulation.moreau] unknown key `stepp`",
    ),
    (
        "negative_step",
        Some(11),
        "[formulation.moreau] step = -0.25 s must be finite and >= 1e-6 s",
    ),
    (
        "negative_distance",
        Some(9),
        "[contact] distance = -0.01 m must be finite and >= 0",
    ),
    (
        "unquoted_dotted_key",
        Some(9),
        "a dotted grid key is written in quotes",
    ),
    (
        "free_drift_table_key",
        Some(9),
        "free-drift reads no [formulation.*] table",
    ),
    (
        "repeated_value",
        Some(9),
        "grid iterations: 2 is listed twice",
    ),
    ("case_not_in_plan", Some(9), "not one of [sweep] cases"),
    (
        "free_drift_on_contacts",
        Some(9),
        "free-drift ignores contacts",
    ),
    ("bad_name", Some(4), "must be [a-z0-9_-]+"),
    (
        "bad_reference_setting",
        Some(5),
        "[formulation.event-driven] unknown key `step`",
    ),
    (
        "tolerance_without_solver",
        Some(9),
        "tolerance is a setting of the iterative solvers",
    ),
    (
        "negative_tolerance",
        Some(11),
        "tolerance = -1e-4 must be finite",
    ),
];

fn bad_plans_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cases/bad_plans")
}

#[test]
fn bad_plans_are_refused_with_one_line_errors_naming_file_line_and_key() {
    let mut listed: Vec<String> = std::fs::read_dir(bad_plans_dir())
        .unwrap()
        .map(|e| {
            e.unwrap()
                .path()
                .file_stem()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    listed.sort();
    let mut named: Vec<String> = BAD_PLANS.iter().map(|b| b.0.to_string()).collect();
    named.sort();
    assert_eq!(listed, named, "every bad plan is tested");
    for (name, line, words) in BAD_PLANS {
        let path = bad_plans_dir().join(format!("{name}.toml"));
        let e = load_plan(&path)
            .err()
            .unwrap_or_else(|| panic!("{name} loads"));
        let msg = e.to_string();
        assert!(!msg.contains('\n'), "{name}: {msg}");
        assert_eq!(e.line, *line, "{name}: {msg}");
        assert!(
            msg.starts_with(&path.display().to_string()),
            "{name}: {msg}"
        );
        assert!(msg.contains(words), "{name}: {msg}");
        // A resolved path is written without `..` (the plan's own text, in
        // quotes, is quoted as written).
        assert!(!msg.contains("bad_plans/../"), "{name}: {msg}");
    }
    // The command line says the same, and writes nothing.
    let out = tempdir();
    let o = floebench()
        .args([
            "sweep".as_ref(),
            bad_plans_dir().join("negative_step.toml").as_os_str(),
            "-o".as_ref(),
            out.path().join("o").as_os_str(),
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("error: ") && stderr.contains("negative_step.toml:11:"),
        "{stderr}"
    );
    assert!(!out.path().join("o").exists());
}

#[test]
fn a_plan_with_a_start_runs_every_point_from_that_state_for_its_duration() {
    // docs/sweep-format.md, `start`: the state of an earlier run at one of
    // its output times, as `run --from … --at` takes it.
    let tmp = tempdir();
    let dir = tmp.path();
    let scn = scenario(&case_text("head_on"));
    let r = crate::common::run(&scn, "event-driven");
    let earlier = dir.join("earlier");
    floebench::run::output::write_run(&earlier, &r).unwrap();
    let body = "start = { trajectory = \"earlier/trajectory.csv\", at = 10.0, duration = 2.5 }\nreference = \"event-driven\"\n[[formulation]]\nname = \"moreau\"\ngrid = { step = [0.5, 0.25] }\n";
    let plan = load(&plan_file(dir, &["head_on"], body));
    let at10: Vec<_> = r.trajectory.iter().filter(|row| row.t == 10.0).collect();
    assert_eq!(at10.len(), 2);
    for p in points(&plan) {
        let s = plan.scenario(p.case, p.table, &p.settings).unwrap();
        assert_eq!((s.duration, s.output_interval), (2.5, 0.5), "{}", p.id);
        for (b, row) in s.floes.iter().zip(&at10) {
            assert_eq!((b.position.x, b.position.y), (row.x, row.y), "{}", p.id);
            assert_eq!((b.velocity.x, b.velocity.y), (row.vx, row.vy), "{}", p.id);
        }
    }
    // The start is part of each point's fingerprint.
    let other = body.replace("at = 10.0", "at = 9.5");
    let plan2 = load(&plan_file(dir, &["head_on"], &other));
    assert_ne!(points(&plan)[0].fingerprint, points(&plan2)[0].fingerprint);
    // A missing state, a duration off the output grid: one-line errors at
    // the start's line.
    for (change, says) in [
        ("earlier/trajectory.csv", "missing/trajectory.csv"),
        ("duration = 2.5", "duration = 2.2"),
    ] {
        let bad = body.replace(change, says);
        let e = load_plan(&plan_file(dir, &["head_on"], &bad))
            .err()
            .unwrap_or_else(|| panic!("{says}: accepted"))
            .to_string();
        assert!(e.contains("plan.toml:5: [sweep] start"), "{e}");
    }
}

#[test]
fn the_dense_plan_loads_with_each_tolerance_beside_its_solver() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/sweeps/dense_work_precision.toml");
    let plan = load(&path);
    let pts = points(&plan);
    assert_eq!(pts.len(), 18);
    let p = pts
        .iter()
        .find(|p| p.id == "bay_jam_200__moreau__tolerance=0.0001__solver=nsgs")
        .unwrap_or_else(|| panic!("{:?}", pts.iter().map(|p| &p.id).collect::<Vec<_>>()));
    let scn = plan.scenario(p.case, p.table, &p.settings).unwrap();
    let s = floebench::formulation::moreau::MoreauSettings::of(&scn).unwrap();
    assert_eq!(s.iterative.map(|o| o.tolerance), Some(1e-4));
}

#[test]
fn the_bundled_plan_loads_and_its_points_are_named_once() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/sweeps/convergence.toml");
    let plan = load(&path);
    let pts = points(&plan);
    let mut ids: Vec<&str> = pts.iter().map(|p| p.id.as_str()).collect();
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), pts.len());
    assert_eq!(pts.len(), 96);
    // A grid value is applied where its formulation reads it.
    let p = pts
        .iter()
        .find(|p| p.id == "bouncing_floe__moreau__step=0.25")
        .unwrap();
    let scn = plan.scenario(p.case, p.table, &p.settings).unwrap();
    let s = floebench::formulation::moreau::MoreauSettings::of(&scn).unwrap();
    assert_eq!(s.step, 0.25);
    let p = pts
        .iter()
        .find(|p| {
            p.id == "head_on__event-driven__contact.distance=0.005__integrator.tolerance=1e-8"
        })
        .unwrap();
    let scn = plan.scenario(p.case, p.table, &p.settings).unwrap();
    assert_eq!(
        (scn.contact.distance, scn.integrator.tolerance),
        (0.005, 1e-8)
    );
    // Inline plans take cases relative to the plan's folder.
    let inline = parse_plan(
        "[sweep]\nversion = 1\ncases = [\"../bouncing_floe.toml\"]\nreference = \"exact\"\n[[formulation]]\nname = \"rapier\"\n",
        &path,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        inline.cases[0].path,
        Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/bouncing_floe.toml")
    );
    assert_eq!(inline.name, "convergence");
}
