//! A sphere-covered robot among closed-form obstacles: conservative, fast checks.

use std::sync::Arc;

use nalgebra::{Isometry3, Point3};
use opengrasp_core::kinematics::forward_kinematics_into;
use opengrasp_core::model::{JointGroup, LinkId, Robot};

use crate::error::Result;

use super::chain::{Chain, LANES};
use super::cover;
use super::soa::{with_scratch, ObstacleFrame, Scratch, SphereSoa};
use super::{MotionBound, ObstacleBox, ObstaclePrimitive, StateValidityChecker};

mod certified;
mod covered;
mod lanes;
mod link_table;
mod table;

use certified::Certificates;
use covered::Covered;
use link_table::LinkTable;
use table::PairTable;

/// Which link pairs a [`SphereWorld`] checks for self-collision.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SelfCollisionPairs {
    /// Pairs the robot does not allow ([`Robot::is_collision_allowed`]) and whose sphere covers
    /// do not overlap at the reference configuration (default; for robots without an SRDF,
    /// whose only allowed pairs are joint-adjacent links).
    #[default]
    NotOverlappingAtReference,
    /// Exactly the pairs the robot does not allow: joint-adjacent links and the SRDF's
    /// `<disable_collisions>` (applied to the robot by
    /// [`Srdf::apply`](opengrasp_core::srdf::Srdf::apply)) are skipped, every other pair of
    /// links with collision geometry is checked — the same matrix as the exact checker's.
    /// A checked pair whose covers overlap at the reference configuration makes that
    /// configuration invalid.
    Robot,
}

/// A robot whose links are covered by spheres, among closed-form obstacles (boxes, and with
/// [`SphereWorld::with_obstacles`] spheres, cylinders, capsules): closed-form, conservative
/// distances and fast state checks.
///
/// Each collision shape is covered by spheres (a capsule or cylinder of radius `r` by spheres
/// along its axis at spacing `s ≤ r`, radius `√(r² + s²/4)`; a box by a grid of spheres; a mesh
/// by its bounding box or, with [`MeshCover::Voxels`], by the cells its surface touches), so
/// the covered robot contains the real one (with voxels: its surface, which suffices unless an
/// obstacle fits wholly inside a link) and every distance is a
/// lower bound on the true distance. Self-collision is checked between sphere sets of link
/// pairs that are neither allowed by [`Robot::is_collision_allowed`] nor already overlapping at
/// the reference configuration (like an SRDF's "default" disabled pairs), or, with
/// [`SelfCollisionPairs::Robot`] ([`SphereWorld::with_self_collision`]), exactly the pairs of
/// the robot's SRDF.
///
/// The clearance is the smallest distance from a link the group moves to a box. For continuous
/// checking, [`StateValidityChecker::link_distances`] reports per link the
/// minimum of its distance to the boxes and half its distance to every checked link, so the
/// bound of [`MotionBound`] certifies self-collision too.
#[derive(Clone, Debug)]
pub struct SphereWorld {
    robot: Arc<Robot>,
    group: JointGroup,
    q_full: Vec<f64>,
    base_pose: Isometry3<f64>,
    /// (index into `links`, centre in link frame, radius)
    spheres: Vec<(usize, Point3<f64>, f64)>,
    /// Range of `spheres` per entry of `links`.
    ranges: Vec<(usize, usize)>,
    links: Vec<LinkId>,
    pairs: Vec<(usize, usize)>,
    /// The pairs with a moving link, checked per state; `fixed_ok`: the links fixed in the
    /// world are clear of the obstacles and of each other (the state-independent part).
    moving_pairs: Vec<(usize, usize)>,
    fixed_ok: bool,
    /// How `pairs` was chosen, and link pairs allowed on top of the robot's.
    pair_mode: SelfCollisionPairs,
    allowed: Vec<(LinkId, LinkId)>,
    boxes: Vec<ObstacleBox>,
    /// Every obstacle: the boxes, then the primitives added by [`SphereWorld::with_obstacles`].
    obstacles: Vec<ObstaclePrimitive>,
    bound: MotionBound,
    /// The group's kinematics, compiled, for the state checks.
    chain: Chain,
    /// The same spheres as `spheres`, struct of arrays in chain frames, for the state checks.
    soa: SphereSoa,
    /// A coarser cover of the same links, tried first ([`SphereWorld::with_coarse_cover`]).
    coarse: Option<(Arc<Covered>, SphereSoa)>,
    /// Whether batches and motions go through the multi-state kernels.
    batched: bool,
    /// The tests of a state check and their motion bounds, and whether motions skip tests
    /// their checked states certify ([`SphereWorld::with_certified_motions`]).
    cert: Certificates,
    certify: bool,
    /// Per moving pair, its distance table if it has one ([`SphereWorld::with_pair_tables`]).
    tables: Vec<Option<Arc<PairTable>>>,
    use_tables: bool,
    /// Per link, the table of its obstacle test if its spheres depend on one group value
    /// ([`SphereWorld::with_link_tables`]).
    link_tables: Vec<Option<Arc<LinkTable>>>,
    use_link_tables: bool,
}

/// How a [`SphereWorld`] covers mesh collision shapes (other shapes have closed-form covers).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum MeshCover {
    /// A grid of spheres over the mesh's bounding box ([`cover::bounding_box_cover`]; default).
    #[default]
    BoundingBox,
    /// One sphere per grid cell of this edge (m) the surface touches
    /// ([`cover::voxel_cover`]): every surface point covered, overhang at most `2√3 · cell`.
    Voxels {
        /// Cell edge (m).
        cell: f64,
    },
    /// Voxels merged into larger spheres within an overhang budget
    /// ([`cover::adaptive_cover`]): every surface point covered, fewer spheres.
    Adaptive {
        /// Smallest cell edge (m).
        cell: f64,
        /// Largest reach of a sphere past the surface (m), at least `2√3 · cell`.
        max_overhang: f64,
    },
    /// Freely placed spheres chosen by greedy set cover ([`cover::greedy_cover`]): every
    /// surface point covered, the fewest spheres for an overhang budget.
    Greedy(cover::GreedyCoverOptions),
}

impl SphereWorld {
    /// A world for `robot` (root link at `base_pose` in the world) moving the joints of
    /// `group`, with the other joints held at `q_full`, among `boxes`.
    ///
    /// # Errors
    /// [`MotionError::Core`](crate::MotionError::Core) if `q_full` is not a valid configuration of `robot`.
    pub fn new(
        robot: Arc<Robot>,
        group: JointGroup,
        q_full: Vec<f64>,
        base_pose: Isometry3<f64>,
        boxes: Vec<ObstacleBox>,
    ) -> Result<Self> {
        Self::with_mesh_cover(robot, group, q_full, base_pose, boxes, MeshCover::default())
    }

    /// Like [`SphereWorld::new`], covering mesh shapes as `meshes` says.
    ///
    /// # Errors
    /// As [`SphereWorld::new`]; [`MotionError::InvalidParameter`](crate::MotionError::InvalidParameter)
    /// for a bad voxel cell.
    pub fn with_mesh_cover(
        robot: Arc<Robot>,
        group: JointGroup,
        q_full: Vec<f64>,
        base_pose: Isometry3<f64>,
        boxes: Vec<ObstacleBox>,
        meshes: MeshCover,
    ) -> Result<Self> {
        robot.validate_configuration(&q_full)?;
        let Covered { links, spheres, ranges, points } = Covered::new(&robot, meshes)?;
        let bound = MotionBound::new(&robot, &group, &links, &points)?;
        let obstacles: Vec<ObstaclePrimitive> = boxes.iter().cloned().map(ObstaclePrimitive::from).collect();
        let chain = Chain::new(&robot, &group, &q_full, &base_pose);
        let link_frames: Vec<_> = links.iter().map(|&l| chain.link(l)).collect();
        let soa = SphereSoa::new(&spheres, &ranges, &link_frames, frames(&obstacles));
        let world = Self {
            robot,
            group,
            q_full,
            base_pose,
            spheres,
            ranges,
            links,
            pairs: Vec::new(),
            moving_pairs: Vec::new(),
            fixed_ok: true,
            pair_mode: SelfCollisionPairs::default(),
            allowed: Vec::new(),
            boxes,
            obstacles,
            bound,
            chain,
            soa,
            coarse: None,
            batched: false,
            cert: Certificates::default(),
            certify: true,
            tables: Vec::new(),
            use_tables: false,
            use_link_tables: false,
            link_tables: Vec::new(),
        };
        Ok(world.with_self_collision(SelfCollisionPairs::default()))
    }

    /// This world checking the self-collision pairs chosen by `pairs`.
    pub fn with_self_collision(mut self, pairs: SelfCollisionPairs) -> Self {
        self.pair_mode = pairs;
        let reference = self.q_full.clone();
        let centres = self.sphere_centres(&reference);
        let n = self.links.len();
        self.pairs.clear();
        for a in 0..n {
            for b in a + 1..n {
                let (la, lb) = (self.links[a], self.links[b]);
                if self.robot.is_collision_allowed(la, lb)
                    || self.allowed.iter().any(|&(x, y)| (x, y) == (la, lb) || (y, x) == (la, lb))
                {
                    continue;
                }
                if pairs == SelfCollisionPairs::Robot || self.pair_distance(&centres, a, b) > 0.0 {
                    self.pairs.push((a, b));
                }
            }
        }
        self.settle();
        self
    }

    /// This world with `obstacles` added (any closed-form solid; the boxes given at
    /// construction stay).
    ///
    /// # Errors
    /// [`MotionError::InvalidParameter`](crate::MotionError::InvalidParameter) for an obstacle
    /// with a non-positive or non-finite size or pose ([`ObstaclePrimitive::validate`]).
    pub fn with_obstacles(mut self, obstacles: impl IntoIterator<Item = ObstaclePrimitive>) -> Result<Self> {
        for o in obstacles {
            o.validate()?;
            self.obstacles.push(o);
        }
        self.rebuild();
        Ok(self)
    }

    /// The same robot model (spheres, self-collision rule) in another problem: the joints
    /// outside the group at `q_full`, among `obstacles` only, with the link pairs `allowed`
    /// to touch on top of the robot's. Cheap next to building the cover: use it to plan many
    /// problems with one robot.
    ///
    /// # Errors
    /// [`MotionError::Core`](crate::MotionError::Core) if `q_full` is not a configuration of
    /// the robot; as [`SphereWorld::with_obstacles`].
    pub fn for_problem(
        &self,
        q_full: Vec<f64>,
        obstacles: impl IntoIterator<Item = ObstaclePrimitive>,
        allowed: &[(LinkId, LinkId)],
    ) -> Result<Self> {
        self.robot.validate_configuration(&q_full)?;
        let mut world =
            Self { q_full, boxes: Vec::new(), obstacles: Vec::new(), allowed: allowed.to_vec(), ..self.clone() };
        world.chain = Chain::new(&world.robot, &world.group, &world.q_full, &world.base_pose);
        world = world.with_obstacles(obstacles)?;
        Ok(world.with_self_collision(self.pair_mode))
    }

    /// This world checking batches ([`StateValidityChecker::are_valid`]) and motions
    /// ([`StateValidityChecker::check_motion`]) a few states at a time, struct of arrays
    /// across the states (forward kinematics and sphere tests with the states innermost), or
    /// one state at a time (`false`, default). The verdicts and counts are the same; on the
    /// baseline x86-64 target (2 `f64` per vector, and the one-state kernels already vectorise
    /// across the spheres of a cluster) the batches are slower, because their states share
    /// the culling (`mbm/*/…one_by_one` bench rows); and batched motions use neither
    /// certificates ([`SphereWorld::with_certified_motions`]) nor pair tables.
    pub fn with_batched_checks(mut self, batched: bool) -> Self {
        self.batched = batched;
        self
    }

    /// This world checking motions ([`StateValidityChecker::check_motion`], one state at a
    /// time) with certificates (`true`, default): a test that passes at a state with sphere
    /// distance `g` is skipped at the states of the motion its links cannot reach within `g`
    /// ([`MotionBound`]; for a link pair, only the joints that move one link and not the
    /// other count), and a state whose tests are all certified is skipped. The verdicts and
    /// counts are those of checking every state (`false`).
    pub fn with_certified_motions(mut self, certify: bool) -> Self {
        self.certify = certify;
        self
    }

    /// This world settling the obstacle test of a link placed by one group value (the torso
    /// and idle arm on a humanoid's hip yaw) from a conservative table over that value first
    /// (`true`; `validity/spheres/link_table.rs`), kept by [`SphereWorld::for_problem`]'s
    /// worlds: a cell passes a test only with a positive lower bound on its gap, so the
    /// verdicts and counts are those without tables (`false`, the default). Each cell is
    /// computed on first use, so the tables pay off for a world that checks many motions
    /// in one environment (PRM's roadmap on the kitchen: setup −46 % instructions), not for
    /// short plans on a fresh world per problem (MotionBenchMaker's Panda: +7 % on cage).
    pub fn with_link_tables(mut self, tables: bool) -> Self {
        self.use_link_tables = tables;
        self.settle();
        self
    }

    /// The robot.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }
    /// The planning group.
    pub fn group(&self) -> &JointGroup {
        &self.group
    }
    /// The boxes given at construction.
    pub fn boxes(&self) -> &[ObstacleBox] {
        &self.boxes
    }
    /// Every obstacle: the boxes given at construction, then those added by
    /// [`SphereWorld::with_obstacles`].
    pub fn obstacles(&self) -> &[ObstaclePrimitive] {
        &self.obstacles
    }
    /// The covering spheres of each covered link: `(link, centre in the link frame, radius)`.
    pub fn spheres(&self) -> impl Iterator<Item = (LinkId, Point3<f64>, f64)> + '_ {
        self.spheres.iter().map(|&(k, c, r)| (self.links[k], c, r))
    }
    /// Number of covering spheres.
    pub fn sphere_count(&self) -> usize {
        self.spheres.len()
    }
    /// Number of spheres of the coarse cover ([`SphereWorld::with_coarse_cover`]), if any.
    pub fn coarse_sphere_count(&self) -> Option<usize> {
        self.coarse.as_ref().map(|(c, _)| c.spheres.len())
    }
    /// Link pairs checked for self-collision.
    pub fn self_collision_pairs(&self) -> Vec<(LinkId, LinkId)> {
        self.pairs.iter().map(|&(a, b)| (self.links[a], self.links[b])).collect()
    }
    /// The full configuration for group values `q` (other joints as given at construction).
    pub fn full_configuration(&self, q: &[f64]) -> Vec<f64> {
        let mut full = self.q_full.clone();
        for (&d, &v) in self.group.dofs().iter().zip(q) {
            full[d] = v;
        }
        full
    }

    fn sphere_centres(&self, q_full: &[f64]) -> Vec<Point3<f64>> {
        let mut poses = Vec::with_capacity(self.robot.links().len());
        forward_kinematics_into(&self.robot, q_full, &mut poses);
        let world: Vec<Isometry3<f64>> = self.links.iter().map(|l| self.base_pose * poses[l.0]).collect();
        self.spheres.iter().map(|(k, c, _)| world[*k] * c).collect()
    }

    fn centres_for(&self, q: &[f64]) -> Vec<Point3<f64>> {
        let full = self.full_configuration(q);
        self.sphere_centres(&full)
    }

    fn pair_distance(&self, centres: &[Point3<f64>], a: usize, b: usize) -> f64 {
        let (ra, rb) = (self.ranges[a], self.ranges[b]);
        let mut best = f64::INFINITY;
        for i in ra.0..ra.1 {
            for j in rb.0..rb.1 {
                let d = (centres[i] - centres[j]).norm() - self.spheres[i].2 - self.spheres[j].2;
                best = best.min(d);
            }
        }
        best
    }

    fn link_obstacle_distance(&self, centres: &[Point3<f64>], k: usize) -> f64 {
        let (s, e) = self.ranges[k];
        let mut best = f64::INFINITY;
        for (c, sphere) in centres[s..e].iter().zip(&self.spheres[s..e]) {
            for o in self.soa.obstacles() {
                best = best.min(o.signed_distance(c.x, c.y, c.z) - sphere.2);
            }
        }
        best
    }
}

fn frames(obstacles: &[ObstaclePrimitive]) -> Vec<ObstacleFrame> {
    obstacles.iter().map(|o| ObstacleFrame::new(&o.pose, o.shape)).collect()
}

impl SphereWorld {
    /// Rebuilds the struct-of-arrays spheres and obstacles from `chain` and `obstacles`.
    fn rebuild(&mut self) {
        let link_frames: Vec<_> = self.links.iter().map(|&l| self.chain.link(l)).collect();
        self.soa = SphereSoa::new(&self.spheres, &self.ranges, &link_frames, frames(&self.obstacles));
        if let Some((cover, _)) = self.coarse.take() {
            let soa = SphereSoa::new(&cover.spheres, &cover.ranges, &link_frames, frames(&self.obstacles));
            self.coarse = Some((cover, soa));
        }
        self.settle();
    }

    /// This world with a second, coarser cover of the same links (e.g. a greedy cover with a
    /// larger overhang budget) tried first: a link is clear of an obstacle or of another link
    /// when either cover says so. Both covers hold every surface point, so the verdicts stay
    /// conservative, and are never stricter than this cover's alone; the coarse cover's few
    /// spheres settle most tests.
    ///
    /// # Errors
    /// As [`SphereWorld::with_mesh_cover`] for the cover.
    pub fn with_coarse_cover(mut self, meshes: MeshCover) -> Result<Self> {
        let cover = Covered::new(&self.robot, meshes)?;
        // Same robot, same links with geometry.
        debug_assert_eq!(cover.links, self.links);
        self.coarse = Some((Arc::new(cover), SphereSoa::new(&[], &[], &[], Vec::new())));
        self.rebuild();
        Ok(self)
    }

    /// Splits the checks into the state-independent part (links fixed in the world against
    /// the obstacles and each other), evaluated once, and the pairs checked per state.
    /// Pairs of links on one chain frame (their relative pose is fixed) count as static too,
    /// checked once at the zero configuration (with the coarse cover first, as per state).
    fn settle(&mut self) {
        let rigid = |&(a, b): &(usize, usize)| self.soa.rigidly_attached(a, b);
        self.moving_pairs = self.pairs.iter().copied().filter(|p| !rigid(p)).collect();
        let static_pairs_clear = with_scratch(|s| {
            self.chain.frames(&vec![0.0; self.group.len()], &mut s.frames);
            self.soa.begin(&s.frames, &mut s.centres);
            let (frames, centres, rough) = (&s.frames, &mut s.centres, &mut s.coarse);
            let coarse = self.coarse.as_ref().map(|(_, soa)| soa);
            if let Some(coarse) = coarse {
                coarse.begin_lazy(rough);
            }
            self.pairs.iter().filter(|p| rigid(p)).all(|&(a, b)| {
                coarse.is_some_and(|coarse| coarse.pair_clear(frames, rough, a, b))
                    || self.soa.pair_clear(frames, centres, a, b)
            })
        });
        self.fixed_ok = self.soa.static_free_of_obstacles() && static_pairs_clear;
        self.cert = self.motion_tests();
        self.tables = self.pair_tables();
        self.link_tables = self.link_tables();
    }

    /// The state check behind [`StateValidityChecker::is_valid`]: the compiled forward
    /// kinematics, the sphere centres as struct-of-arrays, then obstacles and self-collision
    /// pairs, each culled by the link's bounding sphere first.
    fn check_state(&self, q: &[f64], s: &mut Scratch) -> bool {
        if !self.fixed_ok {
            return false;
        }
        self.chain.frames(q, &mut s.frames);
        self.soa.begin(&s.frames, &mut s.centres);
        let (frames, fine) = (&s.frames, &mut s.centres);
        let Some((_, coarse)) = &self.coarse else {
            return self.soa.free_of_obstacles(frames, fine)
                && self
                    .moving_pairs
                    .iter()
                    .enumerate()
                    .all(|(p, &(a, b))| self.table_gap(p, q).is_some() || self.soa.pair_clear(frames, fine, a, b));
        };
        coarse.begin_lazy(&mut s.coarse);
        let rough = &mut s.coarse;
        for o in 0..self.obstacles.len() {
            for k in 0..self.links.len() {
                if self.soa.is_static(k) || !self.soa.link_near(o, k, fine) {
                    continue;
                }
                if !coarse.link_clear(o, k, frames, rough) && !self.soa.link_clear(o, k, frames, fine) {
                    return false;
                }
            }
        }
        self.moving_pairs.iter().enumerate().all(|(p, &(a, b))| {
            self.table_gap(p, q).is_some()
                || coarse.pair_clear(frames, rough, a, b)
                || self.soa.pair_clear(frames, fine, a, b)
        })
    }
}

impl StateValidityChecker for SphereWorld {
    fn dim(&self) -> usize {
        self.group.len()
    }

    fn is_valid(&self, q: &[f64]) -> bool {
        with_scratch(|s| self.check_state(q, s))
    }

    /// One state at a time, or with [`SphereWorld::with_batched_checks`] in batches of a few
    /// states (same verdicts as [`StateValidityChecker::is_valid`] either way).
    fn are_valid(&self, qs: &[f64], out: &mut [bool]) {
        let dim = self.group.len().max(1);
        if !self.batched {
            return with_scratch(|s| {
                for (q, o) in qs.chunks_exact(dim).zip(out.iter_mut()) {
                    *o = self.check_state(q, s);
                }
            });
        }
        with_scratch(|s| {
            for (qs, out) in qs.chunks(dim * LANES).zip(out.chunks_mut(LANES)) {
                let count = (qs.len() / dim).min(out.len());
                let used = self.load_lanes(s, count, |l, q| q.copy_from_slice(&qs[l * dim..(l + 1) * dim]));
                let valid = self.check_lanes(s, used);
                out[..count].copy_from_slice(&valid[..count]);
            }
        })
    }

    /// Coarse to fine, one state at a time on the compiled kernels, or with
    /// [`SphereWorld::with_batched_checks`] in batches of a few states (same verdict and count
    /// as the one-by-one default either way).
    fn check_motion(&self, a: &[f64], b: &[f64], step: f64) -> (bool, u64) {
        with_scratch(|s| {
            if self.batched {
                return self.check_motion_lanes(s, a, b, step);
            }
            if let Some(verdict) = self.certify.then(|| self.check_motion_certified(s, a, b, step, None)).flatten() {
                return verdict;
            }
            let mut q = std::mem::take(&mut s.q);
            let mut checked = 0;
            let valid = crate::validate::segment_valid_discrete_into(
                &mut q,
                |q| {
                    checked += 1;
                    self.check_state(q, s)
                },
                a,
                b,
                step,
            );
            s.q = q;
            (valid, checked)
        })
    }

    fn clearance(&self, q: &[f64]) -> Option<f64> {
        let centres = self.centres_for(q);
        Some(
            (0..self.links.len())
                .filter(|&k| self.bound.is_moving(k))
                .map(|k| self.link_obstacle_distance(&centres, k))
                .fold(f64::INFINITY, f64::min),
        )
    }

    fn link_distances(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        let centres = self.centres_for(q);
        out.clear();
        out.extend((0..self.links.len()).map(|k| self.link_obstacle_distance(&centres, k)));
        for &(a, b) in &self.pairs {
            let half = 0.5 * self.pair_distance(&centres, a, b);
            out[a] = out[a].min(half);
            out[b] = out[b].min(half);
        }
        true
    }

    fn motion_bound(&self) -> Option<&MotionBound> {
        Some(&self.bound)
    }

    fn ccd_covers_self_collision(&self) -> bool {
        true
    }

    /// The gap of every test of the state check (obstacle and pair tests), when motions are
    /// certified and not batched.
    fn state_certificate(&self, q: &[f64], out: &mut Vec<f64>) -> bool {
        if !self.certify || self.batched {
            out.clear();
            return self.is_valid(q);
        }
        with_scratch(|s| self.certify_state(s, q, out))
    }

    /// Certified like [`StateValidityChecker::check_motion`], the tests' gaps at the ends
    /// certifying the states near them.
    fn is_motion_valid_between(&self, a: &[f64], a_cert: &[f64], b: &[f64], b_cert: &[f64], step: f64) -> bool {
        let n = self.test_count();
        if self.certify && !self.batched && a_cert.len() == n && b_cert.len() == n {
            let ends = Some((a_cert, b_cert));
            if let Some((valid, _)) = with_scratch(|s| self.check_motion_certified(s, a, b, step, ends)) {
                return valid;
            }
        }
        self.is_motion_valid(a, b, step)
    }
}
