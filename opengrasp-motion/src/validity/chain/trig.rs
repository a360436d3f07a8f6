//! Sine and cosine in plain `f64` arithmetic, the same bits on every machine (no platform
//! libm), branch-free so that a batch of angles (the joints of a chain, the lanes of a batch)
//! vectorises.
//!
//! The argument is reduced by a multiple `k` of π/2 (Cody–Waite, π/2 split into four parts,
//! the first three short enough that their products with `k` are exact) to a head and tail
//! `r + e` with `|r| ≲ π/4`, then sine and cosine are fdlibm's minimax polynomials of degrees
//! 13 and 14 on `[−π/4, π/4]` (Sun's public coefficients), the quadrant of `k` picking and
//! signing them. Error ≤ 1 ulp against the correctly rounded value (tests: against `std` over
//! millions of angles). Angles beyond [`FAST_LIMIT`] or not finite go to `f64::sin_cos`.

/// Largest `|x|` reduced in plain arithmetic (`|k| < 2²⁰`, so `k` times each short part of
/// π/2 is exact); larger or non-finite angles use `f64::sin_cos`.
pub(super) const FAST_LIMIT: f64 = 1.0e6;

/// π/2 = `P1 + P2 + P3 + P3T` (1.57079632673412561417, 6.07710050630396597660e-11,
/// 2.02226624871116645580e-21, 8.47842766036889956997e-32) to about 2⁻¹⁶⁰: `P1`, `P2`, `P3` have at most 32 significant
/// bits (so `k · Pi` is exact for `|k| < 2²¹`).
const P1: f64 = f64::from_bits(0x3ff9_21fb_5440_0000);
const P2: f64 = f64::from_bits(0x3dd0_b461_1a60_0000);
const P3: f64 = f64::from_bits(0x3ba3_198a_2e00_0000);
const P3T: f64 = f64::from_bits(0x397b_839a_2520_49c1);

/// `1.5 · 2⁵²`: adding and subtracting it rounds to the nearest integer (`|v| < 2⁵¹`), and the
/// sum's low mantissa bits are that integer modulo 4.
const ROUNDER: f64 = 6_755_399_441_055_744.0;

/// fdlibm's sine polynomial: `sin r ≈ r + S1 r³ + … + S6 r¹³` on `[−π/4, π/4]`.
const S: [f64; 6] = [
    -f64::from_bits(0x3fc5_5555_5555_5549),
    f64::from_bits(0x3f81_1111_1110_f8a6),
    -f64::from_bits(0x3f2a_01a0_19c1_61d5),
    f64::from_bits(0x3ec7_1de3_57b1_fe7d),
    -f64::from_bits(0x3e5a_e5e6_8a2b_9ceb),
    f64::from_bits(0x3de5_d93a_5acf_d57c),
];

/// fdlibm's cosine polynomial: `cos r ≈ 1 − r²/2 + C1 r⁴ + … + C6 r¹⁴` on `[−π/4, π/4]`.
const C: [f64; 6] = [
    f64::from_bits(0x3fa5_5555_5555_554c),
    -f64::from_bits(0x3f56_c16c_16c1_5177),
    f64::from_bits(0x3efa_01a0_19cb_1590),
    -f64::from_bits(0x3e92_7e4f_809c_52ad),
    f64::from_bits(0x3e21_ee9e_bdb4_b1c4),
    -f64::from_bits(0x3da8_fae9_be88_38d4),
];

/// `(a − b)` rounded and its exact error (Knuth's two-sum).
#[inline(always)]
fn two_diff(a: f64, b: f64) -> (f64, f64) {
    let s = a - b;
    let a_part = s + b;
    let b_part = a_part - s;
    (s, (a - a_part) - (b - b_part))
}

/// `(sin x, cos x)` for `|x| ≤ FAST_LIMIT`, branch-free (meaningless beyond).
#[inline(always)]
fn kernel(x: f64) -> (f64, f64) {
    let t = x * std::f64::consts::FRAC_2_PI + ROUNDER;
    let k = t - ROUNDER;
    let quadrant = t.to_bits();
    // x − k·π/2 as head + tail: the first difference is exact (Sterbenz), the next two
    // exact through two-sums, the last part's product rounded far below the result's ulp.
    let (s1, e1) = two_diff(x - k * P1, k * P2);
    let (s2, e2) = two_diff(s1, k * P3);
    let lo = (e1 + e2) - k * P3T;
    let r = s2 + lo;
    let e = lo - (r - s2);
    let z = r * r;
    // fdlibm's kernels with the tail: sin(r + e) ≈ r + (S1 r³ + … ) + e (1 − r²/2).
    let v = z * r;
    let sp = S[1] + z * (S[2] + z * (S[3] + z * (S[4] + z * S[5])));
    let sin = r - ((z * (0.5 * e - v * sp) - e) - v * S[0]);
    // cos(r + e) ≈ (1 − r²/2) + C(r) − r e, the head's rounding error carried.
    let cp = z * (C[0] + z * (C[1] + z * (C[2] + z * (C[3] + z * (C[4] + z * C[5])))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let cos = w + (((1.0 - w) - hz) + (z * cp - r * e));
    // Quadrant q = k mod 4: sin x = (sin r, cos r, −sin r, −cos r)[q], cos x likewise a
    // quadrant earlier; chosen and signed with bit masks.
    let swap = (quadrant & 1).wrapping_neg();
    let (sb, cb) = (sin.to_bits(), cos.to_bits());
    let (u, w) = ((cb & swap) | (sb & !swap), (sb & swap) | (cb & !swap));
    let sin_sign = (quadrant & 2) << 62;
    let cos_sign = (quadrant.wrapping_add(1) & 2) << 62;
    (f64::from_bits(u ^ sin_sign), f64::from_bits(w ^ cos_sign))
}

/// `(sin x, cos x)`, within 1 ulp, the same bits on every machine for `|x| ≤ FAST_LIMIT`.
#[inline(always)]
pub(super) fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() <= FAST_LIMIT {
        kernel(x)
    } else {
        x.sin_cos()
    }
}

/// [`sin_cos`] of every entry of `x` (the same bits entry by entry): the fast kernel over the
/// whole array (it vectorises), the few angles beyond [`FAST_LIMIT`] redone after.
#[inline(always)]
pub(super) fn sin_cos_n<const N: usize>(x: &[f64; N]) -> ([f64; N], [f64; N]) {
    let (mut s, mut c) = ([0.0; N], [0.0; N]);
    for i in 0..N {
        (s[i], c[i]) = kernel(x[i]);
    }
    for i in 0..N {
        if x[i].abs() > FAST_LIMIT || x[i].is_nan() {
            (s[i], c[i]) = x[i].sin_cos();
        }
    }
    (s, c)
}

#[cfg(test)]
mod tests;
