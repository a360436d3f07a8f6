//! The physics hold check next to the static torque-limited hold test, grasp by grasp, for
//! both paper hands over the paper's eight objects: where the simulator drops a grasp, is it
//! because the actuators cannot hold it at all?
//!
//! ```text
//! cargo run --release -p opengrasp-grasp --example physics_static -- [per_cell] [hand] [trace]
//! ```
//! Per object and planner the first 128 candidates (spread evenly) are evaluated and
//! `per_cell` (default 5) of the force-closure palm grasps, spread evenly, are checked both
//! ways. Each line: physics result per gravity direction (`H`eld, `S`lipped, `D`ropped), the
//! static load factor per direction (multiples of the weight the grasp can balance), and for
//! the weakest direction the saturated actuators. With `trace`, grasps the static test cannot
//! hold also print the optimal contact forces of their weakest direction.

use opengrasp_assets::hands;
use opengrasp_grasp::evaluator::{physics_check, static_hold, HoldResult, PhysicsCheckOptions, StaticHoldOptions};

mod common;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let per_cell: usize = args.first().map_or(Ok(5), |a| a.parse())?;
    let only = args.get(1).cloned().unwrap_or_default();
    let trace = args.iter().any(|a| a == "trace");
    let (physics, statics) = (PhysicsCheckOptions::default(), StaticHoldOptions::default());
    for (name, hand) in [("barrett", hands::barrett()), ("armar3", hands::armar3_hand())] {
        if !only.is_empty() && only != "all" && only != name {
            continue;
        }
        let robot = hand.robot();
        let joint = |d: usize| robot.joint(robot.dof_joint(d)).name.clone();
        // [physics held][static holdable] counts, and held / slipped / dropped.
        let mut table = [[0usize; 2]; 2];
        let mut hsd = [0usize; 3];
        for common::ObjectSample { object, planners } in common::paper_sample(&hand, per_cell)? {
            for sample in &planners {
                for (j, g) in sample.grasps.iter().enumerate() {
                    let p = physics_check(&hand, &object, g, &physics)?;
                    let s = static_hold(&hand, &object, g, &statics)?;
                    table[usize::from(p.held())][usize::from(s.holdable())] += 1;
                    hsd[match p.result() {
                        Some(HoldResult::Held) | None => 0,
                        Some(HoldResult::Slipped) => 1,
                        Some(HoldResult::Dropped) => 2,
                    }] += 1;
                    let codes: String = p
                        .results
                        .iter()
                        .map(|r| match r {
                            HoldResult::Held => 'H',
                            HoldResult::Slipped => 'S',
                            HoldResult::Dropped => 'D',
                        })
                        .collect();
                    let loads: Vec<String> = s.directions.iter().map(|d| format!("{:.2}", d.load_factor)).collect();
                    let weakest = s.weakest().expect("six directions");
                    let saturated: Vec<String> = weakest.saturated.iter().map(|&d| joint(d)).collect();
                    println!(
                        "{name:8} {:17} {:15} #{j} physics {codes} static [{}] weakest {:?}: {:.2} saturated {saturated:?}",
                        object.name,
                        sample.planner,
                        loads.join(" "),
                        weakest.direction.map(|v| v.round()).as_slice(),
                        weakest.load_factor,
                    );
                    if trace && !s.holdable() {
                        for (c, f) in g.contacts.iter().zip(&weakest.contact_forces) {
                            let n = f.dot(&c.contact.normal);
                            let link = &robot.links()[c.link].name;
                            println!(
                                "    {link:18} normal {n:7.2} N tangential {:6.2} N (μ·N {:6.2})",
                                (f - c.contact.normal.into_inner() * n).norm(),
                                object.friction * n
                            );
                        }
                        for a in &weakest.actuators {
                            println!("    actuator {:22} {:7.3} of {:.3} N·m", joint(a.dof), a.torque, a.limit);
                        }
                    }
                }
            }
        }
        let n: usize = hsd.iter().sum();
        println!(
            "{name}: physics held/slipped/dropped {}/{}/{} of {n}; static holdable {}; agree {} \
             (both hold {}, both not {}, static only {}, physics only {})",
            hsd[0],
            hsd[1],
            hsd[2],
            table[0][1] + table[1][1],
            table[1][1] + table[0][0],
            table[1][1],
            table[0][0],
            table[0][1],
            table[1][0]
        );
    }
    Ok(())
}
