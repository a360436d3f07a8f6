//! Distance queries that stop as soon as the pair is certainly farther than a threshold, with
//! parry's distance bit for bit whenever it may be below.
//!
//! parry's `query::distance` runs GJK (`gjk::closest_points`) for convex support-map pairs with
//! an unbounded `max_dist`, to convergence. The callers here only use a distance when it is
//! below a bound (a branch-and-bound best, the nearest triangle so far). GJK's iteration is
//! the same for every `max_dist` up to the iteration where its lower bound `min_bound` (the
//! distance of the origin to the supporting plane of the Minkowski difference, below every
//! point of it) exceeds `max_dist`, where it returns early. So with `max_dist` the bound plus
//! [`BEYOND_MARGIN`], an early return proves parry's result (the norm of a point of the
//! Minkowski difference, ≥ `min_bound` up to rounding) above the bound, and otherwise the
//! result is parry's, from the very same arithmetic.
//!
//! The pairs parry answers otherwise (balls, box pairs, segments, half-spaces, composite
//! shapes) keep parry's query, as do shape types not listed in [`SupportShape`]. The
//! common convex types are passed to GJK as concrete types instead of `dyn SupportMap`, so
//! their support functions are inlined (the same floating-point operations, in the same order).

use nalgebra::{Isometry3, Unit, Vector3};
use parry3d_f64::query::gjk::{self, CSOPoint, GJKResult, VoronoiSimplex};
use parry3d_f64::query::{self, DefaultQueryDispatcher, QueryDispatcher};
use parry3d_f64::shape::{ConvexPolyhedron, Cuboid, Cylinder, HalfSpace, Shape as ParryShape, SupportMap, Triangle};

use crate::collision::climbing::ClimbingHull;

/// A pair is reported beyond a bound only if GJK's lower bound exceeds the bound by more than
/// this (m): far above the rounding of GJK's bounds and distances (≈ 1e-16 m at grasp and
/// robot scales).
pub(super) const BEYOND_MARGIN: f64 = 1e-10;

/// The outcome of a bounded distance query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Bounded {
    /// parry's distance, bit for bit (it may still exceed the bound by up to the margin).
    Distance(f64),
    /// The pair is farther than the bound (parry's distance would exceed it).
    Beyond,
    /// parry supports no distance query for this pair.
    Unsupported,
}

impl Bounded {
    /// The distance if it is below `bound`.
    pub(super) fn below(self, bound: f64) -> Option<f64> {
        match self {
            Self::Distance(d) if d < bound => Some(d),
            _ => None,
        }
    }
}

/// parry's `distance_support_map_support_map` (GJK started from `-pos12.translation`) stopped
/// once GJK proves the distance above `max_dist` (`None`); otherwise parry's value bit for bit.
pub(super) fn support_map_distance_within<G1, G2>(
    pos12: &Isometry3<f64>,
    g1: &G1,
    g2: &G2,
    max_dist: f64,
) -> Option<f64>
where
    G1: ?Sized + SupportMap,
    G2: ?Sized + SupportMap,
{
    let mut simplex = VoronoiSimplex::new();
    let dir = -pos12.translation.vector;
    let dir = Unit::try_new(dir, parry3d_f64::math::DEFAULT_EPSILON).unwrap_or_else(Vector3::x_axis);
    simplex.reset(CSOPoint::from_shapes(pos12, g1, g2, &dir));
    match gjk::closest_points(pos12, g1, g2, max_dist, true, &mut simplex) {
        GJKResult::Intersection => Some(0.0),
        GJKResult::ClosestPoints(p1, p2, _) => Some(nalgebra::distance(&p1, &p2)),
        // GJK gives up after 100 iterations with the x axis (parry then reports 0); the same
        // axis from the bound test is ambiguous, so that case reruns parry's own query.
        GJKResult::NoIntersection(axis) if axis == Vector3::x_axis() => {
            Some(query::details::distance_support_map_support_map(pos12, g1, g2))
        }
        GJKResult::NoIntersection(_) => None,
        GJKResult::Proximity(_) => unreachable!("GJK reports proximity only without exact distances"),
    }
}

/// The convex shape types whose GJK queries are monomorphised.
pub(super) enum SupportShape<'a> {
    Cuboid(&'a Cuboid),
    Cylinder(&'a Cylinder),
    Triangle(&'a Triangle),
    Polyhedron(&'a ConvexPolyhedron),
    Climbing(&'a ClimbingHull),
    Other(&'a dyn SupportMap),
}

impl<'a> SupportShape<'a> {
    /// The shape for GJK, when parry's dispatcher sends its pairs with a triangle to GJK
    /// (a support map, neither a ball nor a half-space; not a cuboid paired with a cuboid).
    pub(super) fn against_triangle(shape: &'a dyn ParryShape) -> Option<Self> {
        if shape.as_ball().is_some() || shape.as_shape::<HalfSpace>().is_some() {
            return None;
        }
        Self::of(shape)
    }

    fn of(shape: &'a dyn ParryShape) -> Option<Self> {
        if let Some(c) = shape.as_cuboid() {
            Some(Self::Cuboid(c))
        } else if let Some(c) = shape.as_cylinder() {
            Some(Self::Cylinder(c))
        } else if let Some(t) = shape.as_triangle() {
            Some(Self::Triangle(t))
        } else if let Some(p) = shape.as_convex_polyhedron() {
            Some(Self::Polyhedron(p))
        } else if let Some(h) = shape.as_shape::<ClimbingHull>() {
            Some(Self::Climbing(h))
        } else {
            shape.as_support_map().map(Self::Other)
        }
    }
}

/// [`support_map_distance_within`] with `g2` resolved to a concrete type.
fn within_with<G1: ?Sized + SupportMap>(
    pos12: &Isometry3<f64>,
    g1: &G1,
    g2: &SupportShape<'_>,
    max: f64,
) -> Option<f64> {
    match *g2 {
        SupportShape::Cuboid(s) => support_map_distance_within(pos12, g1, s, max),
        SupportShape::Cylinder(s) => support_map_distance_within(pos12, g1, s, max),
        SupportShape::Triangle(s) => support_map_distance_within(pos12, g1, s, max),
        SupportShape::Polyhedron(s) => support_map_distance_within(pos12, g1, s, max),
        SupportShape::Climbing(s) => support_map_distance_within(pos12, g1, s, max),
        SupportShape::Other(s) => support_map_distance_within(pos12, g1, s, max),
    }
}

/// parry's distance from `tri` to `shape` (resolved by [`SupportShape::against_triangle`]) at
/// `pos12` (the shape in the triangle's frame), `None` when certainly above `bound`.
pub(super) fn triangle_distance_within(
    pos12: &Isometry3<f64>,
    tri: &Triangle,
    shape: &SupportShape<'_>,
    bound: f64,
) -> Option<f64> {
    within_with(pos12, tri, shape, bound + BEYOND_MARGIN)
}

/// The distance `DefaultQueryDispatcher::distance(pos12, s1, s2)` returns, unless it is
/// certainly above `bound` ([`Bounded::Beyond`]): support-map pairs run the bounded GJK of
/// [`support_map_distance_within`], every pair parry treats otherwise keeps parry's query
/// (the same case order as parry's dispatcher).
pub(super) fn distance_within_pos12(
    pos12: &Isometry3<f64>,
    s1: &dyn ParryShape,
    s2: &dyn ParryShape,
    bound: f64,
) -> Bounded {
    let special = s1.as_ball().is_some()
        || s2.as_ball().is_some()
        || (s1.as_cuboid().is_some() && s2.as_cuboid().is_some())
        || (s1.as_segment().is_some() && s2.as_segment().is_some())
        || s1.as_shape::<HalfSpace>().is_some()
        || s2.as_shape::<HalfSpace>().is_some();
    if !special {
        if let (Some(g1), Some(g2)) = (SupportShape::of(s1), SupportShape::of(s2)) {
            let max = bound + BEYOND_MARGIN;
            let d = match g1 {
                SupportShape::Cuboid(s) => within_with(pos12, s, &g2, max),
                SupportShape::Cylinder(s) => within_with(pos12, s, &g2, max),
                SupportShape::Triangle(s) => within_with(pos12, s, &g2, max),
                SupportShape::Polyhedron(s) => within_with(pos12, s, &g2, max),
                SupportShape::Climbing(s) => within_with(pos12, s, &g2, max),
                SupportShape::Other(s) => within_with(pos12, s, &g2, max),
            };
            return d.map_or(Bounded::Beyond, Bounded::Distance);
        }
    }
    DefaultQueryDispatcher.distance(pos12, s1, s2).map_or(Bounded::Unsupported, Bounded::Distance)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Point3, UnitQuaternion};
    use parry3d_f64::shape::{Ball, SharedShape};
    use proptest::prelude::*;

    /// A lathed solid of `n` segments (many support ties on its caps), as a climbing hull.
    fn lathed(n: usize) -> ClimbingHull {
        let mut pts = Vec::new();
        for (z, r) in [(0.0, 0.04), (0.07, 0.05), (0.14, 0.03)] {
            for k in 0..n {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                pts.push(Point3::new(r * a.cos(), r * a.sin(), z));
            }
        }
        ClimbingHull::new(ConvexPolyhedron::from_convex_hull(&pts).expect("hull"))
    }

    fn shapes() -> Vec<SharedShape> {
        let tri = Triangle::new(Point3::new(0.0, 0.0, 0.0), Point3::new(0.05, 0.0, 0.01), Point3::new(0.0, 0.04, 0.0));
        vec![
            SharedShape::cuboid(0.01, 0.02, 0.005),
            SharedShape::cylinder(0.01, 0.015),
            SharedShape::new(tri),
            SharedShape::new(lathed(24).polyhedron().clone()),
            SharedShape::new(lathed(80)),
            SharedShape::capsule_z(0.02, 0.01),
            SharedShape::new(Ball::new(0.01)),
        ]
    }

    /// A box and a triangle 0.1 m apart (the triangle in the plane x = 0.6, facing the box's
    /// face x = 0.5): parry's distance below the bound, "beyond" above it.
    #[test]
    fn box_and_triangle_a_known_distance_apart() {
        let cube = Cuboid::new(Vector3::new(0.5, 0.5, 0.5));
        let tri = Triangle::new(Point3::new(0.6, -0.1, -0.1), Point3::new(0.6, 0.2, -0.1), Point3::new(0.6, 0.0, 0.3));
        let pos12 = Isometry3::identity();
        let parry = DefaultQueryDispatcher.distance(&pos12, &cube, &tri).unwrap();
        assert!((parry - 0.1).abs() < 1e-12, "{parry}");
        assert_eq!(distance_within_pos12(&pos12, &cube, &tri, 0.2), Bounded::Distance(parry));
        assert_eq!(distance_within_pos12(&pos12, &cube, &tri, f64::INFINITY), Bounded::Distance(parry));
        assert_eq!(distance_within_pos12(&pos12, &cube, &tri, 0.05), Bounded::Beyond);
        assert_eq!(Bounded::Distance(parry).below(0.2), Some(parry));
        assert_eq!(Bounded::Distance(parry).below(0.09), None);
        assert_eq!(Bounded::Beyond.below(1.0), None);
        // The triangle path resolves the box once and agrees; the scene turned by a generic
        // rotation (GJK's axis is then no coordinate axis, which would be ambiguous with its
        // give-up answer and rerun parry's query).
        let g = SupportShape::against_triangle(&cube).unwrap();
        let pos_tri = Isometry3::rotation(Vector3::new(0.3, -0.2, 0.1));
        let tri = Triangle::new(pos_tri * tri.a, pos_tri * tri.b, pos_tri * tri.c);
        let from_tri = DefaultQueryDispatcher.distance(&pos_tri, &tri, &cube).unwrap();
        assert_eq!(triangle_distance_within(&pos_tri, &tri, &g, 0.2), Some(from_tri));
        assert!((from_tri - 0.1).abs() < 1e-12, "{from_tri}");
        let far = Isometry3::translation(-0.5, 0.0, 0.0) * pos_tri;
        let from_far = DefaultQueryDispatcher.distance(&far, &tri, &cube).unwrap();
        assert!(from_far > 0.5, "{from_far}");
        assert_eq!(triangle_distance_within(&far, &tri, &g, 0.3), None);
        assert_eq!(triangle_distance_within(&far, &tri, &g, 0.7), Some(from_far));
        // Balls keep parry's query (no GJK): never "beyond", always the distance.
        assert!(SupportShape::against_triangle(&Ball::new(0.1)).is_none());
        let ball = Ball::new(0.5);
        assert_eq!(
            distance_within_pos12(&Isometry3::translation(2.0, 0.0, 0.0), &ball, &cube, 0.1),
            Bounded::Distance(1.0)
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]
        /// Every pair gives parry's distance bit for bit, or "beyond" only when parry's
        /// distance exceeds the bound.
        #[test]
        fn bounded_distance_is_parrys_below_the_bound(
            i in 0usize..7, j in 0usize..7,
            t in prop::array::uniform3(-0.15f64..0.15),
            axis in prop::array::uniform3(-1.0f64..1.0),
            angle in 0.0f64..3.1,
            bound in 0.0f64..0.15,
        ) {
            let shapes = shapes();
            let (s1, s2) = (&*shapes[i].0, &*shapes[j].0);
            let rot = UnitQuaternion::from_scaled_axis(Vector3::from(axis).normalize() * angle);
            let pos12 = Isometry3::from_parts(Vector3::from(t).into(), rot);
            let parry = DefaultQueryDispatcher.distance(&pos12, s1, s2).unwrap();
            match distance_within_pos12(&pos12, s1, s2, bound) {
                Bounded::Distance(d) => prop_assert_eq!(d.to_bits(), parry.to_bits()),
                Bounded::Beyond => prop_assert!(parry > bound, "beyond {bound} at {parry}"),
                Bounded::Unsupported => prop_assert!(false, "supported pair reported unsupported"),
            }
            let unbounded = distance_within_pos12(&pos12, s1, s2, f64::INFINITY);
            prop_assert_eq!(unbounded, Bounded::Distance(parry));
        }
    }
}
