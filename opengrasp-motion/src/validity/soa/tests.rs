//! The upright obstacle kernels against the full rotation, bit for bit.

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;

use super::ObstacleFrame;
use crate::validity::ObstacleShape;

/// The four shapes, sized by `a` and `b` (m).
fn shape(kind: usize, a: f64, b: f64) -> ObstacleShape {
    match kind % 4 {
        0 => ObstacleShape::Box { half_extents: Vector3::new(a, b, 0.5 * (a + b)) },
        1 => ObstacleShape::Sphere { radius: a },
        2 => ObstacleShape::Cylinder { radius: a, half_length: b },
        _ => ObstacleShape::Capsule { radius: a, half_length: b },
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]
    /// Obstacles turned about z only are upright, and their distances and least gaps are
    /// those of the full rotation bit for bit, at points on and off their axes and planes.
    #[test]
    fn upright_distances_equal_full_rotation(
        kind in 0usize..4,
        angle in -4.0..4.0f64,
        (a, b) in (0.01..0.5f64, 0.01..0.5f64),
        t in prop::array::uniform3(-1.0..1.0f64),
        points in prop::collection::vec((prop::array::uniform3(-1.5..1.5f64), 0usize..8, 0.0..0.1f64), 1..20),
    ) {
        let pose = Isometry3::from_parts(Translation3::new(t[0], t[1], t[2]), UnitQuaternion::from_axis_angle(&Vector3::z_axis(), angle));
        let o = ObstacleFrame::new(&pose, shape(kind, a, b));
        prop_assert!(o.upright);
        // Zero offsets from the centre in some coordinates (mask bits), where signs of zeros differ.
        let placed: Vec<([f64; 3], f64)> = points
            .iter()
            .map(|&(p, mask, r)| {
                let at = |i: usize| if mask & (1 << i) == 0 { t[i] + p[i] } else { t[i] };
                ([at(0), at(1), at(2)], r)
            })
            .collect();
        for &([x, y, z], _) in &placed {
            prop_assert_eq!(o.signed_distance(x, y, z).to_bits(), o.signed_distance_in::<false>(x, y, z).to_bits());
        }
        let column = |i: usize| placed.iter().map(|s| s.0[i]).collect::<Vec<f64>>();
        let (xs, ys, zs) = (column(0), column(1), column(2));
        let rs: Vec<f64> = placed.iter().map(|s| s.1).collect();
        prop_assert_eq!(o.min_gap(&xs, &ys, &zs, &rs).to_bits(), o.min_gap_in::<false>(&xs, &ys, &zs, &rs).to_bits());
    }
}

/// The MotionBenchMaker cage's orientation is upright; a tilted one is not.
#[test]
fn cage_orientation_is_upright_and_tilt_is_not() {
    let cage = UnitQuaternion::from_quaternion(Quaternion::new(0.999201106504633, 0.0, 0.0, -0.03996434360673529));
    let h = ObstacleShape::Box { half_extents: Vector3::new(0.35, 0.35, 0.02) };
    assert!(ObstacleFrame::new(&Isometry3::from_parts(Translation3::new(0.74, -0.14, 0.18), cage), h).upright);
    let tilt = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 1e-3);
    assert!(!ObstacleFrame::new(&Isometry3::from_parts(Translation3::identity(), tilt), h).upright);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]
    /// The broad phase over upright boxes and cylinders clears an obstacle exactly when the
    /// signed distance of the sphere's centre exceeds its radius, with that distance's gap,
    /// bit for bit.
    #[test]
    fn upright_solids_clear_exactly_by_signed_distance(
        solids in prop::collection::vec((0usize..2, -4.0..4.0f64, (0.01..0.5f64, 0.01..0.5f64), prop::array::uniform3(-1.0..1.0f64)), 1..12),
        centre in prop::array::uniform3(-1.5..1.5f64),
        radius in 0.0..0.6f64,
    ) {
        let frames: Vec<ObstacleFrame> = solids
            .iter()
            .map(|&(kind, angle, (a, b), t)| {
                let pose = Isometry3::from_parts(Translation3::new(t[0], t[1], t[2]), UnitQuaternion::from_axis_angle(&Vector3::z_axis(), angle));
                ObstacleFrame::new(&pose, shape(2 * kind, a, b))
            })
            .collect();
        let solids = super::far::UprightSolids::new(&frames).expect("upright boxes and cylinders");
        let column = |i: usize| frames.iter().map(|o| o.t[i]).collect::<Vec<f64>>();
        let ts = [column(0), column(1), column(2)];
        let (least, near) = solids.clear_of(centre, radius, [&ts[0], &ts[1], &ts[2]], (0, frames.len()), &mut Vec::new());
        let (mut want, mut want_near) = (f64::INFINITY, 0u64);
        for (i, o) in frames.iter().enumerate() {
            let d = o.signed_distance(centre[0], centre[1], centre[2]);
            if d > radius {
                want = want.min(d - radius);
            } else {
                want_near |= 1 << i;
            }
        }
        prop_assert_eq!(near, want_near);
        prop_assert_eq!(least.to_bits(), want.to_bits());
    }
}

/// Spheres, capsules and tilted solids leave the broad phase to the bounding spheres.
#[test]
fn only_upright_boxes_and_cylinders_make_solids() {
    let up = Isometry3::translation(0.1, 0.2, 0.3);
    let tilt =
        Isometry3::from_parts(Translation3::identity(), UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.1));
    let frame = |pose: &Isometry3<f64>, kind: usize| ObstacleFrame::new(pose, shape(kind, 0.1, 0.2));
    assert!(super::far::UprightSolids::new(&[frame(&up, 0), frame(&up, 2)]).is_some());
    assert!(super::far::UprightSolids::new(&[frame(&up, 0), frame(&up, 1)]).is_none());
    assert!(super::far::UprightSolids::new(&[frame(&up, 0), frame(&up, 3)]).is_none());
    assert!(super::far::UprightSolids::new(&[frame(&tilt, 0)]).is_none());
}
