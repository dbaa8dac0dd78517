//! Group looks (docs/model.md §7.2): one dwell serves every confirmed track that sits in the
//! same beam as the track it was planned for, so that an unresolved or tight group costs one
//! look instead of one per member.

use super::config::ResourceConfig;
use super::snapshot::Snapshot;
use mimo_core::DVec3;
use mimo_core::ids::RadarId;

/// The tracks among `candidates` (sorted by id) that `keep` accepts and whose predicted
/// positions at the pass's instant lie, seen from radar `tx`, within `group_beam_fraction` of the
/// narrower beamwidth of `aim` and within `group_radius_m` of it, each with its distance from
/// `aim` (m), by id. Only the tracks the pass's index finds near `aim` are visited
/// ([`Snapshot::near`]), so a look costs its neighbours, not every candidate.
pub fn members(
    cfg: &ResourceConfig,
    snap: &Snapshot,
    aim: DVec3,
    tx: RadarId,
    candidates: &[u64],
    keep: impl Fn(u64) -> bool,
) -> Vec<(u64, f64)> {
    debug_assert!(candidates.windows(2).all(|w| w[0] < w[1]), "candidates not sorted by id");
    let (Some(p), Some(face)) = (snap.geom.params(tx), snap.faces_of(tx).first()) else {
        return Vec::new();
    };
    let site = face.origin_ecef;
    let d0 = aim - site;
    let r0 = d0.length();
    if r0 <= 0.0 {
        return Vec::new();
    }
    let da_max = cfg.group_beam_fraction * p.beamwidth_u().min(p.beamwidth_v());
    // A track whose position ball is farther than the group radius is not predicted.
    snap.near(aim, cfg.group_radius_m)
        .into_iter()
        .filter(|id| candidates.binary_search(id).is_ok() && keep(*id))
        .filter_map(|id| {
            let q = snap.position(id)?;
            let d1 = q - site;
            let r1 = d1.length();
            let dist = (q - aim).length();
            (r1 > 0.0 && dist <= cfg.group_radius_m && (d1 / r1 - d0 / r0).length() <= da_max).then_some((id, dist))
        })
        .collect()
}
