//! Tests of the tactile sensor model: mapping, kernel, characteristic, sources, stock layouts.

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Unit, Vector3};
use opengrasp_assets::hands;
use opengrasp_core::kinematics::forward_kinematics;
use opengrasp_core::model::{Geometry, Link, LinkId, RobotBuilder, Shape, TriangleMesh};
use opengrasp_core::object::ObjectModel;
use opengrasp_core::physics::{PhysicsEngine, PhysicsOptions, RapierBackend};
use opengrasp_core::scene::Scene;
use opengrasp_grasp::contact::{ContactModel, ObjectFrame};
use opengrasp_grasp::evaluator::{hand_info, EvaluationStatus, EvaluatorOptions, GraspEvaluation, GraspEvaluator};
use opengrasp_grasp::planners::{palm_pose, GraspCandidate, Preshape};
use opengrasp_grasp::tactile::sources::{
    evaluation_contacts, physics_tactile_series, PhysicsTactile, TactileSeriesOptions,
};
use opengrasp_grasp::tactile::stock::{armar3_specs, barrett_specs, sdh_specs};
use opengrasp_grasp::tactile::{
    LinkContact, MatrixPad, PadReading, PadSpec, TactileArray, TactileFrame, TactileSensor, DSA_9330, DSA_9335,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

mod common;
use common::cylinder_mesh;

const P: f64 = 0.0034;
const L: LinkId = LinkId(0);

/// Pad frame = link frame: a point at the centre of cell (row, column) of a 6-column pad.
fn cell_centre(row: usize, column: usize) -> Point3<f64> {
    Point3::new(0.0, (column as f64 - 2.5) * P, (row as f64 + 0.5) * P)
}

fn read(pad: &MatrixPad, contacts: &[LinkContact]) -> PadReading {
    let mut r = PadReading::default();
    pad.read(contacts, &mut r);
    r
}

fn pad_9335() -> MatrixPad {
    MatrixPad::new("p", L, Isometry3::identity(), DSA_9335).unwrap()
}

#[test]
fn point_force_at_a_cell_centre_lights_that_cell_with_the_characteristic_value() {
    let pad = pad_9335();
    let r = read(&pad, &[LinkContact::point(L, cell_centre(4, 1), 0.5)]);
    let k = 4 * 6 + 1;
    assert!((r.force[k] - 0.5).abs() < 1e-12);
    // p = 0.5 N / (3.4 mm)² = 43.25 kPa; raw = round(4095 · p / 250 kPa) = 708.
    assert!((r.pressure[k] - 0.5 / (P * P)).abs() < 1e-6);
    assert_eq!(r.raw[k], 708);
    assert_eq!(r.active_cells(), 1);
    assert_eq!(DSA_9335.characteristic.raw(0.5 / (P * P)), 708);
}

#[test]
fn force_between_cells_splits_between_them() {
    let pad = pad_9335();
    // On the line between columns 2 and 3 (u = 0), row 6: half each.
    let r = read(&pad, &[LinkContact::point(L, Point3::new(0.0, 0.0, 6.5 * P), 0.4)]);
    assert!((r.force[6 * 6 + 2] - 0.2).abs() < 1e-12 && (r.force[6 * 6 + 3] - 0.2).abs() < 1e-12);
    assert_eq!(r.raw[6 * 6 + 2], r.raw[6 * 6 + 3]);
    assert_eq!(r.active_cells(), 2);
    // At the corner of four cells: a quarter each.
    let r = read(&pad, &[LinkContact::point(L, Point3::new(0.0, P, 3.0 * P), 0.4)]);
    for k in [2 * 6 + 3, 2 * 6 + 4, 3 * 6 + 3, 3 * 6 + 4] {
        assert!((r.force[k] - 0.1).abs() < 1e-12, "cell {k}: {}", r.force[k]);
    }
    // A quarter pitch off the boundary: the patch (half side b) splits by overlap.
    let b = DSA_9335.characteristic.patch_half_side(0.4);
    let r = read(&pad, &[LinkContact::point(L, Point3::new(0.0, 0.25 * P, 6.5 * P), 0.4)]);
    let right = 0.4 * (0.5 + (0.25 * P).min(b) / (2.0 * b));
    assert!((r.force[6 * 6 + 3] - right).abs() < 1e-12, "{} vs {right}", r.force[6 * 6 + 3]);
    assert!((r.total_force() - 0.4).abs() < 1e-12);
}

#[test]
fn cell_forces_sum_to_the_applied_force_inside_the_pad() {
    let pad = pad_9335();
    let mut rng = ChaCha8Rng::seed_from_u64(15);
    for _ in 0..200 {
        let f = rng.random_range(0.01..20.0);
        let b = DSA_9335.characteristic.patch_half_side(f);
        let u = rng.random_range(-3.0 * P + b..3.0 * P - b);
        let s = rng.random_range(b..14.0 * P - b);
        let r = read(&pad, &[LinkContact::point(L, Point3::new(0.0, u, s), f)]);
        assert!((r.total_force() - f).abs() < 1e-9 * f.max(1.0), "{f} N at ({u}, {s}): {}", r.total_force());
    }
    // Two contacts add up; a contact half off the edge loses the half outside.
    let two = [LinkContact::point(L, cell_centre(2, 2), 1.0), LinkContact::point(L, cell_centre(10, 4), 2.0)];
    assert!((read(&pad, &two).total_force() - 3.0).abs() < 1e-12);
    let edge = read(&pad, &[LinkContact::point(L, Point3::new(0.0, 3.0 * P, 7.0 * P), 1.0)]);
    assert!((edge.total_force() - 0.5).abs() < 1e-12);
}

#[test]
fn saturation_at_full_scale() {
    let pad = pad_9335();
    // 2.89 N on one cell is the full-scale 250 kPa; larger forces spread but the centre saturates.
    let r = read(&pad, &[LinkContact::point(L, cell_centre(7, 2), 30.0)]);
    let k = 7 * 6 + 2;
    assert_eq!(r.raw[k], 4095);
    assert!((r.pressure[k] - 250e3).abs() < 1e-6);
    assert!(r.force[k] > 2.89);
    assert!((r.total_force() - 30.0).abs() < 1e-9);
    assert!(r.raw.iter().all(|&v| v <= 4095));
    let ch = DSA_9335.characteristic;
    assert_eq!(ch.raw(ch.full_scale_pressure()), 4095);
    assert_eq!(ch.raw(1e12), 4095);
    assert_eq!(ch.raw(-1.0), 0);
    assert_eq!(ch.raw(f64::NAN), 0);
}

#[test]
fn contacts_off_the_pad_or_invalid_read_nothing() {
    let pad = pad_9335();
    let bad = [
        LinkContact::point(L, Point3::new(-0.02, 0.0, 0.02), 1.0), // back of the finger
        LinkContact::point(L, Point3::new(0.0, 0.05, 0.02), 1.0),  // beside the pad
        LinkContact::point(L, Point3::new(0.0, 0.0, -0.02), 1.0),  // below the first row
        LinkContact::point(L, cell_centre(3, 3), f64::NAN),
        LinkContact::point(L, cell_centre(3, 3), -1.0),
        LinkContact::point(L, Point3::new(f64::NAN, 0.0, 0.01), 1.0),
        LinkContact::point(LinkId(7), cell_centre(3, 3), 1.0), // another link
    ];
    let r = read(&pad, &bad);
    assert_eq!(r.total_force(), 0.0);
    assert_eq!(r.active_cells(), 0);
    assert_eq!(r.ignored, 4); // beside and below the pad: on the surface plane, outside the cells
}

#[test]
fn curved_tip_cells_map_by_arc_length() {
    let pad = MatrixPad::new("tip", L, Isometry3::identity(), DSA_9330).unwrap();
    let g = DSA_9330.geometry;
    let (flat, radius) = (g.flat_length(), g.bend_radius);
    assert!((flat - 8.0 * P).abs() < 1e-12);
    for row in 8..13 {
        let phi = ((row as f64 + 0.5) * P - flat) / radius;
        let point = Point3::new(-radius + radius * phi.cos(), 0.5 * P, flat + radius * phi.sin());
        let r = read(&pad, &[LinkContact::point(L, point, 0.3)]);
        let k = row * 6 + 3;
        assert!((r.force[k] - 0.3).abs() < 1e-9, "row {row}: {:?}", r.force);
        assert_eq!(r.active_cells(), 1);
    }
    // The fingertip's end face (φ = 90°, 17.3 mm of arc) is past the last row (17 mm): half
    // the patch of a point 0.3 mm beyond it is still on the pad... and nothing behind the tip.
    let behind = Point3::new(-2.0 * radius, 0.0, flat + 0.2 * radius);
    assert_eq!(read(&pad, &[LinkContact::point(L, behind, 1.0)]).total_force(), 0.0);
}

#[test]
fn flat_box_resting_on_a_pad_lights_the_expected_rectangle() {
    // A fixed plate (top face z = 0) carrying a DSA 9335 facing up, rows along -x; a 100 g
    // box of 3 × 4 cells (minus 0.2 mm) rests on cells rows 5..9, columns 1..4 under gravity.
    let plate = Link::new("plate")
        .with_shape(Shape::new(Isometry3::translation(0.0, 0.0, -0.005), Geometry::cuboid(0.08, 0.05, 0.01)));
    let robot = Arc::new(RobotBuilder::new("plate").link(plate).build().unwrap());
    let half = 7.0 * P;
    let spec = PadSpec {
        name: "pad".into(),
        link: "plate".into(),
        pose: Isometry3::from_parts(
            nalgebra::Translation3::new(half, 0.0, 0.0),
            nalgebra::UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(
                nalgebra::Matrix3::new(0.0, 0.0, -1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0),
            )),
        ),
        model: DSA_9335,
    };
    let mut scene = Scene::new("box on pad");
    let rid = scene.add_robot("plate", robot.clone(), Isometry3::identity()).unwrap();
    let (sx, sy, sz) = (4.0 * P - 4e-4, 3.0 * P - 4e-4, 0.01);
    let mesh = TriangleMesh::cuboid(Vector3::new(sx, sy, sz)).unwrap();
    let mass = 0.1;
    let object = ObjectModel::from_mesh("box", mesh, mass, 0.8).unwrap();
    // Rows 5..9 ↔ s ∈ [5P, 9P] ↔ x = half − s ∈ [−2P, 2P]; columns 1..4 ↔ y ∈ [−2P, P].
    let centre = Isometry3::translation(0.0, -0.5 * P, 0.5 * sz + 1e-4);
    scene.add_object(object.to_scene_object(centre)).unwrap();
    let hand = opengrasp_core::hand::Hand::from_robot(
        robot,
        opengrasp_core::hand::HandSpec {
            urdf: None,
            palm_link: "plate".into(),
            palm_frame: Isometry3::identity(),
            approach: Vector3::z(),
            preshapes: vec![],
            fingers: vec![opengrasp_core::hand::FingerSpec { name: "plate".into(), links: vec!["plate".into()] }],
            closing: vec![],
            tactile_links: vec!["plate".into()],
            actuation: Default::default(),
        },
    )
    .unwrap();
    let array = TactileArray::from_specs(&hand, &[spec]).unwrap();
    let mut engine = RapierBackend::from_scene(&scene, &PhysicsOptions::default()).unwrap();
    engine.step_n(240, 1.0 / 240.0).unwrap();
    let mut reader = PhysicsTactile::new();
    let mut frame = TactileFrame::default();
    reader.read(&array, &engine, rid, &engine.contacts(), &mut frame).unwrap();
    let r = &frame.pads[0];
    let weight = mass * 9.81;
    assert!((r.total_force() - weight).abs() < 0.05 * weight, "read {} N of {weight}", r.total_force());
    for row in 0..14 {
        for col in 0..6 {
            let inside = (5..9).contains(&row) && (1..4).contains(&col);
            let f = r.force[row * 6 + col];
            if inside {
                assert!(f > 0.5 * weight / 12.0 && f < 1.5 * weight / 12.0, "cell ({row}, {col}): {f}");
            } else {
                assert!(f < 1e-3 * weight, "cell ({row}, {col}) outside: {f}");
            }
        }
    }
}

/// The SDH closing on a 6 cm cylinder from the side (fingers 1, 3 against finger 2), 2 cm
/// standoff, from a half-open preshape (proximal joints opened 0.6 rad, distal bent back):
/// proximal and distal phalanges touch.
fn sdh_cylinder() -> (opengrasp_core::hand::Hand, ObjectModel, GraspEvaluation, ObjectFrame) {
    let hand = hands::sdh();
    let info = hand_info(&hand).unwrap();
    let object = ObjectModel::from_mesh("can", cylinder_mesh(0.03, 0.2, 48), 0.1, 0.8).unwrap();
    let mut ev = GraspEvaluator::new(&hand, &object, EvaluatorOptions::default()).unwrap();
    let approach = Unit::new_normalize(-Vector3::x());
    let candidate = GraspCandidate {
        hand_pose: palm_pose(&info, &Point3::origin(), &approach, &Vector3::y()),
        // Closing joints (proximal, distal) of fingers 1, 2, 3.
        preshape: Preshape::Joints([-0.6, 0.6].repeat(3)),
        approach,
        standoff: 0.02,
    };
    let e = ev.evaluate(&candidate).unwrap();
    let frame = ObjectFrame::from_points(object.center_of_mass(), object.mesh.vertices()).unwrap();
    (hand, object, e, frame)
}

#[test]
fn sdh_grasping_a_cylinder_lights_the_touching_pads_only() {
    let (hand, _, e, frame) = sdh_cylinder();
    assert_eq!(e.status, EvaluationStatus::Closed);
    assert!(e.fingers_in_contact >= 2, "{:?}", e.contacts);
    let array = TactileArray::stock(&hand).unwrap();
    assert_eq!(array.sensors().len(), 6);
    let model = ContactModel { friction: 0.8, ..ContactModel::default() };
    let contacts = evaluation_contacts(&hand, &e, &frame, &model, 10.0).unwrap();
    let total: f64 = contacts.iter().map(|c| c.force).sum();
    assert!((total - 10.0).abs() < 1e-9);
    let tactile = array.read(&contacts);
    let touched: Vec<usize> = e.contacts.iter().map(|c| c.link).collect();
    let mut lit = 0;
    for (s, r) in array.sensors().iter().zip(&tactile.pads) {
        if r.active_cells() > 0 {
            lit += 1;
            assert!(touched.contains(&s.link().0), "pad {} lit without contact", s.name());
        }
    }
    assert_eq!(lit, 5, "{lit} pads lit; contacts {:?}", e.contacts);
    // Every contact on a padded link that maps onto its pad is read in full.
    let read: f64 = tactile.pads.iter().map(|r| r.total_force()).sum();
    assert!(read > 0.5 * total && read <= total + 1e-9, "read {read} of {total} N");
    // Deterministic.
    let again = array.read(&evaluation_contacts(&hand, &e, &frame, &model, 10.0).unwrap());
    assert_eq!(tactile, again);
    // Compact form round-trips through JSON.
    let compact = tactile.compact(&array);
    let json = serde_json::to_string(&compact).unwrap();
    let back: opengrasp_grasp::tactile::CompactFrame = serde_json::from_str(&json).unwrap();
    assert_eq!(back, compact);
    for (c, r) in compact.pads.iter().zip(&tactile.pads) {
        assert_eq!(c.dense(), r.raw.iter().map(|&v| u32::from(v)).collect::<Vec<_>>());
    }
}

#[test]
fn sdh_physics_squeeze_gives_a_tactile_time_series() {
    let (hand, object, e, _) = sdh_cylinder();
    let array = TactileArray::stock(&hand).unwrap();
    let options = TactileSeriesOptions { duration: 0.2, ..Default::default() };
    let series = physics_tactile_series::<RapierBackend>(&hand, &object, &e, &array, &options).unwrap();
    assert_eq!(series.len(), 8);
    assert!(series.windows(2).all(|w| w[0].time < w[1].time));
    let last = series.last().unwrap();
    let touched: Vec<usize> = e.contacts.iter().map(|c| c.link).collect();
    let mut lit = 0;
    for (s, r) in array.sensors().iter().zip(&last.pads) {
        if r.active_cells() > 0 {
            lit += 1;
            assert!(touched.contains(&s.link().0), "pad {} lit in simulation", s.name());
        }
    }
    assert!(lit >= 2, "{lit} pads lit: {:?}", last.pads.iter().map(|r| r.total_force()).collect::<Vec<_>>());
    let again = physics_tactile_series::<RapierBackend>(&hand, &object, &e, &array, &options).unwrap();
    assert_eq!(series, again);
}

/// Every finger pad faces the way its finger closes from the open hand (cosine of the angle
/// above `min_cos`); palm pads face along the approach.
fn check_layout(hand: &opengrasp_core::hand::Hand, specs: &[PadSpec], min_cos: f64) {
    let robot = hand.robot();
    let q = hand.open_configuration();
    let mut q2 = q.clone();
    for (d, v) in hand.closing_velocity().iter().enumerate() {
        q2[d] += 1e-4 * v.signum() * f64::from(u8::from(*v != 0.0));
    }
    robot.clamp_configuration(&mut q2);
    let (fk, fk2) = (forward_kinematics(robot, &q).unwrap(), forward_kinematics(robot, &q2).unwrap());
    for s in specs {
        let l = robot.link_id(&s.link).unwrap().0;
        let mid = s.pose * Point3::new(0.0, 0.0, 0.5 * s.model.geometry.flat_length());
        let normal = fk.as_slice()[l] * (s.pose.rotation * Vector3::x());
        let moved = fk2.as_slice()[l] * mid - fk.as_slice()[l] * mid;
        if l == hand.palm().0 {
            let approach = fk.as_slice()[l] * (hand.palm_frame().rotation * hand.approach().into_inner());
            assert!(normal.dot(&approach) > 0.99, "{} faces {normal:?}", s.name);
        } else {
            assert!(moved.normalize().dot(&normal) > min_cos, "{} faces {normal:?}, moves {moved:?}", s.name);
        }
    }
}

#[test]
fn stock_layouts_fit_the_stock_hands() {
    // Within 37° for the Barrett and the ARMAR-III; within 63° for the SDH, whose open fingers
    // lie flat at their −90° limit with the distal phalanges upright, so closing starts its
    // distal pads moving 59° upwards (cos 59° = 0.51).
    for (hand, specs, pads, min_cos) in [
        (hands::sdh(), sdh_specs(""), 6, 0.45),
        (hands::barrett(), barrett_specs(""), 4, 0.8),
        (hands::armar3_hand(), armar3_specs(""), 15, 0.8),
    ] {
        assert_eq!(specs.len(), pads);
        let array = TactileArray::from_specs(&hand, &specs).unwrap();
        assert_eq!(array.sensors().len(), pads);
        assert_eq!(TactileArray::stock(&hand).unwrap().sensors().len(), pads);
        check_layout(&hand, &specs, min_cos);
        let json = serde_json::to_string(&specs).unwrap();
        assert_eq!(serde_json::from_str::<Vec<PadSpec>>(&json).unwrap(), specs);
    }
    let g = DSA_9335.geometry;
    assert!((g.width() - 0.0204).abs() < 1e-12 && (g.length() - 0.0476).abs() < 1e-12);
}

#[test]
fn benchmark_records_compact_tactile_frames() {
    use opengrasp_grasp::benchmark::{run_grasp_benchmark, CandidateRecord, GraspBenchmarkConfig, TactileRecording};
    let object = ObjectModel::from_mesh("can", cylinder_mesh(0.03, 0.2, 48), 0.1, 0.8).unwrap();
    let config = GraspBenchmarkConfig {
        hands: vec![hands::sdh()],
        objects: vec![object],
        max_candidates: Some(6),
        record_candidates: true,
        tactile: Some(TactileRecording::default()),
        ..Default::default()
    };
    let results = run_grasp_benchmark(&config).unwrap();
    let records: Vec<&CandidateRecord> = results.cells.iter().flat_map(|c| &c.candidates).collect();
    assert!(!records.is_empty());
    let mut lit = 0;
    for r in &records {
        assert_eq!(r.tactile.is_some(), r.status == EvaluationStatus::Closed && r.contacts > 0);
        if let Some(t) = &r.tactile {
            assert_eq!(t.pads.len(), 6);
            lit += usize::from(t.pads.iter().any(|p| !p.cells.is_empty()));
        }
    }
    assert!(lit > 0, "no record has a lit pad");
    // Files without the field still load.
    let mut json: serde_json::Value = serde_json::to_value(records[0]).unwrap();
    json.as_object_mut().unwrap().remove("tactile");
    let old: CandidateRecord = serde_json::from_value(json).unwrap();
    assert_eq!(old.tactile, None);
}
