//! Path metrics (length, end-effector length, clearance, smoothness) and robust aggregates.

use opengrasp_core::kinematics::link_pose_unchecked;
use opengrasp_core::model::{JointGroup, LinkId, Robot};
use serde::{Deserialize, Serialize};

use crate::validate::{distance, interpolate_into, path_length};
use crate::validity::StateValidityChecker;

/// Smoothness as defined by OMPL (`PathGeometric::smoothness`): for every three consecutive
/// waypoints with sides `a = |s₀s₁|`, `b = |s₁s₂|`, `c = |s₀s₂|`, the turning angle
/// `θ = π − acos((a² + b² − c²) / 2ab)` gives a curvature `k = 2θ / (a + b)`; the smoothness
/// is `Σ k²` (0 for straight paths, lower is smoother).
pub fn smoothness(path: &[Vec<f64>]) -> f64 {
    let mut s = 0.0;
    if path.len() > 2 {
        let mut a = distance(&path[0], &path[1]);
        for i in 2..path.len() {
            let b = distance(&path[i - 1], &path[i]);
            let c = distance(&path[i - 2], &path[i]);
            let cos = (a * a + b * b - c * c) / (2.0 * a * b);
            if cos > -1.0 && cos < 1.0 {
                let angle = std::f64::consts::PI - cos.acos();
                let k = 2.0 * angle / (a + b);
                s += k * k;
            }
            a = b;
        }
    }
    s
}

/// States along a path at most `step` apart (waypoints included).
pub fn densify(path: &[Vec<f64>], step: f64) -> Vec<Vec<f64>> {
    let mut out = Vec::new();
    if let Some(first) = path.first() {
        out.push(first.clone());
    }
    let mut q = Vec::new();
    for w in path.windows(2) {
        let n = ((distance(&w[0], &w[1]) / step).ceil() as usize).max(1);
        for i in 1..=n {
            interpolate_into(&w[0], &w[1], i as f64 / n as f64, &mut q);
            out.push(q.clone());
        }
    }
    out
}

/// Metrics of one path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PathMetrics {
    /// Number of waypoints.
    pub waypoints: usize,
    /// Length in C-space (Euclidean, rad / m).
    pub length: f64,
    /// Length of the end-effector's (tip link origin's) motion in the workspace (m), over the
    /// densified path.
    pub ee_length: Option<f64>,
    /// Mean distance to obstacles over the densified path (m).
    pub clearance_mean: Option<f64>,
    /// Minimum distance to obstacles over the densified path (m).
    pub clearance_min: Option<f64>,
    /// OMPL smoothness of the waypoints (see [`smoothness`]).
    pub smoothness: f64,
}

/// Computes [`PathMetrics`]: the path is densified at `step` for the workspace length and the
/// clearance; `tip` (if given) is the end-effector link.
pub fn path_metrics(
    robot: &Robot,
    group: &JointGroup,
    q_full: &[f64],
    tip: Option<LinkId>,
    checker: &dyn StateValidityChecker,
    path: &[Vec<f64>],
    step: f64,
) -> PathMetrics {
    let dense = densify(path, step);
    let ee_length = tip.map(|tip| {
        let mut full = q_full.to_vec();
        let mut prev: Option<nalgebra::Vector3<f64>> = None;
        let mut len = 0.0;
        for q in &dense {
            for (&d, &v) in group.dofs().iter().zip(q) {
                full[d] = v;
            }
            let p = link_pose_unchecked(robot, &full, tip).translation.vector;
            if let Some(pp) = prev {
                len += (p - pp).norm();
            }
            prev = Some(p);
        }
        len
    });
    let clearances: Option<Vec<f64>> = dense.iter().map(|q| checker.clearance(q)).collect();
    let (clearance_mean, clearance_min) = match clearances {
        Some(c) if !c.is_empty() => {
            (Some(c.iter().sum::<f64>() / c.len() as f64), Some(c.iter().copied().fold(f64::INFINITY, f64::min)))
        }
        _ => (None, None),
    };
    PathMetrics {
        waypoints: path.len(),
        length: path_length(path),
        ee_length,
        clearance_mean,
        clearance_min,
        smoothness: smoothness(path),
    }
}

/// Percentile `p` (0–100) of `values` by linear interpolation between closest ranks (the
/// "type 7" definition of R and NumPy's default). `None` for empty input; NaNs are ignored.
pub fn percentile(values: &[f64], p: f64) -> Option<f64> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
    if v.is_empty() || !(0.0..=100.0).contains(&p) {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let h = (v.len() - 1) as f64 * p / 100.0;
    let lo = h.floor() as usize;
    let hi = h.ceil() as usize;
    Some(v[lo] + (h - lo as f64) * (v[hi] - v[lo]))
}

/// Robust summary of one quantity over runs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    /// Runs with a value.
    pub count: usize,
    /// Runs without a value (failed run, unsupported metric).
    pub missing: usize,
    /// Mean.
    pub mean: Option<f64>,
    /// Minimum.
    pub min: Option<f64>,
    /// 25th percentile.
    pub p25: Option<f64>,
    /// Median.
    pub p50: Option<f64>,
    /// 75th percentile.
    pub p75: Option<f64>,
    /// 95th percentile.
    pub p95: Option<f64>,
    /// Maximum.
    pub max: Option<f64>,
}

impl Stats {
    /// Summary of optional values (`None` counts as missing).
    pub fn from_options(values: impl IntoIterator<Item = Option<f64>>) -> Self {
        let mut present = Vec::new();
        let mut missing = 0;
        for v in values {
            match v {
                Some(x) if x.is_finite() => present.push(x),
                _ => missing += 1,
            }
        }
        let n = present.len();
        Self {
            count: n,
            missing,
            mean: (n > 0).then(|| present.iter().sum::<f64>() / n as f64),
            min: present.iter().copied().reduce(f64::min),
            p25: percentile(&present, 25.0),
            p50: percentile(&present, 50.0),
            p75: percentile(&present, 75.0),
            p95: percentile(&present, 95.0),
            max: present.iter().copied().reduce(f64::max),
        }
    }
}
