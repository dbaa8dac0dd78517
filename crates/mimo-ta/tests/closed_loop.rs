//! The default test article in the closed loop: what the engine delivers to it and when,
//! timelines under its load, truth never reaching it, determinism, stability through the
//! crossover and break-up, coverage loss and re-acquisition, completeness over the full standard
//! scenarios, and the open-loop replay reproducing the closed loop.
//!
//! Every run has a fixed seed.

#[path = "../../mimo-sim/tests/common/mod.rs"]
mod common;

use common::{check_stats, config, end_of, groups, run, standard, timelines};
use mimo_core::DVec3;
use mimo_core::assign::assign_with_miss;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, DwellRow, Requester, RunTables, TrackRow, TrackStatus};
use mimo_core::time::SimTime;
use mimo_sim::messages::{DwellFilter, DwellReport, Reply, Request, StartInfo, Subscription};
use mimo_sim::test_article::{TaFault, TestArticle};
use mimo_sim::{EngineConfig, EngineError, RunStats, TaInfo, World};
use mimo_ta::registry;
use mimo_ta::replay::{ReplayFrom, replay};
use std::collections::BTreeMap;
use std::sync::Mutex;

fn default_ta(world: &World) -> Box<dyn TestArticle + '_> {
    registry::build("default", &registry::default_config("default").expect("config"), world).expect("default TA")
}

/// A test article wrapped to record every call the engine makes to it and every wake-up asked
/// for (by the wrapped TA or added by the test). It subscribes to every dwell.
struct Recorder<'w> {
    inner: Box<dyn TestArticle + 'w>,
    extra_wakes: Vec<f64>,
    calls: Vec<Call>,
    /// Wake-up times requested, as the engine must schedule them (never before "now").
    wakes_requested: Vec<f64>,
    keep_reports: bool,
    reports: Vec<DwellReport>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Call {
    Dwell { ctx_t: f64, group: u64, t_mid: f64, duration: f64 },
    Wake { ctx_t: f64, t: f64 },
}

impl<'w> Recorder<'w> {
    fn new(inner: Box<dyn TestArticle + 'w>) -> Recorder<'w> {
        Recorder {
            inner,
            extra_wakes: Vec::new(),
            calls: Vec::new(),
            wakes_requested: Vec::new(),
            keep_reports: false,
            reports: Vec::new(),
        }
    }
    fn note(&mut self, now: f64, reqs: &[Request]) {
        for r in reqs {
            if let Request::WakeAt(t) = r
                && t.is_finite()
            {
                self.wakes_requested.push(t.max(now));
            }
        }
    }
}

impl TestArticle for Recorder<'_> {
    fn name(&self) -> &str {
        "recorder"
    }
    fn subscription(&self) -> Subscription {
        Subscription { dwells: DwellFilter::All, primitives: true, batch: false }
    }
    fn on_start(&mut self, start: &StartInfo) -> Result<Reply, TaFault> {
        let mut reply = self.inner.on_start(start)?;
        reply.requests.extend(self.extra_wakes.iter().map(|&t| Request::WakeAt(t)));
        self.note(0.0, &reply.requests);
        Ok(reply)
    }
    fn on_dwell(&mut self, report: &DwellReport) -> Result<Reply, TaFault> {
        self.calls.push(Call::Dwell {
            ctx_t: report.end_s,
            group: report.group_id,
            t_mid: report.t_s,
            duration: report.duration_s,
        });
        if self.keep_reports {
            self.reports.push(report.clone());
        }
        let reply = self.inner.on_dwell(report)?;
        self.note(report.end_s, &reply.requests);
        Ok(reply)
    }
    fn on_wake(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        self.calls.push(Call::Wake { ctx_t: t_s, t: t_s });
        let reply = self.inner.on_wake(t_s)?;
        self.note(t_s, &reply.requests);
        Ok(reply)
    }
    fn on_finish(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        self.inner.on_finish(t_s)
    }
}

/// A track's life as docs/design.md §6 scores it: from its first `confirmed` row (inclusive) to its
/// `deleted` row (exclusive); its state at a time is its latest row at or before that time,
/// extrapolated at constant velocity.
struct Life {
    id: u64,
    start: f64,
    end: f64,
    /// (t, position, velocity) of the rows before the deletion, by time.
    rows: Vec<(f64, DVec3, DVec3)>,
}

impl Life {
    fn at(&self, t: f64) -> Option<DVec3> {
        if t < self.start || t >= self.end {
            return None;
        }
        let k = self.rows.partition_point(|r| r.0 <= t);
        let (t0, p, v) = self.rows[k.checked_sub(1)?];
        Some(p + v * (t - t0))
    }
}

fn lives(tracks: &[TrackRow]) -> Vec<Life> {
    let mut by_id: BTreeMap<u64, Vec<&TrackRow>> = BTreeMap::new();
    for r in tracks {
        by_id.entry(r.track_id).or_default().push(r);
    }
    let mut out = Vec::new();
    for (id, mut rows) in by_id {
        rows.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
        let end = rows.iter().find(|r| r.status == TrackStatus::Deleted).map_or(f64::INFINITY, |r| r.t_s);
        let Some(start) = rows.iter().find(|r| r.status == TrackStatus::Confirmed && r.t_s < end).map(|r| r.t_s) else {
            continue;
        };
        let rows = rows
            .iter()
            .take_while(|r| r.status != TrackStatus::Deleted)
            .map(|r| (r.t_s, DVec3::new(r.x_m, r.y_m, r.z_m), DVec3::new(r.vx_mps, r.vy_mps, r.vz_mps)))
            .collect();
        out.push(Life { id, start, end, rows });
    }
    out
}

/// One-to-one gated pairing of `truths` with live track positions (most pairs, then least total
/// distance). Returns, per truth, the index of its track in `tracks` and the distance.
fn pair(truths: &[DVec3], tracks: &[DVec3], gate_m: f64) -> Vec<Option<(usize, f64)>> {
    let (n, m) = (truths.len(), tracks.len());
    let mut cost = vec![f64::INFINITY; n * m];
    for (i, p) in truths.iter().enumerate() {
        for (j, q) in tracks.iter().enumerate() {
            let d = (*p - *q).length();
            if d <= gate_m {
                cost[i * m + j] = d;
            }
        }
    }
    let miss = vec![gate_m * (n as f64 + 1.0); n];
    assign_with_miss(&cost, n, m, &miss)
        .into_iter()
        .enumerate()
        .map(|(i, c)| c.map(|j| (j, (truths[i] - tracks[j]).length())))
        .collect()
}

/// Live confirmed tracks at `t`: (track id, extrapolated position).
fn live_at(lives: &[Life], t: f64) -> Vec<(u64, DVec3)> {
    lives.iter().filter_map(|l| l.at(t).map(|p| (l.id, p))).collect()
}

/// Per-second track completeness: mean over scoring times with a scorable truth, the worst
/// second, and the number of such times.
fn completeness(world: &World, tracks: &[TrackRow], duration_s: f64) -> (f64, f64, usize) {
    let lives = lives(tracks);
    let mut sum = 0.0;
    let mut worst = 1.0f64;
    let mut n_times = 0;
    for k in 1..=(duration_s.floor() as u32) {
        let t = f64::from(k);
        let truths: Vec<DVec3> = world
            .targets_at(t)
            .into_iter()
            .filter(|x| world.scenario.ships.iter().any(|s| s.sees(t, x.pos_ecef, x.alt_m)))
            .map(|x| x.pos_ecef)
            .collect();
        if truths.is_empty() {
            continue;
        }
        let live: Vec<DVec3> = live_at(&lives, t).into_iter().map(|x| x.1).collect();
        let assigned = pair(&truths, &live, 1000.0).iter().filter(|x| x.is_some()).count();
        let c = assigned as f64 / truths.len() as f64;
        sum += c;
        worst = worst.min(c);
        n_times += 1;
    }
    (sum / n_times.max(1) as f64, worst, n_times)
}

// ---------------------------------------------------------------------------------------------
// Event order
// ---------------------------------------------------------------------------------------------

#[test]
fn reports_arrive_in_end_time_order_and_wakes_arrive_on_time() {
    let dur = 30.0;
    let world = standard(1, dur);
    let mut ta = Recorder::new(default_ta(&world));
    // Wake-ups at awkward times, one of them not on a whole nanosecond, one right now.
    ta.extra_wakes = vec![0.123_456_789, 1.5, 2.000_000_000_4, 7.25, 13.0, 13.0, 29.999_999_999, 0.0];
    let (tables, stats) = run(&world, &config(11, dur), &mut ta);
    check_stats(&tables, &stats);
    assert!(stats.ta_dwells > 50, "the default TA asked for dwells: {stats:?}");

    let g = groups(&tables.dwells);
    let mut last_ctx = f64::NEG_INFINITY;
    let mut last_end: Option<(f64, u64)> = None;
    let mut reported = Vec::new();
    for c in &ta.calls {
        let ctx_t = match *c {
            Call::Dwell { ctx_t, group, t_mid, duration } => {
                let rows = &g[&group];
                let end = end_of(rows[0]);
                // Delivered when the dwell ends; stamped with its mid-time.
                assert!((ctx_t - end).abs() < 2e-9, "group {group}: delivered at {ctx_t}, ends at {end}");
                assert!((t_mid - (rows[0].t_s + 0.5 * rows[0].duration_s)).abs() < 1e-9);
                assert_eq!(duration, rows[0].duration_s);
                if let Some((e, gid)) = last_end {
                    assert!(end >= e - 1e-9, "group {group} (end {end}) delivered after group {gid} (end {e})");
                    if (end - e).abs() < 1e-10 {
                        assert!(group > gid, "equal end times go in group order: {gid} then {group}");
                    }
                }
                last_end = Some((end, group));
                reported.push(group);
                ctx_t
            }
            Call::Wake { ctx_t, t } => {
                assert_eq!(ctx_t, t);
                ctx_t
            }
        };
        assert!(ctx_t >= last_ctx, "time went back: {last_ctx} then {ctx_t}");
        last_ctx = ctx_t;
    }
    // Every dwell of the run is reported exactly once.
    reported.sort_unstable();
    assert_eq!(reported, g.keys().copied().collect::<Vec<_>>());

    // Every wake-up asked for (up to the end of the run) arrives exactly when asked.
    let end = SimTime::from_secs(dur);
    let mut asked: Vec<f64> = ta.wakes_requested.iter().copied().filter(|&t| SimTime::from_secs(t) <= end).collect();
    asked.sort_by(f64::total_cmp);
    let mut got: Vec<f64> =
        ta.calls.iter().filter_map(|c| if let Call::Wake { t, .. } = c { Some(*t) } else { None }).collect();
    got.sort_by(f64::total_cmp);
    assert_eq!(asked.len(), got.len(), "asked {asked:?}\ngot {got:?}");
    for (a, b) in asked.iter().zip(&got) {
        assert!((a - b).abs() <= 1e-9, "wake asked for {a}, delivered at {b}");
    }
    for t in [0.123_456_789, 1.5, 7.25, 13.0, 29.999_999_999, 0.0] {
        assert!(got.iter().any(|g| (g - t).abs() <= 1e-9), "wake at {t} missing");
    }
    assert_eq!(got.iter().filter(|&&g| g == 13.0).count(), 2, "both wakes at 13 s are delivered");
}

// ---------------------------------------------------------------------------------------------
// Timelines under the default TA's load
// ---------------------------------------------------------------------------------------------

#[test]
fn no_radar_runs_two_dwells_at_once() {
    let dur = 40.0;
    let world = standard(7, dur);
    let mut ta = default_ta(&world);
    let (tables, stats) = run(&world, &config(3, dur), ta.as_mut());
    check_stats(&tables, &stats);
    let g = groups(&tables.dwells);
    let n_mimo = g.values().filter(|v| v.len() > 1).count();
    assert!(n_mimo > 10, "MIMO dwells ran: {n_mimo}");
    for (radar, line) in timelines(&tables.dwells) {
        for w in line.windows(2) {
            assert!(
                w[1].t_s >= end_of(w[0]) - 1e-9,
                "{radar}: dwell {} [{}, {}) overlaps dwell {} starting at {}",
                w[0].dwell_id,
                w[0].t_s,
                end_of(w[0]),
                w[1].dwell_id,
                w[1].t_s
            );
        }
        let last = line.last().expect("dwells");
        assert!(end_of(last) <= dur + 1e-9);
        assert!(line[0].t_s >= 0.0);
        let busy: f64 = line.iter().map(|d| d.duration_s).sum::<f64>() / dur;
        println!("{radar}: {} dwells, busy {:.4}", line.len(), busy);
    }
    // Every part of a group shares its time and length; group ids are the first part's id.
    for (gid, rows) in &g {
        assert_eq!(rows[0].dwell_id, *gid);
        for r in rows {
            assert_eq!(
                (r.t_s, r.duration_s, r.kind, r.requested_by),
                (rows[0].t_s, rows[0].duration_s, rows[0].kind, rows[0].requested_by)
            );
        }
        let mut radars: Vec<RadarId> = rows.iter().map(|r| r.radar).collect();
        radars.sort_unstable();
        radars.dedup();
        assert_eq!(radars.len(), rows.len(), "a radar appears once per group");
    }
}

// ---------------------------------------------------------------------------------------------
// What the TA sees
// ---------------------------------------------------------------------------------------------

#[test]
fn the_test_article_never_sees_truth() {
    let dur = 30.0;
    let world = standard(7, dur);
    let mut ta = Recorder::new(default_ta(&world));
    ta.keep_reports = true;
    let (tables, stats) = run(&world, &config(8, dur), &mut ta);
    check_stats(&tables, &stats);
    // The recording itself does carry hints (so the check below means something).
    assert!(tables.measurements.iter().filter(|m| m.target_hint.is_some()).count() > 100);
    assert!(tables.primitives.iter().any(|p| p.target_hint.is_some()));
    let mut n_meas = 0;
    let mut n_prim = 0;
    for r in &ta.reports {
        assert!(r.measurements.iter().all(|m| m.target_hint.is_none()), "group {}", r.group_id);
        assert!(r.primitives.iter().all(|p| p.target_hint.is_none()), "group {}", r.group_id);
        n_meas += r.measurements.len();
        n_prim += r.primitives.len();
    }
    // Otherwise the TA gets exactly what was recorded.
    assert_eq!(n_meas, tables.measurements.len());
    assert_eq!(n_prim, tables.primitives.len());
    let mut seen: Vec<_> = ta.reports.iter().flat_map(|r| r.measurements.iter().cloned()).collect();
    let mut recorded = tables.measurements.clone();
    recorded.iter_mut().for_each(|m| m.target_hint = None);
    seen.sort_by_key(|m| m.meas_id);
    recorded.sort_by_key(|m| m.meas_id);
    assert_eq!(seen, recorded);
}

// ---------------------------------------------------------------------------------------------
// Determinism
// ---------------------------------------------------------------------------------------------

#[test]
fn runs_are_deterministic() {
    let dur = 30.0;
    let world = standard(7, dur);
    let cfg = config(21, dur);
    let one = |cfg: &EngineConfig| {
        let mut t = RunTables::default();
        let s = mimo_sim::run_one(&world, cfg, 3, default_ta(&world).as_mut(), &mut t).expect("run");
        (t, s)
    };
    let (a, sa) = one(&cfg);
    let (b, sb) = one(&cfg);
    assert!(!a.tracks.is_empty() && !a.measurements.is_empty());
    assert_eq!(sa, sb);
    assert!(a == b, "two identical runs differ");
    let (c, _) = one(&config(22, dur));
    assert_ne!(a.measurements, c.measurements, "another seed draws other noise");
}

#[test]
fn monte_carlo_is_independent_of_the_thread_count() {
    let dur = 20.0;
    let world = standard(7, dur);
    let cfg = config(9, dur);
    let runs = [0u32, 1, 2, 3];
    let make_ta = |_run: u32| -> Result<Box<dyn TestArticle + '_>, EngineError> { Ok(default_ta(&world)) };
    let make_sink = |_run: u32| -> Result<RunTables, EngineError> { Ok(RunTables::default()) };
    let collect = |threads: usize| -> BTreeMap<u32, (RunTables, RunStats)> {
        let out = Mutex::new(BTreeMap::new());
        let done = |run: u32, t: RunTables, s: RunStats, info: TaInfo| -> Result<(), EngineError> {
            assert_eq!(info.name, "default");
            out.lock().expect("lock").insert(run, (t, s));
            Ok(())
        };
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("pool");
        pool.install(|| mimo_sim::run_monte_carlo(&world, &cfg, &runs, &make_ta, &make_sink, &done)).expect("runs");
        out.into_inner().expect("lock")
    };
    let one = collect(1);
    let two = collect(2);
    assert_eq!(one.len(), runs.len());
    for run in runs {
        let (a, sa) = &one[&run];
        let (b, sb) = &two[&run];
        assert_eq!(sa, sb, "run {run}");
        assert!(a == b, "run {run} differs between 1 and 2 threads");
        assert!(a.truth.iter().all(|r| r.run == run) && a.dwells.iter().all(|r| r.run == run));
    }
    // The same run alone gives the same tables; different runs draw different noise.
    let mut alone = RunTables::default();
    mimo_sim::run_one(&world, &cfg, 2, default_ta(&world).as_mut(), &mut alone).expect("run");
    assert!(alone == one[&2].0);
    assert_ne!(one[&0].0.measurements.len(), 0);
    let strip = |t: &RunTables| t.measurements.iter().map(|m| (m.meas_id, m.range_m)).collect::<Vec<_>>();
    assert_ne!(strip(&one[&0].0), strip(&one[&1].0));
}

// ---------------------------------------------------------------------------------------------
// The default TA where methods fail, coverage loss, completeness
// ---------------------------------------------------------------------------------------------

#[test]
fn default_ta_is_stable_through_crossover_and_break_up() {
    let dur = 200.0;
    let world = standard(7, dur);
    let (tables, stats) = run(&world, &config(7, dur), default_ta(&world).as_mut());
    check_stats(&tables, &stats);
    for r in &tables.tracks {
        let v = [r.x_m, r.y_m, r.z_m, r.vx_mps, r.vy_mps, r.vz_mps];
        assert!(v.iter().chain(&r.cov).all(|x| x.is_finite()), "non-finite track row {r:?}");
        assert!(r.t_s.is_finite() && (0.0..=dur).contains(&r.t_s));
    }
    let t = dur;
    let lives = lives(&tables.tracks);
    let live = live_at(&lives, t);
    let fighters: Vec<(String, DVec3)> = world
        .targets_at(t)
        .into_iter()
        .filter(|x| x.id.starts_with("F-"))
        .map(|x| (x.id.to_string(), x.pos_ecef))
        .collect();
    assert_eq!(fighters.len(), 4);
    let truths: Vec<DVec3> = fighters.iter().map(|f| f.1).collect();
    let tracks: Vec<DVec3> = live.iter().map(|l| l.1).collect();
    let pairs = pair(&truths, &tracks, 1000.0);
    for ((id, _), p) in fighters.iter().zip(&pairs) {
        match p {
            Some((j, d)) => println!("{id}: track {} at {d:.0} m", live[*j].0),
            None => println!("{id}: no track within 1 km"),
        }
    }
    assert!(pairs.iter().all(Option::is_some), "after the break-up every fighter has its own confirmed track");
}

const COVERAGE_LOSS: &str = r#"
name = "coverage-loss"
description = "one ship with one north face; a jet flies east out of the face's sector, turns and comes back"
duration_s = 450.0

[[ships]]
id = "R1"
lat_deg = 36.0
lon_deg = -70.0
heading_deg = 0.0
radar = { face_azimuths_deg = [0.0] }

[aircraft_types.jet]
rcs_m2 = 5.0
min_speed_mps = 150.0
max_speed_mps = 350.0
max_accel_g = 6.0

[[aircraft]]
id = "X"
type = "jet"
start = { lat_deg = 36.225, lon_deg = -70.1666, alt_m = 3000.0 }
heading_deg = 90.0
speed_mps = 300.0
manoeuvres = [ { kind = "turn", at_s = 260.0, turn_deg = -180.0, load_factor = 4.0, ramp_s = 1.0 } ]
"#;

#[test]
fn tracks_are_dropped_out_of_coverage_and_regained_after() {
    let scenario = mimo_scenario::load_str(COVERAGE_LOSS, "coverage-loss", None).expect("scenario");
    let dur = scenario.duration_s;
    let world = World::new(scenario).expect("world");
    let ship = &world.scenario.ships[0];
    let seen = |t: f64| {
        let x = &world.targets_at(t)[0];
        ship.sees(t, x.pos_ecef, x.alt_m)
    };
    // Coverage from the geometry: in, out (the face's sector edge), in again.
    let steps: Vec<f64> = (0..=(dur * 2.0) as u32).map(|k| f64::from(k) * 0.5).collect();
    let t_leave = steps.iter().copied().find(|&t| !seen(t)).expect("X leaves coverage");
    let t_enter = steps.iter().copied().find(|&t| t > t_leave && seen(t)).expect("X comes back");
    assert!(steps.iter().filter(|&&t| t > t_enter).all(|&t| seen(t)));
    assert!(t_leave > 150.0 && t_enter - t_leave > 100.0, "leave {t_leave}, enter {t_enter}");

    let (tables, stats) = run(&world, &config(13, dur), default_ta(&world).as_mut());
    check_stats(&tables, &stats);
    let lives = lives(&tables.tracks);
    let near = |t: f64, gate: f64| -> Vec<(u64, f64)> {
        let x = world.targets_at(t)[0].pos_ecef;
        live_at(&lives, t).into_iter().map(|(id, p)| (id, (p - x).length())).filter(|&(_, d)| d <= gate).collect()
    };
    // Tracked before it leaves.
    let before = near(t_leave - 5.0, 1000.0);
    assert_eq!(before.len(), 1, "one track on X before it leaves coverage: {before:?}");
    let id = before[0].0;
    // That track is deleted while X is out of coverage, and nothing follows X there.
    let deleted = tables
        .tracks
        .iter()
        .find(|r| r.track_id == id && r.status == TrackStatus::Deleted)
        .map(|r| r.t_s)
        .expect("the track is deleted");
    assert!((t_leave..t_enter).contains(&deleted), "deleted at {deleted}, out of coverage {t_leave}..{t_enter}");
    assert!(near(t_enter - 1.0, 20e3).is_empty(), "no track follows X outside coverage");
    // Regained some time after it comes back, and held to the end.
    let regained = (0..=120)
        .map(|k| t_enter + f64::from(k) * 0.5)
        .find(|&t| !near(t, 1000.0).is_empty())
        .expect("a confirmed track on X within 60 s of its return");
    println!(
        "X out of coverage {t_leave}..{t_enter} s; track {id} deleted at {deleted:.1} s; regained at {regained} s \
         ({:.1} s after its return)",
        regained - t_enter
    );
    assert!(near(dur, 1000.0).len() == 1, "X is tracked at the end");
}

#[test]
fn completeness_end_to_end_scenario_1() {
    let (c, _) = completeness_end_to_end(1);
    assert!(c >= 0.98, "scenario 1: completeness {c}");
}

/// Scenario 7 with the default TA (seed 1) measured 0.985 with the hold on unresolved pairs
/// (docs/model.md §7.3), just above the challenge's 0.98: the losses are the default tracker's
/// (initiation of the tight formation at long range in the first minute and the fighters' turns
/// at 60–80 s, 200 s and 240–260 s), not the engine's — every TA dwell starts within 0.25 s of
/// when it was asked for. The test guards the challenge level.
#[test]
fn completeness_end_to_end_scenario_7() {
    let (c, stop) = completeness_end_to_end(7);
    assert!(c >= 0.98, "scenario 7: completeness {c}");
    // No radar gives up its background search for long: the default TA does not re-dwell at
    // 14–16 pulses on pairs in one beam (without the hold, R1 and R3 stopped for about 30 s).
    assert!(stop <= 10.0, "scenario 7: a radar's search stopped for {stop:.1} s");
}

/// Longest stretch (s) in which one radar started no search dwell, over all radars.
fn longest_search_stop(dwells: &[DwellRow], dur: f64) -> f64 {
    let mut last: BTreeMap<RadarId, f64> = BTreeMap::new();
    let mut worst = 0.0f64;
    let mut rows: Vec<_> = dwells.iter().filter(|d| d.kind == DwellKind::Search).collect();
    rows.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    for d in rows {
        let prev = last.insert(d.radar, d.t_s).unwrap_or(0.0);
        worst = worst.max(d.t_s - prev);
    }
    for &t in last.values() {
        worst = worst.max(dur - t);
    }
    worst
}

/// Scenario `n` for the full 1000 s with the default TA (1 run, seed 1): per-second completeness
/// and the longest search stop of any radar (s).
fn completeness_end_to_end(n: u32) -> (f64, f64) {
    let world = standard(n, 1000.0);
    let dur = world.scenario.duration_s;
    let t0 = std::time::Instant::now();
    let (tables, stats) = run(&world, &config(1, dur), default_ta(&world).as_mut());
    let wall = t0.elapsed().as_secs_f64();
    check_stats(&tables, &stats);
    assert!(tables.tracks.iter().all(|r| r.x_m.is_finite() && r.vx_mps.is_finite()));
    let (c, worst, n_times) = completeness(&world, &tables.tracks, dur);
    let stop = longest_search_stop(&tables.dwells, dur);
    println!(
        "scenario {n}: completeness {c:.4} over {n_times} s (worst second {worst:.3}); longest search stop \
         {stop:.1} s; run {wall:.1} s; {} dwells, {} TA dwells, {} measurements, {} rejected",
        stats.dwells, stats.ta_dwells, stats.measurements, stats.rejected_requests
    );
    (c, stop)
}

// ---------------------------------------------------------------------------------------------
// Open-loop replay
// ---------------------------------------------------------------------------------------------

#[test]
fn replay_from_measurements_reproduces_the_closed_loop_tracks_and_from_primitives_the_measurements() {
    let dur = 60.0;
    let world = standard(7, dur);
    let cfg = config(5, dur);
    let (tables, _) = run(&world, &cfg, default_ta(&world).as_mut());
    assert!(tables.tracks.len() > 100);
    let replayed = |from: ReplayFrom| {
        let mut out = RunTables::default();
        let stats = replay(
            &world,
            &cfg,
            default_ta(&world).as_mut(),
            0,
            &tables.dwells,
            &tables.primitives,
            &tables.measurements,
            from,
            &mut out,
        )
        .expect("replay");
        assert_eq!(stats.ignored_requests, 0, "open loop: the default TA does not schedule");
        assert!(out.tracks.iter().all(|r| r.run == 0));
        out
    };
    let m = replayed(ReplayFrom::Measurements);
    assert!(m.tracks == tables.tracks, "replay from measurements = closed loop, bit for bit");
    let p = replayed(ReplayFrom::Primitives);
    let mut recorded = tables.measurements.clone();
    recorded.sort_by_key(|m| m.meas_id);
    assert!(p.measurements == recorded, "measurements re-formed from primitives = recorded ones");
    assert!(p.tracks == tables.tracks);
}

#[test]
fn replay_refuses_a_face_the_radar_lacks_and_a_measurement_of_no_dwell() {
    use mimo_ta::replay::ReplayError;
    let dur = 30.0;
    let world = standard(7, dur);
    let cfg = config(5, dur);
    let (tables, _) = run(&world, &cfg, default_ta(&world).as_mut());
    assert!(!tables.measurements.is_empty());
    let replay_of = |dwells: &[DwellRow]| {
        let mut out = RunTables::default();
        replay(
            &world,
            &cfg,
            default_ta(&world).as_mut(),
            0,
            dwells,
            &tables.primitives,
            &tables.measurements,
            ReplayFrom::Measurements,
            &mut out,
        )
    };
    // A search dwell (no test article hears of it) on face 9 of a four-face radar.
    let mut bad = tables.dwells.clone();
    let i = bad.iter().position(|d| d.kind == DwellKind::Search && d.dwell_id > 100).expect("a search dwell");
    bad[i].face = 9;
    let id = bad[i].dwell_id;
    match replay_of(&bad) {
        Err(ReplayError::UnknownFace { dwell_id, face: 9, .. }) => assert_eq!(dwell_id, id),
        other => panic!("expected an unknown face, got {:?}", other.map(|s| s.dwells)),
    }
    // The dwell of a measurement (and of its primitive, looked up first) removed.
    let gone = tables.measurements[0].dwell_id;
    let fewer: Vec<DwellRow> = tables.dwells.iter().filter(|d| d.dwell_id != gone).cloned().collect();
    match replay_of(&fewer) {
        Err(ReplayError::UnknownDwell { table: "primitives", dwell_id }) => assert_eq!(dwell_id, gone),
        other => panic!("expected an unknown dwell, got {:?}", other.map(|s| s.dwells)),
    }
}

/// Group looks (docs/model.md §7.2): in the first 40 s of scenario 7 the four fighters fly within
/// a quarter beamwidth of each other, so with group looks on (the default) some test-article
/// dwells serve several tracks at once; with them off, every dwell serves one track.
#[test]
fn group_looks_serve_the_tight_formation_with_one_dwell() {
    let dur = 40.0;
    let world = standard(7, dur);
    let largest_group = |overrides: serde_json::Value| {
        let cfg = registry::resolve_config("default", &overrides).expect("config");
        let mut ta = Recorder::new(registry::build("default", &cfg, &world).expect("default TA"));
        ta.keep_reports = true;
        let (tables, stats) = run(&world, &config(3, dur), &mut ta);
        check_stats(&tables, &stats);
        let ta_reports: Vec<_> = ta.reports.iter().filter(|r| r.requested_by == Requester::Ta).collect();
        assert!(ta_reports.len() > 50, "the default TA asked for dwells");
        ta_reports.iter().map(|r| r.tag.len()).max().unwrap_or(0)
    };
    let on = largest_group(serde_json::json!({}));
    let off = largest_group(serde_json::json!({ "resource_manager": { "group_looks": false } }));
    assert!(on >= 2, "group looks on: the largest dwell served {on} track(s)");
    assert_eq!(off, 1, "group looks off: one track per dwell");
}
