//! Grasp quality metrics against analytic cases, an independent epsilon computation and
//! random grasps.

use nalgebra::{Point3, Unit, Vector3, Vector6};
use opengrasp_grasp::quality::solver::{min_norm_distance, min_norm_point};
use opengrasp_grasp::{
    Contact, ContactModel, ContactType, ConvexHull, GraspError, GraspQuality, GraspWrenchSpace, HullOptions,
    ObjectFrame, QualityOptions, QualityReport, RobustOptions,
};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A contact on the sphere of radius `r` centred at the origin in direction `dir`, pushing
/// towards the centre.
fn sphere_contact(r: f64, dir: [f64; 3]) -> Contact {
    let u = Vector3::from(dir).normalize();
    Contact::new(Point3::from(r * u), -u).unwrap()
}

fn unit_frame() -> ObjectFrame {
    ObjectFrame::new(Point3::origin(), 1.0).unwrap()
}

/// The quality options of the tests: the given friction and contact type, 8 cone edges and
/// the hull statistics (volume, facet count) on.
fn options(friction: f64, contact_type: ContactType) -> QualityOptions {
    QualityOptions {
        contact: ContactModel { friction, cone_edges: 8, contact_type },
        hull_statistics: true,
        ..QualityOptions::default()
    }
}

/// The default options with the hull statistics on.
fn with_statistics() -> QualityOptions {
    QualityOptions { hull_statistics: true, ..QualityOptions::default() }
}

/// The volume of a report computed with the hull statistics.
fn volume(report: &QualityReport) -> f64 {
    report.volume.expect("hull statistics requested")
}

fn tetrahedral() -> Vec<Contact> {
    [[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]]
        .iter()
        .map(|d| sphere_contact(1.0, *d))
        .collect()
}

const SOFT: ContactType = ContactType::SoftFinger { torsional_friction: 0.05 };

/// Independent epsilon: `min over unit u of max_i wᵢ · u`, by sampling directions and
/// refining the best ones with a shrinking random search. Always an upper bound.
fn sampled_epsilon(wrenches: &[Vector6<f64>], seed: u64) -> f64 {
    let support = |u: &Vector6<f64>| wrenches.iter().map(|w| w.dot(u)).fold(f64::NEG_INFINITY, f64::max);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut gauss = || {
        let u1: f64 = 1.0 - rng.random::<f64>();
        let u2: f64 = rng.random();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    };
    let mut samples: Vec<(f64, Vector6<f64>)> = (0..20_000)
        .map(|_| {
            let u = Vector6::from_fn(|_, _| gauss()).normalize();
            (support(&u), u)
        })
        .collect();
    samples.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut best = f64::INFINITY;
    for (mut h, mut u) in samples.into_iter().take(10) {
        let mut step = 0.1;
        for _ in 0..3000 {
            let v = (u + step * Vector6::from_fn(|_, _| gauss())).normalize();
            let hv = support(&v);
            if hv < h {
                h = hv;
                u = v;
            } else {
                step *= 0.995;
            }
        }
        best = best.min(h);
    }
    best
}

#[test]
fn antipodal_point_contacts_are_not_force_closure_but_soft_fingers_are() {
    let contacts = [sphere_contact(1.0, [1.0, 0.0, 0.0]), sphere_contact(1.0, [-1.0, 0.0, 0.0])];
    let point =
        GraspQuality::evaluate(&contacts, &unit_frame(), &options(0.5, ContactType::PointWithFriction)).unwrap();
    // No torque about the x axis can be resisted: the wrench space is 5-dimensional and
    // merely touches the origin.
    assert!(!point.force_closure);
    assert!(point.origin_in_hull);
    assert!(point.min_norm_distance < 1e-6);
    assert_eq!(point.wrench_dimension, 5);
    assert!(point.degenerate);
    assert_eq!(point.epsilon, 0.0);
    assert_eq!(point.volume, Some(0.0));
    assert_eq!(point.num_wrenches, 16);

    let soft = GraspQuality::evaluate(&contacts, &unit_frame(), &options(0.5, SOFT)).unwrap();
    assert!(soft.force_closure);
    assert_eq!(soft.wrench_dimension, 6);
    assert!(!soft.degenerate);
    assert!(soft.epsilon > 0.0 && volume(&soft) > 0.0);
    assert_eq!(soft.num_wrenches, 20);
    // The torsional primitives (n, ±γn/ρ) bound the resistible torque about the axis: the
    // pure torsion wrench direction (0,0,0,1,0,0) has support γ = 0.05, so epsilon ≤ 0.05.
    assert!(soft.epsilon <= 0.05 + 1e-9, "epsilon {}", soft.epsilon);
    let ws = GraspWrenchSpace::new(&contacts, &unit_frame(), &options(0.5, SOFT).contact).unwrap();
    let sampled = sampled_epsilon(ws.wrenches(), 3);
    assert!(soft.epsilon <= sampled + 1e-9 && sampled <= soft.epsilon * 1.03, "{} vs {sampled}", soft.epsilon);
}

#[test]
fn tetrahedral_grasp_is_force_closure_and_epsilon_matches_sampled_support() {
    let contacts = tetrahedral();
    let opts = options(0.5, ContactType::PointWithFriction);
    let report = GraspQuality::evaluate(&contacts, &unit_frame(), &opts).unwrap();
    assert!(report.force_closure && report.origin_in_hull);
    assert_eq!(report.min_norm_distance.min(1.0), report.min_norm_distance);
    assert!(report.min_norm_distance < 1e-7);
    assert_eq!(report.wrench_dimension, 6);
    assert_eq!(report.num_wrenches, 32);
    let ws = GraspWrenchSpace::new(&contacts, &unit_frame(), &opts.contact).unwrap();
    let sampled = sampled_epsilon(ws.wrenches(), 1);
    assert!(report.epsilon > 0.05, "epsilon {}", report.epsilon);
    assert!(
        report.epsilon <= sampled + 1e-9 && sampled <= report.epsilon * 1.03,
        "hull epsilon {} vs sampled {sampled}",
        report.epsilon
    );
    // Epsilon and volume are invariant to the object's scale (torques divided by ρ).
    let scaled: Vec<Contact> = contacts.iter().map(|c| Contact::from_unit(c.point * 0.05, c.normal)).collect();
    let frame = ObjectFrame::new(Point3::origin(), 0.05).unwrap();
    let small = GraspQuality::evaluate(&scaled, &frame, &opts).unwrap();
    assert!((small.epsilon - report.epsilon).abs() < 1e-7);
    assert!((volume(&small) - volume(&report)).abs() < 1e-6 * volume(&report));
    // ... and to a translation of object and contacts together.
    let shift = Vector3::new(0.3, -2.0, 1.5);
    let moved: Vec<Contact> = contacts.iter().map(|c| Contact::from_unit(c.point + shift, c.normal)).collect();
    let frame = ObjectFrame::new(Point3::from(shift), 1.0).unwrap();
    let moved = GraspQuality::evaluate(&moved, &frame, &opts).unwrap();
    assert!((moved.epsilon - report.epsilon).abs() < 1e-7);
}

#[test]
fn three_equatorial_contacts_are_force_closure_and_more_friction_helps() {
    let contacts: Vec<Contact> = (0..3)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 3.0;
            sphere_contact(1.0, [a.cos(), a.sin(), 0.0])
        })
        .collect();
    let low = GraspQuality::evaluate(&contacts, &unit_frame(), &options(0.3, ContactType::PointWithFriction)).unwrap();
    let high = GraspQuality::evaluate(&contacts, &unit_frame(), &options(0.8, ContactType::PointWithFriction)).unwrap();
    assert!(low.force_closure && high.force_closure);
    assert!(high.epsilon > low.epsilon && low.epsilon > 0.0);
    assert!(volume(&high) > volume(&low));
    // Frictionless contacts: 3 wrenches cannot span 6-D.
    let none = GraspQuality::evaluate(&contacts, &unit_frame(), &options(0.0, ContactType::PointWithFriction)).unwrap();
    assert!(!none.force_closure && none.degenerate && none.num_wrenches == 3);
}

#[test]
fn two_soft_fingers_friction_score_matches_the_cone_angle() {
    // Contacts (±cos φ, sin φ, 0): the line between them makes the angle φ with both
    // normals, so two soft fingers are force closure iff tan φ < μ (the cones' in-plane
    // edges are exact for these normals).
    let grasp = |tan_phi: f64| {
        let phi = tan_phi.atan();
        [sphere_contact(1.0, [phi.cos(), phi.sin(), 0.0]), sphere_contact(1.0, [-phi.cos(), phi.sin(), 0.0])]
    };
    let opts = options(0.5, SOFT);
    let score = |t| GraspQuality::friction_score(&grasp(t), &unit_frame(), &opts).unwrap();
    assert_eq!(score(0.0), Some(0.2));
    assert_eq!(score(0.3), Some(0.4));
    assert_eq!(score(0.45), Some(0.6));
    assert_eq!(score(0.7), Some(0.8));
    assert_eq!(score(1.1), Some(1.2));
    assert_eq!(score(1.3), None);
    // Just inside / outside the cone at μ = 0.5.
    assert!(GraspQuality::is_force_closure(&grasp(0.48), &unit_frame(), &opts).unwrap());
    assert!(!GraspQuality::is_force_closure(&grasp(0.52), &unit_frame(), &opts).unwrap());
}

#[test]
fn friction_sweep_is_monotone_on_random_grasps() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let frictions: Vec<f64> = (1..=12).map(|k| 0.1 * k as f64).collect();
    for _ in 0..20 {
        let contacts = random_contacts(&mut rng, 3);
        let mut previous = false;
        for &mu in &frictions {
            let fc =
                GraspQuality::is_force_closure(&contacts, &unit_frame(), &options(mu, ContactType::PointWithFriction))
                    .unwrap();
            assert!(fc || !previous, "force closure lost when μ grew to {mu}");
            previous = fc;
        }
        let first = frictions.iter().copied().find(|&mu| {
            GraspQuality::is_force_closure(&contacts, &unit_frame(), &options(mu, ContactType::PointWithFriction))
                .unwrap()
        });
        let swept =
            GraspQuality::friction_sweep(&contacts, &unit_frame(), &QualityOptions::default(), &frictions).unwrap();
        assert_eq!(swept, first);
    }
}

#[test]
fn degenerate_grasps_do_not_panic() {
    let opts = with_statistics();
    let empty = GraspQuality::evaluate(&[], &unit_frame(), &opts).unwrap();
    assert!(!empty.force_closure && !empty.origin_in_hull && empty.degenerate);
    assert_eq!(empty.min_norm_distance, f64::INFINITY);
    assert_eq!((empty.epsilon, empty.volume, empty.num_wrenches), (0.0, Some(0.0), 0));

    let one = GraspQuality::evaluate(&[sphere_contact(1.0, [0.0, 0.0, 1.0])], &unit_frame(), &opts).unwrap();
    assert!(!one.force_closure && !one.origin_in_hull && one.degenerate);
    // Every primitive force has normal component 1: the hull is at distance 1 from the origin.
    assert!((one.min_norm_distance - 1.0).abs() < 1e-6, "{}", one.min_norm_distance);
    assert_eq!(one.wrench_dimension, 2);

    // Coplanar contacts with in-plane normals and no friction: rank 3.
    let planar: Vec<Contact> = (0..5)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 5.0;
            sphere_contact(1.0, [a.cos(), a.sin(), 0.0])
        })
        .collect();
    let flat = GraspQuality::evaluate(&planar, &unit_frame(), &options(0.0, ContactType::PointWithFriction)).unwrap();
    assert!(!flat.force_closure && flat.degenerate && flat.wrench_dimension <= 3);
    assert_eq!((flat.epsilon, flat.volume), (0.0, Some(0.0)));

    // Duplicated contacts give duplicated wrenches: same result as the single copy.
    let mut doubled = tetrahedral();
    doubled.extend(tetrahedral());
    let a = GraspQuality::evaluate(&tetrahedral(), &unit_frame(), &opts).unwrap();
    let b = GraspQuality::evaluate(&doubled, &unit_frame(), &opts).unwrap();
    assert!(
        b.force_closure && (a.epsilon - b.epsilon).abs() < 1e-7 && (volume(&a) - volume(&b)).abs() < 1e-6 * volume(&a)
    );
}

#[test]
fn non_finite_and_invalid_input_are_typed_errors() {
    assert!(matches!(Contact::new(Point3::new(f64::NAN, 0.0, 0.0), Vector3::z()), Err(GraspError::NonFinite { .. })));
    assert!(matches!(Contact::new(Point3::origin(), Vector3::zeros()), Err(GraspError::ZeroNormal { .. })));
    let bad = Contact::from_unit(Point3::origin(), Unit::new_unchecked(Vector3::new(f64::NAN, 0.0, 0.0)));
    let err = GraspQuality::evaluate(&[bad], &unit_frame(), &QualityOptions::default()).unwrap_err();
    assert!(matches!(err, GraspError::NonFinite { .. }), "{err}");
    let unnormalised = Contact::from_unit(Point3::origin(), Unit::new_unchecked(Vector3::new(2.0, 0.0, 0.0)));
    let err = GraspQuality::evaluate(&[unnormalised], &unit_frame(), &QualityOptions::default()).unwrap_err();
    assert!(matches!(err, GraspError::ZeroNormal { index: 0 }));
    assert!(matches!(ObjectFrame::new(Point3::origin(), 0.0), Err(GraspError::InvalidParameter { .. })));
    assert!(matches!(ObjectFrame::new(Point3::origin(), f64::NAN), Err(GraspError::NonFinite { .. })));
    let frame = ObjectFrame { center_of_mass: Point3::origin(), max_radius: -1.0 };
    assert!(GraspQuality::evaluate(&tetrahedral(), &frame, &QualityOptions::default()).is_err());
    for model in [
        ContactModel { friction: -0.1, ..ContactModel::default() },
        ContactModel { friction: f64::NAN, ..ContactModel::default() },
        ContactModel { cone_edges: 2, ..ContactModel::default() },
        ContactModel { contact_type: ContactType::SoftFinger { torsional_friction: -1.0 }, ..ContactModel::default() },
    ] {
        let opts = QualityOptions { contact: model, ..QualityOptions::default() };
        assert!(GraspQuality::evaluate(&tetrahedral(), &unit_frame(), &opts).is_err(), "{model:?}");
    }
    let robust = RobustOptions { samples: 0, ..RobustOptions::default() };
    assert!(GraspQuality::robust_epsilon(&tetrahedral(), &unit_frame(), &QualityOptions::default(), &robust).is_err());
    let err = ConvexHull::new(3, &[vec![0.0, 0.0, 0.0], vec![1.0, 0.0]], &HullOptions::default()).unwrap_err();
    assert!(matches!(err, GraspError::DimensionMismatch { index: 1, expected: 3, actual: 2 }));
}

#[test]
fn robust_epsilon_is_seeded_and_close_to_nominal_for_small_noise() {
    let contacts = tetrahedral();
    let opts = QualityOptions::default();
    let nominal = GraspQuality::evaluate(&contacts, &unit_frame(), &opts).unwrap().epsilon;
    let robust = RobustOptions { samples: 16, seed: 3, ..RobustOptions::default() };
    let a = GraspQuality::robust_epsilon(&contacts, &unit_frame(), &opts, &robust).unwrap();
    let b = GraspQuality::robust_epsilon(&contacts, &unit_frame(), &opts, &robust).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.samples, 16);
    assert_eq!(a.force_closure_rate, 1.0);
    assert!(a.std > 0.0 && (a.mean - nominal).abs() < 0.2 * nominal, "{a:?} vs {nominal}");
    // Without noise every sample is the nominal grasp.
    let exact = RobustOptions { samples: 4, seed: 1, position_std: 0.0, normal_std: 0.0, friction_std: 0.0 };
    let c = GraspQuality::robust_epsilon(&contacts, &unit_frame(), &opts, &exact).unwrap();
    assert!((c.mean - nominal).abs() < 1e-12 && c.std < 1e-9);
}

#[test]
fn hull_of_6d_cross_polytope_and_cube() {
    let mut cross = Vec::new();
    for k in 0..6 {
        for s in [-1.0, 1.0] {
            let mut p = vec![0.0; 6];
            p[k] = s;
            cross.push(p);
        }
    }
    let h = ConvexHull::new(6, &cross, &HullOptions::default()).unwrap();
    assert_eq!(h.num_facets(), 64);
    assert!((h.volume() - 64.0 / 720.0).abs() < 1e-7);
    assert!((h.depth(&[0.0; 6]) - 1.0 / 6f64.sqrt()).abs() < 1e-7);
    let cube: Vec<Vec<f64>> =
        (0..64usize).map(|m| (0..6).map(|k| if m >> k & 1 == 1 { 0.5 } else { -0.5 }).collect()).collect();
    let h = ConvexHull::new(6, &cube, &HullOptions::default()).unwrap();
    assert_eq!(h.vertices().len(), 64);
    assert!((h.volume() - 1.0).abs() < 1e-6);
    assert!((h.depth(&[0.0; 6]) - 0.5).abs() < 1e-7);
    // Interior points of the cube are not vertices.
    let mut with_inner = cube.clone();
    with_inner.push(vec![0.1; 6]);
    let h = ConvexHull::new(6, &with_inner, &HullOptions::default()).unwrap();
    assert!(!h.vertices().contains(&64));
}

#[test]
fn cross_polytope_wrench_space_has_analytic_epsilon_and_volume() {
    let mut wrenches = Vec::new();
    for k in 0..6 {
        for s in [-1.0, 1.0] {
            let mut w = Vector6::zeros();
            w[k] = s;
            wrenches.push(w);
        }
    }
    let ws = GraspWrenchSpace::from_wrenches(wrenches).unwrap();
    let report = GraspQuality::evaluate_wrench_space(&ws, &with_statistics()).unwrap();
    assert!(report.force_closure && report.origin_in_hull && !report.degenerate);
    assert!((report.epsilon - 1.0 / 6f64.sqrt()).abs() < 1e-7, "{}", report.epsilon);
    assert!((volume(&report) - 64.0 / 720.0).abs() < 1e-7);
    assert_eq!(report.hull_facets, Some(64));
    // Every LP weight can be 1/12 (opposite pairs cancel).
    assert!((report.positive_combination_margin - 1.0 / 12.0).abs() < 1e-6);
    // Shifted by 1 along x the origin becomes a vertex of the hull: in the closed hull but
    // not in its interior. Shifted by 1.5 it is outside, at distance 0.5.
    let shift = |dx: f64| {
        let w: Vec<Vector6<f64>> =
            ws.wrenches().iter().map(|w| w + Vector6::new(dx, 0.0, 0.0, 0.0, 0.0, 0.0)).collect();
        GraspQuality::evaluate_wrench_space(&GraspWrenchSpace::from_wrenches(w).unwrap(), &with_statistics()).unwrap()
    };
    let touching = shift(1.0);
    assert!(touching.origin_in_hull && !touching.force_closure && !touching.degenerate);
    assert!(touching.min_norm_distance < 1e-6 && touching.epsilon == 0.0);
    let report = shift(1.5);
    assert!(!report.force_closure && !report.origin_in_hull);
    assert!((report.min_norm_distance - 0.5).abs() < 1e-6);
    assert_eq!(report.epsilon, 0.0);
    assert!((volume(&report) - 64.0 / 720.0).abs() < 1e-7);
}

#[test]
fn hull_statistics_are_opt_in_and_leave_epsilon_unchanged() {
    let contacts = tetrahedral();
    let plain = GraspQuality::evaluate(&contacts, &unit_frame(), &QualityOptions::default()).unwrap();
    assert_eq!((plain.volume, plain.hull_facets), (None, None));
    let full = GraspQuality::evaluate(&contacts, &unit_frame(), &with_statistics()).unwrap();
    assert!(volume(&full) > 0.0 && full.hull_facets.is_some_and(|f| f > 100), "{full:?}");
    // Epsilon comes from the depth search either way: the same bits.
    assert!(plain.epsilon > 0.05);
    assert_eq!(plain.epsilon.to_bits(), full.epsilon.to_bits());
    // Without closure the evaluator's variant skips the hull: statistics 0, not absent.
    let two = [sphere_contact(1.0, [1.0, 0.0, 0.0]), sphere_contact(1.0, [-1.0, 0.0, 0.0])];
    let skipped = GraspQuality::evaluate_hull_if_closure(&two, &unit_frame(), &with_statistics()).unwrap();
    assert_eq!((skipped.epsilon, skipped.volume, skipped.hull_facets), (0.0, Some(0.0), Some(0)));
    // Older serialized options (no `hull_statistics`) load with the statistics off, and a
    // report without them serializes without the two fields.
    let mut json = serde_json::to_value(QualityOptions::default()).unwrap();
    json.as_object_mut().unwrap().remove("hull_statistics");
    let old: QualityOptions = serde_json::from_value(json).unwrap();
    assert!(!old.hull_statistics);
    let text = serde_json::to_string(&plain).unwrap();
    assert!(!text.contains("volume") && !text.contains("hull_facets"), "{text}");
    let back: QualityReport = serde_json::from_str(&text).unwrap();
    assert_eq!(back, plain);
}

#[test]
fn object_frame_from_points_uses_the_farthest_point() {
    let pts = [Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, -3.0, 0.0), Point3::new(0.0, 0.0, 2.0)];
    let frame = ObjectFrame::from_points(Point3::new(0.0, 1.0, 0.0), &pts).unwrap();
    assert!((frame.max_radius - 4.0).abs() < 1e-12);
    assert!(ObjectFrame::from_points(Point3::origin(), &[]).is_err());
}

#[test]
fn hull_of_degenerate_points_is_a_typed_error() {
    let flat = [vec![0.0, 0.0, 0.0], vec![1.0, 0.0, 0.0], vec![0.0, 1.0, 0.0], vec![1.0, 1.0, 0.0]];
    let err = ConvexHull::new(3, &flat, &HullOptions::default()).unwrap_err();
    assert!(matches!(err, GraspError::DegenerateHull { dimension: 3, affine_rank: 2 }));
    let err = ConvexHull::new(2, &[[1.0, 1.0], [1.0, 1.0]], &HullOptions::default()).unwrap_err();
    assert!(matches!(err, GraspError::DegenerateHull { affine_rank: 0, .. }));
    assert!(ConvexHull::new::<[f64; 2]>(2, &[], &HullOptions::default()).is_err());
}

/// Brute-force facets of a point set in general position (2-D or 3-D): every d-subset
/// whose hyperplane has all other points on one side.
fn brute_force_facets(d: usize, pts: &[Vec<f64>]) -> Vec<(Vec<usize>, Vec<f64>, f64)> {
    let n = pts.len();
    let mut out = Vec::new();
    let mut subsets: Vec<Vec<usize>> = Vec::new();
    for i in 0..n {
        for j in (i + 1)..n {
            if d == 2 {
                subsets.push(vec![i, j]);
            } else {
                for k in (j + 1)..n {
                    subsets.push(vec![i, j, k]);
                }
            }
        }
    }
    for s in subsets {
        let normal: Vec<f64> = if d == 2 {
            let (a, b) = (&pts[s[0]], &pts[s[1]]);
            vec![b[1] - a[1], a[0] - b[0]]
        } else {
            let a = Vector3::from_column_slice(&pts[s[0]]);
            let b = Vector3::from_column_slice(&pts[s[1]]);
            let c = Vector3::from_column_slice(&pts[s[2]]);
            (b - a).cross(&(c - a)).iter().copied().collect()
        };
        let len = normal.iter().map(|x| x * x).sum::<f64>().sqrt();
        let normal: Vec<f64> = normal.iter().map(|x| x / len).collect();
        let offset: f64 = normal.iter().zip(&pts[s[0]]).map(|(a, b)| a * b).sum();
        let side: Vec<f64> =
            pts.iter().map(|p| normal.iter().zip(p).map(|(a, b)| a * b).sum::<f64>() - offset).collect();
        if side.iter().all(|&x| x <= 1e-12) {
            out.push((s, normal, offset));
        } else if side.iter().all(|&x| x >= -1e-12) {
            out.push((s, normal.iter().map(|x| -x).collect(), -offset));
        }
    }
    out
}

#[test]
fn hull_matches_brute_force_on_random_points_in_2d_and_3d() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for d in [2usize, 3] {
        for trial in 0..10 {
            let n = 8 + 3 * trial;
            let pts: Vec<Vec<f64>> = (0..n).map(|_| (0..d).map(|_| rng.random_range(-1.0..1.0)).collect()).collect();
            let hull = ConvexHull::new(d, &pts, &HullOptions::default()).unwrap();
            let brute = brute_force_facets(d, &pts);
            let mut brute_vertices: Vec<usize> = brute.iter().flat_map(|f| f.0.clone()).collect();
            brute_vertices.sort_unstable();
            brute_vertices.dedup();
            assert_eq!(hull.vertices(), &brute_vertices[..], "d = {d}, n = {n}");
            assert_eq!(hull.num_facets(), brute.len());
            let mut facets: Vec<Vec<usize>> = hull
                .facets()
                .map(|f| {
                    let mut v = f.vertices.to_vec();
                    v.sort_unstable();
                    v
                })
                .collect();
            facets.sort();
            let mut expected: Vec<Vec<usize>> = brute.iter().map(|f| f.0.clone()).collect();
            expected.sort();
            assert_eq!(facets, expected);
            // Volume: simplices from the centroid over the brute-force facets.
            let centroid: Vec<f64> = (0..d).map(|k| pts.iter().map(|p| p[k]).sum::<f64>() / n as f64).collect();
            let volume: f64 = brute
                .iter()
                .map(|(s, normal, offset)| {
                    let height = offset - normal.iter().zip(&centroid).map(|(a, b)| a * b).sum::<f64>();
                    let base = if d == 2 {
                        let (a, b) = (&pts[s[0]], &pts[s[1]]);
                        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
                    } else {
                        let a = Vector3::from_column_slice(&pts[s[0]]);
                        let b = Vector3::from_column_slice(&pts[s[1]]);
                        let c = Vector3::from_column_slice(&pts[s[2]]);
                        0.5 * (b - a).cross(&(c - a)).norm()
                    };
                    height * base / d as f64
                })
                .sum();
            assert!((hull.volume() - volume).abs() < 1e-6, "{} vs {volume}", hull.volume());
            // Depth of random query points against the brute-force facet planes.
            for _ in 0..20 {
                let q: Vec<f64> = (0..d).map(|_| rng.random_range(-1.2..1.2)).collect();
                let expected = brute
                    .iter()
                    .map(|(_, nrm, off)| off - nrm.iter().zip(&q).map(|(a, b)| a * b).sum::<f64>())
                    .fold(f64::INFINITY, f64::min);
                assert!((hull.depth(&q) - expected).abs() < 1e-7);
            }
        }
    }
}

#[test]
fn min_norm_point_of_a_shifted_simplex() {
    // Hull of (1,0,..), (1,1,0,..), (1,-1,0,..): nearest point to the origin is (1,0,...).
    let w = [
        Vector6::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        Vector6::new(1.0, 1.0, 0.0, 0.0, 0.0, 0.0),
        Vector6::new(1.0, -1.0, 0.5, 0.0, 0.0, 0.0),
        Vector6::new(2.0, 0.0, 0.0, 3.0, 0.0, 0.0),
    ];
    let m = min_norm_point(&w).unwrap();
    assert!((m.distance - 1.0).abs() < 1e-7, "{}", m.distance);
    // Wolfe's algorithm (what the quality metrics use) is exact up to rounding.
    assert!((min_norm_distance(&w).unwrap() - 1.0).abs() < 1e-15);
    assert!((m.weights.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    assert!(m.weights[0] > 0.99);
}

/// Random contacts on the unit sphere with normals tilted up to ~35° from the centre.
fn random_contacts(rng: &mut ChaCha8Rng, n: usize) -> Vec<Contact> {
    (0..n)
        .map(|_| {
            let d = Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
                .normalize();
            let tilt =
                Vector3::new(rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5));
            Contact::new(Point3::from(d), -d + tilt).unwrap()
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1024, ..ProptestConfig::default() })]

    /// The QP/LP force-closure tests and epsilon > 0 (from the hull) agree.
    #[test]
    fn force_closure_tests_agree_with_epsilon(seed in any::<u64>(), n in 2usize..6, mu in 0.1f64..1.0, soft in any::<bool>()) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let contacts = random_contacts(&mut rng, n);
        let contact_type = if soft { SOFT } else { ContactType::PointWithFriction };
        let report = GraspQuality::evaluate(&contacts, &unit_frame(), &options(mu, contact_type)).unwrap();
        let ws = GraspWrenchSpace::new(&contacts, &unit_frame(), &options(mu, contact_type).contact).unwrap();
        let wrenches = ws.wrenches();
        // A ball of radius ε around the origin in the hull gives a zero combination with every
        // weight ≥ t/n, t = ε/(|c|+ε) (c the wrenches' centroid): the origin is t·c plus
        // (1−t)·(−ε c/|c|), a hull point. So the LP margin is at least that bound.
        let centroid_norm = (wrenches.iter().sum::<Vector6<f64>>() / wrenches.len() as f64).norm();
        let margin_bound = report.epsilon / (wrenches.len() as f64 * (centroid_norm + report.epsilon));
        if report.epsilon > 0.0 {
            prop_assert!(
                report.positive_combination_margin >= margin_bound * (1.0 - 1e-6) - 1e-12,
                "margin {} below the epsilon bound {}: {:?}", report.positive_combination_margin, margin_bound, report
            );
        }
        // Skip the measure-zero band where the origin is within tolerance of the boundary: the
        // LP margin (a convex weight, tolerance 1e-6) and ε (a distance) then need not agree.
        let near_boundary = (report.min_norm_distance < 1e-5 && report.epsilon < 1e-5)
            || (report.epsilon > 0.0 && margin_bound <= 1e-6 * (1.0 + 1e-6));
        if !near_boundary {
            prop_assert_eq!(report.force_closure, report.epsilon > 0.0, "{:?}", report);
            prop_assert_eq!(report.origin_in_hull, report.epsilon > 0.0, "{:?}", report);
        }
        // The min-norm QP on its own (evaluate skips it when the LP proves force closure).
        let qp = min_norm_point(wrenches).unwrap().distance;
        if !(qp < 1e-5 && report.epsilon < 1e-5) {
            prop_assert_eq!(qp <= 1e-6, report.epsilon > 0.0, "qp distance {} vs {:?}", qp, report);
        }
        prop_assert!((qp - report.min_norm_distance).abs() < 1e-6, "{} vs {}", qp, report.min_norm_distance);
        prop_assert!(report.min_norm_distance >= 0.0);
        prop_assert!(report.force_closure <= report.origin_in_hull);
        if report.degenerate {
            prop_assert!(!report.force_closure && report.epsilon == 0.0 && report.volume == Some(0.0));
        }
    }
}
