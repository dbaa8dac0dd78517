//! Validation of scenario contents: physically possible values and a consistent structure.
//!
//! The loader validates each definition against the file it came from (so messages name that
//! file); [`Scenario::validate`] re-checks a resolved scenario as a whole, e.g. one read back
//! from a run manifest.

use crate::error::ScenarioError;
use crate::flight::{Controls, Ctx, compile_offsets};
use crate::model::{
    Aircraft, AircraftType, Envelope, Formation, Group, LatLonAlt, Manoeuvre, Offset, Scenario, Ship, Split, Target,
};
use crate::trajectory::centroid;
use mimo_core::params::{Fidelity, Swerling};
use std::collections::HashSet;

/// Longest scenario accepted (s): one day (trajectories are stored at 20 Hz).
pub const MAX_DURATION_S: f64 = 86_400.0;

fn check(ok: bool, ctx: &Ctx, field: &str, expected: impl FnOnce() -> String) -> Result<(), ScenarioError> {
    if ok { Ok(()) } else { Err(ctx.err(field, expected())) }
}

pub(crate) fn validate_duration(d: f64, ctx: &Ctx) -> Result<(), ScenarioError> {
    check(d.is_finite() && d > 0.0 && d <= MAX_DURATION_S, ctx, "duration_s", || {
        format!("a duration in (0, {MAX_DURATION_S}] s, got {d}")
    })
}

pub(crate) fn validate_fidelity(f: &Fidelity, ctx: &Ctx) -> Result<(), ScenarioError> {
    let r = f.truth_rate_hz;
    check(r.is_finite() && r > 0.0 && r <= 1000.0, ctx, "truth_rate_hz", || {
        format!("a truth sample rate in (0, 1000] Hz, got {r}")
    })?;
    if let Some(iso) = f.waveform_isolation_db {
        check(iso.is_finite() && iso >= 0.0, ctx, "waveform_isolation_db", || {
            format!("an isolation of 0 dB or more, got {iso}")
        })?;
    }
    check(f.explicit_cells_each_side <= 1000, ctx, "explicit_cells_each_side", || {
        format!("at most 1000 cells, got {}", f.explicit_cells_each_side)
    })?;
    // The polarimetric model's scattering matrix is Gaussian: every channel fluctuates as SW1
    // (docs/model.md §3.5), so another Swerling case with it would be silently ignored.
    check(!f.polarization || f.swerling == Swerling::Sw1, ctx, "polarization", || {
        format!("swerling = \"sw1\" with polarization on (its scattering matrix is Gaussian), got {:?}", f.swerling)
    })
}

fn latitude(lat: f64, limit: f64, ctx: &Ctx, field: &str) -> Result<(), ScenarioError> {
    check(lat.is_finite() && lat.abs() <= limit, ctx, field, || {
        format!("a latitude between -{limit} and {limit} degrees, got {lat}")
    })
}

fn longitude(lon: f64, ctx: &Ctx, field: &str) -> Result<(), ScenarioError> {
    check(lon.is_finite() && lon.abs() <= 180.0, ctx, field, || {
        format!("a longitude between -180 and 180 degrees, got {lon}")
    })
}

fn heading(h: f64, ctx: &Ctx) -> Result<(), ScenarioError> {
    check(h.is_finite() && h.abs() <= 720.0, ctx, "heading_deg", || {
        format!("a heading in degrees clockwise from north, got {h}")
    })
}

/// A ship at position `index` of the ship list.
pub(crate) fn validate_ship(s: &Ship, index: usize, ctx: &Ctx) -> Result<(), ScenarioError> {
    check(s.id.index() == index, ctx, "id", || {
        format!("ships numbered R1, R2, … in order, so `R{}` here, got `{}`", index + 1, s.id)
    })?;
    latitude(s.lat_deg, 90.0, ctx, "lat_deg")?;
    longitude(s.lon_deg, ctx, "lon_deg")?;
    let h = s.array_height_m;
    check(h.is_finite() && (0.0..=1000.0).contains(&h), ctx, "array_height_m", || {
        format!("an array height between 0 and 1000 m, got {h}")
    })?;
    heading(s.heading_deg, ctx)?;
    let v = s.speed_mps;
    check(v.is_finite() && (0.0..=40.0).contains(&v), ctx, "speed_mps", || {
        format!("a ship speed between 0 and 40 m/s, got {v}")
    })?;
    s.radar.validate().map_err(|(field, expected)| ctx.sub("radar").err(&field, expected))
}

pub(crate) fn validate_type(t: &AircraftType, ctx: &Ctx) -> Result<(), ScenarioError> {
    validate_rcs(t.rcs_m2, ctx, "rcs_m2")?;
    if let Some(p) = &t.polarimetry {
        p.validate().map_err(|(field, expected)| ctx.sub("polarimetry").err(&field, expected))?;
    }
    validate_envelope(&t.envelope(), ctx)
}

fn validate_rcs(rcs: f64, ctx: &Ctx, field: &str) -> Result<(), ScenarioError> {
    check(rcs.is_finite() && rcs > 0.0 && rcs <= 1e6, ctx, field, || format!("a mean RCS in (0, 1e6] m², got {rcs}"))
}

fn validate_envelope(e: &Envelope, ctx: &Ctx) -> Result<(), ScenarioError> {
    let (lo, hi) = (e.min_speed_mps, e.max_speed_mps);
    check(lo.is_finite() && lo >= 0.0, ctx, "min_speed_mps", || format!("a speed of 0 m/s or more, got {lo}"))?;
    check(hi.is_finite() && hi > lo && hi <= 3000.0, ctx, "max_speed_mps", || {
        format!("a speed above min_speed_mps ({lo}) and at most 3000 m/s, got {hi}")
    })?;
    let g = e.max_accel_g;
    check(g.is_finite() && g > 0.0 && g <= 100.0, ctx, "max_accel_g", || {
        format!("an acceleration limit in (0, 100] g, got {g}")
    })
}

fn validate_id(id: &str, ctx: &Ctx, field: &str) -> Result<(), ScenarioError> {
    let ok = !id.is_empty() && id.len() <= 64 && id.chars().all(|c| c.is_alphanumeric() || "-_.".contains(c));
    check(ok, ctx, field, || format!("an id of 1–64 letters, digits, `-`, `_` or `.`, got `{id}`"))
}

fn validate_start(start: &LatLonAlt, heading_deg: f64, speed_mps: f64, ctx: &Ctx) -> Result<(), ScenarioError> {
    let s = ctx.sub("start");
    latitude(start.lat_deg, 89.0, &s, "lat_deg")?;
    longitude(start.lon_deg, &s, "lon_deg")?;
    let h = start.alt_m;
    check(h.is_finite() && (-100.0..=30_000.0).contains(&h), &s, "alt_m", || {
        format!("an altitude between -100 and 30000 m, got {h}")
    })?;
    heading(heading_deg, ctx)?;
    check(speed_mps.is_finite() && speed_mps > 0.0 && speed_mps <= 1500.0, ctx, "speed_mps", || {
        format!("a speed in (0, 1500] m/s, got {speed_mps}")
    })
}

fn validate_offset(o: Offset, ctx: &Ctx) -> Result<(), ScenarioError> {
    for (name, v) in [("along_m", o.along_m), ("right_m", o.right_m), ("up_m", o.up_m)] {
        check(v.is_finite() && v.abs() <= 100_000.0, ctx, name, || format!("an offset within ±100 km, got {v}"))?;
    }
    Ok(())
}

/// A single aircraft.
pub(crate) fn validate_aircraft(a: &Aircraft, ctx: &Ctx) -> Result<(), ScenarioError> {
    validate_id(&a.id, ctx, "id")?;
    validate_start(&a.start, a.heading_deg, a.speed_mps, ctx)?;
    if let Some(rcs) = a.rcs_m2 {
        validate_rcs(rcs, ctx, "rcs_m2")?;
    }
    Controls::compile(&a.manoeuvres, 0.0, a.speed_mps, a.start.alt_m, ctx)?;
    Ok(())
}

/// A formation, including its split groups, recursively.
pub(crate) fn validate_formation(f: &Formation, ctx: &Ctx) -> Result<(), ScenarioError> {
    check(!f.name.trim().is_empty(), ctx, "name", || "a non-empty name".into())?;
    validate_start(&f.start, f.heading_deg, f.speed_mps, ctx)?;
    check(!f.members.is_empty(), ctx, "members", || "at least one member".into())?;
    let mut seen = HashSet::new();
    for (i, m) in f.members.iter().enumerate() {
        let c = ctx.sub(&format!("members[{i}]"));
        validate_id(&m.id, &c, "id")?;
        check(seen.insert(m.id.as_str()), &c, "id", || format!("each member once, `{}` repeats", m.id))?;
        validate_offset(m.offset(), &c)?;
        if let Some(rcs) = m.rcs_m2 {
            validate_rcs(rcs, &c, "rcs_m2")?;
        }
    }
    let members: Vec<(String, Offset)> = f.members.iter().map(|m| (m.id.clone(), m.offset())).collect();
    validate_group_motion(
        &members,
        &f.manoeuvres,
        &f.crossovers,
        f.split.as_ref(),
        0.0,
        f.speed_mps,
        f.start.alt_m,
        ctx,
    )
}

#[allow(clippy::too_many_arguments)]
fn validate_group_motion(
    members: &[(String, Offset)],
    manoeuvres: &[Manoeuvre],
    crossovers: &[crate::model::Crossover],
    split: Option<&Split>,
    t_begin: f64,
    v0: f64,
    h0: f64,
    ctx: &Ctx,
) -> Result<(), ScenarioError> {
    let controls = Controls::compile(manoeuvres, t_begin, v0, h0, ctx)?;
    let tracks = compile_offsets(members, crossovers, t_begin, ctx)?;
    let Some(split) = split else {
        return Ok(());
    };
    let sc = ctx.sub("split");
    let at = split.at_s;
    check(at.is_finite() && at > t_begin, &sc, "at_s", || format!("a split time after {t_begin} s, got {at}"))?;
    if let Some(end) = controls.last_end() {
        check(end <= at + 1e-9, &sc, "at_s", || {
            format!(
                "a split time after the group's last manoeuvre ends ({end:.3} s; manoeuvres after \
                 a split belong to its groups), got {at}"
            )
        })?;
    }
    if let Some(x) = crossovers.last() {
        let end = x.start_s + x.duration_s;
        check(end <= at + 1e-9, &sc, "at_s", || {
            format!("a split time after the group's last crossover ends ({end} s), got {at}")
        })?;
    }
    check(!split.groups.is_empty(), &sc, "groups", || "at least one group".into())?;
    let mut assigned: HashSet<&str> = HashSet::new();
    let v_split = controls.eval(at).speed_mps;
    let h_split = controls.altitude(at);
    for (gi, g) in split.groups.iter().enumerate() {
        let gc = sc.sub(&format!("groups[{gi}]"));
        check(!g.name.trim().is_empty(), &gc, "name", || "a non-empty name".into())?;
        check(!g.members.is_empty(), &gc, "members", || "at least one member".into())?;
        let mut offsets = Vec::with_capacity(g.members.len());
        for (j, id) in g.members.iter().enumerate() {
            let Some(q) = members.iter().position(|(m, _)| m == id) else {
                let ids: Vec<&str> = members.iter().map(|(m, _)| m.as_str()).collect();
                return Err(gc.err(
                    &format!("members[{j}]"),
                    format!("a member of the group that splits ({}), got `{id}`", ids.join(", ")),
                ));
            };
            check(assigned.insert(id.as_str()), &gc, &format!("members[{j}]"), || {
                format!("each member in one group only, `{id}` is in two")
            })?;
            offsets.push(tracks[q].at(at).0);
        }
        let reference = match g.reference {
            Some(r) => {
                validate_offset(r, &gc.sub("reference"))?;
                r
            }
            None => centroid(&offsets),
        };
        let rel: Vec<(String, Offset)> =
            g.members.iter().zip(&offsets).map(|(id, o)| (id.clone(), *o - reference)).collect();
        validate_group_motion(
            &rel,
            &g.manoeuvres,
            &g.crossovers,
            g.split.as_ref(),
            at,
            v_split,
            h_split + reference.up_m,
            &gc,
        )?;
    }
    let missing: Vec<&str> = members.iter().map(|(m, _)| m.as_str()).filter(|m| !assigned.contains(m)).collect();
    check(missing.is_empty(), &sc, "groups", || format!("every member in some group, missing: {}", missing.join(", ")))
}

/// Ids of a formation's members.
pub(crate) fn formation_ids(f: &Formation) -> impl Iterator<Item = &str> {
    f.members.iter().map(|m| m.id.as_str())
}

impl Scenario {
    /// Check the whole resolved scenario: every value physically possible, ships numbered R1…
    /// in order, at least one target, every target flown by exactly one formation or aircraft
    /// (and every flown aircraft a target), manoeuvres and crossovers in order. The loaders call
    /// this; call it yourself on a scenario read back from a manifest.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        let ctx = Ctx::new(&format!("scenario `{}`", self.name), "");
        validate_duration(self.duration_s, &ctx)?;
        validate_fidelity(&self.fidelity, &ctx.sub("fidelity"))?;
        if self.ships.is_empty() {
            return Err(ctx.err("ships", "at least one ship"));
        }
        for (i, s) in self.ships.iter().enumerate() {
            validate_ship(s, i, &ctx.sub(&format!("ships[{i}]")))?;
        }
        self.biases.validate(self.ships.len(), &ctx.sub("biases"))?;
        self.links.validate(self.ships.len(), &ctx.sub("links"))?;
        if self.targets.is_empty() {
            return Err(ctx.err("targets", "at least one target"));
        }
        let mut flown: Vec<(&str, &str)> = Vec::new(); // (id, kind)
        for (i, f) in self.formations.iter().enumerate() {
            let c = ctx.sub(&format!("formations[{i}]"));
            validate_formation(f, &c)?;
            flown.extend(formation_ids(f).map(|id| (id, f.kind.as_str())));
        }
        for (i, a) in self.aircraft.iter().enumerate() {
            validate_aircraft(a, &ctx.sub(&format!("aircraft[{i}]")))?;
            flown.push((a.id.as_str(), a.kind.as_str()));
        }
        let mut ids = HashSet::new();
        for (i, t) in self.targets.iter().enumerate() {
            let c = ctx.sub(&format!("targets[{i}]"));
            validate_target(t, &c)?;
            check(ids.insert(t.id.as_str()), &c, "id", || format!("unique target ids, `{}` repeats", t.id))?;
            let n = flown.iter().filter(|(id, _)| *id == t.id).count();
            check(n == 1, &c, "id", || {
                format!("a target flown by exactly one formation or aircraft, `{}` is flown by {n}", t.id)
            })?;
            if let Some((_, kind)) = flown.iter().find(|(id, _)| *id == t.id) {
                check(*kind == t.kind, &c, "kind", || {
                    format!("the type of the aircraft that flies it (`{kind}`), got `{}`", t.kind)
                })?;
            }
        }
        if let Some((id, _)) = flown.iter().find(|(id, _)| !ids.contains(id)) {
            return Err(ctx.err("targets", format!("every flown aircraft listed as a target, `{id}` is not")));
        }
        Ok(())
    }
}

fn validate_target(t: &Target, ctx: &Ctx) -> Result<(), ScenarioError> {
    validate_id(&t.id, ctx, "id")?;
    check(!t.kind.is_empty(), ctx, "kind", || "an aircraft type name".into())?;
    validate_rcs(t.rcs_m2, ctx, "rcs_m2")?;
    validate_envelope(&t.envelope, &ctx.sub("envelope"))
}

/// Keep only the listed targets in a formation: drop other members, their crossover moves and
/// split-group entries, and groups (and crossovers) left empty. Returns `None` if no member is
/// left. Split-group reference points must already be explicit, so that the remaining members
/// fly exactly as in the full formation.
pub(crate) fn prune_formation(f: &Formation, keep: &HashSet<&str>) -> Option<Formation> {
    let members: Vec<_> = f.members.iter().filter(|m| keep.contains(m.id.as_str())).cloned().collect();
    if members.is_empty() {
        return None;
    }
    Some(Formation {
        members,
        crossovers: prune_crossovers(&f.crossovers, keep),
        split: f.split.as_ref().and_then(|s| prune_split(s, keep)),
        ..f.clone()
    })
}

fn prune_crossovers(xs: &[crate::model::Crossover], keep: &HashSet<&str>) -> Vec<crate::model::Crossover> {
    xs.iter()
        .filter_map(|x| {
            let moves: Vec<_> = x.moves.iter().filter(|m| keep.contains(m.id.as_str())).cloned().collect();
            (!moves.is_empty()).then(|| crate::model::Crossover { moves, ..x.clone() })
        })
        .collect()
}

fn prune_split(s: &Split, keep: &HashSet<&str>) -> Option<Split> {
    let groups: Vec<Group> = s
        .groups
        .iter()
        .filter_map(|g| {
            let members: Vec<String> = g.members.iter().filter(|m| keep.contains(m.as_str())).cloned().collect();
            (!members.is_empty()).then(|| Group {
                name: g.name.clone(),
                members,
                reference: g.reference,
                manoeuvres: g.manoeuvres.clone(),
                crossovers: prune_crossovers(&g.crossovers, keep),
                split: g.split.as_ref().and_then(|s| prune_split(s, keep)),
            })
        })
        .collect();
    (!groups.is_empty()).then_some(Split { at_s: s.at_s, groups })
}

/// Make every split group's reference point explicit (the centroid of its members' offsets at
/// the split, unless given), so that pruning members later never moves the others.
pub(crate) fn fix_references(f: &mut Formation) {
    let members: Vec<(String, Offset)> = f.members.iter().map(|m| (m.id.clone(), m.offset())).collect();
    let ctx = Ctx::new("", "");
    if let Some(split) = f.split.as_mut() {
        fix_split(&members, &f.crossovers, split, &ctx);
    }
}

fn fix_split(members: &[(String, Offset)], crossovers: &[crate::model::Crossover], split: &mut Split, ctx: &Ctx) {
    // Validated before: compiling cannot fail here, but stay total anyway.
    let Ok(tracks) = compile_offsets(members, crossovers, 0.0, ctx) else {
        return;
    };
    for g in &mut split.groups {
        let offsets: Vec<Offset> = g
            .members
            .iter()
            .filter_map(|id| members.iter().position(|(m, _)| m == id).map(|q| tracks[q].at(split.at_s).0))
            .collect();
        let reference = *g.reference.get_or_insert_with(|| centroid(&offsets));
        if let Some(inner) = g.split.as_mut() {
            let rel: Vec<(String, Offset)> =
                g.members.iter().zip(&offsets).map(|(id, o)| (id.clone(), *o - reference)).collect();
            fix_split(&rel, &g.crossovers, inner, ctx);
        }
    }
}
