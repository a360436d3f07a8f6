//! Evaluates the `grasp` bench's throughput mix (the default suite's hands and objects, 4
//! candidates per planner and cell) a fixed number of times: a fixed workload for instruction
//! counts of the grasp evaluator, e.g.
//!
//! ```text
//! valgrind --tool=callgrind --toggle-collect='*GraspEvaluator*evaluate*' \
//!     target/release/examples/eval_profile 1
//! ```
//!
//! Prints the number of evaluations and a digest of their results (closed, force closure,
//! sum of epsilons, the bits of every final configuration), to compare builds quickly; with
//! `EVAL_TRACE` set, also each evaluation's palm position, configuration and epsilon (stderr).

#[path = "../benches/mix/mod.rs"]
mod mix;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let reps: usize = std::env::args().nth(1).map_or(Ok(1), |a| a.parse())?;
    let trace = std::env::var_os("EVAL_TRACE").is_some();
    let mut mix = mix::suite_mix();
    let (mut n, mut closed, mut fc, mut eps) = (0usize, 0usize, 0usize, 0.0f64);
    let mut digest: u64 = 0xcbf2_9ce4_8422_2325;
    for _ in 0..reps {
        for (ev, _, candidates) in &mut mix {
            for candidate in candidates.iter() {
                let e = ev.evaluate(candidate)?;
                n += 1;
                if trace {
                    eprintln!("{n} {:?} {:?} {}", e.hand_pose.translation.vector.as_slice(), e.q, e.epsilon());
                }
                closed += usize::from(e.quality.is_some());
                fc += usize::from(e.force_closure());
                eps += e.epsilon();
                for x in e.q.iter().chain([e.retraction, e.epsilon()].iter()) {
                    digest = (digest ^ x.to_bits()).wrapping_mul(0x0100_0000_01b3);
                }
            }
        }
    }
    println!("{n} evaluations: {closed} closed, {fc} force closure, epsilon sum {eps:.12}, digest {digest:016x}");
    Ok(())
}
