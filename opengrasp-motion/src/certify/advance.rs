//! Conservative advancement on the model, with a certified horizon per link and per pair.
//!
//! Each moving link (and each kept pair) is certified up to its own horizon: evaluated at `t`
//! with a time to contact `τ`, it cannot come within the margin before `t + τ`. The motion
//! advances to the smallest horizon, where only the links and pairs whose horizon is reached
//! are evaluated again. Every link and pair is thus covered by a gapless chain of certified
//! intervals from 0 to its horizon, and the motion is free once every horizon reaches 1.
//!
//! A pair is first measured by its two models' bounding balls; their primitives are placed
//! and measured only when the balls' horizon falls short of the step's (the earliest horizon
//! so far), which the step cannot pass anyway. A shorter horizon is still a certified one: the
//! pair is evaluated again, perhaps by its primitives, when it expires.

use std::cell::RefCell;

use nalgebra::{Isometry3, Vector3};

use super::geometry::{distance, Placed};
use super::{Certificate, SegmentCertifier, SphereCertifier, EXACT_BELOW};
use crate::validity::MotionBound;

/// The motion being certified: `b − a` and its per-link and per-pair rates.
#[derive(Default)]
struct Motion {
    /// `b − a` (group values).
    dq: Vec<f64>,
    /// Per link slot: bound on the speed of its points.
    rates: Vec<f64>,
    /// Per link slot: bound on their vertical speed.
    vertical_rates: Vec<f64>,
    /// Per pair: bound on the relative speed of its two models.
    pair_rates: Vec<f64>,
}

thread_local! {
    /// Buffers of [`SphereCertifier::certify`], kept between calls (sized per call).
    static SCRATCH: RefCell<(Scratch, Motion)> = RefCell::default();
}

/// Buffers of [`SphereCertifier::certify`].
#[derive(Default)]
struct Scratch {
    /// The state being placed (group values).
    q: Vec<f64>,
    full: Vec<f64>,
    poses: Vec<Isometry3<f64>>,
    /// Per model: the step at which it was last placed, bounding ball, primitive range, z
    /// range; the placed primitives.
    stamp: Vec<usize>,
    balls: Vec<(Vector3<f64>, f64)>,
    ranges: Vec<(usize, usize)>,
    z: Vec<(f64, f64)>,
    prims: Vec<Placed>,
    /// Per model: the step at which its bounding ball was last placed (pairs place the balls
    /// alone, the primitives only when the balls do not suffice).
    ball_stamp: Vec<usize>,
    /// Bounding ball of each placed primitive.
    prim_balls: Vec<(Vector3<f64>, f64)>,
    /// Certified horizon of each model and of each pair.
    horizon: Vec<f64>,
    pair_horizon: Vec<f64>,
    /// The models and pairs whose horizon is still before the end of the motion (a horizon
    /// only grows, so the others are certified to the end and never evaluated again).
    active: Vec<usize>,
    active_pairs: Vec<usize>,
    /// Models to refine by an exact query and their model times; the per-link bounds of that
    /// query (0: not queried), its distances.
    refine: Vec<(usize, f64)>,
    bounds: Vec<f64>,
    exact: Vec<f64>,
}

impl Scratch {
    /// The earliest horizon of the models, or any value of at least 1 if every one reaches
    /// the end of the motion; drops those that do from the active list.
    fn earliest_model_horizon(&mut self) -> f64 {
        let Self { horizon, active, .. } = self;
        // The minimum over the dropped ones is at least 1 as well.
        let mut earliest = f64::INFINITY;
        active.retain(|&k| {
            earliest = earliest.min(horizon[k]);
            horizon[k] < 1.0
        });
        earliest
    }
}

/// A step could not advance: a bound is at most the margin.
struct Stuck;

/// Time (segment fraction) to cover `gap − margin` at `rate`: `-inf` if the gap is at most the
/// margin, `+inf` if nothing moves.
fn time(gap: f64, margin: f64, rate: f64) -> f64 {
    if gap <= margin {
        f64::NEG_INFINITY
    } else if rate > 0.0 {
        (gap - margin) / rate
    } else {
        f64::INFINITY
    }
}

/// The smaller of `d` and the distance lower bounds from `o` (bounding ball `o_ball`) to the
/// placed primitives `prims` (with their bounding balls): a primitive whose ball is at least
/// `d` from `o`'s ball is at least `d` away, so only the others are measured.
fn min_distance<'a>(
    prims: impl Iterator<Item = (&'a Placed, &'a (Vector3<f64>, f64))>,
    o: &Placed,
    (oc, or): (&Vector3<f64>, f64),
    mut d: f64,
) -> f64 {
    for (p, (pc, pr)) in prims {
        if (pc - oc).norm() - pr - or < d {
            d = d.min(distance(p, o, d));
        }
    }
    d
}

impl SphereCertifier {
    /// Sizes the buffers for this model and resets them for a new motion.
    fn reset(&self, scratch: &mut Scratch) {
        let models = self.models.len();
        scratch.ranges.clear();
        let mut n = 0;
        for m in &self.models {
            scratch.ranges.push((n, n + m.prims.len()));
            n += m.prims.len();
        }
        let refill = |v: &mut Vec<f64>, len: usize| {
            v.clear();
            v.resize(len, 0.0);
        };
        scratch.stamp.clear();
        scratch.stamp.resize(models, usize::MAX);
        scratch.ball_stamp.clear();
        scratch.ball_stamp.resize(models, usize::MAX);
        scratch.balls.resize(models, (Vector3::zeros(), 0.0));
        scratch.z.resize(models, (0.0, 0.0));
        scratch.prims.resize(n, Placed::Ball(Vector3::zeros(), 0.0));
        scratch.prim_balls.resize(n, (Vector3::zeros(), 0.0));
        refill(&mut scratch.horizon, models);
        refill(&mut scratch.pair_horizon, self.pairs.len());
        scratch.active.clear();
        scratch.active.extend(0..models);
        scratch.active_pairs.clear();
        scratch.active_pairs.extend(0..self.pairs.len());
    }

    /// Forward kinematics at `q` (group values) of the links the models need (the others'
    /// poses are left as they are), the joints the group does not move folded into constant
    /// transforms; the models are placed on demand.
    fn set_state(&self, q: &[f64], scratch: &mut Scratch) {
        scratch.full.clear();
        scratch.full.extend_from_slice(&self.q_full);
        for (&d, &v) in self.dofs.iter().zip(q) {
            scratch.full[d] = v;
        }
        scratch.poses.resize(self.robot.links().len(), Isometry3::identity());
        for &(j, fixed) in &self.chain {
            let joint = self.robot.joint(j);
            let local =
                fixed.unwrap_or_else(|| joint.origin * joint.motion(self.robot.joint_position(&scratch.full, j)));
            scratch.poses[joint.child.0] = scratch.poses[joint.parent.0] * local;
        }
    }

    /// The poses [`SphereCertifier::set_state`] computes at `q`, by link (identity for the links
    /// no model needs).
    #[cfg(test)]
    pub(super) fn link_poses(&self, q: &[f64]) -> Vec<Isometry3<f64>> {
        let mut scratch = Scratch::default();
        self.set_state(q, &mut scratch);
        scratch.poses
    }

    /// Places the bounding ball of model `k` at the state of step `step` unless it already is.
    fn place_ball(&self, k: usize, step: usize, scratch: &mut Scratch) {
        if scratch.ball_stamp[k] == step {
            return;
        }
        scratch.ball_stamp[k] = step;
        let m = &self.models[k];
        scratch.balls[k] = ((self.base_pose * (scratch.poses[m.link.0] * m.ball.0)).coords, m.ball.1);
    }

    /// Places model `k` (its ball and its primitives) at the state of step `step` unless it
    /// already is.
    fn place(&self, k: usize, step: usize, scratch: &mut Scratch) {
        if scratch.stamp[k] == step {
            return;
        }
        scratch.stamp[k] = step;
        self.place_ball(k, step, scratch);
        let m = &self.models[k];
        let pose = self.base_pose * scratch.poses[m.link.0];
        let (start, end) = scratch.ranges[k];
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let slots = scratch.prims[start..end].iter_mut().zip(&mut scratch.prim_balls[start..end]);
        for ((slot, ball), p) in slots.zip(&m.prims) {
            *slot = Placed::new(p, &pose);
            *ball = slot.bounding_ball();
            let (a, b) = slot.z_range();
            lo = lo.min(a);
            hi = hi.max(b);
        }
        scratch.z[k] = (lo, hi);
    }

    /// Lower bound on the time (segment fraction) before placed model `k` comes within
    /// `margin` of an obstacle, or any value of at least `cap` once that is certain (`-inf`
    /// if it may be within `margin` now): per obstacle, the better of the distance bound over
    /// the link's rate and the vertical gap over its vertical rate.
    ///
    /// An obstacle is measured by the model's bounding ball alone when its time reaches
    /// `sufficient` (see [`SphereCertifier::pair_ball_ttc`]).
    fn obstacle_ttc(
        &self,
        scratch: &Scratch,
        k: usize,
        motion: &Motion,
        margin: f64,
        (cap, sufficient): (f64, f64),
    ) -> f64 {
        let slot = self.models[k].slot;
        let (rate, vrate) = (motion.rates[slot], motion.vertical_rates[slot]);
        let (c, r) = scratch.balls[k];
        let (lo, hi) = scratch.z[k];
        let (start, end) = scratch.ranges[k];
        let prims = scratch.prims[start..end].iter().zip(&scratch.prim_balls[start..end]);
        let mut best = cap;
        for ((o, (oc, or)), &(olo, ohi)) in self.obstacles.iter().zip(&self.obstacle_balls).zip(&self.obstacle_z) {
            let vertical = time((lo - ohi).max(olo - hi), margin, vrate);
            if vertical >= best {
                continue;
            }
            // The distance that certifies `best`.
            let enough = rate * best + margin;
            if (c - oc).norm() - r - or >= enough {
                continue;
            }
            let whole = distance(&Placed::Ball(c, r), o, enough);
            if whole >= enough {
                continue;
            }
            let cheap = time(whole, margin, rate).max(vertical);
            if cheap >= sufficient && whole > margin {
                best = best.min(cheap);
                continue;
            }
            // The model's ball bounds every primitive's distance from below as well.
            let d = min_distance(prims.clone(), o, (oc, *or), enough.max(2.0 * margin)).max(whole);
            best = best.min(time(d, margin, rate).max(vertical));
        }
        best
    }

    /// Lower bound on the time before the two models of pair `p` (their balls placed) come
    /// within `margin` of each other, from their bounding balls, if that time reaches the end
    /// of the motion (`cap`) or `sufficient` (a time the step cannot pass anyway: the pair is
    /// evaluated again when it expires); otherwise `Err` with the balls' distance.
    fn pair_ball_ttc(
        &self,
        scratch: &Scratch,
        p: usize,
        motion: &Motion,
        margin: f64,
        (cap, sufficient): (f64, f64),
    ) -> Result<f64, f64> {
        let (i, j) = self.pairs[p];
        let rate = motion.pair_rates[p];
        let ((ca, ra), (cb, rb)) = (scratch.balls[i], scratch.balls[j]);
        let ball = (ca - cb).norm() - ra - rb;
        let ttc = time(ball, margin, rate);
        if ball > margin && (ball >= rate * cap + margin || ttc >= sufficient) {
            Ok(ttc)
        } else {
            Err(ball)
        }
    }

    /// Lower bound on the time before the two placed models of pair `p` come within `margin`
    /// of each other, or any value of at least `cap` once that is certain, from their
    /// primitives and the distance `ball` of their bounding balls.
    fn pair_ttc(&self, scratch: &Scratch, p: usize, motion: &Motion, margin: f64, cap: f64, ball: f64) -> f64 {
        let (i, j) = self.pairs[p];
        let rate = motion.pair_rates[p];
        let (cb, rb) = scratch.balls[j];
        let mut d = (rate * cap + margin).max(2.0 * margin);
        let ((si, ei), (sj, ej)) = (scratch.ranges[i], scratch.ranges[j]);
        let others = scratch.prims[sj..ej].iter().zip(&scratch.prim_balls[sj..ej]);
        for (x, &(xc, xr)) in scratch.prims[si..ei].iter().zip(&scratch.prim_balls[si..ei]) {
            // Only the primitives of `i` whose ball comes within `d` of `j`'s ball can lower it.
            if (xc - cb).norm() - xr - rb < d {
                d = min_distance(others.clone(), x, (&xc, xr), d);
            }
        }
        time(d.max(ball), margin, rate)
    }

    /// Refines the models of `scratch.refine` by one exact distance query at the state of
    /// `scratch.full`: each gets the better of its model time and the exact one.
    ///
    /// No distance beyond `margin + rate × remaining` is needed (it certifies the link to the
    /// end of the motion), so the query is bounded by it, a little enlarged against rounding:
    /// obstacles farther away are skipped before any exact query. The bounded distance is at
    /// most the exact one, so its time is still a lower bound.
    fn refine(&self, scratch: &mut Scratch, motion: &Motion, margin: f64, t: f64, remaining: f64) -> Result<(), Stuck> {
        let Some(checker) = &self.exact else { return Err(Stuck) };
        scratch.bounds.clear();
        scratch.bounds.resize(self.robot.links().len(), 0.0);
        for &(k, _) in &scratch.refine {
            let m = &self.models[k];
            let enough = margin + motion.rates[m.slot] * remaining * (1.0 + 1e-6) + 1e-9;
            let b = &mut scratch.bounds[m.link.0];
            *b = b.max(enough);
        }
        let exact = checker.world().link_distances_below_into(
            self.robot_id,
            &scratch.full,
            &scratch.bounds,
            &mut scratch.exact,
        );
        for &(k, model) in &scratch.refine {
            let m = &self.models[k];
            let refined = match exact {
                Ok(()) => model.max(time(scratch.exact[m.link.0], margin, motion.rates[m.slot])),
                Err(_) => model,
            };
            if refined <= 0.0 {
                return Err(Stuck);
            }
            scratch.horizon[k] = scratch.horizon[k].max(t + refined);
        }
        Ok(())
    }

    /// One advancement step at `t` (the state placed by [`SphereCertifier::set_state`] as
    /// step `step`): evaluates the models and pairs whose horizon is reached, or will be
    /// before `until` (so that those about to expire are evaluated together, in one step).
    /// Returns the earliest horizon of the models and pairs, or any value of at least 1 if
    /// every one reaches the end of the motion, and drops those that do from the active
    /// lists.
    fn step(
        &self,
        scratch: &mut Scratch,
        motion: &Motion,
        margin: f64,
        t: f64,
        until: f64,
        step: usize,
    ) -> Result<f64, Stuck> {
        // Certifying up to a little past the end finishes the motion.
        let remaining = 1.0 - t + 1e-9;
        let refine_below = if self.exact.is_some() { remaining.min(EXACT_BELOW) } else { f64::NEG_INFINITY };
        // The step goes no farther than the horizons that are not evaluated now.
        let floor =
            scratch.active.iter().map(|&k| scratch.horizon[k]).filter(|&h| h > until).fold(f64::INFINITY, f64::min);
        let pairs = self.pairs_step(scratch, motion, margin, (t, until, step), floor)?;
        let mut earliest = floor.min(pairs);
        scratch.refine.clear();
        for a in 0..scratch.active.len() {
            let k = scratch.active[a];
            if scratch.horizon[k] > until {
                continue;
            }
            if !self.bound.is_moving(self.models[k].slot) {
                scratch.horizon[k] = f64::INFINITY;
                continue;
            }
            self.place(k, step, scratch);
            // The models' balls suffice where they certify past the earliest horizon so far
            // (and need no exact refinement).
            let sufficient = (earliest - t).max(refine_below);
            let ttc = self.obstacle_ttc(scratch, k, motion, margin, (remaining, sufficient));
            earliest = earliest.min(t + ttc);
            if ttc < refine_below {
                scratch.refine.push((k, ttc));
            } else if ttc <= 0.0 {
                return Err(Stuck);
            } else {
                scratch.horizon[k] = scratch.horizon[k].max(t + ttc);
            }
        }
        if !scratch.refine.is_empty() {
            self.refine(scratch, motion, margin, t, remaining)?;
        }
        Ok(scratch.earliest_model_horizon().min(pairs))
    }

    /// The pairs' part of [`SphereCertifier::step`] (`(t, until, step)` as there), before the
    /// models', whose horizons not evaluated now are at least `floor`: evaluates the pairs
    /// whose horizon is reached or will be before `until`, drops those certified to the end
    /// and returns the earliest pair horizon (a stuck step leaves the list half compacted: the
    /// motion ends there).
    fn pairs_step(
        &self,
        scratch: &mut Scratch,
        motion: &Motion,
        margin: f64,
        (t, until, step): (f64, f64, usize),
        floor: f64,
    ) -> Result<f64, Stuck> {
        let remaining = 1.0 - t + 1e-9;
        let mut earliest = f64::INFINITY;
        let mut kept = 0;
        for a in 0..scratch.active_pairs.len() {
            let p = scratch.active_pairs[a];
            if scratch.pair_horizon[p] <= until {
                let (i, j) = self.pairs[p];
                self.place_ball(i, step, scratch);
                self.place_ball(j, step, scratch);
                // The step goes no farther than the earliest horizon so far.
                let sufficient = earliest.min(floor) - t;
                let ttc = match self.pair_ball_ttc(scratch, p, motion, margin, (remaining, sufficient)) {
                    Ok(ttc) => ttc,
                    Err(ball) => {
                        self.place(i, step, scratch);
                        self.place(j, step, scratch);
                        self.pair_ttc(scratch, p, motion, margin, remaining, ball)
                    }
                };
                if ttc <= 0.0 {
                    return Err(Stuck);
                }
                scratch.pair_horizon[p] = scratch.pair_horizon[p].max(t + ttc);
            }
            let h = scratch.pair_horizon[p];
            earliest = earliest.min(h);
            if h < 1.0 {
                scratch.active_pairs[kept] = p;
                kept += 1;
            }
        }
        scratch.active_pairs.truncate(kept);
        Ok(earliest)
    }

    /// The rates of the motion `motion.dq` (see [`Motion`]).
    fn rates(&self, motion: &mut Motion) {
        let (bound, dq) = (&self.bound, &motion.dq);
        motion.rates.clear();
        motion.rates.extend((0..bound.links().len()).map(|i| bound.bound(i, dq)));
        motion.vertical_rates.clear();
        motion
            .vertical_rates
            .extend((0..bound.links().len()).map(|i| self.vertical_bound(i, dq).unwrap_or(f64::INFINITY)));
        motion.pair_rates.clear();
        motion.pair_rates.extend(
            self.pair_weights
                .chunks_exact(dq.len().max(1))
                .map(|w| w.iter().zip(dq).map(|(r, d)| r * d.abs()).sum::<f64>()),
        );
    }
}

impl SegmentCertifier for SphereCertifier {
    fn certify(&self, a: &[f64], b: &[f64], bound: &MotionBound, margin: f64, max_steps: usize) -> Certificate {
        let unknown = Certificate::Unknown { near: None, exhausted: false };
        self.staged(a, b, bound, margin, (max_steps, max_steps), None).unwrap_or(unknown)
    }

    /// Resumes the first stage's proof rather than restarting it: the steps of a proof do not
    /// depend on its budget, so the answer is `certify`'s with `max_steps`.
    fn certify_staged(
        &self,
        a: &[f64],
        b: &[f64],
        bound: &MotionBound,
        margin: f64,
        steps: (usize, usize),
        proceed: &mut dyn FnMut() -> bool,
    ) -> Option<Certificate> {
        self.staged(a, b, bound, margin, steps, Some(proceed))
    }
}

impl SphereCertifier {
    /// [`SegmentCertifier::certify_staged`] (without `proceed`: `certify` with the first
    /// budget), after checking the input.
    fn staged(
        &self,
        a: &[f64],
        b: &[f64],
        bound: &MotionBound,
        margin: f64,
        steps: (usize, usize),
        proceed: Option<&mut dyn FnMut() -> bool>,
    ) -> Option<Certificate> {
        let n = self.dofs.len();
        let within = |q: &[f64]| q.len() == n && q.iter().zip(&self.limits).all(|(v, (lo, hi))| *v >= *lo && *v <= *hi);
        if *bound != self.bound || bound.dim() != n || !within(a) || !within(b) || margin.is_nan() || margin <= 0.0 {
            return Some(Certificate::Unknown { near: None, exhausted: false });
        }
        SCRATCH.with(|cell| match cell.try_borrow_mut() {
            Ok(mut buffers) => {
                let (scratch, motion) = &mut *buffers;
                self.advance(a, b, margin, steps, proceed, scratch, motion)
            }
            // Not reached (a certification does not certify another), but never a panic.
            Err(_) => self.advance(a, b, margin, steps, proceed, &mut Scratch::default(), &mut Motion::default()),
        })
    }

    /// Conservative advancement along `a → b` (checked, within limits) with `scratch` and
    /// `motion` as buffers: [`SegmentCertifier::certify_staged`] with `steps`, going on after
    /// the first budget only if `proceed` says so (`None`: stop there).
    #[allow(clippy::too_many_arguments)]
    fn advance(
        &self,
        a: &[f64],
        b: &[f64],
        margin: f64,
        (first_steps, max_steps): (usize, usize),
        mut proceed: Option<&mut dyn FnMut() -> bool>,
        scratch: &mut Scratch,
        motion: &mut Motion,
    ) -> Option<Certificate> {
        self.reset(scratch);
        motion.dq.clear();
        motion.dq.extend(a.iter().zip(b).map(|(x, y)| y - x));
        self.rates(motion);
        let mut q = std::mem::take(&mut scratch.q);
        q.clear();
        q.extend_from_slice(a);
        let (mut t, mut last, mut step, mut budget) = (0.0f64, 0.0f64, 0, first_steps);
        let certificate = loop {
            if step == budget {
                // The budget ran out while the proof was still advancing.
                match proceed.take().map(|go| go()) {
                    Some(true) => {
                        budget = max_steps.max(first_steps);
                        continue;
                    }
                    Some(false) => break None,
                    None => break Some(Certificate::Unknown { near: Some(t), exhausted: true }),
                }
            }
            self.set_state(&q, scratch);
            // What expires within the last advance from here is evaluated now.
            let until = t + (t - last);
            let Ok(earliest) = self.step(scratch, motion, margin, t, until, step) else {
                break Some(Certificate::Unknown { near: Some(t), exhausted: false });
            };
            last = t;
            t = earliest;
            if t >= 1.0 {
                break Some(Certificate::Free);
            }
            for ((x, &a0), &dv) in q.iter_mut().zip(a).zip(&motion.dq) {
                *x = a0 + t * dv;
            }
            step += 1;
        };
        scratch.q = q;
        certificate
    }
}
