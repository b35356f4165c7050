//! Build script: the git commit the binary is built from, for the report
//! pages (`FLOEBENCH_COMMIT`: the abbreviated commit, `+modified` when the
//! sources differ from it, `unknown` without git or outside a repository).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The trimmed standard output of `git args`, if git ran and succeeded.
fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn main() {
    let commit = match git(&["rev-parse", "--short=12", "HEAD"]) {
        Some(c) if !c.is_empty() => {
            let changed = git(&[
                "status",
                "--porcelain",
                "--untracked-files=no",
                "--",
                "src",
                "build.rs",
                "Cargo.toml",
                "Cargo.lock",
            ])
            .is_some_and(|s| !s.is_empty());
            if changed {
                format!("{c}+modified")
            } else {
                c
            }
        }
        _ => "unknown".to_string(),
    };
    println!("cargo:rustc-env=FLOEBENCH_COMMIT={commit}");
    // Again when the commit moves or a source changes. The commit: HEAD,
    // packed-refs and the branch's ref, each only if it exists (cargo reruns
    // a build script on every build while a path it watches is missing); for
    // a branch whose ref is only packed, the folder a commit writes it into.
    // Not the index: `git status` rewrites it, and staging changes no source.
    let git_path = |p: &str| git(&["rev-parse", "--git-path", p]);
    let mut watched: Vec<PathBuf> = ["HEAD", "packed-refs"]
        .iter()
        .filter_map(|p| git_path(p))
        .map(PathBuf::from)
        .filter(|p| p.exists())
        .collect();
    if let Some(r) = git(&["symbolic-ref", "-q", "HEAD"]).and_then(|r| git_path(&r)) {
        let r = PathBuf::from(r);
        watched.extend(r.ancestors().find(|p| p.exists()).map(Path::to_path_buf));
    }
    for p in watched {
        println!("cargo:rerun-if-changed={}", p.display());
    }
    for p in ["src", "build.rs", "Cargo.toml", "Cargo.lock"] {
        println!("cargo:rerun-if-changed={p}");
    }
}
