//! Which energy a study's efficient frontiers are built on (a plan's `frontier_energy`;
//! docs/studies.md, "The challenge"; docs/decisions/0318-frontier-on-the-test-articles-energy.md).
//!
//! * `total` (the default): every transmit dwell of every radar, search and test article — the
//!   challenge's own figure: what the ships radiate to hold 98 %.
//! * `test_article`: the test article's part alone — for a study whose knob shapes only what the
//!   test article spends (a power budget) while the radars' background search fills the rest of
//!   each timeline. There the total *falls* as the budget grows (a test-article dwell takes the
//!   time of a search dwell that would have radiated more), so a frontier on the total would put
//!   the largest budget first and say nothing about what the budget buys.
//!
//! The choice moves the frontier, the crossing, the refinement's brackets and the energy axis of
//! the charts and the page; every figure at 98 % (total and the test article's part) is still
//! read at that one crossing.

use crate::challenge::{AT_ENERGY, AT_TA_ENERGY, RUN_ENERGY, RUN_TA_ENERGY};

/// The energy a frontier is built on.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum FrontierEnergy {
    /// Search and test article: every transmit dwell of every radar.
    #[default]
    Total,
    /// The test article's dwells alone.
    TestArticle,
}

impl FrontierEnergy {
    /// The plan's values, in this order.
    pub const LABELS: [&'static str; 2] = ["total", "test_article"];

    /// The plan's value.
    pub fn name(self) -> &'static str {
        match self {
            FrontierEnergy::Total => Self::LABELS[0],
            FrontierEnergy::TestArticle => Self::LABELS[1],
        }
    }

    /// The basis a plan value names.
    pub fn parse(s: &str) -> Option<FrontierEnergy> {
        match s {
            "total" => Some(FrontierEnergy::Total),
            "test_article" => Some(FrontierEnergy::TestArticle),
            _ => None,
        }
    }

    /// Its per-run figure (an index of `challenge::PointRuns::figures`).
    pub fn run_figure(self) -> usize {
        match self {
            FrontierEnergy::Total => RUN_ENERGY,
            FrontierEnergy::TestArticle => RUN_TA_ENERGY,
        }
    }

    /// Its figure at the crossing (an index of `challenge::AtRequired::figures`).
    pub fn at_figure(self) -> usize {
        match self {
            FrontierEnergy::Total => AT_ENERGY,
            FrontierEnergy::TestArticle => AT_TA_ENERGY,
        }
    }

    /// Its metric in `results.parquet` and `summary.parquet`.
    pub fn metric(self) -> &'static str {
        match self {
            FrontierEnergy::Total => "energy_per_object_j",
            FrontierEnergy::TestArticle => "ta_energy_per_object_j",
        }
    }

    /// How a report or chart names it.
    pub fn words(self) -> &'static str {
        match self {
            FrontierEnergy::Total => "total energy (search and test article)",
            FrontierEnergy::TestArticle => "test-article energy (background search left out)",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_label_names_its_basis() {
        for label in FrontierEnergy::LABELS {
            assert_eq!(FrontierEnergy::parse(label).map(FrontierEnergy::name), Some(label));
        }
        assert_eq!(FrontierEnergy::parse("ta"), None);
        assert_eq!(FrontierEnergy::default(), FrontierEnergy::Total);
        assert_eq!(FrontierEnergy::TestArticle.run_figure(), RUN_TA_ENERGY);
        assert_eq!(FrontierEnergy::TestArticle.at_figure(), AT_TA_ENERGY);
    }
}
