//! Configuration-dependent motion bounds of the certified motion checks.
//!
//! A point `p` of link `k` moves, when the group values move at rate `q̇`, at speed at most
//! `Σₑ |sₑ q̇_{dₑ}| ρₑ(p)` over the moving frames `e` carrying the link (`sₑ` the factor of
//! the joint's value on group value `dₑ`, `ρₑ(p)` the distance of `p` from joint `e`'s axis;
//! `ρₑ = 1` for a prismatic joint). At a checked state the distance from each axis is
//! measured: at most that of the link's bounding-sphere centre plus the radius of a sphere
//! about it holding the link's spheres (of both covers of a layered model). Along the motion, `ρₑ` changes only through the joints distal
//! to `e` (the proximal ones move the axis and the point together), at most by
//! `Σ_{e' distal} |Δq_{dₑ'}| R_{k dₑ'}` with `R` the configuration-independent radii of
//! [`MotionBound`]. Integrating over `m` steps of `w = |Δq| / n` from the checked state:
//!
//! `D(m) ≤ α m + β m²`, `α = Σₑ |sₑ| w_{dₑ} ρₑ`, `β = ½ Σₑ |sₑ| w_{dₑ} Σ_{e' distal} w_{dₑ'} R_{k dₑ'}`.
//!
//! For a link pair only the frames carrying one link and not the other count (rigid motions
//! keep distances): those are a distal-first prefix of each link's lineage, so `α` and `β`
//! are kept as prefix sums over the lineage.

use opengrasp_core::model::LinkId;

use crate::validity::chain::{Chain, Mat34};
use crate::validity::MotionBound;

/// One moving frame carrying a link.
#[derive(Clone, Debug)]
struct Entry {
    frame: usize,
    dof: usize,
    /// `|s|`, the joint value's factor on the group value.
    scale: f64,
    prismatic: bool,
    /// `R_{k d}`: configuration-independent bound of [`MotionBound`].
    radius: f64,
}

/// Per link its lineage (distal first) with the static radii, for [`LinkReach::prefix`].
#[derive(Clone, Debug, Default)]
pub(super) struct LinkReach {
    /// Per link, its range of `entries`; its prefix sums sit at `start + k ..= end + k`.
    spans: Vec<(usize, usize)>,
    entries: Vec<Entry>,
    /// Per link, the radius of a sphere about its bounding-sphere centre holding its geometry.
    extent: Vec<f64>,
    /// Per frame, the unit joint axis in the frame (frame 0: unused).
    axes: Vec<[f64; 3]>,
}

impl LinkReach {
    /// The lineages of `links` in `chain`, with the radii of `bound` (over the same links);
    /// `extent[k]` bounds link `k`'s geometry about its bounding-sphere centre.
    pub fn new(chain: &Chain, links: &[LinkId], bound: &MotionBound, extent: &[f64]) -> Self {
        let mut this = Self { extent: extent.to_vec(), ..Self::default() };
        for (k, &l) in links.iter().enumerate() {
            let start = this.entries.len();
            for (frame, dof) in chain.lineage(chain.link(l).0) {
                let (axis, scale, prismatic) = chain.joint_of(frame);
                let norm = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
                if this.axes.len() <= frame {
                    this.axes.resize(frame + 1, [0.0; 3]);
                }
                this.axes[frame] = if norm > 0.0 { axis.map(|v| v / norm) } else { axis };
                let radius = bound.radius(k, dof);
                this.entries.push(Entry { frame, dof, scale: scale.abs(), prismatic, radius });
            }
            this.spans.push((start, this.entries.len()));
        }
        this
    }

    /// Length of the prefix-sum buffers.
    pub fn len(&self) -> usize {
        self.entries.len() + self.spans.len()
    }

    /// Index of link `k`'s prefix sum over its `count` most distal frames (`count` = lineage
    /// length: all of them).
    pub fn index(&self, k: usize, count: usize) -> usize {
        let (s, e) = self.spans[k];
        s + k + count.min(e - s)
    }

    /// Number of frames carrying link `k`.
    pub fn lineage_len(&self, k: usize) -> usize {
        let (s, e) = self.spans[k];
        e - s
    }

    /// The world joint axes at the state with frame poses `frames`: per frame, its unit
    /// direction and a point on it.
    pub fn world_axes(&self, frames: &[Mat34], out: &mut Vec<[f64; 6]>) {
        out.clear();
        out.extend(self.axes.iter().zip(frames).map(|(&[x, y, z], m)| {
            [
                m[0] * x + m[1] * y + m[2] * z,
                m[4] * x + m[5] * y + m[6] * z,
                m[8] * x + m[9] * y + m[10] * z,
                m[3],
                m[7],
                m[11],
            ]
        }));
    }

    /// Link `k`'s prefix sums of `α` and `β` (module documentation) at the state with world
    /// joint axes `axes` ([`LinkReach::world_axes`]) and the link's bounding-sphere centre
    /// `centre`, for per-step group value changes `w`.
    pub fn prefix(
        &self,
        k: usize,
        centre: &[f64; 3],
        axes: &[[f64; 6]],
        w: &[f64],
        alpha: &mut [f64],
        beta: &mut [f64],
    ) {
        let (s, e) = self.spans[k];
        let base = s + k;
        let (mut a, mut b, mut drift) = (0.0, 0.0, 0.0);
        alpha[base] = 0.0;
        beta[base] = 0.0;
        for (i, en) in self.entries[s..e].iter().enumerate() {
            let wd = w[en.dof];
            if en.prismatic {
                a += en.scale * wd;
            } else {
                let [ux, uy, uz, tx, ty, tz] = axes[en.frame];
                let d = [centre[0] - tx, centre[1] - ty, centre[2] - tz];
                let cross = [d[1] * uz - d[2] * uy, d[2] * ux - d[0] * uz, d[0] * uy - d[1] * ux];
                let rho = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt() + self.extent[k];
                a += en.scale * wd * rho;
                b += 0.5 * en.scale * wd * drift;
            }
            drift += wd * en.radius;
            alpha[base + i + 1] = a;
            beta[base + i + 1] = b;
        }
    }
}

/// The most steps `m ≤ n` with `α m + β m² < g` (`α, β ≥ 0`, inflated against rounding).
pub(super) fn steps_within(alpha: f64, beta: f64, g: f64, n: usize) -> usize {
    if g <= 0.0 {
        return 0;
    }
    let (alpha, beta) = (alpha * (1.0 + 1e-9), beta * (1.0 + 1e-9));
    // The positive root of β m² + α m − g, in the form without cancellation (∞ if α = β = 0).
    let root = 2.0 * g / (alpha + (alpha * alpha + 4.0 * beta * g).sqrt());
    let mut m = (root as usize).min(n);
    while m > 0 && alpha * m as f64 + beta * (m * m) as f64 >= g {
        m -= 1;
    }
    m
}

#[cfg(test)]
mod tests {
    use nalgebra::Isometry3;
    use opengrasp_core::model::samples;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    fn apply(m: &Mat34, p: &[f64; 3]) -> [f64; 3] {
        let [x, y, z] = *p;
        [
            m[0] * x + m[1] * y + m[2] * z + m[3],
            m[4] * x + m[5] * y + m[6] * z + m[7],
            m[8] * x + m[9] * y + m[10] * z + m[11],
        ]
    }

    /// `m⁻¹ · p` for a rigid `m`.
    fn unapply(m: &Mat34, p: &[f64; 3]) -> [f64; 3] {
        let d = [p[0] - m[3], p[1] - m[7], p[2] - m[11]];
        [
            m[0] * d[0] + m[4] * d[1] + m[8] * d[2],
            m[1] * d[0] + m[5] * d[1] + m[9] * d[2],
            m[2] * d[0] + m[6] * d[1] + m[10] * d[2],
        ]
    }

    /// On the sample arm, random straight motions: every geometry point of every link, seen
    /// from the first frame its lineage prefix leaves out (the world for the whole lineage),
    /// moves from a checked state over `m` steps by at most `α m + β m²` of that prefix, and
    /// the bound is tighter than the configuration-independent one somewhere.
    #[test]
    fn prefix_sums_bound_the_displacement_of_every_point() {
        let robot = samples::seven_dof_arm().unwrap();
        let group = robot.group("arm").unwrap().clone();
        let limits = group.limits(&robot);
        let chain = Chain::new(&robot, &group, &robot.home_configuration(), &Isometry3::identity());
        let bound = MotionBound::from_robot(&robot, &group).unwrap();
        let points: Vec<Vec<[f64; 3]>> = bound
            .links()
            .iter()
            .map(|&l| {
                let pose = chain.link(l).1;
                let corners = robot.link(l).collisions.iter().flat_map(|s| s.aabb_corners());
                corners.map(|p| apply(&pose, &[p.x, p.y, p.z])).collect()
            })
            .collect();
        // Each link's points about their first one.
        let extent: Vec<f64> = points
            .iter()
            .map(|p| p.iter().map(|q| (0..3).map(|i| (q[i] - p[0][i]).powi(2)).sum::<f64>().sqrt()).fold(0.0, f64::max))
            .collect();
        let reach = LinkReach::new(&chain, bound.links(), &bound, &extent);
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (mut alpha, mut beta) = (vec![0.0; reach.len()], vec![0.0; reach.len()]);
        let (mut frames, mut other, mut axes) = (Vec::new(), Vec::new(), Vec::new());
        let (mut tighter, mut cases) = (0, 0);
        for _ in 0..300 {
            let a: Vec<f64> = limits.iter().map(|&(lo, hi)| rng.random_range(lo..=hi)).collect();
            let spread = rng.random_range(0.01..1.5);
            let b: Vec<f64> = a
                .iter()
                .zip(&limits)
                .map(|(&x, &(lo, hi))| (x + rng.random_range(-spread..=spread)).clamp(lo, hi))
                .collect();
            let n = rng.random_range(1..64usize);
            let state =
                |i: usize| -> Vec<f64> { a.iter().zip(&b).map(|(x, y)| x + (i as f64 / n as f64) * (y - x)).collect() };
            let w: Vec<f64> = a.iter().zip(&b).map(|(x, y)| (y - x).abs() / n as f64).collect();
            let i = rng.random_range(0..=n);
            chain.frames(&state(i), &mut frames);
            for (k, &l) in bound.links().iter().enumerate() {
                let f = chain.link(l).0;
                reach.world_axes(&frames, &mut axes);
                reach.prefix(k, &apply(&frames[f], &points[k][0]), &axes, &w, &mut alpha, &mut beta);
                let lineage = chain.lineage(f);
                for count in 0..=lineage.len() {
                    // The frame the prefix leaves out: the rest of the lineage moves it and the
                    // link together.
                    let base = lineage.get(count).map_or(0, |&(g, _)| g);
                    let idx = reach.index(k, count);
                    let seen = |frames: &[Mat34], p: &[f64; 3]| unapply(&frames[base], &apply(&frames[f], p));
                    for j in 0..=n {
                        chain.frames(&state(j), &mut other);
                        let m = i.abs_diff(j) as f64;
                        let allowed = alpha[idx] * m + beta[idx] * m * m;
                        let fixed = m * (0..w.len()).map(|d| w[d] * bound.radius(k, d)).sum::<f64>();
                        for p in &points[k] {
                            let (x, y) = (seen(&frames, p), seen(&other, p));
                            let moved = ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2)).sqrt();
                            assert!(
                                moved <= allowed * (1.0 + 1e-9) + 1e-12,
                                "link {k}, prefix {count}: {moved} > {allowed}"
                            );
                        }
                        if count == lineage.len() && m > 0.0 {
                            cases += 1;
                            tighter += usize::from(allowed < fixed);
                        }
                    }
                }
            }
        }
        assert!(tighter * 2 > cases, "tighter in {tighter} of {cases}");
    }

    /// `steps_within` gives the largest step count within the gap.
    #[test]
    fn steps_within_is_the_largest_count_inside_the_gap() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..10_000 {
            let (alpha, beta) =
                (rng.random_range(0.0..0.1), rng.random_range(0.0..0.01) * f64::from(rng.random_range(0..2)));
            let (g, n) = (rng.random_range(-0.01..0.5), rng.random_range(1..64usize));
            let m = steps_within(alpha, beta, g, n);
            let moved = |m: usize| alpha * (m as f64) + beta * ((m * m) as f64);
            assert!(m == 0 || moved(m) < g, "{alpha} {beta} {g}: {m}");
            // One more step would leave the gap (up to the inflation against rounding).
            assert!(m == n || moved(m + 1) * (1.0 + 1e-9) >= g * (1.0 - 1e-12), "{alpha} {beta} {g}: {m}");
        }
        assert_eq!(steps_within(0.0, 0.0, 0.1, 17), 17);
        assert_eq!(steps_within(0.01, 0.0, 0.1, 63), 9);
        assert_eq!(steps_within(0.01, 0.0, -0.1, 63), 0);
    }
}
