//! Self-collision pairs of the sphere model from an SRDF's `<disable_collisions>`
//! ([`SelfCollisionPairs::Robot`]), against the default rule and the exact checker.

use std::collections::BTreeSet;
use std::sync::Arc;

use nalgebra::Isometry3;
use opengrasp_core::collision::CollisionWorld;
use opengrasp_core::model::{samples, JointGroup, LinkId, Robot};
use opengrasp_core::scene::Scene;
use opengrasp_core::srdf::Srdf;
use opengrasp_motion::validity::{CollisionChecker, SelfCollisionPairs, SphereWorld, StateValidityChecker};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

type Pairs = BTreeSet<(LinkId, LinkId)>;

/// The arm with `disabled` applied from an SRDF document.
fn with_srdf(robot: &Robot, disabled: &Pairs) -> Robot {
    let name = |l: LinkId| robot.links()[l.0].name.clone();
    let mut xml = String::from("<robot name=\"seven_dof_arm\">\n");
    for &(a, b) in disabled {
        xml += &format!("  <disable_collisions link1=\"{}\" link2=\"{}\" reason=\"Default\"/>\n", name(a), name(b));
    }
    xml += "</robot>\n";
    let mut out = robot.clone();
    let report = Srdf::parse(&xml).unwrap().apply(&mut out).unwrap();
    assert_eq!(report.allowed_pairs, disabled.len());
    out
}

/// Links with collision geometry, in pairs, minus the pairs `robot` allows.
fn candidates(robot: &Robot) -> Pairs {
    let links: Vec<LinkId> =
        (0..robot.links().len()).map(LinkId).filter(|l| !robot.links()[l.0].collisions.is_empty()).collect();
    let mut out = Pairs::new();
    for (i, &a) in links.iter().enumerate() {
        for &b in &links[i + 1..] {
            if !robot.is_collision_allowed(a, b) {
                out.insert((a, b));
            }
        }
    }
    out
}

fn world(robot: Robot, pairs: SelfCollisionPairs) -> SphereWorld {
    let robot = Arc::new(robot);
    let group = JointGroup::all(&robot, "arm").unwrap();
    let q_full = vec![0.0; robot.dof()];
    SphereWorld::new(robot, group, q_full, Isometry3::identity(), Vec::new()).unwrap().with_self_collision(pairs)
}

fn random_states(n: usize, seed: u64, robot: &Robot) -> Vec<Vec<f64>> {
    let group = JointGroup::all(robot, "arm").unwrap();
    let limits = group.limits(robot);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n).map(|_| limits.iter().map(|&(lo, hi)| rng.random_range(lo..=hi)).collect()).collect()
}

/// An SRDF disabling the pairs the default rule drops (overlapping at the reference
/// configuration, as MoveIt's "Default" reason) gives the same pairs and verdicts.
#[test]
fn srdf_of_the_default_pairs_reproduces_the_default_rule() {
    let bare = samples::seven_dof_arm().unwrap();
    let default = world(bare.clone(), SelfCollisionPairs::default());
    let checked: Pairs = default.self_collision_pairs().into_iter().collect();
    let all = candidates(&bare);
    let dropped: Pairs = all.difference(&checked).copied().collect();
    assert!(!dropped.is_empty() && !checked.is_empty(), "{} checked, {} dropped", checked.len(), dropped.len());

    // Without an SRDF, the `Robot` rule checks every non-adjacent pair.
    let every = world(bare.clone(), SelfCollisionPairs::Robot);
    assert_eq!(every.self_collision_pairs().into_iter().collect::<Pairs>(), all);
    assert!(!every.is_valid(&[0.0; 7]), "pairs overlapping at the reference make it invalid");

    let srdf = world(with_srdf(&bare, &dropped), SelfCollisionPairs::Robot);
    assert_eq!(srdf.self_collision_pairs().into_iter().collect::<Pairs>(), checked);
    let mut invalid = 0;
    for q in random_states(300, 3, &bare) {
        assert_eq!(srdf.is_valid(&q), default.is_valid(&q), "{q:?}");
        invalid += usize::from(!default.is_valid(&q));
    }
    assert!(invalid > 0, "some random states are in self-collision");
}

/// A state is in self-collision iff one of its checked pairs is, and disabling exactly the
/// colliding pairs in the SRDF makes it valid.
#[test]
fn srdf_disabled_pairs_are_exactly_the_ones_skipped() {
    let bare = samples::seven_dof_arm().unwrap();
    let all = candidates(&bare);
    let checked: Pairs =
        world(bare.clone(), SelfCollisionPairs::default()).self_collision_pairs().into_iter().collect();
    let base = with_srdf(&bare, &all.difference(&checked).copied().collect());
    let full = world(base.clone(), SelfCollisionPairs::Robot);
    // One world per checked pair, checking only that pair.
    let single: Vec<((LinkId, LinkId), SphereWorld)> = checked
        .iter()
        .map(|&p| {
            let others: Pairs = all.iter().copied().filter(|&o| o != p).collect();
            let w = world(with_srdf(&bare, &others), SelfCollisionPairs::Robot);
            assert_eq!(w.self_collision_pairs(), vec![p]);
            (p, w)
        })
        .collect();
    let mut tested = 0;
    for q in random_states(30_000, 5, &bare) {
        let colliding: Pairs = single.iter().filter(|(_, w)| !w.is_valid(&q)).map(|(p, _)| *p).collect();
        assert_eq!(full.is_valid(&q), colliding.is_empty(), "{q:?}");
        if !colliding.is_empty() {
            let relaxed = world(with_srdf(&base, &colliding), SelfCollisionPairs::Robot);
            assert!(relaxed.is_valid(&q), "{q:?} still invalid without {colliding:?}");
            tested += 1;
        }
    }
    assert!(tested >= 5, "only {tested} states in self-collision");
}

/// The exact checker uses the same SRDF matrix, and the sphere covers contain the links: a
/// state the sphere model accepts is accepted by the exact checker.
#[test]
fn sphere_model_with_srdf_pairs_is_conservative_against_the_exact_checker() {
    let bare = samples::seven_dof_arm().unwrap();
    let checked: Pairs =
        world(bare.clone(), SelfCollisionPairs::default()).self_collision_pairs().into_iter().collect();
    let robot = Arc::new(with_srdf(&bare, &candidates(&bare).difference(&checked).copied().collect()));
    let spheres = world((*robot).clone(), SelfCollisionPairs::Robot);
    let mut scene = Scene::new("self-collision only");
    let arm = scene.add_robot("arm", robot.clone(), Isometry3::identity()).unwrap();
    let group = JointGroup::all(&robot, "arm").unwrap();
    let exact = CollisionChecker::new(
        Arc::new(CollisionWorld::new(&scene).unwrap()),
        arm,
        robot.clone(),
        group,
        vec![0.0; robot.dof()],
    )
    .unwrap();
    let (mut accepted, mut rejected_by_exact) = (0, 0);
    for q in random_states(3000, 9, &robot) {
        if spheres.is_valid(&q) {
            accepted += 1;
            assert!(exact.is_valid(&q), "{q:?}: spheres accept, exact geometry collides");
        } else if !exact.is_valid(&q) {
            rejected_by_exact += 1;
        }
    }
    assert!(accepted > 100 && rejected_by_exact > 0, "{accepted} accepted, {rejected_by_exact} rejected by both");
}
