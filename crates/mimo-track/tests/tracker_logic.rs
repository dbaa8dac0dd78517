//! Hand-made cases for the multi-target tracker's logic: GNN against greedy association,
//! M-of-N confirmation and deletion sequences, beam-based misses, merged measurements,
//! two-point initiation, revisit bookkeeping, bad input and determinism.

mod common;

use common::*;
use mimo_core::DVec3;
use mimo_core::records::{DwellKind, MeasurementRow, TrackRow, TrackStatus};
use mimo_track::association::GreedyAssociator;
use mimo_track::deletion::DeleteReason;
use mimo_track::initiation::{MOfN, TwoPointConfig};
use mimo_track::{
    Components, DwellContext, InitiatorConfig, Look, MultiTargetTracker, SensorGeometry, StateEcef, TrackerConfig,
    TrackerKind,
};

fn row_at(face: u8, range: f64, u: f64, v: f64, t_s: f64, meas_id: u64, var_u: f64) -> MeasurementRow {
    MeasurementRow {
        run: 0,
        meas_id,
        dwell_id: meas_id,
        t_s,
        rx: R1,
        tx: R1,
        rx_face: face,
        range_m: range,
        u,
        v,
        snr_db: 20.0,
        var_range_m2: 0.01,
        var_u,
        var_v: var_u,
        n_primitives: 2,
        merged: false,
        target_hint: None,
    }
}

fn spawn_at(tr: &mut MultiTargetTracker, sim: &Sim, range: f64, u: f64, pos_var: f64) -> u64 {
    let face = sim.geom.face(R1, 0, 0.0).expect("face");
    let p = face.from_ruv(range, u, 0.0);
    let mut cov = [[0.0; 6]; 6];
    for i in 0..3 {
        cov[i][i] = pos_var;
        cov[i + 3][i + 3] = 1.0;
    }
    let (id, row) =
        tr.spawn_track(0, 0.0, &StateEcef { pos: p, vel: DVec3::ZERO, cov }, TrackStatus::Confirmed).expect("spawn");
    assert_row_finite(&row);
    id
}

#[test]
fn gnn_finds_the_global_optimum_where_greedy_fails() {
    // Tracks A (u = 0) and B (100 m to the side) at 50 km with 50 m position std; detections at
    // +40 m and −70 m. Greedy gives A the nearest (+40 m) and B the far one (d² = 11.6, total
    // 12.2); the optimum crosses them over (d² = 1.96 + 1.44 = 3.4).
    let sim = Sim::new();
    let r = 50_000.0;
    let run = |greedy: bool| {
        let cfg = TrackerConfig::default();
        let mut comps = Components::from_config(&cfg);
        if greedy {
            comps.associator = Box::new(GreedyAssociator { cost: cfg.association });
        }
        let mut tr = MultiTargetTracker::with_components(cfg, sim.centre, comps);
        let a = spawn_at(&mut tr, &sim, r, 0.0, 2500.0);
        let b = spawn_at(&mut tr, &sim, r, 100.0 / r, 2500.0);
        let meas = [row_at(0, r, 40.0 / r, 0.0, 0.0, 11, 1e-14), row_at(0, r, -70.0 / r, 0.0, 0.0, 12, 1e-14)];
        let ctx = DwellContext::aimed(0, 1, 0.0, DwellKind::Track, vec![a, b]);
        let rows = tr.process_dwell(&ctx, &meas, &sim.geom);
        assert_eq!(rows.len(), 2);
        (tr.track(a).and_then(|t| t.last_meas_id), tr.track(b).and_then(|t| t.last_meas_id))
    };
    assert_eq!(run(false), (Some(12), Some(11)), "GNN pairs A–(−70 m) and B–(+40 m)");
    assert_eq!(run(true), (Some(11), Some(12)), "greedy takes the nearest pair first");
}

/// A target at 80 km on face 0's boresight flying at 200 m/s, measured monostatically.
struct Scene {
    sim: Sim,
    x0: [f64; 6],
}

impl Scene {
    fn new() -> Scene {
        let sim = Sim::new();
        let face = sim.geom.face(R1, 0, 0.0).expect("face");
        let p = sim.frame.to_local(face.from_ruv(80_000.0, 0.1, 0.05));
        Scene { sim, x0: [p.x, p.y, p.z, -150.0, -130.0, 0.0] }
    }
    fn truth(&self, t: f64) -> [f64; 6] {
        let x = self.x0;
        [x[0] + t * x[3], x[1] + t * x[4], x[2] + t * x[5], x[3], x[4], x[5]]
    }
    fn meas(&self, t: f64, id: u64) -> MeasurementRow {
        let mut rng = rng(&[id]);
        self.sim.measure(&mut rng, &self.truth(t), R1, R1, 5.0, 5e-4, t, id)
    }
}

fn dwell(
    tr: &mut MultiTargetTracker,
    sc: &Scene,
    kind: DwellKind,
    t: f64,
    targets: Vec<u64>,
    detect: bool,
) -> Vec<TrackRow> {
    let id = (t * 1000.0) as u64;
    let meas = if detect { vec![sc.meas(t, id)] } else { vec![] };
    let ctx = if kind == DwellKind::Search {
        DwellContext::search(0, id, t)
    } else {
        DwellContext::aimed(0, id, t, kind, targets)
    };
    let rows = tr.process_dwell(&ctx, &meas, &sc.sim.geom);
    rows.iter().for_each(assert_row_finite);
    rows
}

#[test]
fn two_of_three_confirms_after_a_miss_and_three_misses_delete() {
    let sc = Scene::new();
    let mut tr = MultiTargetTracker::new(TrackerConfig::default(), sc.sim.centre);
    let rows = dwell(&mut tr, &sc, DwellKind::Search, 0.0, vec![], true);
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0].status, TrackStatus::Tentative);
    let id = rows[0].track_id;
    // Looks: hit (initiation), miss, hit → confirmed on 2-of-3.
    assert!(dwell(&mut tr, &sc, DwellKind::Confirm, 0.3, vec![id], false).is_empty());
    assert_eq!(tr.track(id).map(|t| t.status), Some(TrackStatus::Tentative));
    let rows = dwell(&mut tr, &sc, DwellKind::Confirm, 0.6, vec![id], true);
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0].status, TrackStatus::Confirmed);
    assert_eq!(rows[0].n_updates, 2);
    // Confirmed: miss, miss, hit resets, then three misses delete (one `deleted` row, once).
    for (t, det) in [(1.0, false), (1.5, false), (2.0, true), (2.5, false), (3.0, false)] {
        let rows = dwell(&mut tr, &sc, DwellKind::Track, t, vec![id], det);
        assert!(rows.iter().all(|r| r.status == TrackStatus::Confirmed));
        assert_eq!(rows.len(), usize::from(det));
    }
    assert_eq!(tr.track(id).map(|t| t.consecutive_misses), Some(2));
    let rows = dwell(&mut tr, &sc, DwellKind::Track, 3.5, vec![id], false);
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0].status, TrackStatus::Deleted);
    assert_eq!(rows[0].track_id, id);
    assert!(tr.track(id).is_none());
    assert_eq!(tr.stats().deleted.get(&DeleteReason::Misses), Some(&1));
    assert!(dwell(&mut tr, &sc, DwellKind::Track, 4.0, vec![id], false).is_empty());
}

#[test]
fn two_misses_drop_a_tentative_track() {
    let sc = Scene::new();
    let mut tr = MultiTargetTracker::new(TrackerConfig::default(), sc.sim.centre);
    let id = dwell(&mut tr, &sc, DwellKind::Search, 0.0, vec![], true)[0].track_id;
    assert!(dwell(&mut tr, &sc, DwellKind::Confirm, 0.3, vec![id], false).is_empty());
    let rows = dwell(&mut tr, &sc, DwellKind::Confirm, 0.6, vec![id], false);
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0].status, TrackStatus::Deleted);
    assert_eq!(tr.stats().deleted.get(&DeleteReason::Unconfirmed), Some(&1));
    // Search detections elsewhere in time do not count as misses: only looks do.
    let id2 = dwell(&mut tr, &sc, DwellKind::Search, 1.0, vec![], true)[0].track_id;
    assert_ne!(id2, id);
    assert!(dwell(&mut tr, &sc, DwellKind::Search, 1.2, vec![], false).is_empty());
    assert_eq!(tr.track(id2).map(|t| t.looks.clone()), Some(vec![true]));
}

#[test]
fn three_of_four_needs_three_hits() {
    let sc = Scene::new();
    let cfg = TrackerConfig { confirmation: MOfN { m: 3, n: 4 }, ..TrackerConfig::default() };
    let mut tr = MultiTargetTracker::new(cfg, sc.sim.centre);
    let id = dwell(&mut tr, &sc, DwellKind::Search, 0.0, vec![], true)[0].track_id;
    let r = dwell(&mut tr, &sc, DwellKind::Confirm, 0.3, vec![id], true);
    assert_eq!(r[0].status, TrackStatus::Tentative);
    assert!(dwell(&mut tr, &sc, DwellKind::Confirm, 0.6, vec![id], false).is_empty());
    let r = dwell(&mut tr, &sc, DwellKind::Confirm, 0.9, vec![id], true);
    assert_eq!(r[0].status, TrackStatus::Confirmed);
    assert_eq!(tr.track(id).map(|t| t.looks.clone()), Some(vec![true, true, false, true]));
}

#[test]
fn coasting_tentative_track_is_deleted_by_maintain() {
    let sc = Scene::new();
    let mut tr = MultiTargetTracker::new(TrackerConfig::default(), sc.sim.centre);
    let id = dwell(&mut tr, &sc, DwellKind::Search, 0.0, vec![], true)[0].track_id;
    assert!(tr.maintain(0, 1.0).is_empty());
    let rows = tr.maintain(0, 30.0);
    assert_eq!(rows.len(), 1);
    assert_eq!((rows[0].track_id, rows[0].status), (id, TrackStatus::Deleted));
    assert!(tr.tracks().is_empty());
}

#[test]
fn beam_looks_count_misses_without_track_ids() {
    let sc = Scene::new();
    let mut tr = MultiTargetTracker::new(TrackerConfig::default(), sc.sim.centre);
    let id = dwell(&mut tr, &sc, DwellKind::Search, 0.0, vec![], true)[0].track_id;
    dwell(&mut tr, &sc, DwellKind::Confirm, 0.3, vec![id], true);
    dwell(&mut tr, &sc, DwellKind::Track, 0.6, vec![id], true);
    let g = tr.predict_local(id, 1.0).expect("live track");
    let pm = tr.predict_measurement_of(&g, 1.0, R1, R1, 0, &sc.sim.geom).expect("prediction");
    let truth_rho = (sc.sim.ecef(&sc.truth(1.0)) - sc.sim.geom.face(R1, 0, 1.0).expect("face").origin_ecef).length();
    assert!((pm.rho_m - truth_rho).abs() < 5.0 * pm.sigma_rho_m.max(5.0), "{} vs {truth_rho}", pm.rho_m);
    let look = |du: f64| Look { tx: R1, rx: R1, rx_face: 0, beam_u: pm.u + du, beam_v: pm.v, rho_window_m: None };
    // A beam one beamwidth away does not see the track; one on it does.
    let ctx = DwellContext { looks: vec![look(0.0252)], ..DwellContext::aimed(0, 99, 1.0, DwellKind::Track, vec![]) };
    tr.process_dwell(&ctx, &[], &sc.sim.geom);
    assert_eq!(tr.track(id).map(|t| t.consecutive_misses), Some(0));
    let ctx = DwellContext { looks: vec![look(0.002)], ..DwellContext::aimed(0, 100, 1.0, DwellKind::Track, vec![]) };
    tr.process_dwell(&ctx, &[], &sc.sim.geom);
    assert_eq!(tr.track(id).map(|t| t.consecutive_misses), Some(1));
    // A search dwell never counts a miss.
    let ctx = DwellContext { looks: vec![look(0.0)], ..DwellContext::search(0, 101, 1.0) };
    tr.process_dwell(&ctx, &[], &sc.sim.geom);
    assert_eq!(tr.track(id).map(|t| t.consecutive_misses), Some(1));
    // A range window that excludes the track does not count either.
    let mut l = look(0.0);
    l.rho_window_m = Some((pm.rho_m + 2000.0, pm.rho_m + 4000.0));
    let ctx = DwellContext { looks: vec![l], ..DwellContext::aimed(0, 102, 1.0, DwellKind::Track, vec![]) };
    tr.process_dwell(&ctx, &[], &sc.sim.geom);
    assert_eq!(tr.track(id).map(|t| t.consecutive_misses), Some(1));
}

#[test]
fn merged_measurement_updates_both_unresolved_tracks() {
    let sim = Sim::new();
    let r = 60_000.0;
    for merged in [false, true] {
        let mut tr = MultiTargetTracker::new(TrackerConfig::default(), sim.centre);
        let a = spawn_at(&mut tr, &sim, r, 0.0, 400.0);
        let b = spawn_at(&mut tr, &sim, r, 60.0 / r, 400.0);
        let mut m = row_at(0, r, 30.0 / r, 0.0, 0.5, 5, 1e-8);
        m.merged = merged;
        let rows = tr.process_dwell(&DwellContext::aimed(0, 1, 0.5, DwellKind::Track, vec![a, b]), &[m], &sim.geom);
        assert_eq!(rows.len(), if merged { 2 } else { 1 }, "merged = {merged}");
        assert!(rows.iter().all(|r| r.last_meas_id == Some(5)));
    }
}

#[test]
fn two_point_initiation_waits_for_a_second_detection() {
    let sc = Scene::new();
    let cfg =
        TrackerConfig { initiator: InitiatorConfig::TwoPoint(TwoPointConfig::default()), ..TrackerConfig::default() };
    let mut tr = MultiTargetTracker::new(cfg, sc.sim.centre);
    assert!(dwell(&mut tr, &sc, DwellKind::Search, 0.0, vec![], true).is_empty());
    let rows = dwell(&mut tr, &sc, DwellKind::Search, 2.0, vec![], true);
    assert_eq!(rows.len(), 1);
    // Two detections already make 2-of-3.
    assert_eq!(rows[0].status, TrackStatus::Confirmed);
    assert_eq!(rows[0].n_updates, 2);
    let (nees, _) = sc.sim.nees(&rows[0], &sc.truth(2.0));
    assert!(nees < 30.0, "two-point estimate NEES {nees}");
}

#[test]
fn revisit_bookkeeping_and_due_tracks() {
    let sc = Scene::new();
    let mut tr = MultiTargetTracker::new(TrackerConfig::default(), sc.sim.centre);
    let id = dwell(&mut tr, &sc, DwellKind::Search, 0.0, vec![], true)[0].track_id;
    let info = &tr.tracks()[0];
    assert!((info.next_due_s - 0.3).abs() < 1e-12, "confirmation dwell 0.3 s after initiation");
    assert!(tr.due_tracks(0.2, 0.0).is_empty());
    assert_eq!(tr.due_tracks(0.3, 0.0), vec![id]);
    let mut t = 0.3;
    for _ in 0..8 {
        dwell(&mut tr, &sc, DwellKind::Track, t, vec![id], true);
        let info = &tr.tracks()[0];
        assert_eq!(info.status, TrackStatus::Confirmed);
        let dt = info.next_due_s - t;
        let face = sc.sim.geom.face(R1, 0, t).expect("face");
        let direct = tr.revisit_interval(id, &face).expect("interval");
        assert!((dt - direct).abs() < 1e-9 && (0.25 - 1e-9..=4.0 + 1e-9).contains(&dt), "revisit {dt} vs {direct}");
        t = info.next_due_s;
    }
    // After a missed look the track is due again at once (re-dwell).
    dwell(&mut tr, &sc, DwellKind::Track, t, vec![id], false);
    assert!((tr.tracks()[0].next_due_s - (t + 0.05)).abs() < 1e-12);
}

#[test]
fn bad_rows_are_skipped_and_counted() {
    let sc = Scene::new();
    let mut tr = MultiTargetTracker::new(TrackerConfig::default(), sc.sim.centre);
    let good = sc.meas(0.0, 1);
    let bad = [
        MeasurementRow { u: f64::NAN, meas_id: 2, ..good.clone() },
        MeasurementRow { rx_face: 9, meas_id: 3, ..good.clone() },
        MeasurementRow { var_range_m2: -1.0, meas_id: 4, ..good.clone() },
        MeasurementRow { tx: mimo_core::ids::RadarId(7), meas_id: 5, ..good.clone() },
    ];
    let mut all = bad.to_vec();
    all.push(good);
    let rows = tr.process_dwell(&DwellContext::search(0, 1, 0.0), &all, &sc.sim.geom);
    assert_eq!(rows.len(), 1);
    assert_eq!(tr.stats().rejected_measurements, 4);
    let ctx = DwellContext { t_s: f64::NAN, ..DwellContext::search(0, 2, 0.0) };
    assert!(tr.process_dwell(&ctx, &bad, &sc.sim.geom).is_empty());
    assert!(tr.predict(rows[0].track_id, f64::INFINITY).is_none());
}

/// Three targets, several search and track dwells, some clutter; returns all rows.
fn busy_scene(reverse: bool, kind: TrackerKind) -> Vec<TrackRow> {
    let sim = Sim::new();
    let mut tr = MultiTargetTracker::new(TrackerConfig::for_kind(kind), sim.centre);
    let targets = [
        [40_000.0, 30_000.0, 6_000.0, -200.0, 0.0, 0.0],
        [40_300.0, 30_100.0, 6_000.0, -200.0, 10.0, 0.0],
        [-50_000.0, 20_000.0, 10_000.0, 230.0, 0.0, 0.0],
    ];
    let mut out = Vec::new();
    let mut rng = rng(&[4242]);
    let mut mid = 0;
    for k in 0..30 {
        let t = k as f64 * 0.5;
        let mut meas = Vec::new();
        for x0 in &targets {
            let x = [x0[0] + t * x0[3], x0[1] + t * x0[4], x0[2] + t * x0[5], x0[3], x0[4], x0[5]];
            for rx in [R1, R2] {
                if rng.uniform() < 0.85 {
                    mid += 1;
                    meas.push(sim.measure(&mut rng, &x, rx, rx, 6.0, 8e-4, t, mid));
                }
            }
        }
        if reverse {
            meas.reverse();
        }
        let ids: Vec<u64> = tr.tracks().iter().map(|t| t.id).collect();
        let ctx =
            if k % 3 == 0 { DwellContext::search(0, k, t) } else { DwellContext::aimed(0, k, t, DwellKind::Mimo, ids) };
        let rows = tr.process_dwell(&ctx, &meas, &sim.geom);
        rows.iter().for_each(assert_row_finite);
        out.extend(rows);
    }
    out
}

#[test]
fn results_do_not_depend_on_row_order_and_are_repeatable() {
    for kind in TrackerKind::ALL {
        let a = busy_scene(false, kind);
        let b = busy_scene(true, kind);
        let c = busy_scene(false, kind);
        assert_eq!(a, b, "{kind}: row order changed the result");
        assert_eq!(a, c, "{kind}: not repeatable");
        let confirmed: std::collections::BTreeSet<u64> =
            a.iter().filter(|r| r.status == TrackStatus::Confirmed).map(|r| r.track_id).collect();
        assert_eq!(confirmed.len(), 3, "{kind}: three targets, three confirmed tracks: {confirmed:?}");
    }
}

#[test]
fn config_names_and_serde() {
    assert_eq!("imm".parse::<TrackerKind>(), Ok(TrackerKind::Imm));
    assert_eq!(TrackerKind::parse("default"), Some(TrackerKind::Default));
    assert!("kalman".parse::<TrackerKind>().is_err());
    let cfg = TrackerConfig::for_kind(TrackerKind::Imm);
    cfg.validate().expect("defaults are valid");
    let json = serde_json::to_string(&cfg).expect("serialize");
    let back: TrackerConfig = serde_json::from_str(&json).expect("deserialize");
    assert_eq!(back, cfg);
    let partial: TrackerConfig =
        serde_json::from_str(r#"{"kind": "imm", "confirmation": {"m": 3, "n": 4}}"#).expect("partial");
    assert_eq!(partial.kind, TrackerKind::Imm);
    assert_eq!(partial.gate, TrackerConfig::default().gate);
    let bad = TrackerConfig { confirmation: MOfN { m: 4, n: 3 }, ..TrackerConfig::default() };
    assert!(bad.validate().is_err());
    let centre = mimo_core::geo::Geodetic::from_deg(36.0, -70.0, 0.0);
    assert_eq!(MultiTargetTracker::by_name("imm", centre).map(|t| t.filter_name()), Some("imm-2".to_string()));
    assert!(MultiTargetTracker::by_name("nope", centre).is_none());
}
