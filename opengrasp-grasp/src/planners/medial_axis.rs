//! The medial-axis grasp planner of Przybylski, Asfour and Dillmann (IROS 2010, 2011).
//!
//! The object's medial axis is approximated by a union of inscribed balls: the mesh is
//! voxelised (inside/outside by the winding number along x-rays, so overlapping closed shells such
//! as a cup and its handle work), an exact Euclidean distance transform
//! (Felzenszwalb–Huttenlocher) gives every inside voxel the radius of its largest inscribed
//! ball, and the voxels on the ridge of that distance field are kept. A ridge voxel is one whose
//! radius grows towards no neighbour faster than `max_slope` per unit distance: along a medial
//! sheet with object angle `α` (the angle between the two nearest boundary directions) the
//! radius grows at `cos(α/2)`, so `max_slope` is Przybylski's angle filter in disguise (0.5 keeps
//! sheets with `α ≥ 120°`, pruning the wedges that run into box edges and cylinder rims).
//!
//! The kept balls are grouped into symmetry structures: a principal component analysis gives the
//! object's main axis, the balls are cut into slices across it, and each slice is a local
//! symmetry axis (its balls concentrate around one point or spread evenly around it) or a local
//! symmetry plane (its balls spread along one direction). Candidates approach perpendicular to the
//! main axis towards the slice centre, with the fingers closing around the axis or across the
//! symmetry plane, plus approaches along the main axis onto both ends; a candidate is generated
//! only if the object is narrower than the hand's aperture along the closing direction.

use std::f64::consts::PI;

use crate::error::{GraspError, Result};
use nalgebra::{Matrix2, Matrix3, Point3, Rotation3, SymmetricEigen, Unit, Vector3};
use opengrasp_core::model::TriangleMesh;

use super::{check_positive, palm_pose, GraspCandidate, GraspPlanner, GraspRequest, HandInfo, Preshape};

/// Options of the [`MedialAxisPlanner`].
#[derive(Clone, Debug, PartialEq)]
pub struct MedialAxisOptions {
    /// Voxel edge length (m). Default: `None`, i.e. the longest bounding-box side divided by
    /// `voxels_per_axis`.
    pub voxel_size: Option<f64>,
    /// Voxels along the longest bounding-box side when `voxel_size` is `None`. Default: 48.
    pub voxels_per_axis: usize,
    /// Ridge criterion: a voxel is medial if no neighbour's radius exceeds its own by more than
    /// `max_slope` times their distance. Default: 0.5 (object angle ≥ 120°).
    pub max_slope: f64,
    /// Balls with a radius below this many voxels are dropped as boundary noise. Default: 1.0.
    pub min_radius_voxels: f64,
    /// Thickness (m) of the slices across the main axis. Default: 0.01.
    pub slice_spacing: f64,
    /// Approach directions around a local symmetry axis, evenly spaced over 2π. Default: 12.
    pub around_steps: usize,
    /// Roll angles (evenly spaced over 2π) for the approaches onto the two ends of the main axis.
    /// Default: 4.
    pub end_rolls: usize,
    /// A slice is a local symmetry plane if its balls' spread along their major direction
    /// exceeds `max(plane_spread_voxels · voxel, 0.25 · mean radius)` and the minor spread is less
    /// than `isotropy` times the major. Default: 1.5.
    pub plane_spread_voxels: f64,
    /// Minor/major spread ratio above which a slice counts as isotropic (a local axis). Default: 0.5.
    pub isotropy: f64,
    /// Ratio of PCA eigenvalues below which the whole medial axis is line-like (`λ2/λ1`) or
    /// plane-like (`λ3/λ2`). Default: 0.05.
    pub shape_ratio: f64,
    /// Distances (m) the hand backs off after retraction. Default: `[0.0]`.
    pub standoffs: Vec<f64>,
    /// Preshapes tried for every pose; empty means every preshape of the hand (as Przybylski
    /// et al. pair each symmetry structure with the hand's preshapes). Default: empty.
    pub preshapes: Vec<Preshape>,
}

impl Default for MedialAxisOptions {
    fn default() -> Self {
        Self {
            voxel_size: None,
            voxels_per_axis: 48,
            max_slope: 0.5,
            min_radius_voxels: 1.0,
            slice_spacing: 0.01,
            around_steps: 12,
            end_rolls: 4,
            plane_spread_voxels: 1.5,
            isotropy: 0.5,
            shape_ratio: 0.05,
            standoffs: vec![0.0],
            preshapes: Vec::new(),
        }
    }
}

/// One inscribed ball of the medial axis approximation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MedialBall {
    /// Centre (object frame, m).
    pub center: Point3<f64>,
    /// Radius (m): distance from the centre to the object surface.
    pub radius: f64,
}

/// The kind of a symmetry structure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StructureKind {
    /// The balls lie along a line (cylinder-like part).
    SymmetryAxis,
    /// The balls lie in a plane (box- or plate-like part).
    SymmetryPlane,
    /// Neither (a compact or branching part).
    Volume,
}

/// A symmetry structure of the medial axis (the whole object, or one slice of it).
#[derive(Clone, Debug, PartialEq)]
pub struct MedialStructure {
    /// What the balls look like.
    pub kind: StructureKind,
    /// Centroid of the ball centres (object frame).
    pub centroid: Point3<f64>,
    /// For an axis: its direction; for a plane: a direction within it (the balls' major spread).
    pub direction: Unit<Vector3<f64>>,
    /// For a plane: its normal; otherwise a unit vector perpendicular to `direction`.
    pub normal: Unit<Vector3<f64>>,
    /// Mean ball radius (m).
    pub mean_radius: f64,
    /// Indices into [`MedialAxis::balls`].
    pub balls: Vec<usize>,
}

/// The medial axis approximation of an object.
#[derive(Clone, Debug, PartialEq)]
pub struct MedialAxis {
    /// Voxel edge length used (m).
    pub voxel_size: f64,
    /// The medial balls.
    pub balls: Vec<MedialBall>,
    /// The whole object's structure: `direction` is the main axis (first principal component).
    pub global: MedialStructure,
    /// Slices across the main axis, in order along it; `direction` is the slice's major in-plane
    /// direction, `normal` the in-plane perpendicular.
    pub slices: Vec<MedialStructure>,
}

impl MedialAxis {
    /// Computes the medial axis approximation of a closed mesh.
    ///
    /// # Errors
    /// [`GraspError::InvalidParameter`] for bad options; [`GraspError::Core`] (degenerate mesh) if the mesh
    /// encloses no voxel (open, flat or far smaller than a voxel).
    pub fn compute(mesh: &TriangleMesh, options: &MedialAxisOptions) -> Result<Self> {
        check_positive("max_slope", options.max_slope)?;
        check_positive("slice_spacing", options.slice_spacing)?;
        let (lo, hi) = mesh.aabb();
        let longest = (hi - lo).max();
        let h = match options.voxel_size {
            Some(h) => h,
            None => longest / options.voxels_per_axis.max(1) as f64,
        };
        check_positive("voxel_size", h)?;
        let grid = VoxelGrid::new(mesh, h)?;
        let dist = grid.distance_transform();
        let balls = grid.medial_balls(&dist, options);
        if balls.len() < 2 {
            return Err(GraspError::Core(opengrasp_core::CoreError::DegenerateMesh {
                reason: format!("medial axis has {} balls at voxel size {h} m (open or tiny mesh?)", balls.len()),
            }));
        }
        let all: Vec<usize> = (0..balls.len()).collect();
        let (centroid, axes, eig) = pca(&balls, &all);
        let e1 = axes[0];
        let kind = if eig[1] < options.shape_ratio * eig[0] {
            StructureKind::SymmetryAxis
        } else if eig[2] < options.shape_ratio * eig[1] {
            StructureKind::SymmetryPlane
        } else {
            StructureKind::Volume
        };
        let global = MedialStructure {
            kind,
            centroid,
            direction: Unit::new_normalize(if kind == StructureKind::SymmetryPlane { axes[0] } else { e1 }),
            normal: Unit::new_normalize(axes[2]),
            mean_radius: all.iter().map(|&i| balls[i].radius).sum::<f64>() / balls.len() as f64,
            balls: all,
        };
        let slices = slice(&balls, &global, axes, h, options);
        Ok(Self { voxel_size: h, balls, global, slices })
    }
}

/// Przybylski et al.'s medial-axis grasp planner.
///
/// Candidate order: slices along the main axis (for each: approach directions, then standoffs,
/// then preshapes), then the two end approaches.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MedialAxisPlanner {
    /// The planner's options.
    pub options: MedialAxisOptions,
}

impl MedialAxisPlanner {
    /// A planner with the given options.
    pub fn new(options: MedialAxisOptions) -> Self {
        Self { options }
    }
}

impl GraspPlanner for MedialAxisPlanner {
    fn name(&self) -> &str {
        "medial-axis"
    }

    fn plan(&self, request: &GraspRequest<'_>) -> Result<Vec<GraspCandidate>> {
        let o = &self.options;
        for &s in &o.standoffs {
            super::check_non_negative("standoffs", s)?;
        }
        let ma = MedialAxis::compute(request.object, o)?;
        let mut poses = Vec::new();
        let hand = request.hand;
        let e1 = ma.global.direction.into_inner();
        for s in &ma.slices {
            let width_of = |dir: &Vector3<f64>| extent(&ma.balls, &s.balls, dir);
            match s.kind {
                StructureKind::SymmetryPlane => {
                    let d = s.direction.into_inner();
                    let n = s.normal.into_inner();
                    // Approach within the plane, fingers closing across it; then onto the plane,
                    // fingers closing along it.
                    for (approach, closing) in [(d, n), (-d, n), (n, d), (-n, d)] {
                        if width_of(&closing) <= hand.max_aperture {
                            poses.push(pose(hand, &s.centroid, approach, closing));
                        }
                    }
                }
                _ => {
                    let u = s.direction.into_inner();
                    let v = s.normal.into_inner();
                    let steps = o.around_steps.max(1);
                    for k in 0..steps {
                        let th = 2.0 * PI * k as f64 / steps as f64;
                        let approach = -(u * th.cos() + v * th.sin());
                        let closing = e1.cross(&approach);
                        if width_of(&closing) <= hand.max_aperture {
                            poses.push(pose(hand, &s.centroid, approach, closing));
                        }
                    }
                }
            }
        }
        let ends = [(ma.slices.first(), e1), (ma.slices.last(), -e1)];
        for (s, approach) in ends {
            let Some(s) = s else { continue };
            let reference = s.direction.into_inner();
            let rolls = o.end_rolls.max(1);
            for k in 0..rolls {
                let roll = 2.0 * PI * k as f64 / rolls as f64;
                let closing = Rotation3::from_axis_angle(&Unit::new_normalize(approach), roll) * reference;
                if extent(&ma.balls, &s.balls, &closing) <= hand.max_aperture {
                    poses.push(pose(hand, &s.centroid, approach, closing));
                }
            }
        }
        let hand_preshapes: Vec<Preshape> = if hand.preshapes.is_empty() {
            vec![Preshape::Default]
        } else {
            hand.preshapes.iter().map(|p| Preshape::Named(p.clone())).collect()
        };
        let preshapes: &[Preshape] = if o.preshapes.is_empty() { &hand_preshapes } else { &o.preshapes };
        let standoffs: &[f64] = if o.standoffs.is_empty() { &[0.0] } else { &o.standoffs };
        let mut out = Vec::with_capacity(poses.len() * standoffs.len() * preshapes.len());
        for c in poses {
            for &standoff in standoffs {
                for p in preshapes {
                    out.push(GraspCandidate { preshape: p.clone(), standoff, ..c.clone() });
                }
            }
        }
        Ok(out)
    }
}

fn pose(hand: &HandInfo, at: &Point3<f64>, approach: Vector3<f64>, closing: Vector3<f64>) -> GraspCandidate {
    let approach = Unit::new_normalize(approach);
    GraspCandidate {
        hand_pose: palm_pose(hand, at, &approach, &closing),
        preshape: Preshape::Default,
        approach,
        standoff: 0.0,
    }
}

/// Width of the union of the balls `idx` along `dir` (m).
fn extent(balls: &[MedialBall], idx: &[usize], dir: &Vector3<f64>) -> f64 {
    let dir = dir.normalize();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &i in idx {
        let t = balls[i].center.coords.dot(&dir);
        lo = lo.min(t - balls[i].radius);
        hi = hi.max(t + balls[i].radius);
    }
    hi - lo
}

/// Centroid, principal axes (descending variance) and eigenvalues of the ball centres `idx`.
fn pca(balls: &[MedialBall], idx: &[usize]) -> (Point3<f64>, [Vector3<f64>; 3], [f64; 3]) {
    let n = idx.len().max(1) as f64;
    let mean = idx.iter().map(|&i| balls[i].center.coords).sum::<Vector3<f64>>() / n;
    let mut cov = Matrix3::zeros();
    for &i in idx {
        let d = balls[i].center.coords - mean;
        cov += d * d.transpose();
    }
    cov /= n;
    let eig = SymmetricEigen::new(cov);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let mut axes = order.map(|k| eig.eigenvectors.column(k).into_owned());
    // Deterministic signs: largest component positive; right-handed frame.
    for a in axes.iter_mut().take(2) {
        let k = a.iamax();
        if a[k] < 0.0 {
            *a = -*a;
        }
    }
    axes[2] = axes[0].cross(&axes[1]);
    (Point3::from(mean), axes, order.map(|k| eig.eigenvalues[k].max(0.0)))
}

/// Cuts the balls into slices across the main axis and classifies each slice.
fn slice(
    balls: &[MedialBall],
    global: &MedialStructure,
    axes: [Vector3<f64>; 3],
    h: f64,
    o: &MedialAxisOptions,
) -> Vec<MedialStructure> {
    let [e1, e2, e3] = axes;
    let t: Vec<f64> = balls.iter().map(|b| (b.center - global.centroid).dot(&e1)).collect();
    let tmin = t.iter().copied().fold(f64::INFINITY, f64::min);
    let tmax = t.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let count = (((tmax - tmin) / o.slice_spacing).ceil() as usize).max(1);
    let width = (tmax - tmin) / count as f64;
    let mut members = vec![Vec::new(); count];
    for (i, &ti) in t.iter().enumerate() {
        let k = if width > 0.0 { (((ti - tmin) / width) as usize).min(count - 1) } else { 0 };
        members[k].push(i);
    }
    let mut out = Vec::new();
    for idx in members.into_iter().filter(|m| !m.is_empty()) {
        let n = idx.len() as f64;
        let mean = idx.iter().map(|&i| balls[i].center.coords).sum::<Vector3<f64>>() / n;
        let mut cov = Matrix2::zeros();
        for &i in &idx {
            let d = balls[i].center.coords - mean;
            let p = nalgebra::Vector2::new(d.dot(&e2), d.dot(&e3));
            cov += p * p.transpose();
        }
        cov /= n;
        let eig = SymmetricEigen::new(cov);
        let (major, minor) = if eig.eigenvalues[0] >= eig.eigenvalues[1] { (0, 1) } else { (1, 0) };
        let v = eig.eigenvectors.column(major);
        let mut d = e2 * v[0] + e3 * v[1];
        let k = d.iamax();
        if d[k] < 0.0 {
            d = -d;
        }
        let s_major = eig.eigenvalues[major].max(0.0).sqrt();
        let s_minor = eig.eigenvalues[minor].max(0.0).sqrt();
        let mean_radius = idx.iter().map(|&i| balls[i].radius).sum::<f64>() / n;
        let spread = s_major > (o.plane_spread_voxels * h).max(0.25 * mean_radius);
        let kind = if spread && s_minor < o.isotropy * s_major {
            StructureKind::SymmetryPlane
        } else {
            StructureKind::SymmetryAxis
        };
        out.push(MedialStructure {
            kind,
            centroid: Point3::from(mean),
            direction: Unit::new_normalize(d),
            normal: Unit::new_normalize(e1.cross(&d)),
            mean_radius,
            balls: idx,
        });
    }
    out
}

/// A voxelisation of a closed mesh with inside/outside flags.
struct VoxelGrid {
    origin: Point3<f64>,
    h: f64,
    dims: [usize; 3],
    inside: Vec<bool>,
}

impl VoxelGrid {
    fn index(&self, i: usize, j: usize, k: usize) -> usize {
        (k * self.dims[1] + j) * self.dims[0] + i
    }

    fn center(&self, i: usize, j: usize, k: usize) -> Point3<f64> {
        self.origin + Vector3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) * self.h
    }

    /// Voxelises by winding number along +x rays through every (y, z) voxel column.
    fn new(mesh: &TriangleMesh, h: f64) -> Result<Self> {
        let (lo, hi) = mesh.aabb();
        let origin = lo - Vector3::repeat(h);
        let dims = [0, 1, 2].map(|a| ((hi[a] - lo[a]) / h).ceil() as usize + 2);
        let total = dims[0].saturating_mul(dims[1]).saturating_mul(dims[2]);
        if total > 20_000_000 {
            return Err(GraspError::InvalidParameter {
                name: "voxel_size",
                reason: format!("{h} m gives {total} voxels (limit 2e7)"),
            });
        }
        // Tiny irrational offsets keep column rays off mesh edges and vertices.
        let (jy, jz) = (1.234_567e-6 * h, 2.345_678e-6 * h);
        let mut crossings: Vec<Vec<(f64, i32)>> = vec![Vec::new(); dims[1] * dims[2]];
        let v = mesh.vertices();
        for t in mesh.triangles() {
            let [a, b, c] = t.map(|k| v[k as usize]);
            let ymin = a.y.min(b.y).min(c.y);
            let ymax = a.y.max(b.y).max(c.y);
            let zmin = a.z.min(b.z).min(c.z);
            let zmax = a.z.max(b.z).max(c.z);
            let j0 = (((ymin - origin.y) / h - 0.5).floor().max(0.0)) as usize;
            let j1 = (((ymax - origin.y) / h - 0.5).ceil().max(0.0) as usize).min(dims[1] - 1);
            let k0 = (((zmin - origin.z) / h - 0.5).floor().max(0.0)) as usize;
            let k1 = (((zmax - origin.z) / h - 0.5).ceil().max(0.0) as usize).min(dims[2] - 1);
            for k in k0..=k1 {
                let z = origin.z + (k as f64 + 0.5) * h + jz;
                for j in j0..=j1 {
                    let y = origin.y + (j as f64 + 0.5) * h + jy;
                    if let Some(hit) = column_hit(&a, &b, &c, y, z) {
                        crossings[k * dims[1] + j].push(hit);
                    }
                }
            }
        }
        let mut grid = Self { origin, h, dims, inside: vec![false; total] };
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                let xs = &mut crossings[k * dims[1] + j];
                xs.sort_by(|a, b| a.0.total_cmp(&b.0));
                // Winding number along the ray: +1 entering a shell, -1 leaving it, so
                // overlapping closed shells (a cup and its handle) stay inside.
                let mut winding = 0i32;
                for w in 0..xs.len() {
                    winding += xs[w].1;
                    if winding <= 0 || w + 1 == xs.len() {
                        continue;
                    }
                    let (x0, x1) = (xs[w].0, xs[w + 1].0);
                    let i0 = ((x0 - origin.x) / h - 0.5).ceil().max(0.0) as usize;
                    let i1 = (((x1 - origin.x) / h - 0.5).floor().max(-1.0) + 1.0) as usize;
                    for i in i0..i1.min(dims[0]) {
                        let idx = grid.index(i, j, k);
                        grid.inside[idx] = true;
                    }
                }
            }
        }
        if !grid.inside.iter().any(|&b| b) {
            return Err(GraspError::Core(opengrasp_core::CoreError::DegenerateMesh {
                reason: format!("no voxel of size {h} m lies inside the mesh"),
            }));
        }
        Ok(grid)
    }

    /// Exact squared Euclidean distance (in voxel units²) from each voxel centre to the nearest
    /// outside voxel centre; 0 outside.
    fn distance_transform(&self) -> Vec<f64> {
        let [nx, ny, nz] = self.dims;
        let big = ((nx * nx + ny * ny + nz * nz) as f64) * 4.0 + 1.0;
        let mut d: Vec<f64> = self.inside.iter().map(|&b| if b { big } else { 0.0 }).collect();
        let n = nx.max(ny).max(nz);
        let mut f = vec![0.0; n];
        let mut out = vec![0.0; n];
        let mut v = vec![0usize; n];
        let mut z = vec![0.0; n + 1];
        for (axis, len) in [(0usize, nx), (1, ny), (2, nz)] {
            let (ca, cb) = match axis {
                0 => (ny, nz),
                1 => (nx, nz),
                _ => (nx, ny),
            };
            for b in 0..cb {
                for a in 0..ca {
                    let at = |s: usize| match axis {
                        0 => (b * ny + a) * nx + s,
                        1 => (b * ny + s) * nx + a,
                        _ => (s * ny + b) * nx + a,
                    };
                    for (s, fs) in f.iter_mut().enumerate().take(len) {
                        *fs = d[at(s)];
                    }
                    edt_1d(&f[..len], &mut out[..len], &mut v, &mut z);
                    for (s, os) in out.iter().enumerate().take(len) {
                        d[at(s)] = *os;
                    }
                }
            }
        }
        d
    }

    /// The ridge voxels of the distance field as balls.
    fn medial_balls(&self, d2: &[f64], o: &MedialAxisOptions) -> Vec<MedialBall> {
        let [nx, ny, nz] = self.dims;
        let dist: Vec<f64> = d2.iter().map(|x| x.sqrt()).collect();
        let mut balls = Vec::new();
        for k in 1..nz.saturating_sub(1) {
            for j in 1..ny.saturating_sub(1) {
                for i in 1..nx.saturating_sub(1) {
                    let p = self.index(i, j, k);
                    if !self.inside[p] {
                        continue;
                    }
                    // Radius to the surface: half a voxel less than to the nearest outside centre.
                    let r = dist[p] - 0.5;
                    if r < o.min_radius_voxels {
                        continue;
                    }
                    let mut ridge = true;
                    'n: for dk in -1i64..=1 {
                        for dj in -1i64..=1 {
                            for di in -1i64..=1 {
                                if di == 0 && dj == 0 && dk == 0 {
                                    continue;
                                }
                                let q = self.index(
                                    (i as i64 + di) as usize,
                                    (j as i64 + dj) as usize,
                                    (k as i64 + dk) as usize,
                                );
                                let len = ((di * di + dj * dj + dk * dk) as f64).sqrt();
                                if dist[q] - dist[p] > o.max_slope * len {
                                    ridge = false;
                                    break 'n;
                                }
                            }
                        }
                    }
                    if ridge {
                        balls.push(MedialBall { center: self.center(i, j, k), radius: r * self.h });
                    }
                }
            }
        }
        balls
    }
}

/// Where the line {(x, y, z)} crosses triangle abc, if its (y, z) projection contains (y, z):
/// `(x, +1)` if the ray along +x enters through the triangle (outward normal has x < 0),
/// `(x, -1)` if it leaves.
fn column_hit(a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>, y: f64, z: f64) -> Option<(f64, i32)> {
    let det = (b.y - a.y) * (c.z - a.z) - (c.y - a.y) * (b.z - a.z);
    if det.abs() < 1e-300 {
        return None;
    }
    let u = ((y - a.y) * (c.z - a.z) - (c.y - a.y) * (z - a.z)) / det;
    let w = ((b.y - a.y) * (z - a.z) - (y - a.y) * (b.z - a.z)) / det;
    if u < 0.0 || w < 0.0 || u + w > 1.0 {
        return None;
    }
    Some((a.x + u * (b.x - a.x) + w * (c.x - a.x), if det < 0.0 { 1 } else { -1 }))
}

/// One-dimensional squared distance transform of sampled function `f` (Felzenszwalb–Huttenlocher).
fn edt_1d(f: &[f64], d: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    if n == 0 {
        return;
    }
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in 1..n {
        let mut s;
        loop {
            let p = v[k];
            s = ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q as f64 - p as f64));
            // z[0] is -inf, so this never steps below 0.
            if s <= z[k] {
                k -= 1;
            } else {
                break;
            }
        }
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (q, dq) in d.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        let dx = q as f64 - p as f64;
        *dq = dx * dx + f[p];
    }
}
