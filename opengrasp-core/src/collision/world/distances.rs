//! Distance queries of a placed robot: the nearest obstacle, per-link distances (of every
//! link, or of a few with forward kinematics only along their chains).

use std::ops::ControlFlow;

use parry3d_f64::query;

use super::narrow::{aabb_distance, distance, distance_below_hinted, Placed};
use super::{with_scratch, CollisionWorld, Item, Nearest, Obstacle, Owner, Scratch};
use crate::collision::{Collider, DistanceReport};
use crate::error::{CoreError, Result};
use crate::model::LinkId;
use crate::scene::{ObjectId, RobotId};

impl CollisionWorld {
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
        self.item_min_distance_hinted(rid, item, bound, None)
    }

    /// [`item_min_distance`](Self::item_min_distance) with the triangle-mesh searches
    /// warm-started from the triangle `hint` (updated to the nearest found; the same result).
    fn item_min_distance_hinted(
        &self,
        rid: usize,
        item: &Item,
        bound: f64,
        mut hint: Option<&mut u32>,
    ) -> Option<Nearest<'_>> {
        let placed = self.item_placed(rid, item);
        let mut best: Option<Nearest<'_>> = None;
        let mut bound = bound;
        // The leaf query of the static bodies' search is a `Fn`: the hint goes through a cell.
        let cell = hint.as_deref().map(|&h| std::cell::Cell::new(h));
        let found = self.env_bvh.find_best(
            bound,
            |node, _| aabb_distance(&node.aabb(), &item.aabb),
            |leaf, best| {
                let e = &self.env[leaf as usize];
                let other = Placed { pose: &e.pose, shape: &*e.part.shape, hull: e.part.hull.as_deref() };
                let mut h = cell.as_ref().map(std::cell::Cell::get);
                let d = distance_below_hinted(placed, other, best, h.as_mut());
                if let (Some(c), Some(h)) = (&cell, h) {
                    c.set(h);
                }
                d
            },
        );
        if let (Some(h), Some(c)) = (hint.as_deref_mut(), cell) {
            *h = c.get();
        }
        if let Some((leaf, d)) = found {
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
            if let Some(d) = distance_below_hinted(placed, o.placed(), bound, hint.as_deref_mut()) {
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
        with_scratch(|s| Ok(self.nearest_item_hinted(robot.0, q, s, None)?.1.distance.max(0.0)))
    }

    /// [`min_distance`](Self::min_distance) with the searches against triangle meshes
    /// warm-started from each link's nearest triangle in `hints` (updated), as
    /// [`selected_link_distances_hinted_into`](Self::selected_link_distances_hinted_into):
    /// the same distance bit for bit, fewer triangle tests for a robot moving little between
    /// queries (a hand approaching an object).
    ///
    /// # Errors
    /// As [`distance`](Self::distance).
    pub fn min_distance_hinted(&self, robot: RobotId, q: &[f64], hints: &mut NearestTriangles) -> Result<f64> {
        self.validate(robot, q)?;
        hints.per_link.resize(self.robots[robot.0].n_links(), u32::MAX);
        with_scratch(|s| Ok(self.nearest_item_hinted(robot.0, q, s, Some(hints))?.1.distance.max(0.0)))
    }

    /// Places the robot and finds its nearest item and obstacle by branch-and-bound: items in
    /// increasing order of their AABB lower bound, so that the bound tightens early and far
    /// links are pruned without exact queries.
    fn nearest_item<'w>(&'w self, rid: usize, q: &[f64], s: &mut Scratch) -> Result<(usize, Nearest<'w>)> {
        self.nearest_item_hinted(rid, q, s, None)
    }

    /// [`nearest_item`](Self::nearest_item), the mesh searches warm-started from `hints`
    /// (resized to the link count) when given.
    fn nearest_item_hinted<'w>(
        &'w self,
        rid: usize,
        q: &[f64],
        s: &mut Scratch,
        mut hints: Option<&mut NearestTriangles>,
    ) -> Result<(usize, Nearest<'w>)> {
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
            let item = &s.items[k as usize];
            let hint = hints.as_deref_mut().map(|h| &mut h.per_link[item.link.0]);
            if let Some(n) = self.item_min_distance_hinted(rid, item, bound, hint) {
                bound = n.distance;
                best = Some((k as usize, n));
            }
        }
        best.ok_or_else(|| CoreError::EmptyScene { reason: "no obstacle within reach of the robot's geometry".into() })
    }

    /// Minimum distance of each link (with the objects it carries) to the robot's obstacles,
    /// indexed by [`LinkId`](crate::model::LinkId); self-distance is not included. Links without collision geometry,
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

    /// [`selected_link_distances_into`](Self::selected_link_distances_into) with the searches
    /// against triangle meshes warm-started from each link's nearest triangle of its previous
    /// query, kept in `hints` (see [`NearestTriangles`]): the same distances bit for bit, from
    /// fewer box and triangle tests when the robot moves little between queries (the closing
    /// steps of a grasp).
    ///
    /// # Errors
    /// As [`in_collision`](Self::in_collision).
    pub fn selected_link_distances_hinted_into(
        &self,
        robot: RobotId,
        q: &[f64],
        selected: &[bool],
        out: &mut Vec<f64>,
        hints: &mut NearestTriangles,
    ) -> Result<()> {
        self.validate(robot, q)?;
        let wanted = |l: usize| selected.get(l).copied().unwrap_or(false);
        self.hinted_link_distances(robot.0, q, out, hints, |l| if wanted(l) { f64::INFINITY } else { 0.0 });
        for (l, d) in out.iter_mut().enumerate() {
            if !wanted(l) {
                *d = f64::INFINITY;
            }
        }
        Ok(())
    }

    /// [`link_distances_below_into`](Self::link_distances_below_into) with the searches
    /// against triangle meshes warm-started from `hints` (updated), as
    /// [`selected_link_distances_hinted_into`](Self::selected_link_distances_hinted_into):
    /// `min(dₗ, bounds[l])` for every link, bit for bit, links with a bound ≤ 0 neither placed
    /// nor queried. For callers that need a few links' distances exactly and others only when
    /// they are below some threshold (a closing finger's links that cannot set its step unless
    /// nearer than the step already found): a pair proven beyond its bound stops early.
    ///
    /// # Errors
    /// As [`link_distances_below_into`](Self::link_distances_below_into).
    pub fn link_distances_below_hinted_into(
        &self,
        robot: RobotId,
        q: &[f64],
        bounds: &[f64],
        out: &mut Vec<f64>,
        hints: &mut NearestTriangles,
    ) -> Result<()> {
        self.validate(robot, q)?;
        self.check_link_bounds(robot, bounds)?;
        self.hinted_link_distances(robot.0, q, out, hints, |l| bounds[l]);
        Ok(())
    }

    /// One bound per link of `robot`, none NaN.
    fn check_link_bounds(&self, robot: RobotId, bounds: &[f64]) -> Result<()> {
        let n = self.robots[robot.0].n_links();
        if bounds.len() != n {
            return Err(CoreError::DimensionMismatch { expected: n, actual: bounds.len() });
        }
        if bounds.iter().any(|b| b.is_nan()) {
            return Err(CoreError::NonFinite { what: "link distance bounds".into() });
        }
        Ok(())
    }

    /// `out[l] = min(dₗ, bound(l))` for every link of robot `rid` at `q` (validated), placing
    /// and querying only the links with a positive bound, the mesh searches warm-started
    /// from `hints` (resized to the link count and updated).
    fn hinted_link_distances(
        &self,
        rid: usize,
        q: &[f64],
        out: &mut Vec<f64>,
        hints: &mut NearestTriangles,
        bound: impl Fn(usize) -> f64,
    ) {
        let n = self.robots[rid].n_links();
        hints.per_link.resize(n, u32::MAX);
        out.clear();
        out.extend((0..n).map(bound));
        with_scratch(|s| {
            self.place_links(rid, q, |l: usize| out[l] > 0.0, s);
            for item in &s.items {
                let l = item.link.0;
                if let Some(n) = self.item_min_distance_hinted(rid, item, out[l], Some(&mut hints.per_link[l])) {
                    out[l] = out[l].min(n.distance);
                }
            }
        });
    }

    /// `min(dₗ, bounds[l])` for every link `l`, with `dₗ` its distance of
    /// [`link_distances_into`](Self::link_distances_into) (bit for bit the minimum of that
    /// query and `bounds`). For callers that only need to know whether a link is nearer than
    /// some distance (conservative advancement needs no distance beyond the one that certifies
    /// the rest of a motion): an obstacle whose bounding box, or convex hull, is at least the
    /// bound away is skipped without an exact query, and links with a bound ≤ 0 are neither
    /// placed nor queried (their minimum is the bound, distances being ≥ 0).
    ///
    /// # Errors
    /// [`CoreError::DimensionMismatch`] if `bounds` does not hold one value per link,
    /// [`CoreError::NonFinite`] if one is NaN; otherwise as
    /// [`in_collision`](Self::in_collision).
    pub fn link_distances_below_into(
        &self,
        robot: RobotId,
        q: &[f64],
        bounds: &[f64],
        out: &mut Vec<f64>,
    ) -> Result<()> {
        self.validate(robot, q)?;
        self.check_link_bounds(robot, bounds)?;
        self.bounded_link_distances(robot.0, q, out, |l| bounds[l]);
        Ok(())
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
        self.bounded_link_distances(robot.0, q, out, |l| if wanted(l) { f64::INFINITY } else { 0.0 });
        for (l, d) in out.iter_mut().enumerate() {
            if !wanted(l) {
                *d = f64::INFINITY;
            }
        }
        Ok(())
    }

    /// `out[l] = min(dₗ, bound(l))` for every link of robot `rid` at `q` (validated), placing
    /// and querying only the links with a positive bound.
    fn bounded_link_distances(&self, rid: usize, q: &[f64], out: &mut Vec<f64>, bound: impl Fn(usize) -> f64) {
        out.clear();
        out.extend((0..self.robots[rid].n_links()).map(&bound));
        with_scratch(|s| {
            self.place_links(rid, q, |l: usize| out[l] > 0.0, s);
            for item in &s.items {
                let l = item.link.0;
                if let Some(n) = self.item_min_distance(rid, item, out[l]) {
                    out[l] = out[l].min(n.distance);
                }
            }
        });
    }
}

/// Per-link warm starts of [`CollisionWorld::selected_link_distances_hinted_into`]: the index
/// of the triangle nearest each link at its last query (of whichever mesh it was measured
/// against; any triangle is a valid start, a far one only prunes less). Start empty; reuse
/// it for queries of nearby configurations of the same robot.
#[derive(Clone, Debug, Default)]
pub struct NearestTriangles {
    per_link: Vec<u32>,
}

impl NearestTriangles {
    /// No warm starts yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Forgets every warm start (the next queries search as without hints).
    pub fn clear(&mut self) {
        self.per_link.clear();
    }

    /// The triangle nearest `link` at its last hinted query (an index into the mesh it was
    /// measured against), `None` before any.
    pub fn triangle(&self, link: LinkId) -> Option<u32> {
        self.per_link.get(link.0).copied().filter(|&t| t != u32::MAX)
    }
}
