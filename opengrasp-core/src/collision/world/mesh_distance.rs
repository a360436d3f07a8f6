//! Distance from a convex shape to a triangle mesh, as parry computes it, with triangles that
//! cannot be the nearest skipped before their GJK query.
//!
//! parry's composite distance (`distance_composite_shape_shape`) walks the mesh's BVH nearest
//! box first and runs GJK on every triangle whose box is nearer than the best distance so far.
//! [`mesh_distance_hinted`] walks the same BVH with the same box costs and runs the same GJK
//! query per triangle, but first bounds the triangle's distance from below by the distance of
//! its bounding box to the shape's, both in the shape's frame (parry's boxes are in the mesh
//! frame, where a rotated link's box is loose), and by the distance of the shape's box to the
//! triangle's plane (a triangle of a curved surface tilted away from the link);
//! see [`TriangleBounds`]: a triangle whose bound exceeds the best distance so far (or the caller's bound) by more than
//! [`SKIP_MARGIN`] is farther than the best, so parry's search would not take its distance
//! either. The best distance after every triangle is thus parry's, and so are the pruning of
//! the boxes and the result, bit for bit.
//!
//! [`mesh_contact`] does the same for parry's contact query (`contact_composite_shape_shape`:
//! the deepest contact of the triangles whose boxes meet the shape's box loosened by the
//! prediction distance): a triangle whose bound exceeds the prediction distance has no contact,
//! one whose bound exceeds the deepest contact's separation so far none deeper.
//! [`mesh_intersects`] does it for parry's intersection test: a triangle whose bound is above
//! zero (by the margin) cannot intersect.

use nalgebra::{Isometry3, Matrix3, Point3, Vector3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::bounding_volume::BoundingVolume;
use parry3d_f64::partitioning::BvhNode;
use parry3d_f64::query::{Contact, DefaultQueryDispatcher, QueryDispatcher};
use parry3d_f64::shape::{HalfSpace, Shape as ParryShape, TriMesh, Triangle};

use super::bounded::{triangle_distance_within, SupportShape};

/// A triangle is skipped only if its lower bound exceeds the threshold by more than this (m):
/// far above the rounding of the bound and of GJK's distance (≈ 1e-16 m at grasp scales).
pub(super) const SKIP_MARGIN: f64 = 1e-10;

/// A warm-started mesh search ([`mesh_distance_hinted`]) starts from the hinted triangle's
/// distance plus this (m): far above the rounding of the distances and box costs, so every
/// triangle tying with the hinted one to rounding stays in the search.
const WARM_MARGIN: f64 = 1e-10;

/// Lower bounds of the distance between the triangles of a mesh and a shape inside the box
/// `local` of the shape's own frame, the mesh placed by `to_shape` in that frame (see
/// [`TriangleBounds::exceeds`]). Built once per query: the rotation as a matrix (cheaper per
/// triangle than the quaternion) and the shape's box in the mesh frame.
pub(super) struct TriangleBounds {
    local: Aabb,
    rot: Matrix3<f64>,
    shift: Vector3<f64>,
    /// The box centre in the mesh frame.
    centre: Vector3<f64>,
    /// The box's half axes (half extent times axis) in the mesh frame.
    axes: [Vector3<f64>; 3],
}

impl TriangleBounds {
    /// Bounds for a shape inside `local` (its frame) and a mesh mapped into that frame by
    /// `to_shape`.
    pub(super) fn new(local: Aabb, to_shape: &Isometry3<f64>) -> Self {
        let rot = to_shape.rotation.to_rotation_matrix().into_inner();
        let shift = to_shape.translation.vector;
        // The inverse map: x_mesh = rotᵀ (x_shape − shift).
        let centre = rot.tr_mul(&(local.center().coords - shift));
        let h = local.half_extents();
        let axes = [0, 1, 2].map(|i| rot.row(i).transpose() * h[i]);
        Self { local, rot, shift, centre, axes }
    }

    /// The distance between the shape's box and the triangle's bounding box, both in the
    /// shape's frame (unlike parry's test of the shape's box in the mesh frame, neither box
    /// is loosened by a rotation).
    pub(super) fn box_gap(&self, tri: &Triangle) -> f64 {
        let (a, b, c) = (self.map(&tri.a), self.map(&tri.b), self.map(&tri.c));
        // Plain comparisons rather than `f64::min`/`max` (whose NaN handling costs
        // instructions): the coordinates are finite, and the bound only prunes.
        let (min, max) = (|x: f64, y: f64| if y < x { y } else { x }, |x: f64, y: f64| if y > x { y } else { x });
        let mut sq = 0.0;
        for i in 0..3 {
            let (lo, hi) = (min(min(a[i], b[i]), c[i]), max(max(a[i], b[i]), c[i]));
            let gap = max(max(self.local.mins[i] - hi, lo - self.local.maxs[i]), 0.0);
            sq += gap * gap;
        }
        sq.sqrt()
    }

    /// The distance between the shape's box and the triangle's plane when the box lies
    /// entirely on one side of it (0 otherwise): `|n·(c − a)| − Σᵢ |n·hᵢ|` for the unit normal
    /// `n`, the box centre `c` and half axes `hᵢ`. 0 for a degenerate triangle.
    pub(super) fn plane_gap(&self, tri: &Triangle) -> f64 {
        let n = (tri.b - tri.a).cross(&(tri.c - tri.a));
        let len = n.norm();
        if len == 0.0 || !len.is_finite() {
            return 0.0;
        }
        let reach: f64 = self.axes.iter().map(|h| n.dot(h).abs()).sum();
        ((n.dot(&(self.centre - tri.a.coords)).abs() - reach) / len).max(0.0)
    }

    /// True if the triangle is certainly farther than `threshold` + [`SKIP_MARGIN`] from the
    /// shape: its box gap or its plane gap (both lower bounds of the distance) exceeds that.
    pub(super) fn exceeds(&self, tri: &Triangle, threshold: f64) -> bool {
        let limit = threshold + SKIP_MARGIN;
        self.box_gap(tri) > limit || self.plane_gap(tri) > limit
    }

    fn map(&self, p: &Point3<f64>) -> Vector3<f64> {
        self.rot * p.coords + self.shift
    }
}

/// `s2`'s triangle mesh if `s1` is a convex (support-map, not composite) shape, the pairs
/// parry answers with its composite queries.
fn convex_and_mesh<'a>(s1: &dyn ParryShape, s2: &'a dyn ParryShape) -> Option<&'a TriMesh> {
    (s1.as_support_map().is_some() && s1.as_composite_shape().is_none()).then(|| s2.as_trimesh()).flatten()
}

/// The distance parry's `query::distance(p1, s1, p2, s2)` returns for a convex shape and a
/// triangle mesh (either order) when it is below `bound`, `None` when it is not; `None` from
/// the outer option means the pair is not convex shape and mesh (see the module docs). With
/// a `hint` (a triangle index; out of range means none) the search starts from that
/// triangle's distance and skips every box farther than it, with the same result bit for
/// bit (see `walk`); `hint` is set to the nearest triangle found, for the next query of a
/// nearby pose.
pub(super) fn mesh_distance_hinted(
    p1: &Isometry3<f64>,
    s1: &dyn ParryShape,
    p2: &Isometry3<f64>,
    s2: &dyn ParryShape,
    bound: f64,
    hint: Option<&mut u32>,
) -> Option<Option<f64>> {
    // parry: pos12 = p1⁻¹ p2; the composite query with the mesh first, at pos12⁻¹ when the
    // mesh is the second shape.
    let pos12 = p1.inv_mul(p2);
    if let Some(mesh) = convex_and_mesh(s1, s2) {
        return Some(walk(mesh, s1, &pos12.inverse(), bound, hint));
    }
    let mesh = convex_and_mesh(s2, s1)?;
    Some(walk(mesh, s2, &pos12, bound, hint))
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
    let bounds = TriangleBounds::new(s1.compute_local_aabb(), &pos12);
    let ls_aabb2 = s1.compute_aabb(&pose12).loosened(prediction);
    let mut best: Option<Contact> = None;
    for part in mesh.bvh().intersect_aabb(&ls_aabb2) {
        let tri = mesh.triangle(part);
        // Beyond the prediction, or separated by more than the deepest contact so far (which
        // only a strictly deeper one replaces; the bounds are of the separation, so a
        // penetrating best rules out the separated triangles only): no contact to take.
        let threshold = best.map_or(prediction, |b| b.dist.max(0.0).min(prediction));
        if bounds.exceeds(&tri, threshold) {
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

/// The answer of parry's `query::intersection_test(p1, s1, p2, s2)` for a convex shape and a
/// triangle mesh (either order), with the triangles whose [`TriangleBounds`] put them beyond
/// [`SKIP_MARGIN`] of the shape skipped before their test (they cannot intersect it); `None`
/// when the pair is not a convex shape and a mesh, or the shape is a ball or a half-space
/// (which parry tests otherwise). parry tests the triangles whose boxes meet the shape's box
/// in the mesh frame and reports an intersection if one intersects; the same triangles less
/// the skipped ones give the same answer.
pub(super) fn mesh_intersects(
    p1: &Isometry3<f64>,
    s1: &dyn ParryShape,
    p2: &Isometry3<f64>,
    s2: &dyn ParryShape,
) -> Option<bool> {
    let plain = |s: &dyn ParryShape| s.as_ball().is_none() && s.as_shape::<HalfSpace>().is_none();
    let pos12 = p1.inv_mul(p2);
    // The shape in the mesh frame: parry's composite test with the mesh first (at pos12⁻¹
    // when the mesh is the second shape).
    let (mesh, shape, pose12) = if let Some(mesh) = convex_and_mesh(s1, s2).filter(|_| plain(s1)) {
        (mesh, s1, pos12.inverse())
    } else {
        (convex_and_mesh(s2, s1).filter(|_| plain(s2))?, s2, pos12)
    };
    let bounds = TriangleBounds::new(shape.compute_local_aabb(), &pose12.inverse());
    let ls_aabb2 = shape.compute_aabb(&pose12);
    let hit = mesh.bvh().intersect_aabb(&ls_aabb2).any(|part| {
        let tri = mesh.triangle(part);
        !bounds.exceeds(&tri, 0.0) && DefaultQueryDispatcher.intersection_test(&pose12, &tri, shape) == Ok(true)
    });
    Some(hit)
}

/// Nearest-box-first search of `mesh`'s BVH as in parry's `distance_to_shape`, from parry's
/// unbounded best, or with a valid `hint`, from the hinted triangle's distance plus
/// [`WARM_MARGIN`] (`hint` then becomes the nearest triangle found), and never from above
/// `bound` plus [`WARM_MARGIN`].
///
/// The warm start gives parry's result bit for bit. The search order (children by box cost)
/// does not depend on the best; only the pruning does. With `B` = the hint's distance plus
/// the margin, a box whose cost is at least `B` holds only triangles at least `B` away (a
/// box's cost is below its triangles' distances), so pruning it loses nothing below `B`; a
/// box nearer than `B` passes both searches' tests while neither has found a triangle below
/// `B`, and once one has, both have (the same triangle) and their bests agree from then on.
/// Both thus query the same triangles below `B`, among them the nearest (the hinted one is
/// below `B`), and return the same minimum. The margin keeps this exact when triangles tie
/// with the hinted one to rounding (a flat pad on a face split in two triangles), where
/// starting from the hint's distance itself dropped the tie parry's search keeps.
/// With `B` = `bound` plus the margin instead, the same argument gives the same triangles
/// below `B`, hence the same minimum whenever it is below `bound` (the only one returned);
/// otherwise neither search returns one (the hint may then stay where it was, any triangle
/// being a valid start). `run grasp --grasps` records are identical with this start (an
/// earlier start from the caller's bound, noted here before, moved a grasp cell's mean ε by
/// 0.6 %).
fn walk(
    mesh: &TriMesh,
    shape: &dyn ParryShape,
    pose12: &Isometry3<f64>,
    bound: f64,
    hint: Option<&mut u32>,
) -> Option<f64> {
    let bounds = TriangleBounds::new(shape.compute_local_aabb(), &pose12.inverse());
    let ls_aabb2 = shape.compute_aabb(pose12);
    let msum_shift = -ls_aabb2.center().coords;
    let msum_margin = ls_aabb2.half_extents();
    let query = |tri: &Triangle| DefaultQueryDispatcher.distance(pose12, tri, shape).ok();
    // The triangle queries stop once GJK proves a triangle farther than the best so far
    // (see `super::bounded`): parry's search would not take it either.
    let convex = SupportShape::against_triangle(shape);
    let start = hint
        .as_deref()
        .filter(|&&h| (h as usize) < mesh.num_triangles())
        .and_then(|&h| {
            let tri = mesh.triangle(h);
            convex.as_ref().map_or_else(|| query(&tri), |g| triangle_distance_within(pose12, &tri, g, f64::INFINITY))
        })
        .map_or(f64::MAX, |d| d + WARM_MARGIN)
        .min(bound + WARM_MARGIN);
    let best = mesh.bvh().find_best(
        start,
        |node: &BvhNode, _| {
            let msum =
                Aabb { mins: node.mins() + msum_shift - msum_margin, maxs: node.maxs() + msum_shift + msum_margin };
            msum.distance_to_origin()
        },
        |part, best| {
            let tri = mesh.triangle(part);
            let threshold = best.min(bound);
            if threshold < f64::MAX && bounds.exceeds(&tri, threshold) {
                return None;
            }
            // Stopped beyond the best only (not the caller's bound): a triangle between
            // the two still lowers the best, so the boxes pruned are parry's.
            match &convex {
                Some(g) => triangle_distance_within(pose12, &tri, g, best),
                None => query(&tri),
            }
        },
    );
    if let (Some(h), Some((part, _))) = (hint, best) {
        *h = part;
    }
    let d = best.map_or(f64::MAX, |(_, d)| d);
    (d < bound).then_some(d)
}

#[cfg(test)]
mod tests {
    use super::*;
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
        let gap = |at: Isometry3<f64>| TriangleBounds::new(local, &at.inverse()).box_gap(&tri);
        // Shape centred 0.5 above the triangle's corner (1, 0, 0) and 0.4 beyond it along x:
        // gaps 0.4 − 0.1 along x and 0.5 − 0.3 along z.
        let expected = (0.3f64 * 0.3 + 0.2 * 0.2).sqrt();
        assert!((gap(Isometry3::translation(1.4, 0.0, 0.5)) - expected).abs() < 1e-15);
        // The same shape turned 90° about z: its 0.2 half extent now lies along x.
        let turned = Isometry3::new(Vector3::new(1.4, 0.0, 0.5), Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
        let expected = (0.2f64 * 0.2 + 0.2 * 0.2).sqrt();
        assert!((gap(turned) - expected).abs() < 1e-12);
        // Overlapping boxes bound nothing.
        assert_eq!(gap(Isometry3::translation(0.2, 0.2, 0.1)), 0.0);
    }

    #[test]
    fn plane_bound_is_the_gap_to_the_triangle_plane() {
        // The triangle x + y + z = 1 (unit normal (1, 1, 1)/√3) and a cube of half side 0.1.
        let tri = Triangle::new(Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0), Point3::new(0.0, 0.0, 1.0));
        let local = Cuboid::new(Vector3::repeat(0.1)).local_aabb();
        let gap = |at: Isometry3<f64>| TriangleBounds::new(local, &at.inverse()).plane_gap(&tri);
        // Cube centred at the origin: centre 1/√3 from the plane, the corner (0.1, 0.1, 0.1)
        // reaches 0.3/√3 towards it.
        let expected = 0.7 / 3f64.sqrt();
        assert!((gap(Isometry3::identity()) - expected).abs() < 1e-15);
        // Beyond the plane, centre at (1, 1, 1): 2/√3 from it, the same reach.
        assert!((gap(Isometry3::translation(1.0, 1.0, 1.0)) - 1.7 / 3f64.sqrt()).abs() < 1e-15);
        // Turned so that a face faces the plane: the reach is the half side 0.1 (rotation
        // taking x to (1, 1, 1)/√3), centre still 1/√3 away.
        let n = Vector3::new(1.0, 1.0, 1.0).normalize();
        let turn = nalgebra::UnitQuaternion::rotation_between(&Vector3::x(), &n).unwrap();
        let turned = Isometry3::from_parts(nalgebra::Translation3::identity(), turn);
        assert!((gap(turned) - (1.0 / 3f64.sqrt() - 0.1)).abs() < 1e-15);
        // A cube cut by the plane, and a degenerate triangle, bound nothing.
        assert_eq!(gap(Isometry3::translation(0.3, 0.3, 0.3)), 0.0);
        let flat = Triangle::new(Point3::origin(), Point3::new(1.0, 0.0, 0.0), Point3::new(2.0, 0.0, 0.0));
        assert_eq!(TriangleBounds::new(local, &Isometry3::translation(0.0, 5.0, 0.0)).plane_gap(&flat), 0.0);
    }

    /// Boxes, cylinders, capsules and balls at random poses in and around the notch, the
    /// mesh first or second: the pruned intersection test answers as parry's, on a sample
    /// with both answers, and the pruned contact is parry's (penetrating ones among them).
    #[test]
    fn intersection_and_contact_are_parrys() {
        use rand::{Rng, SeedableRng};
        let mesh = notched_box();
        let mesh_pose = Isometry3::new(Vector3::new(0.01, -0.02, 0.0), Vector3::new(0.0, 0.0, 0.4));
        let shapes: [&dyn ParryShape; 4] = [
            &Cuboid::new(Vector3::new(0.012, 0.01, 0.004)),
            &parry3d_f64::shape::Cylinder::new(0.01, 0.006),
            &parry3d_f64::shape::Capsule::new_z(0.01, 0.004),
            &Ball::new(0.008),
        ];
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let (mut hits, mut misses, mut ours, mut deep) = (0, 0, 0, 0);
        for _ in 0..1500 {
            let t = Vector3::new(
                rng.random_range(-0.03..0.13),
                rng.random_range(-0.05..0.07),
                rng.random_range(-0.03..0.09),
            );
            let r = Vector3::new(rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0));
            let pose = Isometry3::new(t, r);
            for shape in shapes {
                let parry = query::intersection_test(&pose, shape, &mesh_pose, &mesh).unwrap();
                let flipped = query::intersection_test(&mesh_pose, &mesh, &pose, shape).unwrap();
                let ab = mesh_intersects(&pose, shape, &mesh_pose, &mesh);
                let ba = mesh_intersects(&mesh_pose, &mesh, &pose, shape);
                if shape.as_ball().is_some() {
                    assert_eq!((ab, ba), (None, None), "balls keep parry's test");
                    continue;
                }
                assert_eq!((ab, ba), (Some(parry), Some(flipped)), "at {pose:?}");
                // The deepest contact within 1 cm (penetrating or not): parry's, every bit.
                let contact = query::contact(&pose, shape, &mesh_pose, &mesh, 0.01).unwrap();
                let pruned = mesh_contact(&pose, shape, &mesh_pose, &mesh, 0.01).unwrap();
                assert_eq!(format!("{pruned:?}"), format!("{contact:?}"));
                deep += usize::from(contact.is_some_and(|c| c.dist < 0.0));
                ours += 1;
                if parry {
                    hits += 1;
                } else {
                    misses += 1;
                }
            }
        }
        assert!(hits >= 200 && misses >= 200 && deep >= 100, "{hits} hits ({deep} deep), {misses} misses of {ours}");
        // Not a convex shape and a mesh: no answer.
        assert_eq!(mesh_intersects(&mesh_pose, &mesh, &mesh_pose, &mesh), None);
        let c = Cuboid::new(Vector3::repeat(0.1));
        assert_eq!(mesh_intersects(&mesh_pose, &c, &mesh_pose, &c), None);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        /// Boxes and balls around and inside the notch: the pruned search returns parry's
        /// distance bit for bit, and `None` exactly when it is not below the bound.
        #[test]
        fn equals_parry_bit_for_bit(
            x in -0.05..0.15f64, y in -0.05..0.1f64, z in -0.05..0.12f64,
            rx in -3.0..3.0f64, ry in -3.0..3.0f64, hx in 0.002..0.03f64, bound_scale in 0.5..2.0f64,
            hint_pick in 0u32..1000,
        ) {
            let mesh = notched_box();
            let pose = Isometry3::new(Vector3::new(x, y, z), Vector3::new(rx, ry, 0.3));
            let mesh_pose = Isometry3::new(Vector3::new(0.01, -0.02, 0.0), Vector3::new(0.0, 0.0, 0.4));
            let cuboid = Cuboid::new(Vector3::new(hx, 0.01, 0.004));
            let ball = Ball::new(hx);
            for shape in [&cuboid as &dyn ParryShape, &ball as &dyn ParryShape] {
                // Both bounds are below every triangle's distance.
                let bounds = TriangleBounds::new(shape.compute_local_aabb(), &pose.inv_mul(&mesh_pose));
                for tri in mesh.triangles() {
                    let d = query::distance(&mesh_pose, &tri, &pose, shape).unwrap();
                    prop_assert!(bounds.box_gap(&tri) <= d + 1e-12 && bounds.plane_gap(&tri) <= d + 1e-12);
                }
                let reference = query::distance(&pose, shape, &mesh_pose, &mesh).unwrap();
                let all = mesh_distance_hinted(&pose, shape, &mesh_pose, &mesh, f64::INFINITY, None).unwrap();
                prop_assert_eq!(all.map(f64::to_bits), Some(reference.to_bits()));
                // Warm starts from any triangle (or an out-of-range index) give the same bits,
                // and leave the hint at a triangle at that distance.
                for start in [0, 7, hint_pick % 28, u32::MAX] {
                    let mut hint = start;
                    let warm = mesh_distance_hinted(&pose, shape, &mesh_pose, &mesh, f64::INFINITY, Some(&mut hint));
                    prop_assert_eq!(warm.unwrap().map(f64::to_bits), Some(reference.to_bits()));
                    let nearest = query::distance(&mesh_pose, &mesh.triangle(hint), &pose, shape).unwrap();
                    prop_assert!((nearest - reference).abs() <= 1e-12, "{} vs {}", nearest, reference);
                }
                let bound = reference * bound_scale;
                let below = mesh_distance_hinted(&pose, shape, &mesh_pose, &mesh, bound, None).unwrap();
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
