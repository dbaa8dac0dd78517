//! The dwell's target pre-selection (`mimo_radar::reach`): a target whose ball lies beyond every
//! transmitter's reach gives no return, and the dwell evaluated with the targets it may reach
//! alone gives the same channels, primitives and voltages as with every target, on random
//! monostatic and MIMO scenes.

mod common;

use common::{SEED, Ship, dwell_of, rcs_for_snr};
use mimo_core::DVec3;
use mimo_core::params::{Fidelity, PatternModel, RadarParams};
use mimo_core::rng::{Stream, domain};
use mimo_radar::dwell::{Target, evaluate};
use mimo_radar::quiet::TargetBall;
use mimo_radar::reach::DwellReach;

#[test]
fn the_targets_a_dwell_may_reach_give_the_dwell_of_all_targets() {
    let (mut dropped, mut kept, mut returned) = (0, 0, 0);
    let p = RadarParams { pfa: 1e-4, ..RadarParams::default() };
    let (th_u, th_v) = (p.beamwidth_u(), p.beamwidth_v());
    let ids: Vec<String> = (0..12).map(|i| format!("T{i}")).collect();
    for case in 0..400u64 {
        let mut s = Stream::new(SEED, &[domain::TEST, 31, case]);
        let fid = Fidelity { pattern: PatternModel::Gaussian, ..Fidelity::default() };
        let ships = [Ship::new(0, 36.0, -70.0, &p), Ship::new(1, 36.05, -69.9, &p)];
        let face = (case % 4) as usize;
        let (bu, bv) = (0.6 * s.uniform() - 0.3, 0.3 * s.uniform() - 0.05);
        // Every other case a MIMO dwell: both ships transmit and receive on the same face.
        let n_ships = 1 + (case % 2) as usize;
        let txs: Vec<_> = ships[..n_ships].iter().map(|sh| sh.tx(&p, face, bu, bv, 2)).collect();
        let rxs: Vec<_> = ships[..n_ships]
            .iter()
            .enumerate()
            .map(|(k, sh)| sh.rx(&p, 2 * case + k as u64, face, bu, bv, (p.min_range_m, p.instrumented_range_m)))
            .collect();
        // Strong targets up to many beamwidths around the beam, each in a ball of up to 4 km.
        let mut balls = Vec::new();
        let targets: Vec<Target> = (0..12)
            .map(|i| {
                let spread = if i % 3 == 0 { 3.0 } else { 30.0 };
                let (du, dv) = ((s.uniform() - 0.5) * spread * th_u, (s.uniform() - 0.5) * spread * th_v);
                let r = 10e3 + s.uniform() * 250e3;
                let pos = ships[0].point(face, r, bu + du, bv + dv);
                let off = DVec3::new(s.uniform() - 0.5, s.uniform() - 0.5, s.uniform() - 0.5) * 4e3;
                balls.push(TargetBall { center_ecef: pos + off, radius_m: off.length() * (1.0 + s.uniform()) });
                Target { id: &ids[i], index: i as u32, pos_ecef: pos, rcs_m2: rcs_for_snr(&p, 1e3, r, 1.0), pol: None }
            })
            .collect();
        let keys = [5, case];
        let d = dwell_of(&keys, &txs, &rxs, &fid, true);
        let reach = DwellReach::new(&d).expect("the Gaussian pattern without leakage or refraction is pre-selected");
        let near: Vec<bool> = balls.iter().map(|b| reach.may_reach(*b)).collect();
        let subset: Vec<Target> = targets.iter().zip(&near).filter(|(_, n)| **n).map(|(t, _)| *t).collect();
        let all = evaluate(&d, &targets);
        let some = evaluate(&d, &subset);
        // No target beyond reach returns in any channel.
        for ch in &all.channels {
            for r in &ch.returns {
                assert!(near[r.target], "case {case}: target {} returned, yet beyond reach", r.target);
                returned += 1;
            }
        }
        assert_eq!(all.primitives, some.primitives, "case {case}");
        assert_eq!(all.voltages, some.voltages, "case {case}");
        assert_eq!(all.channels.len(), some.channels.len());
        for (a, b) in all.channels.iter().zip(&some.channels) {
            assert_eq!((a.window, a.shortcut_cells, a.false_alarms), (b.window, b.shortcut_cells, b.false_alarms));
            assert_eq!(a.returns.len(), b.returns.len(), "case {case}");
        }
        dropped += near.iter().filter(|n| !**n).count();
        kept += near.iter().filter(|n| **n).count();
    }
    // Both answers occur often and targets do return, so the checks above bite.
    assert!(dropped > 1000 && kept > 1000 && returned > 300, "dropped {dropped}, kept {kept}, returned {returned}");
}

#[test]
fn the_pre_selection_stands_aside_where_a_target_s_place_or_path_matters() {
    let p = RadarParams::default();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let txs = [ship.tx(&p, 0, 0.0, 0.0, 2)];
    let rxs = [ship.rx(&p, 1, 0, 0.0, 0.0, (p.min_range_m, p.instrumented_range_m))];
    let keys = [5, 1];
    let base = Fidelity { pattern: PatternModel::Gaussian, ..Fidelity::default() };
    let cases = [
        (base.clone(), true),
        (Fidelity { pattern: PatternModel::UniformAperture, ..base.clone() }, false),
        (Fidelity { refraction: true, ..base.clone() }, false),
        (Fidelity { waveform_isolation_db: Some(30.0), ..base.clone() }, false),
    ];
    for (fid, applies) in cases {
        let d = dwell_of(&keys, &txs, &rxs, &fid, false);
        assert_eq!(DwellReach::new(&d).is_some(), applies, "{fid:?}");
    }
}
