//! Certified post-processing: the conservative model's proofs imply the exact validators'
//! verdicts, so post-processing with it gives exactly the paths of the exact procedure.

use std::sync::Arc;
use std::time::Duration;

use nalgebra::Isometry3;
use opengrasp_bench::scenes::{armar_standard_scene, certifier_for};
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::model::{Geometry, JointGroup, Robot, Shape};
use opengrasp_core::scene::{RobotId, Scene, SceneObject, StaticBody};
use opengrasp_motion::benchmark::{postprocessing_options, BenchmarkOptions, SceneInstance};
use opengrasp_motion::certify::{Certificate, SegmentCertifier, SphereCertifier};
use opengrasp_motion::planners::RrtConnect;
use opengrasp_motion::smoothing::{repair_with, shortcut_with};
use opengrasp_motion::validate::{validate_path, ValidationOptions};
use opengrasp_motion::validity::{CollisionChecker, CountingChecker, MotionBound, StateValidityChecker};
use opengrasp_motion::{MotionError, MotionPlanner};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The stock kitchen, its humanoid, `group` and the start configuration.
fn kitchen(group: &str) -> (Scene, RobotId, Arc<Robot>, JointGroup, Vec<f64>) {
    let kitchen = opengrasp_assets::scenes::kitchen().unwrap();
    let robot = kitchen.scene.robot(kitchen.robot).unwrap().robot.clone();
    let group = robot.group(group).unwrap().clone();
    (kitchen.scene, kitchen.robot, robot, group, kitchen.start_configuration)
}

/// Clean the Table's group (base, hip, right arm) in the stock kitchen, with its exact
/// checker and certifier.
struct BaseKitchen {
    scene: Scene,
    rid: RobotId,
    robot: Arc<Robot>,
    group: JointGroup,
    q: Vec<f64>,
    checker: CollisionChecker,
    certifier: SphereCertifier,
}

fn base_kitchen() -> BaseKitchen {
    checked_kitchen("base_hip_right_arm")
}

/// `group` in the stock kitchen, with its exact checker and certifier.
fn checked_kitchen(group: &str) -> BaseKitchen {
    let (scene, rid, robot, group, q) = kitchen(group);
    let world = Arc::new(CollisionWorld::new(&scene).unwrap());
    let checker = CollisionChecker::new(world, rid, robot.clone(), group.clone(), q.clone()).unwrap();
    let certifier = certifier_for(&scene, rid, &group, &q, &checker).unwrap();
    BaseKitchen { scene, rid, robot, group, q, checker, certifier }
}

/// Random segments of length up to `reach` from random valid states; returns (certified,
/// tried). Every certified segment must pass the exact discrete, strict and continuous
/// validators.
fn certified_segments_are_valid(
    checker: &dyn StateValidityChecker,
    certifier: &dyn SegmentCertifier,
    limits: &[(f64, f64)],
    centre: &[f64],
    spread: f64,
    reach: f64,
    seed: u64,
) -> (usize, usize) {
    let bound = checker.motion_bound().expect("a motion bound");
    let options = ValidationOptions::default();
    let margin = options.ccd.tolerance + 1e-6;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut draw = |c: &[f64], s: f64| -> Vec<f64> {
        c.iter().zip(limits).map(|(v, (lo, hi))| (v + rng.random_range(-s..=s)).clamp(*lo, *hi)).collect()
    };
    let (mut certified, mut tried, mut draws) = (0, 0, 0);
    while tried < 40 && draws < 4000 {
        draws += 1;
        let a = draw(centre, spread);
        if !checker.is_valid(&a) {
            continue;
        }
        let b = draw(&a, reach);
        tried += 1;
        if certifier.certify(&a, &b, bound, margin, 1000) == Certificate::Free {
            certified += 1;
            let v = validate_path(checker, &[a.clone(), b.clone()], &options);
            assert!(v.discrete && v.strict && v.continuous == Some(true), "{a:?} -> {b:?}: {v:?}");
        }
    }
    (certified, tried)
}

/// Kitchen scene 1 (hip + right arm, the whole humanoid modelled): random segments around
/// the start that the model certifies pass every exact validator, and it certifies many.
#[test]
fn certified_kitchen_segments_pass_the_exact_validators() {
    let instance = (armar_standard_scene().generate)(0).unwrap();
    let certifier = instance.certifier.as_deref().expect("kitchen scenes carry a certifier");
    let limits = instance.group.limits(&instance.robot);
    let (certified, tried) =
        certified_segments_are_valid(&*instance.checker, certifier, &limits, &instance.start, 1.2, 0.6, 1);
    println!("kitchen scene 1: {certified} of {tried} random segments certified");
    assert!(tried == 40 && certified >= tried / 2, "{certified} of {tried}");
}

/// A carried object (a box attached to the palm, Clean the Table's group with the base): the
/// certified segments pass the exact validators with the carried object's motion bound.
#[test]
fn certified_segments_with_a_carried_object_pass_the_exact_validators() {
    let (mut scene, rid, robot, group, mut q) = kitchen("base_hip_right_arm");
    let elbow = robot.dof_index("right_elbow").unwrap();
    q[elbow] = 1.2;
    scene.set_robot_configuration(rid, &q).unwrap();
    let palm = scene.link_world_pose(rid, "right_hand_palm").unwrap();
    let object = SceneObject::new(
        "carried",
        palm * Isometry3::translation(0.1, 0.0, 0.06),
        vec![Shape::at_origin(Geometry::cuboid(0.05, 0.05, 0.08))],
        0.2,
    );
    let id = scene.add_object(object).unwrap();
    scene.attach(id, rid, "right_hand_palm").unwrap();
    let offset = scene.attachment_of(id).unwrap().offset;
    let corners: Vec<_> =
        scene.object(id).unwrap().shapes.iter().flat_map(|s| s.aabb_corners().map(|p| offset * p)).collect();
    let palm_id = robot.link_id("right_hand_palm").unwrap();
    let bound = MotionBound::from_robot_with(&robot, &group, &[(palm_id, corners)]).unwrap();
    let world = Arc::new(CollisionWorld::new(&scene).unwrap());
    let checker = CollisionChecker::new(world, rid, robot.clone(), group.clone(), q.clone()).unwrap().with_bound(bound);
    let certifier = certifier_for(&scene, rid, &group, &q, &checker).unwrap();
    let limits = group.limits(&robot);
    let start = group.extract(&q);
    assert!(checker.is_valid(&start), "the carrying start state collides");
    let (certified, tried) = certified_segments_are_valid(&checker, &certifier, &limits, &start, 0.5, 0.3, 2);
    println!("carried object: {certified} of {tried} random segments certified");
    assert!(tried == 40 && certified >= tried / 2, "{certified} of {tried}");
}

/// Post-processing with the certifier gives exactly the exact procedure's paths (kitchen
/// scene 1, RRT-Connect paths of two seeds), and they pass every validator.
#[test]
fn certified_postprocessing_gives_the_exact_paths() {
    let instance: SceneInstance = (armar_standard_scene().generate)(0).unwrap();
    let limits = instance.group.limits(&instance.robot);
    let options = BenchmarkOptions::default();
    let mut planner = RrtConnect::default();
    for seed in 0..2 {
        let problem = instance.problem(&*instance.checker, Duration::from_secs(10), seed, 0.02);
        let path = planner.plan(&problem).unwrap().path;
        let so = postprocessing_options(&options, seed);
        let run = |certifier: Option<&dyn SegmentCertifier>| {
            let (repaired, _) = repair_with(&*instance.checker, certifier, &path, &limits, &so);
            shortcut_with(&*instance.checker, certifier, &repaired, &so)
        };
        let (exact, exact_stats) = run(None);
        let (fast, fast_stats) = run(instance.certifier.as_deref());
        assert_eq!(fast, exact, "seed {seed}");
        assert_eq!(fast_stats, exact_stats);
        assert!(exact_stats.accepted > 0);
        let v = validate_path(&*instance.checker, &fast, &options.validation);
        assert!(v.discrete && v.strict && v.continuous == Some(true), "{v:?}");
    }
}

/// Scenes the model does not cover and bad configurations are typed errors.
#[test]
fn unsupported_scenes_are_typed_errors() {
    let (mut scene, rid, robot, group, q) = kitchen("hip_right_arm");
    let world = CollisionWorld::new(&scene).unwrap();
    let bound = MotionBound::from_robot(&robot, &group).unwrap();
    let short = SphereCertifier::new(&scene, rid, &group, &q[..3], &bound, &world);
    assert!(matches!(short, Err(MotionError::DimensionMismatch { .. })), "{short:?}");
    let partial = MotionBound::new(&robot, &group, &[], &[]).unwrap();
    let missing = SphereCertifier::new(&scene, rid, &group, &q, &partial, &world);
    assert!(matches!(missing, Err(MotionError::InvalidParameter { name: "bound", .. })), "{missing:?}");
    // The exact refinement needs the checker the certifier was built for.
    let certifier = SphereCertifier::new(&scene, rid, &group, &q, &bound, &world).unwrap();
    let other_group = robot.group("base_hip_right_arm").unwrap().clone();
    let other = CollisionChecker::new(
        Arc::new(CollisionWorld::new(&scene).unwrap()),
        rid,
        robot.clone(),
        other_group,
        q.clone(),
    )
    .unwrap();
    let refined = certifier.with_exact(&other);
    assert!(matches!(refined, Err(MotionError::InvalidParameter { name: "checker", .. })), "{refined:?}");
    scene.add_robot("twin", robot.clone(), Isometry3::translation(4.0, 1.0, 0.0)).unwrap();
    scene.add_body(StaticBody::new("post", Isometry3::identity(), vec![])).unwrap();
    let world = CollisionWorld::new(&scene).unwrap();
    let two = SphereCertifier::new(&scene, rid, &group, &q, &bound, &world);
    assert!(matches!(two, Err(MotionError::InvalidParameter { name: "scene", .. })), "{two:?}");
}

/// The vertical speed bounds hold: on random straight motions of the humanoid with its mobile
/// base (Clean the Table's group), no corner of a link's collision shapes rises or sinks by
/// more than the bound; motions of the base alone (sliding and turning on the floor) give a
/// bound of 0, though every link moves.
#[test]
fn vertical_bounds_hold_on_random_motions() {
    let BaseKitchen { scene, rid, robot, group, q, checker, certifier } = base_kitchen();
    let bound = checker.motion_bound().unwrap();
    let base_pose = scene.robot(rid).unwrap().base_pose;
    let limits = group.limits(&robot);
    let base: Vec<usize> = ["base_x", "base_y", "base_yaw"]
        .iter()
        .map(|j| group.dofs().iter().position(|&d| d == robot.dof_index(j).unwrap()).unwrap())
        .collect();
    let corners: Vec<Vec<_>> = bound
        .links()
        .iter()
        .map(|l| robot.links()[l.0].collisions.iter().flat_map(|s| s.aabb_corners()).collect())
        .collect();
    let heights = |g: &[f64]| {
        let mut full = q.clone();
        group.insert(&mut full, g).unwrap();
        let mut poses = Vec::new();
        opengrasp_core::kinematics::forward_kinematics_into(&robot, &full, &mut poses);
        bound.links().iter().map(|l| base_pose * poses[l.0]).collect::<Vec<_>>()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut tighter, mut checked) = (0, 0);
    for k in 0..200 {
        let a: Vec<f64> = limits.iter().map(|(lo, hi)| rng.random_range(*lo..=*hi)).collect();
        let only_base = k % 4 == 0;
        let b: Vec<f64> =
            a.iter()
                .zip(&limits)
                .enumerate()
                .map(|(j, (v, (lo, hi)))| {
                    if only_base && !base.contains(&j) {
                        *v
                    } else {
                        (v + rng.random_range(-0.4..=0.4)).clamp(*lo, *hi)
                    }
                })
                .collect();
        let dq: Vec<f64> = a.iter().zip(&b).map(|(x, y)| y - x).collect();
        let (pa, pb) = (heights(&a), heights(&b));
        for (i, points) in corners.iter().enumerate() {
            let v = certifier.vertical_bound(i, &dq).unwrap();
            if only_base {
                assert_eq!(v, 0.0, "link {i}: base motions keep heights");
            }
            for p in points {
                let rise = ((pb[i] * p).z - (pa[i] * p).z).abs();
                assert!(rise <= v + 1e-9, "link {i}: rose {rise} > bound {v}");
                checked += 1;
            }
            if v < 0.5 * bound.bound(i, &dq) {
                tighter += 1;
            }
        }
    }
    println!("{checked} corner motions within the vertical bounds; {tighter} link bounds under half the speed bound");
    assert!(checked > 10_000 && tighter > 1000, "{checked} {tighter}");
    assert_eq!(certifier.vertical_bound(bound.links().len(), &vec![0.0; group.len()]), None);
    assert_eq!(certifier.vertical_bound(0, &[0.0]), None);
}

/// Long fast motions of the mobile base (so fast that the tolerance alone would not keep
/// the continuous validator within its query budget): post-processing with the certifier
/// gives exactly the exact procedure's paths, and certifies them (with the larger margin)
/// instead of running the exact continuous check on each.
#[test]
fn long_base_motions_are_certified_with_the_exact_paths() {
    let BaseKitchen { robot, group, q, checker, certifier, .. } = base_kitchen();
    let limits = group.limits(&robot);
    let bound = checker.motion_bound().unwrap().clone();
    let budget = ValidationOptions::default().ccd.tolerance * ValidationOptions::default().ccd.max_queries as f64;
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut path = vec![group.extract(&q)];
    let mut fast_segments = 0;
    while path.len() < 6 {
        let last = path.last().unwrap();
        // Base anywhere, arm and hip within ±0.4 rad of the last waypoint.
        let next: Vec<f64> =
            last.iter()
                .zip(&limits)
                .enumerate()
                .map(|(i, (v, (lo, hi)))| {
                    if i < 3 {
                        rng.random_range(*lo..=*hi)
                    } else {
                        (v + rng.random_range(-0.4..=0.4)).clamp(*lo, *hi)
                    }
                })
                .collect();
        if checker.is_valid(&next) {
            let dq: Vec<f64> = last.iter().zip(&next).map(|(a, b)| b - a).collect();
            let fastest = (0..bound.links().len()).map(|i| bound.bound(i, &dq)).fold(0.0, f64::max);
            fast_segments += usize::from(fastest > budget);
            path.push(next);
        }
    }
    assert!(fast_segments >= 2, "{fast_segments} fast segments");
    let options = BenchmarkOptions::default();
    let so = postprocessing_options(&options, 0);
    let run = |certifier: Option<&dyn SegmentCertifier>| {
        let counting = CountingChecker::new(&checker);
        let (repaired, rs) = repair_with(&counting, certifier, &path, &limits, &so);
        let (smoothed, ss) = shortcut_with(&counting, certifier, &repaired, &so);
        (smoothed, rs, ss, counting.distance_queries())
    };
    let (exact, exact_rs, exact_ss, exact_queries) = run(None);
    let (fast, fast_rs, fast_ss, fast_queries) = run(Some(&certifier));
    assert_eq!(fast, exact);
    assert_eq!((fast_rs, fast_ss), (exact_rs, exact_ss));
    println!("exact distance queries: {exact_queries} exact, {fast_queries} certified");
    assert!(fast_queries * 10 < exact_queries, "{fast_queries} vs {exact_queries}");
}

/// Kitchen scene 1 (it carries a certifier) and its group's limits.
fn scene1() -> (SceneInstance, Vec<(f64, f64)>) {
    let instance = (armar_standard_scene().generate)(0).unwrap();
    let limits = instance.group.limits(&instance.robot);
    (instance, limits)
}

/// A random state within `spread` of `centre` in every joint, clamped to `limits`.
fn around(centre: &[f64], limits: &[(f64, f64)], spread: f64, rng: &mut ChaCha8Rng) -> Vec<f64> {
    centre.iter().zip(limits).map(|(v, (lo, hi))| (v + rng.random_range(-spread..=spread)).clamp(*lo, *hi)).collect()
}

/// A certificate holds for every piece of its segment (post-processing accepts the pieces of
/// certified segments without certifying them again): random pieces of certified kitchen
/// segments pass every exact validator.
#[test]
fn pieces_of_certified_segments_pass_the_exact_validators() {
    let (instance, limits) = scene1();
    let (checker, certifier) = (&*instance.checker, instance.certifier.as_deref().unwrap());
    let bound = checker.motion_bound().unwrap();
    let options = ValidationOptions::default();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let draw = |rng: &mut ChaCha8Rng, c: &[f64], s: f64| -> Vec<f64> {
        c.iter().zip(&limits).map(|(v, (lo, hi))| (v + rng.random_range(-s..=s)).clamp(*lo, *hi)).collect()
    };
    let lerp = |a: &[f64], b: &[f64], t: f64| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x + t * (y - x)).collect() };
    let (mut pieces, mut draws) = (0, 0);
    while pieces < 24 && draws < 2000 {
        draws += 1;
        let a = draw(&mut rng, &instance.start, 1.2);
        let b = draw(&mut rng, &a, 0.6);
        if !checker.is_valid(&a)
            || certifier.certify(&a, &b, bound, options.ccd.tolerance + 1e-6, 1000) != Certificate::Free
        {
            continue;
        }
        let (s, t): (f64, f64) = (rng.random(), rng.random());
        let piece = [lerp(&a, &b, s.min(t)), lerp(&a, &b, s.max(t))];
        let v = validate_path(checker, &piece, &options);
        assert!(v.discrete && v.strict && v.continuous == Some(true), "{piece:?}: {v:?}");
        pieces += 1;
    }
    println!("{pieces} pieces of certified segments in {draws} draws");
    assert_eq!(pieces, 24, "{draws} draws");
}

/// The certifier tells a proof that ran out of steps (`exhausted`, still advancing) from one
/// stuck at the margin: a certified segment given one step is exhausted at a `t` in (0, 1);
/// random long segments through the kitchen get stuck (not exhausted) before their end.
#[test]
fn unknown_certificates_tell_exhausted_from_stuck() {
    let (instance, limits) = scene1();
    let (checker, certifier) = (&*instance.checker, instance.certifier.as_deref().unwrap());
    let bound = checker.motion_bound().unwrap();
    let margin = ValidationOptions::default().ccd.tolerance + 1e-6;
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut exhausted, mut stuck) = (0, 0);
    for _ in 0..400 {
        let a = around(&instance.start, &limits, 1.2, &mut rng);
        let b: Vec<f64> = limits.iter().map(|(lo, hi)| rng.random_range(*lo..=*hi)).collect();
        if !checker.is_valid(&a) {
            continue;
        }
        match certifier.certify(&a, &b, bound, margin, 1000) {
            Certificate::Free => match certifier.certify(&a, &b, bound, margin, 1) {
                Certificate::Unknown { near: Some(t), exhausted: true } => {
                    assert!(t > 0.0 && t < 1.0, "t = {t}");
                    exhausted += 1;
                }
                // One step may prove a short motion far from everything.
                c => assert_eq!(c, Certificate::Free),
            },
            Certificate::Unknown { near: Some(t), exhausted: false } => {
                assert!((0.0..1.0).contains(&t), "t = {t}");
                // Stuck: a bound fell to the margin, so the state there is near a contact.
                stuck += 1;
            }
            Certificate::Unknown { .. } => {}
        }
    }
    println!("{exhausted} exhausted, {stuck} stuck");
    assert!(exhausted >= 100 && stuck >= 20, "{exhausted} exhausted, {stuck} stuck");
}

/// The certifier keeps its buffers per thread between calls: certificates of two certifiers
/// of different sizes (scene 1's hip and arm, Clean the Table's base, hip and arm), asked in
/// turn on one thread, are those each gives alone on a fresh thread.
#[test]
fn interleaved_certifiers_give_the_certificates_of_fresh_ones() {
    let (arm, base) = (checked_kitchen("hip_right_arm"), base_kitchen());
    let margin = ValidationOptions::default().ccd.tolerance + 1e-6;
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let limits = [arm.group.limits(&arm.robot), base.group.limits(&base.robot)];
    let centres = [arm.group.extract(&arm.q), base.group.extract(&base.q)];
    assert_ne!(limits[0].len(), limits[1].len());
    let draw = |rng: &mut ChaCha8Rng, k: usize, centre: &[f64], s: f64| -> Vec<f64> {
        centre.iter().zip(&limits[k]).map(|(v, (lo, hi))| (v + rng.random_range(-s..=s)).clamp(*lo, *hi)).collect()
    };
    let motions: Vec<(usize, Vec<f64>, Vec<f64>)> = (0..40)
        .map(|i| {
            let k = i % 2;
            let a = draw(&mut rng, k, &centres[k], 0.8);
            (k, draw(&mut rng, k, &a, 0.5), a)
        })
        .collect();
    let kitchens = [&arm, &base];
    let certify = |(k, b, a): &(usize, Vec<f64>, Vec<f64>)| {
        let kitchen = kitchens[*k];
        kitchen.certifier.certify(a, b, kitchen.checker.motion_bound().unwrap(), margin, 300)
    };
    let interleaved: Vec<Certificate> = motions.iter().map(certify).collect();
    let fresh: Vec<Certificate> =
        std::thread::scope(|s| motions.iter().map(|m| s.spawn(|| certify(m)).join().unwrap()).collect());
    assert_eq!(interleaved, fresh);
    let free = interleaved.iter().filter(|c| **c == Certificate::Free).count();
    println!("{free} of {} free", interleaved.len());
    assert!(free >= 5 && free < interleaved.len(), "{free} free");
}

/// A certifier with only `certify`: its `certify_staged` is the trait's default, which
/// restarts the proof for the second stage.
struct Restarting<'a>(&'a dyn SegmentCertifier);

impl SegmentCertifier for Restarting<'_> {
    fn certify(&self, a: &[f64], b: &[f64], bound: &MotionBound, margin: f64, max_steps: usize) -> Certificate {
        self.0.certify(a, b, bound, margin, max_steps)
    }
}

/// The sphere model resumes a staged proof where its first stage stopped, with the answers of
/// the restarting default and of `certify` with the whole budget: random kitchen segments
/// with first budgets of 5 and 20 steps, the second stage allowed or not (`None` exactly
/// when the first stage runs out while still advancing, and then only).
#[test]
fn staged_certificates_resume_to_the_whole_budget_answer() {
    let (instance, limits) = scene1();
    let (checker, certifier) = (&*instance.checker, instance.certifier.as_deref().unwrap());
    let bound = checker.motion_bound().unwrap();
    let margin = ValidationOptions::default().ccd.tolerance + 1e-6;
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let (mut resumed, mut resumed_free, mut resumed_stuck) = (0, 0, 0);
    for k in 0..120 {
        let a = around(&instance.start, &limits, 1.2, &mut rng);
        let b = around(&a, &limits, 0.6, &mut rng);
        let first = if k % 2 == 0 { 5 } else { 20 };
        let (short, whole) =
            (certifier.certify(&a, &b, bound, margin, first), certifier.certify(&a, &b, bound, margin, 1000));
        let exhausted = matches!(short, Certificate::Unknown { exhausted: true, .. });
        for allow in [true, false] {
            let mut asked = 0;
            let mut proceed = || {
                asked += 1;
                allow
            };
            let staged = certifier.certify_staged(&a, &b, bound, margin, (first, 1000), &mut proceed);
            let default = Restarting(certifier).certify_staged(&a, &b, bound, margin, (first, 1000), &mut || allow);
            assert_eq!(staged, default, "{a:?} -> {b:?}");
            assert_eq!(asked, usize::from(exhausted));
            let expected = match (exhausted, allow) {
                (false, _) => Some(short),
                (true, true) => Some(whole),
                (true, false) => None,
            };
            assert_eq!(staged, expected, "{a:?} -> {b:?}, first {first}, allowed {allow}");
        }
        if exhausted {
            resumed += 1;
            resumed_free += usize::from(whole == Certificate::Free);
            resumed_stuck += usize::from(matches!(whole, Certificate::Unknown { exhausted: false, .. }));
        }
    }
    println!("{resumed} resumed: {resumed_free} free, {resumed_stuck} stuck");
    assert!(resumed >= 30 && resumed_free >= 10 && resumed_stuck >= 5, "{resumed} {resumed_free} {resumed_stuck}");
}
