//! Why the physics check's failures fail: each benchmark grasp's traced contact forces over the
//! gravity-free control run, and a count per failure class.
//!
//! ```text
//! cargo run --release -p opengrasp-grasp --example physics_classes -- [per_cell=5] [hand=armar3|barrett] [show=OBJECT+ID]
//! ```
//! The grasps are those of `physics_sweep` (the paper's eight objects × both reference planners,
//! `per_cell` force-closure palm grasps each), checked with the default options. For every
//! grasp the check's own settle ([`settle_grip`]) is repeated and its control run (no gravity)
//! traced every 10 ms: the contacts' total normal force `ΣN` (and the palm's share) at the
//! release, the finger links that press at the release and have lost their contact when the
//! object has moved 5 mm (or at the end), and the time the object first moves 2 cm. The
//! static torque-limited test ([`static_hold`]) gives the load factor the same grasp balances
//! with the hand's effort limits. Each failure gets one class:
//!
//! - `gravity`: the control run keeps the object (the grip alone holds), gravity moves it;
//! - `unbalanced`: the control run loses it, and at the release the traced normal forces push
//!   the object with more than one weight whatever friction does inside the cones, the palm
//!   pushing freely ([`PhysicsOutcome::release_push`]);
//! - `lost contact`: the control run loses it from a grip balanced at the release (push ≤ one
//!   weight), and a finger link that pressed at the release has let go by the time the object
//!   moved 5 mm (the object rolls or slides off that finger);
//! - `creep`: as `lost contact`, but every pressing finger link still touches: the object
//!   slides through a grip whose contacts all stay closed.
//!
//! Every grasp prints one line; per hand the table of classes follows, with counts, medians of
//! `μΣN / mg` and of the release push, and up to three example grasps (object, planner index
//! `m` medial axis / `s` surface normal, and the grasp's index). `show=OBJECT+ID` (e.g.
//! `show=bread_box+m0`) also prints that grasp's planned balanced grip, its simulated normal
//! forces at the release, its joints (marking those on a limit) and its contacts every 10 ms
//! for the first 100 ms of the control run; `balanced=f` and `compliance=θ` set those options
//! (0: off) instead of the hand's actuator model. The class table also counts the failures
//! that had a balanced grip at all (the check falls back to position control where none
//! squeezes).

use opengrasp_assets::hands;
use opengrasp_core::error::CoreError;
use opengrasp_core::model::JointId;
use opengrasp_core::physics::{PhysicsEngine, RapierBackend};
use opengrasp_core::scene::ObjectId;
use opengrasp_grasp::error::GraspError;
use opengrasp_grasp::evaluator::{
    grip_torques, physics_check, settle_grip, simulated_contacts, static_hold, GraspEvaluation, PhysicsCheckOptions,
    PhysicsOutcome, StaticHoldOptions,
};

mod common;

/// Object displacement (m) at which the lost contacts are read.
const LOST_AT: f64 = 0.005;
/// Object displacement (m) reported as the time of escape.
const ESCAPE_AT: f64 = 0.02;
/// Trace interval (s).
const EVERY: f64 = 0.01;

/// The traced control run of one grasp.
struct Trace {
    /// Total normal force (N) of the contacts at the release, and the palm's share.
    normal: f64,
    palm: f64,
    /// Finger links pressing at the release that have no contact once the object moved
    /// `LOST_AT` (or at the end of the run).
    lost: Vec<String>,
    /// Time (s) after the release at which the object first moved `ESCAPE_AT`.
    escape: Option<f64>,
    /// The object's speed (m/s) 10 ms after the release.
    kick: f64,
    /// The check pressed a balanced grip (`false`: the hand's actuation has none, or no balanced
    /// grip squeezes and the check fell back to position control).
    balanced: bool,
}

/// Per link, the summed normal force (N) of its contacts with the object.
fn link_forces<E: PhysicsEngine>(
    engine: &E,
    robot: opengrasp_core::scene::RobotId,
    grasp: &GraspEvaluation,
) -> Result<Vec<(usize, f64)>, GraspError> {
    let mut out: Vec<(usize, f64)> = Vec::new();
    for (c, f) in simulated_contacts(engine, robot, ObjectId(0), grasp)? {
        match out.iter_mut().find(|l| l.0 == c.link) {
            Some(l) => l.1 += f,
            None => out.push((c.link, f)),
        }
    }
    Ok(out)
}

fn trace(
    hand: &opengrasp_core::hand::Hand,
    object: &opengrasp_core::object::ObjectModel,
    grasp: &GraspEvaluation,
    options: &PhysicsCheckOptions,
    show: bool,
) -> Result<Trace, GraspError> {
    let options = options.for_hand(hand);
    let settled = settle_grip::<RapierBackend>(hand, object, grasp, &options)?;
    let (mut engine, robot) = (settled.engine, settled.robot);
    let palm = hand.palm().0;
    let start = link_forces(&engine, robot, grasp)?;
    if show {
        describe(hand, object, grasp, &options, &engine, robot, &start)?;
    }
    let pressing: Vec<usize> = start.iter().filter(|l| l.0 != palm && l.1 > 0.01).map(|l| l.0).collect();
    let mut out = Trace {
        normal: start.iter().map(|l| l.1).sum(),
        palm: start.iter().filter(|l| l.0 == palm).map(|l| l.1).sum(),
        lost: Vec::new(),
        escape: None,
        kick: 0.0,
        balanced: match options.balanced {
            Some(f) => {
                grip_torques(hand, object, grasp, f, options.grip_margin, options.physics.coupled_actuators)?.squeezes()
            }
            None => false,
        },
    };
    let origin = engine.object_pose(ObjectId(0))?.translation.vector;
    let dt = options.physics.timestep;
    let chunks = (options.duration / EVERY).round() as usize;
    let mut read = false;
    for k in 1..=chunks {
        engine.step_n((EVERY / dt).round() as usize, dt)?;
        let moved = (engine.object_pose(ObjectId(0))?.translation.vector - origin).norm();
        if k == 1 {
            out.kick = engine.object_velocity(ObjectId(0))?.linear.norm();
        }
        if show && k <= 10 {
            let v = engine.object_velocity(ObjectId(0))?;
            let now = link_forces(&engine, robot, grasp)?;
            let name = |l: usize| hand.robot().link(opengrasp_core::model::LinkId(l)).name.clone();
            let forces: Vec<String> = now.iter().map(|&(l, f)| format!("{} {f:.1}", name(l))).collect();
            println!(
                "  {:3.0} ms: moved {:.4} m, speed {:.3} m/s, spin {:.2} rad/s; normal forces (N) {}",
                1e3 * k as f64 * EVERY,
                moved,
                v.linear.norm(),
                v.angular.norm(),
                forces.join(", ")
            );
        }
        if out.escape.is_none() && moved > ESCAPE_AT {
            out.escape = Some(k as f64 * EVERY);
        }
        if !read && (moved > LOST_AT || k == chunks) {
            read = true;
            let now = link_forces(&engine, robot, grasp)?;
            out.lost = pressing
                .iter()
                .filter(|&&l| !now.iter().any(|n| n.0 == l && n.1 > 0.01))
                .map(|&l| hand.robot().link(opengrasp_core::model::LinkId(l)).name.clone())
                .collect();
        }
    }
    Ok(out)
}

/// Prints the balanced grip's planned normal force per contact link next to the simulated one at
/// the release, and the joints at their limits.
fn describe<E: PhysicsEngine>(
    hand: &opengrasp_core::hand::Hand,
    object: &opengrasp_core::object::ObjectModel,
    grasp: &GraspEvaluation,
    options: &PhysicsCheckOptions,
    engine: &E,
    robot: opengrasp_core::scene::RobotId,
    start: &[(usize, f64)],
) -> Result<(), GraspError> {
    let model = hand.robot();
    let name = |l: usize| model.link(opengrasp_core::model::LinkId(l)).name.clone();
    if let Some(f) = options.balanced {
        let g = grip_torques(hand, object, grasp, f, options.grip_margin, options.physics.coupled_actuators)?;
        for (c, force) in grasp.contacts.iter().zip(&g.contact_forces) {
            let n = force.dot(&c.contact.normal);
            let t = (force - c.contact.normal.into_inner() * n).norm();
            println!("  planned {:10} normal {n:7.2} N tangential {t:6.2} N", name(c.link));
        }
        for j in g.joints.iter().filter(|j| j.torque != 0.0) {
            println!("  planned torque {:16} {:7.3} of {:.3}", model.joint(JointId(j.joint)).name, j.torque, j.limit);
        }
    }
    for &(l, f) in start {
        println!("  simulated {:10} normal {f:7.2} N", name(l));
    }
    let q = engine.joint_positions(robot)?;
    for (d, (&qd, &qe)) in q.iter().zip(&grasp.q).enumerate() {
        let joint = model.joint(model.dof_joint(d));
        let at = joint.limits.map_or("", |l| {
            if qd >= l.upper - 1e-3 {
                " at upper"
            } else if qd <= l.lower + 1e-3 {
                " at lower"
            } else {
                ""
            }
        });
        println!("  dof {:16} q {qd:7.3} (evaluated {qe:7.3}){at}", joint.name);
    }
    Ok(())
}

/// One class of the table: failures, their μΣN/mg and release pushes, examples, how many had a
/// balanced grip, and their speeds 10 ms after the release.
type Row = (usize, Vec<f64>, Vec<f64>, Vec<String>, usize, Vec<f64>);

const CLASSES: [&str; 5] = ["gravity", "unbalanced", "lost contact", "creep", "diverged"];

fn class(outcome: &PhysicsOutcome, t: &Trace) -> usize {
    if !outcome.grip_escapes {
        0
    } else if outcome.release_push > 1.0 {
        1
    } else if !t.lost.is_empty() {
        2
    } else {
        3
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut options = PhysicsCheckOptions::default();
    let (mut per_cell, mut only, mut show) = (5usize, String::new(), String::new());
    for arg in std::env::args().skip(1) {
        match arg.split_once('=') {
            Some(("per_cell", v)) => per_cell = v.parse()?,
            Some(("hand", v)) => only = v.to_string(),
            Some(("balanced", v)) => options.balanced = Some(v.parse()?).filter(|&f: &f64| f > 0.0),
            Some(("compliance", v)) => options.grip_compliance = Some(v.parse()?).filter(|&f: &f64| f > 0.0),
            Some(("show", v)) => show = v.replace('+', " "),
            _ => return Err(format!("expected per_cell=N or hand=NAME, got `{arg}`").into()),
        }
    }
    for (name, hand) in [("barrett", hands::barrett()), ("armar3", hands::armar3_hand())] {
        if !only.is_empty() && only != name {
            continue;
        }
        // Per class: count, μΣN/mg, release pushes, examples.
        let mut table: Vec<Row> =
            (0..CLASSES.len()).map(|_| (0, Vec::new(), Vec::new(), Vec::new(), 0, Vec::new())).collect();
        let (mut checked, mut held, mut held_kicks) = (0, 0, Vec::new());
        for common::ObjectSample { object, planners } in common::paper_sample(&hand, per_cell)? {
            let weight = object.inertial.mass * options.gravity;
            for (p, sample) in planners.iter().enumerate() {
                for (j, grasp) in sample.grasps.iter().enumerate() {
                    checked += 1;
                    let id = format!("{} {}{j}", object.name, ["m", "s"][p]);
                    let outcome = match physics_check(&hand, &object, grasp, &options) {
                        Ok(o) => o,
                        Err(GraspError::Core(CoreError::SimulationDiverged { .. })) => {
                            table[4].0 += 1;
                            table[4].3.push(id);
                            continue;
                        }
                        Err(e) => return Err(e.into()),
                    };
                    let t = trace(&hand, &object, grasp, &options, id.starts_with(&show) && !show.is_empty())?;
                    let load = static_hold(&hand, &object, grasp, &StaticHoldOptions::default())?
                        .weakest()
                        .map_or(0.0, |d| d.load_factor);
                    let verdict = if outcome.held() { "held".to_string() } else { format!("{:?}", outcome.result()) };
                    println!(
                        "{name:8} {id:20} {verdict:14} sum N {:7.2} N (palm {:5.2}), mu sum N / mg {:6.2}, push / mg {:6.2}, static load {:5.2}, grip moved {:.3} m, speed at 10 ms {:.3} m/s, escape {:>6}, balanced {}, lost {:?}",
                        t.normal,
                        t.palm,
                        object.friction * t.normal / weight,
                        outcome.release_push,
                        load,
                        outcome.grip_translation,
                        t.kick,
                        t.escape.map_or("-".to_string(), |s| format!("{s:.2} s")),
                        t.balanced,
                        t.lost
                    );
                    if outcome.held() {
                        held += 1;
                        held_kicks.push(t.kick);
                        continue;
                    }
                    let row = &mut table[class(&outcome, &t)];
                    row.0 += 1;
                    row.1.push(object.friction * t.normal / weight);
                    row.2.push(outcome.release_push);
                    row.4 += usize::from(t.balanced);
                    row.5.push(t.kick);
                    if row.3.len() < 3 {
                        row.3.push(format!("{id} (lost {:?})", t.lost));
                    }
                }
            }
        }
        println!(
            "{name}: held {held}/{checked} (median speed 10 ms after the release {:.3} m/s)",
            median(&mut held_kicks)
        );
        println!("{name}: | class | failures | with a balanced grip | median μΣN/mg | median push/mg | median speed at 10 ms (m/s) | examples |");
        for (label, (n, strength, push, examples, balanced, kick)) in CLASSES.iter().zip(&mut table) {
            println!(
                "{name}: | {label} | {n} | {balanced} | {:.1} | {:.2} | {:.3} | {} |",
                median(strength),
                median(push),
                median(kick),
                examples.join("; ")
            );
        }
    }
    Ok(())
}
