//! Arithmetic shared by the certified motion checks of the sphere model
//! (`spheres/certified.rs`) and of the exact checker (`exact/certified.rs`): per test, its
//! distance bound per step of a motion ([`StepWeights`]), the states a passing test's gap certifies, and the
//! bit sets that record them.

/// Per test, one weight per group value: the test's distance changes by at most
/// `Σⱼ |Δqⱼ| wⱼ` over a straight motion by `Δq`. Stored in blocks of [`TESTS`] tests, joint by
/// joint within a block, so that a motion's bounds are summed a block at a time in registers
/// (a loop the compiler vectorises).
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct StepWeights {
    tests: usize,
    dim: usize,
    /// `by_block[(blk * dim + j) * TESTS + l]`: the weight of group value `j` in test
    /// `blk * TESTS + l` (zero past the last test).
    by_block: Vec<f64>,
}

/// Tests whose bounds [`StepWeights::per_step_into`] sums together.
const TESTS: usize = 8;

/// Group values whose `|Δqⱼ|` [`StepWeights::per_step_into`] computes ahead of a pass.
const JOINTS: usize = 16;

impl StepWeights {
    /// The weights given test by test: `rows[t * dim + j]`.
    pub(super) fn from_rows(rows: &[f64], dim: usize) -> Self {
        let tests = rows.len().checked_div(dim).unwrap_or(0);
        let weight = |t: usize, j: usize| if t < tests { rows[t * dim + j] } else { 0.0 };
        let by_block = (0..tests.div_ceil(TESTS))
            .flat_map(|blk| (0..dim).flat_map(move |j| (0..TESTS).map(move |l| (blk * TESTS + l, j))))
            .map(|(t, j)| weight(t, j))
            .collect();
        Self { tests, dim, by_block }
    }

    /// The weights of test `t`, one per group value (zeros past the last test).
    pub(super) fn row(&self, t: usize) -> Vec<f64> {
        let (blk, l) = (t / TESTS, t % TESTS);
        (0..self.dim).map(|j| self.by_block.get((blk * self.dim + j) * TESTS + l).copied().unwrap_or(0.0)).collect()
    }

    /// Per test, the reciprocal of its bound per step of the straight motion `a → b` in `n`
    /// steps (∞ if the test cannot change), the bound inflated against rounding, into `out`.
    /// Each test's sum runs over the joints in order from `0.0`, so the values are those of
    /// summing its row.
    #[inline(always)]
    pub(super) fn per_step_into(&self, a: &[f64], b: &[f64], n: usize, out: &mut Vec<f64>) {
        out.clear();
        out.resize(self.tests.div_ceil(TESTS) * TESTS, 0.0);
        let joints = self.dim.min(a.len()).min(b.len());
        if self.dim > 0 {
            for j0 in (0..joints).step_by(JOINTS) {
                let count = (joints - j0).min(JOINTS);
                let mut dq = [0.0f64; JOINTS];
                for ((d, x), y) in dq.iter_mut().zip(&a[j0..j0 + count]).zip(&b[j0..j0 + count]) {
                    *d = (y - x).abs();
                }
                let blocks = out.chunks_exact_mut(TESTS).zip(self.by_block.chunks_exact(self.dim * TESTS));
                for (sums, block) in blocks {
                    let mut acc = [0.0f64; TESTS];
                    acc.copy_from_slice(sums);
                    for (w, &dq) in block[j0 * TESTS..(j0 + count) * TESTS].chunks_exact(TESTS).zip(&dq[..count]) {
                        for (d, w) in acc.iter_mut().zip(w) {
                            *d += w * dq;
                        }
                    }
                    sums.copy_from_slice(&acc);
                }
            }
        }
        out.truncate(self.tests);
        let steps = n.max(1) as f64;
        for d in out.iter_mut() {
            *d = steps / (*d * (1.0 + 1e-9));
        }
    }
}

/// The states of a motion of `n` steps that a test passing with `gap` at state `i` certifies:
/// `lo..=hi`, those within `⌊(gap − slack) · per_step⌋` of `i`, saturating (negative → only
/// `i`, ∞ → all).
#[inline(always)]
pub(super) fn reach(gap: f64, slack: f64, per_step: f64, i: usize, n: usize) -> (usize, usize) {
    let reach = steps_within((gap - slack) * per_step, n);
    (i.saturating_sub(reach), (i + reach).min(n))
}

/// `(x as usize).min(n)` without the saturating float-to-unsigned conversion (NaN and
/// negatives → 0, ≥ `n` or ∞ → `n`): in range, the value fits an `i64`, whose truncating
/// conversion is a single instruction.
#[inline(always)]
fn steps_within(x: f64, n: usize) -> usize {
    // 2⁶³: every non-negative f64 below it converts to `i64` exactly (truncated).
    const I64_END: f64 = 9_223_372_036_854_775_808.0;
    if x >= n as f64 {
        n
    } else if x > 0.0 && x < I64_END {
        x as i64 as usize
    } else if x > 0.0 {
        (x as usize).min(n)
    } else {
        0
    }
}

/// Sets the bits `lo..=hi` of a bit set stored one word every `stride` entries of `bits`.
#[inline(always)]
pub(super) fn set_bits(bits: &mut [u64], stride: usize, span: (usize, usize)) {
    for_words(span, |w, mask| bits[w * stride] |= mask);
}

/// Calls `f(w, mask)` for each word `w` of a bit set holding bits of `lo..=hi`, `mask` the
/// bits of `lo..=hi` in word `w` (state `i` is bit `i % 64` of word `i / 64`).
#[inline(always)]
pub(super) fn for_words((lo, hi): (usize, usize), mut f: impl FnMut(usize, u64)) {
    for w in lo / 64..=hi / 64 {
        let from = if w == lo / 64 { lo % 64 } else { 0 };
        let to = if w == hi / 64 { hi % 64 } else { 63 };
        f(w, (u64::MAX >> (63 - to)) & (u64::MAX << from));
    }
}

#[cfg(test)]
mod tests {
    use super::{reach, set_bits, steps_within, StepWeights};
    use proptest::prelude::*;

    /// The row-by-row bounds `StepWeights::per_step_into` must equal.
    fn per_step_by_rows(rows: &[f64], dim: usize, a: &[f64], b: &[f64], n: usize) -> Vec<f64> {
        rows.chunks_exact(dim)
            .map(|w| {
                let d: f64 = w.iter().zip(a).zip(b).map(|((w, x), y)| w * (y - x).abs()).sum();
                n.max(1) as f64 / (d * (1.0 + 1e-9))
            })
            .collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2_000))]
        /// In blocks of tests, the bounds are bit for bit those of summing each test's row (zero
        /// weights and motions along a few joints, whose bounds are ∞, included).
        #[test]
        fn per_step_equals_per_step_by_rows(
            dim in 1usize..40,
            tests in 0usize..40,
            n in 0usize..300,
            seed in any::<u64>(),
        ) {
            use rand::{Rng, SeedableRng};
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let mut value = |zero: f64| if rng.random::<f64>() < zero { 0.0 } else { rng.random_range(0.0..3.0) };
            let rows: Vec<f64> = (0..tests * dim).map(|_| value(0.3)).collect();
            let a: Vec<f64> = (0..dim).map(|_| value(0.0) - 1.5).collect();
            let b: Vec<f64> = a.iter().map(|&x| x + value(0.4) - 1.5).collect();
            let mut out = vec![7.0];
            StepWeights::from_rows(&rows, dim).per_step_into(&a, &b, n, &mut out);
            let expected = per_step_by_rows(&rows, dim, &a, &b, n);
            prop_assert_eq!(out.len(), expected.len());
            for (x, y) in out.iter().zip(&expected) {
                prop_assert_eq!(x.to_bits(), y.to_bits());
            }
        }
    }

    /// The saturating conversion `steps_within` replaces.
    fn saturating(x: f64, n: usize) -> usize {
        (x as usize).min(n)
    }

    /// Any f64 bit pattern: NaNs, ±∞, subnormals, huge and negative values.
    fn any_f64() -> impl Strategy<Value = f64> {
        prop_oneof![
            any::<u64>().prop_map(f64::from_bits),
            -10.0..5000.0f64,
            Just(f64::NAN),
            Just(f64::INFINITY),
            Just(f64::NEG_INFINITY),
            Just(-0.0),
            Just(9_223_372_036_854_775_808.0),
            Just(18_446_744_073_709_551_616.0),
        ]
    }

    fn any_n() -> impl Strategy<Value = usize> {
        prop_oneof![0..5000usize, any::<usize>(), Just(usize::MAX), Just(1 << 63)]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]
        #[test]
        fn steps_within_matches_saturating_cast(x in any_f64(), n in any_n()) {
            prop_assert_eq!(steps_within(x, n), saturating(x, n));
        }
    }

    #[test]
    fn steps_within_edge_cases() {
        assert_eq!(steps_within(f64::NAN, 7), 0);
        assert_eq!(steps_within(-3.5, 7), 0);
        assert_eq!(steps_within(3.99, 7), 3);
        assert_eq!(steps_within(7.0, 7), 7);
        assert_eq!(steps_within(f64::INFINITY, 7), 7);
        assert_eq!(steps_within(1e300, usize::MAX), usize::MAX);
        assert_eq!(steps_within(9_223_372_036_854_775_808.0, usize::MAX), 1 << 63);
        // Around every representable boundary near 2⁶³ and 2⁶⁴.
        for n in [(1usize << 63) - 1, 1 << 63, (1 << 63) + 2048, usize::MAX - 1, usize::MAX] {
            for x in [n as f64, (n as f64).next_down(), (n as f64).next_up()] {
                assert_eq!(steps_within(x, n), saturating(x, n), "x = {x}, n = {n}");
            }
        }
    }

    #[test]
    fn reach_counts_whole_steps_inside_the_gap() {
        // gap 0.1 m, 0.03 m per step: 3 steps either side (0.09 < 0.1 − slack < 0.12).
        assert_eq!(reach(0.1, 1e-6, 1.0 / 0.03, 10, 20), (7, 13));
        assert_eq!(reach(0.1, 1e-6, 1.0 / 0.03, 1, 20), (0, 4));
        assert_eq!(reach(0.1, 1e-6, 1.0 / 0.03, 19, 20), (16, 20));
        // A gap within the slack certifies only the state itself; an unbounded one all.
        assert_eq!(reach(0.5e-6, 1e-6, 1e9, 5, 20), (5, 5));
        assert_eq!(reach(0.1, 1e-6, f64::INFINITY, 5, 20), (0, 20));
    }

    #[test]
    fn set_bits_spans_words() {
        let mut bits = [0u64; 3];
        set_bits(&mut bits, 1, (60, 130));
        assert_eq!(bits[0], 0xF000_0000_0000_0000);
        assert_eq!(bits[1], u64::MAX);
        assert_eq!(bits[2], 0b111);
        let mut one = [0u64; 1];
        set_bits(&mut one, 1, (5, 5));
        assert_eq!(one[0], 1 << 5);
    }
}
