//! Tests of the discrete-event engine through its public interface: radar timelines, MIMO
//! dwells, background search, reservations, unservable and invalid requests, and what a test
//! article is sent. The default test article's end-to-end tests live in `mimo-ta`.
//!
//! Every run has a fixed seed. Test articles written here implement [`TestArticle`] directly.

mod common;

use common::{check_stats, config, end_of, groups, run, standard, timelines};
use mimo_core::DVec3;
use mimo_core::geo::{EnuFrame, Geodetic};
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, DwellRow, Requester, Role, RunTables, TrackRow, TrackStatus};
use mimo_radar::energy::{dwell_duration_s, dwell_energy_j};
use mimo_radar::geometry::beam_point;
use mimo_sim::messages::{DwellFilter, DwellReport, DwellRequest, Reply, Request, StartInfo, Subscription, TxOrder};
use mimo_sim::test_article::{TaFault, TestArticle};
use mimo_sim::{EngineConfig, EngineError, SearchConfig, World};
use std::collections::BTreeMap;

const R1: RadarId = RadarId(0);
const R2: RadarId = RadarId(1);
const R3: RadarId = RadarId(2);
const R4: RadarId = RadarId(3);

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// Run a test article that must fail; returns the fault.
fn fault_of(world: &World, cfg: &EngineConfig, ta: &mut dyn TestArticle) -> TaFault {
    let mut tables = RunTables::default();
    match mimo_sim::run_one(world, cfg, 0, ta, &mut tables) {
        Err(EngineError::Ta { fault, .. }) => fault,
        other => panic!("expected a test-article fault, got {other:?}"),
    }
}

/// A point `east_m`, `north_m` from the scenario centre at height `alt_m` (ECEF).
fn point(world: &World, east_m: f64, north_m: f64, alt_m: f64) -> DVec3 {
    let c = world.scenario.centre();
    let frame = EnuFrame::at(Geodetic::from_deg(c.lat_deg(), c.lon_deg(), 0.0));
    // Put the point at the wanted height above the ellipsoid (not above the tangent plane).
    let p = frame.to_ecef(DVec3::new(east_m, north_m, 0.0));
    let g = mimo_core::geo::ecef_to_geodetic(p);
    Geodetic::from_deg(g.lat_deg(), g.lon_deg(), alt_m).to_ecef()
}

/// Can radar `r` steer a beam at `p` at `t_s` (a face within its scan limit)?
fn steerable(world: &World, r: RadarId, t_s: f64, p: DVec3) -> bool {
    beam_point(&world.faces_at(r, t_s), world.params(r), p).is_some()
}

fn monostatic(kind: DwellKind, radar: RadarId, earliest_s: f64, aim: DVec3, n_pulses: u32) -> Request {
    Request::Dwell(DwellRequest {
        kind,
        earliest_s,
        aim_ecef: aim,
        transmitters: vec![TxOrder { radar, n_pulses }],
        receivers: vec![radar],
        window_half_m: 1000.0,
        predicted_snr: None,
        tag: Vec::new(),
    })
}

// ---------------------------------------------------------------------------------------------
// MIMO dwells
// ---------------------------------------------------------------------------------------------

/// Asks, at t = 0, for MIMO dwells at fixed times aimed at airliner A (from truth: a test may),
/// R1 (16 pulses) and R3 (12 pulses) transmitting, R1, R2 and R4 receiving.
struct MimoTa<'w> {
    world: &'w World,
    times: Vec<f64>,
    reports: Vec<DwellReport>,
}

impl MimoTa<'_> {
    fn aim(&self, t: f64) -> DVec3 {
        let a = self.world.scenario.target_index("A").expect("airliner A");
        self.world.targets_at(t)[a].pos_ecef
    }
}

impl TestArticle for MimoTa<'_> {
    fn name(&self) -> &str {
        "mimo-test"
    }
    fn subscription(&self) -> Subscription {
        Subscription { dwells: DwellFilter::All, primitives: true, batch: false }
    }
    fn on_start(&mut self, _start: &StartInfo) -> Result<Reply, TaFault> {
        let reqs = self
            .times
            .iter()
            .enumerate()
            .map(|(i, &t)| {
                Request::Dwell(DwellRequest {
                    kind: DwellKind::Mimo,
                    earliest_s: t,
                    aim_ecef: self.aim(t),
                    transmitters: vec![TxOrder { radar: R1, n_pulses: 16 }, TxOrder { radar: R3, n_pulses: 12 }],
                    receivers: vec![R1, R2, R4],
                    window_half_m: 1000.0,
                    predicted_snr: None,
                    tag: vec![i as u64, 77],
                })
            })
            .collect();
        Ok(Reply::requests(reqs))
    }
    fn on_dwell(&mut self, report: &DwellReport) -> Result<Reply, TaFault> {
        if report.requested_by == Requester::Ta {
            self.reports.push(report.clone());
        }
        Ok(Reply::default())
    }
    fn on_wake(&mut self, _t_s: f64) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
}

#[test]
fn mimo_dwells_occupy_every_participant() {
    let dur = 25.0;
    let world = standard(1, dur);
    let times = vec![5.0, 10.0, 12.5, 20.0];
    let mut ta = MimoTa { world: &world, times: times.clone(), reports: Vec::new() };
    for &t in &times {
        for r in [R1, R2, R3, R4] {
            assert!(steerable(&world, r, t, ta.aim(t)), "{r} must see airliner A at {t} s for this test");
        }
    }
    let (tables, stats) = run(&world, &config(5, dur), &mut ta);
    check_stats(&tables, &stats);
    assert_eq!(stats.ta_dwells, times.len() as u64);
    assert_eq!(stats.rejected_requests, 0);

    let p1 = world.params(R1);
    let p3 = world.params(R3);
    let expected_duration = dwell_duration_s(p1, 16).max(dwell_duration_s(p3, 12));
    let g = groups(&tables.dwells);
    let mimo: Vec<(&u64, &Vec<&DwellRow>)> = g.iter().filter(|(_, v)| v[0].requested_by == Requester::Ta).collect();
    assert_eq!(mimo.len(), times.len());
    assert_eq!(ta.reports.len(), times.len());
    let mut channels: BTreeMap<(RadarId, RadarId), usize> = BTreeMap::new();
    for (i, ((&(&gid, rows), &t), report)) in mimo.iter().zip(&times).zip(&ta.reports).enumerate() {
        // Parts: R1 transmits and receives, R3 only transmits, R2 and R4 only receive.
        let roles: Vec<(RadarId, Role)> = rows.iter().map(|r| (r.radar, r.role)).collect();
        assert_eq!(roles, vec![(R1, Role::Txrx), (R3, Role::Tx), (R2, Role::Rx), (R4, Role::Rx)]);
        for r in rows.iter() {
            assert_eq!(r.group_id, gid);
            assert_eq!(r.kind, DwellKind::Mimo);
            // Reserved at t = 0 for a free slot: it starts exactly when asked.
            assert!((r.t_s - t).abs() < 1e-9, "group {gid} starts at {} instead of {t}", r.t_s);
            assert!((r.duration_s - expected_duration).abs() < 1e-12, "duration {}", r.duration_s);
        }
        let r1 = rows[0];
        let r3 = rows[1];
        assert_eq!((r1.n_pulses, r3.n_pulses, rows[2].n_pulses, rows[3].n_pulses), (16, 12, 0, 0));
        assert_eq!(r1.energy_j, dwell_energy_j(p1, 16));
        assert_eq!(r1.energy_j, p1.peak_power_w * p1.pulse_width_s * 16.0);
        assert_eq!(r3.energy_j, p3.peak_power_w * p3.pulse_width_s * 12.0);
        assert_eq!(r1.peak_power_w, p1.peak_power_w);
        for rx in &rows[2..] {
            assert_eq!((rx.energy_j, rx.peak_power_w), (0.0, 0.0));
        }
        assert_ne!(r1.waveform, r3.waveform, "the two transmitters use different waveforms");

        // The report describes the same parts.
        assert_eq!(report.group_id, gid);
        assert_eq!(report.kind, DwellKind::Mimo);
        assert_eq!(report.tag, vec![i as u64, 77]);
        assert!((report.t_s - (t + 0.5 * expected_duration)).abs() < 1e-9);
        assert_eq!(report.duration_s, r1.duration_s);
        assert!((report.aim_ecef - DVec3::new(r1.aim_x_m, r1.aim_y_m, r1.aim_z_m)).length() < 1e-6);
        assert_eq!(report.parts.len(), rows.len());
        for (p, r) in report.parts.iter().zip(rows.iter()) {
            assert_eq!(p.radar, r.radar);
            assert_eq!(p.dwell_id, r.dwell_id);
            assert_eq!(p.transmits, r.role.transmits());
            assert_eq!(p.receives, matches!(r.role, Role::Rx | Role::Txrx));
            assert_eq!((p.face, p.beam_u, p.beam_v, p.n_pulses), (r.face, r.beam_u, r.beam_v, r.n_pulses));
            // The face frame the part used: the site and rotation of the radar's face then.
            let f = world.faces_at(r.radar, report.t_s)[r.face as usize];
            assert!((p.site_ecef - f.origin_ecef).length() < 1e-6);
            assert!((p.frame().face_from_ecef - f.face_from_ecef).abs_diff_eq(mimo_core::DMat3::ZERO, 1e-12));
        }
        assert!((report.end_s - (t + expected_duration)).abs() < 1e-9);
        // Measurements: received only by the receivers' parts, from either transmitter.
        let part_of: BTreeMap<u64, RadarId> = rows.iter().map(|r| (r.dwell_id, r.radar)).collect();
        for m in tables.measurements.iter().filter(|m| part_of.contains_key(&m.dwell_id)) {
            assert_eq!(part_of[&m.dwell_id], m.rx);
            assert!([R1, R2, R4].contains(&m.rx), "{m:?}");
            assert!([R1, R3].contains(&m.tx), "{m:?}");
            *channels.entry((m.tx, m.rx)).or_default() += 1;
        }
        assert_eq!(
            report.measurements.len(),
            tables.measurements.iter().filter(|m| part_of.contains_key(&m.dwell_id)).count()
        );
    }
    println!("channels with detections of A (tx, rx): {channels:?}");
    // Both transmitters' waveforms were separated and detected by more than one receiver.
    assert!(channels.keys().any(|c| c.0 == R1) && channels.keys().any(|c| c.0 == R3), "{channels:?}");
    assert!(channels.len() >= 4, "{channels:?}");
}

// ---------------------------------------------------------------------------------------------
// Background search
// ---------------------------------------------------------------------------------------------

/// Asks for nothing and is sent only its own dwells: background search alone runs.
struct Quiet {
    reports: usize,
}

impl TestArticle for Quiet {
    fn name(&self) -> &str {
        "quiet"
    }
    fn subscription(&self) -> Subscription {
        Subscription { dwells: DwellFilter::Own, ..Subscription::default() }
    }
    fn on_start(&mut self, _start: &StartInfo) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_dwell(&mut self, _report: &DwellReport) -> Result<Reply, TaFault> {
        self.reports += 1;
        Ok(Reply::default())
    }
    fn on_wake(&mut self, _t_s: f64) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
}

#[test]
fn search_fills_every_idle_moment() {
    let dur = 30.0;
    let world = standard(1, dur);
    let mut ta = Quiet { reports: 0 };
    let (tables, stats) = run(&world, &config(2, dur), &mut ta);
    assert_eq!(ta.reports, 0, "a test article subscribed to its own dwells hears nothing of search");
    check_stats(&tables, &stats);
    assert_eq!(stats.ta_dwells, 0);
    let lines = timelines(&tables.dwells);
    assert_eq!(lines.len(), 4);
    for (radar, line) in lines {
        assert!(line.iter().all(|d| d.kind == DwellKind::Search && d.role == Role::Txrx));
        assert_eq!(line[0].t_s, 0.0);
        for w in line.windows(2) {
            assert!((w[1].t_s - end_of(w[0])).abs() < 1e-9, "{radar}: gap after dwell {}", w[0].dwell_id);
        }
        let busy = line.iter().map(|d| d.duration_s).sum::<f64>() / dur;
        assert!(busy >= 0.99, "{radar} busy {busy}");
    }
}

/// Asks at t = 0 for a long R1 dwell at 10 s and a wake-up at 5 s, when it asks for an R3 dwell
/// as soon as possible.
struct ReserveTa {
    aim: DVec3,
    seen_wake: bool,
}

impl TestArticle for ReserveTa {
    fn name(&self) -> &str {
        "reserve-test"
    }
    fn on_start(&mut self, _start: &StartInfo) -> Result<Reply, TaFault> {
        Ok(Reply::requests(vec![monostatic(DwellKind::Track, R1, 10.0, self.aim, 16), Request::WakeAt(5.0)]))
    }
    fn on_dwell(&mut self, _report: &DwellReport) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_wake(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        self.seen_wake = true;
        Ok(Reply::requests(vec![monostatic(DwellKind::Confirm, R3, t_s, self.aim, 16)]))
    }
}

#[test]
fn search_yields_to_reservations_without_wasting_time() {
    let dur = 20.0;
    let world = standard(1, dur);
    let aim = point(&world, 0.0, 100e3, 5000.0);
    assert!(steerable(&world, R1, 10.0, aim) && steerable(&world, R3, 5.0, aim));
    let mut ta = ReserveTa { aim, seen_wake: false };
    let (tables, stats) = run(&world, &config(4, dur), &mut ta);
    check_stats(&tables, &stats);
    assert!(ta.seen_wake);
    assert_eq!(stats.ta_dwells, 2);
    let lines = timelines(&tables.dwells);
    let max_search = SearchConfig::default()
        .bands
        .iter()
        .map(|b| dwell_duration_s(world.params(R1), b.n_pulses))
        .fold(0.0, f64::max);
    let long = dwell_duration_s(world.params(R1), 16);

    // R1: reserved in advance; search runs until just before it, and it starts on time.
    let l1 = &lines[&R1];
    let k = l1.iter().position(|d| d.requested_by == Requester::Ta).expect("R1's reserved dwell");
    let res = l1[k];
    assert!((res.t_s - 10.0).abs() < 1e-9, "R1's reserved dwell starts at {}", res.t_s);
    assert!((res.duration_s - long).abs() < 1e-12);
    let before = l1[k - 1];
    assert_eq!(before.kind, DwellKind::Search);
    let gap = res.t_s - end_of(before);
    assert!((-1e-9..max_search).contains(&gap), "R1 idled {gap} s before its reservation");
    assert!((l1[k + 1].t_s - end_of(res)).abs() < 1e-9, "search resumes right after the reserved dwell");
    for w in l1[..k].windows(2) {
        assert!((w[1].t_s - end_of(w[0])).abs() < 1e-9, "R1 idled before its reservation was due");
    }

    // R3: asked for at 5 s, "now": it starts when the dwell in progress ends.
    let l3 = &lines[&R3];
    let k = l3.iter().position(|d| d.requested_by == Requester::Ta).expect("R3's dwell");
    let res = l3[k];
    let expected = l3.iter().find(|d| d.t_s < 5.0 && end_of(d) > 5.0).map_or(5.0, |d| end_of(d));
    assert!((res.t_s - expected).abs() < 1e-9, "R3's dwell starts at {} instead of {expected}", res.t_s);
    assert!(res.t_s - 5.0 < max_search + 1e-9);

    // Every radar stays busy.
    for (radar, line) in &lines {
        let busy = line.iter().map(|d| d.duration_s).sum::<f64>() / dur;
        assert!(busy >= 0.99, "{radar} busy {busy}");
    }
}

// ---------------------------------------------------------------------------------------------
// Unservable and invalid requests
// ---------------------------------------------------------------------------------------------

/// Asks at t = 0 for a list of requests, and may answer its first report with track rows.
struct BadTa {
    requests: Vec<Request>,
    rows: Vec<TrackRow>,
}

impl BadTa {
    fn asking(requests: Vec<Request>) -> BadTa {
        BadTa { requests, rows: Vec::new() }
    }
}

impl TestArticle for BadTa {
    fn name(&self) -> &str {
        "bad-test"
    }
    fn on_start(&mut self, _start: &StartInfo) -> Result<Reply, TaFault> {
        Ok(Reply::with_tracks(std::mem::take(&mut self.requests), std::mem::take(&mut self.rows)))
    }
    fn on_dwell(&mut self, _report: &DwellReport) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_wake(&mut self, _t_s: f64) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
}

/// A point R1 cannot steer at (straight above it), one R2 cannot (its blind sector), and one
/// every radar sees.
fn test_points(world: &World) -> (DVec3, DVec3, DVec3) {
    let good = point(world, 0.0, 100e3, 5000.0);
    // Straight above R1: 75° off every (15°-tilted) face, beyond the 60° scan limit.
    let r1 = world.scenario.ships[0].start_position();
    let overhead = Geodetic::from_deg(r1.lat_deg(), r1.lon_deg(), 20e3).to_ecef();
    // In R2's blind sector (south of R2: its faces look 280° and 010°).
    let south_of_r2 = point(world, 20e3, -60e3, 5000.0);
    assert!(!steerable(world, R1, 1.0, overhead));
    assert!(!steerable(world, R2, 1.0, south_of_r2));
    assert!(steerable(world, R1, 1.0, good));
    (overhead, south_of_r2, good)
}

fn mimo_req(tx: Vec<TxOrder>, rx: Vec<RadarId>, aim: DVec3) -> Request {
    Request::Dwell(DwellRequest {
        kind: DwellKind::Mimo,
        earliest_s: 1.0,
        aim_ecef: aim,
        transmitters: tx,
        receivers: rx,
        window_half_m: 1000.0,
        predicted_snr: None,
        tag: Vec::new(),
    })
}

#[test]
fn unservable_requests_are_rejected_and_counted() {
    let dur = 10.0;
    let world = standard(1, dur);
    let (overhead, south_of_r2, good) = test_points(&world);
    let unservable = vec![
        monostatic(DwellKind::Track, R1, 1.0, overhead, 4),
        monostatic(DwellKind::Track, R2, 1.0, south_of_r2, 4),
        // Ends after the run.
        monostatic(DwellKind::Track, R1, dur - 0.001, good, 16),
        // No transmitter at all; no receiver at all.
        mimo_req(Vec::new(), vec![R1, R2], good),
        mimo_req(vec![TxOrder { radar: R1, n_pulses: 4 }], Vec::new(), good),
        // R1 transmits, but its only receiver cannot look there.
        mimo_req(vec![TxOrder { radar: R1, n_pulses: 4 }], vec![R2], south_of_r2),
    ];
    let n_bad = unservable.len() as u64;
    let mut requests = unservable;
    requests.push(monostatic(DwellKind::Track, R1, 1.0, good, 4));
    requests.push(Request::StopLocalTracking(R2));
    let mut ta = BadTa::asking(requests);
    let (tables, stats) = run(&world, &config(1, dur), &mut ta);
    check_stats(&tables, &stats);
    assert_eq!(stats.rejected_requests, n_bad, "{stats:?}");
    assert_eq!(stats.ta_dwells, 1);
    assert_eq!(stats.stop_local_tracking_orders, 1);
    let ta_rows: Vec<&DwellRow> = tables.dwells.iter().filter(|d| d.requested_by == Requester::Ta).collect();
    assert_eq!(ta_rows.len(), 1);
    assert_eq!(ta_rows[0].radar, R1);
    // Search went on as usual.
    for (radar, line) in timelines(&tables.dwells) {
        let busy = line.iter().map(|d| d.duration_s).sum::<f64>() / dur;
        assert!(busy >= 0.99, "{radar} busy {busy}");
    }
}

#[test]
fn invalid_requests_stop_the_run_and_say_why() {
    let dur = 10.0;
    let world = standard(1, dur);
    let (_, _, good) = test_points(&world);
    let cfg = config(1, dur);
    let cases: Vec<(Request, &str)> = vec![
        (monostatic(DwellKind::Track, RadarId(9), 1.0, good, 4), "unknown radar R10"),
        (mimo_req(vec![TxOrder { radar: R1, n_pulses: 4 }], vec![RadarId(200), R2], good), "unknown radar R201"),
        (monostatic(DwellKind::Track, R1, 1.0, DVec3::new(f64::NAN, 0.0, 0.0), 4), "not finite"),
        (monostatic(DwellKind::Track, R1, 2.0 * dur, good, 4), "outside the run"),
        (monostatic(DwellKind::Track, R1, -1.0, good, 4), "outside the run"),
        (monostatic(DwellKind::Track, R1, f64::INFINITY, good, 4), "outside the run"),
        (Request::WakeAt(f64::NAN), "wake_at"),
        (Request::WakeAt(-3.0), "wake_at"),
        (Request::StopLocalTracking(RadarId(4)), "unknown radar R5"),
    ];
    for (req, why) in cases {
        let fault = fault_of(&world, &cfg, &mut BadTa::asking(vec![req.clone()]));
        assert!(matches!(&fault, TaFault::InvalidRequest(m) if m.contains(why)), "{req:?}: {fault}");
    }
    // A track row that is not finite.
    let row = TrackRow {
        run: 0,
        t_s: 0.0,
        track_id: 1,
        status: TrackStatus::Confirmed,
        x_m: f64::NAN,
        y_m: 0.0,
        z_m: 0.0,
        vx_mps: 0.0,
        vy_mps: 0.0,
        vz_mps: 0.0,
        cov: [0.0; 21],
        n_updates: 1,
        last_meas_id: None,
    };
    let mut ta = BadTa { requests: Vec::new(), rows: vec![row] };
    let fault = fault_of(&world, &cfg, &mut ta);
    assert!(matches!(&fault, TaFault::InvalidRequest(m) if m.contains("non-finite")), "{fault}");
}

// ---------------------------------------------------------------------------------------------
// What a test article is sent
// ---------------------------------------------------------------------------------------------

/// Records what it is sent under a subscription; asks for one dwell at 2 s and wake-ups.
struct Listener {
    sub: Subscription,
    aim: DVec3,
    events: Vec<(f64, usize, Requester, usize)>,
    finished: Option<f64>,
    wakes: Vec<f64>,
}

impl TestArticle for Listener {
    fn name(&self) -> &str {
        "listener"
    }
    fn subscription(&self) -> Subscription {
        self.sub
    }
    fn on_start(&mut self, start: &StartInfo) -> Result<Reply, TaFault> {
        assert_eq!(start.ships.len(), 4);
        assert!(start.closed_loop);
        Ok(Reply::requests(vec![
            monostatic(DwellKind::Track, R1, 2.0, self.aim, 4),
            Request::WakeAt(3.0),
            Request::WakeAt(3.0),
        ]))
    }
    fn on_dwell(&mut self, r: &DwellReport) -> Result<Reply, TaFault> {
        self.events.push((r.end_s, r.measurements.len(), r.requested_by, r.primitives.len()));
        Ok(Reply::default())
    }
    fn on_wake(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        self.wakes.push(t_s);
        Ok(Reply::default())
    }
    fn on_finish(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        self.finished = Some(t_s);
        Ok(Reply::default())
    }
}

#[test]
fn a_test_article_is_sent_what_it_subscribed_to() {
    let dur = 20.0;
    let world = standard(7, dur);
    let cfg = config(3, dur);
    let aim = point(&world, 0.0, 100e3, 5000.0);
    let listen = |sub: Subscription| {
        let mut ta = Listener { sub, aim, events: Vec::new(), finished: None, wakes: Vec::new() };
        let (tables, stats) = run(&world, &cfg, &mut ta);
        assert_eq!(ta.finished, Some(dur));
        assert_eq!(ta.wakes, vec![3.0, 3.0], "both wake-ups, at the time asked");
        assert_eq!(stats.reports_delivered, ta.events.len() as u64);
        (tables, ta.events)
    };
    let all = Subscription { dwells: DwellFilter::All, primitives: true, batch: false };
    let (tables, every) = listen(all);
    assert_eq!(every.len(), groups(&tables.dwells).len(), "one report per dwell");
    assert_eq!(every.iter().map(|e| e.1).sum::<usize>(), tables.measurements.len());
    assert_eq!(every.iter().map(|e| e.3).sum::<usize>(), tables.primitives.len());
    // With detections: every dwell with a measurement, and the test article's own.
    let (t2, det) = listen(Subscription::default());
    assert_eq!(t2, tables, "what a test article is sent never changes the run");
    let want: Vec<_> = every.iter().filter(|e| e.1 > 0 || e.2 == Requester::Ta).map(|e| (e.0, e.1, e.2, 0)).collect();
    assert_eq!(det, want);
    assert!(det.len() * 20 < every.len(), "{} of {} dwells", det.len(), every.len());
    // Own dwells only.
    let (_, own) = listen(Subscription { dwells: DwellFilter::Own, ..Subscription::default() });
    assert_eq!(own.len(), 1);
    assert_eq!(own[0].2, Requester::Ta);
}
