//! Captures the git commit the harness is built from (`OPENGRASP_GIT_COMMIT`), so results
//! record the code that produced them, not whatever checkout the command runs in.

use std::path::Path;
use std::process::Command;

fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git").arg("-C").arg(dir).args(args).output().ok()?;
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (out.status.success() && !s.is_empty()).then_some(s)
}

fn main() {
    println!("cargo:rerun-if-env-changed=OPENGRASP_GIT_COMMIT");
    if let Ok(commit) = std::env::var("OPENGRASP_GIT_COMMIT") {
        println!("cargo:rustc-env=OPENGRASP_GIT_COMMIT={commit}");
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let Some(commit) = git(dir, &["rev-parse", "HEAD"]) else { return };
    // Rebuild when HEAD moves: HEAD itself, the branch it names, and packed refs.
    // `--git-path` also finds them in a linked worktree.
    let mut watched = vec!["HEAD".to_string(), "packed-refs".to_string()];
    watched.extend(git(dir, &["symbolic-ref", "-q", "HEAD"]));
    for name in watched {
        if let Some(path) = git(dir, &["rev-parse", "--git-path", &name]) {
            println!("cargo:rerun-if-changed={}", dir.join(path).display());
        }
    }
    println!("cargo:rustc-env=OPENGRASP_GIT_COMMIT={commit}");
}
