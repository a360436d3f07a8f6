//! Distance from a convex shape to a triangle mesh, as parry computes it, with triangles that
//! cannot be the nearest skipped before their GJK query.
//!
//! parry's composite distance (`distance_composite_shape_shape`) walks the mesh's BVH nearest
//! box first and runs GJK on every triangle whose box is nearer than the best distance so far.
//! [`mesh_distance_below`] walks the same BVH with the same box costs and runs the same GJK
//! query per triangle, but first bounds the triangle's distance from below by the distance of
//! its bounding box to the shape's, both in the shape's frame ([`box_lower_bound`]; parry's
//! boxes are in the mesh frame, where a rotated link's box is loose): a triangle whose
//! bound exceeds the best distance so far (or the caller's bound) by more than
//! [`SKIP_MARGIN`] is farther than the best, so parry's search would not take its distance
//! either. The best distance after every triangle is thus parry's, and so are the pruning of
//! the boxes and the result, bit for bit.
//!
//! [`mesh_contact`] does the same for parry's contact query (`contact_composite_shape_shape`:
//! the deepest contact of the triangles whose boxes meet the shape's box loosened by the
//! prediction distance): a triangle whose bound exceeds the prediction distance has no contact.

use nalgebra::{Isometry3, Vector3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::bounding_volume::BoundingVolume;
use parry3d_f64::partitioning::BvhNode;
use parry3d_f64::query::{Contact, DefaultQueryDispatcher, QueryDispatcher};
use parry3d_f64::shape::{Shape as ParryShape, TriMesh, Triangle};

/// A triangle is skipped only if its lower bound exceeds the threshold by more than this (m):
/// far above the rounding of the bound and of GJK's distance (≈ 1e-16 m at grasp scales).
pub(super) const SKIP_MARGIN: f64 = 1e-10;

/// Lower bound of the distance between `tri` (in the mesh frame) and a shape inside the box
/// `local` of its own frame, `to_shape` mapping the mesh frame to the shape's: the distance
/// between that box and the triangle's bounding box in the shape's frame. Unlike parry's
/// test of the shape's box in the mesh frame, neither box is loosened by a rotation.
pub(super) fn box_lower_bound(tri: &Triangle, local: &Aabb, to_shape: &Isometry3<f64>) -> f64 {
    let (a, b, c) = (to_shape * tri.a, to_shape * tri.b, to_shape * tri.c);
    let lo = a.coords.inf(&b.coords).inf(&c.coords);
    let hi = a.coords.sup(&b.coords).sup(&c.coords);
    let gap = (local.mins.coords - hi).sup(&(lo - local.maxs.coords)).sup(&Vector3::zeros());
    gap.norm()
}

/// `s2`'s triangle mesh if `s1` is a convex (support-map, not composite) shape, the pairs
/// parry answers with its composite queries.
fn convex_and_mesh<'a>(s1: &dyn ParryShape, s2: &'a dyn ParryShape) -> Option<&'a TriMesh> {
    (s1.as_support_map().is_some() && s1.as_composite_shape().is_none()).then(|| s2.as_trimesh()).flatten()
}

/// The distance parry's `query::distance(p1, s1, p2, s2)` returns for a convex shape and a
/// triangle mesh (either order), when it is below `bound`; `None` when it is not (see the
/// module docs). `None` from the outer option means the pair is not convex shape and mesh.
pub(super) fn mesh_distance_below(
    p1: &Isometry3<f64>,
    s1: &dyn ParryShape,
    p2: &Isometry3<f64>,
    s2: &dyn ParryShape,
    bound: f64,
) -> Option<Option<f64>> {
    // parry: pos12 = p1⁻¹ p2; the composite query with the mesh first, at pos12⁻¹ when the
    // mesh is the second shape.
    let pos12 = p1.inv_mul(p2);
    if let Some(mesh) = convex_and_mesh(s1, s2) {
        return Some(walk(mesh, s1, &pos12.inverse(), bound));
    }
    let mesh = convex_and_mesh(s2, s1)?;
    Some(walk(mesh, s2, &pos12, bound))
}

/// The contact parry's `query::contact(p1, s1, p2, s2, prediction)` returns for a convex `s1`
/// and a triangle mesh `s2` (see the module docs); `None` when the pair is not convex shape
/// and mesh.
pub(super) fn mesh_contact(
    p1: &Isometry3<f64>,
    s1: &dyn ParryShape,
    p2: &Isometry3<f64>,
    s2: &dyn ParryShape,
    prediction: f64,
) -> Option<Option<Contact>> {
    let mesh = convex_and_mesh(s1, s2)?;
    // parry: pos12 = p1⁻¹ p2, the composite query with the mesh first at pos12⁻¹, the contact
    // flipped back and moved to the world frame.
    let pos12 = p1.inv_mul(p2);
    let pose12 = pos12.inverse();
    let local = s1.compute_local_aabb();
    let ls_aabb2 = s1.compute_aabb(&pose12).loosened(prediction);
    let mut best: Option<Contact> = None;
    for part in mesh.bvh().intersect_aabb(&ls_aabb2) {
        let tri = mesh.triangle(part);
        if box_lower_bound(&tri, &local, &pos12) > prediction + SKIP_MARGIN {
            continue;
        }
        if let Ok(Some(c)) = DefaultQueryDispatcher.contact(&pose12, &tri, s1, prediction) {
            if best.is_none_or(|b| c.dist < b.dist) {
                best = Some(c);
            }
        }
    }
    Some(best.map(|c| {
        let mut c = c.flipped();
        c.transform_by_mut(p1, p2);
        c
    }))
}

/// Nearest-box-first search of `mesh`'s BVH as in parry's `distance_to_shape`, from parry's
/// unbounded best. (Starting the search from a finite `bound` instead changed one grasp
/// cell's mean ε by 0.6 % on the default suite: a node box's cost is not always below its
/// triangles' GJK distances, so which nodes get pruned depends on the search order; the
/// bound is used for the per-triangle skip only, which keeps parry's result bit for bit.)
fn walk(mesh: &TriMesh, shape: &dyn ParryShape, pose12: &Isometry3<f64>, bound: f64) -> Option<f64> {
    let local = shape.compute_local_aabb();
    let to_shape = pose12.inverse();
    let ls_aabb2 = shape.compute_aabb(pose12);
    let msum_shift = -ls_aabb2.center().coords;
    let msum_margin = ls_aabb2.half_extents();
    let best = mesh.bvh().find_best(
        f64::MAX,
        |node: &BvhNode, _| {
            let msum =
                Aabb { mins: node.mins() + msum_shift - msum_margin, maxs: node.maxs() + msum_shift + msum_margin };
            msum.distance_to_origin()
        },
        |part, best| {
            let tri = mesh.triangle(part);
            let threshold = best.min(bound);
            if threshold < f64::MAX && box_lower_bound(&tri, &local, &to_shape) > threshold + SKIP_MARGIN {
                return None;
            }
            DefaultQueryDispatcher.distance(pose12, &tri, shape).ok()
        },
    );
    let d = best.map_or(f64::MAX, |(_, d)| d);
    (d < bound).then_some(d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;
    use parry3d_f64::query;
    use parry3d_f64::shape::{Ball, Cuboid};
    use proptest::prelude::*;

    /// A closed, non-convex mesh: a box with a notch cut in its top (a "U" extruded along y).
    fn notched_box() -> TriMesh {
        let profile =
            [(0.0, 0.0), (0.1, 0.0), (0.1, 0.06), (0.07, 0.06), (0.07, 0.02), (0.03, 0.02), (0.03, 0.06), (0.0, 0.06)];
        let n = profile.len() as u32;
        let mut pts = Vec::new();
        for y in [0.0, 0.05] {
            for &(x, z) in &profile {
                pts.push(Point3::new(x, y, z));
            }
        }
        let mut idx = Vec::new();
        for i in 0..n {
            let j = (i + 1) % n;
            idx.push([i, j, n + j]);
            idx.push([i, n + j, n + i]);
        }
        // End caps as fans over the convex pieces of the U: bottom slab and two posts.
        for (base, flip) in [(0, false), (n, true)] {
            for tri in [[0, 1, 4], [0, 4, 5], [1, 2, 3], [1, 3, 4], [0, 5, 6], [0, 6, 7]] {
                let t = tri.map(|k| base + k);
                idx.push(if flip { [t[0], t[2], t[1]] } else { t });
            }
        }
        TriMesh::new(pts, idx).expect("mesh")
    }

    #[test]
    fn box_bound_is_the_gap_in_the_shape_frame() {
        let tri = Triangle::new(Point3::origin(), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0));
        let local = Cuboid::new(Vector3::new(0.1, 0.2, 0.3)).local_aabb();
        // Shape centred 0.5 above the triangle's corner (1, 0, 0) and 0.4 beyond it along x:
        // gaps 0.4 − 0.1 along x and 0.5 − 0.3 along z.
        let at = Isometry3::translation(1.4, 0.0, 0.5);
        let expected = (0.3f64 * 0.3 + 0.2 * 0.2).sqrt();
        assert!((box_lower_bound(&tri, &local, &at.inverse()) - expected).abs() < 1e-15);
        // The same shape turned 90° about z: its 0.2 half extent now lies along x.
        let turned = Isometry3::new(Vector3::new(1.4, 0.0, 0.5), Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
        let expected = (0.2f64 * 0.2 + 0.2 * 0.2).sqrt();
        assert!((box_lower_bound(&tri, &local, &turned.inverse()) - expected).abs() < 1e-12);
        // Overlapping boxes bound nothing.
        assert_eq!(box_lower_bound(&tri, &local, &Isometry3::translation(0.2, 0.2, 0.1).inverse()), 0.0);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        /// Boxes and balls around and inside the notch: the pruned search returns parry's
        /// distance bit for bit, and `None` exactly when it is not below the bound.
        #[test]
        fn equals_parry_bit_for_bit(
            x in -0.05..0.15f64, y in -0.05..0.1f64, z in -0.05..0.12f64,
            rx in -3.0..3.0f64, ry in -3.0..3.0f64, hx in 0.002..0.03f64, bound_scale in 0.5..2.0f64,
        ) {
            let mesh = notched_box();
            let pose = Isometry3::new(Vector3::new(x, y, z), Vector3::new(rx, ry, 0.3));
            let mesh_pose = Isometry3::new(Vector3::new(0.01, -0.02, 0.0), Vector3::new(0.0, 0.0, 0.4));
            let cuboid = Cuboid::new(Vector3::new(hx, 0.01, 0.004));
            let ball = Ball::new(hx);
            for shape in [&cuboid as &dyn ParryShape, &ball as &dyn ParryShape] {
                let reference = query::distance(&pose, shape, &mesh_pose, &mesh).unwrap();
                let all = mesh_distance_below(&pose, shape, &mesh_pose, &mesh, f64::INFINITY).unwrap();
                prop_assert_eq!(all.map(f64::to_bits), Some(reference.to_bits()));
                let bound = reference * bound_scale;
                let below = mesh_distance_below(&pose, shape, &mesh_pose, &mesh, bound).unwrap();
                prop_assert_eq!(below.map(f64::to_bits), (reference < bound).then_some(reference.to_bits()));
                // Contacts within a prediction distance around the distance: the same contact
                // (points, normals, depth; Debug prints every bit of an f64).
                let prediction = reference * bound_scale;
                let reference = query::contact(&pose, shape, &mesh_pose, &mesh, prediction).unwrap();
                let ours = mesh_contact(&pose, shape, &mesh_pose, &mesh, prediction).unwrap();
                prop_assert_eq!(format!("{ours:?}"), format!("{reference:?}"));
            }
        }
    }
}
