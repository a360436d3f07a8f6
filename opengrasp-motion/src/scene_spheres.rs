//! A conservative sphere model of a robot in a core [`Scene`], for planning.
//!
//! [`SceneSphereModel`] turns a scene into a [`SphereWorld`] whose verdicts are never more
//! lenient than those of core's exact [`CollisionWorld`]: every state the model accepts is
//! collision-free under the exact geometry. Planners may search on it (fast closed-form
//! checks); the benchmark's validators keep judging with the exact checker.
//!
//! - **Links the group moves** are covered by spheres that contain their *solid* (not only the
//!   surface), so two solids that meet have covers that meet ([`shape_cover`]):
//!   a sphere by itself; a capsule by balls of its radius at the segment ends and slice balls
//!   between them; a cylinder by slice balls along its axis; a box by the circumspheres of
//!   cells tiling it (the fewer of the best uniform grid and an adaptive tree, whose cells are
//!   halved along their longest side), each reaching at most the budget beyond the box; a mesh
//!   by its guaranteed greedy surface cover
//!   ([`greedy_cover`]: surface only).
//! - **Links the group does not move** never change pose: they become obstacles with their
//!   exact closed-form shapes (meshes: the oriented box of their bounding box). Every moving
//!   link is checked against them, allowed pairs included (stricter than the exact world).
//!   Their collisions with the environment do not depend on the state: decided once by the
//!   exact world's link distances.
//! - **Obstacles**: static bodies and free objects with their exact closed-form shapes, meshes
//!   as the oriented box of their bounding box (which contains the mesh).
//! - **Self-collision**: the link pairs the exact world checks (its allowed-collision matrix).
//!   Moving links that move rigidly together (the same last group joint on their chains) and
//!   are allowed to touch the same links elsewhere are merged into one sphere-world link, so a
//!   state check culls a few bodies rather than dozens of links; the pairs inside such a body
//!   never change and are decided once, on the covers.
//! - **Reach**: obstacles no moving link can reach in any configuration (a ball about the first
//!   group joint on its chain) are left out.
//!
//! Carried objects and scenes with several robots are refused with a typed error.

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Translation3, Vector3};
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::kinematics::forward_kinematics_into;
use opengrasp_core::model::{Geometry, JointGroup, JointId, LinkId, Robot, Shape};
use opengrasp_core::scene::{RobotId, Scene};

use crate::error::{MotionError, Result};
use crate::validity::cover::{greedy_cover, slice_balls, GreedyCoverOptions};
use crate::validity::{ObstaclePrimitive, ObstacleShape, SelfCollisionPairs, SphereWorld, StateValidityChecker};

/// Most spheres [`shape_cover`] makes for one shape before refusing the budget.
pub const MAX_SHAPE_SPHERES: usize = 4096;

/// Options of [`SceneSphereModel`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneModelOptions {
    /// Largest reach of a box cover, and of a capsule's or cylinder's side cover, beyond the
    /// solid (m). Default 0.004.
    pub max_overhang: f64,
    /// The same as a fraction of the shape's thinnest half extent (box) or radius (capsule,
    /// cylinder), used when larger than `max_overhang`: fewer spheres for big links. Default
    /// 0.2.
    pub relative_overhang: f64,
    /// Cover of mesh links (surface guarantee). Default: [`GreedyCoverOptions::default`].
    pub meshes: GreedyCoverOptions,
}

impl Default for SceneModelOptions {
    fn default() -> Self {
        Self { max_overhang: 0.004, relative_overhang: 0.2, meshes: GreedyCoverOptions::default() }
    }
}

impl SceneModelOptions {
    fn validate(&self) -> Result<()> {
        if !(self.max_overhang.is_finite() && self.max_overhang > 0.0) {
            return Err(MotionError::InvalidParameter {
                name: "max_overhang",
                reason: format!("{} is not a positive length", self.max_overhang),
            });
        }
        if !(self.relative_overhang.is_finite() && self.relative_overhang >= 0.0) {
            return Err(MotionError::InvalidParameter {
                name: "relative_overhang",
                reason: format!("{} is not a fraction ≥ 0", self.relative_overhang),
            });
        }
        Ok(())
    }
}

/// Appends to `out` spheres `(centre, radius)` in the parent frame of `geometry` (placed at
/// `origin`) whose union contains the solid (for meshes: the surface), as described in the
/// [module docs](self).
///
/// # Errors
/// [`MotionError::InvalidParameter`] for bad options or a budget needing more than
/// [`MAX_SHAPE_SPHERES`] spheres; errors of [`greedy_cover`] for meshes.
pub fn shape_cover(
    geometry: &Geometry,
    origin: &Isometry3<f64>,
    options: &SceneModelOptions,
    out: &mut Vec<(Point3<f64>, f64)>,
) -> Result<()> {
    options.validate()?;
    let budget = |size: f64| options.max_overhang.max(options.relative_overhang * size);
    // Rounding slack: a computed radius never falls short of the exact one.
    let grow = |r: f64| r * (1.0 + 1e-9) + 1e-12;
    match geometry {
        Geometry::Sphere { radius } => out.push((origin * Point3::origin(), *radius)),
        Geometry::Capsule { radius, length } => {
            // End balls of the capsule's radius; the cylinder between them covered by slice balls.
            for z in [-0.5 * length, 0.5 * length] {
                out.push((origin * Point3::new(0.0, 0.0, z), *radius));
            }
            let n = slices(*radius, *length, budget(*radius));
            out.extend(slice_balls(origin, *radius, *length, n).map(|(c, r)| (c, grow(r))));
        }
        Geometry::Cylinder { radius, length } => {
            let n = slices(*radius, *length, budget(*radius));
            out.extend(slice_balls(origin, *radius, *length, n).map(|(c, r)| (c, grow(r))));
        }
        Geometry::Box { half_extents: h } => {
            let budget = budget(h.min());
            let grid = box_grid(h, budget);
            let tree = box_tree(h, budget)?;
            let cells = if grid.len() <= tree.len() { grid } else { tree };
            out.extend(cells.iter().map(|(c, e)| (origin * Point3::from(*c), grow(e.norm()))));
        }
        Geometry::Mesh(mesh) => {
            out.extend(greedy_cover(mesh, &options.meshes)?.spheres.iter().map(|(c, r)| (origin * c, *r)));
        }
    }
    Ok(())
}

/// Cells `(centre, half extents)` tiling a box of half extents `h`: the uniform grid with the
/// fewest cells whose circumspheres reach at most `budget` beyond the box (a cell's
/// circumsphere reaches at most `|e| − depth(c)` beyond it, and the shallowest cell centre is
/// half the smallest cell side deep).
fn box_grid(h: &Vector3<f64>, budget: f64) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    // Cubic cells of side `budget / (√3 − 1) · 2` meet the budget: an upper bound per axis.
    let most = h.map(|e| ((e * (3f64.sqrt() - 1.0) / budget).ceil() as usize + 1).clamp(1, MAX_SHAPE_SPHERES));
    let mut best: Option<[usize; 3]> = None;
    for nx in 1..=most.x {
        for ny in 1..=most.y {
            for nz in 1..=most.z {
                let count = nx * ny * nz;
                if best.is_some_and(|b| b[0] * b[1] * b[2] <= count) || count > MAX_SHAPE_SPHERES {
                    break;
                }
                let e = Vector3::new(h.x / nx as f64, h.y / ny as f64, h.z / nz as f64);
                if e.norm() - e.min() <= budget {
                    best = Some([nx, ny, nz]);
                }
            }
        }
    }
    let Some(n) = best else { return Vec::new() };
    let e = Vector3::new(h.x / n[0] as f64, h.y / n[1] as f64, h.z / n[2] as f64);
    let mut cells = Vec::with_capacity(n[0] * n[1] * n[2]);
    for i in 0..n[0] {
        for j in 0..n[1] {
            for k in 0..n[2] {
                let at = |m: usize, e: f64, h: f64| -h + e * (2 * m + 1) as f64;
                cells.push((Vector3::new(at(i, e.x, h.x), at(j, e.y, h.y), at(k, e.z, h.z)), e));
            }
        }
    }
    cells
}

/// Cells tiling a box of half extents `h`, halved along their longest side until the
/// circumsphere reaches at most `budget` beyond the box (`|e| − depth(c)`, as for
/// [`box_grid`]): large cells inside, small ones at the surface.
///
/// # Errors
/// [`MotionError::InvalidParameter`] past [`MAX_SHAPE_SPHERES`] cells.
fn box_tree(h: &Vector3<f64>, budget: f64) -> Result<Vec<(Vector3<f64>, Vector3<f64>)>> {
    let mut cells = Vec::new();
    let mut stack = vec![(Vector3::zeros(), *h)];
    while let Some((c, e)) = stack.pop() {
        let depth = (h - c.abs()).min();
        if e.norm() - depth <= budget {
            cells.push((c, e));
            if cells.len() > MAX_SHAPE_SPHERES {
                return Err(MotionError::InvalidParameter {
                    name: "max_overhang",
                    reason: format!("{budget} m needs more than {MAX_SHAPE_SPHERES} spheres for a box"),
                });
            }
            continue;
        }
        let i = e.imax();
        let mut half = e;
        half[i] *= 0.5;
        let d = Vector3::ith(i, half[i]);
        stack.push((c - d, half));
        stack.push((c + d, half));
    }
    Ok(cells)
}

/// How many slices of a cylinder of `radius` and `length` keep their [`slice_balls`]
/// (radius `√(r² + s²/4)`) within `budget` of its side.
fn slices(radius: f64, length: f64, budget: f64) -> usize {
    let most = 2.0 * ((radius + budget).powi(2) - radius * radius).sqrt();
    ((length / most).ceil() as usize).max(1)
}

/// How far the spheres of [`shape_cover`] reach beyond a closed-form `geometry` at the origin
/// (m): the largest `radius + signed distance of the centre`, an upper bound on the distance
/// from a sphere point to the solid. `None` for meshes.
pub fn cover_overhang(geometry: &Geometry, spheres: &[(Point3<f64>, f64)]) -> Option<f64> {
    let solid = ObstaclePrimitive::from_geometry("shape", Isometry3::identity(), geometry).ok()?;
    Some(spheres.iter().map(|(c, r)| r + solid.signed_distance(c)).fold(f64::NEG_INFINITY, f64::max))
}

/// A conservative sphere model of one robot of a core scene (see the [module docs](self)):
/// a [`SphereWorld`] of the links the group moves among the scene's obstacles and the links it
/// does not move. A planning checker: only the state and motion checks are provided.
#[derive(Clone, Debug)]
pub struct SceneSphereModel {
    world: SphereWorld,
    /// The links the group does not move are clear of the environment (exact, once).
    static_clear: bool,
    overhang: f64,
    static_links: usize,
    /// Obstacles left out because no moving link can reach them.
    unreachable: usize,
    /// Links of the sphere world (moving links merged into rigid bodies).
    bodies: usize,
}

impl SceneSphereModel {
    /// The model of robot `robot_id` of `scene`, moving the joints of `group` with the others
    /// at `q_full`; `world` is the exact collision world of `scene` (its allowed-collision
    /// matrix and the once-per-model check of the links the group does not move).
    ///
    /// # Errors
    /// [`MotionError::InvalidParameter`] for bad options, a scene with other robots or
    /// carried objects (not modelled), or two links the group does not move that the exact
    /// world checks against each other (not modelled); [`MotionError::DimensionMismatch`] for
    /// a `q_full` of the wrong length; core errors for a bad robot handle or configuration.
    pub fn new(
        scene: &Scene,
        robot_id: RobotId,
        group: &JointGroup,
        q_full: &[f64],
        world: &CollisionWorld,
        options: &SceneModelOptions,
    ) -> Result<Self> {
        options.validate()?;
        let not_modelled = |reason: String| MotionError::InvalidParameter { name: "scene", reason };
        if scene.robots().len() != 1 {
            return Err(not_modelled("the sphere model takes scenes with one robot".into()));
        }
        if !scene.attachments().is_empty() {
            return Err(not_modelled("the sphere model does not model carried objects".into()));
        }
        let entry = scene.robot(robot_id)?;
        let robot = entry.robot.clone();
        if q_full.len() != robot.dof() {
            return Err(MotionError::DimensionMismatch { expected: robot.dof(), actual: q_full.len() });
        }
        robot.validate_configuration(q_full)?;
        let mut poses = Vec::new();
        forward_kinematics_into(&robot, q_full, &mut poses);
        let moved = moved_links(&robot, group);
        let with_geometry: Vec<usize> =
            (0..robot.links().len()).filter(|&l| !robot.links()[l].collisions.is_empty()).collect();

        // Links the group does not move: obstacles, checked against the environment once.
        let mut obstacles = Vec::new();
        let fixed: Vec<usize> = with_geometry.iter().copied().filter(|&l| !moved[l]).collect();
        for (i, &a) in fixed.iter().enumerate() {
            for &b in &fixed[i + 1..] {
                if !world.is_collision_allowed(robot_id, LinkId(a), LinkId(b))? {
                    return Err(not_modelled(format!(
                        "links `{}` and `{}` do not move with the group and are checked against each other",
                        robot.links()[a].name,
                        robot.links()[b].name
                    )));
                }
            }
            let link = &robot.links()[a];
            let pose = entry.base_pose * poses[a];
            obstacles.extend(link.collisions.iter().map(|s| solid(&link.name, &pose, s)));
        }
        let selected: Vec<bool> = (0..robot.links().len()).map(|l| !moved[l]).collect();
        let mut distances = Vec::new();
        world.selected_link_distances_into(robot_id, q_full, &selected, &mut distances)?;
        let static_clear = fixed.iter().all(|&l| distances[l] > 0.0);
        for body in scene.bodies() {
            obstacles.extend(body.shapes.iter().map(|s| solid(&body.name, &body.pose, s)));
        }
        for object in scene.objects() {
            obstacles.extend(object.shapes.iter().map(|s| solid(&object.name, &object.pose, s)));
        }

        // Links the group moves: their solids covered by spheres (in the link frame).
        let mut covers: Vec<Vec<(Point3<f64>, f64)>> = vec![Vec::new(); robot.links().len()];
        let mut overhang: f64 = 0.0;
        let mut buf = Vec::new();
        let moving: Vec<usize> = with_geometry.iter().copied().filter(|&l| moved[l]).collect();
        for &l in &moving {
            for shape in &robot.links()[l].collisions {
                buf.clear();
                shape_cover(&shape.geometry, &Isometry3::identity(), options, &mut buf)?;
                overhang = overhang.max(cover_overhang(&shape.geometry, &buf).unwrap_or(options.meshes.max_overhang));
                covers[l].extend(buf.iter().map(|(c, r)| (shape.origin * c, *r)));
            }
        }
        // Links that move rigidly together (the same last group joint on their chains) and are
        // allowed to touch the same links of the other bodies are merged into one (fewer
        // links to cull per state). Pairs inside a body never change: decided once here.
        let body = |l: usize| robot.chain_to(LinkId(l)).into_iter().rev().find(|&j| in_group(&robot, group, j));
        let mut allowed_with = vec![vec![false; robot.links().len()]; robot.links().len()];
        for &a in &moving {
            for &b in &moving {
                allowed_with[a][b] = a == b || world.is_collision_allowed(robot_id, LinkId(a), LinkId(b))?;
            }
        }
        let signature = |a: usize| -> Vec<bool> {
            moving.iter().filter(|&&b| body(b) != body(a)).map(|&b| allowed_with[a][b]).collect()
        };
        let mut rigid_clear = true;
        let mut classes: Vec<(Option<JointId>, Vec<bool>, Vec<usize>)> = Vec::new();
        for &a in &moving {
            let (key, sig) = (body(a), signature(a));
            for &b in moving.iter().filter(|&&b| b < a && body(b) == key && !allowed_with[a][b]) {
                rigid_clear &= covers_apart(&covers[a], &poses[a], &covers[b], &poses[b]);
            }
            // A body is split into pieces no wider than `PIECE` so that culling stays tight.
            let ball = cover_ball(&covers[a], &poses[a]);
            let piece = classes.iter_mut().find(|c| {
                c.0 == key && c.1 == sig && {
                    let (p, r) = cover_ball(
                        &c.2.iter().flat_map(|&m| world_cover(&covers[m], &poses[m])).collect::<Vec<_>>(),
                        &Isometry3::identity(),
                    );
                    (p - ball.0).norm() + ball.1.max(r) <= PIECE
                }
            });
            match piece {
                Some(class) => class.2.push(a),
                None => classes.push((key, sig, vec![a])),
            }
        }
        let mut spherized: Robot = (*robot).clone();
        for &l in &with_geometry {
            spherized.link_mut(LinkId(l)).collisions.clear();
        }
        for (_, _, members) in &classes {
            let rep = members[0];
            let into_rep = poses[rep].inverse();
            spherized.link_mut(LinkId(rep)).collisions = members
                .iter()
                .flat_map(|&m| covers[m].iter().map(move |&(c, r)| (m, c, r)))
                .map(|(m, c, r)| {
                    let c = into_rep * (poses[m] * c);
                    Shape::new(Translation3::from(c.coords).into(), Geometry::Sphere { radius: r })
                })
                .collect();
        }
        let mut allowed = Vec::new();
        for (i, a) in classes.iter().enumerate() {
            for b in &classes[i + 1..] {
                let (ra, rb) = (a.2[0], b.2[0]);
                // Pairs of one body are decided above; the others by the shared rule.
                if a.0 == b.0 || allowed_with[ra][rb] {
                    allowed.push((LinkId(ra), LinkId(rb)));
                }
            }
        }
        let static_clear = static_clear && rigid_clear;
        // Obstacles no moving link can reach are left out.
        let reach = reach_balls(&robot, group, &spherized, &moved, &poses, &entry.base_pose);
        let total = obstacles.len();
        if let Some(reach) = reach {
            obstacles.retain(|o| reach.iter().any(|(p, r)| o.signed_distance(p) <= *r));
        }
        let model = SphereWorld::new(Arc::new(spherized), group.clone(), q_full.to_vec(), entry.base_pose, Vec::new())?
            .with_self_collision(SelfCollisionPairs::Robot)
            .with_link_tables(true);
        let kept = obstacles.len();
        let world = model.for_problem(q_full.to_vec(), obstacles, &allowed)?;
        Ok(Self {
            world,
            static_clear,
            overhang,
            static_links: fixed.len(),
            unreachable: total - kept,
            bodies: classes.len(),
        })
    }

    /// The sphere world of the links the group moves.
    pub fn sphere_world(&self) -> &SphereWorld {
        &self.world
    }

    /// True if the links the group does not move are clear of the environment (exact);
    /// otherwise every state is invalid, as under the exact geometry.
    pub fn static_clear(&self) -> bool {
        self.static_clear
    }

    /// Upper bound on how far a covering sphere reaches beyond its link's solid (m; for mesh
    /// links the greedy cover's budget).
    pub fn max_overhang(&self) -> f64 {
        self.overhang
    }

    /// Number of links the group does not move (modelled as obstacles).
    pub fn static_link_count(&self) -> usize {
        self.static_links
    }

    /// Number of obstacles left out because no moving link can reach them.
    pub fn unreachable_obstacle_count(&self) -> usize {
        self.unreachable
    }

    /// Number of sphere-world links: the moving links with geometry, merged where they move
    /// rigidly together and may touch the same links of the other bodies.
    pub fn body_count(&self) -> usize {
        self.bodies
    }
}

/// Largest radius of a merged body piece (m): see [`SceneSphereModel`].
const PIECE: f64 = 0.12;

/// The spheres of `cover` placed at `pose`.
fn world_cover(cover: &[(Point3<f64>, f64)], pose: &Isometry3<f64>) -> Vec<(Point3<f64>, f64)> {
    cover.iter().map(|(c, r)| (pose * c, *r)).collect()
}

/// A ball holding the spheres of `cover` placed at `pose`: about their mean centre.
fn cover_ball(cover: &[(Point3<f64>, f64)], pose: &Isometry3<f64>) -> (Point3<f64>, f64) {
    let placed = world_cover(cover, pose);
    let n = placed.len().max(1) as f64;
    let c = placed.iter().fold(Point3::origin(), |acc, (p, _)| acc + p.coords / n);
    (c, placed.iter().map(|(p, r)| (p - c).norm() + r).fold(0.0, f64::max))
}

/// True if joint `j` is driven by a dof of `group`.
fn in_group(robot: &Robot, group: &JointGroup, j: JointId) -> bool {
    robot.driving_dof(j).is_some_and(|(dof, _)| group.dofs().contains(&dof))
}

/// True if no sphere of cover `a` (link frame at `pa`) touches one of `b` (at `pb`).
fn covers_apart(a: &[(Point3<f64>, f64)], pa: &Isometry3<f64>, b: &[(Point3<f64>, f64)], pb: &Isometry3<f64>) -> bool {
    let b: Vec<_> = b.iter().map(|(c, r)| (pb * c, *r)).collect();
    a.iter().all(|(c, r)| {
        let c = pa * c;
        b.iter().all(|(d, s)| (c - d).norm() > r + s)
    })
}

/// Per moving link of `spherized` (covered by spheres), a ball that holds its spheres in every
/// configuration of the group: centred at the origin of the first group joint on its chain
/// (fixed in the world: the joints above it are held at `q_full`), of radius the sum of the
/// joint offsets below it plus the farthest sphere. `None` if a group joint translates
/// (prismatic: the reach depends on its limits; nothing is left out).
fn reach_balls(
    robot: &Robot,
    group: &JointGroup,
    spherized: &Robot,
    moved: &[bool],
    poses: &[Isometry3<f64>],
    base: &Isometry3<f64>,
) -> Option<Vec<(Point3<f64>, f64)>> {
    let mut balls = Vec::new();
    for (l, link) in spherized.links().iter().enumerate() {
        if !moved[l] || link.collisions.is_empty() {
            continue;
        }
        let chain = robot.chain_to(LinkId(l));
        let first = chain.iter().position(|&j| in_group(robot, group, j))?;
        let mut radius = 0.0;
        for &j in &chain[first..] {
            let joint = robot.joint(j);
            if joint.kind == opengrasp_core::model::JointKind::Prismatic {
                return None;
            }
            if j != chain[first] {
                radius += joint.origin.translation.vector.norm();
            }
        }
        let farthest = link
            .collisions
            .iter()
            .map(|s| {
                let r = match s.geometry {
                    Geometry::Sphere { radius } => radius,
                    _ => return f64::INFINITY,
                };
                s.origin.translation.vector.norm() + r
            })
            .fold(0.0, f64::max);
        let joint = robot.joint(chain[first]);
        let centre = base * poses[joint.parent.0] * Point3::from(joint.origin.translation.vector);
        balls.push((centre, radius + farthest));
    }
    Some(balls)
}

/// Per link: whether a joint of `group` (or a joint mimicking one) is on its chain.
fn moved_links(robot: &Robot, group: &JointGroup) -> Vec<bool> {
    (0..robot.links().len()).map(|l| robot.chain_to(LinkId(l)).iter().any(|&j| in_group(robot, group, j))).collect()
}

/// The obstacle of `shape` on a body at `pose`: its exact closed-form solid, or for a mesh
/// the oriented box of its bounding box.
fn solid(name: &str, pose: &Isometry3<f64>, shape: &Shape) -> ObstaclePrimitive {
    let at = pose * shape.origin;
    ObstaclePrimitive::from_geometry(name, at, &shape.geometry).unwrap_or_else(|_| {
        let (lo, hi) = shape.geometry.local_aabb();
        let c = nalgebra::center(&lo, &hi);
        let half_extents = 0.5 * (hi - lo);
        ObstaclePrimitive::new(name, at * Isometry3::translation(c.x, c.y, c.z), ObstacleShape::Box { half_extents })
    })
}

impl StateValidityChecker for SceneSphereModel {
    fn dim(&self) -> usize {
        self.world.dim()
    }

    fn is_valid(&self, q: &[f64]) -> bool {
        self.static_clear && self.world.is_valid(q)
    }

    fn are_valid(&self, qs: &[f64], out: &mut [bool]) {
        if self.static_clear {
            self.world.are_valid(qs, out);
        } else {
            out.fill(false);
        }
    }

    fn check_motion(&self, a: &[f64], b: &[f64], step: f64) -> (bool, u64) {
        if self.static_clear {
            self.world.check_motion(a, b, step)
        } else {
            (false, 1)
        }
    }

    fn state_certificate(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        out.clear();
        self.static_clear && self.world.state_certificate(q, out)
    }

    fn is_motion_valid_between(&self, a: &[f64], a_cert: &[f64], b: &[f64], b_cert: &[f64], step: f64) -> bool {
        self.static_clear && self.world.is_motion_valid_between(a, a_cert, b, b_cert, step)
    }
}
