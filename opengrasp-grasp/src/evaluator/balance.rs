//! Why a simulated grip lets go: the balance of its traced contact forces at the release.
//!
//! At the end of the physics check's clamped squeeze every simulated finger contact `c` presses
//! the object with its normal force `N_c` (traced from the simulator) along its inward normal
//! `n_c`. [`release_imbalance`] asks whether *any* friction forces inside the cones, together
//! with whatever the palm can push (the palm is the hand's fixed root: while the object is
//! clamped the simulator makes no palm contacts, so the evaluator's palm contacts get free
//! normal forces), balance those normal forces:
//!
//! ```text
//! minimise   ‖w‖,   w = Σ_c (N_c n_c + t_c, (p_c − c) × (N_c n_c + t_c) / r)
//!                     + Σ_p (f_p, (p_p − c) × f_p / r)               (net wrench, N)
//! subject to ‖t_c‖ ≤ μ N_c,  t_c ⟂ n_c                               (finger contacts, N_c fixed)
//!            ‖f_p − (f_p·n_p) n_p‖ ≤ μ (f_p·n_p)                       (palm contacts, free)
//! ```
//!
//! (`c` the centre of mass, `r` the object's radius, so torques count as forces at its
//! surface). The optimum is the least net push the fingers put on the freed object whatever
//! friction does: the object must accelerate with at least this force when the fixture lets go,
//! before gravity has moved it at all.

use clarabel::solver::SupportedConeT;
use nalgebra::{Matrix3, Vector3};
use opengrasp_core::hand::Hand;
use opengrasp_core::object::ObjectModel;
use opengrasp_core::physics::PhysicsEngine;
use opengrasp_core::scene::{ObjectId, RobotId};

use super::grip_sim::simulated_contacts;
use super::GraspEvaluation;
use crate::contact::Contact;
use crate::error::Result;

/// One contact of the program: its local frame (columns `n, t₁, t₂`, object frame), lever
/// about the centre of mass, and fixed normal force (`None`: a free palm contact).
struct Row {
    frame: Matrix3<f64>,
    lever: Vector3<f64>,
    normal: Option<f64>,
}

impl Row {
    fn new(contact: &Contact, com: &nalgebra::Point3<f64>, normal: Option<f64>) -> Self {
        let (t1, t2) = contact.tangents();
        let frame = Matrix3::from_columns(&[contact.normal.into_inner(), t1, t2]);
        Self { frame, lever: contact.point - com, normal }
    }
}

/// The least net wrench (N, torques divided by the object's radius) that the contacts of the
/// hand `robot` in `engine` can put on `object` (scene object `oid`) with their simulated normal
/// forces and the best friction inside cones of the object's μ, the palm contacts of
/// `evaluation` pushing freely (see the module docs). Read-only: the engine is not stepped.
///
/// # Errors
/// [`crate::GraspError::Core`] from the engine, [`crate::GraspError::NonFinite`] for a
/// non-finite contact, [`crate::GraspError::Solver`] if the conic solver fails.
pub fn release_imbalance<E: PhysicsEngine + ?Sized>(
    engine: &E,
    hand: &Hand,
    robot: RobotId,
    oid: ObjectId,
    object: &ObjectModel,
    evaluation: &GraspEvaluation,
) -> Result<f64> {
    let com = object.center_of_mass();
    let palm = hand.palm().0;
    let mut rows: Vec<Row> = simulated_contacts(engine, robot, oid, evaluation)?
        .into_iter()
        .filter(|(g, _)| g.link != palm)
        .map(|(g, n)| Row::new(&g.contact, &com, Some(n)))
        .collect();
    rows.extend(evaluation.contacts.iter().filter(|g| g.link == palm).map(|g| Row::new(&g.contact, &com, None)));
    let radius = (object.size().norm() / 2.0).max(1e-3);
    solve(&rows, object.friction, radius)
}

/// The program of the module docs: returns the optimal `‖w‖`.
fn solve(rows: &[Row], mu: f64, radius: f64) -> Result<f64> {
    // Variables: per contact its tangential components (and the normal one for a free contact),
    // then the residual's norm s. Rows (b − A x ∈ cones): the 7-row cone (s, w), then a 3-row
    // cone per contact.
    let mut first = Vec::with_capacity(rows.len());
    let mut nx = 0;
    for r in rows {
        first.push(nx);
        nx += if r.normal.is_some() { 2 } else { 3 };
    }
    let s = nx;
    let n_rows = 7 + 3 * rows.len();
    let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nx + 1];
    let mut b = vec![0.0; n_rows];
    cols[s].push((0, -1.0));
    let wrench = |f: Vector3<f64>, lever: &Vector3<f64>| {
        let m = lever.cross(&f) / radius;
        [f.x, f.y, f.z, m.x, m.y, m.z]
    };
    for (c, r) in rows.iter().enumerate() {
        let cone = 7 + 3 * c;
        // The first local component that is a variable: the normal one of a free contact.
        let k0 = match r.normal {
            Some(n) => {
                for (row, v) in wrench(r.frame.column(0) * n, &r.lever).into_iter().enumerate() {
                    b[1 + row] += v;
                }
                b[cone] = mu * n;
                1
            }
            None => 0,
        };
        for k in k0..3 {
            let x = first[c] + k - k0;
            for (row, v) in wrench(r.frame.column(k).into_owned(), &r.lever).into_iter().enumerate() {
                cols[x].push((1 + row, -v));
            }
            cols[x].push((cone + k, if k == 0 { -mu } else { -1.0 }));
        }
    }
    let mut q = vec![0.0; nx + 1];
    q[s] = 1.0;
    let mut cones = vec![SupportedConeT::SecondOrderConeT(7)];
    cones.extend(rows.iter().map(|_| SupportedConeT::SecondOrderConeT(3)));
    let x = super::static_hold::solve_conic("release imbalance socp", n_rows, cols, &q, &b, &cones)?;
    Ok(x[s].max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;

    fn row(normal: Vector3<f64>, point: Vector3<f64>, force: Option<f64>) -> Row {
        Row::new(&Contact::new(point.into(), normal).unwrap(), &Point3::origin(), force)
    }

    /// Two contacts on the x axis pressing towards each other with `a` and `b` newtons.
    fn pinch(a: f64, b: f64) -> [Row; 2] {
        [row(-Vector3::x(), Vector3::x() * 0.03, Some(a)), row(Vector3::x(), -Vector3::x() * 0.03, Some(b))]
    }

    #[test]
    fn equal_pinch_balances() {
        assert!(solve(&pinch(10.0, 10.0), 0.5, 0.05).unwrap() < 1e-6);
    }

    #[test]
    fn unequal_pinch_pushes_by_the_difference() {
        // 10 N against 4 N on one line: friction (tangential) cannot cancel a normal surplus.
        let w = solve(&pinch(10.0, 4.0), 0.5, 0.05).unwrap();
        assert!((w - 6.0).abs() < 1e-4, "{w}");
    }

    #[test]
    fn a_palm_takes_the_surplus() {
        // The 6 N surplus pushes the object towards −x, onto a free palm contact.
        let mut rows = pinch(10.0, 4.0).into_iter().collect::<Vec<_>>();
        rows.push(row(Vector3::x(), -Vector3::x() * 0.03 + Vector3::y() * 0.001, None));
        assert!(solve(&rows, 0.5, 0.05).unwrap() < 1e-4);
        // A palm on the other side cannot pull.
        rows.pop();
        rows.push(row(-Vector3::x(), Vector3::x() * 0.03, None));
        assert!((solve(&rows, 0.5, 0.05).unwrap() - 6.0).abs() < 1e-4);
    }

    #[test]
    fn friction_turns_tilted_forces_back_within_the_cone() {
        // Normals leaning 20° off the common line (tan 20° = 0.36): μ = 0.5 balances them; with
        // μ = 0.2 the net normal force 2·10 sin 20° (along +y) keeps what friction, at most
        // 2·0.2·10 cos 20°, cannot take back.
        let a = 20f64.to_radians();
        let (n1, n2) = (Vector3::new(-a.cos(), a.sin(), 0.0), Vector3::new(a.cos(), a.sin(), 0.0));
        let rows = [row(n1, Vector3::x() * 0.03, Some(10.0)), row(n2, -Vector3::x() * 0.03, Some(10.0))];
        assert!(solve(&rows, 0.5, 0.05).unwrap() < 1e-4);
        let expected = 20.0 * a.sin() - 4.0 * a.cos();
        let w = solve(&rows, 0.2, 0.05).unwrap();
        assert!((w - expected).abs() < 1e-3, "{w} vs {expected}");
    }

    #[test]
    fn offset_pair_leaves_a_couple() {
        // Equal, opposite forces 2 cm apart along y: no net force, a couple of 10 × 0.02 N·m,
        // counted as 0.2 / r newtons (no friction at these points can cancel it: μ = 0).
        let rows = [
            row(-Vector3::x(), Vector3::new(0.03, 0.01, 0.0), Some(10.0)),
            row(Vector3::x(), Vector3::new(-0.03, -0.01, 0.0), Some(10.0)),
        ];
        let w = solve(&rows, 0.0, 0.05).unwrap();
        assert!((w - 0.2 / 0.05).abs() < 1e-3, "{w}");
    }
}
