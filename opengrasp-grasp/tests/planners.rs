//! Tests of the reference grasp planners on analytic meshes.

use std::f64::consts::PI;

use nalgebra::{Point3, Unit, Vector3};
use opengrasp_core::model::TriangleMesh;
use opengrasp_grasp::planners::{
    ApproachSampling, GraspPlanner, GraspRequest, HandInfo, MedialAxis, MedialAxisOptions, MedialAxisPlanner,
    StructureKind, SurfaceNormalOptions, SurfaceNormalPlanner,
};
use opengrasp_grasp::GraspError;

mod common;
use common::cylinder_mesh;

/// A closed box mesh centred at the origin with the given full sizes.
fn box_mesh(sx: f64, sy: f64, sz: f64) -> TriangleMesh {
    let (x, y, z) = (sx / 2.0, sy / 2.0, sz / 2.0);
    let v = vec![
        Point3::new(-x, -y, -z),
        Point3::new(x, -y, -z),
        Point3::new(x, y, -z),
        Point3::new(-x, y, -z),
        Point3::new(-x, -y, z),
        Point3::new(x, -y, z),
        Point3::new(x, y, z),
        Point3::new(-x, y, z),
    ];
    let t = vec![
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [1, 2, 6],
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 0, 4],
        [3, 4, 7],
    ];
    TriangleMesh::new(v, t).unwrap()
}

fn hand() -> HandInfo {
    HandInfo {
        name: "test".into(),
        approach: Unit::new_normalize(Vector3::z()),
        closing: Unit::new_normalize(Vector3::x()),
        preshapes: vec!["open".into()],
        max_aperture: 0.2,
        preshape_apertures: vec![0.2],
    }
}

#[test]
fn meshes_are_closed() {
    assert!(box_mesh(0.1, 0.06, 0.04).is_watertight());
    let c = cylinder_mesh(0.03, 0.2, 32);
    assert!(c.is_watertight());
    assert!(c.signed_volume() > 0.0);
}

#[test]
fn surface_normals_on_a_box_approach_against_the_face_normals() {
    let mesh = box_mesh(0.1, 0.06, 0.04);
    let hand = hand();
    let planner = SurfaceNormalPlanner::default();
    let cands = planner.plan(&GraspRequest { hand: &hand, object: &mesh, seed: 1 }).unwrap();
    // Grid points per face at delta 0.02: ±x 3×2, ±y 5×2, ±z 5×3 → 62; × 4 rolls × 2 standoffs.
    assert_eq!(cands.len(), 62 * 4 * 2);
    let normals = [Vector3::x(), -Vector3::x(), Vector3::y(), -Vector3::y(), Vector3::z(), -Vector3::z()];
    let mut per_face = [0usize; 6];
    for c in &cands {
        let k = normals.iter().position(|n| (c.approach.into_inner() + n).norm() < 1e-9).expect("approach = -normal");
        per_face[k] += 1;
        // The palm's approach axis (z in the palm frame) points along the approach.
        let a = c.hand_pose.rotation * hand.approach.into_inner();
        assert!((a - c.approach.into_inner()).norm() < 1e-9);
        // The palm sits on the face.
        let p = c.hand_pose.translation.vector;
        let half = Vector3::new(0.05, 0.03, 0.02);
        assert!((p.dot(&normals[k]) - half.dot(&normals[k].abs())).abs() < 1e-9);
        assert!(c.standoff == 0.0 || (c.standoff - 0.025).abs() < 1e-12);
    }
    assert_eq!(per_face, [48, 48, 80, 80, 120, 120]);
}

#[test]
fn surface_normal_rolls_are_evenly_spaced() {
    let mesh = box_mesh(0.1, 0.06, 0.04);
    let hand = hand();
    let options = SurfaceNormalOptions { rolls: 8, standoffs: vec![0.0], ..Default::default() };
    let cands = SurfaceNormalPlanner::new(options).plan(&GraspRequest { hand: &hand, object: &mesh, seed: 0 }).unwrap();
    assert_eq!(cands.len(), 62 * 8);
    // The 8 rolls of the first point: closing axes 45° apart, all perpendicular to the approach.
    let closing: Vec<Vector3<f64>> =
        cands[..8].iter().map(|c| c.hand_pose.rotation * hand.closing.into_inner()).collect();
    for k in 0..8 {
        assert!(closing[k].dot(&cands[k].approach).abs() < 1e-9);
        let angle = closing[k].angle(&closing[(k + 1) % 8]);
        assert!((angle - PI / 4.0).abs() < 1e-9, "roll step {angle}");
    }
}

#[test]
fn area_weighted_sampling_is_seeded_and_on_the_surface() {
    let mesh = box_mesh(0.1, 0.06, 0.04);
    let hand = hand();
    let options =
        SurfaceNormalOptions { sampling: ApproachSampling::AreaWeighted { count: 200 }, ..Default::default() };
    let planner = SurfaceNormalPlanner::new(options);
    let a = planner.plan(&GraspRequest { hand: &hand, object: &mesh, seed: 7 }).unwrap();
    let b = planner.plan(&GraspRequest { hand: &hand, object: &mesh, seed: 7 }).unwrap();
    let c = planner.plan(&GraspRequest { hand: &hand, object: &mesh, seed: 8 }).unwrap();
    assert_eq!(a, b);
    assert_ne!(a, c);
    assert_eq!(a.len(), 200 * 8);
    // Points lie on the box surface; faces are hit in proportion to area (±z: 0.006 of 0.0208 m²).
    let mut on_z = 0;
    for cand in a.iter().step_by(8) {
        let p = cand.hand_pose.translation.vector;
        let on_face =
            (p.x.abs() - 0.05).abs() < 1e-9 || (p.y.abs() - 0.03).abs() < 1e-9 || (p.z.abs() - 0.02).abs() < 1e-9;
        assert!(on_face, "{p:?}");
        if (p.z.abs() - 0.02).abs() < 1e-9 {
            on_z += 1;
        }
    }
    let expected = 200.0 * 0.012 / 0.0208;
    assert!((on_z as f64 - expected).abs() < 25.0, "{on_z} vs {expected}");
}

#[test]
fn cylinder_medial_axis_is_its_axis() {
    let (r, len) = (0.03, 0.2);
    let mesh = cylinder_mesh(r, len, 48);
    let h = 0.004;
    let ma = MedialAxis::compute(&mesh, &MedialAxisOptions { voxel_size: Some(h), ..Default::default() }).unwrap();
    assert_eq!(ma.global.kind, StructureKind::SymmetryAxis);
    assert!(ma.global.direction.z.abs() > 0.999, "main axis {:?}", ma.global.direction);
    // Every kept ball is near the axis; its radius is the cylinder's within a voxel.
    let inner: Vec<_> = ma.balls.iter().filter(|b| b.center.z.abs() < len / 2.0 - r).collect();
    assert!(inner.len() >= 30, "{} balls", inner.len());
    for b in &inner {
        let off = b.center.x.hypot(b.center.y);
        assert!(off < h, "ball at {off} m from the axis");
        // The 48-gon's inradius is r·cos(π/48).
        assert!((b.radius - r).abs() < h, "radius {}", b.radius);
    }
    for s in &ma.slices {
        assert_eq!(s.kind, StructureKind::SymmetryAxis);
    }
}

#[test]
fn box_medial_axis_is_its_mid_plane() {
    let mesh = box_mesh(0.2, 0.12, 0.04);
    let h = 0.004;
    let ma = MedialAxis::compute(&mesh, &MedialAxisOptions { voxel_size: Some(h), ..Default::default() }).unwrap();
    assert_eq!(ma.global.kind, StructureKind::SymmetryPlane);
    assert!(ma.global.normal.z.abs() > 0.999, "plane normal {:?}", ma.global.normal);
    for b in &ma.balls {
        assert!(b.center.z.abs() < h, "ball off the mid-plane at z = {}", b.center.z);
        assert!((b.radius - 0.02).abs() < h, "radius {}", b.radius);
    }
    assert!(ma.slices.iter().all(|s| s.kind == StructureKind::SymmetryPlane));
}

#[test]
fn medial_axis_candidates_close_around_the_cylinder() {
    let mesh = cylinder_mesh(0.03, 0.2, 32);
    let hand = hand();
    let planner = MedialAxisPlanner::new(MedialAxisOptions { voxel_size: Some(0.005), ..Default::default() });
    let cands = planner.plan(&GraspRequest { hand: &hand, object: &mesh, seed: 0 }).unwrap();
    let again = planner.plan(&GraspRequest { hand: &hand, object: &mesh, seed: 0 }).unwrap();
    assert_eq!(cands, again);
    let side: Vec<_> = cands.iter().filter(|c| c.approach.z.abs() < 0.05).collect();
    let ends = cands.iter().filter(|c| c.approach.z.abs() > 0.99).count();
    // Axis length 0.2 - 2r covered by 0.01 m slices, 12 directions each; 4 rolls at each end.
    assert_eq!(side.len() % 12, 0);
    assert!(side.len() >= 12 * 12, "{} side candidates", side.len());
    assert_eq!(ends, 8);
    for c in side {
        let p = c.hand_pose.translation.vector;
        assert!(p.x.hypot(p.y) < 0.005, "aims at the axis");
        let closing = c.hand_pose.rotation * hand.closing.into_inner();
        assert!(closing.z.abs() < 0.05 && closing.dot(&c.approach).abs() < 1e-9, "fingers close around the axis");
    }
    // A hand too small for the diameter gets no side grasps.
    let small = HandInfo { max_aperture: 0.05, ..hand };
    let none = planner.plan(&GraspRequest { hand: &small, object: &mesh, seed: 0 }).unwrap();
    assert!(none.iter().all(|c| c.approach.z.abs() > 0.99));
}

#[test]
fn planners_are_object_safe() {
    let planners: Vec<Box<dyn GraspPlanner>> =
        vec![Box::new(SurfaceNormalPlanner::default()), Box::new(MedialAxisPlanner::default())];
    let names: Vec<&str> = planners.iter().map(|p| p.name()).collect();
    assert_eq!(names, ["surface-normals", "medial-axis"]);
    let by_ref: &dyn GraspPlanner = &planners[0];
    assert_eq!(by_ref.name(), "surface-normals");
}

#[test]
fn bad_options_are_errors() {
    let mesh = box_mesh(0.1, 0.06, 0.04);
    let hand = hand();
    let req = GraspRequest { hand: &hand, object: &mesh, seed: 0 };
    let bad = SurfaceNormalPlanner::new(SurfaceNormalOptions {
        sampling: ApproachSampling::BoxGrid { delta: 0.0 },
        ..Default::default()
    });
    assert!(bad.plan(&req).is_err());
    let bad = SurfaceNormalPlanner::new(SurfaceNormalOptions { standoffs: vec![f64::NAN], ..Default::default() });
    assert!(bad.plan(&req).is_err());
    // A negative or infinite standoff is a typed error naming the option, for both planners.
    for s in [-1e-3, f64::INFINITY] {
        let sn = SurfaceNormalPlanner::new(SurfaceNormalOptions { standoffs: vec![0.0, s], ..Default::default() });
        let ma = MedialAxisPlanner::new(MedialAxisOptions { standoffs: vec![s], ..Default::default() });
        for err in [sn.plan(&req).unwrap_err(), ma.plan(&req).unwrap_err()] {
            assert!(matches!(err, GraspError::InvalidParameter { name: "standoffs", .. }), "{err}");
        }
    }
    let bad = MedialAxisPlanner::new(MedialAxisOptions { voxel_size: Some(-1.0), ..Default::default() });
    assert!(bad.plan(&req).is_err());
    // Voxels far larger than the object: nothing inside.
    let coarse = MedialAxisPlanner::new(MedialAxisOptions { voxel_size: Some(1.0), ..Default::default() });
    assert!(coarse.plan(&req).is_err());
}

#[test]
fn medial_axis_candidates_close_across_a_box_mid_plane() {
    let mesh = box_mesh(0.2, 0.12, 0.04);
    let hand = hand();
    let planner = MedialAxisPlanner::new(MedialAxisOptions { voxel_size: Some(0.004), ..Default::default() });
    let cands = planner.plan(&GraspRequest { hand: &hand, object: &mesh, seed: 0 }).unwrap();
    // In-plane approaches (along y towards the box centre) close the fingers along z, across
    // the 4 cm thickness; approaches onto the big faces (along z) close along y.
    let in_plane: Vec<_> = cands.iter().filter(|c| c.approach.y.abs() > 0.99).collect();
    let onto_face: Vec<_> = cands.iter().filter(|c| c.approach.z.abs() > 0.99).collect();
    assert!(!in_plane.is_empty() && in_plane.len() == onto_face.len());
    for c in &in_plane {
        let closing = c.hand_pose.rotation * hand.closing.into_inner();
        assert!(closing.z.abs() > 0.99, "closing {closing:?}");
        assert!(c.hand_pose.translation.vector.z.abs() < 0.004, "aims at the mid-plane");
    }
    for c in &onto_face {
        let closing = c.hand_pose.rotation * hand.closing.into_inner();
        assert!(closing.y.abs() > 0.99, "closing {closing:?}");
    }
}
