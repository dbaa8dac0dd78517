//! Means over Monte Carlo runs with fixed additions, so that the same rows give the same bits on
//! every machine: a [`GroupMean`] over a group's values in row order is the value itself for a
//! group of one row, else a compensated (Kahan) sum from 0 over the non-null values divided by
//! their count (null when every value is null). These are the additions of a grouped float mean
//! in polars 0.55, which computed the score tables before; the tables are bit for bit those it
//! wrote.

/// A compensated sum from 0, its error term kept only while finite.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct KahanSum {
    sum: f64,
    err: f64,
}

impl KahanSum {
    /// Add one value.
    pub(crate) fn add(&mut self, v: f64) {
        let y = v - self.err;
        let new_sum = self.sum + y;
        let new_err = (new_sum - self.sum) - y;
        self.sum = new_sum;
        if new_err.is_finite() {
            self.err = new_err;
        }
    }

    /// The sum so far.
    pub(crate) fn value(&self) -> f64 {
        self.sum
    }
}

/// The mean of a group's values (nulls left out), added in row order.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct GroupMean {
    rows: u32,
    first: Option<f64>,
    valid: u32,
    sum: KahanSum,
}

impl GroupMean {
    /// One more row's value (`None` for null).
    pub(crate) fn push(&mut self, v: Option<f64>) {
        if self.rows == 0 {
            self.first = v;
        }
        self.rows += 1;
        if let Some(v) = v {
            self.valid += 1;
            self.sum.add(v);
        }
    }

    /// The mean; `None` when no value is defined.
    pub(crate) fn value(&self) -> Option<f64> {
        match (self.rows, self.valid) {
            (_, 0) => None,
            (1, _) => self.first,
            (_, n) => Some(self.sum.value() / f64::from(n)),
        }
    }

    /// The Kahan sum of the defined values (a group of one row: that value; none: 0).
    pub(crate) fn sum(&self) -> f64 {
        match self.rows {
            1 => self.first.unwrap_or(0.0),
            _ => self.sum.value(),
        }
    }

    /// The number of rows with a defined value.
    pub(crate) fn count(&self) -> u32 {
        self.valid
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The compensated sum keeps what a plain sum loses, and nulls are left out of the mean.
    #[test]
    fn kahan_mean_of_a_hand_made_group() {
        let mut m = GroupMean::default();
        for v in [Some(1.0), None, Some(1e-16), Some(1e-16), None] {
            m.push(v);
        }
        assert_eq!(m.count(), 3);
        // A plain sum gives exactly 1.0; the compensated one keeps the two 1e-16.
        assert_eq!(1.0 + 1e-16 + 1e-16, 1.0);
        assert!(m.sum() > 1.0, "{}", m.sum());
        assert_eq!(m.value(), Some(m.sum() / 3.0));
        let mut one = GroupMean::default();
        one.push(Some(-0.0));
        assert_eq!(one.value().map(f64::to_bits), Some((-0.0f64).to_bits()));
        let mut none = GroupMean::default();
        none.push(None);
        none.push(None);
        assert_eq!(none.value(), None);
    }
}
