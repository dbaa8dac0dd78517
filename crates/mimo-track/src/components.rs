//! The component factory: the built-in components a [`TrackerConfig`] asks for.

use crate::association::{Associator, GnnAssociator};
use crate::config::{AssociationMethod, InitiatorConfig, TrackerConfig, TrackerKind};
use crate::deletion::Deleter;
use crate::filter::{ImmFilter, SingleModelFilter, TrackFilter};
use crate::gating::Gater;
use crate::initiation::{Confirmer, Initiator, OnePointInitiator, TwoPointInitiator};
use crate::jpda::JpdaAssociator;
use crate::motion::{HorizontalTurn, KalmanPredictor, Ncv, Predictor, ProcessNoise};
use crate::update::EkfUpdater;

/// The components a tracker is made of. Build your own to compose a custom tracker.
pub struct Components {
    /// Per-track state estimation (prediction and update).
    pub filter: Box<dyn TrackFilter>,
    /// Which track–measurement pairs are plausible.
    pub gater: Box<dyn Gater>,
    /// Which measurement updates which track.
    pub associator: Box<dyn Associator>,
    /// Tentative tracks from unclaimed detections.
    pub initiator: Box<dyn Initiator>,
    /// Confirmation of tentative tracks.
    pub confirmer: Box<dyn Confirmer>,
    /// When a track ends.
    pub deleter: Box<dyn Deleter>,
}

impl Components {
    /// The built-in components for a configuration.
    pub fn from_config(cfg: &TrackerConfig) -> Components {
        let filter: Box<dyn TrackFilter> = match cfg.kind {
            TrackerKind::Default => Box::new(SingleModelFilter {
                name: "ekf-ncv".into(),
                predictor: Box::new(KalmanPredictor::new(Ncv { noise: cfg.ekf_noise })),
                updater: Box::new(EkfUpdater::default()),
            }),
            TrackerKind::Imm => {
                let c = &cfg.imm;
                let mut predictors: Vec<Box<dyn Predictor>> = vec![
                    Box::new(KalmanPredictor::new(Ncv::dwna(c.sigma_low_mps2))),
                    Box::new(KalmanPredictor::new(Ncv::dwna(c.sigma_high_mps2))),
                ];
                let mut sojourn_s = vec![c.sojourn_low_s, c.sojourn_high_s];
                if let Some(rate) = c.turn_rate_dps {
                    for sign in [1.0, -1.0] {
                        predictors.push(Box::new(KalmanPredictor::new(HorizontalTurn {
                            omega_radps: sign * rate.to_radians(),
                            noise: ProcessNoise::Dwna { sigma_a_mps2: c.sigma_low_mps2 },
                        })));
                        sojourn_s.push(c.sojourn_high_s);
                    }
                }
                let initial_mu = match &c.initial_mu {
                    Some(mu) => mu.clone(),
                    None => {
                        let s: f64 = sojourn_s.iter().sum();
                        sojourn_s.iter().map(|t| t / s).collect()
                    }
                };
                Box::new(ImmFilter {
                    name: format!("imm-{}", predictors.len()),
                    predictors,
                    sojourn_s,
                    initial_mu,
                    updater: Box::new(EkfUpdater::default()),
                })
            }
        };
        let initiator: Box<dyn Initiator> = match cfg.initiator {
            InitiatorConfig::OnePoint { velocity_std_mps } => Box::new(OnePointInitiator { velocity_std_mps }),
            InitiatorConfig::TwoPoint(c) => Box::new(TwoPointInitiator::new(c)),
        };
        Components {
            filter,
            gater: Box::new(cfg.gate),
            associator: match cfg.association_method {
                AssociationMethod::Gnn => Box::new(GnnAssociator { cost: cfg.association }),
                AssociationMethod::Jpda => Box::new(JpdaAssociator {
                    cost: cfg.association,
                    max_events: cfg.jpda.max_events,
                    min_probability: cfg.jpda.min_probability,
                }),
            },
            initiator,
            confirmer: Box::new(cfg.confirmation),
            deleter: Box::new(cfg.deletion.build()),
        }
    }
}
