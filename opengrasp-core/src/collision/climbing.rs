//! A convex polyhedron whose support function climbs the vertex graph instead of scanning
//! every vertex.
//!
//! parry's `ConvexPolyhedron` finds support points by a linear scan over its vertices, which
//! dominates GJK on hulls of a few hundred vertices (scanned objects, lathed or lofted meshes).
//! [`ClimbingHull`] wraps the same polyhedron (same geometry, same vertices) and answers the
//! support query by hill climbing from a precomputed vertex: the support vertex of the centre
//! of the query direction's cell in a cube map (6 × 32 × 32 cells, each found at construction
//! by climbing from the previous cell's), usually the answer or one or two edges from it; on a
//! convex polyhedron a vertex no neighbour improves is a global maximum. The vertices within a tiny tolerance of the maximum are then searched for the one
//! parry's linear scan would return (the largest dot product, lowest index among equals; the
//! linear scan itself for a plateau of more than 32 vertices, a finely lathed cap), so the
//! support points — and hence every GJK/EPA result — are the same as with the plain
//! `ConvexPolyhedron`. The query allocates nothing.

use nalgebra::{Point3, Unit, Vector3};
use parry3d_f64::bounding_volume::{Aabb, BoundingSphere};
use parry3d_f64::mass_properties::MassProperties;
use parry3d_f64::query::gjk::VoronoiSimplex;
use parry3d_f64::query::point::local_point_projection_on_support_map;
use parry3d_f64::query::{PointProjection, PointQuery, Ray, RayCast, RayIntersection};
use parry3d_f64::shape::{ConvexPolyhedron, FeatureId, PolygonalFeatureMap, Shape, ShapeType, SupportMap, TypedShape};

/// Cells per face edge of the direction cube map that seeds the climb.
const CUBE_CELLS: usize = 32;

/// Largest plateau (near-tied vertices) searched on the vertex graph; a larger one is answered
/// by the linear scan. Large enough for the cap of a finely lathed solid (64–127 segments)
/// facing the direction, which a scan of every vertex would answer several times slower.
const PLATEAU_CAP: usize = 128;

/// Words of the stack bitset marking a plateau search's visited vertices: hulls of up to
/// `64 × MARK_WORDS` vertices. Larger hulls search plateaus of at most
/// [`SMALL_PLATEAU_CAP`] vertices with a list lookup instead.
const MARK_WORDS: usize = 32;

/// Plateau size searched without the bitset (hulls of more than `64 × MARK_WORDS` vertices).
const SMALL_PLATEAU_CAP: usize = 32;

/// Cube-map cell of a direction: the face of its largest component (by sign) and the cell of
/// the other two components divided by it. `None` for a zero or non-finite direction.
fn cube_cell(dir: &Vector3<f64>) -> Option<usize> {
    let a = dir.map(f64::abs);
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    let m = dir[axis];
    if m == 0.0 || !(a.x + a.y + a.z).is_finite() {
        return None;
    }
    let (u, v) = (dir[(axis + 1) % 3] / m.abs(), dir[(axis + 2) % 3] / m.abs());
    let k = CUBE_CELLS as f64;
    // `u, v ∈ [−1, 1]`: the cell is in 0..=16 before the clamp. Through i32, a signed
    // conversion x86 does in one instruction (f64 → usize needs a branchy unsigned one).
    let cell = |t: f64| (((t + 1.0) * 0.5 * k) as i32).clamp(0, CUBE_CELLS as i32 - 1) as usize;
    let face = 2 * axis + usize::from(m < 0.0);
    Some((face * CUBE_CELLS + cell(u)) * CUBE_CELLS + cell(v))
}

/// The centre direction of every cube-map cell, in cell order.
fn cube_directions() -> Vec<Vector3<f64>> {
    let k = CUBE_CELLS as f64;
    let mut out = Vec::with_capacity(6 * CUBE_CELLS * CUBE_CELLS);
    for face in 0..6 {
        let (axis, sign) = (face / 2, if face % 2 == 0 { 1.0 } else { -1.0 });
        for i in 0..CUBE_CELLS {
            for j in 0..CUBE_CELLS {
                let mut d = Vector3::zeros();
                d[axis] = sign;
                d[(axis + 1) % 3] = (i as f64 + 0.5) / k * 2.0 - 1.0;
                d[(axis + 2) % 3] = (j as f64 + 0.5) / k * 2.0 - 1.0;
                out.push(d);
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

/// The vertices a plateau search of [`ClimbingHull::support_id`] has visited: a bitset, or
/// (`marked` false, hulls of more than `64 × MARK_WORDS` vertices) the search's own list.
struct Visited {
    marked: bool,
    marks: [u64; MARK_WORDS],
}

impl Visited {
    /// Marks `v` visited; true if it was not before. `seen` is the search's list of the
    /// vertices visited so far (read only when the bitset is not used).
    #[inline(always)]
    fn first_visit(&mut self, v: u32, seen: &[u32]) -> bool {
        if self.marked {
            let (word, bit) = (v as usize / 64, 1u64 << (v % 64));
            let fresh = self.marks[word] & bit == 0;
            self.marks[word] |= bit;
            fresh
        } else {
            !seen.contains(&v)
        }
    }
}

/// A convex polyhedron with a hill-climbing support function (see the module docs).
#[derive(Clone, Debug)]
pub struct ClimbingHull {
    poly: ConvexPolyhedron,
    /// Vertex adjacency (CSR): neighbours of vertex `v` are `adj[start[v]..start[v + 1]]`.
    start: Vec<u32>,
    adj: Vec<u32>,
    /// Support vertex of each cube-map cell's centre direction: where the climb starts.
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
        let radius = poly.points().iter().map(|p| p.coords.norm()).fold(0.0, f64::max);
        let tolerance = 1e-12 * radius.max(1e-300);
        let mut hull = Self { poly, start, adj, seeds: Vec::new(), tolerance };
        hull.seeds = hull.cube_seeds();
        hull
    }

    /// The support vertex of every cube-map cell's centre direction, in cell order: the first
    /// by the linear scan, each next one climbed from the one before (an adjacent cell's, but
    /// for the first of a row or face; any start climbs to the linear scan's vertex, so these
    /// are the linear scan's answers at a fraction of its cost on large hulls).
    fn cube_seeds(&self) -> Vec<u32> {
        let mut seeds: Vec<u32> = Vec::with_capacity(6 * CUBE_CELLS * CUBE_CELLS);
        for d in cube_directions() {
            let s = match seeds.last() {
                Some(&prev) => self.support_from(prev as usize, &d),
                None => linear_support_id(self.poly.points(), &d),
            };
            seeds.push(s as u32);
        }
        seeds
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
        let Some(cell) = cube_cell(dir) else {
            return linear_support_id(self.poly.points(), dir);
        };
        self.support_from(self.seeds[cell] as usize, dir)
    }

    /// [`support_id`](Self::support_id) climbing from vertex `start` (any vertex gives the
    /// same answer, a nearer one sooner).
    #[inline(always)]
    fn support_from(&self, start: usize, dir: &Vector3<f64>) -> usize {
        let pts = self.poly.points();
        let dot = |v: usize| pts[v].coords.dot(dir);
        let mut best = start;
        let mut best_dot = dot(best);
        if !best_dot.is_finite() {
            return linear_support_id(pts, dir);
        }
        // Climb until no neighbour improves; the last pass saw every neighbour of the top.
        let top_neighbour = loop {
            let mut moved = false;
            let mut top = f64::NEG_INFINITY;
            for &nb in self.neighbours(best) {
                let d = dot(nb as usize);
                // `f64::max` without its NaN handling: a NaN `d` is skipped either way.
                if d > top {
                    top = d;
                }
                if d > best_dot {
                    best = nb as usize;
                    best_dot = d;
                    moved = true;
                }
            }
            if !moved {
                break top;
            }
        };
        // Near-ties (a face or edge orthogonal to `dir`): search the plateau for the largest
        // dot, lowest index, as the linear scan would pick.
        let threshold = best_dot - self.tolerance;
        if top_neighbour < threshold {
            return best;
        }
        // The plateau's vertices in discovery order; `seen[..next]` have been expanded.
        // Visited vertices are marked in a bitset (or, on very large hulls, looked up in
        // `seen`, which then holds at most SMALL_PLATEAU_CAP vertices).
        let mut visited = Visited { marked: pts.len() <= 64 * MARK_WORDS, marks: [0; MARK_WORDS] };
        let cap = if visited.marked { PLATEAU_CAP } else { SMALL_PLATEAU_CAP };
        let mut seen = [0u32; PLATEAU_CAP];
        seen[0] = best as u32;
        visited.first_visit(best as u32, &[]);
        let (mut len, mut next) = (1, 0);
        let (mut win, mut win_dot) = (best, best_dot);
        while next < len {
            let v = seen[next] as usize;
            next += 1;
            for &nb in self.neighbours(v) {
                if !visited.first_visit(nb, &seen[..len]) {
                    continue;
                }
                let d = dot(nb as usize);
                if d >= threshold {
                    if len == cap {
                        return linear_support_id(pts, dir);
                    }
                    seen[len] = nb;
                    len += 1;
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
        // Caps of 48 and 128 vertices (searched on the graph) and of 300 (beyond the plateau
        // cap: the linear scan).
        for n in [48, 128, 300] {
            let poly = cylinder(n);
            let hull = ClimbingHull::new(poly.clone());
            let tilted = Vector3::new(1e-14, 0.0, 1.0);
            for d in [
                Vector3::z(),
                -Vector3::z(),
                Vector3::x(),
                Vector3::y(),
                Vector3::new(1.0, 1.0, 0.0),
                Vector3::zeros(),
                tilted,
            ] {
                assert_eq!(hull.support_id(&d), linear_support_id(poly.points(), &d), "{n} segments, {d:?}");
            }
            // Along the axis every cap vertex ties: the lowest index of the top cap wins.
            assert_eq!(hull.support_id(&Vector3::z()), linear_support_id(poly.points(), &Vector3::z()));
            assert_eq!(poly.points()[hull.support_id(&Vector3::z())].z, 0.14);
        }
    }

    /// The climbed cube-map seeds are the linear scan's vertices of the cells' directions.
    #[test]
    fn climbed_seeds_are_the_linear_scan_vertices() {
        for n in [7, 48, 300] {
            let poly = cylinder(n);
            let hull = ClimbingHull::new(poly.clone());
            let linear: Vec<u32> =
                cube_directions().iter().map(|d| linear_support_id(poly.points(), d) as u32).collect();
            assert_eq!(hull.seeds, linear, "{n} segments");
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

    #[test]
    fn cube_cells_cover_every_direction_once() {
        let dirs = cube_directions();
        assert_eq!(dirs.len(), 6 * CUBE_CELLS * CUBE_CELLS);
        for (c, d) in dirs.iter().enumerate() {
            assert_eq!(cube_cell(d), Some(c));
            assert_eq!(cube_cell(&(d * 1e-200)), Some(c));
        }
        // Cell edges and face edges (ties of the largest component) still map into range.
        for d in [Vector3::new(1.0, 1.0, 1.0), Vector3::new(-1.0, 1.0, -1.0), Vector3::new(0.0, -1.0, 1.0)] {
            assert!(cube_cell(&d).is_some_and(|c| c < dirs.len()));
        }
        for d in [Vector3::zeros(), Vector3::new(f64::NAN, 1.0, 0.0), Vector3::new(f64::INFINITY, 0.0, 0.0)] {
            assert_eq!(cube_cell(&d), None);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]
        /// Random point clouds (no symmetry, a few hundred hull vertices at most) and random
        /// directions, including ones with zero components and tiny magnitudes.
        #[test]
        fn support_equals_linear_scan_on_random_hulls(
            seed in 0u64..1_000,
            n in 4usize..300,
            dirs in proptest::collection::vec((-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), 16),
        ) {
            let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let mut next = || {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            };
            let pts: Vec<Point3<f64>> = (0..n).map(|_| Point3::new(next(), 0.5 * next(), 0.2 * next())).collect();
            let Some(poly) = ConvexPolyhedron::from_convex_hull(&pts) else { return Ok(()) };
            let hull = ClimbingHull::new(poly.clone());
            for (x, y, z) in dirs {
                for d in [Vector3::new(x, y, z), Vector3::new(x, 0.0, z), Vector3::new(x, y, z) * 1e-150] {
                    prop_assert_eq!(hull.support_id(&d), linear_support_id(poly.points(), &d));
                }
            }
        }


        #[test]
        fn support_equals_linear_scan(x in -1.0..1.0f64, y in -1.0..1.0f64, z in -1.0..1.0f64, n in 8usize..300) {
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
