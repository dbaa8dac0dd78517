//! The test-article messages as JSON: the shapes docs/ta-protocol.md documents, round trips,
//! and what is refused.

use mimo_core::DVec3;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, MeasurementRow, Requester, TrackStatus};
use mimo_sim::messages::{
    DwellFilter, DwellReport, EventMessage, PartReport, Reply, ReplyMessage, Request, Subscription, TaEvent,
};
use serde_json::{Value, json};

fn measurement() -> MeasurementRow {
    MeasurementRow {
        run: 3,
        meas_id: 335_544_320,
        dwell_id: 81_920,
        t_s: 12.3401,
        rx: RadarId(0),
        tx: RadarId(0),
        rx_face: 2,
        range_m: 181_234.5,
        u: 0.0121,
        v: -0.2279,
        snr_db: 17.3,
        var_range_m2: 41.2,
        var_u: 2.1e-6,
        var_v: 2.3e-6,
        n_primitives: 1,
        merged: false,
        target_hint: Some("F-1".into()),
    }
}

fn report() -> DwellReport {
    DwellReport {
        run: 3,
        group_id: 81_920,
        kind: DwellKind::Search,
        requested_by: Requester::Radar,
        t_s: 12.3401,
        duration_s: 0.0077,
        end_s: 12.34395,
        aim_ecef: DVec3::new(1.2e6, -4.7e6, 4.1e6),
        tag: Vec::new(),
        parts: vec![PartReport {
            radar: RadarId(0),
            dwell_id: 81_920,
            transmits: true,
            receives: true,
            face: 2,
            beam_u: 0.0113,
            beam_v: -0.2268,
            n_pulses: 2,
            site_ecef: DVec3::new(1.3e6, -4.8e6, 3.7e6),
            face_from_ecef: [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]],
        }],
        measurements: vec![measurement()],
        primitives: Vec::new(),
    }
}

#[test]
fn a_dwell_report_is_json_without_truth_or_run() {
    let msg = EventMessage { t_s: 12.34395, events: vec![TaEvent::DwellEnded(report())] };
    let v: Value = serde_json::to_value(&msg).expect("json");
    let ev = &v["events"][0];
    assert_eq!(ev["event"], json!("dwell_ended"));
    assert_eq!(ev["kind"], json!("search"));
    assert_eq!(ev["requested_by"], json!("radar"));
    assert_eq!(ev["aim_ecef"], json!([1.2e6, -4.7e6, 4.1e6]));
    assert_eq!(ev["parts"][0]["radar"], json!("R1"));
    assert_eq!(ev["parts"][0]["face_from_ecef"][2], json!([1.0, 0.0, 0.0]));
    let m = &ev["measurements"][0];
    assert_eq!(m["rx"], json!("R1"));
    assert_eq!(m["range_m"], json!(181_234.5));
    assert!(m.get("target_hint").is_none(), "truth never appears: {m}");
    assert!(m.get("run").is_none());
    // Back again: everything but the skipped columns survives.
    let back: EventMessage = serde_json::from_value(v).expect("parse");
    let TaEvent::DwellEnded(r) = &back.events[0] else { panic!("not a dwell report") };
    let mut want = report();
    want.measurements[0].run = 0;
    want.measurements[0].target_hint = None;
    assert_eq!(r, &want);
    // The part's frame is the rotation whose rows were sent.
    let f = r.parts[0].frame();
    assert!((f.face_from_ecef * DVec3::new(0.0, 1.0, 0.0) - DVec3::new(1.0, 0.0, 0.0)).length() < 1e-15);
}

#[test]
fn every_event_round_trips() {
    for ev in [TaEvent::Wake { t_s: 15.25 }, TaEvent::Finish { t_s: 1000.0 }, TaEvent::DwellEnded(report())] {
        let text = serde_json::to_string(&ev).expect("json");
        let back: TaEvent = serde_json::from_str(&text).expect("parse");
        let again = serde_json::to_string(&back).expect("json");
        assert_eq!(text, again);
    }
    assert_eq!(
        serde_json::to_value(TaEvent::Wake { t_s: 15.25 }).expect("json"),
        json!({"event": "wake", "t_s": 15.25})
    );
}

#[test]
fn the_documented_reply_parses() {
    let text = r#"{"requests": [
       {"dwell": {"kind": "track", "earliest_s": 12.35, "aim_ecef": [1.2e6, -4.7e6, 4.1e6],
                  "transmitters": [{"radar": "R1", "n_pulses": 4}], "receivers": ["R1", "R3"],
                  "window_half_m": 1000.0, "predicted_snr": null, "tag": [17]}},
       {"wake_at": 13.1},
       {"stop_local_tracking": "R2"}
     ],
     "tracks": [
       {"t_s": 12.3401, "track_id": 17, "status": "confirmed",
        "x_m": 1.21e6, "y_m": -4.71e6, "z_m": 4.09e6, "vx_mps": 210.0, "vy_mps": -30.5, "vz_mps": 2.0,
        "cov": [100.0, 0.0, 0.0, 0.0, 0.0, 0.0, 100.0, 0.0, 0.0, 0.0, 0.0, 100.0, 0.0, 0.0, 0.0,
                25.0, 0.0, 0.0, 25.0, 0.0, 25.0],
        "n_updates": 5, "last_meas_id": 335544320}
     ]}"#;
    let r: Reply = serde_json::from_str(text).expect("reply");
    assert_eq!(r.requests.len(), 3);
    let Request::Dwell(d) = &r.requests[0] else { panic!("not a dwell") };
    assert_eq!(d.kind, DwellKind::Track);
    assert_eq!(d.transmitters[0].radar, RadarId(0));
    assert_eq!(d.receivers, vec![RadarId(0), RadarId(2)]);
    assert_eq!(d.tag, vec![17]);
    assert_eq!(r.requests[1], Request::WakeAt(13.1));
    assert_eq!(r.requests[2], Request::StopLocalTracking(RadarId(1)));
    assert_eq!(r.tracks[0].status, TrackStatus::Confirmed);
    assert_eq!(r.tracks[0].cov[15], 25.0);
    assert_eq!(r.tracks[0].last_meas_id, Some(335_544_320));
    // An empty reply, and the start reply's extra keys.
    assert_eq!(serde_json::from_str::<Reply>("{}").expect("empty"), Reply::default());
    let s: ReplyMessage = serde_json::from_str(
        r#"{"name": "simple-ta", "config": {"sigma_a_mps2": 15.0},
            "subscribe": {"dwells": "own", "primitives": true}, "requests": [{"wake_at": 1.0}]}"#,
    )
    .expect("start reply");
    assert_eq!(s.subscribe, Some(Subscription { dwells: DwellFilter::Own, primitives: true, batch: false }));
    assert_eq!(s.name.as_deref(), Some("simple-ta"));
}

#[test]
fn malformed_replies_are_refused() {
    for bad in [
        r#"{"request": []}"#,
        r#"{"requests": [{"sleep": 1.0}]}"#,
        r#"{"requests": [{"wake_at": "soon"}]}"#,
        r#"{"requests": [{"dwell": {"kind": "track"}}]}"#,
        r#"{"tracks": [{"t_s": 1.0, "track_id": 1, "status": "lost"}]}"#,
        r#"{"requests": [{"stop_local_tracking": "X2"}]}"#,
        r#"{"tracks": [{"run": 0, "t_s": 1.0, "track_id": 1, "status": "confirmed", "x_m": 0, "y_m": 0, "z_m": 0,
             "vx_mps": 0, "vy_mps": 0, "vz_mps": 0, "cov": [0], "n_updates": 1, "last_meas_id": null}]}"#,
    ] {
        assert!(serde_json::from_str::<Reply>(bad).is_err(), "accepted: {bad}");
    }
}
