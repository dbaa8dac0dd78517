//! Search under the test article's control (docs/model.md §7.4, docs/ta-protocol.md §3): search
//! orders shape each radar's background search, a radar with nothing to do idles, search dwells
//! the test article asks for are recorded as its own, and bad orders are test-article faults.

mod common;

use common::{check_stats, config, end_of, run, standard, timelines};
use mimo_core::DVec3;
use mimo_core::geo::{EnuFrame, Geodetic};
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, DwellRow, Requester, Role, RunTables};
use mimo_sim::messages::{
    AzSector, DwellFilter, DwellReport, DwellRequest, Reply, Request, SearchBand, SearchOrder, SearchPlan, StartInfo,
    Subscription, TxOrder,
};
use mimo_sim::test_article::{TaFault, TestArticle};
use mimo_sim::{EngineError, SearchConfig, World};
use std::collections::BTreeMap;

const R1: RadarId = RadarId(0);
const R2: RadarId = RadarId(1);
const R3: RadarId = RadarId(2);

/// Sends `at_start` with its start reply and `at_wake[t]` when woken at `t` (it asks for every
/// wake-up at start); keeps the reports of its own dwells.
#[derive(Default)]
struct Scripted {
    at_start: Vec<Request>,
    at_wake: BTreeMap<u64, Vec<Request>>,
    own: Vec<DwellReport>,
}

impl Scripted {
    fn new(at_start: Vec<Request>) -> Scripted {
        Scripted { at_start, ..Scripted::default() }
    }
    fn then_at(mut self, t_s: f64, reqs: Vec<Request>) -> Scripted {
        self.at_wake.insert(t_s.to_bits(), reqs);
        self
    }
}

impl TestArticle for Scripted {
    fn name(&self) -> &str {
        "scripted"
    }
    fn subscription(&self) -> Subscription {
        Subscription { dwells: DwellFilter::Own, ..Subscription::default() }
    }
    fn on_start(&mut self, _start: &StartInfo) -> Result<Reply, TaFault> {
        let mut reqs = std::mem::take(&mut self.at_start);
        reqs.extend(self.at_wake.keys().map(|&b| Request::WakeAt(f64::from_bits(b))));
        Ok(Reply::requests(reqs))
    }
    fn on_dwell(&mut self, report: &DwellReport) -> Result<Reply, TaFault> {
        self.own.push(report.clone());
        Ok(Reply::default())
    }
    fn on_wake(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        Ok(Reply::requests(self.at_wake.remove(&t_s.to_bits()).unwrap_or_default()))
    }
}

fn default_plan() -> SearchPlan {
    SearchPlan { bands: SearchConfig::default().bands, ..SearchPlan::none() }
}

fn order(radar: Option<RadarId>, plan: SearchPlan) -> Request {
    Request::Search(SearchOrder { radar, plan })
}

/// Search dwell time (s) per radar.
fn search_time(t: &RunTables) -> BTreeMap<RadarId, f64> {
    let mut out = BTreeMap::new();
    for d in t.dwells.iter().filter(|d| d.kind == DwellKind::Search) {
        *out.entry(d.radar).or_insert(0.0) += d.duration_s;
    }
    out
}

/// A point `east_m`, `north_m` from the scenario centre at `alt_m` (ECEF).
fn point(world: &World, east_m: f64, north_m: f64, alt_m: f64) -> DVec3 {
    let c = world.scenario.centre();
    let frame = EnuFrame::at(Geodetic::from_deg(c.lat_deg(), c.lon_deg(), 0.0));
    let g = mimo_core::geo::ecef_to_geodetic(frame.to_ecef(DVec3::new(east_m, north_m, 0.0)));
    Geodetic::from_deg(g.lat_deg(), g.lon_deg(), alt_m).to_ecef()
}

#[test]
fn the_default_raster_ordered_at_start_is_the_search_of_no_order() {
    let dur = 12.0;
    let world = standard(1, dur);
    let (plain, _) = run(&world, &config(3, dur), &mut Scripted::default());
    let (ordered, stats) = run(&world, &config(3, dur), &mut Scripted::new(vec![order(None, default_plan())]));
    check_stats(&ordered, &stats);
    assert!(plain.dwells.len() > 4000);
    assert_eq!(plain.dwells, ordered.dwells);
    assert_eq!(plain.measurements, ordered.measurements);
}

#[test]
fn a_share_of_one_half_halves_the_search_dwell_time() {
    let dur = 30.0;
    let world = standard(1, dur);
    let (full, _) = run(&world, &config(5, dur), &mut Scripted::default());
    let half = SearchPlan { share: 0.5, ..default_plan() };
    let (shaped, stats) = run(&world, &config(5, dur), &mut Scripted::new(vec![order(None, half)]));
    check_stats(&shaped, &stats);
    let (a, b) = (search_time(&full), search_time(&shaped));
    assert_eq!(a.len(), 4);
    for (r, t_full) in &a {
        let ratio = b[r] / t_full;
        assert!((0.49..=0.51).contains(&ratio), "{r}: {ratio}");
    }
    // After each search dwell the radar waits exactly as long as the dwell lasted.
    for (r, line) in timelines(&shaped.dwells) {
        for w in line.windows(2) {
            let gap = w[1].t_s - end_of(w[0]);
            assert!((gap - w[0].duration_s).abs() < 1e-8, "{r}: gap {gap} after a {} s dwell", w[0].duration_s);
        }
    }
}

#[test]
fn a_radar_with_no_search_idles_runs_its_reservations_and_searches_again_on_a_new_plan() {
    let dur = 20.0;
    let world = standard(1, dur);
    let aim = point(&world, 0.0, 100e3, 5000.0);
    let look = Request::Dwell(DwellRequest {
        kind: DwellKind::Track,
        earliest_s: 5.0,
        aim_ecef: aim,
        transmitters: vec![TxOrder { radar: R2, n_pulses: 4 }],
        receivers: vec![R2],
        window_half_m: 1000.0,
        predicted_snr: None,
        tag: vec![1],
    });
    let zero = SearchPlan { share: 0.0, ..default_plan() };
    let mut ta = Scripted::new(vec![order(Some(R2), SearchPlan::none()), order(Some(R3), zero), look])
        .then_at(12.0, vec![order(Some(R2), default_plan())]);
    let (t, stats) = run(&world, &config(7, dur), &mut ta);
    check_stats(&t, &stats);
    let lines = timelines(&t.dwells);
    assert!(!lines.contains_key(&R3), "R3 with share 0 and nothing to do must not dwell");
    // R2: its one reservation at exactly 5 s, then nothing until the new plan at 12 s, from
    // when search fills its time again.
    let r2 = &lines[&R2];
    assert_eq!((r2[0].kind, r2[0].requested_by, r2[0].t_s), (DwellKind::Track, Requester::Ta, 5.0));
    assert_eq!(ta.own.len(), 1);
    assert_eq!(r2[1].t_s, 12.0);
    assert!(r2[1..].iter().all(|d| d.kind == DwellKind::Search && d.requested_by == Requester::Radar));
    let busy: f64 = r2[1..].iter().map(|d| d.duration_s).sum::<f64>() / (dur - 12.0);
    assert!(busy > 0.99, "R2 searches {busy} of its time after the new plan");
    // R1 and R4 kept the default search.
    for r in [R1, RadarId(3)] {
        let busy: f64 = lines[&r].iter().map(|d| d.duration_s).sum::<f64>() / dur;
        assert!(busy > 0.99, "{r} busy {busy}");
    }
}

#[test]
fn a_frame_period_spaces_the_frames() {
    let dur = 65.0;
    let world = standard(1, dur);
    let low = SearchBand { el_min_deg: 0.0, el_max_deg: 2.5, n_pulses: 2, every_frames: 1 };
    let plan = SearchPlan { bands: vec![low], frame_period_s: Some(20.0), ..SearchPlan::none() };
    let (t, _) = run(&world, &config(9, dur), &mut Scripted::new(vec![order(Some(R1), plan)]));
    let line = &timelines(&t.dwells)[&R1];
    let first = line[0];
    let same_beam = |d: &DwellRow| d.face == first.face && d.beam_u == first.beam_u && d.beam_v == first.beam_v;
    let starts: Vec<f64> = line.iter().filter(|d| same_beam(d)).map(|d| d.t_s).collect();
    assert_eq!(starts.len(), 4, "{starts:?}");
    for (k, t) in starts.iter().enumerate() {
        assert!((t - 20.0 * k as f64).abs() < 1e-9, "frame {k} starts at {t} s");
    }
    // A frame is swept back to back, then the radar idles until the next one.
    let per_frame = line.iter().filter(|d| d.t_s < 20.0).count();
    assert_eq!(line.len(), 4 * per_frame);
    let sweep_s = end_of(line[per_frame - 1]);
    assert!(sweep_s > 3.0 && sweep_s < 10.0, "one frame takes {sweep_s} s");
}

#[test]
fn sectors_restrict_the_beam_azimuths() {
    let dur = 10.0;
    let world = standard(1, dur);
    let sector = AzSector { from_deg: 300.0, to_deg: 30.0 };
    let plan = SearchPlan { sectors: vec![sector], ..default_plan() };
    let (t, _) = run(&world, &config(11, dur), &mut Scripted::new(vec![order(Some(R1), plan)]));
    let ship = &world.scenario.ships[0];
    let mut azimuths = Vec::new();
    for d in t.dwells.iter().filter(|d| d.radar == R1) {
        let enu = EnuFrame::at(ship.position_at(d.t_s)).to_enu(DVec3::new(d.aim_x_m, d.aim_y_m, d.aim_z_m));
        let az = enu.x.atan2(enu.y).to_degrees().rem_euclid(360.0);
        assert!(AzSector { from_deg: 299.9, to_deg: 30.1 }.contains(az), "beam at azimuth {az}");
        azimuths.push((az + 180.0).rem_euclid(360.0)); // 300…30 → 120…210
    }
    let (lo, hi) = azimuths.iter().fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(lo < 123.0 && hi > 207.0, "the sector is covered: {lo}…{hi} (shifted by 180°)");
    // A smaller raster with share 1 still fills the radar's time: the sector is swept more often.
    let busy: f64 = t.dwells.iter().filter(|d| d.radar == R1).map(|d| d.duration_s).sum::<f64>() / dur;
    assert!(busy > 0.99);
}

#[test]
fn search_dwells_the_test_article_asks_for_are_recorded_as_its_own() {
    let dur = 6.0;
    let world = standard(1, dur);
    let aim = point(&world, 0.0, 150e3, 3000.0);
    let search = |t: f64, rx: Vec<RadarId>| {
        Request::Dwell(DwellRequest {
            kind: DwellKind::Search,
            earliest_s: t,
            aim_ecef: aim,
            transmitters: vec![TxOrder { radar: R1, n_pulses: 3 }],
            receivers: rx,
            window_half_m: 100e3,
            predicted_snr: None,
            tag: vec![9],
        })
    };
    // No background search anywhere: the table holds the test article's search dwells only.
    let mut ta =
        Scripted::new(vec![order(None, SearchPlan::none()), search(1.0, vec![R1]), search(2.0, vec![R1, R2, R3])]);
    let (t, stats) = run(&world, &config(13, dur), &mut ta);
    check_stats(&t, &stats);
    assert_eq!((stats.search_dwells, stats.ta_dwells), (0, 2));
    assert!(t.dwells.iter().all(|d| d.kind == DwellKind::Search && d.requested_by == Requester::Ta));
    let roles: Vec<(RadarId, Role, f64)> = t.dwells.iter().map(|d| (d.radar, d.role, d.t_s)).collect();
    assert_eq!(roles, vec![(R1, Role::Txrx, 1.0), (R1, Role::Txrx, 2.0), (R2, Role::Rx, 2.0), (R3, Role::Rx, 2.0)]);
    assert!(t.dwells.iter().all(|d| (d.aim_x_m, d.aim_y_m, d.aim_z_m) == (aim.x, aim.y, aim.z)));
    assert_eq!(ta.own.len(), 2);
    assert!(ta.own.iter().all(|r| r.kind == DwellKind::Search && r.tag == vec![9]));
    assert_eq!(ta.own[1].parts.len(), 3);
}

#[test]
fn bad_search_orders_stop_the_run_and_name_the_field() {
    let dur = 5.0;
    let world = standard(1, dur);
    let band =
        |lo: f64, hi: f64, n: u32, k: u32| SearchBand { el_min_deg: lo, el_max_deg: hi, n_pulses: n, every_frames: k };
    let with = |bands: Vec<SearchBand>| SearchPlan { bands, ..SearchPlan::none() };
    let cases: Vec<(Request, &str)> = vec![
        (order(Some(RadarId(7)), default_plan()), "search: radar: unknown radar R8"),
        (order(None, with(vec![band(-91.0, 2.0, 1, 1)])), "plan.bands[0].el_min_deg"),
        (order(None, with(vec![band(0.0, 2.0, 1, 1), band(4.0, 3.0, 1, 1)])), "plan.bands[1].el_min_deg"),
        (order(None, with(vec![band(0.0, 95.0, 1, 1)])), "plan.bands[0].el_max_deg"),
        (order(None, with(vec![band(0.0, 2.0, 0, 1)])), "plan.bands[0].n_pulses"),
        (order(None, with(vec![band(0.0, 2.0, 1, 0)])), "plan.bands[0].every_frames"),
        (order(None, SearchPlan { share: 1.01, ..default_plan() }), "plan.share"),
        (order(None, SearchPlan { share: -0.5, ..default_plan() }), "plan.share"),
        (order(None, SearchPlan { frame_period_s: Some(-1.0), ..default_plan() }), "plan.frame_period_s"),
        (order(None, SearchPlan { frame_period_s: Some(f64::NAN), ..default_plan() }), "plan.frame_period_s"),
        // R2 has two faces (bow ±45°): due south is outside what they search.
        (
            order(
                Some(R2),
                SearchPlan { sectors: vec![AzSector { from_deg: 170.0, to_deg: 190.0 }], ..default_plan() },
            ),
            "search: R2: plan.sectors[0]",
        ),
        (
            order(None, SearchPlan { sectors: vec![AzSector { from_deg: 170.0, to_deg: 190.0 }], ..default_plan() }),
            "search: R2: plan.sectors[0]",
        ),
    ];
    for (req, why) in cases {
        let mut tables = RunTables::default();
        let mut ta = Scripted::new(vec![req.clone()]);
        match mimo_sim::run_one(&world, &config(1, dur), 0, &mut ta, &mut tables) {
            Err(EngineError::Ta { fault: TaFault::InvalidRequest(m), .. }) => {
                assert!(m.contains(why), "{req:?}: {m}")
            }
            other => panic!("{req:?}: expected an invalid request, got {other:?}"),
        }
    }
    // R1 sees all round: any sector is inside its faces.
    let ok = SearchPlan { sectors: vec![AzSector { from_deg: 170.0, to_deg: 190.0 }], ..default_plan() };
    run(&world, &config(1, dur), &mut Scripted::new(vec![order(Some(R1), ok)]));
}
