//! Closing the fingers by conservative advancement (see the module docs of [`super`]), with
//! per-link lower bounds that spare the distance queries which cannot change a step.
//!
//! Each iteration needs, per active closing dof, the step `min_l (d_l − touch/2) / R_l` over
//! its links and whether `min_l d_l ≤ touch`; `d_l` is the distance to the object's convex
//! hull, or the exact distance once one of the dof's links is within [`HULL_SWITCH_DISTANCE`]
//! of the hull of a non-convex object (the other dofs step by their hull distances, lower
//! bounds of the exact ones). Both are minima, so a link whose *lower bound* already puts it above the
//! minimum of the links queried cannot change them, and a link whose bound exceeds the touch
//! distance cannot stop its finger. The lower bounds are:
//! - the last distance known minus `Σ_c R_{c,l} |Δq_c|` (the speed bounds of the closing dofs
//!   that moved the link since): the distance to a fixed set drops by at most the largest
//!   displacement of the link's points;
//! - for exact distances also the hull distance (the object lies inside its hull).
//!
//! [`GraspEvaluator::refine`] queries the links in rounds, most limiting bound first, until no
//! unqueried link's bound is below its dof's minimum. Every step and stop decision is therefore
//! the one that querying every link gives, bit for bit (the bounds only decide which links
//! need a query, and for the hull, how far: a link that can only matter if nearer than some
//! threshold has its query stopped once it is proven beyond it);
//! `tests::lower_bounds_leave_every_closing_bit_identical` checks this
//! against the loop that queries every link.

use opengrasp_core::collision::NearestTriangles;

use super::{GraspEvaluator, HULL_SWITCH_DISTANCE};
use crate::error::Result;

/// Subtracted from every propagated lower bound (m), plus [`BOUND_RELATIVE`] of it: room for
/// the rounding of the distance queries and GJK's tolerance (relative 4.7e-8).
const BOUND_MARGIN: f64 = 1e-9;

/// The part of [`BOUND_MARGIN`] proportional to the distance.
const BOUND_RELATIVE: f64 = 1e-7;

/// The distances a refinement of the closing step queries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Distances {
    /// To the object's convex hull (`GraspEvaluator::hull_world`).
    Hull,
    /// To the object itself (`GraspEvaluator::world`).
    Exact,
}

/// The distance below which a link of speed bound `r` could set a step below `current`:
/// `current r + touch/2`, raised by a margin (1e-12 m plus 1e-9 of `current r`) far above
/// the rounding of that product and of the step `(d − touch/2) / r` computed back from it, so
/// that a link proven no nearer than the threshold gets a step of at least `current`.
fn step_threshold(current: f64, r: f64, half_touch: f64) -> f64 {
    let reach = current * r;
    reach + half_touch + 1e-12 + 1e-9 * reach.abs()
}

/// Per-link buffers of [`GraspEvaluator::close`], reused across its iterations.
struct Buffers {
    /// Hull distance per link: queried this iteration, or a lower bound.
    hull: Vec<f64>,
    /// Distance per link the step reads: exact, hull or a lower bound of them.
    dist: Vec<f64>,
    /// Lower bound of each link's hull distance at the current configuration.
    hull_lower: Vec<f64>,
    /// Lower bound of each link's exact distance at the current configuration.
    exact_lower: Vec<f64>,
    /// Bound on how far each link's distances dropped over the last step.
    drop: Vec<f64>,
    known: Vec<bool>,
    /// Per link, what a refinement round asks of its query (see [`GraspEvaluator::refine`]).
    bounds: Vec<f64>,
    query: Vec<f64>,
    /// Each link's nearest triangle of the object mesh at its last exact query (the hull
    /// world's queries leave it alone: the hull is no triangle mesh).
    hints: NearestTriangles,
}

impl GraspEvaluator {
    /// Replaces the lower bounds in `dist` by the distances `which` wherever the closing
    /// step reads them: afterwards every active closing dof gets exactly the step and stop
    /// decision it would get from those distances for all its links.
    ///
    /// Every link with `dist ≤ force` is queried (it may stop its finger, or need the exact
    /// distance); for a dof with none of those, its most limiting link by bound. Then, in
    /// rounds, every unqueried link whose bound on the step `(d − touch/2) / R` is below the
    /// smallest step `s` of the queried links of its dof. For the hull, such a query stops
    /// once the link is proven beyond [`step_threshold`]`(s)`, and the link keeps that
    /// threshold as its bound, which puts its step above `s` (`s` only decreases over the
    /// rounds). A link never queried keeps its bound, which is above `force` and never lowers
    /// its dof's minimum. `known` marks the queried links.
    ///
    /// `force` is the touch distance, and for the hull of a non-convex object
    /// [`HULL_SWITCH_DISTANCE`] (where its exact distances start). Only the hull's queries
    /// stop early: stopping the exact (mesh) ones too saves 0.2 % of the `eval_profile` mix's
    /// instructions but moved 3 closings of the default suite (`run grasp --grasps`, up to
    /// 5 mrad); the cause is not found, so they run to the end.
    fn refine(&self, which: Distances, q: &[f64], active: &[bool], dist: &mut [f64], b: &mut Buffers) -> Result<()> {
        let touch = self.options.touch_distance;
        let (world, force, stop_beyond) = match which {
            Distances::Hull => (&self.hull_world, if self.convex { touch } else { HULL_SWITCH_DISTANCE }, true),
            Distances::Exact => (&self.world, touch, false),
        };
        let half_touch = 0.5 * touch;
        b.known.iter_mut().for_each(|k| *k = false);
        let mut first = true;
        loop {
            // 0: not queried, +inf: exactly, otherwise only below the threshold.
            b.bounds.iter_mut().for_each(|m| *m = 0.0);
            let mut any = false;
            for (c, _) in self.data.closing.iter().zip(active).filter(|(_, &act)| act) {
                let bound = |l: usize, r: f64| (dist[l] - half_touch) / r;
                let links = || c.links.iter().copied().zip(c.speed_bounds.iter().copied());
                if first {
                    let mut forced = false;
                    for (l, _) in links().filter(|&(l, _)| dist[l] <= force) {
                        b.bounds[l] = f64::INFINITY;
                        forced = true;
                    }
                    if !forced {
                        let pick = links().min_by(|x, y| bound(x.0, x.1).total_cmp(&bound(y.0, y.1)));
                        if let Some((l, _)) = pick {
                            b.bounds[l] = f64::INFINITY;
                        }
                    }
                    any = true;
                } else {
                    let current =
                        links().filter(|&(l, _)| b.known[l]).map(|(l, r)| bound(l, r)).fold(f64::INFINITY, f64::min);
                    for (l, r) in links() {
                        if !b.known[l] && bound(l, r) < current {
                            // A link of several dofs is asked for the largest threshold.
                            let t = if stop_beyond { step_threshold(current, r, half_touch) } else { f64::INFINITY };
                            b.bounds[l] = b.bounds[l].max(t);
                            any = true;
                        }
                    }
                }
            }
            if !any {
                return Ok(());
            }
            world.link_distances_below_hinted_into(self.robot, q, &b.bounds, &mut b.query, &mut b.hints)?;
            for (((d, known), &m), &x) in dist.iter_mut().zip(b.known.iter_mut()).zip(&b.bounds).zip(&b.query) {
                if m > 0.0 && !*known {
                    *d = x;
                    *known = true;
                }
            }
            first = false;
        }
    }

    /// Closes the fingers from `q` (see the module docs): returns the closed configuration.
    pub(super) fn close(&self, mut q: Vec<f64>) -> Result<Vec<f64>> {
        let o = &self.options;
        let robot = self.hand.robot();
        let n = robot.links().len();
        let mut active: Vec<bool> = vec![true; self.data.closing.len()];
        let mut near_dofs: Vec<bool> = vec![false; self.data.closing.len()];
        // Nothing is known before the first query.
        let mut b = Buffers {
            hull: vec![f64::NEG_INFINITY; n],
            dist: vec![f64::NEG_INFINITY; n],
            hull_lower: vec![f64::NEG_INFINITY; n],
            exact_lower: vec![f64::NEG_INFINITY; n],
            drop: vec![0.0; n],
            known: vec![false; n],
            bounds: vec![0.0; n],
            query: Vec::new(),
            hints: NearestTriangles::new(),
        };
        for _ in 0..o.max_close_iterations {
            if !active.iter().any(|&x| x) {
                break;
            }
            // Distances to the object's convex hull are lower bounds of the exact ones and far
            // cheaper for non-convex meshes; near the hull, the exact distances are needed.
            // Only the links of active closing dofs are read (the palm and stopped fingers
            // never are), and of those only the ones whose bounds could matter.
            let mut hull = std::mem::take(&mut b.hull);
            hull.clone_from(&b.hull_lower);
            self.refine(Distances::Hull, &q, &active, &mut hull, &mut b)?;
            b.hull = hull;
            // Only the fingers with a link near the hull read exact distances; the others step
            // by their hull distances (lower bounds of the exact ones, so still safe).
            for ((n, c), &act) in near_dofs.iter_mut().zip(&self.data.closing).zip(&active) {
                *n = act && !self.convex && c.links.iter().any(|&l| b.hull[l] <= HULL_SWITCH_DISTANCE);
            }
            let near = near_dofs.iter().any(|&x| x);
            let mut dist = std::mem::take(&mut b.dist);
            if near {
                dist.clone_from(&b.hull);
                for (c, _) in self.data.closing.iter().zip(&near_dofs).filter(|(_, &n)| n) {
                    for &l in &c.links {
                        dist[l] = b.hull[l].max(b.exact_lower[l]);
                    }
                }
                self.refine(Distances::Exact, &q, &near_dofs, &mut dist, &mut b)?;
            } else {
                dist.clone_from(&b.hull);
            }
            b.drop.iter_mut().for_each(|x| *x = 0.0);
            for (c, act) in self.data.closing.iter().zip(active.iter_mut()) {
                if !*act {
                    continue;
                }
                let mut gap = f64::INFINITY;
                let mut advance = f64::INFINITY;
                for (&l, &r) in c.links.iter().zip(&c.speed_bounds) {
                    gap = gap.min(dist[l]);
                    advance = advance.min((dist[l] - 0.5 * o.touch_distance) / r);
                }
                if gap <= o.touch_distance {
                    *act = false;
                    continue;
                }
                let ds = advance.max(o.min_close_step);
                let (lo, hi) = robot.dof_limits(c.dof);
                let next = (q[c.dof] + c.velocity.signum() * ds).clamp(lo, hi);
                if next == q[c.dof] {
                    *act = false;
                }
                let moved = (next - q[c.dof]).abs();
                q[c.dof] = next;
                for (&l, &r) in c.links.iter().zip(&c.speed_bounds) {
                    b.drop[l] += r * moved;
                }
            }
            // The bounds at the new configuration (a link that did not move keeps its
            // distances exactly: same pose, same query).
            let lower =
                |x: f64, drop: f64| if drop == 0.0 { x } else { x - drop - BOUND_MARGIN - BOUND_RELATIVE * x.abs() };
            let links = b.exact_lower.iter_mut().zip(b.hull_lower.iter_mut()).zip(&b.hull).zip(&b.drop).zip(&dist);
            for ((((exact, hull_lower), &hull), &drop), &d) in links {
                let known = if near { exact.max(d) } else { *exact };
                *exact = lower(known.max(hull), drop);
                *hull_lower = lower(hull, drop);
            }
            b.dist = dist;
        }
        Ok(q)
    }
}

#[cfg(test)]
mod tests {
    use opengrasp_assets::{hands, objects};

    use super::super::{EvaluationStatus, EvaluatorOptions, GraspEvaluator, Worlds};
    use super::HULL_SWITCH_DISTANCE;
    use crate::planners::{GraspPlanner, GraspRequest, MedialAxisPlanner, SurfaceNormalPlanner};

    proptest::proptest! {
        /// A link no nearer than its step threshold gets a step `(d − touch/2) / r` of at
        /// least the step `current` the threshold was made from, despite rounding.
        #[test]
        fn step_threshold_keeps_the_step_at_or_above_current(
            current in -1e-3f64..2.0,
            r in 1e-3f64..0.5,
            half_touch in 1e-5f64..1e-2,
        ) {
            let t = super::step_threshold(current, r, half_touch);
            proptest::prop_assert!((t - half_touch) / r >= current, "threshold {t}");
            // And it is tight: within a nanometre plus 1e-9 of the reach.
            proptest::prop_assert!(t - (current * r + half_touch) <= 2e-12 + 2e-9 * (current * r).abs());
        }
    }

    /// The exact refinement as it was before the lower bounds (hull distances as the only
    /// bounds, every link within 5 mm of the hull queried).
    fn refine_exact_oracle(
        ev: &GraspEvaluator,
        q: &[f64],
        active: &[bool],
        dist: &mut [f64],
        known: &mut [bool],
        mask: &mut [bool],
        exact: &mut Vec<f64>,
    ) {
        let half_touch = 0.5 * ev.options.touch_distance;
        known.iter_mut().for_each(|k| *k = false);
        let mut first = true;
        loop {
            mask.iter_mut().for_each(|m| *m = false);
            let mut any = false;
            for (c, _) in ev.data.closing.iter().zip(active).filter(|(_, &act)| act) {
                let bound = |l: usize, r: f64| (dist[l] - half_touch) / r;
                let mut current = f64::INFINITY;
                for (&l, &r) in c.links.iter().zip(&c.speed_bounds) {
                    if known[l] || (first && dist[l] <= HULL_SWITCH_DISTANCE) {
                        current = current.min(bound(l, r));
                    }
                }
                if first {
                    for &l in &c.links {
                        if dist[l] <= HULL_SWITCH_DISTANCE {
                            mask[l] = true;
                            any = true;
                        }
                    }
                }
                if current == f64::INFINITY {
                    // Nothing exact yet for this dof: start with its most limiting link.
                    let pick = c
                        .links
                        .iter()
                        .zip(&c.speed_bounds)
                        .filter(|(&l, _)| !known[l])
                        .min_by(|a, b| bound(*a.0, *a.1).total_cmp(&bound(*b.0, *b.1)));
                    if let Some((&l, _)) = pick {
                        mask[l] = true;
                        any = true;
                    }
                } else if !first {
                    for (&l, &r) in c.links.iter().zip(&c.speed_bounds) {
                        if !known[l] && bound(l, r) < current {
                            mask[l] = true;
                            any = true;
                        }
                    }
                }
            }
            if !any {
                return;
            }
            ev.world.selected_link_distances_into(ev.robot, q, mask, exact).unwrap();
            for l in 0..dist.len() {
                if mask[l] && !known[l] {
                    dist[l] = exact[l];
                    known[l] = true;
                }
            }
            first = false;
        }
    }

    /// The closing loop as it was before the lower bounds: every link of every active dof is
    /// queried at every iteration (the oracle of the test below).
    fn close_querying_every_link(ev: &GraspEvaluator, mut q: Vec<f64>) -> Vec<f64> {
        let o = &ev.options;
        let robot = ev.hand.robot();
        let n = robot.links().len();
        let mut active = vec![true; ev.data.closing.len()];
        let (mut dist, mut exact) = (Vec::new(), Vec::new());
        let (mut near, mut known, mut moving) = (vec![false; n], vec![false; n], vec![false; n]);
        for _ in 0..o.max_close_iterations {
            if !active.iter().any(|&x| x) {
                break;
            }
            moving.iter_mut().for_each(|x| *x = false);
            for (c, _) in ev.data.closing.iter().zip(&active).filter(|(_, &act)| act) {
                c.links.iter().for_each(|&l| moving[l] = true);
            }
            ev.hull_world.selected_link_distances_into(ev.robot, &q, &moving, &mut dist).unwrap();
            // The fingers with a link near the hull.
            let near_dofs: Vec<bool> = ev
                .data
                .closing
                .iter()
                .zip(&active)
                .map(|(c, &act)| act && !ev.convex && c.links.iter().any(|&l| dist[l] <= HULL_SWITCH_DISTANCE))
                .collect();
            if near_dofs.iter().any(|&x| x) {
                refine_exact_oracle(ev, &q, &near_dofs, &mut dist, &mut known, &mut near, &mut exact);
            }
            for (c, act) in ev.data.closing.iter().zip(active.iter_mut()) {
                if !*act {
                    continue;
                }
                let gap = c.links.iter().map(|&l| dist[l]).fold(f64::INFINITY, f64::min);
                let advance = c
                    .links
                    .iter()
                    .zip(&c.speed_bounds)
                    .map(|(&l, &r)| (dist[l] - 0.5 * o.touch_distance) / r)
                    .fold(f64::INFINITY, f64::min);
                if gap <= o.touch_distance {
                    *act = false;
                    continue;
                }
                let (lo, hi) = robot.dof_limits(c.dof);
                let next = (q[c.dof] + c.velocity.signum() * advance.max(o.min_close_step)).clamp(lo, hi);
                *act = next != q[c.dof];
                q[c.dof] = next;
            }
        }
        q
    }

    /// Closing with lower bounds (fewer queries) ends in the very configuration, bit for bit,
    /// that querying every link gives: on both stock hands, a convex object (salt can) and
    /// non-convex ones (cups, detergent bottle), with both reference planners' candidates.
    #[test]
    fn lower_bounds_leave_every_closing_bit_identical() {
        let mut compared = 0;
        let mut moved_dofs = 0;
        for hand in [hands::barrett(), hands::armar3_hand()] {
            for name in ["salt_can", "white_cup", "detergent_bottle", "green_cup"] {
                let object = objects::by_name(name).unwrap();
                let mut ev = GraspEvaluator::new(&hand, &object, EvaluatorOptions::default()).unwrap();
                let info = ev.hand_info().clone();
                let request = GraspRequest { hand: &info, object: &object.mesh, seed: 0 };
                let planners: [&dyn GraspPlanner; 2] =
                    [&MedialAxisPlanner::default(), &SurfaceNormalPlanner::default()];
                for planner in planners {
                    let all = planner.plan(&request).unwrap();
                    for candidate in all.iter().step_by((all.len() / 6).max(1)) {
                        let evaluation = ev.evaluate(candidate).unwrap();
                        if evaluation.status != EvaluationStatus::Closed {
                            continue;
                        }
                        let (pi, q_open) = ev.preshape(&candidate.preshape).unwrap();
                        let rfp = ev.data.root_from_palm[pi];
                        ev.place(&evaluation.hand_pose, &rfp, Worlds::Both).unwrap();
                        let reference = close_querying_every_link(&ev, q_open.clone());
                        let bits = |q: &[f64]| q.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                        assert_eq!(bits(&evaluation.q), bits(&reference), "{name}, candidate {candidate:?}");
                        moved_dofs += q_open.iter().zip(&reference).filter(|(a, b)| a != b).count();
                        compared += 1;
                    }
                }
            }
        }
        // The comparison covers real closings, not hands that never moved.
        assert!(compared >= 60, "only {compared} closed candidates compared");
        assert!(moved_dofs >= 2 * compared, "only {moved_dofs} closing dofs moved in {compared} closings");
    }
}
