//! Conservative tables for obstacle tests of links placed by one group value alone (on the
//! ARMAR-III kitchen: the torso and the idle arm, moved by the hip yaw only).
//!
//! If a test's motion bound (the certificates' weights, [`super::certified`]) has one
//! non-zero weight `w`, for group value `j`, the link's spheres depend on `qⱼ` alone, and
//! moving `qⱼ` by `δ` moves them by at most `w·|δ|`. A [`LinkTable`] holds per cell of a
//! grid over `qⱼ`'s limits a sound lower bound of the test's gap over the whole cell: the
//! test's gap at the cell's centre minus `w` times the half width (inflated against
//! rounding) and the certificates' slack. A positive entry settles the test with that gap;
//! other cells, and values outside the limits, fall back to the direct test, so verdicts
//! never change. Cells are computed on first use (a few per motion at most).

use std::sync::atomic::{AtomicU64, Ordering};

/// Largest loss (m) of a cell's bound to the motion within it: sets the grid.
const MARGIN: f64 = 1e-3;
/// Most cells per table.
const MAX_CELLS: usize = 1 << 16;
/// Absolute slack (m) against the rounding of the kinematics, as the certificates'.
const SLACK: f64 = 1e-9;
/// A cell not computed yet (a NaN no bound computation returns: those are `≥ 0` or `-1`).
const UNKNOWN: u64 = u64::MAX;

/// The obstacle-test table of one link (see the module documentation).
#[derive(Debug)]
pub(super) struct LinkTable {
    /// The group value the link depends on, its lower limit, cell width and weight.
    dof: usize,
    lo: f64,
    width: f64,
    weight: f64,
    /// Per cell the bound's bits, `-1` if it does not settle the test, [`UNKNOWN`] before
    /// its first use.
    cells: Vec<AtomicU64>,
}

impl LinkTable {
    /// The table of a test with the weights `row` (one per group value) over `limits`, if
    /// exactly one weight is non-zero, finite, and its limits are finite.
    pub fn new(row: &[f64], limits: &[(f64, f64)]) -> Option<Self> {
        let mut moving = row.iter().enumerate().filter(|&(_, &w)| w != 0.0);
        let (dof, &weight) = moving.next()?;
        let &(lo, hi) = limits.get(dof)?;
        if moving.next().is_some() || !weight.is_finite() || weight < 0.0 || !(lo.is_finite() && hi > lo) {
            return None;
        }
        let span = hi - lo;
        if !span.is_finite() {
            return None;
        }
        let count = (weight * span / (2.0 * MARGIN)).ceil().clamp(1.0, MAX_CELLS as f64) as usize;
        let cells = (0..count).map(|_| AtomicU64::new(UNKNOWN)).collect();
        Some(Self { dof, lo, width: span / count as f64, weight, cells })
    }

    /// The test's gap at `q` if the table settles it: `gap_at_centre(c)` computes the
    /// direct test's gap (`None` if it fails) at the group values `c` (those of `q`, `qⱼ`
    /// moved to the cell's centre) the first time a cell is used.
    #[inline]
    pub fn gap(&self, q: &[f64], gap_at_centre: impl FnOnce(&[f64]) -> Option<f64>) -> Option<f64> {
        let x = (q.get(self.dof)? - self.lo) / self.width;
        if !(x >= 0.0 && x < self.cells.len() as f64) {
            return None;
        }
        let cell = &self.cells[x as usize];
        let bits = cell.load(Ordering::Relaxed);
        let bound = if bits == UNKNOWN {
            let centre = self.lo + (x.floor() + 0.5) * self.width;
            let mut c = q.to_vec();
            c[self.dof] = centre;
            // The farthest `qⱼ` of the cell from its centre is half a width away (inflated
            // against the rounding of `x` and of the centre).
            let loss = self.weight * (0.5 * self.width * (1.0 + 1e-6) + 1e-12) + SLACK;
            let bound = gap_at_centre(&c).map_or(-1.0, |g| g - loss);
            let bound = if bound > 0.0 { bound } else { -1.0 };
            cell.store(bound.to_bits(), Ordering::Relaxed);
            bound
        } else {
            f64::from_bits(bits)
        };
        (bound > 0.0).then_some(bound)
    }
}
