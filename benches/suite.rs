//! The harness end to end: a tiny suite (grasp cells and motion runs in parallel jobs), the
//! results file round trip and the report, i.e. what the runner adds on top of the planners.
//!
//! ```sh
//! cargo bench --bench suite -- --warm-up-time 1 --measurement-time 5
//! ```

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use opengrasp::report::{self, Format};
use opengrasp::results::ResultsFile;
use opengrasp::suite::{Suite, SuiteSize};

fn suite(c: &mut Criterion) {
    let mut group = c.benchmark_group("suite");
    group.sample_size(10);
    group.bench_function("tiny_standard_suite_run", |b| {
        b.iter(|| Suite::standard(SuiteSize::Tiny).jobs(1).seed(1).run().expect("the tiny suite runs"))
    });
    let results = Suite::standard(SuiteSize::Tiny).jobs(1).seed(1).run().expect("the tiny suite runs");
    let json = results.to_json().expect("serialisable");
    group.bench_function("results_json_parse_and_validate", |b| {
        b.iter(|| ResultsFile::from_json(black_box(&json)).expect("valid"))
    });
    group.bench_function("report_markdown", |b| b.iter(|| report::render(black_box(&results), Format::Markdown)));
    group.finish();
}

criterion_group!(benches, suite);
criterion_main!(benches);
