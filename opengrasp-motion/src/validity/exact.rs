//! Exact checks on core's parry-based collision world.

use std::sync::Arc;

use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::model::{JointGroup, Robot};
use opengrasp_core::scene::RobotId;

use crate::error::Result;

use super::{MotionBound, StateValidityChecker};

mod certified;

use certified::ExactCertificates;

/// A checker over core's [`CollisionWorld`]: one robot of the world moving the joints of
/// `group`, the other joints held at `q_full`.
///
/// Validity is [`CollisionWorld::in_collision_unchecked`] (environment, objects, other robots,
/// self-collision with the allowed-collision matrix, attached objects); per-link distances are
/// [`CollisionWorld::link_distances`] (environment only) and the clearance is their minimum over
/// the links the group moves (links it cannot move, such as a mobile base resting 2 cm above
/// the floor, would otherwise fix the clearance of every path), with a [`MotionBound`] from the
/// links' collision geometry. Because the link distances exclude self-distance, the continuous
/// validator checks self-collision by a fine discrete check
/// ([`CcdOptions::self_collision_step`](crate::validate::CcdOptions::self_collision_step)).
/// Motion checks ([`StateValidityChecker::check_motion`], and PRM's roadmap edges with the
/// vertices' [`StateValidityChecker::state_certificate`]s) skip the states that the distance
/// lower bounds of a checked state ([`CollisionWorld::gaps_unchecked`]) and the motion bound
/// certify: same verdicts and counts as checking every state.
/// Objects attached to a link are not in the motion bound: pass your own bound with
/// [`CollisionChecker::with_bound`] when carrying objects.
#[derive(Clone, Debug)]
pub struct CollisionChecker {
    world: Arc<CollisionWorld>,
    robot_id: RobotId,
    robot: Arc<Robot>,
    group: JointGroup,
    q_full: Vec<f64>,
    bound: MotionBound,
    /// The state check's tests and their motion bounds, for certified motion checks (`None`
    /// when the world cannot split the check).
    certificates: Option<Arc<ExactCertificates>>,
}

impl CollisionChecker {
    /// A checker for robot `robot_id` of `world` (whose model is `robot`).
    ///
    /// # Errors
    /// [`MotionError::Core`](crate::MotionError::Core) if `q_full` is not a valid configuration of `robot` or `robot_id`
    /// is not a robot of the world.
    pub fn new(
        world: Arc<CollisionWorld>,
        robot_id: RobotId,
        robot: Arc<Robot>,
        group: JointGroup,
        q_full: Vec<f64>,
    ) -> Result<Self> {
        world.in_collision(robot_id, &q_full)?;
        let bound = MotionBound::from_robot(&robot, &group)?;
        let certificates = ExactCertificates::new(&world, robot_id, &robot, &group, &bound).map(Arc::new);
        Ok(Self { world, robot_id, robot, group, q_full, bound, certificates })
    }

    /// Replaces the motion bound (e.g. one that includes carried objects).
    pub fn with_bound(mut self, bound: MotionBound) -> Self {
        self.bound = bound;
        self
    }

    /// The collision world.
    pub fn world(&self) -> &CollisionWorld {
        &self.world
    }

    /// [`ExactCertificates::motion_valid`] on this world (the default check without tests).
    fn certified_motion(&self, a: &[f64], b: &[f64], step: f64, ends: (&[f64], &[f64])) -> (bool, u64) {
        let Some(cert) = &self.certificates else {
            return super::OneByOne(self).check_motion(a, b, step);
        };
        cert.motion_valid(a, b, step, ends, |q, skip, gaps| {
            self.world.gaps_unchecked(self.robot_id, &self.full(q), &cert.tests, certified::CAP, skip, gaps)
        })
    }

    fn full(&self, q: &[f64]) -> Vec<f64> {
        let mut full = self.q_full.clone();
        for (&d, &v) in self.group.dofs().iter().zip(q) {
            full[d] = v;
        }
        full
    }
}

impl StateValidityChecker for CollisionChecker {
    fn dim(&self) -> usize {
        self.group.len()
    }
    fn is_valid(&self, q: &[f64]) -> bool {
        !self.world.in_collision_unchecked(self.robot_id, &self.full(q))
    }
    fn clearance(&self, q: &[f64]) -> Option<f64> {
        let mut d = Vec::new();
        if !self.link_distances(q, &mut d) {
            return None;
        }
        Some((0..d.len()).filter(|&i| self.bound.is_moving(i)).map(|i| d[i]).fold(f64::INFINITY, f64::min))
    }
    fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        let mut full = self.full(q);
        self.robot.clamp_configuration(&mut full);
        match self.world.link_distances(self.robot_id, &full) {
            Ok(all) => {
                out.clear();
                out.extend(self.bound.links().iter().map(|l| all.get(l.0).copied().unwrap_or(f64::INFINITY)));
                true
            }
            Err(_) => false,
        }
    }
    fn motion_bound(&self) -> Option<&MotionBound> {
        Some(&self.bound)
    }
    fn residual_valid(&self, q: &[f64]) -> Option<bool> {
        let full = self.full(q);
        // The link distances are measured at the configuration clamped to the joint limits:
        // only within the limits do they describe `q` itself.
        let mut clamped = full.clone();
        self.robot.clamp_configuration(&mut clamped);
        if clamped != full {
            return None;
        }
        Some(!self.world.in_self_collision_unchecked(self.robot_id, &full))
    }
    /// The gap of every test of the state check (see [`CollisionWorld::gap_tests`]): lower
    /// bounds on the distances of each self-collision pair and of each part to the obstacles.
    fn state_certificate(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        let Some(cert) = &self.certificates else {
            out.clear();
            return self.is_valid(q);
        };
        let valid =
            self.world.gaps_unchecked(self.robot_id, &self.full(q), &cert.tests, certified::CAP, |_| false, out);
        if !valid {
            out.clear();
        }
        valid
    }
    /// The states near the ends and near each checked state are certified by the tests'
    /// gaps and the motion bound, not checked (same verdict as checking every state).
    fn is_motion_valid_between(&self, a: &[f64], a_cert: &[f64], b: &[f64], b_cert: &[f64], step: f64) -> bool {
        self.certified_motion(a, b, step, (a_cert, b_cert)).0
    }
    /// The one-by-one verdict and count, with the states each checked state certifies
    /// skipped (see [`CollisionChecker::is_motion_valid_between`]).
    fn check_motion(&self, a: &[f64], b: &[f64], step: f64) -> (bool, u64) {
        self.certified_motion(a, b, step, (&[], &[]))
    }
}
