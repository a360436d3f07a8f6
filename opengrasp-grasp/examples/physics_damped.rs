//! Where the quasi-static closing ([`PhysicsCheckOptions::closing_damping`]) leaves the object
//! of each benchmark grasp: does the simulated grip find an equilibrium near the evaluated pose?
//!
//! ```text
//! cargo run --release -p opengrasp-grasp --example physics_damped -- [HAND] [TAU] [PER_CELL]
//! ```
//! HAND `armar3` (default) or `barrett`; TAU the damping time constant (s, default 0.01);
//! PER_CELL grasps per planner and object (default 3, spread evenly over the force-closure palm
//! grasps of the first 128 candidates, as `physics_sweep`). Per grasp: the free, damped
//! object's displacement and turn from the evaluated pose after the `settle` closing and after
//! the damping ramp; the links touching it then and their total normal force; how far the
//! grip alone moves and turns it in the undamped, gravity-free `duration` after the ramp (the
//! control run) and where that leaves it from the grasp; the largest displacement gravity adds;
//! the check's result. Each grasp falls into one class: `expelled` (after the ramp the fingers
//! press the object with less than 1 % of its weight in total: the closing pushed it out of
//! the grip), `drifting` (still pressed, but the control run moves it more than the check's
//! `max_translation` or turns it more than `max_rotation`: the simulated grip has no
//! equilibrium there) or `settled` (within them); per class the count held.

use opengrasp_assets::hands;
use opengrasp_core::physics::{ContactBody, PhysicsEngine, RapierBackend};
use opengrasp_core::scene::ObjectId;
use opengrasp_grasp::evaluator::{physics_check, undamp_gradually, PhysicsCheckOptions};
use opengrasp_grasp::tactile::sources::{squeeze_engine, TactileSeriesOptions};

mod common;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let hand =
        if args.first().map(String::as_str) == Some("barrett") { hands::barrett() } else { hands::armar3_hand() };
    let tau: f64 = args.get(1).map_or(Ok(0.01), |s| s.parse())?;
    let per_cell: usize = args.get(2).map_or(Ok(3), |s| s.parse())?;
    // Position control, as the closing this example repeats step by step.
    let options = PhysicsCheckOptions {
        fixture: false,
        closing_damping: Some(tau),
        hand_actuation: false,
        ..PhysicsCheckOptions::default()
    };
    let (oid, dt) = (ObjectId(0), options.physics.timestep);
    // Per class (expelled, drifting, settled): checked, held.
    let mut classes = [[0usize; 2]; 3];
    for common::ObjectSample { object, planners } in common::paper_sample(&hand, per_cell)? {
        let name = &object.name;
        for sample in &planners {
            for (j, grasp) in sample.grasps.iter().enumerate() {
                let squeeze = TactileSeriesOptions {
                    squeeze: options.squeeze,
                    gravity: nalgebra::Vector3::zeros(),
                    physics: options.physics.clone(),
                    ..TactileSeriesOptions::default()
                };
                // The check's damped closing, repeated with the object's pose read in between.
                let (mut engine, _) = squeeze_engine::<RapierBackend>(&hand, &object, grasp, &squeeze)?;
                engine.set_object_damping(oid, 1.0 / tau, 1.0 / tau)?;
                engine.step_n((options.settle / dt).ceil() as usize, dt)?;
                let closed = engine.object_pose(oid)?;
                undamp_gradually(&mut engine, oid, 1.0 / tau, options.damping_ramp, dt)?;
                let ramped = engine.object_pose(oid)?;
                let (mut touching, mut normal) = (std::collections::BTreeSet::new(), 0.0);
                for c in engine.contacts() {
                    if let (ContactBody::Link { link, .. }, ContactBody::Object(_))
                    | (ContactBody::Object(_), ContactBody::Link { link, .. }) = (c.body1, c.body2)
                    {
                        touching.insert(link.0);
                        normal += c.normal_force;
                    }
                }
                // The control run's gravity-free `duration`, continued from the ramp's end.
                let mut control = engine.snapshot().ok_or("rapier snapshots")?;
                control.step_n((options.duration / dt).ceil() as usize, dt)?;
                let after = control.object_pose(oid)?;
                let drift = (after.translation.vector - ramped.translation.vector).norm();
                let turn = after.rotation.angle_to(&ramped.rotation);
                let moved = drift > options.max_translation || turn > options.max_rotation;
                let class = if normal < 0.01 * object.inertial.mass * options.gravity {
                    0
                } else if moved {
                    1
                } else {
                    2
                };
                // A diverged simulation holds nothing.
                let outcome = physics_check(&hand, &object, grasp, &options).ok();
                let held = outcome.as_ref().is_some_and(|o| o.held());
                let (control, worst) = outcome.map_or((f64::NAN, f64::NAN), |o| {
                    (o.grip_translation, o.translations.iter().copied().fold(0.0, f64::max))
                });
                classes[class][0] += 1;
                classes[class][1] += usize::from(held);
                println!(
                    "{name:16} {:15} {j}: closed {:5.1} mm {:4.2} rad, ramped {:5.1} mm {:4.2} rad, {} links {:6.1} N, then undamped {:5.1} mm {:4.2} rad (control run {:5.1} mm from the grasp), gravity up to {:5.1} mm more, {}: {}",
                    sample.planner,
                    1e3 * closed.translation.vector.norm(),
                    closed.rotation.angle(),
                    1e3 * ramped.translation.vector.norm(),
                    ramped.rotation.angle(),
                    touching.len(),
                    normal,
                    1e3 * drift,
                    turn,
                    1e3 * control,
                    1e3 * worst,
                    ["expelled", "drifting", "settled"][class],
                    if held { "held" } else { "not held" }
                );
            }
        }
    }
    for (class, label) in ["expelled", "drifting", "settled"].iter().enumerate() {
        println!("{label:9} held {}/{}", classes[class][1], classes[class][0]);
    }
    Ok(())
}
