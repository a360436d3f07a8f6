//! Viscous damping of free objects ([`PhysicsEngine::set_object_damping`]): rapier against the
//! analytic decay of its implicit damping and the terminal velocity `F / (m r)` of a pushed
//! body, and the errors for bad rates and handles on both backends; the errors of
//! [`PhysicsEngine::set_contact_frequency`].
#![cfg(feature = "rapier")]

use nalgebra::{Isometry3, Matrix3, Point3, Vector3};
use opengrasp_core::model::{Geometry, Shape};
use opengrasp_core::physics::{MockBackend, PhysicsEngine, PhysicsOptions, RapierBackend};
use opengrasp_core::scene::{ObjectId, Scene, SceneObject};
use opengrasp_core::CoreError;

const MASS: f64 = 0.4;
const INERTIA: f64 = 1e-3;
const H: f64 = 1.0 / 240.0;

/// A 0.4 kg ball (isotropic inertia 1e-3 kg·m²) alone in space, 1 m up.
fn ball() -> Scene {
    let mut scene = Scene::new("damped ball");
    let ball = SceneObject {
        inertia: Matrix3::identity() * INERTIA,
        ..SceneObject::new(
            "ball",
            Isometry3::translation(0.0, 0.0, 1.0),
            vec![Shape::at_origin(Geometry::Sphere { radius: 0.05 })],
            MASS,
        )
    };
    scene.add_object(ball).unwrap();
    scene
}

/// The ball without gravity, stepped once at rest (rapier applies the mass properties in its
/// first step: an impulse before it moves nothing).
fn engine() -> RapierBackend {
    let mut e = RapierBackend::from_scene(&ball(), &PhysicsOptions::default()).unwrap();
    e.set_gravity(Vector3::zeros()).unwrap();
    e.step(H).unwrap();
    e
}

#[test]
fn kicked_ball_decays_as_implicit_viscous_damping() {
    let (linear, angular, n) = (20.0, 5.0, 48usize);
    let mut e = engine();
    e.set_object_damping(ObjectId(0), linear, angular).unwrap();
    // An off-centre kick: v0 = J / m, ω0 = (r × J) / I.
    let (j, r) = (Vector3::new(0.2, 0.0, 0.0), Vector3::new(0.0, 0.05, 0.0));
    e.apply_object_impulse(ObjectId(0), j, Point3::from(Vector3::new(0.0, 0.0, 1.0) + r)).unwrap();
    let (v0, w0) = (j / MASS, r.cross(&j) / INERTIA);
    e.step_n(n, H).unwrap();
    // Each step divides the velocities by 1 + h·rate (rapier's implicit damping).
    let v = e.object_velocity(ObjectId(0)).unwrap();
    let (decay_v, decay_w) = ((1.0 + H * linear).powi(-(n as i32)), (1.0 + H * angular).powi(-(n as i32)));
    assert!((v.linear - v0 * decay_v).norm() < 1e-9 * v0.norm(), "{:?} vs {:?}", v.linear, v0 * decay_v);
    assert!((v.angular - w0 * decay_w).norm() < 1e-9 * w0.norm(), "{:?} vs {:?}", v.angular, w0 * decay_w);
    // ... which is exp(−rate t) to first order in h·rate.
    let t = n as f64 * H;
    assert!((decay_v - (-linear * t).exp()).abs() < 0.5 * H * linear * linear * t * (-linear * t).exp() * 1.2);
    // Travelled h Σ v0 (1 + h r)^-k for k < n.
    let x = e.object_pose(ObjectId(0)).unwrap().translation.x;
    let q = 1.0 / (1.0 + H * linear);
    let expected = H * v0.x * (1.0 - q.powi(n as i32)) / (1.0 - q);
    assert!((x - expected).abs() < 1e-9, "x = {x}, expected {expected}");
    // Zero rates remove the damping: the velocity is then kept.
    e.set_object_damping(ObjectId(0), 0.0, 0.0).unwrap();
    let before = e.object_velocity(ObjectId(0)).unwrap();
    e.step_n(10, H).unwrap();
    let after = e.object_velocity(ObjectId(0)).unwrap();
    assert!((after.linear - before.linear).norm() < 1e-12 && (after.angular - before.angular).norm() < 1e-12);
}

#[test]
fn pushed_damped_ball_drifts_at_terminal_velocity() {
    // A body in a viscous medium of time constant τ pushed by F creeps at F τ / m.
    let (tau, force) = (0.01, Vector3::new(0.0, 3.0, 0.0));
    let mut e = engine();
    e.set_object_damping(ObjectId(0), 1.0 / tau, 1.0 / tau).unwrap();
    e.set_object_force(ObjectId(0), force, Vector3::zeros()).unwrap();
    e.step_n(240, H).unwrap();
    let v = e.object_velocity(ObjectId(0)).unwrap().linear;
    // Discrete fixed point: v = (v + F h / m) / (1 + h / τ), so v = F τ / m exactly.
    let terminal = force * tau / MASS;
    assert!((v - terminal).norm() < 1e-9, "{v:?} vs {terminal:?}");
    // Undamped, the same force would have reached F t / m = 7.5 m/s.
    assert!(v.norm() < 0.01 * force.norm() / MASS);
}

fn rejects_bad_rates<E: PhysicsEngine>(mut e: E) {
    for (l, a) in [(-1.0, 0.0), (0.0, -1e-3), (f64::NAN, 0.0), (0.0, f64::INFINITY)] {
        assert!(matches!(e.set_object_damping(ObjectId(0), l, a), Err(CoreError::InvalidParameter { .. })), "{l}, {a}");
    }
    assert!(matches!(e.set_object_damping(ObjectId(3), 1.0, 1.0), Err(CoreError::InvalidHandle { .. })));
    e.set_object_damping(ObjectId(0), 1.0, 2.0).unwrap();
}

#[test]
fn bad_damping_is_rejected_on_both_backends() {
    rejects_bad_rates(engine());
    rejects_bad_rates(MockBackend::from_scene(&ball(), &PhysicsOptions::default()).unwrap());
}

#[test]
fn contact_frequency_is_checked_and_only_rapier_tunes_it() {
    let mut rapier = engine();
    let mut mock = MockBackend::from_scene(&ball(), &PhysicsOptions::default()).unwrap();
    for bad in [0.0, -30.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(rapier.set_contact_frequency(bad), Err(CoreError::InvalidParameter { .. })));
        assert!(matches!(mock.set_contact_frequency(bad), Err(CoreError::InvalidParameter { .. })));
    }
    assert!(rapier.set_contact_frequency(120.0).is_ok());
    assert!(matches!(mock.set_contact_frequency(120.0), Err(CoreError::Physics { .. })));
}
