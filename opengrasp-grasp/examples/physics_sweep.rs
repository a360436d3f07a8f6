//! Hold rates of the physics check for both paper hands over the paper's eight objects, under
//! check and simulator settings given on the command line: for comparing settings A/B.
//!
//! ```text
//! cargo run --release -p opengrasp-grasp --example physics_sweep -- [KEY=VALUE ...]
//! ```
//! Keys (defaults are [`PhysicsCheckOptions::default`]'s): `stiffness` (joint motor, s⁻²),
//! `damping` (s⁻¹), `squeeze` (rad), `effort` (fraction of the effort limits; 0: position
//! control with `squeeze`), `balanced` (fraction of the joints' effort shares for the balanced
//! grip torques; 0: off), `grip_margin`, `compliance` (rad: the balanced grip as joint springs,
//! full effort at this deflection; 0: off), `spring` (rad: the closing joints as springs with their full effort share θ before their rest positions; 0: off), `resolve` (0/1: re-solve the balanced grip on
//! the simulated contacts after the squeeze), `regrip` (s: re-solve it every this often during the squeeze; 0: off), `hand_actuation` (0/1: each hand's own actuator model where no other is set), `contact_hz`, `iterations`, `timestep` (s), `fixture`
//! (0/1), `release` (s: the fixture's wrench ramped to zero over this time; 0: at once), `tau` (s: quasi-static closing on the free object with viscous damping of this time constant, needs `fixture=0`; 0: off), `damping_ramp` (s), `settle` (s), `coupled` (0/1), `armature` (kg·m², [`opengrasp_core::physics::PhysicsOptions::joint_armature`]), `window_dt` (s), `window_hz`, `window_before` (s), `window_after` (s) (the fine release window, [`PhysicsCheckOptions::release_window`]; a key sets one field, the others 1 ms, 120 Hz, 20 ms, 30 ms where no window was set; `window=0`: none), `adaptive_speed` (m/s), `adaptive_substeps` (0: no adaptive stepping) ([`PhysicsCheckOptions::adaptive_step`]), `early_drop` (0/1), `verdicts` (0/1: print each check's results per direction), `per_cell` (grasps per planner and object, default 3), `hand`
//! (`barrett` or `armar3`; default both). Per object and planner the first 128 candidates
//! (spread evenly) are evaluated and `per_cell` of the force-closure palm grasps, spread
//! evenly, are checked; the line shows `[force-closure palm grasps] held/checked`. Per hand the
//! failures are split into those the grip explains (the gravity-free control run loses the
//! object too, [`opengrasp_grasp::evaluator::PhysicsOutcome::grip_escapes`]) and the rest, with the median of their traced
//! release pushes ([`opengrasp_grasp::evaluator::PhysicsOutcome::release_push`]); `explain=1` prints each push. A check whose
//! simulation diverges ([`CoreError::SimulationDiverged`]) counts as checked and not held, and is reported.
//! `palm_push=d` (m) moves each grasp's hand `d` further along its approach direction (into
//! the object) before the check. `explain=1` repeats each check's clamped squeeze and prints its contacts' total normal force
//! `ΣN` (the palm's share), `μΣN / mg`, the fixture's load / mg and the deepest penetration, then counts held per class:
//! weak (`μΣN < mg`: friction cannot carry the weight across the squeeze) and pushed out (the
//! fixture holds more than the weight: the grip alone pushes the object out when freed).

use opengrasp_assets::hands;
use opengrasp_core::error::CoreError;
use opengrasp_grasp::error::GraspError;
use opengrasp_grasp::evaluator::{physics_check, AdaptiveStep, HoldResult, PhysicsCheckOptions, ReleaseWindow};

mod common;

/// The options' adaptive stepping, created (the default) if unset.
fn adaptive(options: &mut PhysicsCheckOptions) -> &mut AdaptiveStep {
    options.adaptive_step.get_or_insert_with(AdaptiveStep::default)
}

/// The options' release window, created (1 ms, 120 Hz, 20 ms before, 30 ms after) if unset.
fn window(options: &mut PhysicsCheckOptions) -> &mut ReleaseWindow {
    options.release_window.get_or_insert(ReleaseWindow {
        timestep: 1e-3,
        contact_frequency: 120.0,
        before: 0.02,
        after: 0.03,
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut options = PhysicsCheckOptions::default();
    let (mut per_cell, mut only, mut explain, mut palm_push) = (3usize, String::new(), false, 0.0);
    let mut verdicts = false;
    for arg in std::env::args().skip(1) {
        let (key, value) = arg.split_once('=').ok_or_else(|| format!("expected KEY=VALUE, got `{arg}`"))?;
        let p = &mut options.physics;
        match key {
            "stiffness" => p.joint_stiffness = value.parse()?,
            "damping" => p.joint_damping = value.parse()?,
            "squeeze" => options.squeeze = value.parse()?,
            "effort" => options.effort = Some(value.parse()?).filter(|&f: &f64| f > 0.0),
            "balanced" => options.balanced = Some(value.parse()?).filter(|&f: &f64| f > 0.0),
            "grip_margin" => options.grip_margin = value.parse()?,
            "resolve" => options.resolve_grip = value != "0",
            "regrip" => options.regrip = Some(value.parse()?).filter(|&t: &f64| t > 0.0),
            "hand_actuation" => options.hand_actuation = value != "0",
            "spring" => options.spring = Some(value.parse()?).filter(|&f: &f64| f > 0.0),
            "compliance" => options.grip_compliance = Some(value.parse()?).filter(|&f: &f64| f > 0.0),
            "contact_hz" => p.contact_frequency = value.parse()?,
            "iterations" => p.solver_iterations = value.parse()?,
            "timestep" => p.timestep = value.parse()?,
            "fixture" => options.fixture = value != "0",
            "release" => options.release = value.parse()?,
            "tau" => options.closing_damping = Some(value.parse()?).filter(|&t: &f64| t > 0.0),
            "damping_ramp" => options.damping_ramp = value.parse()?,
            "settle" => options.settle = value.parse()?,
            "coupled" => p.coupled_actuators = value != "0",
            "armature" => p.joint_armature = value.parse()?,
            "window" if value == "0" => options.release_window = None,
            "window_dt" => window(&mut options).timestep = value.parse()?,
            "window_hz" => window(&mut options).contact_frequency = value.parse()?,
            "window_before" => window(&mut options).before = value.parse()?,
            "window_after" => window(&mut options).after = value.parse()?,
            "per_cell" => per_cell = value.parse()?,
            "hand" => only = value.to_string(),
            "explain" => explain = value != "0",
            "palm_push" => palm_push = value.parse()?,
            "adaptive_speed" => adaptive(&mut options).speed = value.parse()?,
            "adaptive_substeps" => match value.parse()? {
                0 => options.adaptive_step = None,
                n => adaptive(&mut options).substeps = n,
            },
            "early_drop" => options.early_drop = value != "0",
            "verdicts" => verdicts = value != "0",
            _ => return Err(format!("unknown key `{key}`").into()),
        }
    }
    for (name, hand) in [("barrett", hands::barrett()), ("armar3", hands::armar3_hand())] {
        if !only.is_empty() && only != name {
            continue;
        }
        let (mut checked, mut held, mut slipped, mut diverged, mut escaped) = (0, 0, 0, 0, 0);
        // Release pushes (weights) of the failures the grip explains and of the others.
        let mut pushes: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
        // Per class of clamped squeeze (weak? pushed out?): checked and held.
        let mut classes = [[0usize; 2]; 4];
        for common::ObjectSample { object, planners } in common::paper_sample(&hand, per_cell)? {
            let mut line = format!("{name:8} {:17}", object.name);
            for sample in planners {
                let k = sample.grasps.len();
                let mut h = 0;
                for (j, grasp) in sample.grasps.into_iter().enumerate() {
                    let mut grasp = grasp;
                    // The hand moved `palm_push` further along its approach, into the object.
                    grasp.hand_pose *= nalgebra::Translation3::from(hand.approach().into_inner() * palm_push);
                    let grasp = &grasp;
                    let outcome = match physics_check(&hand, &object, grasp, &options) {
                        Ok(outcome) => outcome,
                        // A simulation that blew up holds nothing; counted, and the sweep goes on.
                        Err(GraspError::Core(e @ CoreError::SimulationDiverged { .. })) => {
                            eprintln!("{name} {} grasp {j}: {e}", object.name);
                            diverged += 1;
                            continue;
                        }
                        Err(e) => return Err(e.into()),
                    };
                    h += usize::from(outcome.held());
                    if verdicts {
                        println!("  {name} {} {j}: {:?}", object.name, outcome.results);
                    }
                    if !outcome.held() {
                        escaped += usize::from(outcome.grip_escapes);
                        pushes[usize::from(!outcome.grip_escapes)].push(outcome.release_push);
                    }
                    if explain {
                        let s = clamped_squeeze(&hand, &object, grasp, &options)?;
                        let weight = object.inertial.mass * options.gravity;
                        let (weak, pushed) = (object.friction * s.normal < weight, s.fixture > weight);
                        let class = 2 * usize::from(weak) + usize::from(pushed);
                        classes[class][0] += 1;
                        classes[class][1] += usize::from(outcome.held());
                        println!(
                            "  {:17} {j}: sum N {:7.2} N (palm {:6.2}), mu sum N / mg {:5.2}, fixture / mg {:5.2}, least push / mg {:5.2}, grip moved {:5.3} m {:4.2} rad, deepest {:4.1} mm: {:?}",
                            object.name,
                            s.normal,
                            s.palm,
                            object.friction * s.normal / weight,
                            s.fixture / weight,
                            outcome.release_push,
                            outcome.grip_translation,
                            outcome.grip_rotation,
                            1e3 * s.depth,
                            outcome.result().unwrap_or(HoldResult::Dropped)
                        );
                    }
                    slipped += usize::from(outcome.result() == Some(HoldResult::Slipped));
                }
                checked += k;
                held += h;
                line += &format!("  [{:3}] {h}/{k}", sample.found);
            }
            println!("{line}");
        }
        let rate = 100.0 * held as f64 / checked.max(1) as f64;
        println!("{name}: held {held}/{checked} ({rate:.0} %), slipped {slipped}, diverged {diverged}");
        let failed = checked - held - diverged;
        let median = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
        };
        let (m0, m1) = (median(&mut pushes[0]), median(&mut pushes[1]));
        println!(
            "{name}: of {failed} failures {escaped} explained by the grip (gravity off, it moved the object out; median release push {m0:.1} weights), {} not (median push {m1:.1})",
            failed - escaped
        );
        if explain {
            for (class, label) in
                ["strong, balanced", "strong, pushed out", "weak, balanced", "weak, pushed out"].iter().enumerate()
            {
                println!("{name}: {label:18} held {}/{}", classes[class][1], classes[class][0]);
            }
        }
    }
    Ok(())
}

/// What the physics check's clamped squeeze of one grasp ends with (position or effort control;
/// the balanced-grip modes are not reproduced).
pub struct Squeeze {
    /// Sum of the contacts' normal forces on the object (N).
    pub normal: f64,
    /// The palm's share of it (N). Zero while the object is clamped if the palm is on the
    /// hand's fixed root: rapier makes no contacts between two fixed bodies, so the palm takes
    /// load only once the object is freed.
    pub palm: f64,
    /// Magnitude of the force (N) the fixture holds the object with: the grip's net push
    /// ([`opengrasp_grasp::evaluator::fixture_wrench`], whose probe frees the object, so a palm
    /// it touches is counted).
    pub fixture: f64,
    /// Deepest penetration (m) of a link into the object.
    pub depth: f64,
}

/// Repeats the check's squeeze (`options.settle` with the object clamped) and sums its contacts.
pub fn clamped_squeeze(
    hand: &opengrasp_core::hand::Hand,
    object: &opengrasp_core::object::ObjectModel,
    grasp: &opengrasp_grasp::evaluator::GraspEvaluation,
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
