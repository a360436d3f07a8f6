//! Shared by the `physics_*` examples: the force-closure palm grasps of one planner.

use opengrasp_core::object::ObjectModel;
use opengrasp_grasp::evaluator::{GraspEvaluation, GraspEvaluator};
use opengrasp_grasp::planners::{GraspPlanner, GraspRequest};

/// Evaluates the first 128 of `planner`'s candidates for the evaluator's hand on `object`
/// (spread evenly) and returns those with the palm touching in force closure.
pub fn fc_palm_grasps(
    evaluator: &mut GraspEvaluator,
    object: &ObjectModel,
    planner: &dyn GraspPlanner,
) -> Result<Vec<GraspEvaluation>, Box<dyn std::error::Error>> {
    let info = evaluator.hand_info().clone();
    let candidates = planner.plan(&GraspRequest { hand: &info, object: &object.mesh, seed: 0 })?;
    let m = candidates.len().min(128);
    let mut grasps = Vec::new();
    for i in 0..m {
        let e = evaluator.evaluate(&candidates[i * candidates.len() / m])?;
        if e.palm_contact && e.force_closure() {
            grasps.push(e);
        }
    }
    Ok(grasps)
}

/// What the physics check's clamped squeeze of one grasp ends with (position or effort control;
/// the balanced-grip modes are not reproduced).
pub struct Squeeze {
    /// Sum of the contacts' normal forces on the object (N).
    pub normal: f64,
    /// The palm's share of it (N).
    pub palm: f64,
    /// Magnitude of the force (N) the fixture holds the object with: the grip's net push.
    pub fixture: f64,
    /// Deepest penetration (m) of a link into the object.
    pub depth: f64,
}

/// Repeats the check's squeeze (`options.settle` with the object clamped) and sums its contacts.
pub fn clamped_squeeze(
    hand: &opengrasp_core::hand::Hand,
    object: &ObjectModel,
    grasp: &GraspEvaluation,
    options: &opengrasp_grasp::evaluator::PhysicsCheckOptions,
) -> Result<Squeeze, Box<dyn std::error::Error>> {
    use opengrasp_core::physics::{ContactBody, PhysicsEngine, RapierBackend};
    use opengrasp_core::scene::ObjectId;
    use opengrasp_grasp::tactile::sources::{squeeze_engine, TactileSeriesOptions};
    let squeeze = TactileSeriesOptions {
        squeeze: options.squeeze,
        effort: options.effort,
        gravity: nalgebra::Vector3::zeros(),
        physics: options.physics.clone(),
        ..TactileSeriesOptions::default()
    };
    let (mut engine, _) = squeeze_engine::<RapierBackend>(hand, object, grasp, &squeeze)?;
    let dt = options.physics.timestep;
    engine.set_object_fixed(ObjectId(0), true)?;
    engine.step_n((options.settle / dt).ceil() as usize, dt)?;
    let mut out = Squeeze { normal: 0.0, palm: 0.0, fixture: 0.0, depth: 0.0 };
    for c in engine.contacts() {
        let link = match (c.body1, c.body2) {
            (ContactBody::Link { link, .. }, ContactBody::Object(_)) => link,
            (ContactBody::Object(_), ContactBody::Link { link, .. }) => link,
            _ => continue,
        };
        out.normal += c.normal_force;
        out.depth = out.depth.max(-c.distance);
        if link == hand.palm() {
            out.palm += c.normal_force;
        }
    }
    let wrench = opengrasp_grasp::evaluator::fixture_wrench(&engine, ObjectId(0), object, dt)?;
    out.fixture = wrench.map_or(0.0, |(f, _)| f.norm());
    Ok(out)
}
