//! Queries of a placed robot: collision, distance and contacts.

use std::ops::ControlFlow;

use nalgebra::Isometry3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::partitioning::TraversalAction;
use parry3d_f64::query;
use parry3d_f64::shape::Shape as ParryShape;

use super::narrow::{aabb_distance, distance, distance_below, intersects_placed, Placed};
use super::{with_scratch, CollisionWorld, Item, Nearest, Obstacle, Owner, Scratch};
use crate::collision::shapes::Part;
use crate::collision::{Collider, Contact, DistanceReport};
use crate::error::{CoreError, Result};
use crate::kinematics::forward_kinematics_into;
use crate::model::LinkId;
use crate::scene::{ObjectId, RobotId};

impl CollisionWorld {
    // ----------------------------------------------------------------------------------------
    // Query machinery
    // ----------------------------------------------------------------------------------------

    /// Places every part of robot `rid` (and of its attached objects) at configuration `q`.
    pub(super) fn place(&self, rid: usize, q: &[f64], scratch: &mut Scratch) {
        let r = &self.robots[rid];
        forward_kinematics_into(&r.robot, q, &mut scratch.link_poses);
        scratch.items.clear();
        for (i, (p, l)) in r.parts.iter().zip(&r.part_link).enumerate() {
            let pose = r.base_pose * scratch.link_poses[l.0] * p.local;
            let aabb = p.shape.compute_aabb(&pose);
            scratch.items.push(Item { owner: Owner::Link { part: i as u32 }, link: *l, pose, aabb });
        }
        for (oi, o) in self.objects.iter().enumerate() {
            if let Some(a) = o.attached.as_ref().filter(|a| a.robot.0 == rid) {
                let obj_pose = r.base_pose * scratch.link_poses[a.link.0] * a.offset;
                for (pi, p) in o.parts.iter().enumerate() {
                    let pose = obj_pose * p.local;
                    let aabb = p.shape.compute_aabb(&pose);
                    scratch.items.push(Item {
                        owner: Owner::Attached { object: oi as u32, part: pi as u32 },
                        link: a.link,
                        pose,
                        aabb,
                    });
                }
            }
        }
    }

    pub(super) fn item_shape(&self, rid: usize, item: &Item) -> &dyn ParryShape {
        &*self.item_part(rid, item).shape
    }

    fn item_part(&self, rid: usize, item: &Item) -> &Part {
        match item.owner {
            Owner::Link { part } => &self.robots[rid].parts[part as usize],
            Owner::Attached { object, part } => &self.objects[object as usize].parts[part as usize],
        }
    }

    /// The item placed, with its hull if it has one.
    fn item_placed<'a>(&'a self, rid: usize, item: &'a Item) -> Placed<'a> {
        let part = self.item_part(rid, item);
        Placed { pose: &item.pose, shape: &*part.shape, hull: part.hull.as_deref() }
    }

    /// Visits the movable obstacles of robot `rid`: objects it does not carry and the parts of
    /// other robots.
    pub(super) fn visit_dynamic<'a>(
        &'a self,
        rid: usize,
        mut f: impl FnMut(Obstacle<'a>) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        for (oi, o) in self.objects.iter().enumerate() {
            if o.attached.as_ref().is_some_and(|a| a.robot.0 == rid) {
                continue;
            }
            for (p, (pose, aabb)) in o.parts.iter().zip(&o.world) {
                f(Obstacle {
                    id: Collider::Object(ObjectId(oi)),
                    pose,
                    shape: &*p.shape,
                    hull: p.hull.as_deref(),
                    aabb,
                })?;
            }
        }
        for (ri, r) in self.robots.iter().enumerate() {
            if ri == rid {
                continue;
            }
            for ((p, l), (pose, aabb)) in r.parts.iter().zip(&r.part_link).zip(&r.world) {
                f(Obstacle {
                    id: Collider::Link(RobotId(ri), *l),
                    pose,
                    shape: &*p.shape,
                    hull: p.hull.as_deref(),
                    aabb,
                })?;
            }
        }
        ControlFlow::Continue(())
    }

    pub(super) fn has_obstacles(&self, rid: usize) -> bool {
        !self.env.is_empty() || self.visit_dynamic(rid, |_| ControlFlow::Break(())).is_break()
    }

    /// Visits every obstacle (static or movable) whose AABB comes within `margin` of `aabb`.
    pub(super) fn visit_near<'a>(
        &'a self,
        rid: usize,
        aabb: &Aabb,
        margin: f64,
        mut f: impl FnMut(Obstacle<'a>) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let query = aabb.loosened(margin);
        let mut flow = ControlFlow::Continue(());
        self.env_bvh.traverse(|node| {
            if !node.aabb().intersects(&query) {
                return TraversalAction::Prune;
            }
            if let Some(leaf) = node.leaf_data() {
                let e = &self.env[leaf as usize];
                if e.aabb.intersects(&query) {
                    let o = Obstacle {
                        id: Collider::Body(e.body),
                        pose: &e.pose,
                        shape: &*e.part.shape,
                        hull: e.part.hull.as_deref(),
                        aabb: &e.aabb,
                    };
                    if f(o).is_break() {
                        flow = ControlFlow::Break(());
                        return TraversalAction::EarlyExit;
                    }
                }
            }
            TraversalAction::Continue
        });
        flow?;
        self.visit_dynamic(rid, |o| if o.aabb.intersects(&query) { f(o) } else { ControlFlow::Continue(()) })
    }

    pub(super) fn validate(&self, robot: RobotId, q: &[f64]) -> Result<()> {
        self.robot_entry(robot)?.robot.validate_configuration(q)
    }

    // ----------------------------------------------------------------------------------------
    // Boolean collision
    // ----------------------------------------------------------------------------------------

    /// True if the robot at configuration `q` collides with anything: see the
    /// [type-level documentation](CollisionWorld) for what is checked.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for a bad robot; [`CoreError::DimensionMismatch`],
    /// [`CoreError::NonFiniteJointValue`] or [`CoreError::JointOutOfLimits`] for a bad `q`.
    pub fn in_collision(&self, robot: RobotId, q: &[f64]) -> Result<bool> {
        self.validate(robot, q)?;
        Ok(self.in_collision_unchecked(robot, q))
    }

    /// [`in_collision`](Self::in_collision) without validating `q` (for planners' inner loops
    /// on configurations known to be valid; joint limits are not checked).
    ///
    /// # Panics
    /// If `robot` is not a robot of this world or `q` is shorter than the robot's DoF.
    pub fn in_collision_unchecked(&self, robot: RobotId, q: &[f64]) -> bool {
        let rid = robot.0;
        with_scratch(|s| {
            self.place(rid, q, s);
            // Self-collision first: the pair list is precomputed and short.
            if self.self_pairs_hit(rid, s) {
                return true;
            }
            for item in &s.items {
                let placed = self.item_placed(rid, item);
                let hit = self
                    .visit_near(rid, &item.aabb, 0.0, |o| {
                        if intersects_placed(placed, o.placed()) {
                            ControlFlow::Break(())
                        } else {
                            ControlFlow::Continue(())
                        }
                    })
                    .is_break();
                if hit || self.attached_hits_own_links(rid, s, item) {
                    return true;
                }
            }
            false
        })
    }

    /// The part of [`in_collision_unchecked`](Self::in_collision_unchecked) that
    /// [`link_distances`](Self::link_distances) does not measure: self-collision (non-allowed
    /// link pairs) and carried objects against the robot's own links. Environment, free
    /// objects and other robots are *not* checked.
    ///
    /// So for a `q` at which every link distance is positive, `in_collision_unchecked(q) ==
    /// in_self_collision_unchecked(q)`: once conservative advancement has certified a motion's
    /// clearance, fine discrete checks along it need only this cheaper test.
    ///
    /// # Panics
    /// As [`in_collision_unchecked`](Self::in_collision_unchecked).
    pub fn in_self_collision_unchecked(&self, robot: RobotId, q: &[f64]) -> bool {
        let rid = robot.0;
        with_scratch(|s| {
            self.place(rid, q, s);
            self.self_pairs_hit(rid, s) || s.items.iter().any(|item| self.attached_hits_own_links(rid, s, item))
        })
    }

    /// True if a non-allowed pair of the placed robot's parts intersects.
    fn self_pairs_hit(&self, rid: usize, s: &Scratch) -> bool {
        let r = &self.robots[rid];
        r.self_pairs.iter().any(|&(i, j)| {
            let (a, b) = (&s.items[i as usize], &s.items[j as usize]);
            a.aabb.intersects(&b.aabb) && intersects_placed(self.item_placed(rid, a), self.item_placed(rid, b))
        })
    }

    /// True if `item`, a part of an attached object, intersects a link of its robot it may not
    /// touch (false for robot parts).
    fn attached_hits_own_links(&self, rid: usize, s: &Scratch, item: &Item) -> bool {
        let Owner::Attached { object, .. } = item.owner else { return false };
        let r = &self.robots[rid];
        let placed = self.item_placed(rid, item);
        let touch = self.objects[object as usize].attached.as_ref().map(|a| &a.touch[..]).unwrap_or(&[]);
        s.items[..r.parts.len()].iter().any(|link_item| {
            !touch.contains(&link_item.link)
                && link_item.aabb.intersects(&item.aabb)
                && intersects_placed(placed, self.item_placed(rid, link_item))
        })
    }

    // ----------------------------------------------------------------------------------------
    // Distances
    // ----------------------------------------------------------------------------------------

    /// Lower bound of the distance from one item to the obstacles: the distance between its
    /// AABB and the nearest obstacle AABB (`+inf` without obstacles).
    pub(super) fn item_lower_bound(&self, rid: usize, item: &Item) -> f64 {
        let mut lb = self
            .env_bvh
            .find_best(
                f64::INFINITY,
                |node, _| aabb_distance(&node.aabb(), &item.aabb),
                |leaf, _| Some(aabb_distance(&self.env[leaf as usize].aabb, &item.aabb)),
            )
            .map_or(f64::INFINITY, |(_, d)| d);
        let _ = self.visit_dynamic(rid, |o| {
            lb = lb.min(aabb_distance(o.aabb, &item.aabb));
            ControlFlow::Continue(())
        });
        lb
    }

    /// Nearest obstacle of one item if nearer than `bound` (branch and bound over the
    /// hierarchy, nearest AABB first); distances are ≥ 0 (0 when touching or overlapping).
    pub(super) fn item_min_distance(&self, rid: usize, item: &Item, bound: f64) -> Option<Nearest<'_>> {
        let placed = self.item_placed(rid, item);
        let mut best: Option<Nearest<'_>> = None;
        let mut bound = bound;
        if let Some((leaf, d)) = self.env_bvh.find_best(
            bound,
            |node, _| aabb_distance(&node.aabb(), &item.aabb),
            |leaf, best| {
                let e = &self.env[leaf as usize];
                let other = Placed { pose: &e.pose, shape: &*e.part.shape, hull: e.part.hull.as_deref() };
                distance_below(placed, other, best)
            },
        ) {
            bound = d;
            let e = &self.env[leaf as usize];
            best = Some(Nearest { distance: d, id: Collider::Body(e.body), pose: e.pose, shape: &*e.part.shape });
        }
        // Movable obstacles nearest bounding box first, so that the bound tightens early and
        // the farther ones are skipped without an exact query.
        let mut near: Vec<(f64, Obstacle<'_>)> = Vec::new();
        let _ = self.visit_dynamic(rid, |o| {
            let lb = aabb_distance(o.aabb, &item.aabb);
            if lb < bound {
                near.push((lb, o));
            }
            ControlFlow::Continue(())
        });
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (lb, o) in near {
            if lb >= bound {
                break;
            }
            if let Some(d) = distance_below(placed, o.placed(), bound) {
                bound = d;
                best = Some(Nearest { distance: d, id: o.id, pose: *o.pose, shape: o.shape });
            }
        }
        best
    }

    /// Deepest penetration of one item into any obstacle: `(depth > 0, contact)` with the
    /// contact oriented item → obstacle.
    pub(super) fn item_deepest_penetration(&self, rid: usize, item: &Item) -> Option<(Collider, query::Contact)> {
        let shape = self.item_shape(rid, item);
        let mut best: Option<(Collider, query::Contact)> = None;
        let _ = self.visit_near(rid, &item.aabb, 0.0, |o| {
            // Separated pairs are skipped with the (cheaper) distance before running EPA.
            if distance(&item.pose, shape, o.pose, o.shape).is_some_and(|d| d > 0.0) {
                return ControlFlow::Continue(());
            }
            if let Ok(Some(c)) = query::contact(&item.pose, shape, o.pose, o.shape, 0.0) {
                if c.dist <= 0.0 && best.as_ref().is_none_or(|(_, b)| c.dist < b.dist) {
                    best = Some((o.id, c));
                }
            }
            ControlFlow::Continue(())
        });
        best
    }

    /// Minimum distance from the robot at `q` (links and attached objects) to its obstacles —
    /// static bodies, objects it does not carry, other robots — with the closest pair and
    /// witness points. Self-distance is not included.
    ///
    /// The distance is the gap when separated and `-depth` of the most deeply penetrating pair
    /// when the robot overlaps an obstacle (`0` when exactly touching). The search is
    /// branch-and-bound: links are visited with the best distance found so far as a bound, and
    /// any obstacle whose bounding box is farther than the bound is skipped without an exact
    /// query.
    ///
    /// # Errors
    /// [`CoreError::EmptyScene`] if the robot has no obstacle at all (no static body, no other
    /// object, no other robot) or no collision geometry — there is no pair to report
    /// ([`link_distances`](Self::link_distances) returns `+inf` instead); plus the errors of
    /// [`in_collision`](Self::in_collision).
    pub fn distance(&self, robot: RobotId, q: &[f64]) -> Result<DistanceReport> {
        self.validate(robot, q)?;
        let rid = robot.0;
        with_scratch(|s| {
            let (k, nearest) = self.nearest_item(rid, q, s)?;
            let d = nearest.distance;
            let (k, contact, other) = if d <= 0.0 {
                // Penetrating: report the deepest penetration over all items.
                let mut deepest: Option<(usize, Collider, query::Contact)> = None;
                for (k, item) in s.items.iter().enumerate() {
                    if let Some((id, c)) = self.item_deepest_penetration(rid, item) {
                        if deepest.as_ref().is_none_or(|(_, _, b)| c.dist < b.dist) {
                            deepest = Some((k, id, c));
                        }
                    }
                }
                match deepest {
                    Some((k, id, c)) => (k, Some(c), id),
                    None => (k, None, nearest.id),
                }
            } else {
                // Witness points of the nearest pair.
                let item = &s.items[k];
                let shape = self.item_shape(rid, item);
                // Generous: parry's GJK may find a slightly larger distance than the search.
                let prediction = 2.0 * d + 1e-6;
                let c = query::contact(&item.pose, shape, &nearest.pose, nearest.shape, prediction).ok().flatten();
                (k, c, nearest.id)
            };
            let item = &s.items[k];
            let attached = match item.owner {
                Owner::Attached { object, .. } => Some(ObjectId(object as usize)),
                Owner::Link { .. } => None,
            };
            let (distance, p1, p2) = match contact {
                // The searched distance is kept when separated, so that it equals the minimum
                // of `link_distances` exactly.
                Some(c) => (if d > 0.0 { d } else { c.dist }, c.point1, c.point2),
                None => (d.max(0.0), item.pose.translation.vector.into(), item.pose.translation.vector.into()),
            };
            Ok(DistanceReport { distance, link: item.link, attached, other, point_on_robot: p1, point_on_other: p2 })
        })
    }

    /// The separation of [`distance`](Self::distance) alone, without its witness points and
    /// penetration depth: the same value when the robot is clear of its obstacles, `0` when
    /// it touches or overlaps one. Cheaper (no contact query for the witness points), and all
    /// that conservative advancement needs.
    ///
    /// # Errors
    /// As [`distance`](Self::distance).
    pub fn min_distance(&self, robot: RobotId, q: &[f64]) -> Result<f64> {
        self.validate(robot, q)?;
        with_scratch(|s| Ok(self.nearest_item(robot.0, q, s)?.1.distance.max(0.0)))
    }

    /// Places the robot and finds its nearest item and obstacle by branch-and-bound: items in
    /// increasing order of their AABB lower bound, so that the bound tightens early and far
    /// links are pruned without exact queries.
    fn nearest_item<'w>(&'w self, rid: usize, q: &[f64], s: &mut Scratch) -> Result<(usize, Nearest<'w>)> {
        if !self.has_obstacles(rid) {
            return Err(CoreError::EmptyScene { reason: "the robot has no obstacle to measure a distance to".into() });
        }
        self.place(rid, q, s);
        s.order.clear();
        for (k, item) in s.items.iter().enumerate() {
            s.order.push((self.item_lower_bound(rid, item), k as u32));
        }
        s.order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let mut best: Option<(usize, Nearest<'_>)> = None;
        let mut bound = f64::INFINITY;
        for &(lb, k) in &s.order {
            if lb >= bound {
                break;
            }
            if let Some(n) = self.item_min_distance(rid, &s.items[k as usize], bound) {
                bound = n.distance;
                best = Some((k as usize, n));
            }
        }
        best.ok_or_else(|| CoreError::EmptyScene { reason: "no obstacle within reach of the robot's geometry".into() })
    }

    /// Minimum distance of each link (with the objects it carries) to the robot's obstacles,
    /// indexed by [`LinkId`]; self-distance is not included. Links without collision geometry,
    /// and every link when the robot has no obstacles, get `+inf`. Overlapping links get `0`
    /// (exact distance, not a penetration depth: use [`distance`](Self::distance) for depth).
    /// Each value is a safe bound for conservative-advancement collision checking.
    ///
    /// # Errors
    /// As [`in_collision`](Self::in_collision).
    pub fn link_distances(&self, robot: RobotId, q: &[f64]) -> Result<Vec<f64>> {
        let mut out = Vec::new();
        self.link_distances_into(robot, q, &mut out)?;
        Ok(out)
    }

    /// [`link_distances`](Self::link_distances) into a reused buffer (cleared and resized to
    /// the link count).
    ///
    /// # Errors
    /// As [`in_collision`](Self::in_collision).
    pub fn link_distances_into(&self, robot: RobotId, q: &[f64], out: &mut Vec<f64>) -> Result<()> {
        self.link_distances_where(robot, q, out, |_| true)
    }

    /// [`link_distances_into`](Self::link_distances_into) restricted to the links with
    /// `selected[link] == true`: the others (and links beyond `selected`'s length) get `+inf`
    /// without any query. For callers that already hold cheaper lower bounds for most links
    /// and need exact distances for a few (e.g. a grasp evaluator refining the links near an
    /// object's convex hull).
    ///
    /// # Errors
    /// As [`in_collision`](Self::in_collision).
    pub fn selected_link_distances_into(
        &self,
        robot: RobotId,
        q: &[f64],
        selected: &[bool],
        out: &mut Vec<f64>,
    ) -> Result<()> {
        self.link_distances_where(robot, q, out, |l| selected.get(l).copied().unwrap_or(false))
    }

    /// Exact distance of every link `l` with `wanted(l)` to everything it can hit (`+inf` for
    /// the others, which are not queried).
    fn link_distances_where(
        &self,
        robot: RobotId,
        q: &[f64],
        out: &mut Vec<f64>,
        wanted: impl Fn(usize) -> bool,
    ) -> Result<()> {
        self.validate(robot, q)?;
        let rid = robot.0;
        out.clear();
        out.resize(self.robots[rid].n_links(), f64::INFINITY);
        with_scratch(|s| {
            self.place(rid, q, s);
            for item in s.items.iter().filter(|item| wanted(item.link.0)) {
                let l = item.link.0;
                if let Some(n) = self.item_min_distance(rid, item, out[l]) {
                    out[l] = out[l].min(n.distance);
                }
            }
        });
        Ok(())
    }

    // ----------------------------------------------------------------------------------------
    // Contacts
    // ----------------------------------------------------------------------------------------

    pub(super) fn check_margin(margin: f64) -> Result<()> {
        if margin.is_finite() && margin >= 0.0 {
            Ok(())
        } else {
            Err(CoreError::InvalidParameter {
                name: "margin".into(),
                reason: format!("must be finite and >= 0, got {margin}"),
            })
        }
    }

    /// Contacts of the robot's links at `q` with static bodies, objects it does not carry,
    /// other robots' links and its own links (non-allowed pairs, reported once with
    /// `other = Collider::Link(robot, _)`), including separated pairs closer than `margin`
    /// (negative depth). One contact (the deepest point, from parry's `query::contact`) per pair
    /// of collision parts. Objects the robot carries are not reported (see
    /// [`contacts_with_object`](Self::contacts_with_object)).
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] for a negative or non-finite margin, plus the errors of
    /// [`in_collision`](Self::in_collision).
    pub fn contacts(&self, robot: RobotId, q: &[f64], margin: f64) -> Result<Vec<Contact>> {
        self.validate(robot, q)?;
        Self::check_margin(margin)?;
        let rid = robot.0;
        let r = &self.robots[rid];
        let mut out = Vec::new();
        with_scratch(|s| {
            self.place(rid, q, s);
            for item in s.items.iter().filter(|i| matches!(i.owner, Owner::Link { .. })) {
                let shape = self.item_shape(rid, item);
                let _ = self.visit_near(rid, &item.aabb, margin, |o| {
                    if let Ok(Some(c)) = query::contact(&item.pose, shape, o.pose, o.shape, margin) {
                        out.push(to_contact(item.link, o.id, &c));
                    }
                    ControlFlow::Continue(())
                });
            }
            for &(i, j) in &r.self_pairs {
                let (a, b) = (&s.items[i as usize], &s.items[j as usize]);
                if aabb_distance(&a.aabb, &b.aabb) <= margin {
                    let (sa, sb) = (&*r.parts[i as usize].shape, &*r.parts[j as usize].shape);
                    if let Ok(Some(c)) = query::contact(&a.pose, sa, &b.pose, sb, margin) {
                        out.push(to_contact(a.link, Collider::Link(robot, b.link), &c));
                    }
                }
            }
        });
        Ok(out)
    }

    /// Contacts of every link of the robot at `q` with one object, including separated pairs
    /// closer than `margin` (negative depth). An object carried by this robot is placed with
    /// its link at `q`, and every link (the carrying one included) is tested — this is what a
    /// grasp evaluator closing a hand on an object needs.
    ///
    /// # Errors
    /// [`CoreError::InvalidHandle`] for a bad object, plus the errors of
    /// [`contacts`](Self::contacts).
    pub fn contacts_with_object(
        &self,
        robot: RobotId,
        q: &[f64],
        object: ObjectId,
        margin: f64,
    ) -> Result<Vec<Contact>> {
        self.validate(robot, q)?;
        Self::check_margin(margin)?;
        self.object_entry(object)?;
        let rid = robot.0;
        let o = &self.objects[object.0];
        let mut out = Vec::new();
        with_scratch(|s| {
            self.place(rid, q, s);
            let carried = o.attached.as_ref().filter(|a| a.robot == robot).map(|a| {
                let r = &self.robots[rid];
                r.base_pose * s.link_poses[a.link.0] * a.offset
            });
            let obj_parts: Vec<(Isometry3<f64>, Aabb)> = match carried {
                Some(pose) => o
                    .parts
                    .iter()
                    .map(|p| {
                        let w = pose * p.local;
                        (w, p.shape.compute_aabb(&w))
                    })
                    .collect(),
                None => o.world.clone(),
            };
            for item in s.items.iter().filter(|i| matches!(i.owner, Owner::Link { .. })) {
                let shape = self.item_shape(rid, item);
                for (p, (pose, aabb)) in o.parts.iter().zip(&obj_parts) {
                    if aabb_distance(aabb, &item.aabb) <= margin {
                        if let Ok(Some(c)) = query::contact(&item.pose, shape, pose, &*p.shape, margin) {
                            out.push(to_contact(item.link, Collider::Object(object), &c));
                        }
                    }
                }
            }
        });
        Ok(out)
    }
}

/// Converts a parry contact (shape 1 = robot link) to ours.
fn to_contact(link: LinkId, other: Collider, c: &query::Contact) -> Contact {
    Contact { link, other, point_on_robot: c.point1, point_on_other: c.point2, normal: -c.normal1, depth: -c.dist }
}
