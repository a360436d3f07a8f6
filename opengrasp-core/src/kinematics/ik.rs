//! Inverse kinematics by damped least squares (Levenberg-Marquardt) with random restarts.
//!
//! [`solve_ik`] moves the joints of a [`JointGroup`] so that a frame on a tip link reaches a
//! target pose in the robot's root frame. Each iteration solves
//! `Δq = Jᵀ (J Jᵀ + λ I)⁻¹ e` for the pose error `e = [p* − p; log(R* Rᵀ)]` (only the position
//! rows in position-only mode), clamps `q + Δq` into the joint limits (continuous joints are
//! unbounded) and accepts the step only if it lowers `|e|²`.
//!
//! The damping `λ` is adaptive: it starts at [`IkOptions::damping`], is divided by 10 after an
//! accepted step (never below 1e-9, so convergence near the solution is Gauss-Newton fast) and
//! multiplied by 10 after a rejected one (so steps shrink towards gradient descent near
//! singularities). An attempt ends when the tolerances are met, after
//! [`IkOptions::max_iterations`], or when it stalls (typically pinned against a joint limit or
//! in a local minimum): `λ` exceeds 1e6, or `|e|²` falls by less than half over 10 iterations
//! while still above 1e-6 (errors of about 1 mm / 1 mrad). The solver then restarts from a
//! configuration sampled uniformly within the group's limits (seeded by [`IkOptions::seed`]), up to
//! [`IkOptions::max_restarts`] times, and returns the best configuration found.

use nalgebra::{Cholesky, Isometry3, Matrix3, Matrix6, Matrix6xX, Vector3, Vector6};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::jacobian::{check_dofs, check_link, frame_jacobian_into};
use crate::error::{ensure_finite, CoreError, Result};
use crate::model::{JointGroup, LinkId, Robot};

/// Smallest damping the adaptive schedule reaches.
const MIN_DAMPING: f64 = 1e-9;
/// Damping above which an attempt counts as stalled.
const MAX_DAMPING: f64 = 1e6;
/// An attempt stalls if `|e|²` falls by less than this factor over `STALL_WINDOW` iterations.
const STALL_RATIO: f64 = 0.5;
/// Below this `|e|²` (errors of about 1 mm / 1 mrad) an attempt is never declared stalled:
/// convergence towards a singular solution is slow but sure.
const NEAR_COST: f64 = 1e-6;
/// Iterations over which progress is measured.
const STALL_WINDOW: usize = 10;
/// Distance to a limit below which a joint counts as pinned for [`IkStatus::AtJointLimits`].
const LIMIT_EPS: f64 = 1e-9;

/// Options of [`solve_ik`].
#[derive(Clone, Debug, PartialEq)]
pub struct IkOptions {
    /// Position tolerance on the tip frame origin, in metres (default 1e-6).
    pub position_tolerance: f64,
    /// Orientation tolerance (rotation angle between tip frame and target), in radians
    /// (default 1e-6). Ignored when [`IkOptions::position_only`] is set.
    pub orientation_tolerance: f64,
    /// Maximum iterations per attempt (the start plus each restart), at least 1 (default 100).
    pub max_iterations: usize,
    /// Maximum random restarts after the attempt from `q_start` fails (default 50).
    pub max_restarts: usize,
    /// Initial damping `λ` of the adaptive Levenberg-Marquardt schedule, finite and positive
    /// (default 1e-3).
    pub damping: f64,
    /// Seed of the ChaCha8 generator that samples restart configurations (default 0).
    pub seed: u64,
    /// Reach the target position only, with any orientation (default false).
    pub position_only: bool,
    /// The frame on the tip link that must reach the target, in the tip link frame
    /// (default identity: the tip link frame itself).
    pub tip_offset: Isometry3<f64>,
}

impl Default for IkOptions {
    fn default() -> Self {
        Self {
            position_tolerance: 1e-6,
            orientation_tolerance: 1e-6,
            max_iterations: 100,
            max_restarts: 50,
            damping: 1e-3,
            seed: 0,
            position_only: false,
            tip_offset: Isometry3::identity(),
        }
    }
}

impl IkOptions {
    /// Checks that every option is in range.
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] naming the first offending option, or
    /// [`CoreError::NonFinite`] for a non-finite `tip_offset`.
    pub fn validate(&self) -> Result<()> {
        let positive = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(CoreError::InvalidParameter {
                    name: name.into(),
                    reason: format!("must be finite and > 0, got {v}"),
                })
            }
        };
        positive("position_tolerance", self.position_tolerance)?;
        positive("orientation_tolerance", self.orientation_tolerance)?;
        positive("damping", self.damping)?;
        if self.max_iterations == 0 {
            return Err(CoreError::InvalidParameter {
                name: "max_iterations".into(),
                reason: "must be at least 1".into(),
            });
        }
        ensure_finite("tip_offset", isometry_values(&self.tip_offset))
    }
}

/// Outcome of an IK solve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IkStatus {
    /// The tolerances are met.
    Converged,
    /// No attempt met the tolerances; the best configuration found is returned.
    Unreachable,
    /// No attempt met the tolerances and the best configuration has a joint pinned at a limit.
    AtJointLimits,
}

/// Result of [`solve_ik`].
#[derive(Clone, Debug, PartialEq)]
pub struct IkSolution {
    /// Whether the target was reached.
    pub status: IkStatus,
    /// The full configuration ([`Robot::dof`] values): group joints solved, every other joint
    /// as in `q_start`.
    pub q: Vec<f64>,
    /// Distance from the tip frame origin to the target position, in metres.
    pub position_error: f64,
    /// Rotation angle between the tip frame and the target orientation, in radians (reported
    /// but not minimised in position-only mode).
    pub orientation_error: f64,
    /// Iterations performed over all attempts.
    pub iterations: usize,
    /// Random restarts performed (0 when the attempt from `q_start` succeeded).
    pub restarts: usize,
}

/// Moves the joints of `group` so that `options.tip_offset` on link `tip` reaches `target`
/// (a pose in the robot's root frame), starting from the full configuration `q_start`.
///
/// Failing to converge is not an error: the best configuration found is returned with status
/// [`IkStatus::Unreachable`] or [`IkStatus::AtJointLimits`]. The result is deterministic for
/// given inputs and [`IkOptions::seed`]. See the module docs for the algorithm.
///
/// # Errors
/// [`CoreError::NonFinite`] for a non-finite `target`; [`CoreError::DimensionMismatch`],
/// [`CoreError::NonFiniteJointValue`] or [`CoreError::JointOutOfLimits`] for a bad `q_start`;
/// [`CoreError::InvalidParameter`] for options out of range (see [`IkOptions::validate`]), a
/// `tip` that is not a link of `robot` or a group with indices beyond [`Robot::dof`].
pub fn solve_ik(
    robot: &Robot,
    group: &JointGroup,
    tip: LinkId,
    target: &Isometry3<f64>,
    q_start: &[f64],
    options: &IkOptions,
) -> Result<IkSolution> {
    ensure_finite("target", isometry_values(target))?;
    robot.validate_configuration(q_start)?;
    options.validate()?;
    check_link(robot, tip)?;
    check_dofs(robot, group.dofs())?;

    let dofs = group.dofs();
    let limits = group.limits(robot);
    let mut ws = Workspace {
        robot,
        tip,
        target,
        options,
        dofs,
        limits: &limits,
        q: q_start.to_vec(),
        cand: q_start.to_vec(),
        jac: Matrix6xX::zeros(dofs.len()),
        jac_cand: Matrix6xX::zeros(dofs.len()),
        dq: vec![0.0; dofs.len()],
        iterations: 0,
    };
    let mut best_q = q_start.to_vec();
    let mut best = Attempt { cost: f64::INFINITY, position_error: f64::INFINITY, orientation_error: f64::INFINITY };
    let mut rng: Option<ChaCha8Rng> = None;

    for attempt in 0..=options.max_restarts {
        if attempt > 0 {
            let rng = rng.get_or_insert_with(|| ChaCha8Rng::seed_from_u64(options.seed));
            for (&d, &(lo, hi)) in dofs.iter().zip(&limits) {
                let (lo, hi) = if lo.is_finite() && hi.is_finite() {
                    (lo, hi)
                } else {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                };
                ws.q[d] = lo + (hi - lo) * rng.random::<f64>();
            }
        }
        let (result, converged) = ws.run();
        if result.cost < best.cost {
            best = result;
            best_q.copy_from_slice(&ws.q);
        }
        if converged {
            return Ok(IkSolution {
                status: IkStatus::Converged,
                q: best_q,
                position_error: best.position_error,
                orientation_error: best.orientation_error,
                iterations: ws.iterations,
                restarts: attempt,
            });
        }
    }

    let pinned =
        dofs.iter().zip(&limits).any(|(&d, &(lo, hi))| best_q[d] - lo <= LIMIT_EPS || hi - best_q[d] <= LIMIT_EPS);
    Ok(IkSolution {
        status: if pinned { IkStatus::AtJointLimits } else { IkStatus::Unreachable },
        q: best_q,
        position_error: best.position_error,
        orientation_error: best.orientation_error,
        iterations: ws.iterations,
        restarts: options.max_restarts,
    })
}

/// The 12 numbers of an isometry (quaternion and translation).
fn isometry_values(iso: &Isometry3<f64>) -> impl Iterator<Item = f64> + '_ {
    iso.rotation.coords.iter().chain(iso.translation.vector.iter()).copied()
}

/// Errors of one configuration.
#[derive(Clone, Copy, Debug)]
struct Attempt {
    /// The minimised objective `|e|²`.
    cost: f64,
    position_error: f64,
    orientation_error: f64,
}

/// Buffers and inputs of one solve, so the iteration loop does not allocate.
struct Workspace<'a> {
    robot: &'a Robot,
    tip: LinkId,
    target: &'a Isometry3<f64>,
    options: &'a IkOptions,
    dofs: &'a [usize],
    limits: &'a [(f64, f64)],
    /// Current full configuration (the attempt's start on entry to [`Workspace::run`]).
    q: Vec<f64>,
    /// Candidate full configuration.
    cand: Vec<f64>,
    jac: Matrix6xX<f64>,
    jac_cand: Matrix6xX<f64>,
    dq: Vec<f64>,
    iterations: usize,
}

impl Workspace<'_> {
    /// Pose error of `cand`/`q` as `[p* − p; log(R* Rᵀ)]`, with the attempt summary.
    fn error(&self, pose: &Isometry3<f64>) -> (Vector6<f64>, Attempt) {
        let ep = self.target.translation.vector - pose.translation.vector;
        let eo = (self.target.rotation * pose.rotation.inverse()).scaled_axis();
        let cost = if self.options.position_only { ep.norm_squared() } else { ep.norm_squared() + eo.norm_squared() };
        let e = Vector6::new(ep.x, ep.y, ep.z, eo.x, eo.y, eo.z);
        (e, Attempt { cost, position_error: ep.norm(), orientation_error: eo.norm() })
    }

    fn converged(&self, a: &Attempt) -> bool {
        a.position_error <= self.options.position_tolerance
            && (self.options.position_only || a.orientation_error <= self.options.orientation_tolerance)
    }

    /// One damped least-squares descent from `self.q`; leaves the attempt's best configuration
    /// in `self.q` and returns its errors and whether it converged.
    fn run(&mut self) -> (Attempt, bool) {
        let pose = frame_jacobian_into(
            self.robot,
            &self.q,
            self.tip,
            &self.options.tip_offset,
            self.dofs,
            Some(&mut self.jac),
        );
        let (mut e, mut current) = self.error(&pose);
        let mut lambda = self.options.damping;
        let mut window_cost = current.cost;
        for it in 0..self.options.max_iterations {
            if self.converged(&current) {
                return (current, true);
            }
            if it > 0 && it % STALL_WINDOW == 0 {
                if current.cost > STALL_RATIO * window_cost && current.cost > NEAR_COST {
                    break;
                }
                window_cost = current.cost;
            }
            self.iterations += 1;
            if self.step(&e, lambda) {
                self.cand.copy_from_slice(&self.q);
                for ((&d, &(lo, hi)), &dq) in self.dofs.iter().zip(self.limits).zip(&self.dq) {
                    self.cand[d] = (self.cand[d] + dq).clamp(lo, hi);
                }
                let pose = frame_jacobian_into(
                    self.robot,
                    &self.cand,
                    self.tip,
                    &self.options.tip_offset,
                    self.dofs,
                    Some(&mut self.jac_cand),
                );
                let (e_cand, cand) = self.error(&pose);
                if cand.cost < current.cost {
                    std::mem::swap(&mut self.q, &mut self.cand);
                    std::mem::swap(&mut self.jac, &mut self.jac_cand);
                    e = e_cand;
                    current = cand;
                    lambda = (lambda * 0.1).max(MIN_DAMPING);
                    continue;
                }
            }
            lambda *= 10.0;
            if lambda > MAX_DAMPING {
                break;
            }
        }
        let ok = self.converged(&current);
        (current, ok)
    }

    /// Writes the damped least-squares step `Jᵀ (J Jᵀ + λ I)⁻¹ e` into `self.dq`; false if the
    /// system could not be factored.
    fn step(&mut self, e: &Vector6<f64>, lambda: f64) -> bool {
        let j = &self.jac;
        if self.options.position_only {
            let mut a = Matrix3::identity() * lambda;
            for c in j.column_iter() {
                let v = Vector3::new(c[0], c[1], c[2]);
                a += v * v.transpose();
            }
            let Some(ch) = Cholesky::new(a) else { return false };
            let y = ch.solve(&Vector3::new(e[0], e[1], e[2]));
            for (dq, c) in self.dq.iter_mut().zip(j.column_iter()) {
                *dq = c[0] * y[0] + c[1] * y[1] + c[2] * y[2];
            }
        } else {
            let mut a = Matrix6::identity() * lambda;
            for c in j.column_iter() {
                a.ger(1.0, &c, &c, 1.0);
            }
            let Some(ch) = Cholesky::new(a) else { return false };
            let y = ch.solve(e);
            for (dq, c) in self.dq.iter_mut().zip(j.column_iter()) {
                *dq = c.dot(&y);
            }
        }
        self.dq.iter().all(|v| v.is_finite())
    }
}
