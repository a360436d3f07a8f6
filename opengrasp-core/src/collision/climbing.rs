//! A convex polyhedron whose support function climbs the vertex graph instead of scanning
//! every vertex.
//!
//! parry's `ConvexPolyhedron` finds support points by a linear scan over its vertices, which
//! dominates GJK on hulls of a few hundred vertices (scanned objects, lathed or lofted meshes).
//! [`ClimbingHull`] wraps the same polyhedron (same geometry, same vertices) and answers the
//! support query by hill climbing from the best of a few precomputed extreme vertices; on a
//! convex polyhedron a vertex no neighbour improves is a global maximum. The vertices within a
//! tiny tolerance of the maximum are then searched for the one parry's linear scan would return
//! (the largest dot product, lowest index among equals), so the support points — and hence
//! every GJK/EPA result — are the same as with the plain `ConvexPolyhedron`.

use nalgebra::{Point3, Unit, Vector3};
use parry3d_f64::bounding_volume::{Aabb, BoundingSphere};
use parry3d_f64::mass_properties::MassProperties;
use parry3d_f64::query::gjk::VoronoiSimplex;
use parry3d_f64::query::point::local_point_projection_on_support_map;
use parry3d_f64::query::{PointProjection, PointQuery, Ray, RayCast, RayIntersection};
use parry3d_f64::shape::{ConvexPolyhedron, FeatureId, PolygonalFeatureMap, Shape, ShapeType, SupportMap, TypedShape};

/// Directions whose support vertices seed the climb (the 26 neighbours of a cube's centre).
fn seed_directions() -> Vec<Vector3<f64>> {
    let mut out = Vec::with_capacity(26);
    for x in -1..=1 {
        for y in -1..=1 {
            for z in -1..=1 {
                if (x, y, z) != (0, 0, 0) {
                    out.push(Vector3::new(x as f64, y as f64, z as f64).normalize());
                }
            }
        }
    }
    out
}

/// First index of the largest dot product (parry's linear-scan rule).
fn linear_support_id(points: &[Point3<f64>], dir: &Vector3<f64>) -> usize {
    let mut best = 0;
    let mut best_dot = points[0].coords.dot(dir);
    for (i, p) in points.iter().enumerate().skip(1) {
        let d = p.coords.dot(dir);
        if d > best_dot {
            best = i;
            best_dot = d;
        }
    }
    best
}

/// A convex polyhedron with a hill-climbing support function (see the module docs).
#[derive(Clone, Debug)]
pub struct ClimbingHull {
    poly: ConvexPolyhedron,
    /// Vertex adjacency (CSR): neighbours of vertex `v` are `adj[start[v]..start[v + 1]]`.
    start: Vec<u32>,
    adj: Vec<u32>,
    /// Support vertices of the seed directions, deduplicated.
    seeds: Vec<u32>,
    /// Dot products within this of the maximum are re-examined for the linear-scan winner.
    tolerance: f64,
}

impl ClimbingHull {
    /// Wraps a convex polyhedron, building its vertex adjacency from the face polygons.
    pub fn new(poly: ConvexPolyhedron) -> Self {
        let n = poly.points().len();
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); n];
        let ring = poly.vertices_adj_to_face();
        for f in poly.faces() {
            let (first, count) = (f.first_vertex_or_edge as usize, f.num_vertices_or_edges as usize);
            for k in 0..count {
                let a = ring[first + k];
                let b = ring[first + (k + 1) % count];
                if a != b {
                    lists[a as usize].push(b);
                    lists[b as usize].push(a);
                }
            }
        }
        let mut start = Vec::with_capacity(n + 1);
        let mut adj = Vec::new();
        for l in &mut lists {
            l.sort_unstable();
            l.dedup();
            start.push(adj.len() as u32);
            adj.extend_from_slice(l);
        }
        start.push(adj.len() as u32);
        let mut seeds: Vec<u32> =
            seed_directions().iter().map(|d| linear_support_id(poly.points(), d) as u32).collect();
        seeds.sort_unstable();
        seeds.dedup();
        let radius = poly.points().iter().map(|p| p.coords.norm()).fold(0.0, f64::max);
        let tolerance = 1e-12 * radius.max(1e-300);
        Self { poly, start, adj, seeds, tolerance }
    }

    /// The wrapped polyhedron.
    pub fn polyhedron(&self) -> &ConvexPolyhedron {
        &self.poly
    }

    fn neighbours(&self, v: usize) -> &[u32] {
        &self.adj[self.start[v] as usize..self.start[v + 1] as usize]
    }

    /// Index of the support vertex in direction `dir`: the vertex parry's linear scan returns.
    pub fn support_id(&self, dir: &Vector3<f64>) -> usize {
        let pts = self.poly.points();
        let dot = |v: usize| pts[v].coords.dot(dir);
        let mut best = self.seeds[0] as usize;
        let mut best_dot = dot(best);
        for &s in &self.seeds[1..] {
            let d = dot(s as usize);
            if d > best_dot {
                best = s as usize;
                best_dot = d;
            }
        }
        if !best_dot.is_finite() {
            return linear_support_id(pts, dir);
        }
        loop {
            let mut moved = false;
            for &nb in self.neighbours(best) {
                let d = dot(nb as usize);
                if d > best_dot {
                    best = nb as usize;
                    best_dot = d;
                    moved = true;
                }
            }
            if !moved {
                break;
            }
        }
        // Near-ties (a face or edge orthogonal to `dir`): search the plateau for the largest
        // dot, lowest index, as the linear scan would pick.
        let threshold = best_dot - self.tolerance;
        let mut plateau = false;
        for &nb in self.neighbours(best) {
            if dot(nb as usize) >= threshold {
                plateau = true;
                break;
            }
        }
        if !plateau {
            return best;
        }
        let mut stack = vec![best as u32];
        let mut seen = vec![best as u32];
        let (mut win, mut win_dot) = (best, best_dot);
        while let Some(v) = stack.pop() {
            for &nb in self.neighbours(v as usize) {
                if seen.contains(&nb) {
                    continue;
                }
                let d = dot(nb as usize);
                if d >= threshold {
                    seen.push(nb);
                    stack.push(nb);
                    if d > win_dot || (d == win_dot && (nb as usize) < win) {
                        win = nb as usize;
                        win_dot = d;
                    }
                }
            }
        }
        win
    }
}

impl SupportMap for ClimbingHull {
    fn local_support_point(&self, dir: &Vector3<f64>) -> Point3<f64> {
        self.poly.points()[self.support_id(dir)]
    }
}

impl PointQuery for ClimbingHull {
    fn project_local_point(&self, point: &Point3<f64>, solid: bool) -> PointProjection {
        local_point_projection_on_support_map(self, &mut VoronoiSimplex::new(), point, solid)
    }

    fn project_local_point_and_get_feature(&self, point: &Point3<f64>) -> (PointProjection, FeatureId) {
        self.poly.project_local_point_and_get_feature(point)
    }
}

impl RayCast for ClimbingHull {
    fn cast_local_ray_and_get_normal(
        &self,
        ray: &Ray,
        max_time_of_impact: f64,
        solid: bool,
    ) -> Option<RayIntersection> {
        self.poly.cast_local_ray_and_get_normal(ray, max_time_of_impact, solid)
    }
}

impl Shape for ClimbingHull {
    fn compute_local_aabb(&self) -> Aabb {
        self.poly.local_aabb()
    }

    fn compute_local_bounding_sphere(&self) -> BoundingSphere {
        self.poly.local_bounding_sphere()
    }

    fn clone_dyn(&self) -> Box<dyn Shape> {
        Box::new(self.clone())
    }

    fn scale_dyn(&self, scale: &Vector3<f64>, _num_subdivisions: u32) -> Option<Box<dyn Shape>> {
        Some(Box::new(Self::new(self.poly.clone().scaled(scale)?)))
    }

    fn mass_properties(&self, density: f64) -> MassProperties {
        self.poly.mass_properties(density)
    }

    fn shape_type(&self) -> ShapeType {
        ShapeType::Custom
    }

    fn as_typed_shape(&self) -> TypedShape<'_> {
        TypedShape::Custom(self)
    }

    fn ccd_thickness(&self) -> f64 {
        self.poly.ccd_thickness()
    }

    fn ccd_angular_thickness(&self) -> f64 {
        self.poly.ccd_angular_thickness()
    }

    fn is_convex(&self) -> bool {
        true
    }

    fn as_support_map(&self) -> Option<&dyn SupportMap> {
        Some(self as &dyn SupportMap)
    }

    fn as_polygonal_feature_map(&self) -> Option<(&dyn PolygonalFeatureMap, f64)> {
        Some((&self.poly as &dyn PolygonalFeatureMap, 0.0))
    }

    fn feature_normal_at_point(&self, feature: FeatureId, point: &Point3<f64>) -> Option<Unit<Vector3<f64>>> {
        self.poly.feature_normal_at_point(feature, point)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Isometry3;
    use parry3d_f64::query;
    use proptest::prelude::*;

    /// A lathed cylinder (radius 0.04, height 0.14, `n` segments): many coplanar cap vertices,
    /// i.e. many support ties along the axis.
    fn cylinder(n: usize) -> ConvexPolyhedron {
        let mut pts = Vec::new();
        for z in [0.0, 0.14] {
            for k in 0..n {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                pts.push(Point3::new(0.04 * a.cos(), 0.04 * a.sin(), z));
            }
        }
        ConvexPolyhedron::from_convex_hull(&pts).expect("hull")
    }

    #[test]
    fn ties_pick_the_linear_scan_vertex() {
        let poly = cylinder(48);
        let hull = ClimbingHull::new(poly.clone());
        for d in
            [Vector3::z(), -Vector3::z(), Vector3::x(), Vector3::y(), Vector3::new(1.0, 1.0, 0.0), Vector3::zeros()]
        {
            assert_eq!(hull.support_id(&d), linear_support_id(poly.points(), &d), "direction {d:?}");
        }
    }

    #[test]
    fn distances_equal_the_plain_polyhedron() {
        let poly = cylinder(48);
        let hull = ClimbingHull::new(poly.clone());
        let ball = parry3d_f64::shape::Ball::new(0.01);
        let cuboid = parry3d_f64::shape::Cuboid::new(Vector3::new(0.01, 0.02, 0.03));
        let id = Isometry3::identity();
        for (k, t) in [[0.1, 0.0, 0.07], [0.0, 0.0, 0.2], [0.03, 0.03, -0.05], [0.05, 0.0, 0.07]].iter().enumerate() {
            let pose = Isometry3::new(Vector3::new(t[0], t[1], t[2]), Vector3::new(0.3 * k as f64, 0.1, 0.0));
            for other in [&ball as &dyn Shape, &cuboid as &dyn Shape] {
                let a = query::distance(&id, &poly, &pose, other).expect("supported");
                let b = query::distance(&id, &hull, &pose, other).expect("supported");
                assert_eq!(a, b);
            }
        }
        let c = query::contact(&id, &hull, &Isometry3::translation(0.045, 0.0, 0.07), &ball, 0.0).unwrap().unwrap();
        assert!((c.dist + 0.005).abs() < 1e-9, "depth {}", c.dist);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]
        #[test]
        fn support_equals_linear_scan(x in -1.0..1.0f64, y in -1.0..1.0f64, z in -1.0..1.0f64, n in 8usize..80) {
            let poly = cylinder(n);
            let hull = ClimbingHull::new(poly.clone());
            let d = Vector3::new(x, y, z);
            prop_assert_eq!(hull.support_id(&d), linear_support_id(poly.points(), &d));
            // Axis-aligned variants hit the ties of the caps and the side quads.
            for d in [Vector3::new(x, y, 0.0), Vector3::new(0.0, 0.0, z), Vector3::new(x, 0.0, z)] {
                prop_assert_eq!(hull.support_id(&d), linear_support_id(poly.points(), &d));
            }
        }
    }
}
