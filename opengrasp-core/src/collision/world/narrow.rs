//! Narrow-phase tests between two placed shapes: intersection, exact distance (with the
//! closed-form capsule–box case) and bounding-box distance.

use nalgebra::Isometry3;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::query;
use parry3d_f64::shape::Shape as ParryShape;

use super::bounded::{distance_within_pos12, support_map_distance_within, Bounded, BEYOND_MARGIN};

/// Euclidean distance between two AABBs (0 when they overlap): a lower bound of the distance
/// between anything they contain.
pub(super) fn aabb_distance(a: &Aabb, b: &Aabb) -> f64 {
    let lo = b.mins - a.maxs;
    let hi = a.mins - b.maxs;
    let gap = lo.sup(&hi).sup(&nalgebra::Vector3::zeros());
    gap.norm()
}

/// Conservative intersection test: an unsupported shape pair falls back to the distance query,
/// and counts as colliding if that is unsupported too. Convex shapes against triangle meshes
/// skip the triangles certainly clear of the shape (`mesh_distance::mesh_intersects`, parry's
/// answer).
pub(super) fn intersects(p1: &Isometry3<f64>, s1: &dyn ParryShape, p2: &Isometry3<f64>, s2: &dyn ParryShape) -> bool {
    if let Some(hit) = super::mesh_distance::mesh_intersects(p1, s1, p2, s2) {
        return hit;
    }
    match query::intersection_test(p1, s1, p2, s2) {
        Ok(hit) => hit,
        Err(_) => distance(p1, s1, p2, s2).is_none_or(|d| d <= 0.0),
    }
}

/// Slack (m) of the hull pre-check of [`distance_below_hinted`], plus [`HULL_SLACK_RELATIVE`]
/// of the bound: room for GJK's tolerance (relative ~5e-8) between a hull's distance estimate
/// and the contained shape's where they share the nearest feature.
const HULL_SLACK_ABSOLUTE: f64 = 1e-9;

/// The part of the hull pre-check's slack proportional to the bound.
const HULL_SLACK_RELATIVE: f64 = 1e-7;

/// A placed shape with an optional convex stand-in that contains it (the hull of a triangle
/// mesh), used to rule out pairs cheaply.
#[derive(Clone, Copy)]
pub(super) struct Placed<'a> {
    pub pose: &'a Isometry3<f64>,
    pub shape: &'a dyn ParryShape,
    pub hull: Option<&'a dyn ParryShape>,
}

impl<'a> Placed<'a> {
    fn outer(&self) -> &'a dyn ParryShape {
        self.hull.unwrap_or(self.shape)
    }
}

/// [`intersects`], first testing the hulls when either shape has one: shapes inside
/// separated hulls cannot intersect.
pub(super) fn intersects_placed(a: Placed<'_>, b: Placed<'_>) -> bool {
    if (a.hull.is_some() || b.hull.is_some()) && !intersects(a.pose, a.outer(), b.pose, b.outer()) {
        return false;
    }
    intersects(a.pose, a.shape, b.pose, b.shape)
}

/// [`distance`] when it is below `bound`, `None` otherwise (or for unsupported pairs). When
/// either shape has a hull, the hulls' distance (a lower bound) is computed first and the
/// exact query is skipped if it already reaches `bound`. The value returned is always the
/// exact distance. With an infinite `bound` nothing can be ruled out, so the hulls are not
/// queried (the first query of a branch-and-bound search, or one link's only part). Both
/// queries stop early once GJK proves the pair beyond `bound` (see [`super::bounded`]).
///
/// A triangle-mesh pair's search is warm-started from the triangle `hint` when there is one
/// (the same result; see `mesh_distance::mesh_distance_hinted`).
pub(super) fn distance_below_hinted(a: Placed<'_>, b: Placed<'_>, bound: f64, hint: Option<&mut u32>) -> Option<f64> {
    if (a.hull.is_some() || b.hull.is_some()) && bound < f64::INFINITY {
        // The hulls' distance is a lower bound only up to GJK's tolerance: where the shape's
        // nearest feature lies on its hull, the hull's estimate can exceed the shape's own by
        // that much, so the pair is ruled out only beyond the bound plus that slack.
        let rule_out = bound + HULL_SLACK_ABSOLUTE + HULL_SLACK_RELATIVE * bound.abs();
        match distance_within(a.pose, a.outer(), b.pose, b.outer(), rule_out) {
            Bounded::Beyond => return None,
            Bounded::Distance(lb) if lb >= rule_out => return None,
            _ => {}
        }
    }
    if let Some(d) = super::mesh_distance::mesh_distance_hinted(a.pose, a.shape, b.pose, b.shape, bound, hint) {
        return d;
    }
    distance_within(a.pose, a.shape, b.pose, b.shape, bound).below(bound)
}

/// [`distance`] unless the pair is certainly farther than `bound` ([`Bounded::Beyond`]); the
/// same value bit for bit otherwise.
pub(super) fn distance_within(
    p1: &Isometry3<f64>,
    s1: &dyn ParryShape,
    p2: &Isometry3<f64>,
    s2: &dyn ParryShape,
    bound: f64,
) -> Bounded {
    if let (Some(c1), Some(c2)) = (s1.as_cuboid(), s2.as_cuboid()) {
        let d = support_map_distance_within(&p1.inv_mul(p2), c1, c2, bound + BEYOND_MARGIN);
        return d.map_or(Bounded::Beyond, Bounded::Distance);
    }
    if s1.as_capsule().is_some() && s2.as_cuboid().is_some() || s1.as_cuboid().is_some() && s2.as_capsule().is_some() {
        return distance(p1, s1, p2, s2).map_or(Bounded::Unsupported, Bounded::Distance);
    }
    distance_within_pos12(&p1.inv_mul(p2), s1, s2, bound)
}

/// Exact distance (0 when overlapping), `None` for unsupported shape pairs.
///
/// parry3d 0.25.3's cuboid–cuboid distance (`distance_cuboid_cuboid`) transforms the second
/// witness point twice and over-estimates separations, so box pairs go through GJK instead.
/// Capsule–cuboid pairs (robot links against boxes, the common case) use the closed form of
/// [`capsule_cuboid_distance`], several times faster than GJK.
pub(super) fn distance(
    p1: &Isometry3<f64>,
    s1: &dyn ParryShape,
    p2: &Isometry3<f64>,
    s2: &dyn ParryShape,
) -> Option<f64> {
    if let (Some(c1), Some(c2)) = (s1.as_cuboid(), s2.as_cuboid()) {
        return Some(query::details::distance_support_map_support_map(&p1.inv_mul(p2), c1, c2));
    }
    if let (Some(c), Some(b)) = (s1.as_capsule(), s2.as_cuboid()) {
        return Some(capsule_cuboid_distance(p1, c, p2, b));
    }
    if let (Some(b), Some(c)) = (s1.as_cuboid(), s2.as_capsule()) {
        return Some(capsule_cuboid_distance(p2, c, p1, b));
    }
    query::distance(p1, s1, p2, s2).ok()
}

/// Distance between a capsule and a cuboid (0 when they overlap), in closed form.
///
/// In the box frame, the squared distance from the capsule's axis point `p(t) = a + t d` to the
/// box is `Σᵢ max(|pᵢ(t)| − hᵢ, 0)²`: convex and quadratic between the parameters where a
/// coordinate crosses a face plane (`pᵢ(t) = ±hᵢ`). Minimising the quadratic on each of these
/// (at most seven) intervals gives the axis–box distance exactly; the capsule radius is then
/// subtracted.
pub(super) fn capsule_cuboid_distance(
    capsule_pose: &Isometry3<f64>,
    capsule: &parry3d_f64::shape::Capsule,
    box_pose: &Isometry3<f64>,
    cuboid: &parry3d_f64::shape::Cuboid,
) -> f64 {
    let to_box = box_pose.inv_mul(capsule_pose);
    let a = to_box * capsule.segment.a;
    let d = to_box * capsule.segment.b - a;
    let h = cuboid.half_extents;
    let mut breaks = [0.0_f64; 8];
    let mut n = 0;
    breaks[n] = 0.0;
    n += 1;
    for i in 0..3 {
        if d[i] != 0.0 {
            for face in [-h[i], h[i]] {
                let t = (face - a[i]) / d[i];
                if t > 0.0 && t < 1.0 {
                    breaks[n] = t;
                    n += 1;
                }
            }
        }
    }
    breaks[n] = 1.0;
    n += 1;
    let breaks = &mut breaks[..n];
    breaks.sort_unstable_by(f64::total_cmp);
    let sq_dist = |t: f64| -> f64 {
        (0..3)
            .map(|i| {
                let excess = (a[i] + t * d[i]).abs() - h[i];
                if excess > 0.0 {
                    excess * excess
                } else {
                    0.0
                }
            })
            .sum()
    };
    let mut best = sq_dist(0.0).min(sq_dist(1.0));
    for w in breaks.windows(2) {
        let (t0, t1) = (w[0], w[1]);
        if t1 <= t0 {
            continue;
        }
        // Active faces are fixed on the interval: g(t) = Σ (c + t e)² over active axes.
        let mid = 0.5 * (t0 + t1);
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..3 {
            let p = a[i] + mid * d[i];
            if p.abs() > h[i] {
                let sign = p.signum();
                let (c, e) = (sign * a[i] - h[i], sign * d[i]);
                num -= c * e;
                den += e * e;
            }
        }
        let t = if den > 0.0 { (num / den).clamp(t0, t1) } else { mid };
        best = best.min(sq_dist(t));
    }
    (best.sqrt() - capsule.radius).max(0.0)
}
