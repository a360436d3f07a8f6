//! Tables I and II: grasp planners per hand.

use super::{abbreviation, pct, Table};
use crate::paper::{PAPER_OBJECTS, PAPER_RESULTS};
use crate::results::GraspSection;

/// Tables I/II: one table per hand (see the [module docs](super)).
pub fn grasp_tables(g: &GraspSection) -> Vec<Table> {
    let max_candidates = g.max_candidates;
    let mut hands: Vec<&str> = g.hands.iter().map(String::as_str).collect();
    let mut objects: Vec<&str> = g.objects.iter().map(String::as_str).collect();
    let mut planners: Vec<&str> = g.planners.iter().map(|p| p.name.as_str()).collect();
    for r in &g.cells {
        for (list, v) in [(&mut hands, &r.cell.hand), (&mut objects, &r.cell.object), (&mut planners, &r.cell.planner)]
        {
            if !list.contains(&v.as_str()) {
                list.push(v);
            }
        }
    }
    let mut tables = Vec::new();
    for hand in hands {
        let cells: Vec<_> = g.cells.iter().filter(|r| r.cell.hand == hand).map(|r| &r.cell).collect();
        if cells.is_empty() {
            continue;
        }
        let hand_planners: Vec<&str> =
            planners.iter().copied().filter(|p| cells.iter().any(|c| c.planner == *p)).collect();
        let with_paper = |p: &str| PAPER_RESULTS.iter().any(|r| r.1 == hand && r.2 == p);
        // A physics column (held / tested in the rapier hold check) when the check ran.
        let with_physics = cells.iter().any(|c| c.physics_tested > 0);
        let mut headers = vec!["object".to_string()];
        for p in &hand_planners {
            let a = abbreviation(p);
            headers.push(format!("{a} n"));
            headers.push(format!("{a} FC%"));
            headers.push(format!("{a} eps"));
            if with_physics {
                headers.push(format!("{a} held"));
                headers.push(format!("{a} stat"));
            }
            if with_paper(p) {
                headers.push(format!("{a} p.n"));
                headers.push(format!("{a} p.FC%"));
            }
        }
        let mut rows = Vec::new();
        for object in objects.iter().copied().filter(|o| cells.iter().any(|c| c.object == *o)) {
            let label = PAPER_OBJECTS.iter().find(|(_, n)| *n == object).map_or(object, |(l, _)| l);
            let mut row = vec![label.to_string()];
            for p in &hand_planners {
                match cells.iter().find(|c| c.object == object && c.planner == *p) {
                    Some(c) => {
                        row.push(c.palm_contact.to_string());
                        row.push(pct(c.force_closure_palm, c.palm_contact));
                        row.push(epsilon(c.mean_epsilon, c.force_closure_palm));
                        if with_physics {
                            row.push(held(c.physics_held, c.physics_tested));
                            row.push(held(c.static_holdable, c.physics_tested));
                        }
                    }
                    None => row.extend(std::iter::repeat_n("-".to_string(), 3 + 2 * usize::from(with_physics))),
                }
                if with_paper(p) {
                    match PAPER_RESULTS.iter().find(|r| r.0 == object && r.1 == hand && r.2 == *p) {
                        Some(r) => {
                            row.push(r.3.to_string());
                            row.push(format!("{:.1}", r.4));
                        }
                        None => row.extend(std::iter::repeat_n("-".to_string(), 2)),
                    }
                }
            }
            rows.push(row);
        }
        let mut total = vec!["total".to_string()];
        for p in &hand_planners {
            let pc: Vec<_> = cells.iter().filter(|c| c.planner == *p).collect();
            let palm: usize = pc.iter().map(|c| c.palm_contact).sum();
            let fc: usize = pc.iter().map(|c| c.force_closure_palm).sum();
            // Cell epsilons are means over their force-closure palm-contact grasps.
            let eps = if fc == 0 {
                0.0
            } else {
                pc.iter().map(|c| c.mean_epsilon * c.force_closure_palm as f64).sum::<f64>() / fc as f64
            };
            total.extend([palm.to_string(), pct(fc, palm), epsilon(eps, fc)]);
            if with_physics {
                let tested: usize = pc.iter().map(|c| c.physics_tested).sum();
                let n_held: usize = pc.iter().map(|c| c.physics_held).sum();
                let n_static: usize = pc.iter().map(|c| c.static_holdable).sum();
                total.push(held(n_held, tested));
                total.push(held(n_static, tested));
            }
            if with_paper(p) {
                let pr: Vec<_> = PAPER_RESULTS
                    .iter()
                    .filter(|r| r.1 == hand && r.2 == *p && pc.iter().any(|c| c.object == r.0))
                    .collect();
                let n: usize = pr.iter().map(|r| r.3).sum();
                let f: f64 = pr.iter().map(|r| r.3 as f64 * r.4 / 100.0).sum();
                total.push(n.to_string());
                total.push(if n == 0 { "-".into() } else { format!("{:.1}", 100.0 * f / n as f64) });
            }
        }
        rows.push(total);
        let which = match hand {
            "armar3" => "Table I",
            "barrett" => "Table II",
            _ => "grasp table",
        };
        let mut legend = vec![
            "n: candidates tested (evaluated grasps whose palm touches the object, the paper's count); \
             FC%: force-closure grasps among them; eps: their mean Ferrari-Canny epsilon (L1, torques / object radius)."
                .to_string(),
        ];
        if with_physics {
            legend.push("held: of the force-closure palm grasps simulated in rapier, those that kept the object in all six gravity directions (held/simulated); the fingers act as the hand's actuators do: position servos pressing past the closed configuration, or, for compliant actuators such as the ARMAR-III hand's fluidic ones, balanced grip torques through joint springs.".into());
            legend.push(
                "stat: of the same grasps, those whose contacts can balance the object's weight in all six directions with \
                 forces inside the friction cones and every actuator within its effort limit (static torque-limited test, \
                 rigid bodies; a necessary condition for holding)."
                    .into(),
            );
            legend.push(failures_explained(&cells));
            let diverged: usize = cells.iter().map(|c| c.physics_diverged).sum();
            if diverged > 0 {
                legend.push(format!(
                    "{diverged} of the simulations diverged (a body beyond 1e6 m or 1e6 m/s): counted as simulated and not held."
                ));
            }
        }
        if hand_planners.iter().any(|p| with_paper(p)) {
            legend.push("p.n, p.FC%: the OpenGRASP paper's n and FC% for the same hand, object and planner.".into());
        }
        let abbreviated: Vec<String> = hand_planners
            .iter()
            .filter(|p| abbreviation(p) != **p)
            .map(|p| format!("{} = {p}", abbreviation(p)))
            .collect();
        if !abbreviated.is_empty() {
            legend.push(format!("Planners: {}.", abbreviated.join(", ")));
        }
        if let Some(max) = max_candidates {
            legend.push(format!(
                "At most {max} candidates evaluated per cell (an even stride over each planner's list); the paper evaluated all."
            ));
        }
        legend.push(
            "-: no data (no palm-contact grasp, no force-closure grasp for eps, none simulated for held, or no paper \
             figure); 0.0 is a measured 0 %."
                .into(),
        );
        tables.push(Table { title: format!("{which}: grasp planners, hand {hand}"), headers, rows, legend });
    }
    tables
}

/// Mean epsilon of `n` force-closure grasps, `-` (no data) when there are none.
fn epsilon(mean: f64, n: usize) -> String {
    if n == 0 {
        "-".into()
    } else {
        format!("{mean:.4}")
    }
}

/// `held/simulated`, `-` (no data) when nothing was simulated.
fn held(held: usize, tested: usize) -> String {
    if tested == 0 {
        "-".into()
    } else {
        format!("{held}/{tested}")
    }
}

/// The legend sentence that splits one hand's physics failures (simulations that finished and
/// did not hold) into those explained by the hand's actuation (the grip alone, gravity off,
/// moved the object out of the hold tolerance) and the rest.
fn failures_explained(cells: &[&opengrasp_grasp::benchmark::CellResult]) -> String {
    let sum = |f: fn(&opengrasp_grasp::benchmark::CellResult) -> usize| cells.iter().map(|c| f(c)).sum::<usize>();
    let failed = sum(|c| c.physics_tested.saturating_sub(c.physics_held + c.physics_diverged));
    let escaped = sum(|c| c.physics_grip_escaped);
    format!(
        "Of the {failed} simulated grasps not held, {escaped} are explained by the hand's actuation: with gravity off \
         the squeeze alone moved the object beyond the hold tolerance (by default 2 cm, 20°), its traced contact forces at the \
         release pushing it out; {} kept the grasp without gravity and lost it under gravity (unexplained by the grip).",
        failed.saturating_sub(escaped)
    )
}
