//! Counting one cell's physics checks, with a diverged simulation recorded rather than fatal.

use opengrasp_core::CoreError;

use crate::error::{GraspError, Result};
use crate::evaluator::{HoldResult, PhysicsOutcome};

/// The physics columns of one benchmark cell, accumulated one simulated grasp at a time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct PhysicsTally {
    /// Grasps sent to the physics check (diverged ones included).
    pub tested: usize,
    /// Held in every gravity direction.
    pub held: usize,
    /// Some direction made the object slip but none dropped it.
    pub slipped: usize,
    /// Some direction dropped the object.
    pub dropped: usize,
    /// The squeeze alone moved the object farther than the drop distance.
    pub grip_moved: usize,
    /// The simulation diverged: counted as tested and not held, with no other outcome.
    pub diverged: usize,
    /// Not held, and the squeeze alone (no gravity) moved the object out of the hold tolerance
    /// ([`PhysicsOutcome::grip_escapes`]): failures of the hand's actuation.
    pub grip_escaped: usize,
    /// The static torque-limited test finds the grasp able to hold the weight.
    pub static_holdable: usize,
    /// Static test and simulation agree (simulations that finished only).
    pub static_agree: usize,
}

impl PhysicsTally {
    /// Adds one simulated grasp: the physics check's result, the static test's verdict, and the
    /// drop distance (m) that classifies the squeeze's own displacement. Returns whether the
    /// grasp held, or `None` if its simulation diverged.
    ///
    /// # Errors
    /// Any error of the check other than [`CoreError::SimulationDiverged`] is passed on.
    pub(crate) fn add(
        &mut self,
        check: Result<PhysicsOutcome>,
        static_holdable: bool,
        drop_translation: f64,
    ) -> Result<Option<bool>> {
        let outcome = match check {
            Ok(outcome) => Some(outcome),
            Err(GraspError::Core(CoreError::SimulationDiverged { .. })) => None,
            Err(e) => return Err(e),
        };
        self.tested += 1;
        self.static_holdable += usize::from(static_holdable);
        let Some(outcome) = outcome else {
            self.diverged += 1;
            return Ok(None);
        };
        let held = outcome.held();
        self.held += usize::from(held);
        self.slipped += usize::from(outcome.result() == Some(HoldResult::Slipped));
        self.dropped += usize::from(outcome.result() == Some(HoldResult::Dropped));
        self.grip_moved += usize::from(outcome.grip_translation > drop_translation);
        self.static_agree += usize::from(static_holdable == held);
        self.grip_escaped += usize::from(!held && outcome.grip_escapes);
        Ok(Some(held))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outcome(translations: &[f64], grip_translation: f64) -> PhysicsOutcome {
        let options = crate::evaluator::PhysicsCheckOptions::default();
        let results: Vec<HoldResult> = translations
            .iter()
            .map(|&t| {
                if t > options.drop_translation {
                    HoldResult::Dropped
                } else if t > options.max_translation {
                    HoldResult::Slipped
                } else {
                    HoldResult::Held
                }
            })
            .collect();
        PhysicsOutcome {
            translations: translations.to_vec(),
            rotations: vec![0.0; translations.len()],
            held_per_direction: results.iter().map(|&r| r == HoldResult::Held).collect(),
            results,
            grip_translation,
            grip_rotation: 0.0,
            release_push: 0.0,
            grip_escapes: grip_translation > options.max_translation,
        }
    }

    #[test]
    fn diverged_checks_count_as_tested_and_not_held_other_errors_pass_on() {
        let drop = crate::evaluator::PhysicsCheckOptions::default().drop_translation;
        let mut tally = PhysicsTally::default();
        assert_eq!(tally.add(Ok(outcome(&[0.0; 6], 0.0)), true, drop).unwrap(), Some(true));
        assert_eq!(tally.add(Ok(outcome(&[0.0, 1.0, 0.0, 0.0, 0.0, 0.0], 1.0)), true, drop).unwrap(), Some(false));
        let diverged = CoreError::SimulationDiverged { time: 0.083, distance: 0.4, speed: 2.8e6 };
        assert_eq!(tally.add(Err(diverged.into()), false, drop).unwrap(), None);
        let expected = PhysicsTally {
            tested: 3,
            held: 1,
            slipped: 0,
            dropped: 1,
            grip_moved: 1,
            diverged: 1,
            grip_escaped: 1,
            static_holdable: 2,
            static_agree: 1,
        };
        assert_eq!(tally, expected);
        // Any other failure is the benchmark's error and leaves the counts alone.
        let other = CoreError::Physics { reason: "multibody vanished".into() };
        assert!(matches!(tally.add(Err(other.into()), true, drop), Err(GraspError::Core(CoreError::Physics { .. }))));
        assert_eq!(tally, expected);
    }
}
