//! Usage by purpose (docs/design.md §6): every transmit `dwells` row (role `tx` or `txrx`)
//! attributed to one [`Purpose`] by [`crate::purpose_rule`], its count, dwell time and energy
//! summed per run, radar and scoring interval.
//!
//! Each dwells file is read once, in the one pass over the dwells that also gives the usage sums
//! ([`crate::dwell_pass`], through the dwells reader `mimo_store::dwell_chunks`), or batch by
//! batch by the checked Arrow reader ([`crate::purpose_read`]) when that pass gives up: search rows are added as they come; the other rows (a few per cent) are kept, grouped into their looks by
//! `(run, group_id)` and classified with the truth of their run at each look's mid-time (the
//! truth samples interpolated as the track metrics interpolate them), then added in row order,
//! so the sums never depend on the thread count. Files are summed again in file order.

use crate::purpose_read::{Batch, for_batches};
use crate::purpose_rule::{BeamGeometry, LookPart, Purpose, holds_truth};
use crate::track_metrics::{TruthSample, truth_at};
use crate::truth_reach::TruthBalls;
use crate::{MetricsError, PurposeUsage, UsageByPurposeRow, UsagePair};
use glam::DVec3;
use mimo_core::records::{DwellColumns, DwellKind, DwellRow, Role, TruthColumns, TruthRow};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// Count, dwell time and energy of some transmit rows.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct PurposeSum {
    pub dwells: u32,
    pub dwell_time_s: f64,
    pub energy_j: f64,
}

impl PurposeSum {
    fn add(&mut self, dwell_time_s: f64, energy_j: f64) {
        self.dwells = self.dwells.saturating_add(1);
        self.dwell_time_s += dwell_time_s;
        self.energy_j += energy_j;
    }

    fn add_sum(&mut self, o: &PurposeSum) {
        self.dwells = self.dwells.saturating_add(o.dwells);
        self.dwell_time_s += o.dwell_time_s;
        self.energy_j += o.energy_j;
    }
}

/// One file's sums per (run, index of the radar among the file's radars, interval).
type FileSums = Vec<((u32, usize, i64), [PurposeSum; 5])>;

/// Sums per (run, radar, interval), one per purpose in [`Purpose::ALL`] order.
pub(crate) type PurposeSums = BTreeMap<(u32, String, i64), [PurposeSum; 5]>;

/// Where the usage by purpose reads from, and how.
pub(crate) struct PurposeInput<'a> {
    pub dwells: &'a [PathBuf],
    pub truth: &'a [PathBuf],
    pub geometry: &'a BeamGeometry,
    pub interval_s: f64,
    pub threads: usize,
}

/// One non-search row of a dwells file.
#[derive(Debug, Clone)]
struct Part {
    row: usize,
    run: u32,
    group: u64,
    radar: usize,
    role: Role,
    kind: DwellKind,
    t_s: f64,
    duration_s: f64,
    energy_j: f64,
    face: u8,
    beam: (f64, f64),
    aim: DVec3,
}

/// A file's rows as read: the search sums and the other parts.
#[derive(Default)]
pub(crate) struct FileRows {
    radars: Vec<String>,
    sums: FileSums,
    /// Index in `sums` of each key.
    index: HashMap<(u32, usize, i64), usize>,
    /// The latest key of each (run, radar) and its index in `sums`, so that most rows find
    /// their sums without hashing.
    latest: Vec<((u32, usize, i64), usize)>,
    parts: Vec<Part>,
}

/// The columns of some rows of a dwells file that the usage by purpose reads, its labels
/// parsed (radars as indices among the file's radars in order of first appearance).
pub(crate) struct PurposeCols<'a> {
    /// Index of the first row in the file.
    pub first_row: usize,
    pub run: &'a [u32],
    pub group: &'a [u64],
    pub radar: &'a [usize],
    pub role: &'a [Role],
    pub kind: &'a [DwellKind],
    pub t_s: &'a [f64],
    pub duration_s: &'a [f64],
    pub energy_j: &'a [f64],
    pub face: &'a [u8],
    pub beam_u: &'a [f64],
    pub beam_v: &'a [f64],
    pub aim_m: [&'a [f64]; 3],
}

/// The dwells table's column names (from its declaration).
const D: DwellColumns = DwellRow::COLUMNS;
/// The truth table's column names (from its declaration).
const T: TruthColumns = TruthRow::COLUMNS;

/// The dwells columns read.
const COLUMNS: [&str; 14] = [
    D.run,
    D.group_id,
    D.radar,
    D.role,
    D.kind,
    D.t_s,
    D.duration_s,
    D.energy_j,
    D.face,
    D.beam_u,
    D.beam_v,
    D.aim_x_m,
    D.aim_y_m,
    D.aim_z_m,
];

fn interval_of(t_s: f64, interval_s: f64) -> i64 {
    (t_s / interval_s) as i64 + 1
}

impl FileRows {
    fn radar_index(&mut self, name: &str) -> usize {
        match self.radars.iter().position(|r| r == name) {
            Some(i) => i,
            None => {
                self.radars.push(name.to_string());
                self.radars.len() - 1
            }
        }
    }

    /// What was read, for comparisons in tests: radars, sums and parts in order.
    #[cfg(test)]
    pub(crate) fn view(&self) -> String {
        format!("{:?} {:?} {:?}", self.radars, self.sums, self.parts)
    }

    /// The file's radars, in order of first appearance (when read by another reader).
    pub(crate) fn set_radars(&mut self, radars: Vec<String>) {
        self.radars = radars;
    }

    /// The sums of key (run, radar, interval), created at zero.
    fn slot(&mut self, key: (u32, usize, i64)) -> &mut [PurposeSum; 5] {
        let latest = self.latest.iter().position(|(k, _)| (k.0, k.1) == (key.0, key.1));
        let i = match latest {
            Some(l) if self.latest[l].0 == key => self.latest[l].1,
            _ => {
                let next = self.sums.len();
                let i = *self.index.entry(key).or_insert(next);
                if i == next {
                    self.sums.push((key, [PurposeSum::default(); 5]));
                }
                match latest {
                    Some(l) => self.latest[l] = (key, i),
                    None => self.latest.push((key, i)),
                }
                i
            }
        };
        &mut self.sums[i].1
    }

    /// One batch read by the Arrow reader: its labels parsed, then [`Self::add`].
    fn batch(&mut self, b: &Batch<'_>, interval_s: f64) -> Result<(), MetricsError> {
        let (run, group, face) = (b.u32(D.run)?, b.u64(D.group_id)?, b.u8(D.face)?);
        let (radar, role, kind) = (b.utf8(D.radar)?, b.utf8(D.role)?, b.utf8(D.kind)?);
        let (t, dur, energy) = (b.f64(D.t_s)?, b.f64(D.duration_s)?, b.f64(D.energy_j)?);
        let (bu, bv) = (b.f64(D.beam_u)?, b.f64(D.beam_v)?);
        let (ax, ay, az) = (b.f64(D.aim_x_m)?, b.f64(D.aim_y_m)?, b.f64(D.aim_z_m)?);
        let (mut roles, mut kinds, mut radars) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..b.len() {
            let Some(role) = Role::parse(role.value(i)) else {
                return Err(b.invalid(D.role, i, role.value(i).to_string(), "tx, rx or txrx"));
            };
            let Some(kind) = DwellKind::parse(kind.value(i)) else {
                return Err(b.invalid(D.kind, i, kind.value(i).to_string(), "search, confirm, track or mimo"));
            };
            roles.push(role);
            kinds.push(kind);
            radars.push(self.radar_index(radar.value(i)));
        }
        self.add(
            &PurposeCols {
                first_row: b.first_row,
                run: run.values(),
                group: group.values(),
                radar: &radars,
                role: &roles,
                kind: &kinds,
                t_s: t.values(),
                duration_s: dur.values(),
                energy_j: energy.values(),
                face: face.values(),
                beam_u: bu.values(),
                beam_v: bv.values(),
                aim_m: [ax.values(), ay.values(), az.values()],
            },
            interval_s,
        );
        Ok(())
    }

    /// Some rows: search rows summed (transmit ones), other rows kept.
    pub(crate) fn add(&mut self, c: &PurposeCols<'_>, interval_s: f64) {
        for i in 0..c.run.len() {
            let (role, kind, r) = (c.role[i], c.kind[i], c.radar[i]);
            if kind == DwellKind::Search {
                if role != Role::Rx {
                    let slot = self.slot((c.run[i], r, interval_of(c.t_s[i], interval_s)));
                    slot[Purpose::Search.index()].add(c.duration_s[i], c.energy_j[i]);
                }
                continue;
            }
            self.parts.push(Part {
                row: c.first_row + i,
                run: c.run[i],
                group: c.group[i],
                radar: r,
                role,
                kind,
                t_s: c.t_s[i],
                duration_s: c.duration_s[i],
                energy_j: c.energy_j[i],
                face: c.face[i],
                beam: (c.beam_u[i], c.beam_v[i]),
                aim: DVec3::new(c.aim_m[0][i], c.aim_m[1][i], c.aim_m[2][i]),
            });
        }
    }
}

/// Each target's truth samples of one run, sorted by time.
type RunTruth = Vec<Vec<TruthSample>>;

/// One run's targets as read: (name, samples in file order), in order of first appearance.
#[derive(Default)]
struct RunTargets {
    targets: Vec<(String, Vec<TruthSample>)>,
    /// Index in `targets` of each name.
    index: HashMap<String, usize>,
    /// The target of the row before, whose successor is tried first (the truth is written time
    /// by time, its targets in the same order each time).
    last: usize,
}

impl RunTargets {
    /// The samples of target `name`, found without building a string unless it is new.
    fn samples(&mut self, name: &str) -> &mut Vec<TruthSample> {
        let n = self.targets.len();
        let next = if n == 0 { 0 } else { (self.last + 1) % n };
        let i = if n > 0 && self.targets[next].0 == name {
            next
        } else {
            match self.index.get(name) {
                Some(&i) => i,
                None => {
                    self.index.insert(name.to_string(), n);
                    self.targets.push((name.to_string(), Vec::new()));
                    n
                }
            }
        };
        self.last = i;
        &mut self.targets[i].1
    }
}

/// The truth of `runs` from the truth files: each run's targets in name order, each target's
/// samples sorted by time (stably, so samples of one time keep their file order).
fn load_truth(paths: &[PathBuf], runs: &BTreeSet<u32>) -> Result<BTreeMap<u32, RunTruth>, MetricsError> {
    let mut slot_of_run: BTreeMap<u32, usize> = BTreeMap::new();
    let mut slots: Vec<RunTargets> = Vec::new();
    for path in paths {
        let mut chunks = crate::load::open_rows::<TruthRow>(path)?;
        while let Some(batch) = chunks.next_batch()? {
            let b = chunks.view(&batch);
            let (run, target, t, alt) =
                (b.u32_values(T.run)?, b.utf8(T.target)?, b.f64_values(T.t_s)?, b.f64_values(T.alt_m)?);
            let (x, y, z) = (b.f64_values(T.x_m)?, b.f64_values(T.y_m)?, b.f64_values(T.z_m)?);
            let (vx, vy, vz) = (b.f64_values(T.vx_mps)?, b.f64_values(T.vy_mps)?, b.f64_values(T.vz_mps)?);
            // The slot of the row's run, looked up when the run changes (`None`: not scored).
            let mut current: Option<(u32, Option<usize>)> = None;
            for i in 0..b.num_rows() {
                let slot = match current {
                    Some((r, slot)) if r == run[i] => slot,
                    _ => {
                        let slot = runs.contains(&run[i]).then(|| {
                            *slot_of_run.entry(run[i]).or_insert_with(|| {
                                slots.push(RunTargets::default());
                                slots.len() - 1
                            })
                        });
                        current = Some((run[i], slot));
                        slot
                    }
                };
                let Some(slot) = slot else { continue };
                let sample = TruthSample {
                    t: t[i],
                    p: DVec3::new(x[i], y[i], z[i]),
                    v: DVec3::new(vx[i], vy[i], vz[i]),
                    alt: alt[i],
                };
                slots[slot].samples(target.value(i)).push(sample);
            }
        }
    }
    let mut out: BTreeMap<u32, RunTruth> = BTreeMap::new();
    for (run, slot) in slot_of_run {
        let mut targets = std::mem::take(&mut slots[slot].targets);
        targets.sort_by(|a, b| a.0.cmp(&b.0));
        let samples = targets.into_iter().map(|(_, mut samples)| {
            samples.sort_by(|a, b| a.t.total_cmp(&b.t));
            samples
        });
        out.insert(run, samples.collect());
    }
    Ok(out)
}

/// The position of a target at `t_s`, if inside its sampled span.
fn position_at(samples: &[TruthSample], t_s: f64) -> Option<DVec3> {
    let mut cursor = samples.partition_point(|s| s.t <= t_s).saturating_sub(1);
    truth_at(samples, &mut cursor, t_s).map(|(p, _, _)| p)
}

/// The look part of `p` at `t_s`, if the geometry knows its radar and face.
fn look_part(rows: &FileRows, geometry: &BeamGeometry, p: &Part, t_s: f64) -> Option<LookPart> {
    let (frame, theta_u, theta_v) = geometry.face(&rows.radars[p.radar], p.face, t_s)?;
    let (beam_u, beam_v) = p.beam;
    Some(LookPart { frame, theta_u, theta_v, beam_u, beam_v, receives: p.role != Role::Tx })
}

/// The purpose of each transmit part of one look (its parts, any order), as (row, part index,
/// purpose).
fn classify_look(
    rows: &FileRows,
    look: &[usize],
    geometry: &BeamGeometry,
    truth: Option<&RunTruth>,
    balls: &[TruthBalls],
    out: &mut Vec<(usize, usize, Purpose)>,
) {
    for &ti in look {
        let tx = &rows.parts[ti];
        if tx.role == Role::Rx {
            continue;
        }
        let t_mid = tx.t_s + 0.5 * tx.duration_s;
        let held = look_part(rows, geometry, tx, t_mid).is_some_and(|tx_part| {
            let receivers: Vec<LookPart> = look
                .iter()
                .map(|&ri| &rows.parts[ri])
                .filter(|r| r.role != Role::Tx)
                .filter_map(|r| look_part(rows, geometry, r, t_mid))
                .collect();
            truth.into_iter().flatten().enumerate().any(|(k, samples)| {
                // A target surely outside the transmitter's footprint is not interpolated.
                if balls.get(k).is_some_and(|b| b.surely_outside(&tx_part, t_mid)) {
                    return false;
                }
                position_at(samples, t_mid).is_some_and(|p| holds_truth(&tx_part, &receivers, tx.aim, p))
            })
        });
        if let Some(purpose) = Purpose::of_look(tx.kind, held) {
            out.push((tx.row, ti, purpose));
        }
    }
}

/// The truth files holding each run.
pub(crate) type TruthFiles = BTreeMap<u32, Vec<usize>>;

/// One file's radars and sums by purpose.
pub(crate) type FilePurposeSums = (Vec<String>, FileSums);

/// One dwells file's rows read with the Arrow reader, every column checked.
pub(crate) fn read_rows(path: &Path, interval_s: f64) -> Result<FileRows, MetricsError> {
    let mut rows = FileRows::default();
    for_batches(DwellRow::TABLE, path, &COLUMNS, |b| rows.batch(b, interval_s))?;
    Ok(rows)
}

/// One dwells file's rows reduced to its sums by purpose: the looks classified with the truth of
/// their runs and added in row order.
pub(crate) fn classify(
    mut rows: FileRows,
    input: &PurposeInput<'_>,
    truth_files: &TruthFiles,
) -> Result<FilePurposeSums, MetricsError> {
    let runs: BTreeSet<u32> = rows.parts.iter().map(|p| p.run).collect();
    let files: BTreeSet<usize> = runs.iter().filter_map(|r| truth_files.get(r)).flatten().copied().collect();
    let files: Vec<PathBuf> = files.into_iter().map(|i| input.truth[i].clone()).collect();
    let truth = load_truth(&files, &runs)?;
    let balls: BTreeMap<u32, Vec<TruthBalls>> =
        truth.iter().map(|(&run, targets)| (run, targets.iter().map(|t| TruthBalls::of(t)).collect())).collect();
    let mut order: Vec<usize> = (0..rows.parts.len()).collect();
    order.sort_by_key(|&i| (rows.parts[i].run, rows.parts[i].group, rows.parts[i].row));
    let mut classified = Vec::new();
    for look in
        order.chunk_by(|&a, &b| (rows.parts[a].run, rows.parts[a].group) == (rows.parts[b].run, rows.parts[b].group))
    {
        let run = rows.parts[look[0]].run;
        let run_balls = balls.get(&run).map_or(&[][..], Vec::as_slice);
        classify_look(&rows, look, input.geometry, truth.get(&run), run_balls, &mut classified);
    }
    classified.sort_by_key(|c| c.0);
    let parts = std::mem::take(&mut rows.parts);
    for (_, i, purpose) in classified {
        let p = &parts[i];
        let slot = rows.slot((p.run, p.radar, interval_of(p.t_s, input.interval_s)));
        slot[purpose.index()].add(p.duration_s, p.energy_j);
    }
    Ok((rows.radars, rows.sums))
}

/// Which truth files hold each run (their `run` column only), so that each dwells file reads
/// the truth of its own runs.
pub(crate) fn truth_files(input: &PurposeInput<'_>) -> Result<TruthFiles, MetricsError> {
    let runs_of_file = crate::parallel::parallel(input.truth, input.threads, &|path: &PathBuf| {
        let mut runs = BTreeSet::new();
        for_batches(TruthRow::TABLE, path, &[T.run], |b| {
            runs.extend(b.u32(T.run)?.values().iter().copied());
            Ok(())
        })
        .map(|()| runs)
    });
    let mut truth_files = TruthFiles::new();
    for (i, runs) in runs_of_file.into_iter().enumerate() {
        for run in runs? {
            truth_files.entry(run).or_default().push(i);
        }
    }
    Ok(truth_files)
}

/// The files' sums by purpose summed by run, radar and interval, in file order (the first error
/// in that order returned).
pub(crate) fn merge(per_file: Vec<Result<FilePurposeSums, MetricsError>>) -> Result<PurposeSums, MetricsError> {
    let mut out = PurposeSums::new();
    for file in per_file {
        let (radars, sums) = file?;
        // Keys in a fixed order, so files and keys are added in the same order every time.
        let sorted: BTreeMap<(u32, &str, i64), [PurposeSum; 5]> =
            sums.into_iter().map(|((run, r, k), s)| ((run, radars[r].as_str(), k), s)).collect();
        for ((run, radar, k), s) in sorted {
            let slot = out.entry((run, radar.to_string(), k)).or_default();
            for (a, b) in slot.iter_mut().zip(&s) {
                a.add_sum(b);
            }
        }
    }
    Ok(out)
}

/// The table rows and per-run totals of the sums.
pub(crate) struct PurposeOutput {
    /// One row per run, radar, scoring interval and purpose.
    pub rows: Vec<UsageByPurposeRow>,
    /// Per run: every transmit row of every radar and interval (also after the last scoring time).
    pub per_run: BTreeMap<u32, PurposeUsage>,
    /// `per_run` averaged over runs.
    pub mean: PurposeUsage,
}

fn usage_of(s: &[PurposeSum; 5]) -> PurposeUsage {
    let pair = |p: Purpose| UsagePair { dwell_time_s: s[p.index()].dwell_time_s, energy_j: s[p.index()].energy_j };
    PurposeUsage {
        search: pair(Purpose::Search),
        confirm_true: pair(Purpose::ConfirmTrue),
        confirm_false: pair(Purpose::ConfirmFalse),
        track: pair(Purpose::Track),
        track_false: pair(Purpose::TrackFalse),
    }
}

/// Rows for every run of `runs`, radar of `radars` (in that order), scoring interval
/// `1..=K_run` (`n_times[run]`) and purpose, zeros included; totals per run and their mean.
pub(crate) fn purpose_output(
    sums: &PurposeSums,
    runs: &[u32],
    radars: &[String],
    n_times: &BTreeMap<u32, usize>,
    interval_s: f64,
) -> PurposeOutput {
    let zero = [PurposeSum::default(); 5];
    let mut rows = Vec::new();
    for &run in runs {
        let k_max = n_times.get(&run).copied().unwrap_or(0);
        for radar in radars {
            for k in 1..=k_max {
                let s = sums.get(&(run, radar.clone(), k as i64)).unwrap_or(&zero);
                for p in Purpose::ALL {
                    let v = s[p.index()];
                    rows.push(UsageByPurposeRow {
                        run,
                        interval: k as u32,
                        t_start_s: (k - 1) as f64 * interval_s,
                        t_end_s: k as f64 * interval_s,
                        radar: radar.clone(),
                        purpose: p.name().to_string(),
                        dwells: v.dwells,
                        dwell_time_s: v.dwell_time_s,
                        energy_j: v.energy_j,
                    });
                }
            }
        }
    }
    let mut totals: BTreeMap<u32, [PurposeSum; 5]> = runs.iter().map(|&r| (r, zero)).collect();
    for ((run, _, _), s) in sums {
        if let Some(t) = totals.get_mut(run) {
            for (a, b) in t.iter_mut().zip(s) {
                a.add_sum(b);
            }
        }
    }
    let per_run: BTreeMap<u32, PurposeUsage> = totals.iter().map(|(&r, s)| (r, usage_of(s))).collect();
    let n = totals.len().max(1) as f64;
    let mut acc = zero;
    for s in totals.values() {
        for (a, b) in acc.iter_mut().zip(s) {
            a.add_sum(b);
        }
    }
    for a in &mut acc {
        a.dwell_time_s /= n;
        a.energy_j /= n;
    }
    PurposeOutput { rows, per_run, mean: usage_of(&acc) }
}
