//! Tests of the shared grasp evaluator with the asset hands on analytic meshes.

use std::sync::Arc;

use nalgebra::{Point3, Unit, Vector3};
use opengrasp_assets::hands;
use opengrasp_grasp::evaluator::{
    hand_info, physics_check, static_hold, EvaluationStatus, EvaluatorOptions, GraspEvaluation, GraspEvaluator,
    HoldResult, PhysicsCheckOptions, StaticHoldOptions,
};
use opengrasp_grasp::planners::{
    fitting_preshape, palm_pose, GraspCandidate, GraspPlanner, GraspRequest, HandInfo, MedialAxisPlanner, Preshape,
    SurfaceNormalOptions, SurfaceNormalPlanner,
};

mod common;
use common::cylinder_mesh;

/// A 20 cm, 0.1 kg cylinder of radius `radius` (m) with μ = 0.8.
fn cylinder_object(radius: f64) -> opengrasp_assets::objects::ObjectModel {
    opengrasp_assets::objects::ObjectModel::from_mesh("can", cylinder_mesh(radius, 0.2, 32), 0.1, 0.8).unwrap()
}

fn side_grasp(info: &HandInfo) -> GraspCandidate {
    // Hand on the +x side moving towards -x, fingers closing along y around the z axis.
    let approach = Unit::new_normalize(-Vector3::x());
    GraspCandidate {
        hand_pose: palm_pose(info, &Point3::origin(), &approach, &Vector3::y()),
        preshape: Preshape::Default,
        approach,
        standoff: 0.0,
    }
}

#[test]
fn barrett_wraps_a_cylinder_in_force_closure() {
    let hand = hands::barrett();
    let info = hand_info(&hand).unwrap();
    let radius = 0.02;
    let mesh = Arc::new(cylinder_mesh(radius, 0.3, 48));
    let mut ev = GraspEvaluator::from_mesh(&hand, mesh, Point3::origin(), 0.5, EvaluatorOptions::default()).unwrap();
    let e = ev.evaluate(&side_grasp(&info)).unwrap();
    assert_eq!(e.status, EvaluationStatus::Closed);
    // The palm was retracted to the surface: its origin ends about one radius from the axis.
    let p = e.hand_pose.translation.vector;
    assert!((p.x - radius).abs() < 2e-3, "palm at {p:?}");
    assert!(e.palm_contact);
    assert_eq!(e.fingers_in_contact, 3, "{:?}", e.contacts);
    assert!(e.force_closure());
    assert!(e.epsilon() > 0.0);
    for c in &e.contacts {
        // Contacts lie on the cylinder surface with inward (radial) normals.
        let r = c.contact.point.x.hypot(c.contact.point.y);
        assert!((r - radius).abs() < 3e-3, "contact at radius {r}");
    }
}

#[test]
fn hand_info_of_the_stock_hands() {
    // Barrett: palm normal +z, F3 opposite F1/F2 along x.
    let barrett = hand_info(&hands::barrett()).unwrap();
    assert!((barrett.approach.into_inner() - Vector3::z()).norm() < 1e-12);
    assert!(barrett.closing.x.abs() > 0.99, "{:?}", barrett.closing);
    assert!(barrett.max_aperture > 0.1 && barrett.max_aperture < 0.4, "{}", barrett.max_aperture);
    // ARMAR-III: palm normal +x, fingers curl along the palm's long axis z.
    let armar = hand_info(&hands::armar3_hand()).unwrap();
    assert!((armar.approach.into_inner() - Vector3::x()).norm() < 1e-12);
    assert!(armar.closing.z.abs() > 0.9, "{:?}", armar.closing);
    assert_eq!(armar.preshapes[0], "open");
    // Per-preshape apertures along the closing axis: the Barrett's spread swings F1 and F2 off
    // the closing axis (168, 149, 129 mm at 0°, 60°, 90°); the ARMAR-III's power preshape
    // raises the thumb from along the palm (267 mm, wrist to fingertips) to 251 mm.
    let ap = |info: &HandInfo| info.preshape_apertures.clone();
    assert_eq!(barrett.preshapes, ["open", "spherical", "opposed"]);
    let b = ap(&barrett);
    assert!((b[0] - 0.168).abs() < 1e-3 && (b[1] - 0.1489).abs() < 1e-3 && (b[2] - 0.129).abs() < 1e-3, "{b:?}");
    assert!((b[0] - barrett.max_aperture).abs() < 1e-12);
    let a = ap(&armar);
    assert!((a[0] - 0.267).abs() < 1e-3 && (a[1] - 0.2511).abs() < 1e-3, "{a:?}");
    // The surface-normal planner's fitted choice: the tightest aperture with 1 cm clearance
    // per side, else the widest.
    assert_eq!(fitting_preshape(&barrett, 0.10), Preshape::Named("opposed".into()));
    assert_eq!(fitting_preshape(&barrett, 0.12), Preshape::Named("spherical".into()));
    assert_eq!(fitting_preshape(&barrett, 0.14), Preshape::Default);
    assert_eq!(fitting_preshape(&barrett, 0.5), Preshape::Default);
    assert_eq!(fitting_preshape(&armar, 0.2), Preshape::Named("power".into()));
    let unknown = HandInfo { preshape_apertures: Vec::new(), ..armar.clone() };
    assert_eq!(fitting_preshape(&unknown, 0.2), Preshape::Default);
}

#[test]
fn surface_normal_planner_fits_a_preshape_per_candidate_when_none_is_listed() {
    let hand = hands::barrett();
    let info = hand_info(&hand).unwrap();
    // A 4 × 16 cm plate: 4 cm wide (opposed spread fits) or 16 cm wide (only the open hand
    // comes close: the widest) along the closing axis, depending on the roll.
    let mesh = opengrasp_core::model::TriangleMesh::cuboid(Vector3::new(0.16, 0.04, 0.3)).unwrap();
    let fitted = SurfaceNormalPlanner::new(SurfaceNormalOptions { preshapes: Vec::new(), ..Default::default() });
    let candidates = fitted.plan(&GraspRequest { hand: &info, object: &mesh, seed: 0 }).unwrap();
    let default = SurfaceNormalPlanner::default().plan(&GraspRequest { hand: &info, object: &mesh, seed: 0 }).unwrap();
    assert_eq!(candidates.len(), default.len());
    assert!(default.iter().all(|c| c.preshape == Preshape::Default));
    let mut seen = (0, 0);
    for c in &candidates {
        let axis = c.hand_pose.rotation * info.closing.into_inner();
        let (lo, hi) = mesh.vertices().iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v.coords.dot(&axis)), hi.max(v.coords.dot(&axis)))
        });
        assert_eq!(c.preshape, fitting_preshape(&info, hi - lo));
        seen.0 += usize::from(c.preshape == Preshape::Named("opposed".into()));
        seen.1 += usize::from(c.preshape == Preshape::Default);
    }
    assert!(seen.0 > 0 && seen.1 > 0, "{seen:?}");
}

#[test]
fn approach_that_misses_the_object_is_reported() {
    let hand = hands::barrett();
    let info = hand_info(&hand).unwrap();
    let mesh = Arc::new(cylinder_mesh(0.02, 0.2, 32));
    let mut ev = GraspEvaluator::from_mesh(&hand, mesh, Point3::origin(), 0.5, EvaluatorOptions::default()).unwrap();
    // Aimed 0.5 m beside the cylinder.
    let mut c = side_grasp(&info);
    c.hand_pose.translation.vector.y = 0.5;
    let e = ev.evaluate(&c).unwrap();
    assert_eq!(e.status, EvaluationStatus::Missed);
    assert!(e.contacts.is_empty() && !e.force_closure() && e.quality.is_none());
    // Unknown preshape and non-finite poses are errors, not panics.
    let mut bad = side_grasp(&info);
    bad.preshape = Preshape::Named("no such preshape".into());
    assert!(ev.evaluate(&bad).is_err());
    let mut bad = side_grasp(&info);
    bad.hand_pose.translation.vector.x = f64::NAN;
    assert!(ev.evaluate(&bad).is_err());
}

#[test]
fn standoff_keeps_the_palm_off_the_object() {
    let hand = hands::barrett();
    let info = hand_info(&hand).unwrap();
    let radius = 0.02;
    let mesh = Arc::new(cylinder_mesh(radius, 0.3, 48));
    let mut ev = GraspEvaluator::from_mesh(&hand, mesh, Point3::origin(), 0.5, EvaluatorOptions::default()).unwrap();
    let mut c = side_grasp(&info);
    c.standoff = 0.025;
    let e = ev.evaluate(&c).unwrap();
    let p = e.hand_pose.translation.vector;
    assert!((p.x - radius - 0.025).abs() < 2e-3, "palm at {p:?}");
    assert!(!e.palm_contact);
    // Palm contact means touching, as the paper's "palm in direct contact with the object": a
    // palm held 1.5 mm off (within the 2 mm contact margin, so its contact is collected)
    // does not touch (farther than the 1 mm touch distance); 0.5 mm off it does.
    let palm = hand.robot().link_id("palm").unwrap().0;
    let gap = |e: &GraspEvaluation| {
        e.contacts.iter().filter(|c| c.link == palm).map(|c| -c.depth).fold(f64::INFINITY, f64::min)
    };
    c.standoff = 0.0015;
    let off = ev.evaluate(&c).unwrap();
    assert!(gap(&off) > 1e-3 && gap(&off) < 2e-3, "palm gap {}", gap(&off));
    assert!(!off.palm_contact);
    c.standoff = 0.0005;
    let near = ev.evaluate(&c).unwrap();
    assert!(gap(&near) < 1e-3, "palm gap {}", gap(&near));
    assert!(near.palm_contact);
}

#[test]
fn evaluation_is_deterministic_and_planners_share_the_criterion() {
    let hand = hands::armar3_hand();
    let object = opengrasp_assets::objects::by_name("salt_can").unwrap();
    let mut ev = GraspEvaluator::new(&hand, &object, EvaluatorOptions::default()).unwrap();
    let info = ev.hand_info().clone();
    let request = GraspRequest { hand: &info, object: &object.mesh, seed: 3 };
    let planners: [&dyn GraspPlanner; 2] = [&MedialAxisPlanner::default(), &SurfaceNormalPlanner::default()];
    for planner in planners {
        let candidates = planner.plan(&request).unwrap();
        let picked: Vec<_> = candidates.iter().step_by(candidates.len() / 6 + 1).collect();
        let first: Vec<_> = picked.iter().map(|c| ev.evaluate(c).unwrap()).collect();
        let second: Vec<_> = picked.iter().map(|c| ev.evaluate(c).unwrap()).collect();
        assert_eq!(first, second);
        assert!(first.iter().any(|e| e.status == EvaluationStatus::Closed && !e.contacts.is_empty()));
    }
}

#[test]
fn physics_check_holds_a_force_closure_wrap() {
    let hand = hands::barrett();
    let info = hand_info(&hand).unwrap();
    let object = cylinder_object(0.02);
    let mut ev = GraspEvaluator::new(&hand, &object, EvaluatorOptions::default()).unwrap();
    let e = ev.evaluate(&side_grasp(&info)).unwrap();
    assert!(e.force_closure());
    let options = PhysicsCheckOptions { directions: vec![-Vector3::z(), Vector3::y()], ..Default::default() };
    let outcome = physics_check(&hand, &object, &e, &options).unwrap();
    assert_eq!(outcome.held_per_direction.len(), 2);
    assert!(outcome.held(), "{outcome:?}");
    // An open hand that does not squeeze lets the can slide out along its axis.
    let open = GraspEvaluation { q: hand.open_configuration(), ..e.clone() };
    let loose = PhysicsCheckOptions { squeeze: 0.0, directions: vec![-Vector3::z()], ..Default::default() };
    let dropped = physics_check(&hand, &object, &open, &loose).unwrap();
    assert!(!dropped.held(), "{dropped:?}");
}

#[test]
fn physics_check_armar3_hand_holds_a_6cm_cylinder_but_not_a_fingertip_pinch() {
    // The ARMAR-III hand wraps a 6 cm cylinder (palm, four fingers, thumb) and holds it
    // against gravity in every direction. Turned 90° about the approach (cylinder axis along
    // the fingers), the fingertips and the thumb only touch its sides near the palm, without
    // force closure, and the cylinder falls out.
    let hand = hands::armar3_hand();
    let info = hand_info(&hand).unwrap();
    let object = cylinder_object(0.03);
    let mut ev = GraspEvaluator::new(&hand, &object, EvaluatorOptions::default()).unwrap();
    let wrap = ev.evaluate(&side_grasp(&info)).unwrap();
    assert!(wrap.force_closure() && wrap.palm_contact, "{wrap:?}");
    assert!(wrap.fingers_in_contact >= 4, "{wrap:?}");
    let held = physics_check(&hand, &object, &wrap, &PhysicsCheckOptions::default()).unwrap();
    assert!(held.held(), "{held:?}");
    assert!(held.translations.iter().all(|&t| t < 0.015), "{held:?}");
    let approach = Unit::new_normalize(-Vector3::x());
    let turned = GraspCandidate {
        hand_pose: palm_pose(&info, &Point3::origin(), &approach, &Vector3::z()),
        preshape: Preshape::Default,
        approach,
        standoff: 0.0,
    };
    let pinch = ev.evaluate(&turned).unwrap();
    assert!(!pinch.force_closure(), "{pinch:?}");
    let dropped = physics_check(&hand, &object, &pinch, &PhysicsCheckOptions::default()).unwrap();
    assert!(!dropped.held(), "{dropped:?}");
    assert!(dropped.translations.iter().any(|&t| t > 0.5), "{dropped:?}");
    assert_eq!(dropped.result(), Some(HoldResult::Dropped), "{dropped:?}");
    // Every direction is classified by its own displacement.
    for ((&t, &r), &h) in dropped.translations.iter().zip(&dropped.results).zip(&dropped.held_per_direction) {
        assert_eq!(h, r == HoldResult::Held);
        if !h {
            assert_eq!(r == HoldResult::Dropped, t > 0.1, "{t} {r:?}");
        }
    }
}

#[test]
fn small_benchmark_has_the_paper_table_shape() {
    use opengrasp_grasp::benchmark::{run_grasp_benchmark, GraspBenchmarkConfig, GraspBenchmarkResults};
    let config = GraspBenchmarkConfig {
        objects: vec![opengrasp_assets::objects::by_name("salt_box").unwrap()],
        hands: vec![hands::barrett().with_name("barrett")],
        max_candidates: Some(6),
        ..Default::default()
    };
    let results = run_grasp_benchmark(&config).unwrap();
    assert_eq!(results.cells.len(), 2);
    assert_eq!(results.total_evaluated, 12);
    for c in &results.cells {
        assert_eq!(c.evaluated, 6);
        assert!(c.generated >= 6);
        assert!(c.force_closure_palm <= c.palm_contact && c.palm_contact <= c.evaluated);
        assert!((0.0..=100.0).contains(&c.fc_percent_palm));
        // Epsilon statistics cover the same grasps as the FC column: none, no epsilon.
        assert_eq!(c.force_closure_palm == 0, c.mean_epsilon == 0.0, "{c:?}");
        assert!(c.median_epsilon >= 0.0 && c.median_epsilon <= 1.0);
    }
    let table = results.table("barrett");
    // A row per object, a column per planner.
    assert!(
        table.contains("salt_box") && table.contains("medial-axis") && table.contains("surface-normals"),
        "{table}"
    );
    let json = results.to_json().unwrap();
    let back: GraspBenchmarkResults = serde_json::from_str(&json).unwrap();
    assert_eq!(back, results);
    // Same seed, same numbers (timings aside).
    let again = run_grasp_benchmark(&config).unwrap();
    for (a, b) in results.cells.iter().zip(&again.cells) {
        assert_eq!(
            (a.palm_contact, a.force_closure, a.mean_epsilon),
            (b.palm_contact, b.force_closure, b.mean_epsilon)
        );
    }
}

#[test]
fn optional_metrics_friction_score_and_robust_epsilon() {
    let hand = hands::barrett();
    let info = hand_info(&hand).unwrap();
    let mesh = Arc::new(cylinder_mesh(0.02, 0.3, 48));
    let options = EvaluatorOptions {
        friction_score: true,
        robust: Some(opengrasp_grasp::RobustOptions { samples: 8, ..Default::default() }),
        ..Default::default()
    };
    let mut ev = GraspEvaluator::from_mesh(&hand, mesh, Point3::origin(), 0.5, options).unwrap();
    let e = ev.evaluate(&side_grasp(&info)).unwrap();
    assert!(e.force_closure());
    // Force closure at μ = 0.5, so the smallest sufficient μ of the sweep is at most 0.4.
    let mu = e.friction_score.expect("requested").expect("force closure within the sweep");
    assert!(mu <= 0.4 + 1e-12, "friction score {mu}");
    let robust = e.robust_epsilon.expect("requested");
    assert_eq!(robust.samples, 8);
    assert!(robust.mean > 0.0 && robust.force_closure_rate > 0.0);
    // Not requested: absent.
    let mut plain = GraspEvaluator::from_mesh(
        &hand,
        Arc::new(cylinder_mesh(0.02, 0.3, 48)),
        Point3::origin(),
        0.5,
        EvaluatorOptions::default(),
    )
    .unwrap();
    let p = plain.evaluate(&side_grasp(&info)).unwrap();
    assert!(p.friction_score.is_none() && p.robust_epsilon.is_none());
}

#[test]
fn armar3_power_grasp_on_a_6cm_cylinder_is_force_closure() {
    // The thumb, swung out of the palm by its base rotation, pushes the cylinder from the
    // wrist side against the fingers wrapped around it from the fingertip side.
    let hand = hands::armar3_hand();
    let info = hand_info(&hand).unwrap();
    let radius = 0.03;
    let mesh = Arc::new(cylinder_mesh(radius, 0.3, 48));
    let mut ev = GraspEvaluator::from_mesh(&hand, mesh, Point3::origin(), 0.5, EvaluatorOptions::default()).unwrap();
    let mut c = side_grasp(&info);
    c.preshape = Preshape::Named("power".into());
    let e = ev.evaluate(&c).unwrap();
    assert_eq!(e.status, EvaluationStatus::Closed);
    assert!(e.palm_contact, "{:?}", e.contacts);
    let thumb = hand.fingers().iter().position(|f| f.name == "thumb").unwrap();
    assert!(e.contacts.iter().any(|c| c.finger == Some(thumb)), "thumb does not touch: {:?}", e.contacts);
    assert!(e.fingers_in_contact >= 4, "{} fingers touch", e.fingers_in_contact);
    assert!(e.force_closure(), "{:?}", e.quality);
    assert!(e.epsilon() > 0.0);
}

#[test]
fn barrett_power_grasp_holds_a_salt_can_against_gravity_in_all_six_directions() {
    // Palm on the side of the 8 cm salt can at mid-height, fingers wrapped around it.
    let hand = hands::barrett();
    let object = opengrasp_assets::objects::by_name("salt_can").unwrap();
    let mut ev = GraspEvaluator::new(&hand, &object, EvaluatorOptions::default()).unwrap();
    let info = ev.hand_info().clone();
    let mut c = side_grasp(&info);
    c.hand_pose.translation.vector.z = 0.07;
    let e = ev.evaluate(&c).unwrap();
    assert!(e.palm_contact && e.force_closure(), "{:?}", e.quality);
    let options = PhysicsCheckOptions::default();
    assert_eq!(options.directions.len(), 6);
    let outcome = physics_check(&hand, &object, &e, &options).unwrap();
    assert!(outcome.held(), "{outcome:?}");
    assert_eq!(outcome.results, vec![HoldResult::Held; 6]);
    // Deterministic: the same check gives the same displacements to the last bit.
    assert_eq!(physics_check(&hand, &object, &e, &options).unwrap(), outcome);
    assert_eq!(outcome.result(), Some(HoldResult::Held));
    // The squeeze alone creeps the can by 2.6 cm in 0.7 s (the solver artefact the control run
    // cancels), far less than a drop.
    assert!(outcome.grip_translation > 0.005 && outcome.grip_translation < 0.05, "{outcome:?}");
    // The object really is free: without friction (the object's μ is also the links'),
    // gravity along the can's axis pulls it out of the hand.
    let slippery = opengrasp_assets::objects::ObjectModel { friction: 0.0, ..object.clone() };
    let along_axis = PhysicsCheckOptions { directions: vec![-Vector3::z()], ..Default::default() };
    let dropped = physics_check(&hand, &slippery, &e, &along_axis).unwrap();
    assert!(!dropped.held(), "{dropped:?}");
    assert!(dropped.translations[0] > 0.05, "{dropped:?}");
    let expected = if dropped.translations[0] > 0.1 { HoldResult::Dropped } else { HoldResult::Slipped };
    assert_eq!(dropped.result(), Some(expected), "{dropped:?}");
    // The static torque-limited test agrees: with μ = 0.5 the wrap balances the weight in all
    // six directions (with a margin: every load factor above 5); without friction every contact
    // normal is perpendicular to the can's axis, so nothing balances gravity along it (0).
    let statics = static_hold(&hand, &object, &e, &StaticHoldOptions::default()).unwrap();
    assert!(statics.holdable() && statics.weakest().unwrap().load_factor > 5.0, "{statics:?}");
    let axial = StaticHoldOptions { directions: vec![-Vector3::z()], friction: Some(0.0), ..Default::default() };
    let slips = static_hold(&hand, &object, &e, &axial).unwrap();
    assert!(slips.directions[0].load_factor < 1e-6, "{slips:?}");
}

#[test]
fn stall_torque_grip_holds_the_barrett_wrap_but_squeezes_the_armar3_cylinder_out() {
    // The cylinder wraps of the position-control tests above, with the closing motors as
    // stall-torque actuators at their effort limits (stiff 1 kHz contacts, so the 8–60 g
    // phalanges do not sink into the object), and without the check's default joint armature
    // (with 1e-3 kg·m² the heavier fingers do not roll off: the ARMAR-III wrap holds).
    let defaults = PhysicsCheckOptions::default();
    let options = PhysicsCheckOptions {
        effort: Some(1.0),
        physics: opengrasp_core::physics::PhysicsOptions {
            contact_frequency: 1000.0,
            joint_armature: 0.0,
            ..defaults.physics.clone()
        },
        ..defaults
    };
    // Barrett (one actuator per finger, distal joint coupled): held in all six directions,
    // every displacement under 15 mm (measured 1.4–12.2 mm with each finger its own
    // multibody, the check's default `independent_chains`; 1.2–4.9 mm as one multibody: the
    // stall-torque grip is marginal and amplifies rounding).
    let barrett = hands::barrett();
    let can = opengrasp_assets::objects::by_name("salt_can").unwrap();
    let mut ev = GraspEvaluator::new(&barrett, &can, EvaluatorOptions::default()).unwrap();
    let mut c = side_grasp(&ev.hand_info().clone());
    c.hand_pose.translation.vector.z = 0.07;
    let e = ev.evaluate(&c).unwrap();
    let held = physics_check(&barrett, &can, &e, &options).unwrap();
    assert_eq!(held.results, vec![HoldResult::Held; 6], "{held:?}");
    assert!(held.translations.iter().all(|&t| t < 0.015), "{held:?}");
    assert_eq!(physics_check(&barrett, &can, &e, &options).unwrap(), held);
    // ARMAR-III (two actuators per index/middle finger: proximal, and middle+distal coupled):
    // equal stall torques on a finger touching with its tip only are not in equilibrium, so
    // the tips roll round the cylinder to the distal joint limit and the tilted contact
    // normals push it out of the hand without any gravity (measured: 2.4 m in 0.7 s). Position
    // control holds the same grasp (`physics_check_armar3_hand_holds_a_6cm_cylinder_...`).
    let armar = hands::armar3_hand();
    let info = hand_info(&armar).unwrap();
    let cylinder = cylinder_object(0.03);
    let mut ev = GraspEvaluator::new(&armar, &cylinder, EvaluatorOptions::default()).unwrap();
    let wrap = ev.evaluate(&side_grasp(&info)).unwrap();
    // As one multibody the simulation stays finite and throws the cylinder out; with each
    // finger its own multibody (the check's default) the rolling tips blow the simulation up
    // (a body at > 1e6 m/s after 83 ms), which the backend reports as a typed error instead
    // of stepping on into a panic in parry's broad phase.
    let one_multibody = PhysicsCheckOptions {
        physics: opengrasp_core::physics::PhysicsOptions { independent_chains: false, ..options.physics.clone() },
        ..options.clone()
    };
    let out = physics_check(&armar, &cylinder, &wrap, &one_multibody).unwrap();
    assert!(out.grip_translation > 0.1, "{out:?}");
    assert_eq!(out.result(), Some(HoldResult::Dropped), "{out:?}");
    match physics_check(&armar, &cylinder, &wrap, &options) {
        Err(opengrasp_grasp::GraspError::Core(opengrasp_core::CoreError::SimulationDiverged {
            time,
            distance,
            speed,
        })) => assert!(time > 0.0 && time < 1.0 && !(distance <= 1e6 && speed <= 1e6), "{time} {distance} {speed}"),
        other => panic!("expected the divergence error, got {other:?}"),
    }
}

#[test]
fn the_benchmark_records_a_diverged_physics_check_instead_of_failing() {
    // The stall-torque ARMAR-III cylinder wrap of the test above, whose simulation diverges,
    // planned by a one-candidate planner and checked by the benchmark.
    struct Wrap(GraspCandidate);
    impl GraspPlanner for Wrap {
        fn name(&self) -> &str {
            "wrap"
        }
        fn plan(&self, _: &GraspRequest<'_>) -> opengrasp_grasp::Result<Vec<GraspCandidate>> {
            Ok(vec![self.0.clone()])
        }
    }
    let armar = hands::armar3_hand();
    let wrap = Wrap(side_grasp(&hand_info(&armar).unwrap()));
    let defaults = PhysicsCheckOptions::default();
    let physics = PhysicsCheckOptions {
        effort: Some(1.0),
        physics: opengrasp_core::physics::PhysicsOptions {
            contact_frequency: 1000.0,
            joint_armature: 0.0,
            ..defaults.physics.clone()
        },
        ..defaults
    };
    let config = opengrasp_grasp::benchmark::GraspBenchmarkConfig {
        hands: vec![armar],
        objects: vec![cylinder_object(0.03)],
        physics_per_cell: 1,
        physics,
        record_candidates: true,
        ..Default::default()
    };
    let results = opengrasp_grasp::benchmark::run_grasp_benchmark_with(&config, &[&wrap]).unwrap();
    let cell = &results.cells[0];
    let counts = (cell.force_closure_palm, cell.physics_tested, cell.physics_diverged, cell.physics_held);
    assert_eq!(counts, (1, 1, 1, 0), "{cell:?}");
    assert_eq!((cell.physics_slipped, cell.physics_dropped, cell.physics_grip_moved, cell.static_agree), (0, 0, 0, 0));
    assert_eq!(cell.candidates[0].physics_held, Some(false));
    // The count is written only when not 0, so records without divergences read as before.
    let json = serde_json::to_value(cell).unwrap();
    assert_eq!(json["physics_diverged"], 1);
    let quiet = opengrasp_grasp::benchmark::CellResult { physics_diverged: 0, ..cell.clone() };
    assert!(serde_json::to_value(&quiet).unwrap().get("physics_diverged").is_none());
}
