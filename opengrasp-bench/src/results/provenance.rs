//! Provenance: where, when and with what results were produced.

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;
use std::time::{SystemTime, UNIX_EPOCH};

use serde::{Deserialize, Serialize};

use super::SUITE_VERSION;

/// The git commit this crate was built from (set by its build script from `git rev-parse
/// HEAD`, or from the `OPENGRASP_GIT_COMMIT` variable at build time); `None` outside a checkout.
pub const BUILD_GIT_COMMIT: Option<&str> = option_env!("OPENGRASP_GIT_COMMIT");

/// Where, when and with what the results were produced.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// [`SUITE_VERSION`] of the suite that ran.
    pub suite_version: String,
    /// Suite size that ran (`"default"`, `"paper"`, `"tiny"` or `"custom"`).
    pub suite_size: String,
    /// Version of the benchmark harness (`opengrasp-bench`, which the `opengrasp` command runs).
    pub opengrasp_version: String,
    /// Versions of the member crates (`opengrasp-bench`, `-core`, `-grasp`, `-motion`, `-assets`),
    /// each as the crate reports it (`VERSION`).
    pub crate_versions: BTreeMap<String, String>,
    /// Git commit the harness was built from, captured at build time ([`BUILD_GIT_COMMIT`]);
    /// `None` for a build outside a git checkout.
    pub git_commit: Option<String>,
    /// CPU model (`model name` of `/proc/cpuinfo`), if known.
    pub cpu_model: Option<String>,
    /// Logical CPU cores available.
    pub cpu_cores: usize,
    /// Operating system (`std::env::consts::OS`).
    pub os: String,
    /// CPU architecture (`std::env::consts::ARCH`).
    pub arch: String,
    /// Start of the run, UTC ISO-8601 (`2026-11-23T01:40:00Z`).
    pub started_at: String,
    /// End of the run, UTC ISO-8601.
    pub finished_at: String,
    /// Wall time of the whole run (s).
    pub wall_seconds: f64,
    /// Worker threads used.
    pub jobs: usize,
    /// The slice of the suite this file holds, for one shard of a sharded run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<Shard>,
    /// For a merged file: the provenance of every shard, in shard order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub merged_from: Vec<Provenance>,
}

/// One slice of a suite split across machines: shard `index` of `count` (0-based) runs the
/// suite's jobs `index, index + count, index + 2·count, ...` in job order — a grasp job is a
/// hand × object cell, a motion job a scene × planner pair (or one run of it when its
/// environment changes per run) or a Clean the Table episode — with exactly the seeds an
/// unsharded run gives them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// This shard, `0..count`.
    pub index: usize,
    /// Number of shards (at least 1).
    pub count: usize,
}

impl Shard {
    /// Parses `"K/N"` (0-based `K < N`), as given to `opengrasp run --shard`.
    ///
    /// # Errors
    /// [`crate::Error::InvalidOption`] naming what is wrong.
    pub fn parse(text: &str) -> crate::Result<Self> {
        let bad = |reason: String| crate::Error::InvalidOption { name: "shard", reason };
        let (k, n) = text.split_once('/').ok_or_else(|| bad(format!("{text:?}: expected K/N, e.g. 0/4")))?;
        let parse = |v: &str| v.trim().parse::<usize>().map_err(|e| bad(format!("{text:?}: {e}")));
        Self::new(parse(k)?, parse(n)?)
    }

    /// Shard `index` of `count`.
    ///
    /// # Errors
    /// [`crate::Error::InvalidOption`] unless `index < count`.
    pub fn new(index: usize, count: usize) -> crate::Result<Self> {
        if index >= count {
            return Err(crate::Error::InvalidOption {
                name: "shard",
                reason: format!("shard {index}/{count}: the index must be below the count (0-based)"),
            });
        }
        Ok(Self { index, count })
    }

    /// True if job `job` (in job order) belongs to this shard.
    pub fn owns(&self, job: usize) -> bool {
        job % self.count == self.index
    }
}

impl Provenance {
    /// Collects the provenance of this process and machine now (`finished_at` = `started_at`,
    /// `wall_seconds` = 0 until [`Provenance::finish`]).
    pub fn collect(suite_size: &str, jobs: usize) -> Self {
        let now = utc_now_iso8601();
        let crate_versions = [
            ("opengrasp-bench", crate::VERSION),
            ("opengrasp-core", opengrasp_core::VERSION),
            ("opengrasp-grasp", opengrasp_grasp::VERSION),
            ("opengrasp-motion", opengrasp_motion::VERSION),
            ("opengrasp-assets", opengrasp_assets::VERSION),
        ]
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
        Self {
            suite_version: SUITE_VERSION.to_string(),
            suite_size: suite_size.to_string(),
            opengrasp_version: crate::VERSION.to_string(),
            crate_versions,
            git_commit: BUILD_GIT_COMMIT.map(str::to_string),
            cpu_model: cpu_model(),
            cpu_cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            os: std::env::consts::OS.to_string(),
            arch: std::env::consts::ARCH.to_string(),
            started_at: now.clone(),
            finished_at: now,
            wall_seconds: 0.0,
            jobs,
            shard: None,
            merged_from: Vec::new(),
        }
    }

    /// Stamps the end of the run.
    pub fn finish(&mut self, wall_seconds: f64) {
        self.finished_at = utc_now_iso8601();
        self.wall_seconds = wall_seconds;
    }
}

/// The git commit of the repository containing `dir` (searching upwards): `.git/HEAD` and
/// the ref it names (loose or in `packed-refs`), else `git rev-parse HEAD`; `None` if neither
/// works.
pub fn git_commit(dir: &Path) -> Option<String> {
    let is_hash = |s: &str| s.len() >= 40 && s.chars().all(|c| c.is_ascii_hexdigit());
    for d in dir.ancestors() {
        let git = d.join(".git");
        if !git.exists() {
            continue;
        }
        if !git.is_dir() {
            // A worktree or submodule (`.git` file): ask git itself.
            break;
        }
        if let Ok(head) = fs::read_to_string(git.join("HEAD")) {
            let head = head.trim();
            if let Some(reference) = head.strip_prefix("ref:") {
                let reference = reference.trim();
                if let Ok(h) = fs::read_to_string(git.join(reference)) {
                    if is_hash(h.trim()) {
                        return Some(h.trim().to_string());
                    }
                }
                if let Ok(packed) = fs::read_to_string(git.join("packed-refs")) {
                    for line in packed.lines() {
                        if let Some((h, r)) = line.split_once(' ') {
                            if r.trim() == reference && is_hash(h) {
                                return Some(h.to_string());
                            }
                        }
                    }
                }
            } else if is_hash(head) {
                return Some(head.to_string());
            }
        }
        break;
    }
    let out = std::process::Command::new("git").arg("-C").arg(dir).args(["rev-parse", "HEAD"]).output().ok()?;
    let h = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (out.status.success() && is_hash(&h)).then_some(h)
}

/// The CPU model (`model name` in `/proc/cpuinfo`), if available.
pub fn cpu_model() -> Option<String> {
    let text = fs::read_to_string("/proc/cpuinfo").ok()?;
    text.lines()
        .filter_map(|l| l.split_once(':'))
        .find(|(k, _)| k.trim() == "model name")
        .map(|(_, v)| v.trim().to_string())
        .filter(|v| !v.is_empty())
}

/// The current UTC time as ISO-8601 with second resolution (`2026-11-23T01:40:00Z`).
pub fn utc_now_iso8601() -> String {
    let secs = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
    iso8601_from_unix(secs as i64)
}

/// Formats seconds since the Unix epoch as UTC ISO-8601 (`1970-01-01T00:00:00Z`).
pub fn iso8601_from_unix(secs: i64) -> String {
    let days = secs.div_euclid(86_400);
    let rem = secs.rem_euclid(86_400);
    let (y, m, d) = civil_from_days(days);
    format!("{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z", rem / 3600, rem % 3600 / 60, rem % 60)
}

/// Proleptic Gregorian date `(year, month, day)` of a day count since 1970-01-01
/// (H. Hinnant's `civil_from_days`).
pub fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097); // [0, 146096]
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365; // [0, 399]
    let y = yoe + era * 400;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100); // [0, 365]
    let mp = (5 * doy + 2) / 153; // [0, 11]
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32; // [1, 31]
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32; // [1, 12]
    (if m <= 2 { y + 1 } else { y }, m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn civil_dates_match_known_days() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
        assert_eq!(civil_from_days(59), (1970, 3, 1));
        // 2000-02-29 is day 11016; 2024-02-29 is day 19782.
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(19_782), (2024, 2, 29));
        assert_eq!(iso8601_from_unix(1_700_000_000), "2023-11-14T22:13:20Z");
    }
}
