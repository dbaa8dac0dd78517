//! Group update of an unresolved group (docs/model.md §6.5): tracks that share one `merged`
//! measurement move together by the correction of the track the measurement was assigned to,
//! so that their relative geometry survives the merged look instead of collapsing onto the
//! measurement.

use crate::filter::{FilterPrediction, FilterState};

/// The correction a track's update made to its combined mean, `x⁺ − x⁻`.
pub fn correction(posterior: &FilterState, pred: &FilterPrediction) -> [f64; 6] {
    let after = posterior.combined().x;
    let mut dx = [0.0; 6];
    for (k, d) in dx.iter_mut().enumerate() {
        *d = after[k] - pred.combined.x[k];
    }
    dx
}

/// Replace every mode mean of `posterior` by its prediction moved by `dx` (the group's
/// correction). Covariances and mode probabilities stay those of the track's own update.
pub fn shift_modes(posterior: &mut FilterState, pred: &FilterPrediction, dx: &[f64; 6]) {
    for (mode, prior) in posterior.modes.iter_mut().zip(&pred.modes) {
        mode.x = std::array::from_fn(|k| prior.x[k] + dx[k]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Gaussian;
    use crate::linalg::identity;

    fn pred(x: [f64; 6]) -> FilterPrediction {
        let g = Gaussian { x, p: identity() };
        FilterPrediction { modes: vec![g, g], cbar: vec![0.5, 0.5], combined: g }
    }

    #[test]
    fn members_move_by_the_same_correction() {
        // Leader predicted at 0, updated to 40 m east and +2 m/s; the member 300 m north keeps its
        // offset after the shared update.
        let lead = pred([0.0; 6]);
        let mut lead_post = FilterState {
            modes: vec![Gaussian { x: [40.0, 0.0, 0.0, 2.0, 0.0, 0.0], p: identity() }; 2],
            mu: vec![0.5, 0.5],
        };
        let dx = correction(&lead_post, &lead);
        assert_eq!(dx, [40.0, 0.0, 0.0, 2.0, 0.0, 0.0]);
        let member = pred([0.0, 300.0, 0.0, 0.0, 0.0, 0.0]);
        // The member's own update pulled it onto the measurement; the group update undoes that.
        let mut member_post = lead_post.clone();
        shift_modes(&mut member_post, &member, &dx);
        for m in &member_post.modes {
            assert_eq!(m.x, [40.0, 300.0, 0.0, 2.0, 0.0, 0.0]);
        }
        let sep = member_post.combined().x[1] - lead_post.combined().x[1];
        assert_eq!(sep, 300.0);
        // Shifting by a zero correction returns the prediction.
        shift_modes(&mut lead_post, &lead, &[0.0; 6]);
        assert_eq!(lead_post.combined().x, [0.0; 6]);
    }
}
