//! A robot's collision check split into tests that each report a lower bound on their
//! distance (a *gap*), so that a motion check can skip the tests a nearby state certifies.

use std::ops::ControlFlow;

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};

use super::narrow::{aabb_distance, capsule_cuboid_distance, distance, intersects_placed, Placed};
use super::{with_scratch, CollisionWorld};
use crate::error::Result;
use crate::model::LinkId;
use crate::scene::RobotId;

/// One test of a robot's collision check (see [`CollisionWorld::gap_tests`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GapTest {
    /// Collision part `part` of the robot (on link `link`) against every obstacle: static
    /// bodies, objects and the links of other robots.
    Obstacles {
        /// Index of the part among the robot's collision parts.
        part: usize,
        /// The link carrying the part.
        link: LinkId,
    },
    /// Parts `a` and `b` of the robot, a self-collision pair the check tests.
    Pair {
        /// First part.
        a: usize,
        /// Second part.
        b: usize,
        /// The link of part `a`.
        link_a: LinkId,
        /// The link of part `b`.
        link_b: LinkId,
    },
}

impl CollisionWorld {
    /// The tests of robot `robot`'s collision check ([`in_collision_unchecked`](Self::in_collision_unchecked)):
    /// its self-collision pairs, then each of its parts against the obstacles. The robot's
    /// configuration is collision-free exactly when every test passes. `None` when the robot
    /// carries objects (their tests are not covered).
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`](crate::CoreError::InvalidHandle) for a bad robot.
    pub fn gap_tests(&self, robot: RobotId) -> Result<Option<Vec<GapTest>>> {
        let r = self.robot_entry(robot)?;
        if self.carries_objects(robot.0) {
            return Ok(None);
        }
        let mut tests: Vec<GapTest> = r
            .self_pairs
            .iter()
            .map(|&(a, b)| GapTest::Pair {
                a: a as usize,
                b: b as usize,
                link_a: r.part_link[a as usize],
                link_b: r.part_link[b as usize],
            })
            .collect();
        tests.extend(r.part_link.iter().enumerate().map(|(part, &link)| GapTest::Obstacles { part, link }));
        Ok(Some(tests))
    }

    fn carries_objects(&self, rid: usize) -> bool {
        self.objects.iter().any(|o| o.attached.as_ref().is_some_and(|a| a.robot.0 == rid))
    }

    /// Runs the tests of [`gap_tests`](Self::gap_tests) (`tests`, from this world and robot)
    /// at configuration `q`, except those with `skip(t)`, and returns true if all of them
    /// pass: with nothing skipped, exactly `!in_collision_unchecked(robot, q)`.
    ///
    /// `out` receives one entry per test: for a test that ran and passed, a lower bound on the
    /// distance between its shapes (between the part and every obstacle), at most `cap`;
    /// `NaN` for a skipped test. Obstacles farther than `cap` from a part's bounding box are
    /// not visited. On a failed test `out`'s content is unspecified. A robot carrying objects
    /// gets the plain check and gaps of 0.
    ///
    /// # Panics
    /// If `robot` is not a robot of this world, `q` is shorter than the robot's DoF, or a test
    /// refers to a part the robot does not have.
    pub fn gaps_unchecked(
        &self,
        robot: RobotId,
        q: &[f64],
        tests: &[GapTest],
        cap: f64,
        skip: impl Fn(usize) -> bool,
        out: &mut Vec<f64>,
    ) -> bool {
        out.clear();
        let rid = robot.0;
        if self.carries_objects(rid) {
            out.resize(tests.len(), 0.0);
            return !self.in_collision_unchecked(robot, q);
        }
        with_scratch(|s| {
            self.place(rid, q, s);
            for (t, test) in tests.iter().enumerate() {
                if skip(t) {
                    out.push(f64::NAN);
                    continue;
                }
                let gap = match *test {
                    GapTest::Pair { a, b, .. } => {
                        let (a, b) = (&s.items[a], &s.items[b]);
                        let (pa, pb) = (self.item_placed(rid, a), self.item_placed(rid, b));
                        if a.aabb.intersects(&b.aabb) && intersects_placed(pa, pb) {
                            return false;
                        }
                        gap_lower_bound(pa, &a.aabb, pb, &b.aabb).min(cap)
                    }
                    GapTest::Obstacles { part, .. } => {
                        let item = &s.items[part];
                        let placed = self.item_placed(rid, item);
                        let mut gap = cap;
                        let hit = self
                            .visit_near(rid, &item.aabb, cap, |o| {
                                // The test of `in_collision_unchecked`: boxes overlapping, then the shapes.
                                if o.aabb.intersects(&item.aabb) && intersects_placed(placed, o.placed()) {
                                    return ControlFlow::Break(());
                                }
                                gap = gap.min(gap_lower_bound(placed, &item.aabb, o.placed(), o.aabb));
                                ControlFlow::Continue(())
                            })
                            .is_break();
                        if hit {
                            return false;
                        }
                        gap
                    }
                };
                out.push(gap.max(0.0));
            }
            true
        })
    }
}

/// A lower bound on the distance between two shapes that do not intersect: the closed-form
/// capsule–box distance, else the boxes' distance when they are apart, else the exact
/// distance of two convex shapes, else 0.
fn gap_lower_bound(a: Placed<'_>, a_box: &Aabb, b: Placed<'_>, b_box: &Aabb) -> f64 {
    if a.hull.is_none() && b.hull.is_none() {
        if let (Some(c), Some(k)) = (a.shape.as_capsule(), b.shape.as_cuboid()) {
            return capsule_cuboid_distance(a.pose, c, b.pose, k);
        }
        if let (Some(k), Some(c)) = (a.shape.as_cuboid(), b.shape.as_capsule()) {
            return capsule_cuboid_distance(b.pose, c, a.pose, k);
        }
    }
    if !a_box.intersects(b_box) {
        return aabb_distance(a_box, b_box);
    }
    if a.hull.is_none() && b.hull.is_none() && a.shape.is_convex() && b.shape.is_convex() {
        return distance(a.pose, a.shape, b.pose, b.shape).unwrap_or(0.0);
    }
    0.0
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use nalgebra::Isometry3;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::model::{samples, Geometry, Shape};
    use crate::scene::{Scene, SceneObject, StaticBody};

    /// The seven-joint arm among a wall, a ball and a post (box, sphere, cylinder obstacles).
    fn arm_among_obstacles() -> (Scene, CollisionWorld, RobotId) {
        let mut scene = Scene::new("arm among obstacles");
        let arm = scene.add_robot("arm", Arc::new(samples::seven_dof_arm().unwrap()), Isometry3::identity()).unwrap();
        let body =
            |name: &str, pose: Isometry3<f64>, g: Geometry| StaticBody::new(name, pose, vec![Shape::at_origin(g)]);
        scene.add_body(body("wall", Isometry3::translation(0.5, 0.0, 0.5), Geometry::cuboid(0.05, 1.0, 1.0))).unwrap();
        scene
            .add_body(body("ball", Isometry3::translation(-0.3, 0.3, 0.8), Geometry::Sphere { radius: 0.12 }))
            .unwrap();
        let post = Geometry::Cylinder { radius: 0.05, length: 1.2 };
        scene.add_body(body("post", Isometry3::translation(-0.1, -0.45, 0.6), post)).unwrap();
        (scene.clone(), CollisionWorld::new(&scene).unwrap(), arm)
    }

    /// With nothing skipped the tests decide exactly `in_collision_unchecked`; each gap of a
    /// valid state is in `[0, cap]` and at most the exact distance of its shapes (of its part
    /// to the nearest obstacle, of its pair).
    #[test]
    fn gaps_agree_with_the_check_and_bound_the_distances() {
        let (_, world, arm) = arm_among_obstacles();
        let tests = world.gap_tests(arm).unwrap().unwrap();
        let pairs = tests.iter().filter(|t| matches!(t, GapTest::Pair { .. })).count();
        assert_eq!(pairs, world.self_collision_pair_count(arm).unwrap());
        assert_eq!(tests.len() - pairs, 9, "base, 7 links, tool");
        let limits: Vec<f64> = vec![2.96, 2.09, 2.96, 2.09, 2.96, 2.09, 3.05];
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let (mut valid, mut invalid, mut positive) = (0, 0, 0);
        let mut gaps = Vec::new();
        for _ in 0..400 {
            let q: Vec<f64> = limits.iter().map(|&l| rng.random_range(-l..l)).collect();
            let ok = world.gaps_unchecked(arm, &q, &tests, 0.5, |_| false, &mut gaps);
            assert_eq!(ok, !world.in_collision_unchecked(arm, &q), "{q:?}");
            if !ok {
                invalid += 1;
                continue;
            }
            valid += 1;
            assert_eq!(gaps.len(), tests.len());
            let links = world.link_distances(arm, &q).unwrap();
            let items = with_scratch(|s| {
                world.place(arm.0, &q, s);
                s.items.clone()
            });
            for (test, &gap) in tests.iter().zip(&gaps) {
                assert!((0.0..=0.5).contains(&gap), "{test:?}: {gap}");
                positive += usize::from(gap > 0.0);
                let exact = match *test {
                    GapTest::Obstacles { link, .. } => links[link.0],
                    GapTest::Pair { a, b, .. } => {
                        let (a, b) = (&items[a], &items[b]);
                        let (sa, sb) = (world.item_shape(arm.0, a), world.item_shape(arm.0, b));
                        distance(&a.pose, sa, &b.pose, sb).unwrap()
                    }
                };
                assert!(gap <= exact + 1e-9, "{test:?}: gap {gap} > distance {exact}");
            }
        }
        assert!(valid > 80 && invalid > 80, "{valid} valid, {invalid} invalid");
        assert!(positive > valid * tests.len() / 2, "{positive} positive gaps");
    }

    /// The arm straight up beside a box whose face is at x = 0.4: the parts' gaps are their
    /// distances to the face (capsules of radius 0.06, the base of radius 0.08, the 8 cm
    /// tool); skipped tests read NaN; the cap caps.
    #[test]
    fn part_gaps_of_the_upright_arm_are_the_distances_to_the_face() {
        let mut scene = Scene::new("box");
        let arm = scene.add_robot("arm", Arc::new(samples::seven_dof_arm().unwrap()), Isometry3::identity()).unwrap();
        let block = Shape::at_origin(Geometry::cuboid(0.2, 0.2, 4.0));
        scene.add_body(StaticBody::new("block", Isometry3::translation(0.5, 0.0, 0.0), vec![block])).unwrap();
        let world = CollisionWorld::new(&scene).unwrap();
        let tests = world.gap_tests(arm).unwrap().unwrap();
        let mut gaps = Vec::new();
        assert!(world.gaps_unchecked(arm, &[0.0; 7], &tests, 1.0, |_| false, &mut gaps));
        let part_gaps: Vec<f64> =
            tests.iter().zip(&gaps).filter(|(t, _)| matches!(t, GapTest::Obstacles { .. })).map(|(_, &g)| g).collect();
        let expected = [0.32, 0.34, 0.34, 0.34, 0.34, 0.34, 0.34, 0.34, 0.36];
        assert_eq!(part_gaps.len(), expected.len());
        for (g, e) in part_gaps.iter().zip(expected) {
            assert!((g - e).abs() < 1e-9, "{part_gaps:?}");
        }
        assert!(world.gaps_unchecked(arm, &[0.0; 7], &tests, 0.33, |t| t % 2 == 0, &mut gaps));
        for (t, &g) in gaps.iter().enumerate() {
            assert!(if t % 2 == 0 { g.is_nan() } else { g <= 0.33 }, "{t}: {g}");
        }
        assert!(gaps.contains(&0.33));
    }

    /// A robot carrying an object has no split check; its gaps are 0 and its verdict the
    /// plain check's.
    #[test]
    fn carrying_robots_have_no_gap_tests() {
        let (mut scene, _, arm) = arm_among_obstacles();
        let cube = Shape::at_origin(Geometry::cuboid(0.05, 0.05, 0.05));
        let held =
            scene.add_object(SceneObject::new("cube", Isometry3::translation(0.0, 0.0, 1.4), vec![cube], 0.1)).unwrap();
        scene.attach(held, arm, "tool").unwrap();
        let world = CollisionWorld::new(&scene).unwrap();
        assert_eq!(world.gap_tests(arm).unwrap(), None);
        let tests = [GapTest::Obstacles { part: 0, link: LinkId(0) }];
        let mut gaps = Vec::new();
        let q = [0.0; 7];
        assert_eq!(
            world.gaps_unchecked(arm, &q, &tests, 0.5, |_| false, &mut gaps),
            !world.in_collision_unchecked(arm, &q)
        );
        assert_eq!(gaps, vec![0.0]);
        assert!(world.gap_tests(RobotId(7)).is_err());
    }
}
