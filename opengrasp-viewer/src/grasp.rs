//! Grasp candidates as pictures: the object, the hand in its final (closed) pose coloured by
//! force closure, the contacts and their friction cones.
//!
//! Results files recorded with `run grasp --grasps` keep every candidate's final hand pose
//! and configuration but not its contact points, so the candidate is evaluated again with the
//! shared evaluator (deterministic) and the replay is checked against the record.

use std::f64::consts::TAU;

use nalgebra::{Isometry3, Point3};
use opengrasp_bench::results::{GraspRecord, GraspSection};
use opengrasp_bench::stock::{resolve_hand, resolve_object};
use opengrasp_core::hand::Hand;
use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::object::ObjectModel;
use opengrasp_core::scene::{Scene, SceneObject};
use opengrasp_grasp::benchmark::CandidateRecord;
use opengrasp_grasp::evaluator::{EvaluatorOptions, GraspEvaluation, GraspEvaluator};

use crate::drawing::{Dot, Drawing, Kind, Polyline};
use crate::error::{Result, ViewerError};

/// Hand colour of a force-closure grasp.
pub const FORCE_CLOSURE: [u8; 3] = [40, 170, 80];
/// Hand colour of a grasp without force closure.
pub const NO_FORCE_CLOSURE: [u8; 3] = [230, 120, 40];
/// Colour of the grasped object.
pub const GRASPED_OBJECT: [u8; 3] = [185, 185, 200];
/// Colour of contact points and friction cones.
pub const CONTACT: [u8; 3] = [200, 20, 160];
/// Length of a drawn friction cone (m).
pub const CONE_LENGTH: f64 = 0.03;
/// Edges of a drawn friction cone.
const CONE_EDGES: usize = 8;

/// The id of a candidate: `planner/hand/object/index` (index in the planner's list).
pub fn grasp_id(cell: &GraspRecord, c: &CandidateRecord) -> String {
    format!("{}/{}/{}/{}", cell.cell.planner, cell.cell.hand, cell.cell.object, c.index)
}

/// Finds a recorded candidate by id: `planner/hand/object/index` or its position among all
/// recorded candidates of the file (`0`, `1`, ...).
///
/// # Errors
/// [`ViewerError::UnknownGrasp`] if there is none (also when the file was written without
/// `--grasps`).
pub fn find_grasp<'a>(grasp: &'a GraspSection, id: &str) -> Result<(&'a GraspRecord, &'a CandidateRecord)> {
    let all = || grasp.cells.iter().flat_map(|cell| cell.cell.candidates.iter().map(move |c| (cell, c)));
    let by_index = id.parse::<usize>().ok().and_then(|i| all().nth(i));
    by_index.or_else(|| all().find(|(cell, c)| grasp_id(cell, c) == id)).ok_or_else(|| ViewerError::UnknownGrasp {
        id: id.to_string(),
        available: all().count(),
        example: all()
            .next()
            .map_or_else(|| "(none recorded: run with `opengrasp run grasp --grasps`)".into(), |(g, c)| grasp_id(g, c)),
    })
}

/// The best recorded candidate of a cell: the largest epsilon (the last of equals), `None`
/// if the cell has no recorded candidates.
pub fn best_candidate(cell: &GraspRecord) -> Option<&CandidateRecord> {
    cell.cell.candidates.iter().max_by(|a, b| a.epsilon.total_cmp(&b.epsilon))
}

/// A recorded candidate evaluated again.
pub struct ReplayedGrasp {
    /// The hand.
    pub hand: Hand,
    /// The object.
    pub object: ObjectModel,
    /// The record.
    pub record: CandidateRecord,
    /// The evaluation (contacts in the object frame).
    pub evaluation: GraspEvaluation,
}

/// Evaluates a recorded candidate again with the default evaluator options (those of the
/// benchmark) and checks the final pose, configuration and force closure against the record.
///
/// # Errors
/// [`ViewerError::Results`] for a hand or object that does not resolve;
/// [`ViewerError::ReplayDiffers`] if the evaluation differs from the record.
pub fn replay_grasp(cell: &GraspRecord, record: &CandidateRecord) -> Result<ReplayedGrasp> {
    let hand = resolve_hand(&cell.cell.hand)?;
    let object = resolve_object(&cell.cell.object)?;
    let mut evaluator = GraspEvaluator::new(&hand, &object, EvaluatorOptions::default())?;
    let evaluation = evaluator.evaluate(&record.candidate)?;
    let same_q =
        evaluation.q.len() == record.q.len() && evaluation.q.iter().zip(&record.q).all(|(a, b)| (a - b).abs() <= 1e-9);
    let same_pose = (evaluation.hand_pose.translation.vector - record.hand_pose.translation.vector).norm() <= 1e-9;
    if !same_q || !same_pose || evaluation.force_closure() != record.force_closure {
        return Err(ViewerError::ReplayDiffers {
            run: grasp_id(cell, record),
            what: format!(
                "force closure {} (recorded {}), configuration or pose differs: {}",
                evaluation.force_closure(),
                record.force_closure,
                !(same_q && same_pose)
            ),
        });
    }
    Ok(ReplayedGrasp { hand, object, record: record.clone(), evaluation })
}

/// Pose of the hand's root link that puts its palm frame at `palm` (object frame).
///
/// # Errors
/// [`ViewerError::Core`] if `q` does not fit the hand.
pub fn hand_base_pose(hand: &Hand, q: &[f64], palm: &Isometry3<f64>) -> Result<Isometry3<f64>> {
    let fk = forward_kinematics(hand.robot(), q)?;
    let root_from_palm = fk.as_slice()[hand.palm().0] * hand.palm_frame();
    Ok(palm * root_from_palm.inverse())
}

/// The scene of a grasp (object frame = world frame): the object and the hand at its final
/// pose and configuration.
///
/// # Errors
/// [`ViewerError::Core`] for an invalid configuration.
pub fn grasp_scene(g: &ReplayedGrasp) -> Result<Scene> {
    let mut scene = Scene::new("grasp");
    let object = SceneObject::new(g.object.name.clone(), Isometry3::identity(), vec![g.object.shape()], 1.0);
    scene.add_object(object)?;
    let base = hand_base_pose(&g.hand, &g.record.q, &g.record.hand_pose)?;
    let id = scene.add_robot(g.hand.name().to_string(), g.hand.robot_arc(), base)?;
    scene.set_robot_configuration(id, &g.record.q)?;
    Ok(scene)
}

/// Friction cone edges at a contact: from `CONE_LENGTH` outside the surface to the contact
/// point, at the friction angle `atan(mu)` about the inward normal.
pub fn friction_cone(point: &Point3<f64>, normal: &nalgebra::Unit<nalgebra::Vector3<f64>>, mu: f64) -> Vec<Polyline> {
    let contact = opengrasp_grasp::contact::Contact::from_unit(*point, *normal);
    let (t1, t2) = contact.tangents();
    let apex_to_base = |k: usize| {
        let a = TAU * k as f64 / CONE_EDGES as f64;
        let force = (normal.into_inner() + mu * (a.cos() * t1 + a.sin() * t2)).normalize();
        point - force * CONE_LENGTH
    };
    let mut lines: Vec<Polyline> = (0..CONE_EDGES)
        .map(|k| Polyline { name: format!("edge_{k}"), colour: CONTACT, points: vec![apex_to_base(k), *point] })
        .collect();
    let rim: Vec<Point3<f64>> = (0..=CONE_EDGES).map(|k| apex_to_base(k % CONE_EDGES)).collect();
    lines.push(Polyline { name: "rim".into(), colour: CONTACT, points: rim });
    lines
}

/// The drawing of a grasp: object (grey), hand coloured by force closure, contacts as dots and
/// their friction cones (the object's friction coefficient).
///
/// # Errors
/// As [`grasp_scene`].
pub fn grasp_drawing(g: &ReplayedGrasp) -> Result<Drawing> {
    let mut drawing = Drawing::new();
    drawing.add_scene(&grasp_scene(g)?, Kind::Robot)?;
    let hand_colour = if g.evaluation.force_closure() { FORCE_CLOSURE } else { NO_FORCE_CLOSURE };
    for m in &mut drawing.meshes {
        m.colour = if m.kind == Kind::Robot { hand_colour } else { GRASPED_OBJECT };
    }
    for (i, c) in g.evaluation.contacts.iter().enumerate() {
        drawing.dots.push(Dot { name: format!("contact/{i}"), colour: CONTACT, position: c.contact.point });
        for mut l in friction_cone(&c.contact.point, &c.contact.normal, g.object.friction) {
            l.name = format!("cone/{i}/{}", l.name);
            drawing.lines.push(l);
        }
    }
    Ok(drawing)
}
