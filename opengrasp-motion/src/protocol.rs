//! Benchmark protocols: how paths are post-processed and validated, and what setup time counts.
//!
//! - [`Protocol::Certified`] (the default): planning at the 0.02 step, shortcuts accepted only
//!   when the strict (0.002) and certified continuous checks pass, segments the validators
//!   reject repaired — so post-processed paths are valid by construction; setup time is the
//!   planner's `setup` alone.
//! - [`Protocol::Paper`]: the OpenGRASP paper's reference evaluation (Ulbrich et al. 2011,
//!   section IV-B, Table III): discrete checks at the 0.05 planning step, plain shortcutting
//!   checked at that same step only, validity re-checked afterwards at a tiny step (0.005) and
//!   continuously; setup time includes loading and preparing the scene (building the robot,
//!   collision world and checker) as well as the planner's setup. Shortcuts then graze
//!   obstacles between the coarse samples, which is the validity drop the paper reports
//!   (98.1 % of planned vs 76.9 % of post-processed paths valid).

use serde::{Deserialize, Serialize};

use crate::benchmark::BenchmarkOptions;

/// The paper protocol's planning (and shortcut) step, in the C-space norm.
pub const PAPER_STEP: f64 = 0.05;
/// The paper protocol's re-check step ("a tiny step size"): a tenth of the planning step.
pub const PAPER_STRICT_STEP: f64 = 0.005;

/// How a motion benchmark post-processes, validates and times (see the [module docs](self)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Protocol {
    /// Certified shortcutting; post-processed paths valid by construction.
    #[default]
    Certified,
    /// The paper's reference evaluation: step 0.05, plain shortcutting, fine re-check.
    Paper,
}

impl Protocol {
    /// `"certified"` or `"paper"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Certified => "certified",
            Self::Paper => "paper",
        }
    }

    /// What the protocol means, for reports.
    pub fn description(self) -> &'static str {
        match self {
            Self::Certified => {
                "certified: planning step 0.02; shortcuts accepted only if the strict (0.002) and continuous \
                 checks pass, rejected segments repaired; setup time = planner setup"
            }
            Self::Paper => {
                "paper: planning step 0.05; plain shortcutting checked at 0.05 only; validity re-checked at 0.005 \
                 and continuously; setup time = scene loading and preparation + planner setup"
            }
        }
    }

    /// `options` with this protocol's steps, shortcut checks and setup timing (runs, seed, time
    /// limit and the other settings are kept).
    pub fn apply(self, options: BenchmarkOptions) -> BenchmarkOptions {
        match self {
            Self::Certified => {
                let defaults = BenchmarkOptions::default();
                BenchmarkOptions {
                    protocol: self,
                    validation: defaults.validation,
                    shortcut: crate::smoothing::ShortcutOptions { seed: options.shortcut.seed, ..defaults.shortcut },
                    ..options
                }
            }
            Self::Paper => {
                let mut o = BenchmarkOptions { protocol: self, ..options };
                o.validation.step = PAPER_STEP;
                o.validation.strict_step = PAPER_STRICT_STEP;
                o.shortcut.step = PAPER_STEP;
                o.shortcut.planning_step = PAPER_STEP;
                o.shortcut.certify = false;
                o
            }
        }
    }
}
