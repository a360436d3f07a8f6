//! Unit tests of the model's private distance bounds.

use super::geometry::*;
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, UnitQuaternion, Vector3};
use opengrasp_core::model::{Geometry, Shape};
use proptest::prelude::*;

fn placed_box(centre: Vector3<f64>, rot: Rotation3<f64>, h: Vector3<f64>) -> Placed {
    Placed::Box(centre, rot.into_inner(), h)
}

/// Exact box–box distance by sampling is not available, but face-separated axis-aligned
/// boxes have a known gap, and any gap is at most the distance between any two points.
#[test]
fn box_bounds_are_exact_for_face_separated_boxes() {
    let a = placed_box(Vector3::zeros(), Rotation3::identity(), Vector3::new(0.1, 0.2, 0.3));
    let b = placed_box(Vector3::new(0.35, 0.05, -0.1), Rotation3::identity(), Vector3::new(0.05, 0.05, 0.05));
    assert!((distance(&a, &b, f64::INFINITY) - 0.2).abs() < 1e-12);
    let ball = Placed::Ball(Vector3::new(0.0, 0.0, 0.5), 0.1);
    assert!((distance(&a, &ball, f64::INFINITY) - 0.1).abs() < 1e-12);
    // Cylinder along z, radius 0.2, half length 0.1: a point 0.3 out radially and 0.2 above.
    let cyl = Placed::Cylinder(Vector3::zeros(), Matrix3::identity(), 0.2, 0.1);
    let p = Placed::Ball(Vector3::new(0.5, 0.0, 0.3), 0.0);
    assert!((distance(&cyl, &p, f64::INFINITY) - (0.3f64).hypot(0.2)).abs() < 1e-12);
    // A corner-to-corner pair: the bound is positive and at most the corner distance.
    let rot = Rotation3::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_4);
    let c = placed_box(Vector3::new(1.0, 1.0, 0.0), rot, Vector3::new(0.1, 0.1, 0.1));
    let d = distance(&a, &c, f64::INFINITY);
    let corner = Vector3::new(1.0 - 0.1 * std::f64::consts::SQRT_2 / 2.0 * 2.0, 1.0, 0.0);
    assert!(d > 0.0 && d <= (corner - Vector3::new(0.1, 0.2, 0.0)).norm() + 1e-12, "{d}");
}

/// The cylinder–box bound uses the cylinder's own support: an upright cylinder beside a
/// turned box's face or vertical edge gets the exact distance whatever its own yaw (its
/// bounding box would lose up to (√2 − 1) r), and a cylinder pair is bounded through the
/// second one's box.
#[test]
fn upright_cylinder_beside_a_box_gets_the_exact_distance() {
    let (bc, rot, h) =
        (Vector3::new(1.0, 0.5, 0.45), Rotation3::from_euler_angles(0.0, 0.0, 0.4), Vector3::new(0.4, 0.3, 0.45));
    let table = placed_box(bc, rot, h);
    let (r, l) = (0.35, 0.05);
    let edge = Vector3::new(1.0, 1.0, 0.0).normalize();
    for yaw in [0.0, 0.3, std::f64::consts::FRAC_PI_4, 2.0] {
        let upright = Rotation3::from_euler_angles(0.0, 0.0, yaw).into_inner();
        // Beside the +x face, 7 cm away, below mid height.
        let beside = bc + rot * Vector3::new(h.x + 0.07 + r, 0.1, -0.2);
        let d = distance(&Placed::Cylinder(beside, upright, r, l), &table, f64::INFINITY);
        assert!((d - 0.07).abs() < 1e-12, "face, yaw {yaw}: {d}");
        // Beside the (+x, +y) vertical edge, 5 cm away diagonally.
        let corner = bc + rot * (Vector3::new(h.x, h.y, 0.0) + edge * (0.05 + r));
        let d = distance(&table, &Placed::Cylinder(corner, upright, r, l), f64::INFINITY);
        assert!((d - 0.05).abs() < 1e-12, "edge, yaw {yaw}: {d}");
        // A thin upright cylinder 4 cm from the big one's side: its box is 1.5 cm wide.
        let can = Placed::Cylinder(beside + Vector3::new(r + 0.04 + 0.015, 0.0, 0.0), upright, 0.015, 0.1);
        let d = distance(&Placed::Cylinder(beside, upright, r, l), &can, f64::INFINITY);
        assert!(
            d > 0.04 - 0.015 * (std::f64::consts::SQRT_2 - 1.0) - 1e-12 && d <= 0.04 + 1e-12,
            "pair, yaw {yaw}: {d}"
        );
    }
}

/// The balls of a capsule contain it: points on its surface and axis are inside a ball,
/// and no ball reaches farther than 6.8 % of the radius beyond it.
#[test]
fn capsule_balls_contain_the_capsule() {
    let (radius, length) = (0.045, 0.221);
    let origin = Isometry3::translation(0.1, 0.0, -0.2);
    let shape = Shape::new(origin, Geometry::Capsule { radius, length });
    let balls: Vec<(Point3<f64>, f64)> = shape_prims(&shape).iter().map(Prim::bounding_ball).collect();
    assert_eq!(balls.len(), 2 + (length / (CAPSULE_SPACING * radius)).ceil() as usize);
    for k in 0..=400 {
        let z = -0.5 * length - radius + (length + 2.0 * radius) * k as f64 / 400.0;
        for a in 0..24 {
            let angle = a as f64 * std::f64::consts::TAU / 24.0;
            // The capsule's surface point at height z in direction `angle`.
            let axial = z.clamp(-0.5 * length, 0.5 * length);
            let rho = (radius * radius - (z - axial).powi(2)).max(0.0).sqrt();
            let p = origin * Point3::new(rho * angle.cos(), rho * angle.sin(), z);
            assert!(balls.iter().any(|(c, r)| (p - c).norm() <= r + 1e-12), "{p:?} uncovered");
        }
    }
    let reach = balls.iter().map(|(_, r)| r - radius).fold(0.0, f64::max);
    assert!(reach <= 0.068 * radius, "{reach}");
}

proptest! {
    /// Every lower bound is at most the distance between any point of one primitive and
    /// any point of the other (points sampled in each), for random poses.
    #[test]
    fn lower_bounds_never_exceed_point_distances(
        ea in proptest::array::uniform3(-3.0f64..3.0), eb in proptest::array::uniform3(-3.0f64..3.0),
        cb in proptest::array::uniform3(-0.5f64..0.5), ha in proptest::array::uniform3(0.01f64..0.2),
        hb in proptest::array::uniform3(0.01f64..0.2), kinds in 0usize..9, seed in 0u64..1000,
    ) {
        use rand::{Rng, SeedableRng};
        let ra = UnitQuaternion::from_euler_angles(ea[0], ea[1], ea[2]);
        let rb = UnitQuaternion::from_euler_angles(eb[0], eb[1], eb[2]);
        let make = |k: usize, pose: Isometry3<f64>, h: [f64; 3]| match k {
            0 => Prim::Ball(pose * Point3::origin(), h[0]),
            1 => Prim::Box(pose, Vector3::from(h)),
            _ => Prim::Cylinder(pose, h[0], h[1]),
        };
        let pa = make(kinds % 3, Isometry3::from_parts(Default::default(), ra), ha);
        let pb = make(kinds / 3, Isometry3::from_parts(Vector3::from(cb).into(), rb), hb);
        let (a, b) = (Placed::new(&pa, &Isometry3::identity()), Placed::new(&pb, &Isometry3::identity()));
        let d = distance(&a, &b, f64::INFINITY);
        // Points inside each primitive, in its local frame then placed.
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut sample = |p: &Prim| -> Point3<f64> {
            loop {
                let u = Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
                match p {
                    Prim::Ball(c, r) if u.norm() <= 1.0 => return c + u * *r,
                    Prim::Box(pose, h) => return pose * Point3::from(u.component_mul(h)),
                    Prim::Cylinder(pose, r, l) if u.x.hypot(u.y) <= 1.0 => {
                        return pose * Point3::new(u.x * r, u.y * r, u.z * l)
                    }
                    _ => {}
                }
            }
        };
        // The z ranges contain the primitives, and their supports reach them (sampled
        // points come within 15 % of the half height of the extremes).
        let (za, zb) = (a.z_range(), b.z_range());
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for _ in 0..200 {
            let (x, y) = (sample(&pa), sample(&pb));
            prop_assert!(d <= (x - y).norm() + 1e-9, "bound {d} > point distance {}", (x - y).norm());
            prop_assert!(za.0 - 1e-12 <= x.z && x.z <= za.1 + 1e-12, "{} outside {za:?}", x.z);
            prop_assert!(zb.0 - 1e-12 <= y.z && y.z <= zb.1 + 1e-12, "{} outside {zb:?}", y.z);
            lo = lo.min(x.z);
            hi = hi.max(x.z);
        }
        if kinds % 3 == 1 {
            // A box's support along z is attained at a corner: sample the corners too.
            for c in 0..8 {
                let u = Vector3::new(
                    if c & 1 == 0 { -1.0 } else { 1.0 },
                    if c & 2 == 0 { -1.0 } else { 1.0 },
                    if c & 4 == 0 { -1.0 } else { 1.0 },
                );
                let z = (ra * u.component_mul(&Vector3::from(ha))).z;
                lo = lo.min(z);
                hi = hi.max(z);
            }
            prop_assert!((lo - za.0).abs() < 1e-12 && (hi - za.1).abs() < 1e-12, "{lo} {hi} vs {za:?}");
        }
    }
}

/// The folded forward kinematics of the certifier (joints the group does not move as
/// constant transforms, only the models' chains) gives the poses of full forward kinematics.
#[test]
fn folded_kinematics_match_full_kinematics() {
    use opengrasp_core::collision::CollisionWorld;
    use opengrasp_core::kinematics::forward_kinematics_into;
    use opengrasp_core::model::{samples::seven_dof_arm, JointGroup};
    use opengrasp_core::scene::Scene;
    use rand::{Rng, SeedableRng};

    use crate::certify::SphereCertifier;
    use crate::validity::MotionBound;

    let robot = std::sync::Arc::new(seven_dof_arm().unwrap());
    let group = JointGroup::new(&robot, "some", &["joint2", "joint4", "joint5"]).unwrap();
    let mut scene = Scene::new("arm alone");
    let rid = scene.add_robot("arm", robot.clone(), Isometry3::translation(0.3, -0.2, 0.1)).unwrap();
    let world = CollisionWorld::new(&scene).unwrap();
    let bound = MotionBound::from_robot(&robot, &group).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let q_full: Vec<f64> = (0..robot.dof())
        .map(|d| {
            let (lo, hi) = robot.dof_limits(d);
            rng.random_range(lo.max(-3.0)..=hi.min(3.0))
        })
        .collect();
    let certifier = SphereCertifier::new(&scene, rid, &group, &q_full, &bound, &world).unwrap();
    let mut full = Vec::new();
    for _ in 0..50 {
        let q: Vec<f64> = group.limits(&robot).iter().map(|(lo, hi)| rng.random_range(*lo..=*hi)).collect();
        let mut q_all = q_full.clone();
        group.insert(&mut q_all, &q).unwrap();
        forward_kinematics_into(&robot, &q_all, &mut full);
        let folded = certifier.link_poses(&q);
        let mut compared = 0;
        for (i, link) in robot.links().iter().enumerate() {
            if !link.collisions.is_empty() {
                let d = folded[i].inverse() * full[i];
                assert!(d.translation.vector.norm() < 1e-12 && d.rotation.angle() < 1e-12, "link {i}");
                compared += 1;
            }
        }
        assert!(compared >= 7, "{compared}");
    }
}
