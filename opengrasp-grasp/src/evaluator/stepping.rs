//! Time stepping of the physics check's runs after the release (the gravity-free control run
//! and the gravity runs): adaptive sub-stepping of a moving object ([`AdaptiveStep`]) and the
//! early stop of a gravity run whose object is certainly dropped ([`DropBound`]).

use nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::hand::Hand;
use opengrasp_core::model::{JointKind, LinkId, Robot};
use opengrasp_core::object::ObjectModel;
use opengrasp_core::physics::{ContactBody, PhysicsEngine};
use opengrasp_core::scene::{ObjectId, RobotId};

use crate::error::{GraspError, Result};

/// Sub-stepping while the object moves ([`super::PhysicsCheckOptions::adaptive_step`]): each
/// step of the check's runs after the release that starts with the object's centre of mass
/// moving at `speed` or faster while it touches the hand (an active contact) is simulated as
/// `substeps` equal steps; a slower or untouched object takes the normal step. A grip in
/// balance keeps the object nearly still, where the normal step is accurate; a shifting object
/// meets the fingers' soft contacts at speed, where a coarse step overshoots the contact depths
/// and kicks a grip that would hold out of balance; free flight gains nothing from the split.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveStep {
    /// Speed (m/s) of the object's centre of mass from which a step is split. Default: 0.01.
    pub speed: f64,
    /// Steps each split step is divided into (at least 1; 1 splits nothing). Default: 3
    /// (about 1.4 ms at the check's 1/240 s step).
    pub substeps: usize,
}

impl Default for AdaptiveStep {
    fn default() -> Self {
        Self { speed: 0.01, substeps: 3 }
    }
}

impl AdaptiveStep {
    /// Checks the values.
    ///
    /// # Errors
    /// [`GraspError::InvalidParameter`] for a `speed` that is not finite and non-negative, or
    /// zero `substeps`.
    pub fn validate(&self) -> Result<()> {
        crate::planners::check_non_negative("adaptive_step.speed", self.speed)?;
        if self.substeps == 0 {
            return Err(GraspError::InvalidParameter {
                name: "adaptive_step.substeps",
                reason: "must be at least 1".into(),
            });
        }
        Ok(())
    }
}

/// What a run may stop early for: the object `oid` is certainly dropped, `bound` and the
/// run's gravity `gravity` say when ([`DropBound::certain`]).
pub(super) struct EarlyStop<'a> {
    pub(super) bound: &'a DropBound,
    pub(super) gravity: Vector3<f64>,
}

/// `steps` steps of `dt` of `engine` (each split as `adaptive` says while object `oid` moves
/// in contact), stopped after the first step at which `stop` is certain. Returns whether it
/// stopped early.
///
/// # Errors
/// [`GraspError::Core`] from the engine.
pub(super) fn run<E: PhysicsEngine>(
    engine: &mut E,
    oid: ObjectId,
    steps: usize,
    dt: f64,
    adaptive: Option<&AdaptiveStep>,
    stop: Option<&EarlyStop<'_>>,
) -> Result<bool> {
    for _ in 0..steps {
        match adaptive {
            Some(a)
                if a.substeps > 1 && engine.object_velocity(oid)?.linear.norm() >= a.speed && touching(engine, oid) =>
            {
                let h = dt / a.substeps as f64;
                engine.step_n(a.substeps, h)?;
            }
            _ => engine.step(dt)?,
        }
        if let Some(stop) = stop {
            if stop.bound.certain(engine, oid, &stop.gravity)? {
                return Ok(true);
            }
        }
    }
    Ok(false)
}

/// True if object `oid` of `engine` has an active contact (the scene's only other bodies are
/// the hand's links).
fn touching<E: PhysicsEngine>(engine: &E, oid: ObjectId) -> bool {
    let is = |b: ContactBody| b == ContactBody::Object(oid);
    engine.contacts().iter().any(|c| is(c.body1) || is(c.body2))
}

/// When a gravity run's object is certainly dropped ([`super::PhysicsCheckOptions::early_drop`]).
///
/// The scene holds only the fixed hand and the object, and after the release nothing but
/// gravity `g` and the contacts acts on the object. Let `u` be its centre of mass relative to a
/// fixed point and `v` its velocity. If `u·v ≥ 0`, `u·g ≥ 0` and `v·g ≥ 0`, then in free
/// flight `|u|` never decreases: the simulator's semi-implicit Euler steps (`v' = v + h g`,
/// `u' = u + h v'`, any step lengths `h`) keep all three products non-negative and
/// `|u'|² = |u|² + 2h u·v' + h²|v'|² ≥ |u|²` with `u·v' = u·v + h u·g ≥ 0`.
/// Taken about the centre of each ball of a set containing the hand in every configuration
/// ([`hand_balls`]), with the object's centre farther than each ball's radius plus the
/// object's own (its hull's farthest vertex from the centre of mass), the flight can never
/// meet the hand again, so it lasts to the end of the run; taken about the control run's final
/// centre of mass, the distance to it only grows, and once it exceeds `beyond` (the verdict's
/// thresholds plus twice the centre of mass's offset from the object origin, since the verdict
/// measures the origin) the full run would end [`super::HoldResult::Dropped`] too. All the
/// conditions at once make the early verdict the full run's.
pub(super) struct DropBound {
    /// Centres (world) of balls containing the hand in every configuration, each with its
    /// radius plus the object's radius about its centre of mass plus a margin (m).
    balls: Vec<Ball>,
    /// The control run's final centre of mass (world).
    control_com: Vector3<f64>,
    /// Distance (m) from `control_com` beyond which the verdict is a drop.
    beyond: f64,
    /// The object's centre of mass in its frame.
    com: Point3<f64>,
}

/// A ball: its centre (world) and radius (m).
type Ball = (Vector3<f64>, f64);

/// Added to the clearance and the drop distance (m): the soft contacts act a little before
/// touch, and rounding may shrink a growing distance by far less.
const MARGIN: f64 = 0.01;

impl DropBound {
    /// The bound for the gravity runs of a check on `engine` (robot `robot` = `hand`, object
    /// `object`), whose control run ended with the object at `control`; the verdict is a drop
    /// beyond `drop_translation` when that also exceeds `max_translation`. `None` if the hand
    /// has a prismatic joint without limits (no ball contains it).
    ///
    /// # Errors
    /// [`GraspError::Core`] from the engine.
    pub(super) fn new<E: PhysicsEngine>(
        engine: &E,
        robot: RobotId,
        hand: &Hand,
        object: &ObjectModel,
        control: &Isometry3<f64>,
        drop_translation: f64,
        max_translation: f64,
    ) -> Result<Option<Self>> {
        let com = object.center_of_mass();
        let object_radius = object.mesh.vertices().iter().map(|v| (v - com).norm()).fold(0.0, f64::max);
        let Some(balls) = hand_balls(engine, robot, hand.robot())? else { return Ok(None) };
        Ok(Some(Self {
            balls: balls.into_iter().map(|(c, r)| (c, r + object_radius + MARGIN)).collect(),
            control_com: (control * com).coords,
            beyond: drop_translation.max(max_translation) + 2.0 * com.coords.norm() + MARGIN,
            com,
        }))
    }

    /// True if object `oid` of `engine` is certainly dropped under `gravity` (see
    /// [`DropBound`]): out of every hand ball and moving away from each, and beyond the drop
    /// distance from the control run's final pose and moving away from it.
    ///
    /// # Errors
    /// [`GraspError::Core`] from the engine.
    pub(super) fn certain<E: PhysicsEngine>(&self, engine: &E, oid: ObjectId, gravity: &Vector3<f64>) -> Result<bool> {
        let x = (engine.object_pose(oid)? * self.com).coords;
        let v = engine.object_velocity(oid)?.linear;
        let receding = |u: Vector3<f64>, distance: f64| {
            u.norm() > distance && u.dot(&v) >= 0.0 && u.dot(gravity) >= 0.0 && v.dot(gravity) >= 0.0
        };
        Ok(receding(x - self.control_com, self.beyond) && self.balls.iter().all(|(c, r)| receding(x - c, *r)))
    }
}

/// Balls (world centre, radius in m) that together contain every collision shape of `robot`
/// (robot `id` of `engine`, its root fixed) in every configuration: one per link rigid with
/// the root, about its origin (its shapes' farthest bounding-box corner), and one per movable
/// joint whose parent is rigid with the root, about that joint's origin, containing the links
/// it carries: per link the distances of the joints' origins from their parents' (a revolute
/// joint turns about its origin and moves nothing farther), their prismatic travel, and its
/// shapes' corners. `None` for a prismatic joint without limits.
///
/// # Errors
/// [`GraspError::Core`] from the engine.
fn hand_balls<E: PhysicsEngine>(engine: &E, id: RobotId, robot: &Robot) -> Result<Option<Vec<Ball>>> {
    let corner = |link: usize| {
        let shapes = robot.links()[link].collisions.iter();
        shapes.flat_map(|s| s.aabb_corners().map(|c| c.coords.norm())).fold(f64::NEG_INFINITY, f64::max)
    };
    // Per link: the ball that holds it (`None`: rigid with the root) and its origin's reach
    // from that ball's centre.
    let mut ball_of: Vec<Option<usize>> = vec![None; robot.links().len()];
    let mut reach = vec![0.0; robot.links().len()];
    let mut balls: Vec<Ball> = Vec::new();
    for &j in robot.joints_topological() {
        let joint = robot.joint(j);
        let (parent, child) = (joint.parent.0, joint.child.0);
        let travel = match joint.kind {
            JointKind::Prismatic => match joint.limits {
                Some(limits) => limits.lower.abs().max(limits.upper.abs()),
                None => return Ok(None),
            },
            _ => 0.0,
        };
        match (ball_of[parent], joint.is_movable()) {
            (None, false) => {}
            (None, true) => {
                let centre = engine.link_pose(id, joint.parent)? * Point3::from(joint.origin.translation.vector);
                balls.push((centre.coords, 0.0));
                ball_of[child] = Some(balls.len() - 1);
                reach[child] = travel;
            }
            (Some(b), _) => {
                ball_of[child] = Some(b);
                reach[child] = reach[parent] + joint.origin.translation.vector.norm() + travel;
            }
        }
    }
    let mut rigid = Vec::new();
    for (link, ball) in ball_of.iter().enumerate() {
        let extent = corner(link);
        if extent == f64::NEG_INFINITY {
            continue;
        }
        match ball {
            Some(b) => balls[*b].1 = balls[*b].1.max(reach[link] + extent),
            None => rigid.push((engine.link_pose(id, LinkId(link))?.translation.vector, extent)),
        }
    }
    balls.extend(rigid);
    Ok(Some(balls))
}
