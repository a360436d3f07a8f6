//! The optimised quickhull against the previous builder it replaced
//! (`ConvexHull::from_flat_reference`): same facets, planes, volume and epsilon, bit for bit,
//! on random grasp wrench spaces (3–9 contacts, point and soft-finger, 4–8 cone edges) and on
//! random point clouds in 2–7 dimensions, including points with exact duplicates; and
//! `ConvexHull::summary_flat` (depth, volume, facet count without the hull) against both;
//! and the expanding-polytope depth search (`ConvexHull::depth_flat`, the Ferrari-Canny
//! epsilon without the hull) against the hull's depth on the same sets, shifted so the origin
//! is sometimes outside, and on boundary and degenerate cases.

use nalgebra::{Point3, Vector3};
use opengrasp_grasp::{Contact, ContactModel, ContactType, ConvexHull, GraspWrenchSpace, HullOptions, ObjectFrame};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Both builds of `coords`: equal results (errors included), checked field by field.
fn assert_same(dim: usize, coords: &[f64], options: &HullOptions) -> Result<Option<ConvexHull>, TestCaseError> {
    let new = ConvexHull::from_flat(dim, coords, options);
    let old = ConvexHull::from_flat_reference(dim, coords, options);
    match (new, old) {
        (Ok(a), Ok(b)) => {
            prop_assert_eq!(a.num_facets(), b.num_facets());
            for (fa, fb) in a.facets().zip(b.facets()) {
                prop_assert_eq!(fa.vertices, fb.vertices);
                let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                prop_assert_eq!(bits(fa.normal), bits(fb.normal));
                prop_assert_eq!(fa.offset.to_bits(), fb.offset.to_bits());
            }
            prop_assert_eq!(a.volume().to_bits(), b.volume().to_bits());
            prop_assert_eq!(a.vertices(), b.vertices());
            prop_assert_eq!(a.interior_point(), b.interior_point());
            prop_assert_eq!(a.attempts(), b.attempts());
            prop_assert_eq!(a.joggle().to_bits(), b.joggle().to_bits());
            let origin = vec![0.0; dim];
            prop_assert_eq!(a.depth(&origin).to_bits(), b.depth(&origin).to_bits());
            // The summary without the hull: the same three numbers, bit for bit.
            let summary = ConvexHull::summary_flat(dim, coords, options, &origin)
                .map_err(|e| TestCaseError::fail(format!("summary failed where the hull did not: {e}")))?;
            prop_assert_eq!(summary.depth.to_bits(), a.depth(&origin).to_bits());
            prop_assert_eq!(summary.volume.to_bits(), a.volume().to_bits());
            prop_assert_eq!(summary.facets, a.num_facets());
            assert_depth_agrees(dim, coords, options, &origin)?;
            Ok(Some(a))
        }
        (Err(a), Err(b)) => {
            prop_assert_eq!(a.to_string(), b.to_string());
            let summary = ConvexHull::summary_flat(dim, coords, options, &vec![0.0; dim]);
            prop_assert_eq!(summary.map_err(|e| e.to_string()), Err(a.to_string()));
            let search = ConvexHull::depth_flat(dim, coords, options, &vec![0.0; dim]);
            prop_assert_eq!(search.map_err(|e| e.to_string()), Err(a.to_string()));
            Ok(None)
        }
        (a, b) => Err(TestCaseError::fail(format!("new {:?} vs reference {:?}", a.err(), b.err()))),
    }
}

/// Largest absolute coordinate (the joggle's and the builder's tolerance scale).
fn scale(coords: &[f64]) -> f64 {
    coords.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// The depth search's depth of `point` against the hull's, both on the first joggle (a hull
/// that fails its verification there is retried on a ten times larger joggle, which moves the
/// depth by about `1e-8 × scale`: that is no disagreement of the two methods, so such sets are
/// skipped): within `1e-12` relative (plus `1e-14 × scale` absolute, for depths near zero)
/// when the point is inside; at most the builder's tolerance `1e-13 × scale` when outside.
fn assert_depth_agrees(dim: usize, coords: &[f64], options: &HullOptions, point: &[f64]) -> Result<(), TestCaseError> {
    let first = HullOptions { max_attempts: 1, ..options.clone() };
    let Ok(hull) = ConvexHull::summary_flat(dim, coords, &first, point) else {
        return Ok(());
    };
    let search = ConvexHull::depth_flat(dim, coords, &first, point)
        .map_err(|e| TestCaseError::fail(format!("depth search failed where the hull did not: {e}")))?;
    let scale = scale(coords);
    if hull.depth > 0.0 {
        let diff = (search - hull.depth).abs();
        prop_assert!(
            diff <= 1e-12 * hull.depth + 1e-14 * scale,
            "search {search} vs hull {} (diff {diff:e})",
            hull.depth
        );
    } else {
        prop_assert!(search <= 1e-13 * scale, "search {search} vs hull {} (point outside)", hull.depth);
    }
    Ok(())
}

fn wrench_coords(rng: &mut ChaCha8Rng, contacts: usize, model: &ContactModel) -> Vec<f64> {
    let cs: Vec<Contact> = (0..contacts)
        .map(|_| {
            let d = Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
                .normalize();
            let tilt =
                Vector3::new(rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5));
            Contact::new(Point3::from(d * rng.random_range(0.5..1.0)), -d + tilt).unwrap()
        })
        .collect();
    let frame = ObjectFrame::new(Point3::origin(), 1.0).unwrap();
    let ws = GraspWrenchSpace::new(&cs, &frame, model).unwrap();
    ws.wrenches().iter().flat_map(|w| w.iter().copied()).collect()
}

#[test]
fn equivalence_covers_full_hulls_and_degenerate_input() {
    // A 6-D grasp hull with many facets, and a degenerate set: both builders agree on each.
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let coords = wrench_coords(&mut rng, 6, &ContactModel::default());
    let hull = assert_same(6, &coords, &HullOptions::default()).unwrap().expect("full-dimensional");
    assert!(hull.num_facets() > 200, "{} facets", hull.num_facets());
    assert!(hull.volume() > 0.0);
    let flat: Vec<f64> = (0..20).flat_map(|i| [i as f64, 2.0 * i as f64, 0.0]).collect();
    assert!(assert_same(3, &flat, &HullOptions::default()).unwrap().is_none());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn grasp_wrench_hulls_are_bit_identical(
        seed in any::<u64>(),
        contacts in 3usize..10,
        mu in 0.1f64..1.2,
        edges in 4usize..9,
        soft in any::<bool>(),
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let contact_type =
            if soft { ContactType::SoftFinger { torsional_friction: 0.05 } } else { ContactType::PointWithFriction };
        let model = ContactModel { friction: mu, cone_edges: edges, contact_type };
        let coords = wrench_coords(&mut rng, contacts, &model);
        assert_same(6, &coords, &HullOptions { seed, ..HullOptions::default() })?;
    }

    #[test]
    fn depth_search_agrees_with_the_hull_off_centre(
        seed in any::<u64>(),
        contacts in 3usize..10,
        shift in prop::array::uniform6(-0.3f64..0.3),
    ) {
        // The depth of points other than the origin, inside or outside the grasp hull.
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let coords = wrench_coords(&mut rng, contacts, &ContactModel::default());
        assert_depth_agrees(6, &coords, &HullOptions::default(), &shift)?;
    }

    #[test]
    fn random_point_hulls_are_bit_identical(seed in any::<u64>(), dim in 2usize..8, extra in 0usize..40, dup in any::<bool>()) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let n = dim + 1 + extra;
        let mut coords: Vec<f64> = (0..n * dim).map(|_| rng.random_range(-1.0..1.0)).collect();
        if dup {
            let copy = coords[..dim].to_vec();
            coords.extend(copy);
        }
        assert_same(dim, &coords, &HullOptions::default())?;
        // The same cloud moved off the origin (the origin then often outside).
        let offset = rng.random_range(-1.5..1.5);
        let moved: Vec<f64> = coords.iter().map(|x| x + offset).collect();
        assert_same(dim, &moved, &HullOptions::default())?;
    }
}

/// The `d`-cube `[-1, 1]^d` moved by `shift` along the first axis.
fn cube_coords(d: usize, shift: f64) -> Vec<f64> {
    (0..1usize << d)
        .flat_map(|m| (0..d).map(move |k| if m >> k & 1 == 1 { 1.0 } else { -1.0 } + if k == 0 { shift } else { 0.0 }))
        .collect()
}

#[test]
fn depth_search_on_boundary_outside_and_degenerate_sets() {
    let options = HullOptions::default();
    for d in [2, 3, 6] {
        let origin = vec![0.0; d];
        // Centred: depth 1 (the joggle moves it by about 1e-9).
        let inside = ConvexHull::depth_flat(d, &cube_coords(d, 0.0), &options, &origin).unwrap();
        assert!((inside - 1.0).abs() < 1e-8, "{d}-cube: {inside}");
        // The origin on a facet: depth 0 up to the joggle, as the hull's.
        let on = cube_coords(d, 1.0);
        let search = ConvexHull::depth_flat(d, &on, &options, &origin).unwrap();
        let hull = ConvexHull::summary_flat(d, &on, &options, &origin).unwrap().depth;
        assert!(search.abs() < 1e-8 && (search - hull).abs() < 1e-14, "{d}-cube on a facet: {search} vs {hull}");
        // Outside: non-positive.
        let out = ConvexHull::depth_flat(d, &cube_coords(d, 1.5), &options, &origin).unwrap();
        assert!(out < -0.4, "{d}-cube outside: {out}");
    }
    // Lower-dimensional sets and wrong point sizes are the hull's errors.
    let flat: Vec<f64> = (0..20).flat_map(|i| [i as f64, 2.0 * i as f64, 0.0]).collect();
    let search = ConvexHull::depth_flat(3, &flat, &options, &[0.0; 3]).unwrap_err().to_string();
    assert_eq!(search, ConvexHull::summary_flat(3, &flat, &options, &[0.0; 3]).unwrap_err().to_string());
    assert!(ConvexHull::depth_flat(3, &cube_coords(3, 0.0), &options, &[0.0; 2]).is_err());
    // The 6-D cross-polytope: epsilon 1/√6.
    let cross: Vec<f64> =
        (0..12).flat_map(|k| (0..6).map(move |j| if j == k / 2 { [-1.0, 1.0][k % 2] } else { 0.0 })).collect();
    let eps = ConvexHull::depth_flat(6, &cross, &options, &[0.0; 6]).unwrap();
    assert!((eps - 1.0 / 6f64.sqrt()).abs() < 1e-8, "{eps}");
}
