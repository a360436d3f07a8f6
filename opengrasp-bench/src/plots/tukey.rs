//! Box-plot statistics after Tukey: quartiles, whiskers clipped to the data, outliers.

/// The numbers a Tukey box plot draws for one sample.
///
/// Quartiles interpolate linearly between order statistics (Hyndman and Fan type 7, the default
/// of R's `quantile` and NumPy's `percentile`). The whiskers end at the most extreme data points
/// within 1.5 IQR of the box (`q1 - 1.5 IQR ..= q3 + 1.5 IQR`), so a whisker never reaches past
/// the sample's minimum or maximum; every point beyond is an outlier and drawn on its own.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxStats {
    /// Number of (finite) values in the sample.
    pub n: usize,
    /// First quartile (25th percentile).
    pub q1: f64,
    /// Median.
    pub median: f64,
    /// Third quartile (75th percentile).
    pub q3: f64,
    /// Lower whisker end: the smallest value `>= q1 - 1.5 IQR`.
    pub whisker_low: f64,
    /// Upper whisker end: the largest value `<= q3 + 1.5 IQR`.
    pub whisker_high: f64,
    /// Values outside the whiskers, ascending.
    pub outliers: Vec<f64>,
}

/// The whisker reach in interquartile ranges (Tukey's 1.5).
pub const WHISKER_IQR: f64 = 1.5;

impl BoxStats {
    /// Statistics of `values`; non-finite values are ignored. `None` if no finite value is left.
    #[must_use]
    pub fn new(values: &[f64]) -> Option<Self> {
        let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        let (q1, median, q3) = (quantile(&v, 0.25), quantile(&v, 0.5), quantile(&v, 0.75));
        let iqr = q3 - q1;
        let (fence_low, fence_high) = (q1 - WHISKER_IQR * iqr, q3 + WHISKER_IQR * iqr);
        // The sample is sorted and the fences bracket the quartiles, so both searches succeed.
        let whisker_low = v.iter().copied().find(|&x| x >= fence_low).unwrap_or(q1);
        let whisker_high = v.iter().rev().copied().find(|&x| x <= fence_high).unwrap_or(q3);
        let outliers = v.iter().copied().filter(|&x| x < fence_low || x > fence_high).collect();
        Some(Self { n: v.len(), q1, median, q3, whisker_low, whisker_high, outliers })
    }

    /// The smallest and largest value drawn (whisker ends and outliers).
    #[must_use]
    pub fn extent(&self) -> (f64, f64) {
        let lo = self.outliers.first().map_or(self.whisker_low, |&o| o.min(self.whisker_low));
        let hi = self.outliers.last().map_or(self.whisker_high, |&o| o.max(self.whisker_high));
        (lo, hi)
    }
}

/// The `p`-quantile of sorted, non-empty `v` by linear interpolation (type 7).
fn quantile(v: &[f64], p: f64) -> f64 {
    let h = (v.len() - 1) as f64 * p;
    let (i, frac) = (h.floor() as usize, h - h.floor());
    match v.get(i + 1) {
        Some(next) => v[i] + frac * (next - v[i]),
        None => v[i],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOL: f64 = 1e-12;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < TOL
    }

    #[test]
    fn known_sample_with_outliers_on_both_sides() {
        // Sorted: 1, 10, 11, 12, 13, 14, 15, 40. Type 7: q1 = 10.75, median 12.5, q3 = 14.25,
        // IQR 3.5, fences 5.5 and 19.5.
        let s = BoxStats::new(&[12.0, 40.0, 10.0, 1.0, 15.0, 13.0, 11.0, 14.0]).unwrap();
        assert_eq!(s.n, 8);
        assert!(close(s.q1, 10.75) && close(s.median, 12.5) && close(s.q3, 14.25), "{s:?}");
        // Whiskers end at data points inside the fences, not at the fences.
        assert!(close(s.whisker_low, 10.0) && close(s.whisker_high, 15.0), "{s:?}");
        assert_eq!(s.outliers, vec![1.0, 40.0]);
        assert_eq!(s.extent(), (1.0, 40.0));
    }

    /// Issue 16: PRM's lower whisker was drawn at the fence (0 ms, clamped) below its 6.96 ms
    /// minimum. The whisker must stop at the minimum.
    #[test]
    fn issue_16_whisker_never_below_the_minimum() {
        let s = BoxStats::new(&[6.96, 20.0, 21.0, 22.0, 60.0]).unwrap();
        // q1 = 20, q3 = 22, fences 17 and 25: 6.96 and 60 are outliers, whiskers 20 and 22.
        assert!(close(s.whisker_low, 20.0) && close(s.whisker_high, 22.0), "{s:?}");
        assert_eq!(s.outliers, vec![6.96, 60.0]);
        // Without outliers the whiskers are the minimum and maximum exactly.
        let s = BoxStats::new(&[6.96, 7.5, 8.0, 9.1, 10.2]).unwrap();
        assert!(close(s.whisker_low, 6.96) && close(s.whisker_high, 10.2), "{s:?}");
        assert!(s.outliers.is_empty());
    }

    #[test]
    fn degenerate_samples() {
        assert_eq!(BoxStats::new(&[]), None);
        assert_eq!(BoxStats::new(&[f64::NAN]), None);
        let one = BoxStats::new(&[3.0, f64::INFINITY]).unwrap();
        assert_eq!((one.n, one.q1, one.median, one.q3), (1, 3.0, 3.0, 3.0));
        assert_eq!((one.whisker_low, one.whisker_high), (3.0, 3.0));
        let two = BoxStats::new(&[1.0, 2.0]).unwrap();
        assert!(close(two.q1, 1.25) && close(two.median, 1.5) && close(two.q3, 1.75));
        assert_eq!((two.whisker_low, two.whisker_high), (1.0, 2.0));
    }
}
