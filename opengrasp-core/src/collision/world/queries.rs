//! Queries of a placed robot: collision, distance and contacts.

use std::ops::ControlFlow;
use std::sync::Arc;

use nalgebra::Isometry3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::partitioning::TraversalAction;
use parry3d_f64::query;
use parry3d_f64::shape::Shape as ParryShape;

use super::narrow::{aabb_distance, intersects_placed, Placed};
use super::{with_scratch, CollisionWorld, Item, Obstacle, Owner, Scratch};
use crate::collision::shapes::Part;
use crate::collision::{Collider, Contact};
use crate::error::{CoreError, Result};
use crate::model::LinkId;
use crate::scene::{ObjectId, RobotId};

impl CollisionWorld {
    // ----------------------------------------------------------------------------------------
    // Query machinery
    // ----------------------------------------------------------------------------------------

    /// Places every part of robot `rid` (and of its attached objects) at configuration `q`.
    pub(super) fn place(&self, rid: usize, q: &[f64], scratch: &mut Scratch) {
        self.place_links(rid, q, |_| true, scratch);
    }

    /// [`place`](Self::place) restricted to the links with `wanted(link)`: places their parts
    /// and the parts of the objects they carry (in `place`'s order: link parts by link, then
    /// carried objects by object), computing forward kinematics only along the chains of the
    /// links placed. The poses of the other links in `scratch.link_poses` are left as they
    /// were. Each pose is computed by the same operations whatever `wanted` is, so a part's
    /// pose and bounding box do not depend on which other links are placed. Links behind fixed
    /// joints only (a robot's base) are copied from the robot's entry, which computed them by
    /// these operations too.
    pub(super) fn place_links(&self, rid: usize, q: &[f64], wanted: impl Fn(usize) -> bool, scratch: &mut Scratch) {
        let r = &self.robots[rid];
        let robot = &*r.robot;
        let carried = || self.objects.iter().filter_map(|o| o.attached.as_ref().filter(|a| a.robot.0 == rid));
        // The links to place, then the joints on their chains.
        scratch.links.clear();
        scratch.links.extend(r.link_parts.iter().enumerate().map(|(l, &(start, end))| start < end && wanted(l)));
        for a in carried() {
            scratch.links[a.link.0] = wanted(a.link.0);
        }
        scratch.joints.clear();
        scratch.joints.resize(robot.joints().len(), false);
        for l in (0..scratch.links.len()).filter(|&l| scratch.links[l]) {
            let mut link = LinkId(l);
            while let Some(j) = robot.parent_joint(link) {
                if std::mem::replace(&mut scratch.joints[j.0], true) {
                    break;
                }
                link = robot.joint(j).parent;
            }
        }
        // Poses computed at this very configuration of this robot are kept.
        let same = std::ptr::eq(scratch.fk_robot.as_ptr(), Arc::as_ptr(&r.robot))
            && scratch.fk_q.len() == q.len()
            && scratch.fk_q.iter().zip(q).all(|(a, b)| a.to_bits() == b.to_bits());
        if !same {
            scratch.fk_robot = Arc::downgrade(&r.robot);
            scratch.fk_q.clear();
            scratch.fk_q.extend_from_slice(q);
            scratch.fk_posed.clear();
        }
        scratch.fk_posed.resize(robot.links().len(), false);
        let poses = &mut scratch.link_poses;
        poses.resize(robot.links().len(), Isometry3::identity());
        poses[robot.root().0] = Isometry3::identity();
        for &j in robot.joints_topological().iter().filter(|j| scratch.joints[j.0]) {
            let joint = robot.joint(j);
            if std::mem::replace(&mut scratch.fk_posed[joint.child.0], true) {
                continue;
            }
            poses[joint.child.0] = if r.fixed_link[joint.child.0] {
                r.link_poses[joint.child.0]
            } else {
                poses[joint.parent.0] * joint.origin * joint.motion(robot.joint_position(q, j))
            };
        }
        scratch.items.clear();
        for (l, &(start, end)) in r.link_parts.iter().enumerate().filter(|&(l, _)| scratch.links[l]) {
            for i in start..end {
                // Links behind fixed joints only: the pose and box `place_world` computed.
                let (pose, aabb) = if r.fixed_link[l] {
                    r.world[i as usize]
                } else {
                    let pose = r.base_pose * poses[l] * r.parts[i as usize].local;
                    (pose, r.parts[i as usize].shape.compute_aabb(&pose))
                };
                scratch.items.push(Item { owner: Owner::Link { part: i }, link: LinkId(l), pose, aabb });
            }
        }
        for (oi, o) in self.objects.iter().enumerate() {
            if let Some(a) = o.attached.as_ref().filter(|a| a.robot.0 == rid && wanted(a.link.0)) {
                let obj_pose = r.base_pose * poses[a.link.0] * a.offset;
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
    pub(super) fn item_placed<'a>(&'a self, rid: usize, item: &'a Item) -> Placed<'a> {
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
                        let contact = super::mesh_distance::mesh_contact(&item.pose, shape, pose, &*p.shape, margin)
                            .unwrap_or_else(|| {
                                query::contact(&item.pose, shape, pose, &*p.shape, margin).ok().flatten()
                            });
                        if let Some(c) = contact {
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
