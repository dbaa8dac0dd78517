//! Which targets a dwell's transmit beams can reach: a pre-selection that lets a dwell visit only
//! the targets near its beams (docs/model.md §4.7).
//!
//! A target returns in channel `(j → i)` only when transmitter `j` looks at it: in front of the
//! face, above the horizon and with a one-way pattern power `max(Σ², Δa², Δe²)` at least
//! [`PATTERN_FLOOR`] of the peak (`crate::returns`). With the Gaussian pattern of
//! docs/model.md §2.2, `a = Δu/θ_u`, `b = Δv/θ_v` and `r² = a² + b²`, the one-way power is
//! `e^{−4 ln2 r²} · max(1, k_m² a², k_m² b²) ≤ e^{−4 ln2 r²} · max(1, k_m² r²)`, and since
//! `r² ≤ e^{r² − 1}` this is at most `max(1, k_m²/e) · e^{−(4 ln2 − 1) r²}`, decreasing in `r`.
//! Beyond `r₁`, where that bound is half the floor, no transmitter look exists. A ball of radius
//! `ρ` whose centre is at face-frame distance `R ≥ 2ρ` is seen within a sine-space distance
//! `1.05 ρ/R` of its centre (as in [`crate::quiet::QuietRadar::beam_clear`]). A target whose ball
//! is beyond every transmitter's reach gives no look, so no return, and the dwell evaluated
//! without it is the dwell evaluated with it, bit for bit — provided nothing else depends on the
//! target's place in the list: [`DwellReach::new`] answers `None` (take every target) when
//! waveform leakage (keyed by that place), refraction (looks off the geometric direction),
//! another pattern model or the all-cells option is on.

use crate::dwell::{Dwell, PATTERN_FLOOR};
use crate::pattern::Antenna;
use crate::quiet::TargetBall;
use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::params::PatternModel;

/// One transmitter's beam and its reach (sine-space distance beyond which no look exists).
#[derive(Debug, Clone, Copy)]
struct BeamReach {
    frame: FaceFrame,
    beam_u: f64,
    beam_v: f64,
    reach: f64,
}

/// The transmit beams of one dwell, for [`DwellReach::may_reach`].
#[derive(Debug, Clone)]
pub struct DwellReach {
    beams: Vec<BeamReach>,
}

impl DwellReach {
    /// The reach of dwell `d`'s transmitters; `None` when the pre-selection does not apply (see
    /// the module documentation) and every target must be evaluated.
    pub fn new(d: &Dwell) -> Option<DwellReach> {
        let f = d.fidelity;
        if f.pattern != PatternModel::Gaussian
            || f.refraction
            || f.waveform_isolation_db.is_some()
            || d.simulate_all_cells
        {
            return None;
        }
        let beams = d
            .transmitters
            .iter()
            .map(|tx| {
                let reach = one_way_reach(&Antenna::new(tx.params, PatternModel::Gaussian))?;
                Some(BeamReach { frame: tx.frame, beam_u: tx.beam_u, beam_v: tx.beam_v, reach })
            })
            .collect::<Option<Vec<_>>>()?;
        Some(DwellReach { beams })
    }

    /// Whether some transmitter may look at a target inside `ball`; `false` only when every
    /// transmitter's pattern gate certainly drops it.
    pub fn may_reach(&self, ball: TargetBall) -> bool {
        self.beams.iter().any(|b| !beyond(b, ball))
    }
}

/// Whether every point of `ball` lies beyond beam `b`'s reach.
fn beyond(b: &BeamReach, ball: TargetBall) -> bool {
    let l: DVec3 = b.frame.face_from_ecef * (ball.center_ecef - b.frame.origin_ecef);
    let range_m = l.length();
    if !(ball.radius_m >= 0.0 && range_m >= 2.0 * ball.radius_m && range_m > 0.0) {
        return false;
    }
    let (du, dv) = (l.x / range_m - b.beam_u, l.y / range_m - b.beam_v);
    let need = b.reach + 1.05 * ball.radius_m / range_m;
    du * du + dv * dv > need * need
}

/// Sine-space distance from the beam beyond which the one-way Gaussian pattern power is below
/// half of [`PATTERN_FLOOR`] (with 1 % for rounding); `None` for an unusable antenna.
fn one_way_reach(ant: &Antenna) -> Option<f64> {
    let k2 = ant.slope() * ant.slope();
    let r1_sq = (2.0 * (k2 / std::f64::consts::E).max(1.0) / PATTERN_FLOOR).ln() / (4.0 * std::f64::consts::LN_2 - 1.0);
    let theta = ant.theta_u().max(ant.theta_v());
    (r1_sq.is_finite() && r1_sq > 0.0 && theta.is_finite() && theta > 0.0).then(|| 1.01 * r1_sq.sqrt() * theta)
}
