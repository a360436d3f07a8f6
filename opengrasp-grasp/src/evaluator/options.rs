//! Options of the grasp evaluator.

use crate::error::{GraspError, Result};
use crate::quality::{QualityOptions, RobustOptions};

/// Options of the [`GraspEvaluator`](super::GraspEvaluator).
#[derive(Clone, Debug, PartialEq)]
pub struct EvaluatorOptions {
    /// The hand approaches until it is this close to the object (m). Default: 2.5e-4.
    pub approach_tolerance: f64,
    /// Largest number of conservative-advancement steps along the approach. Default: 100.
    pub max_approach_steps: usize,
    /// How far (m) the hand may travel past the candidate pose before the candidate counts as
    /// missing the object. Default: 0.5.
    pub max_advance: f64,
    /// A finger stops when its links are closer than this to the object (m). Default: 1e-3.
    pub touch_distance: f64,
    /// Contacts are collected within this distance (m). Default: 2e-3.
    pub contact_margin: f64,
    /// Maximum conservative-advancement iterations while closing. Default: 60.
    pub max_close_iterations: usize,
    /// Smallest closing step per iteration (rad or m of the driving joint). Default: 2e-3.
    pub min_close_step: f64,
    /// Friction coefficient between hand and object; `None` uses the object's. Default: `None`.
    pub friction: Option<f64>,
    /// Quality metrics options; its friction is replaced by `friction` (or the object's).
    /// Default: [`QualityOptions::default`] (8-edge cones, epsilon, no hull statistics).
    pub quality: QualityOptions,
    /// Also compute GraspNet's friction score (smallest μ in 0.2..1.2 giving force closure).
    /// Default: `false`.
    pub friction_score: bool,
    /// Also compute Dex-Net's robust epsilon under contact perturbations (expensive: one hull
    /// per sample). Default: `None`.
    pub robust: Option<RobustOptions>,
}

impl Default for EvaluatorOptions {
    fn default() -> Self {
        Self {
            approach_tolerance: 2.5e-4,
            max_approach_steps: 100,
            max_advance: 0.5,
            touch_distance: 1e-3,
            contact_margin: 2e-3,
            max_close_iterations: 60,
            min_close_step: 2e-3,
            friction: None,
            quality: QualityOptions::default(),
            friction_score: false,
            robust: None,
        }
    }
}

impl EvaluatorOptions {
    pub(super) fn validate(&self) -> Result<()> {
        let positive = [
            ("approach_tolerance", self.approach_tolerance),
            ("max_advance", self.max_advance),
            ("touch_distance", self.touch_distance),
            ("contact_margin", self.contact_margin),
            ("min_close_step", self.min_close_step),
        ];
        for (name, v) in positive {
            crate::planners::check_positive(name, v)?;
        }
        self.quality.validate()?;
        if let Some(mu) = self.friction {
            if !(mu.is_finite() && mu >= 0.0) {
                return Err(GraspError::InvalidParameter {
                    name: "friction",
                    reason: format!("must be >= 0, got {mu}"),
                });
            }
        }
        Ok(())
    }
}
