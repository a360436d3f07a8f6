//! Traces the contact forces of physics hold checks: why does a force-closure grasp hold or not?
//!
//! ```text
//! cargo run --release -p opengrasp-grasp --example physics_trace -- [HAND] [OBJECT] [K|all] [SQUEEZE] [solo]
//! ```
//! HAND is `armar3` (default), `barrett` or `sdh`; OBJECT a stock object (default `salt_can`).
//! The force-closure palm grasps of both reference planners (every `n/200`-th candidate) are
//! listed; `all` runs the hold check on ten of them, spread evenly, and prints the outcomes;
//! `K` (0..9, default 0) traces the K-th of those ten: its evaluator contacts with the share
//! of the grip the force-closure solver gives each (`evaluation_contacts`), then the
//! simulated contact forces per link (with the largest slip speed of its contacts) at the end of the clamped squeeze and every 10 ms for
//! 50 ms after the release, with the net force the contacts put on the object and how far the
//! joints moved; before the simulation, the static torque-limited test's weakest direction with
//! its contact forces and actuator torques. The fingers push with their effort limits
//! ([`PhysicsCheckOptions::effort`]); a SQUEEZE switches to the former position control with
//! that [`PhysicsCheckOptions::squeeze`]; `solo` gives every coupled joint its own full motor
//! (`coupled_actuators` off) for comparison with the shared actuator. The environment variable
//! `CONTACT_HZ` overrides the contact natural frequency (`PhysicsOptions::contact_frequency`),
//! `SQUEEZE` the squeeze, `STIFFNESS=k` the joint motors' stiffness (s⁻², critically damped), `BALANCED=f` switches to the balanced grip torques
//! ([`PhysicsCheckOptions::balanced`], printed with their contact forces), `COMPLIANCE=θ` makes
//! them joint springs ([`PhysicsCheckOptions::grip_compliance`]), `RESOLVE=1` re-solves them on
//! the simulated contacts ([`PhysicsCheckOptions::resolve_grip`]), `RELEASE=s` ramps the
//! fixture's wrench to zero over `s` seconds ([`PhysicsCheckOptions::release`]; the trace then
//! starts at the end of the ramp) and `GRAVITY=x,y,z`
//! (object frame, m/s²) switches gravity on at the release of the traced grasp.

use nalgebra::Vector3;
use opengrasp_assets::{hands, objects};
use opengrasp_core::physics::{ContactBody, PhysicsEngine, RapierBackend};
use opengrasp_core::scene::ObjectId;
use opengrasp_grasp::contact::ObjectFrame;
use opengrasp_grasp::evaluator::{
    after_squeeze, command_grip, grip_torques, physics_check, release_gradually, static_hold, EvaluatorOptions,
    GraspEvaluator, PhysicsCheckOptions, StaticHoldOptions,
};
use opengrasp_grasp::planners::{GraspPlanner, GraspRequest, MedialAxisPlanner, SurfaceNormalPlanner};
use opengrasp_grasp::tactile::sources::{evaluation_contacts, squeeze_engine, TactileSeriesOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let hand = match args.first().map_or("armar3", String::as_str) {
        "barrett" => hands::barrett(),
        "sdh" => hands::sdh(),
        _ => hands::armar3_hand(),
    };
    let object = objects::by_name(args.get(1).map_or("salt_can", String::as_str))?;
    let mut evaluator = GraspEvaluator::new(&hand, &object, EvaluatorOptions::default())?;
    let info = evaluator.hand_info().clone();
    let request = GraspRequest { hand: &info, object: &object.mesh, seed: 0 };
    let mut candidates = MedialAxisPlanner::default().plan(&request)?;
    candidates.extend(SurfaceNormalPlanner::default().plan(&request)?);
    let mut grasps = Vec::new();
    for c in candidates.iter().step_by((candidates.len() / 200).max(1)) {
        let e = evaluator.evaluate(c)?;
        if e.palm_contact && e.force_closure() {
            grasps.push(e);
        }
    }
    println!(
        "{} force-closure palm grasps; object {:.2} kg, μ {}",
        grasps.len(),
        object.inertial.mass,
        object.friction
    );
    if grasps.is_empty() {
        return Ok(());
    }
    let mut options = PhysicsCheckOptions::default();
    if let Some(squeeze) = args.get(3) {
        options.squeeze = squeeze.parse()?;
        options.effort = None;
    }
    options.physics.coupled_actuators = args.get(4).map(String::as_str) != Some("solo");
    if let Ok(hz) = std::env::var("CONTACT_HZ") {
        options.physics.contact_frequency = hz.parse()?;
    }
    if let Ok(k) = std::env::var("STIFFNESS") {
        options.physics.joint_stiffness = k.parse()?;
        options.physics.joint_damping = 2.0 * options.physics.joint_stiffness.sqrt();
    }
    if let Ok(s) = std::env::var("SQUEEZE") {
        options.squeeze = s.parse()?;
    }
    if let Ok(f) = std::env::var("BALANCED") {
        options.balanced = Some(f.parse()?);
    }
    options.resolve_grip = std::env::var("RESOLVE").is_ok_and(|v| v != "0");
    if let Ok(t) = std::env::var("RELEASE") {
        options.release = t.parse()?;
    }
    if let Ok(theta) = std::env::var("COMPLIANCE") {
        options.grip_compliance = Some(theta.parse()?);
    }
    // The hand's own actuator model where none is chosen above, as the check applies it.
    let options = options.for_hand(&hand);
    let pick = |k: usize| &grasps[k * grasps.len() / 10];
    if args.get(2).map(String::as_str) == Some("all") {
        for k in 0..10 {
            let o = physics_check(&hand, &object, pick(k), &options)?;
            println!(
                "grasp {k}: {:?}, grip moved {:.3} m / {:.2} rad, per direction {:.3?} m",
                o.result(),
                o.grip_translation,
                o.grip_rotation,
                o.translations
            );
        }
        return Ok(());
    }
    let grasp = pick(args.get(2).map_or(Ok(0), |s| s.parse())?);
    let robot = hand.robot();
    // The force-closure solver's distribution of a 100 N total normal force over the contacts
    // (forces the evaluator's test assumes the hand can apply), next to each contact.
    let frame = ObjectFrame::from_points(object.center_of_mass(), object.mesh.vertices())?;
    let mut model = EvaluatorOptions::default().quality.contact;
    model.friction = object.friction;
    let solver = evaluation_contacts(&hand, grasp, &frame, &model, 100.0)?;
    for (c, f) in grasp.contacts.iter().zip(&solver) {
        let (p, n) = (c.contact.point, c.contact.normal);
        let name = &robot.link(opengrasp_core::model::LinkId(c.link)).name;
        println!(
            "evaluator contact {name:10} at {:.3?} inward normal {:.2?}; FC solver: {:5.1} % of the grip",
            p.coords.as_slice(),
            n.as_slice(),
            f.force
        );
    }
    // The static torque-limited test: its weakest gravity direction, the forces it finds there
    // at the largest load, and the actuators' torques.
    let statics = static_hold(&hand, &object, grasp, &StaticHoldOptions::default())?;
    let loads: Vec<String> = statics.directions.iter().map(|d| format!("{:.2}", d.load_factor)).collect();
    let weakest = statics.weakest().expect("six directions");
    println!(
        "static test: load factor per direction (±x ±y ±z) [{}]; weakest {:.0?} at {:.2} × the weight",
        loads.join(" "),
        weakest.direction.as_slice(),
        weakest.load_factor
    );
    for (c, f) in grasp.contacts.iter().zip(&weakest.contact_forces) {
        let n = f.dot(&c.contact.normal);
        let name = &robot.link(opengrasp_core::model::LinkId(c.link)).name;
        println!(
            "  static {name:10} normal {n:7.2} N, tangential {:6.2} N",
            (f - c.contact.normal.into_inner() * n).norm()
        );
    }
    for a in &weakest.actuators {
        let name = &robot.joint(robot.dof_joint(a.dof)).name;
        println!("  static actuator {name:14} {:7.3} of {:.3} N·m", a.torque, a.limit);
    }
    let grip = match options.balanced {
        Some(f) => {
            Some(grip_torques(&hand, &object, grasp, f, options.grip_margin, options.physics.coupled_actuators)?)
        }
        None => None,
    };
    if let Some(g) = &grip {
        println!("balanced grip: smallest normal force {:.2} N", g.min_normal);
        for (c, f) in grasp.contacts.iter().zip(&g.contact_forces) {
            let name = &robot.link(opengrasp_core::model::LinkId(c.link)).name;
            println!("  grip {name:10} normal {:7.2} N, force {:.2?}", f.dot(&c.contact.normal), f.as_slice());
        }
        for j in &g.joints {
            let name = &robot.joint(opengrasp_core::model::JointId(j.joint)).name;
            println!("  grip joint {name:14} {:7.3} of {:.3} N·m", j.torque, j.limit);
        }
    }
    let squeeze = TactileSeriesOptions {
        squeeze: options.squeeze,
        effort: if grip.is_some() { None } else { options.effort },
        physics: options.physics.clone(),
        ..Default::default()
    };
    let (mut engine, rid) = squeeze_engine::<RapierBackend>(&hand, &object, grasp, &squeeze)?;
    if let Some(g) = &grip {
        command_grip(&mut engine, rid, &hand, g)?;
    }
    let dt = options.physics.timestep;
    engine.set_object_fixed(ObjectId(0), true)?;
    engine.step_n((options.settle / dt).ceil() as usize, dt)?;
    print_forces("end of the clamped squeeze", &engine, robot, dt, object.friction)?;
    if let Some(g) = &grip {
        let g = after_squeeze(&mut engine, rid, &hand, &object, grasp, g, &options)?;
        if options.resolve_grip {
            for j in &g.joints {
                let name = &robot.joint(opengrasp_core::model::JointId(j.joint)).name;
                println!("  re-solved grip joint {name:14} {:7.3} of {:.3} N·m", j.torque, j.limit);
            }
        }
    }
    let q0 = engine.joint_positions(rid)?;
    println!("joints at the end of the squeeze {q0:.3?} (evaluated {:.3?})", grasp.q);
    release_gradually(&mut engine, ObjectId(0), &object, options.release, dt)?;
    if options.release > 0.0 {
        print_forces(&format!("end of the {} s release", options.release), &engine, robot, dt, object.friction)?;
    }
    if let Ok(g) = std::env::var("GRAVITY") {
        let v: Vec<f64> = g.split(',').map(str::parse).collect::<Result<_, _>>()?;
        engine.set_gravity(Vector3::new(v[0], v[1], v[2]))?;
    }
    for k in 1..=5 {
        engine.step_n((0.01 / dt).ceil() as usize, dt)?;
        print_forces(&format!("{} ms after the release", 10 * k), &engine, robot, dt, object.friction)?;
        let q = engine.joint_positions(rid)?;
        println!("  joints moved {:.3?} rad", q.iter().zip(&q0).map(|(a, b)| a - b).collect::<Vec<_>>());
    }
    Ok(())
}

/// Per link: summed normal force on the object (vector and magnitude), friction magnitude, and
/// the largest slip speed of its contacts: the tangential velocity of the object's material
/// point at the contact relative to the link's (finite difference over one substep of a copy
/// of the engine). Slip near zero while the object moves means the link and object move together
/// at the contact (sticking, or the object rolling about it); slip near the object's speed means
/// sliding. Also the object's speed and spin.
fn print_forces(
    when: &str,
    engine: &RapierBackend,
    robot: &opengrasp_core::model::Robot,
    dt: f64,
    mu: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    let pose = engine.object_pose(ObjectId(0))?;
    let v = engine.object_velocity(ObjectId(0))?;
    println!(
        "{when}: object moved {:.4} m, turned {:.3} rad; speed {:.3} m/s, spin {:.2} rad/s",
        pose.translation.vector.norm(),
        pose.rotation.angle(),
        v.linear.norm(),
        v.angular.norm()
    );
    let mut next = engine.snapshot().ok_or("rapier copies its state")?;
    next.step(dt)?;
    let next_pose = next.object_pose(ObjectId(0))?;
    let mut per_link: Vec<(String, Vector3<f64>, f64, f64, f64)> = Vec::new();
    for c in engine.contacts() {
        let (rid, link, sign) = match (c.body1, c.body2) {
            (ContactBody::Link { robot, link }, ContactBody::Object(_)) => (robot, link, 1.0),
            (ContactBody::Object(_), ContactBody::Link { robot, link }) => (robot, link, -1.0),
            _ => continue,
        };
        // Where the material points at the contact are one substep later, on either body.
        let on_object = next_pose * pose.inverse_transform_point(&c.point);
        let on_link = next.link_pose(rid, link)? * engine.link_pose(rid, link)?.inverse_transform_point(&c.point);
        let d = on_object - on_link;
        let slip = (d - c.normal * d.dot(&c.normal)).norm() / dt;
        let name = robot.link(link).name.clone();
        let i = per_link.iter().position(|l| l.0 == name).unwrap_or_else(|| {
            per_link.push((name, Vector3::zeros(), 0.0, 0.0, 0.0));
            per_link.len() - 1
        });
        per_link[i].1 += c.normal * (sign * c.normal_force);
        per_link[i].2 += c.normal_force;
        per_link[i].3 += c.friction_impulse / dt;
        per_link[i].4 = per_link[i].4.max(slip);
    }
    let mut net = Vector3::zeros();
    for (name, f, n, t, slip) in &per_link {
        net += f;
        println!(
            "  {name:10} normal force {n:6.2} N along {:.2?}, friction {t:6.2} N (μ·N {:6.2}), slip {:.4} m/s",
            f.normalize().as_slice(),
            n * mu,
            slip
        );
    }
    println!("  net normal force on the object {:.2?} N", net.as_slice());
    Ok(())
}
