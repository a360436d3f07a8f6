//! The plain-arithmetic sine and cosine against `std` (the platform's, within half an ulp
//! or so of the exact values): within 1 ulp everywhere, the same bits batched or not.

use proptest::prelude::*;

use super::{sin_cos, sin_cos_n, FAST_LIMIT, P1, P2, P3};

/// Ulps between `a` and `b` (0 for equal values, counting across zero).
fn ulps(a: f64, b: f64) -> u64 {
    let ordered = |v: f64| {
        let bits = v.to_bits() as i64;
        if bits < 0 {
            i64::MIN - bits
        } else {
            bits
        }
    };
    ordered(a).abs_diff(ordered(b))
}

/// The larger of sine's and cosine's ulps against `std` at `x`.
fn error(x: f64) -> u64 {
    let ((s, c), (rs, rc)) = (sin_cos(x), x.sin_cos());
    ulps(s, rs).max(ulps(c, rc))
}

#[test]
fn the_short_parts_of_half_pi_times_k_are_exact() {
    // At most 32 significant bits each: `k · P` is exact for `|k| < 2²¹`.
    for p in [P1, P2, P3] {
        assert!(p.to_bits().trailing_zeros() >= 21, "{p:e}");
    }
    assert_eq!(P1 + P2, std::f64::consts::FRAC_PI_2);
}

#[test]
fn within_one_ulp_of_std_on_a_fine_grid_of_joint_angles() {
    // Every 1e-5 rad over four turns, both signs: 2.5 million angles.
    let (mut worst, mut differ) = (0, 0);
    for i in -1_256_637..=1_256_637 {
        let x = f64::from(i) * 1e-5;
        let e = error(x);
        worst = worst.max(e);
        differ += usize::from(e > 0);
    }
    assert!(worst <= 1, "{worst} ulps");
    // Both are within an ulp of the exact value, mostly correctly rounded: 151,968 differ.
    assert!(differ < 200_000, "{differ} of 2.5 M differ");
}

#[test]
fn within_one_ulp_of_std_next_to_multiples_of_half_pi() {
    // Where the reduced angle cancels to a few ulps of x (sin kπ, cos (k + ½)π ≈ 1e-16 x).
    for k in -2_000i32..=2_000 {
        let centre = f64::from(k) * std::f64::consts::FRAC_PI_2;
        let mut x = (0..4).fold(centre, |x, _| x.next_down());
        for _ in 0..9 {
            assert!(error(x) <= 1, "{x:e}: {} ulps", error(x));
            x = x.next_up();
        }
    }
}

#[test]
fn special_angles_are_exact() {
    for (x, s, c) in [(0.0, 0.0, 1.0), (-0.0, -0.0, 1.0)] {
        let (ss, cc) = sin_cos(x);
        assert_eq!((ss.to_bits(), cc.to_bits()), (f64::to_bits(s), f64::to_bits(c)), "{x}");
    }
    // Tiny angles: sin x = x, cos x = 1 (subnormals included).
    for x in [1e-300, -5e-324, 1e-20, -3e-9] {
        assert_eq!(sin_cos(x).0, x);
        assert_eq!(sin_cos(x).1, 1.0);
    }
    // Beyond the reduction's range, and for non-finite angles, std's values.
    for x in [FAST_LIMIT * 1.5, -1e300, f64::INFINITY, f64::NAN] {
        let ((s, c), (rs, rc)) = (sin_cos(x), x.sin_cos());
        assert_eq!((s.to_bits(), c.to_bits()), (rs.to_bits(), rc.to_bits()), "{x}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn within_one_ulp_of_std_up_to_the_limit(x in -FAST_LIMIT..=FAST_LIMIT) {
        prop_assert!(error(x) <= 1, "{:e}: {} ulps", x, error(x));
    }

    /// Doubles of every binary exponent up to 2¹⁹, subnormals included (the reduction's tiny
    /// and large arguments alike).
    #[test]
    fn within_one_ulp_of_std_at_every_exponent(bits in any::<u64>(), exponent in 0u64..1043) {
        let x = f64::from_bits((bits & !(0x7ff << 52)) | exponent << 52);
        prop_assert!(error(x) <= 1, "{:e}: {} ulps", x, error(x));
    }

    /// The batched form gives every entry's [`sin_cos`] bits, the slow path among them.
    #[test]
    fn batched_equals_one_by_one(xs in prop::array::uniform8(prop_oneof![
        -10.0..10.0f64,
        -2e6..2e6f64,
        Just(f64::NAN),
        Just(f64::NEG_INFINITY),
    ])) {
        let (s, c) = sin_cos_n(&xs);
        for (i, &x) in xs.iter().enumerate() {
            let (si, ci) = sin_cos(x);
            prop_assert_eq!((s[i].to_bits(), c[i].to_bits()), (si.to_bits(), ci.to_bits()), "{}", x);
        }
    }
}
