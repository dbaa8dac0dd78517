//! Property tests of the test-article protocol's line parser and track-row check
//! (docs/ta-protocol.md, docs/design.md §7): whatever a child process writes, reading it as a
//! reply gives a reply or one `bad reply` line quoting at most 120 characters — never a panic; a
//! reply written by the protocol's own types reads back as itself; and the track rows of a reply
//! are refused exactly when a track steps back beyond the out-of-sequence window.

use mimo_core::records::{TrackRow, TrackStatus};
use mimo_core::table_rules::TRACK_OUT_OF_SEQUENCE_S;
use mimo_sim::messages::{ReplyMessage, Request};
use mimo_sim::test_article::TaFault;
use mimo_sim::track_check::TrackRowCheck;
use mimo_ta::process::parse_reply;
use proptest::prelude::*;

fn row(track_id: u64, t_s: f64, x_m: f64) -> TrackRow {
    TrackRow {
        run: 0,
        t_s,
        track_id,
        status: TrackStatus::Confirmed,
        x_m,
        y_m: -x_m,
        z_m: 0.5 * x_m,
        vx_mps: 1.0,
        vy_mps: 2.0,
        vz_mps: 3.0,
        cov: [1.0; 21],
        n_updates: 3,
        last_meas_id: Some(track_id * 7),
    }
}

fn check_bad(line: &str) {
    if let Err(e) = parse_reply(line, 12.5) {
        let msg = e.to_string();
        assert!(matches!(e, TaFault::BadMessage(_)), "{msg}");
        assert!(!msg.contains('\n') && !msg.contains('\r'), "one line: {msg:?}");
        assert!(msg.contains("t = 12.5 s"), "names the message: {msg}");
    }
}

/// A valid reply, as a test article would write it.
const VALID: &str = r#"{"requests":[{"wake_at":3.5},{"stop_local_tracking":"R2"}],"tracks":[{"t_s":1.0,"track_id":4,"status":"confirmed","x_m":1.0,"y_m":2.0,"z_m":3.0,"vx_mps":0.0,"vy_mps":0.0,"vz_mps":0.0,"cov":[1,0,0,0,0,0,1,0,0,0,0,1,0,0,0,1,0,0,1,0,1],"n_updates":2,"last_meas_id":null}]}"#;

#[test]
fn a_reply_that_is_not_a_json_object_is_refused() {
    for line in ["[]", "[[], []]", "42", "\"{}\"", "null"] {
        let e = parse_reply(line, 12.5).expect_err(line).to_string();
        assert!(e.contains("expected a JSON object") && e.contains("t = 12.5 s"), "{line}: {e}");
    }
    assert!(parse_reply(" {}", 0.0).is_ok(), "leading space before an object");
}

#[test]
fn the_valid_reply_reads() {
    let r = parse_reply(&format!("{VALID}\r\n"), 0.0).expect("valid");
    assert_eq!(r.requests.len(), 2);
    assert_eq!(r.tracks[0].track_id, 4);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn any_line_is_a_reply_or_one_bad_reply_line(line in "\\PC{0,300}") {
        check_bad(&line);
    }

    #[test]
    fn mutated_replies_never_panic(at in 0usize..VALID.len(), len in 0usize..10, with in "[-0-9a-z_.:,{}\\[\\]\" ]{0,10}") {
        let mut text = VALID.as_bytes().to_vec();
        let end = (at + len).min(text.len());
        text.splice(at..end, with.bytes());
        if let Ok(t) = String::from_utf8(text) {
            check_bad(&t);
        }
    }

    #[test]
    fn replies_round_trip(ids in proptest::collection::vec(0u64..50, 0..6), t in 0.0f64..1e4, wake in 0.0f64..1e4) {
        let tracks: Vec<TrackRow> = ids.iter().enumerate().map(|(i, &id)| row(id, t + i as f64, 1e5 + i as f64)).collect();
        let reply = ReplyMessage { requests: vec![Request::WakeAt(wake)], tracks, ..ReplyMessage::default() };
        let line = serde_json::to_string(&reply).expect("json") + "\n";
        prop_assert_eq!(parse_reply(&line, t).expect("reads back"), reply);
    }

    #[test]
    fn track_rows_are_refused_exactly_beyond_the_window(steps in proptest::collection::vec(-3.0f64..3.0, 1..40)) {
        // One track whose times move by `steps`; the check must fail at the first row more than
        // the window behind the latest time so far, and nowhere else.
        let mut t = 100.0;
        let mut latest = f64::MIN;
        let mut expected_fail = None;
        let mut rows = Vec::new();
        for (i, s) in steps.iter().enumerate() {
            t += s;
            if expected_fail.is_none() && t < latest - TRACK_OUT_OF_SEQUENCE_S {
                expected_fail = Some(i);
            }
            latest = latest.max(t);
            rows.push(row(1, t, 0.0));
        }
        let mut check = TrackRowCheck::default();
        let first_fail = rows.iter_mut().position(|r| check.check(std::slice::from_mut(r)).is_err());
        prop_assert_eq!(first_fail, expected_fail);
    }
}
