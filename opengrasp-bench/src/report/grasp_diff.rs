//! Where our grasp cells differ from the paper's, with the reasons measured in the records.

use super::{abbreviation, pct, Table};
use crate::paper::{PAPER_OBJECTS, PAPER_RESULTS};
use crate::results::GraspSection;
use opengrasp_grasp::benchmark::CellResult;

/// Differences of FC% (percentage points) up to this count as agreement.
pub const AGREEMENT_PP: f64 = 15.0;

/// One table comparing every cell that has a paper figure with the paper, and saying from the
/// records why they differ: the evaluation cap, the candidate count, the palm-contact rule
/// (FC% of all closed grasps beside FC% of the palm-contact ones) and, when neither explains
/// the gap, the contact model (where the hand touches, friction and the force-closure test).
/// A legend line per hand compares the planner ranking with the paper's.
/// Empty when no cell has a paper figure.
pub fn grasp_differences(g: &GraspSection) -> Vec<Table> {
    let headers = ["cell", "n", "p.n", "FC%", "p.FC%", "diff", "FC% all", "kept %", "reason"];
    let mut rows = Vec::new();
    let mut legend = vec![
        "cell: hand / object / planner; n, FC%: ours (palm-contact grasps, force closure among them); p.n, p.FC%: the \
         paper's; diff: FC% minus p.FC% (percentage points); FC% all: force closure among all grasps whose fingers \
         closed on the object, without the palm-contact rule; kept %: share of those closed grasps the palm-contact \
         rule keeps; reason: what the records show — agrees: within 15 pp; cap e/g: e of the g generated candidates \
         evaluated; n Rx: our n is R times the paper's; palm rule: FC% all is nearer the paper's figure, so the \
         palm-contact rule makes most of the gap; model: neither explains it, so the contact model does (where the \
         fingers land, friction cones, the FC test); no palm grasp: none of the closed grasps touches the palm."
            .to_string(),
    ];
    let mut hands: Vec<&str> = Vec::new();
    for r in &g.cells {
        let c = &r.cell;
        let Some(p) = PAPER_RESULTS.iter().find(|p| p.0 == c.object && p.1 == c.hand && p.2 == c.planner) else {
            continue;
        };
        if !hands.contains(&c.hand.as_str()) {
            hands.push(&c.hand);
        }
        let label = PAPER_OBJECTS.iter().find(|(_, n)| *n == c.object).map_or(c.object.as_str(), |(l, _)| l);
        let ours = (c.palm_contact > 0).then(|| 100.0 * c.force_closure_palm as f64 / c.palm_contact as f64);
        rows.push(vec![
            format!("{} / {label} / {}", c.hand, abbreviation(&c.planner)),
            c.palm_contact.to_string(),
            p.3.to_string(),
            pct(c.force_closure_palm, c.palm_contact),
            format!("{:.1}", p.4),
            ours.map_or("-".into(), |o| format!("{:+.1}", o - p.4)),
            pct(c.force_closure, c.closed),
            pct(c.palm_contact, c.closed),
            reason(c, p.3, p.4),
        ]);
    }
    if rows.is_empty() {
        return Vec::new();
    }
    for hand in hands {
        legend.push(ranking(g, hand));
    }
    if let Some(max) = g.max_candidates {
        legend.push(format!("Evaluation capped at {max} candidates per cell: n counts only the evaluated ones."));
    }
    vec![Table {
        title: "Differences from the paper (Tables I/II)".into(),
        headers: headers.map(String::from).to_vec(),
        rows,
        legend,
    }]
}

/// The measured reasons a cell differs from the paper's `(paper_n, paper_fc)`.
fn reason(c: &CellResult, paper_n: usize, paper_fc: f64) -> String {
    if c.palm_contact == 0 {
        return if c.closed == 0 { "none closed".into() } else { format!("no palm grasp of {} closed", c.closed) };
    }
    let ours = 100.0 * c.force_closure_palm as f64 / c.palm_contact as f64;
    let gap = (ours - paper_fc).abs();
    let mut why = Vec::new();
    if c.evaluated < c.generated {
        why.push(format!("cap {}/{}", c.evaluated, c.generated));
    }
    let ratio = c.palm_contact as f64 / paper_n as f64;
    if !(0.5..=2.0).contains(&ratio) {
        why.push(format!("n {ratio:.2}x"));
    }
    if gap <= AGREEMENT_PP {
        return if why.is_empty() { "agrees".into() } else { format!("agrees ({})", why.join("; ")) };
    }
    let all = if c.closed == 0 { 0.0 } else { 100.0 * c.force_closure as f64 / c.closed as f64 };
    if (all - paper_fc).abs() + 5.0 < gap {
        why.push(format!("palm rule ({all:.1} % without)"));
    } else {
        why.push(if ours > paper_fc { "model: more FC".into() } else { "model: less FC".into() });
    }
    why.join("; ")
}

/// A planner's totals over the paper's objects: name, our n and force-closure count, the
/// paper's n and force-closure count.
type Totals<'a> = (&'a str, f64, f64, f64, f64);

/// Whether the planner ranking by total FC% over the paper's objects matches the paper's.
fn ranking(g: &GraspSection, hand: &str) -> String {
    // Per planner: (name, our n, our FC, paper n, paper FC).
    let mut totals: Vec<Totals<'_>> = Vec::new();
    for r in g.cells.iter().filter(|r| r.cell.hand == hand) {
        let c = &r.cell;
        let Some(p) = PAPER_RESULTS.iter().find(|p| p.0 == c.object && p.1 == hand && p.2 == c.planner) else {
            continue;
        };
        let k = match totals.iter().position(|t| t.0 == c.planner) {
            Some(k) => k,
            None => {
                totals.push((&c.planner, 0.0, 0.0, 0.0, 0.0));
                totals.len() - 1
            }
        };
        let t = &mut totals[k];
        t.1 += c.palm_contact as f64;
        t.2 += c.force_closure_palm as f64;
        t.3 += p.3 as f64;
        t.4 += p.3 as f64 * p.4 / 100.0;
    }
    let ranked = |pick: &dyn Fn(&Totals<'_>) -> Option<f64>| -> Vec<(&str, Option<f64>)> {
        let mut v: Vec<(&str, Option<f64>)> = totals.iter().map(|t| (abbreviation(t.0), pick(t))).collect();
        v.sort_by(|a, b| b.1.unwrap_or(-1.0).total_cmp(&a.1.unwrap_or(-1.0)).then_with(|| a.0.cmp(b.0)));
        v
    };
    let ours = ranked(&|t| (t.1 > 0.0).then(|| 100.0 * t.2 / t.1));
    let paper = ranked(&|t| (t.3 > 0.0).then(|| 100.0 * t.4 / t.3));
    let fmt = |v: &[(&str, Option<f64>)]| {
        v.iter()
            .map(|(p, f)| f.map_or(format!("{p} no data"), |f| format!("{p} {f:.1} %")))
            .collect::<Vec<_>>()
            .join(" > ")
    };
    let same = ours.iter().map(|x| x.0).eq(paper.iter().map(|x| x.0));
    format!(
        "Hand {hand}, planners ranked by FC% over these objects: ours {}, paper {}: the ranking {}.",
        fmt(&ours),
        fmt(&paper),
        if same { "agrees" } else { "differs" }
    )
}
