//! Every benchmark hand (ARMAR-III, Barrett, SDH) gets palm-contact grasps on every paper
//! object from both reference planners (the paper counts only those): the hands' open
//! preshapes leave room for the palm.

use opengrasp_assets::{hands, objects};
use opengrasp_grasp::benchmark::{run_grasp_benchmark, GraspBenchmarkConfig};

/// The paper's eight objects: the stock objects without the measuring cup.
const OBJECTS: &[&str] = objects::NAMES.split_at(8).0;

#[test]
fn every_hand_and_object_has_palm_contact_grasps_from_both_planners() {
    let config = GraspBenchmarkConfig {
        objects: OBJECTS.iter().map(|o| objects::by_name(o).unwrap()).collect(),
        hands: vec![
            hands::armar3_hand().with_name("armar3"),
            hands::barrett().with_name("barrett"),
            hands::sdh().with_name("sdh"),
        ],
        max_candidates: Some(64),
        ..Default::default()
    };
    let results = run_grasp_benchmark(&config).unwrap();
    assert_eq!(results.cells.len(), 3 * 8 * 2);
    for c in &results.cells {
        println!(
            "{:8} {:18} {:16} palm {:3} fc-palm {:3}",
            c.hand, c.object, c.planner, c.palm_contact, c.force_closure_palm
        );
    }
    // No gap: the SDH's open preshapes lay its proximal phalanges flat at their −90° limit,
    // clear of the salt box's 60 mm faces (at 83° their corners touched first and that cell
    // had no palm-contact grasp).
    let missing: Vec<String> = results
        .cells
        .iter()
        .filter(|c| c.palm_contact == 0)
        .map(|c| format!("{} / {} / {}", c.hand, c.object, c.planner))
        .collect();
    assert!(missing.is_empty(), "no palm-contact grasp: {missing:?}");
    // Every hand closes in force closure with the palm touching on most objects.
    for hand in ["armar3", "barrett", "sdh"] {
        let with_fc = results.cells.iter().filter(|c| c.hand == hand && c.force_closure_palm > 0).count();
        assert!(with_fc >= 12, "{hand}: force-closure palm grasps in only {with_fc} of 16 cells");
    }
}
