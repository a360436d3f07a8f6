//! The quasi-static, torque-limited hold test: can the closed hand's actuators balance the
//! object's weight through its contacts?
//!
//! Standard grasp analysis (rigid bodies, Coulomb friction, no dynamics): for each gravity
//! direction `d` the test solves the second-order cone program
//!
//! ```text
//! maximise   s
//! subject to Σ_c f_c + s·m g d = 0,   Σ_c (p_c − c) × f_c = 0      (object equilibrium)
//!            ‖f_c − (f_c·n_c) n_c‖ ≤ μ (f_c·n_c)                    (exact friction cones)
//!            |Σ_c J_{c,k}ᵀ f_c| ≤ τ_k  for every actuator k         (effort limits)
//!            0 ≤ s ≤ max_load_factor
//! ```
//!
//! where `f_c` is the force contact `c` applies to the object at `p_c` (inward normal `n_c`),
//! `c` the centre of mass and `J_{c,k}` the linear velocity of the contact point per unit
//! motion of actuator `k` (one actuator per configuration dof; coupled joints add their
//! mimic multiplier × their column, so an actuator's torque is shared by virtual work, the
//! rigid-coupling statics). Palm contacts have zero Jacobian: the arm holds the palm. The
//! optimum `s*` is the largest multiple of the weight the grasp can balance in that direction:
//! `s* ≥ 1` means some set of contact forces inside the friction cones, with every actuator
//! within its effort limit, holds the object. It is a necessary condition for a real hand
//! (rigid or not) to hold it statically; it is not sufficient for a simulator or a compliant
//! hand, whose contact forces follow from stiffness rather than from this choice.

use nalgebra::{Isometry3, Matrix3, Point3, Vector3};
use opengrasp_core::hand::Hand;
use opengrasp_core::kinematics::{forward_kinematics, jacobian};
use opengrasp_core::model::LinkId;
use opengrasp_core::object::ObjectModel;
use serde::{Deserialize, Serialize};

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};

use super::{EvaluationStatus, GraspEvaluation};
use crate::error::{GraspError, Result};

/// Options of the static hold test ([`static_hold`]).
#[derive(Clone, Debug, PartialEq)]
pub struct StaticHoldOptions {
    /// Gravity directions (object frame), each tested on its own. Default: ±x, ±y, ±z (the
    /// physics check's).
    pub directions: Vec<Vector3<f64>>,
    /// Magnitude of gravity (m/s²). Default: 9.81.
    pub gravity: f64,
    /// Coulomb friction coefficient of the contacts; `None`: the object's (as the physics
    /// check uses). Default: `None`.
    pub friction: Option<f64>,
    /// Cap on the load factor: a direction the palm supports needs no actuator torque and would
    /// be unbounded. Default: 100.
    pub max_load_factor: f64,
    /// An actuator counts as saturated at the optimum if its torque is within this fraction of
    /// its limit. Default: 0.01.
    pub saturation_tolerance: f64,
}

impl Default for StaticHoldOptions {
    fn default() -> Self {
        Self {
            directions: super::physics_options::axis_directions(),
            gravity: 9.81,
            friction: None,
            max_load_factor: 100.0,
            saturation_tolerance: 0.01,
        }
    }
}

/// Torque of one actuator at the optimum of one direction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ActuatorLoad {
    /// Configuration dof (actuator) index.
    pub dof: usize,
    /// Torque (N·m, or N for a prismatic actuator) the actuator supplies.
    pub torque: f64,
    /// Its effort limit.
    pub limit: f64,
}

/// The static test's answer for one gravity direction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StaticDirection {
    /// Unit gravity direction (object frame).
    pub direction: Vector3<f64>,
    /// Largest multiple of the object's weight the grasp balances in this direction (capped
    /// at [`StaticHoldOptions::max_load_factor`]); ≥ 1 means it holds.
    pub load_factor: f64,
    /// Forces (N, object frame) the contacts apply at the optimum, in the order of the
    /// evaluation's contacts.
    pub contact_forces: Vec<Vector3<f64>>,
    /// Torque of every actuator with an effort limit at the optimum.
    pub actuators: Vec<ActuatorLoad>,
    /// Actuators at their effort limit at the optimum (those that limit the load; empty if
    /// friction or the cap limits it).
    pub saturated: Vec<usize>,
}

/// Result of [`static_hold`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StaticHoldOutcome {
    /// One entry per direction of [`StaticHoldOptions::directions`].
    pub directions: Vec<StaticDirection>,
}

impl StaticHoldOutcome {
    /// True if the grasp balances the weight in every direction (load factor ≥ 1).
    pub fn holdable(&self) -> bool {
        !self.directions.is_empty() && self.directions.iter().all(|d| d.load_factor >= 1.0)
    }

    /// The direction with the smallest load factor (`None` without directions).
    pub fn weakest(&self) -> Option<&StaticDirection> {
        self.directions.iter().min_by(|a, b| a.load_factor.total_cmp(&b.load_factor))
    }
}

/// One contact prepared for the program: its local frame (columns `n, t₁, t₂`, object frame),
/// lever about the centre of mass, and actuator torque per unit local force component.
struct Prepared {
    frame: Matrix3<f64>,
    lever: Vector3<f64>,
    /// `torque[k][i]`: torque on actuator `k` per newton of local component `i`.
    torque: Vec<[f64; 3]>,
}

/// Tests whether the closed grasp `evaluation` of `object` by `hand` can hold the object's
/// weight statically with the hand's effort limits (see the module docs for the program).
///
/// # Errors
/// [`GraspError::InvalidParameter`] for bad options, an evaluation that did not close, a
/// contact on a link the hand does not have or an object without mass;
/// [`GraspError::Core`] for a configuration the hand's model rejects; [`GraspError::Solver`]
/// if the conic solver fails.
pub fn static_hold(
    hand: &Hand,
    object: &ObjectModel,
    evaluation: &GraspEvaluation,
    options: &StaticHoldOptions,
) -> Result<StaticHoldOutcome> {
    if evaluation.status != EvaluationStatus::Closed {
        return Err(GraspError::InvalidParameter { name: "evaluation", reason: "the hand did not close".into() });
    }
    crate::planners::check_positive("gravity", options.gravity)?;
    crate::planners::check_positive("mass", object.mass())?;
    crate::planners::check_positive("max_load_factor", options.max_load_factor)?;
    let mu = options.friction.unwrap_or(object.friction);
    crate::planners::check_non_negative("friction", mu)?;
    crate::planners::check_non_negative("saturation_tolerance", options.saturation_tolerance)?;
    let robot = hand.robot();
    let fk = forward_kinematics(robot, &evaluation.q)?;
    let root_from_palm = fk.as_slice()[hand.palm().0] * hand.palm_frame();
    let root_from_object: Isometry3<f64> = root_from_palm * evaluation.hand_pose.inverse();
    // Actuators: configuration dofs whose leading joint has a finite, positive effort limit.
    let actuators: Vec<(usize, f64)> = (0..robot.dof())
        .filter_map(|d| {
            let e = robot.joint(robot.dof_joint(d)).limits?.effort;
            (e.is_finite() && e > 0.0).then_some((d, e))
        })
        .collect();
    let dofs: Vec<usize> = (0..robot.dof()).collect();
    let com = object.center_of_mass();
    let mut prepared = Vec::with_capacity(evaluation.contacts.len());
    for gc in &evaluation.contacts {
        if gc.link >= robot.links().len() {
            return Err(GraspError::InvalidParameter {
                name: "evaluation",
                reason: format!("contact on link {} of a hand with {}", gc.link, robot.links().len()),
            });
        }
        let c = &gc.contact;
        let (t1, t2) = c.tangents();
        let frame = Matrix3::from_columns(&[c.normal.into_inner(), t1, t2]);
        let p_root = root_from_object * c.point;
        let p_link: Point3<f64> = fk.as_slice()[gc.link].inverse_transform_point(&p_root);
        let j = jacobian(robot, &evaluation.q, LinkId(gc.link), &p_link, &dofs)?;
        let root_frame = root_from_object.rotation.to_rotation_matrix().into_inner() * frame;
        let torque = actuators
            .iter()
            .map(|&(d, _)| {
                let v = j.fixed_view::<3, 1>(0, d).into_owned();
                [0, 1, 2].map(|i| v.dot(&root_frame.column(i)))
            })
            .collect();
        prepared.push(Prepared { frame, lever: c.point - com, torque });
    }
    let weight = object.mass() * options.gravity;
    let radius = (object.size().norm() / 2.0).max(1e-3);
    let mut directions = Vec::with_capacity(options.directions.len());
    for dir in &options.directions {
        let n = dir.norm();
        if !(n.is_finite() && n > 0.0) {
            return Err(GraspError::InvalidParameter { name: "directions", reason: format!("bad direction {dir:?}") });
        }
        let d = dir / n;
        let (load, x) = solve(&prepared, &actuators, mu, &d, weight, radius, options.max_load_factor)?;
        let contact_forces: Vec<Vector3<f64>> = prepared
            .iter()
            .enumerate()
            .map(|(c, p)| p.frame * Vector3::new(x[3 * c], x[3 * c + 1], x[3 * c + 2]) * weight)
            .collect();
        let loads: Vec<ActuatorLoad> = actuators
            .iter()
            .enumerate()
            .map(|(k, &(dof, limit))| {
                let torque = prepared
                    .iter()
                    .enumerate()
                    .map(|(c, p)| (0..3).map(|i| p.torque[k][i] * x[3 * c + i]).sum::<f64>())
                    .sum::<f64>()
                    * weight;
                ActuatorLoad { dof, torque, limit }
            })
            .collect();
        let saturated = loads
            .iter()
            .filter(|a| a.torque.abs() >= a.limit * (1.0 - options.saturation_tolerance))
            .map(|a| a.dof)
            .collect();
        directions.push(StaticDirection {
            direction: d,
            load_factor: load,
            contact_forces,
            actuators: loads,
            saturated,
        });
    }
    Ok(StaticHoldOutcome { directions })
}

/// Solves the program of one direction with forces in units of the weight; returns the load
/// factor and the local force components (3 per contact).
fn solve(
    contacts: &[Prepared],
    actuators: &[(usize, f64)],
    mu: f64,
    d: &Vector3<f64>,
    weight: f64,
    radius: f64,
    cap: f64,
) -> Result<(f64, Vec<f64>)> {
    let nc = contacts.len();
    let nx = 3 * nc + 1;
    let na = actuators.len();
    // Rows: 0..6 equilibrium (zero cone); then nonnegative rows: 2 per actuator, s ≤ cap,
    // s ≥ 0, fₙ ≥ 0 per contact; then one 3-row second-order cone per contact.
    let nonneg = 2 * na + 2 + nc;
    let rows = 6 + nonneg + 3 * nc;
    let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nx];
    for (c, p) in contacts.iter().enumerate() {
        for i in 0..3 {
            let col = &mut cols[3 * c + i];
            let f = p.frame.column(i).into_owned();
            let m = p.lever.cross(&f) / radius;
            for r in 0..3 {
                col.push((r, f[r]));
                col.push((3 + r, m[r]));
            }
            for k in 0..na {
                let t = p.torque[k][i] * weight;
                col.push((6 + 2 * k, t));
                col.push((6 + 2 * k + 1, -t));
            }
            // Second-order cone (μ fₙ, f_t1, f_t2): slack = −A x.
            let soc = 6 + nonneg + 3 * c;
            col.push((soc + i, if i == 0 { -mu } else { -1.0 }));
        }
        cols[3 * c].push((6 + 2 * na + 2 + c, -1.0));
    }
    let s = &mut cols[3 * nc];
    for r in 0..3 {
        s.push((r, d[r]));
    }
    s.push((6 + 2 * na, 1.0));
    s.push((6 + 2 * na + 1, -1.0));
    let mut b = vec![0.0; rows];
    for (k, &(_, limit)) in actuators.iter().enumerate() {
        b[6 + 2 * k] = limit;
        b[6 + 2 * k + 1] = limit;
    }
    b[6 + 2 * na] = cap;
    let mut q = vec![0.0; nx];
    q[3 * nc] = -1.0;
    let mut cones = vec![SupportedConeT::ZeroConeT(6), SupportedConeT::NonnegativeConeT(nonneg)];
    cones.extend((0..nc).map(|_| SupportedConeT::SecondOrderConeT(3)));
    let x = solve_conic("static hold socp", rows, cols, &q, &b, &cones)?;
    Ok((x[3 * nc].clamp(0.0, cap), x))
}

/// Minimises `qᵀx` subject to `A x + s = b`, `s ∈ cones`, for `A` given by its columns (row,
/// value pairs, any order) with `rows` rows; returns `x`.
pub(super) fn solve_conic(
    problem: &'static str,
    rows: usize,
    mut cols: Vec<Vec<(usize, f64)>>,
    q: &[f64],
    b: &[f64],
    cones: &[SupportedConeT<f64>],
) -> Result<Vec<f64>> {
    let nx = cols.len();
    let (mut colptr, mut rowval, mut nzval) = (Vec::with_capacity(nx + 1), Vec::new(), Vec::new());
    for col in &mut cols {
        col.sort_by_key(|&(r, _)| r);
        colptr.push(rowval.len());
        for &(r, v) in col.iter() {
            if v != 0.0 {
                rowval.push(r);
                nzval.push(v);
            }
        }
    }
    colptr.push(rowval.len());
    let a = CscMatrix::new(rows, nx, colptr, rowval, nzval);
    let p = CscMatrix::zeros((nx, nx));
    let settings = DefaultSettings { verbose: false, max_iter: 200, ..DefaultSettings::default() };
    let mut solver = DefaultSolver::new(&p, q, &a, b, cones, settings)
        .map_err(|e| GraspError::Solver { problem, status: format!("{e:?}") })?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(solver.solution.x.clone()),
        status => Err(GraspError::Solver { problem, status: format!("{status:?}") }),
    }
}
