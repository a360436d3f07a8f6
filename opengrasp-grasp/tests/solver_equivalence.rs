//! The dense force-closure solvers (`strict_combination_vertex`: a two-phase simplex;
//! `min_norm_distance`: Wolfe's algorithm) against the clarabel interior-point solves they
//! replace in the quality metrics, on random grasp wrench spaces (2–8 contacts, point and
//! soft-finger, 4–8 cone edges, μ 0.05–1.2), near-degenerate ones (antipodal pairs, whose
//! optimum is the origin on the boundary) and random 6-D point sets shifted so the origin falls
//! inside, outside or near the boundary of their hull; plus analytic cases.
//!
//! Tolerances: clarabel stops at about 1e-8 (absolute, on data of norm ~1); the dense solvers are
//! exact up to rounding. So values must agree within 1e-7 (relative for values above 1), and the force-closure verdict
//! (margin > 1e-6) may differ only where clarabel's margin is within 1e-7 of 1e-6.

use nalgebra::{Point3, Vector3, Vector6};
use opengrasp_grasp::quality::solver::{
    min_norm_distance, min_norm_point, strict_combination, strict_combination_vertex,
};
use opengrasp_grasp::{Contact, ContactModel, ContactType, GraspError, GraspWrenchSpace, ObjectFrame, Wrench};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const TOLERANCE: f64 = 1e-6;
const AGREE: f64 = 1e-7;

fn unit_vector(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    loop {
        let v = Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        if v.norm() > 0.1 {
            return v.normalize();
        }
    }
}

/// Wrenches of `n` random contacts near the unit sphere (normals tilted from the centre);
/// with `antipodal`, the contacts come in exactly opposite pairs (wrench spaces touching the
/// origin or containing it on a face).
fn grasp_wrenches(rng: &mut ChaCha8Rng, n: usize, model: &ContactModel, antipodal: bool) -> Vec<Wrench> {
    let mut contacts = Vec::new();
    while contacts.len() < n {
        let d = unit_vector(rng);
        if antipodal {
            contacts.push(Contact::new(Point3::from(d), -d).unwrap());
            contacts.push(Contact::new(Point3::from(-d), d).unwrap());
        } else {
            let tilt = 0.5 * unit_vector(rng) * rng.random_range(0.0..1.0);
            contacts.push(Contact::new(Point3::from(d * rng.random_range(0.5..1.0)), -d + tilt).unwrap());
        }
    }
    let frame = ObjectFrame::new(Point3::origin(), 1.0).unwrap();
    GraspWrenchSpace::new(&contacts, &frame, model).unwrap().wrenches().to_vec()
}

/// Checks both solvers on `w` against clarabel; returns (clarabel margin, dense margin).
fn check(w: &[Wrench]) -> Result<(f64, f64), TestCaseError> {
    let fast = strict_combination_vertex(w).unwrap();
    let slow = strict_combination(w).unwrap();
    let (s, c) = (fast.margin, slow.margin);
    if c.is_finite() {
        prop_assert!((s - c).abs() <= AGREE * c.abs().max(1.0), "margin {} vs clarabel {}", s, c);
    } else {
        // Clarabel found no margin (infeasible, or a stall at the optimum s = 0).
        prop_assert!(s <= AGREE, "margin {} where clarabel found none", s);
    }
    if (c - TOLERANCE).abs() > AGREE {
        prop_assert_eq!(s > TOLERANCE, c > TOLERANCE, "verdict: margin {} vs clarabel {}", s, c);
    }
    if s.is_finite() {
        // The vertex weights are feasible: Σλ = 1, λ ≥ s, Σ λ w = 0, to rounding error (relative
        // to the weights' size: a negative margin makes them large and of both signs).
        let l = fast.weights.as_ref().expect("weights with a finite margin");
        let size = l.iter().map(|x| x.abs()).sum::<f64>();
        prop_assert!((l.iter().sum::<f64>() - 1.0).abs() < 1e-13 * size, "sum {}", l.iter().sum::<f64>());
        prop_assert!(l.iter().all(|&x| x >= s));
        let r: Wrench = w.iter().zip(l).map(|(wi, &li)| wi * li).sum();
        prop_assert!(r.norm() < 1e-13 * size, "residual {}", r.norm());
    } else {
        prop_assert!(fast.weights.is_none());
        prop_assert!(!c.is_finite(), "clarabel margin {} where the simplex found the LP infeasible", c);
    }
    let d = min_norm_distance(w).unwrap();
    let q = min_norm_point(w).unwrap().distance;
    prop_assert!((d - q).abs() <= AGREE * q.max(1.0), "min-norm {} vs clarabel {}", d, q);
    prop_assert!(d >= 0.0);
    if (q - TOLERANCE).abs() > AGREE {
        prop_assert_eq!(d <= TOLERANCE, q <= TOLERANCE, "origin in hull: {} vs clarabel {}", d, q);
    }
    // A strict margin puts the origin inside the hull.
    if s > TOLERANCE {
        prop_assert!(d <= 1e-9, "margin {} but distance {}", s, d);
    }
    Ok((c, s))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn dense_solvers_agree_with_clarabel_on_grasps(
        seed in any::<u64>(),
        n in 2usize..9,
        mu in 0.05f64..1.2,
        edges in 4usize..9,
        soft in any::<bool>(),
        antipodal in any::<bool>(),
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let contact_type =
            if soft { ContactType::SoftFinger { torsional_friction: 0.01 } } else { ContactType::PointWithFriction };
        let model = ContactModel { friction: mu, cone_edges: edges, contact_type };
        check(&grasp_wrenches(&mut rng, n, &model, antipodal))?;
    }

    #[test]
    fn dense_solvers_agree_with_clarabel_on_point_sets(seed in any::<u64>(), n in 1usize..80, shift in 0.0f64..1.5) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let offset = Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0)).normalize() * shift;
        let w: Vec<Wrench> =
            (0..n).map(|_| Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0)) + offset).collect();
        check(&w)?;
    }
}

#[test]
fn regular_simplex_margin_and_distance() {
    // The 7 vertices of a regular simplex centred on the origin: the uniform weights 1/7 are
    // the only zero combination, so the margin is exactly 1/7; shifting the simplex by t along
    // a vertex direction v puts the nearest hull point at distance t − (inradius), …
    let mut v: Vec<Wrench> = (0..6).map(|i| Vector6::from_fn(|r, _| f64::from(u8::from(r == i)))).collect();
    let c = (1.0 - 7f64.sqrt()) / 6.0;
    v.push(Vector6::repeat(c));
    let mean: Wrench = v.iter().sum::<Wrench>() / 7.0;
    let w: Vec<Wrench> = v.iter().map(|x| x - mean).collect();
    let fast = strict_combination_vertex(&w).unwrap();
    assert!((fast.margin - 1.0 / 7.0).abs() < 1e-14, "{}", fast.margin);
    assert!(fast.weights.unwrap().iter().all(|&l| (l - 1.0 / 7.0).abs() < 1e-14));
    assert!(min_norm_distance(&w).unwrap() < 1e-14);
    // Shift by 3 along the first vertex direction: the nearest point is the opposite facet's
    // centroid (the negative of the vertex scaled by 1/6), at distance 3 − ‖w₀‖/6.
    let u = w[0].normalize();
    let shifted: Vec<Wrench> = w.iter().map(|x| x + 3.0 * u).collect();
    let d = min_norm_distance(&shifted).unwrap();
    assert!((d - (3.0 - w[0].norm() / 6.0)).abs() < 1e-13, "{d}");
    // Outside the hull but inside its affine hull (full dimension): the margin is negative.
    let s = strict_combination_vertex(&shifted).unwrap().margin;
    assert!(s < -0.1, "{s}");
}

#[test]
fn min_norm_distance_of_a_segment_and_single_points() {
    // (The shifted-simplex case is in tests/quality.rs.) A segment from (−1, 1, …) to (3, 1, …): nearest point (0, 1, …) in its interior.
    let seg = [Vector6::new(-1.0, 1.0, 0.0, 0.0, 0.0, 0.0), Vector6::new(3.0, 1.0, 0.0, 0.0, 0.0, 0.0)];
    assert!((min_norm_distance(&seg).unwrap() - 1.0).abs() < 1e-15);
    // A single point, and a set with the origin as a member.
    assert!((min_norm_distance(&[Vector6::new(0.0, 3.0, 4.0, 0.0, 0.0, 0.0)]).unwrap() - 5.0).abs() < 1e-15);
    assert_eq!(min_norm_distance(&[Vector6::zeros(), Vector6::repeat(1.0)]).unwrap(), 0.0);
}

#[test]
fn antipodal_pair_is_a_relative_interior_point() {
    // Two opposite frictional point contacts with 8-edge cones: the uniform weights 1/16 sum
    // the wrenches to zero (the cone edges cancel pairwise), so the LP margin is exactly 1/16 —
    // but the set spans only 5 dimensions (no torque about the contact axis), which is why the
    // force-closure test also requires full rank.
    let model = ContactModel { friction: 0.5, cone_edges: 8, contact_type: ContactType::PointWithFriction };
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let w = grasp_wrenches(&mut rng, 2, &model, true);
    let s = strict_combination_vertex(&w).unwrap().margin;
    assert!((s - 1.0 / 16.0).abs() < 1e-14, "{s}");
    assert!((strict_combination(&w).unwrap().margin - 1.0 / 16.0).abs() < 1e-8);
    assert!(min_norm_distance(&w).unwrap() < 1e-15);
    assert_eq!(GraspWrenchSpace::from_wrenches(w).unwrap().affine_rank(1e-9), 5);
}

#[test]
fn origin_on_a_facet_has_zero_margin() {
    // All points in the half-space x₀ ≥ 0, and a simplex of points with x₀ = 0 around the
    // origin: the origin lies on the hull's boundary, the optimum margin is exactly 0 (every
    // point with x₀ > 0 must get weight 0) and the distance is 0. Clarabel stalls on such
    // programs and reports no margin; the simplex reports the optimum 0.
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for _ in 0..50 {
        let mut w: Vec<Wrench> = (0..20)
            .map(|_| {
                let mut p: Wrench = Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0));
                p[0] = p[0].abs() + 0.1;
                p
            })
            .collect();
        // A 5-simplex in x₀ = 0 containing the origin: 5 unit vectors and minus their sum.
        for i in 1..6 {
            w.push(Vector6::from_fn(|r, _| f64::from(u8::from(r == i))));
        }
        w.push(Vector6::new(0.0, -1.0, -1.0, -1.0, -1.0, -1.0));
        let s = strict_combination_vertex(&w).unwrap().margin;
        assert!(s.abs() < 1e-12, "{s}");
        let c = strict_combination(&w).unwrap().margin;
        assert!(c <= AGREE, "{c}");
        assert!(min_norm_distance(&w).unwrap() < 1e-15);
    }
}

#[test]
fn empty_and_non_finite_wrench_sets_are_rejected() {
    assert!(matches!(strict_combination_vertex(&[]), Err(GraspError::InvalidParameter { .. })));
    assert!(matches!(min_norm_distance(&[]), Err(GraspError::InvalidParameter { .. })));
    for bad in [f64::NAN, f64::INFINITY] {
        let mut w = vec![Vector6::repeat(1.0), Vector6::repeat(-1.0), Vector6::new(1.0, -1.0, 0.0, 0.0, 0.0, 0.0)];
        w[0][2] = bad;
        assert!(matches!(strict_combination_vertex(&w), Err(GraspError::NonFinite { .. })));
        assert!(matches!(min_norm_distance(&w), Err(GraspError::NonFinite { .. })));
    }
}

/// A wrench set of affine rank 5 (six random wrenches in `x₅ = 0` and their mean's mirror
/// images) lifted off that hyperplane by `lift` in one wrench: the decomposition's rank is 5
/// or 6 depending on `lift` against the tolerance, the hard case of the Gram certificate.
fn near_flat(rng: &mut ChaCha8Rng, n: usize, lift: f64) -> Vec<Wrench> {
    let mut w: Vec<Wrench> = (0..n)
        .map(|_| {
            let mut p: Wrench = Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0));
            p[5] = 0.0;
            p
        })
        .collect();
    w[0][5] = lift;
    w
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]
    /// The affine rank with the Gram-matrix certificate of full rank equals the singular
    /// value decomposition's count on random grasp wrench spaces, near-flat sets lifted by
    /// 1e-16 to 1 (both sides of every tolerance), scaled by 1e-9 to 1e6, for tolerances
    /// from 0 to 0.5.
    #[test]
    fn certified_affine_rank_is_the_decompositions(
        seed in 0u64..1_000_000,
        n in 2usize..9,
        lift_exp in -16.0f64..0.0,
        scale_exp in -9.0f64..6.0,
        tol_index in 0usize..5,
        soft in proptest::bool::ANY,
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let tol = [0.0, 1e-12, 1e-9, 1e-3, 0.5][tol_index];
        let scale = 10f64.powf(scale_exp);
        let contact_type = if soft { ContactType::SoftFinger { torsional_friction: 0.01 } } else { ContactType::PointWithFriction };
        let model = ContactModel { friction: rng.random_range(0.05..1.2), cone_edges: 4 + n % 5, contact_type };
        let sets = [
            grasp_wrenches(&mut rng, n, &model, false),
            grasp_wrenches(&mut rng, n, &model, true),
            near_flat(&mut rng, 6 * n, 10f64.powf(lift_exp)),
        ];
        for w in sets {
            let w: Vec<Wrench> = w.iter().map(|x| x * scale).collect();
            let ws = GraspWrenchSpace::from_wrenches(w).unwrap();
            prop_assert_eq!(ws.affine_rank(tol), ws.affine_rank_svd(tol), "tolerance {}", tol);
        }
    }
}

#[test]
fn affine_rank_of_known_sets() {
    // The 12 signed unit vectors span 6 dimensions; the decomposition agrees.
    let axes: Vec<Wrench> =
        (0..12).map(|k| Vector6::from_fn(|r, _| if r == k / 2 { 1.0 - 2.0 * (k % 2) as f64 } else { 0.0 })).collect();
    let ws = GraspWrenchSpace::from_wrenches(axes.clone()).unwrap();
    assert_eq!((ws.affine_rank(1e-9), ws.affine_rank_svd(1e-9)), (6, 6));
    // Flattened by 1e-10 in the last axis: rank 6 for the tolerance 1e-12, 5 for 1e-9.
    let flat: Vec<Wrench> = axes.iter().map(|a| Vector6::new(a[0], a[1], a[2], a[3], a[4], a[5] * 1e-10)).collect();
    let ws = GraspWrenchSpace::from_wrenches(flat).unwrap();
    assert_eq!(ws.affine_rank(1e-12), 6);
    assert_eq!(ws.affine_rank(1e-9), 5);
    // Seven points in general position span 6 (the fewest); six span at most 5.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let seven: Vec<Wrench> = (0..7).map(|_| Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0))).collect();
    assert_eq!(GraspWrenchSpace::from_wrenches(seven.clone()).unwrap().affine_rank(1e-9), 6);
    assert_eq!(GraspWrenchSpace::from_wrenches(seven[..6].to_vec()).unwrap().affine_rank(1e-9), 5);
}
