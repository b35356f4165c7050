//! The tasks of a cluster job against the local run, and a manifest of
//! another plan refused.

use super::{load, plan_file, sweep};
use crate::common::tempdir;
use floebench::sweep::execute::run_task;
use floebench::sweep::points::{points, tasks};
use floebench::sweep::{collect, slurm};
use std::path::Path;

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
