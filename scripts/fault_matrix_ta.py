#!/usr/bin/env python3
"""A test article that misbehaves on purpose (scripts/fault_matrix.sh).

    python3 scripts/fault_matrix_ta.py MODE

It answers `start` by subscribing to every dwell and asking for a wake-up at t = 2 s, and
commits its fault at the first message after `start` (a dwell in an open-loop `mimo track`, a
dwell or the wake-up in `mimo simulate`). Plain json only, so each fault is exactly the bytes
written here.
"""

import json
import sys
import time

MODE = sys.argv[1]
ROW = {"track_id": 7, "status": "confirmed", "x_m": 1.3e6, "y_m": -4.8e6, "z_m": 3.9e6, "vx_mps": 0.0,
       "vy_mps": 0.0, "vz_mps": 0.0, "cov": [1.0, 0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 1.0, 0, 0, 1.0, 0, 1.0],
       "n_updates": 2, "last_meas_id": None}


def track(now, **over):
    return json.dumps({"tracks": [dict(ROW, t_s=now, **over)]})


def fault(now):
    faults = {
        "crash": lambda: sys.exit(3),
        "close_stdout": lambda: "{}",
        "exit_zero_early": lambda: sys.exit(0),
        "hang": lambda: time.sleep(120),
        "not_json": lambda: "hello, mimo",
        "garbage_bytes": lambda: "\x00\x01\xff\xfe{{{",
        "empty_line": lambda: "",
        "json_array": lambda: "[]",
        "json_number": lambda: "42",
        "huge_line": lambda: json.dumps({"requests": [], "pad": "x" * (200 * 1024 * 1024)}),
        "deep_nesting": lambda: "[" * 100000 + "]" * 100000,
        "two_lines": lambda: "{}\n{}",
        "unknown_key": lambda: json.dumps({"requests": [], "trackz": []}),
        "track_back": lambda: json.dumps({"tracks": [dict(ROW, t_s=now + 30.0), dict(ROW, t_s=now)]}),
        "track_future": lambda: track(now + 1.0e6),
        "track_nan_cov": lambda: track(now, cov=[float("nan")] + ROW["cov"][1:]),
        "track_neg_var": lambda: track(now, cov=[-1.0] + ROW["cov"][1:]),
        "track_cov_len20": lambda: track(now, cov=ROW["cov"][:20]),
        "track_non_psd": lambda: track(now, cov=[1.0, 100.0] + ROW["cov"][2:]),
        # Correlation 1 + 2e-6 between x and y: smallest eigenvalue -1e-6 of the largest (2),
        # repaired and counted; 1.02: -1e-2 of it, refused with the eigenvalue named.
        "track_near_psd": lambda: track(now, cov=[1.0, 1.0 + 2e-6] + ROW["cov"][2:]),
        "track_far_psd": lambda: track(now, cov=[1.0, 1.02] + ROW["cov"][2:]),
        "track_bad_status": lambda: track(now, status="bogus"),
        "track_neg_id": lambda: track(now, track_id=-1),
        "track_huge_x": lambda: track(now, x_m=1.0e300),
        "track_string_x": lambda: track(now, x_m="abc"),
        "wake_nan": lambda: '{"requests": [{"wake_at": NaN}]}',
        "wake_past": lambda: json.dumps({"requests": [{"wake_at": now - 1.5}]}),
        "dwell_zero_pulses": lambda: json.dumps({"requests": [{"dwell": {
            "kind": "track", "earliest_s": now, "aim_ecef": [1.3e6, -4.8e6, 3.9e6],
            "transmitters": [{"radar": "R1", "n_pulses": 0}], "receivers": ["R1"], "window_half_m": 1000.0}}]}),
        "dwell_huge_pulses": lambda: json.dumps({"requests": [{"dwell": {
            "kind": "track", "earliest_s": now, "aim_ecef": [1.3e6, -4.8e6, 3.9e6],
            "transmitters": [{"radar": "R1", "n_pulses": 4294967295}], "receivers": ["R1"],
            "window_half_m": 1000.0}}]}),
        "many_wakes": lambda: json.dumps({"requests": [{"wake_at": now + 1e-9 * (i + 1)} for i in range(2000000)]}),
    }
    return faults[MODE]()


started = False  # between `start` and the fault: the fault is committed once
for line in sys.stdin:
    msg = json.loads(line)
    kinds = [e["event"] for e in msg["events"]]
    if "start" in kinds:
        out = json.dumps({"name": "fault-" + MODE, "subscribe": {"dwells": "all"}, "requests": [{"wake_at": 2.0}]})
        started = True
    elif "finish" in kinds or not started:
        out = "{}"
    else:
        out = fault(msg["t_s"])
        started = False
    sys.stdout.write(out + "\n")
    sys.stdout.flush()
    if MODE == "close_stdout" and started is False:
        sys.stdout.close()
        time.sleep(5)
        sys.exit(0)
