"""The run behind the learning environments: one ``mimo simulate`` driven from Python.

The protocol is callback-style: ``mimo`` writes a message and waits for the reply
(docs/ta-protocol.md §1). Here control is inverted without threads: ``mimo`` is started with a
test-article command that hands its stdin and stdout — mimo's two pipes — to this process over a
Unix socket (SCM_RIGHTS) and exits, so the environment reads each message from mimo's pipe when
the agent asks for the next decision and writes the reply when the agent says ``wait``. (Until
issue 41's speed work the command was a relay of two ``cat`` processes, two more pipe hops each
way.) Nothing is sent before the agent's decision is complete, so the
run stays the deterministic function of the seed and of the decisions that docs/ta-protocol.md §6
promises.

The tracker is, by default (``tracker="builtin"``), the built-in default test article's (IMM +
JPDA): mimo runs with ``--ta-role resource-manager`` (docs/ta-protocol.md §7,
docs/decisions/0316-built-in-tracker-external-resource-manager.md), sends the tracker's rows and
the built-in rule's proposed looks with every message, and the agent's reply says which proposals
to make (``accept``) and what else. With ``tracker="simple"`` it is the Python simple test
article's (``mimo_ta.simple``: EKF + nearest neighbour, the default test article's revisit and pulse
rules) with its scheduling replaced by the agent's decisions, over the whole-test-article role
(docs/decisions/0311-learning-environments.md).

Reward (docs/decisions/0311-learning-environments.md): at every scoring time ``t_k`` the online
completeness ``A_k / N_k`` of the challenge (docs/design.md §6: scorable truths paired with live
confirmed tracks, gated 1000 m, most pairs first) divided by the number of scoring times with a
scorable truth — so an episode's completeness terms sum to ``mimo score``'s completeness — minus
``energy_weight`` × the energy spent (kJ): the transmitted energy of every look the agent orders,
and the background search's, estimated from each radar's search share and its full-search
energy rate. Which truths are scorable, and where they are, come from a reference run of the
same scenario and seed with ``--tracker none`` (truth does not depend on the test article).
"""

from __future__ import annotations

import bisect
import glob
import json
import math
import os
import select
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import weakref
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..binary import find_mimo_bin
from ..measurement import jacobian
from ..messages import DwellRequest, Finish, SearchOrder, SearchPlan, StartInfo, TxOrder, Wake, WakeAt, parse_event
from ..geo import (EARTH_MEAN_RADIUS_M, K_EFFECTIVE_EARTH, SHIP_FRAME_STEP_S, WGS84_A_M, WGS84_B_M,
                   ecef_to_geodetic_rad)
from ..radar import (BOLTZMANN_J_PER_K, T0_K, db_to_lin, pointing_loss, predict_pair, pulses_for, required_snr_sw1,
                     straddle_loss)
from ..geo import EnuFrame, Ship
from ..messages import TrackRow
from ..simple import PENDING_TIMEOUT_S, SimpleTa, Track

TRACKERS = ("builtin", "simple")
"""``builtin``: the built-in default test article's tracker, the agent its resource manager
(docs/ta-protocol.md §7); ``simple``: ``mimo_ta.simple``'s tracker run in the environment."""
BUILTIN_T_MAX_S = 2.0
"""The built-in test articles' longest revisit of a confirmed track (s; docs/model.md §7.1): the
observation's time to the rule's revisit of a track the rule has not proposed yet is measured to
its last update plus this."""

SEARCH_SHARES = (1.0, 0.5, 0.25, 0.1, 0.0)
"""The search shares an agent may order (docs/model.md §7.4): 1 is the radars' own raster."""
PULSE_LEVELS = (0, 1, 2, 4, 8, 16)
"""Pulses of a look: 0 is the default test article's rule (sized for P_D 0.9 with the expected
losses, doubled after each miss; docs/model.md §7.2); the others are fixed counts, clipped to a
radar's ``max_pulses``."""
SCORING_LAG_S = 0.1
"""A scoring time is evaluated once the simulation is this far past it: a dwell whose mid-time
(the time of its track rows) is before ``t_k`` may end after it (dwells last < 0.1 s)."""


class MimoError(RuntimeError):
    """``mimo`` refused the scenario or stopped: the message holds its error line(s)."""


# ---------------------------------------------------------------------------------------------
# The reference run: truth, scorable truths, search energy rates


@dataclass
class Reference:
    times: np.ndarray  # scoring times with at least one scorable truth
    scorable: dict  # t_k -> list of target names
    truth: dict  # target -> (t array, position (n, 3) array)
    search_rate_j_per_s: dict  # radar -> energy per second of full background search
    gate_m: float

    def truth_at(self, target: str, t_s: float) -> np.ndarray:
        ts, pos = self.truth[target]
        i = int(np.searchsorted(ts, t_s))
        if i < len(ts) and abs(ts[i] - t_s) < 1e-6:
            return pos[i]
        i = min(max(i, 1), len(ts) - 1)
        w = (t_s - ts[i - 1]) / (ts[i] - ts[i - 1])
        return pos[i - 1] * (1 - w) + pos[i] * w


_REFERENCES: dict = {}
_REFERENCES_KEPT = 64
_I3 = np.eye(3)


def _run(cmd: list, what: str) -> None:
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        lines = [ln for ln in (p.stderr or "").splitlines() if ln.strip()]
        raise MimoError(f"{what}: " + ("\n".join(lines) if lines else f"exit status {p.returncode}"))


def reference(mimo: str, scenario: str, seed: int, duration_s: float, extra_args: tuple) -> Reference:
    """The reference run of (scenario, seed, duration), made once per process and kept in memory."""
    key = (mimo, scenario, seed, duration_s, extra_args)
    if key in _REFERENCES:
        return _REFERENCES[key]
    import pyarrow.parquet as pq

    tmp = tempfile.mkdtemp(prefix="mimo-gym-ref-")
    try:
        out = os.path.join(tmp, "run")
        _run([mimo, "simulate", "--scenario", scenario, "--seed", str(seed), "--duration", repr(duration_s),
              "--tracker", "none", "--threads", "1", "--quiet", "--out", out, *extra_args], "mimo simulate")
        _run([mimo, "score", out, "--no-charts", "--quiet", "--threads", "1"], "mimo score")
        truth = pq.read_table(glob.glob(os.path.join(out, "truth", "*.parquet"))).to_pydict()
        by_target: dict = {}
        for t, name, x, y, z in zip(truth["t_s"], truth["target"], truth["x_m"], truth["y_m"], truth["z_m"]):
            by_target.setdefault(name, ([], []))
            by_target[name][0].append(t)
            by_target[name][1].append((x, y, z))
        truth_arrays = {k: (np.array(v[0]), np.array(v[1])) for k, v in by_target.items()}
        a = pq.read_table(os.path.join(out, "score", "assignments.parquet")).to_pydict()
        scorable: dict = {}
        for t, name in zip(a["t_s"], a["target"]):
            scorable.setdefault(t, []).append(name)
        with open(os.path.join(out, "score", "summary.json")) as f:
            summary = json.load(f)
        rates = {r: u["energy_j"] / duration_s for r, u in summary["usage"]["per_radar"].items()}
        ref = Reference(np.array(sorted(scorable)), scorable, truth_arrays, rates, float(summary.get("gate_m", 1000.0)))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if len(_REFERENCES) >= _REFERENCES_KEPT:  # training draws many seeds: keep the latest
        _REFERENCES.pop(next(iter(_REFERENCES)))
    _REFERENCES[key] = ref
    return ref


# ---------------------------------------------------------------------------------------------
# The tracker: the simple test article without its scheduler


class AgentTracker(SimpleTa):
    """``mimo_ta.simple.SimpleTa`` whose looks are the agent's: its ``schedule`` does nothing."""

    name = "gym-agent (simple-ta tracker)"

    def schedule(self, now_s: float) -> None:  # the agent schedules
        pass


class RuleTracks(AgentTracker):
    """The built-in tracker's tracks as the agent sees them (``tracker="builtin"``): each track is
    its latest row from mimo (docs/ta-protocol.md §7), turned into the ENU frame of
    ``mimo_ta.simple`` so that predictions, visibility and the looks' sizing are the same code.
    Nothing is tracked here; ``misses_in_row`` counts the looks at a track whose report brought no
    row of it."""

    name = "gym-agent (built-in tracker)"

    def on_start(self, start) -> None:  # the built-in's settings are mimo's (--set), not ours
        c = start.centre
        self.enu = EnuFrame.at(c.lat_deg, c.lon_deg, 0.0)
        self.ships = {sh.radar: Ship.from_info(sh, start.duration_s) for sh in start.ships}
        self.params = {sh.radar: sh.radar_params for sh in start.ships}
        self.tracks, self.next_id, self.next_wake_s = {}, 1, math.inf
        self._rot = self.enu.enu_from_ecef
        self._big = np.zeros((6, 6))
        self._big[:3, :3] = self._big[3:, 3:] = self._rot
        self._iu = np.triu_indices(6)

    def ingest(self, rows: list, looked: list, now_s: float) -> list:
        """Take the rows of one message; ``looked``: the track ids of the test article's looks
        reported in it. Returns the rows as :class:`TrackRow` (for the online score)."""
        out = []
        seen = set()
        for d in rows:
            tid = int(d["track_id"])
            seen.add(tid)
            row = TrackRow(d["t_s"], tid, d["status"], d["x_m"], d["y_m"], d["z_m"], d["vx_mps"], d["vy_mps"],
                           d["vz_mps"], d["cov"], d["n_updates"], d.get("last_meas_id"))
            out.append(row)
            if row.status == "deleted":
                self.tracks.pop(tid, None)
                continue
            m = np.empty((6, 6))
            m[self._iu] = row.cov
            m.T[self._iu] = row.cov
            x = np.concatenate([self.enu.to_enu(np.array([row.x_m, row.y_m, row.z_m])),
                                self._rot @ np.array([row.vx_mps, row.vy_mps, row.vz_mps])])
            pm = self._big @ m @ self._big.T
            t = self.tracks.get(tid)
            if t is None:
                t = self.tracks[tid] = Track(tid, x, pm, row.t_s, row.status, row.n_updates, last_update_s=row.t_s,
                                             next_due_s=math.inf)
            else:
                if row.n_updates != t.n_updates:
                    t.last_update_s = row.t_s
                    t.misses_in_row = 0
                t.x, t.p, t.t_s, t.status, t.n_updates = x, pm, row.t_s, row.status, row.n_updates
        for tid in looked:
            t = self.tracks.get(tid)
            if t is not None and tid not in seen:
                t.misses_in_row += 1
        return out


# ---------------------------------------------------------------------------------------------
# The online score


class OnlineScore:
    """The challenge's completeness and breaks at each scoring time, from the track rows as they
    are emitted (docs/design.md §6: a track is live from its first
    ``confirmed`` row to its ``deleted`` row, its state the latest row at or before ``t_k``
    extrapolated at constant velocity)."""

    def __init__(self, ref: Reference) -> None:
        self.ref = ref
        self.rows: dict = {}  # track id -> ([t], [(pos, vel)])
        self.confirmed_at: dict = {}
        self.deleted_at: dict = {}
        self.k = 0
        self.assigned_prev: set = set()
        self.breaks = 0
        self.completeness_sum = 0.0

    def add(self, row) -> None:
        tid = row.track_id
        if tid in self.deleted_at:
            return
        ts, st = self.rows.setdefault(tid, ([], []))
        ts.append(row.t_s)
        st.append((np.array([row.x_m, row.y_m, row.z_m]), np.array([row.vx_mps, row.vy_mps, row.vz_mps])))
        if row.status == "confirmed" and tid not in self.confirmed_at:
            self.confirmed_at[tid] = row.t_s
        if row.status == "deleted":
            self.deleted_at[tid] = row.t_s

    def advance(self, now_s: float, final: bool = False) -> float:
        """Evaluate the scoring times now settled; return their summed completeness share."""
        from scipy.optimize import linear_sum_assignment

        gained = 0.0
        times = self.ref.times
        while self.k < len(times) and (final or times[self.k] + SCORING_LAG_S <= now_s):
            t = float(times[self.k])
            self.k += 1
            targets = self.ref.scorable[t]
            live = []
            for tid, c in self.confirmed_at.items():
                if c <= t and not (tid in self.deleted_at and self.deleted_at[tid] <= t):
                    ts, st = self.rows[tid]
                    i = bisect.bisect_right(ts, t) - 1
                    if i >= 0:
                        p, v = st[i]
                        live.append((tid, p + v * (t - ts[i])))
            assigned = set()
            if live:
                truth = np.array([self.ref.truth_at(g, t) for g in targets])
                tracks = np.array([p for _, p in live])
                d = np.linalg.norm(truth[:, None, :] - tracks[None, :, :], axis=2)
                ok = d <= self.ref.gate_m
                big = 1e9
                rows, cols = linear_sum_assignment(np.where(ok, d - big, 0.0))
                assigned = {targets[r] for r, c in zip(rows, cols) if ok[r, c]}
            self.breaks += len((self.assigned_prev & set(targets)) - assigned)
            self.assigned_prev = assigned
            share = len(assigned) / len(targets) / len(times)
            self.completeness_sum += share
            gained += share
        return gained


# ---------------------------------------------------------------------------------------------
# The run


def _scenario_arg(scenario) -> str:
    return str(scenario) if isinstance(scenario, (int, np.integer)) else os.fspath(scenario)


class NetworkRun:
    """One episode: ``mimo simulate`` with mimo's pipes held here, the tracker, the online score, and the
    decision point the agent is at. Used by :class:`mimo_ta.gym.NetworkEnv` (one agent) and
    :class:`mimo_ta.gym.ParallelNetworkEnv` (one agent per ship)."""

    def __init__(self, *, scenario, seed: int, duration_s: float, max_tracks: int, energy_weight: float,
                 decision_period_s: float, mimo_bin: Optional[str], tracker_config: Optional[dict],
                 extra_args: tuple, reply_timeout_s: float, workdir: str, tracker: str = "builtin") -> None:
        if tracker not in TRACKERS:
            raise ValueError(f"tracker: {tracker!r}, expected one of {TRACKERS}")
        self.builtin = tracker == "builtin"
        self.mimo = mimo_bin or find_mimo_bin()
        self.scenario = _scenario_arg(scenario)
        self.seed = int(seed)
        self.duration_s = float(duration_s)
        self.k_max = int(max_tracks)
        self.energy_weight = float(energy_weight)
        self.decision_period_s = float(decision_period_s)
        self.workdir = workdir
        self.run_dir = os.path.join(workdir, "run")
        self.proc: Optional[subprocess.Popen] = None
        self._rfd: Optional[int] = None
        self._wfd: Optional[int] = None
        self.done = False
        self.score: Optional[dict] = None
        self.ref = reference(self.mimo, self.scenario, self.seed, self.duration_s, tuple(extra_args))
        self.online = OnlineScore(self.ref)
        self.tracker = RuleTracks() if self.builtin else AgentTracker()
        self._tracker_config = dict(tracker_config or {})
        self.proposed: list = []  # the built-in rule's proposals at this decision point (raw JSON)
        self.due: dict = {}  # track id -> time the rule first proposed a look not made yet (builtin)
        self.energy_kj = 0.0
        self.energy_by_radar_kj: dict = {}
        self.ta_time_by_radar_s: dict = {}
        self.pending_time: dict = {}  # radar -> {tag: dwell duration} of looks not reported yet
        self.next_wake_s = math.inf
        self.steps = 0
        self.now_s = 0.0
        self.step_energy_kj = 0.0  # energy spent since the environment last reset it (kJ)
        self._consts = None  # per-radar constants of visibility (_radar_constants)
        self._frame_samples = None  # the ships' sampled frames as arrays (_frames_now)
        self._stack = None  # the slots' tracks and states, stacked (predicted_all)
        self.born: dict = {}  # track id -> time first seen
        self.last_look: dict = {}  # track id -> time of the agent's last look at it
        self._start(tuple(extra_args), reply_timeout_s)

    # -- the process --------------------------------------------------------------------------

    def _start(self, extra_args: tuple, reply_timeout_s: float) -> None:
        # The test article is a helper that hands its stdin and stdout (mimo's pipes) to this
        # process over a Unix socket (SCM_RIGHTS) and exits: the environment then reads and
        # writes mimo's pipes itself, with no relay between them.
        sock_path = os.path.join(tempfile.mkdtemp(prefix="mimo-gym-sock-"), "ta.sock")
        listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        listener.bind(sock_path)
        listener.listen(1)
        handoff = f"{shlex.quote(sys.executable)} -S -c {shlex.quote(_HANDOFF)} {shlex.quote(sock_path)}"
        self._stderr = tempfile.TemporaryFile(mode="w+b")
        cmd = [self.mimo, "simulate", "--scenario", self.scenario, "--seed", str(self.seed),
               "--duration", repr(self.duration_s), "--threads", "1", "--quiet", "--force",
               "--out", self.run_dir, "--ta-cmd", handoff, "--ta-timeout", repr(float(reply_timeout_s)), *extra_args]
        if self.builtin:  # the built-in default's tracker; tracker_config holds its --set keys
            cmd += ["--ta-role", "resource-manager"]
            for k, v in self._tracker_config.items():
                cmd += ["--set", f"{k}={json.dumps(v) if isinstance(v, bool) else v}"]
        try:
            self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=self._stderr, stderr=self._stderr,
                                         start_new_session=True)
        except BaseException:
            listener.close()
            shutil.rmtree(os.path.dirname(sock_path), ignore_errors=True)
            self._stderr.close()
            raise
        self._buf = bytearray()
        # An environment dropped without close(), or an interpreter that exits, still ends the run.
        weakref.finalize(self, _kill_group, self.proc)
        try:
            self._rfd, self._wfd = self._receive_pipes(listener)
        except BaseException:
            self.close()
            raise
        finally:
            listener.close()
            shutil.rmtree(os.path.dirname(sock_path), ignore_errors=True)
        try:
            self.read_until_decision()
        except BaseException:
            self.close()
            raise

    def _receive_pipes(self, listener: socket.socket) -> tuple:
        """mimo's two pipes, (read end of its messages, write end for the replies), from the
        helper; a mimo that ends first (a scenario it refuses) raises its error."""
        listener.settimeout(0.1)
        while True:
            try:
                conn, _ = listener.accept()
                break
            except socket.timeout:
                if self.proc.poll() is not None:
                    raise self._died("stopped before the run started") from None
        with conn:
            conn.settimeout(60.0)
            _msg, fds, _flags, _addr = socket.recv_fds(conn, 16, 2)
        if len(fds) != 2:
            for fd in fds:
                os.close(fd)
            raise self._died("did not start the test article")
        return fds[0], fds[1]

    def _stderr_text(self) -> str:
        self._stderr.seek(0)
        return self._stderr.read().decode("utf-8", "replace")

    def _died(self, what: str) -> MimoError:
        code = None
        try:
            code = self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            pass
        text = self._stderr_text()
        self.kill()
        lines = [ln for ln in text.splitlines() if ln.strip()]
        return MimoError(f"mimo {what} (exit status {code}): " + ("\n".join(lines) if lines else "no message"))

    def kill(self) -> None:
        """Stop mimo (its process group) and close the pipes; idempotent."""
        if self.proc is not None and self.proc.returncode is None:
            try:
                os.killpg(self.proc.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                pass
        elif self.proc is not None:
            # What of mimo's group outlives it by a moment. The test-article helper has a process
            # group of its own (docs/decisions/0325-test-article-process-group.md) and exits by
            # itself once it has handed the pipes over, or cannot connect.
            try:
                os.killpg(self.proc.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        if self._rfd is not None:
            os.close(self._rfd)
            self._rfd = None
        if self._wfd is not None:
            os.close(self._wfd)
            self._wfd = None

    def close(self) -> None:
        self.kill()
        if not self._stderr.closed:
            self._stderr.close()

    def _send(self, reply: dict) -> None:
        line = (json.dumps(reply, allow_nan=False, separators=(",", ":")) + "\n").encode()
        try:
            _write_all(self._wfd, line)
        except BrokenPipeError:
            raise self._died("stopped") from None

    def _readline(self) -> bytes:
        """The next line from mimo, or b"" once mimo has ended without one (end of file, or mimo
        seen ended by polling it)."""
        while True:
            i = self._buf.find(b"\n")
            if i >= 0:
                line = bytes(self._buf[: i + 1])
                del self._buf[: i + 1]
                return line
            ready, _, _ = select.select([self._rfd], [], [], 0.5)
            if ready:
                chunk = os.read(self._rfd, 1 << 16)
                if not chunk:
                    return b""
                self._buf += chunk
            elif self.proc.poll() is not None and not select.select([self._rfd], [], [], 0.05)[0]:
                return b""

    # -- messages -----------------------------------------------------------------------------

    def read_until_decision(self) -> float:
        """Read and process messages until one is a decision point (every message but ``finish``);
        on ``finish`` reply, end the run and score it. Returns the completeness share gained."""
        while True:
            line = self._readline()
            if not line:
                raise self._died("stopped before the run ended")
            msg = json.loads(line)
            tr = self.tracker
            tr._requests, tr._tracks = [], []
            now = float(msg["t_s"])
            self.elapsed_s = now - self.now_s
            tr.now_s = self.now_s = now
            self.is_start = False
            finish = False
            if self.builtin:
                finish = self._builtin_events(msg, now)
                if tr._tracks:
                    self._stack = None
            else:
                finish = self._simple_events(msg)
                self._stack = None  # the simple tracker updates its tracks in place
            for row in tr._tracks:
                self.online.add(row)
            self._search_energy(self.elapsed_s)
            if finish:
                self._send(self._reply([]))
                return self._end()
            self._sync_slots()
            self.looked: set = set()
            self.requests: list = []
            self.search_ordered = False
            self._vis_cache: dict = {}
            return self.online.advance(now)

    def _simple_events(self, msg: dict) -> bool:
        """The events of a message through ``mimo_ta.simple``'s tracker; whether one is ``finish``."""
        tr = self.tracker
        finish = False
        for raw in msg["events"]:
            ev = parse_event(raw)
            if isinstance(ev, StartInfo):
                self.is_start = True
                tr.start = ev
                tr.on_start(ev)
                for k, v in self._tracker_config.items():
                    if k not in tr.cfg:
                        raise ValueError(f"tracker_config: unknown setting {k!r}; known: {sorted(tr.cfg)}")
                    tr.cfg[k] = float(v)
                self._on_start(ev)
            elif isinstance(ev, Wake):
                if ev.t_s + 1e-9 >= self.next_wake_s:
                    self.next_wake_s = math.inf
                tr.on_wake(ev.t_s)
            elif isinstance(ev, Finish):
                tr.on_finish(ev.t_s)
                finish = True
            else:
                for tag in ev.tag:
                    for radar in self.radars:
                        self.pending_time[radar].pop(tag, None)
                tr.on_dwell(ev)
        return finish

    def _builtin_events(self, msg: dict, now: float) -> bool:
        """The events of a message with the built-in tracker's rows and the rule's proposals
        (docs/ta-protocol.md §7); whether one is ``finish``."""
        tr = self.tracker
        finish = False
        looked = []
        for raw in msg["events"]:
            kind = raw["event"]
            if kind == "start":
                ev = parse_event(raw)
                self.is_start = True
                tr.start = ev
                tr.on_start(ev)
                self._on_start(ev)
            elif kind == "wake":
                if raw["t_s"] + 1e-9 >= self.next_wake_s:
                    self.next_wake_s = math.inf
            elif kind == "finish":
                finish = True
            else:
                tags = raw.get("tag") or ()
                for tag in tags:
                    for radar in self.radars:
                        self.pending_time[radar].pop(tag, None)
                    t = tr.tracks.get(tag)
                    if t is not None:
                        t.pending_since_s = None
                if raw["requested_by"] == "ta":
                    looked.extend(tags)
        tr._tracks = tr.ingest(msg.get("tracks") or (), looked, now)
        self.proposed = msg.get("proposed") or []
        for p in self.proposed:
            d = p.get("dwell")
            if d is not None:
                for tid in d["tag"]:
                    self.due.setdefault(tid, now)
        for tid in list(self.due):
            t = tr.tracks.get(tid)
            if t is None or t.pending_since_s is not None:
                del self.due[tid]
        for tid, t in tr.tracks.items():
            t.next_due_s = self.due[tid] if tid in self.due else t.last_update_s + BUILTIN_T_MAX_S
        return finish

    def _on_start(self, start: StartInfo) -> None:
        self.radars = [s.radar for s in start.ships]
        self.params = {s.radar: s.radar_params for s in start.ships}
        self.share = {r: 1.0 for r in self.radars}
        self.energy_by_radar_kj = {r: 0.0 for r in self.radars}
        self.ta_time_by_radar_s = {r: 0.0 for r in self.radars}
        self.pending_time = {r: {} for r in self.radars}
        self.owed_s = {r: 0.0 for r in self.radars}
        self.slots: list = [None] * self.k_max
        self.next_tag = 1 << 40  # never a track id: tags of looks are the track's id

    def _search_energy(self, dt: float) -> None:
        if dt <= 0 or not hasattr(self, "radars"):
            return
        for r in self.radars:
            # Time the radar spent on looks is not searched (the looks' time is owed when ordered).
            busy = min(self.owed_s[r], dt)
            self.owed_s[r] -= busy
            e = self.share[r] * self.ref.search_rate_j_per_s.get(r, 0.0) * (dt - busy) / 1e3
            self.energy_by_radar_kj[r] += e
            self.energy_kj += e
            self.step_energy_kj += e

    def _reply(self, requests: list, accept: tuple = ()) -> dict:
        tr = self.tracker
        reply: dict = {}
        if self.builtin:  # docs/ta-protocol.md §7: the rows are the built-in's
            if self.is_start:
                reply["name"] = tr.name
            if accept:
                reply["accept"] = list(accept)
            if requests:
                reply["requests"] = [r.to_json() for r in requests]
            return reply
        if self.is_start:
            reply["name"] = tr.name
            reply["config"] = tr.config()
            reply["subscribe"] = tr.subscription.to_json()
        if requests:
            reply["requests"] = [r.to_json() for r in requests]
        if tr._tracks:
            reply["tracks"] = [t.to_json() for t in tr._tracks]
        return reply

    def _end(self) -> float:
        gained = self.online.advance(self.duration_s, final=True)
        os.close(self._wfd)
        self._wfd = None
        try:
            code = self.proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            code = None
        if code != 0:
            raise self._died("failed at the end of the run")
        self.kill()
        _run([self.mimo, "score", self.run_dir, "--no-charts", "--quiet", "--threads", "1"], "mimo score")
        with open(os.path.join(self.run_dir, "score", "summary.json")) as f:
            s = json.load(f)
        self.score = {"completeness": s["track"]["completeness"], "breaks": s["track"]["breaks"],
                      "energy_j": s["usage"]["total_energy_j"], "ta_energy_j": s["usage"]["ta_energy_j"],
                      "search_energy_j": s["usage"]["by_purpose"]["search"]["energy_j"],
                      "position_rmse_m": s["track"]["position_rmse_m"], "run_dir": self.run_dir,
                      "online_completeness": self.online.completeness_sum, "online_breaks": self.online.breaks,
                      "energy_estimate_j": self.energy_kj * 1e3}
        self.done = True
        return gained

    # -- the decision point ------------------------------------------------------------------

    def _sync_slots(self) -> None:
        before = list(self.slots)
        self._sync_slots_now()
        if self.slots != before:
            self._stack = None

    def _sync_slots_now(self) -> None:
        live = self.tracker.tracks
        for i, tid in enumerate(self.slots):
            if tid is not None and tid not in live:
                self.slots[i] = None
        held = set(s for s in self.slots if s is not None)
        free = [i for i, s in enumerate(self.slots) if s is None]
        for tid in sorted(live):
            if not free:
                break
            if tid not in held:
                self.slots[free.pop(0)] = tid
        for tid in live:
            self.born.setdefault(tid, self.now_s)
        now = self.now_s
        for t in live.values():  # a look not reported in time was rejected (as SimpleTa.schedule)
            if t.pending_since_s is not None and now - t.pending_since_s >= PENDING_TIMEOUT_S:
                t.pending_since_s = None

    def predicted_all(self) -> tuple:
        """Every slot's track predicted to now, computed once per decision point as arrays:
        (slots, x (N, 6), P (N, 6, 6)) in the tracker's ENU frame (nearly-constant velocity,
        docs/model.md §6.1; the arithmetic of one track at a time, element by element)."""
        if "pred" not in self._vis_cache:
            if self._stack is None:  # the slots' states, stacked, kept until a track or a slot changes
                slots = [i for i in range(self.k_max) if self.track_in(i) is not None]
                tracks = [self.track_in(i) for i in slots]
                self._stack = (slots, tracks, np.array([t.x for t in tracks]).reshape(-1, 6),
                               np.array([t.p for t in tracks]).reshape(-1, 6, 6))
            slots, tracks, x, p = self._stack
            n = len(tracks)
            xs, ps = np.empty((n, 6)), np.empty((n, 6, 6))
            if n:
                q = self.tracker.cfg["sigma_a_mps2"] ** 2
                dts = [self.now_s - t.t_s for t in tracks]
                dt = np.array(dts)[:, None, None]
                c4 = np.array([q * abs(d) ** 4 / 4 for d in dts])[:, None, None]
                c3 = np.array([q * abs(d) ** 3 / 2 for d in dts])[:, None, None]
                c2 = np.array([q * abs(d) * abs(d) for d in dts])[:, None, None]
                pp, pv, vv = p[:, :3, :3], p[:, :3, 3:], p[:, 3:, 3:]
                ps[:, :3, :3] = pp + dt * (pv + pv.transpose(0, 2, 1)) + dt * dt * vv + c4 * _I3
                ps[:, :3, 3:] = pv + dt * vv + c3 * _I3
                ps[:, 3:, :3] = ps[:, :3, 3:].transpose(0, 2, 1)
                ps[:, 3:, 3:] = vv + c2 * _I3
                xs[:, :3] = x[:, :3] + dt[:, 0] * x[:, 3:]
                xs[:, 3:] = x[:, 3:]
            self._vis_cache["pred"] = (slots, xs, ps, {s: k for k, s in enumerate(slots)})
        return self._vis_cache["pred"]

    def predicted(self, slot: int):
        """The track in ``slot`` predicted to now: (x, P) (:meth:`predicted_all`)."""
        _, xs, ps, index = self.predicted_all()
        k = index[slot]
        return xs[k], ps[k]

    def track_in(self, slot: int):
        tid = self.slots[slot] if 0 <= slot < self.k_max else None
        return None if tid is None else self.tracker.tracks.get(tid)

    def visibility(self, slot: int) -> dict:
        """Radar -> predicted single-pulse SNR (linear, 2 m^2) of its monostatic look at the
        track's predicted position, for the radars that can see it (scan limit, 4/3-earth
        horizon; docs/model.md §1.5, §1.7, §3.1). Computed for every slot at once, vectorized;
        the altitude of the horizon test is the height above the ellipsoid's geocentric radius
        (within a metre of the geodetic one at these ranges): a prediction, as every mask is —
        mimo has the last word on who takes part in a dwell (docs/ta-protocol.md §3)."""
        if "vis" not in self._vis_cache:
            slots, seen, snr = self.visibility_arrays()
            radars = self.radars
            self._vis_cache["vis"] = {i: {r: v for r, ok, v in zip(radars, ok_j, snr_j) if ok}
                                      for i, ok_j, snr_j in zip(slots, seen.T.tolist(), snr.T.tolist())}
        return self._vis_cache["vis"].get(slot, {})

    def visibility_arrays(self) -> tuple:
        """:meth:`visibility` of every slot as arrays: (slots, seen (R, N) booleans, SNR (R, N)
        linear), radars in radar order, slots as :meth:`predicted_all`'s."""
        if "visarr" not in self._vis_cache:
            self._vis_cache["visarr"] = self._visibility_all()
        return self._vis_cache["visarr"]

    def _radar_constants(self) -> tuple:
        """Per radar, in radar order, what visibility needs and does not change: scan limit,
        scan-loss exponent, peak gain, the radar equation's numerator and denominator factors,
        and the horizon angle of its site (ships keep their array height)."""
        if self._consts is None:
            tr = self.tracker
            rows = []
            for r in self.radars:
                par = self.params[r]
                origin = tr.ships[r].faces_sampled(0.0)[0].origin_ecef
                ha = max(ecef_to_geodetic_rad(origin)[2], 0.0)
                re = K_EFFECTIVE_EARTH * EARTH_MEAN_RADIUS_M
                lam = par.wavelength_m
                rows.append((par.min_scan_w, par.scan_loss_exponent, par.peak_gain, par.peak_power_w, lam * 1.0,
                             par.pulse_width_s, T0_K * db_to_lin(par.noise_figure_db), db_to_lin(par.loss_db),
                             math.acos(re / (re + ha))))
            cols = [np.array(c) for c in zip(*rows)]
            self._consts = tuple(c[:, None] for c in cols)  # (R, 1) each, to broadcast over tracks
        return self._consts

    def _visibility_all(self) -> tuple:
        """Every slot against every radar in one pass of arrays (R radars × N tracks), the same
        arithmetic, in the same order, as one radar at a time."""
        tr = self.tracker
        slots, xs, _, _ = self.predicted_all()
        if not slots:
            return slots, np.zeros((len(self.radars), 0), dtype=bool), np.zeros((len(self.radars), 0))
        pts = tr.enu.to_ecef(xs[:, :3])  # (N, 3)
        norm_p = _norms(pts, 1)
        sin_lat_c = pts[:, 2] / norm_p
        a, b = WGS84_A_M, WGS84_B_M
        r_ell = a * b / np.sqrt((b * b) * (1 - sin_lat_c**2) + (a * a) * sin_lat_c**2)
        h_t = np.maximum(norm_p - r_ell, 0.0)
        re = K_EFFECTIVE_EARTH * EARTH_MEAN_RADIUS_M
        min_w, expo, gain, power, lam, tau, t_sys, loss, horizon = self._radar_constants()
        origins, normals = self._frames_now()
        d = pts[None, :, :] - origins[:, None, :]  # (R, N, 3)
        rng = _norms(d, 2)
        w = np.einsum("rfj,rnj->rnf", normals, d).max(axis=2) / rng
        cos_psi = np.clip((pts @ origins.T).T / (norm_p[None, :] * _norms(origins, 1)[:, None]), -1.0, 1.0)
        psi_e = EARTH_MEAN_RADIUS_M * np.arccos(cos_psi) / re
        seen = (w >= min_w - 1e-12) & (psi_e <= horizon + np.arccos(re / (re + h_t))[None, :])
        g = gain * np.where(w > 0, np.abs(w) ** expo, 0.0)
        snr = (power * g * g * lam * lam * tr.cfg["assumed_rcs_m2"] * tau
               / ((4.0 * math.pi) ** 3 * rng**4 * BOLTZMANN_J_PER_K * t_sys * loss))
        return slots, seen, snr

    def _frames_now(self) -> tuple:
        """Every radar's array centre (R, 3) and face boresights (R, F, 3) now, interpolated from
        the ships' samples as :meth:`mimo_ta.geo.Ship.faces_sampled` does, for all radars at once
        (a radar with fewer faces repeats its first: the largest cosine is unchanged)."""
        if self._frame_samples is None:
            ships = [self.tracker.ships[r] for r in self.radars]
            n_faces = max(len(sh._samples[0]) for sh in ships)
            n = max(len(sh._samples) for sh in ships)  # a stationary ship has one sample
            samples = [sh._samples if len(sh._samples) == n else sh._samples[:1] * n for sh in ships]
            o = np.array([[fs[0].origin_ecef for fs in ss] for ss in samples])  # (R, n, 3)
            nb = np.array([[[fs[min(k, len(fs) - 1)].face_from_ecef[2] for k in range(n_faces)] for fs in ss]
                           for ss in samples])  # (R, n, F, 3)
            self._frame_samples = (o, nb)
        if "frames" not in self._vis_cache:
            o, nb = self._frame_samples
            n = o.shape[1]
            if n == 1 or not math.isfinite(self.now_s):
                self._vis_cache["frames"] = (o[:, 0], nb[:, 0])
            else:
                x = self.now_s / SHIP_FRAME_STEP_S
                k = min(int(max(math.floor(x), 0.0)), n - 2)
                w = x - k
                self._vis_cache["frames"] = (o[:, k] + (o[:, k + 1] - o[:, k]) * w,
                                             nb[:, k] + (nb[:, k + 1] - nb[:, k]) * w)
        return self._vis_cache["frames"]

    def _faces(self, radar: str):
        key = ("faces", radar)
        if key not in self._vis_cache:
            self._vis_cache[key] = self.tracker.ships[radar].faces_sampled(self.now_s)
        return self._vis_cache[key]

    def look_problem(self, slot: int, tx: str, mimo: bool, pulses: int) -> Optional[tuple]:
        """Why a look is not allowed now, as (field, reason), or None."""
        t = self.track_in(slot)
        if t is None:
            return ("track", f"slot {slot} holds no track")
        if slot in self.looked:
            return ("track", f"slot {slot} (track {t.id}) was already given a look at this decision")
        if t.pending_since_s is not None:
            return ("track", f"slot {slot} (track {t.id}) has a look ordered and not reported yet")
        vis = self.visibility(slot)
        if tx not in vis:
            return ("transmitter", f"{tx} cannot see track {t.id} (scan limit or horizon)")
        if mimo and not any(r in vis for r in self.radars if r != tx):
            return ("receivers", f"no radar but {tx} can see track {t.id}: no MIMO look")
        if pulses > self.params[tx].max_pulses:
            return ("pulses", f"{pulses} is above {tx}'s max_pulses = {self.params[tx].max_pulses}")
        return None

    def look(self, slot: int, tx: str, mimo: bool, pulses: int, receivers: Optional[list] = None) -> float:
        """Order a look (checked beforehand with :meth:`look_problem`); returns its energy (kJ).
        ``receivers`` (MIMO only): the radars allowed to receive, the transmitter's choice of
        those that can see the target (the default: all of them, as the default test article)."""
        tr = self.tracker
        t = self.track_in(slot)
        now = self.now_s
        x, p = tr.predict(t, now)
        aim = tr.enu.to_ecef(x[:3])
        par = self.params[tx]
        exact = predict_pair(par, self._faces(tx), par, self._faces(tx), aim, tr.cfg["assumed_rcs_m2"])
        snr1 = exact[0] if exact is not None else self.visibility(slot)[tx]
        rx = [tx]
        if mimo:
            tx_faces = self._faces(tx)
            for other in self.radars:
                if other != tx and (receivers is None or other in receivers) and predict_pair(
                        par, tx_faces, self.params[other], self._faces(other), aim,
                        tr.cfg["assumed_rcs_m2"]) is not None:
                    rx.append(other)
        fresh = t.status == "tentative" and t.n_updates <= 1
        if pulses == 0:  # the default rule (as SimpleTa.plan, docs/model.md §7.2)
            pd = tr.cfg["confirm_pd"] if fresh else tr.cfg["pd_target"]
            n = pulses_for(required_snr_sw1(pd, par.pfa), snr1, pointing_loss(0.2) * straddle_loss(), par.max_pulses)
            if not fresh:
                n = min(n * 2 ** (t.misses_in_row % 3), par.max_pulses)
        else:
            n = min(int(pulses), par.max_pulses)
        site = tr.enu.to_enu(tr.ships[tx].site_sampled(now))
        hr = np.zeros(6)
        hr[:3] = jacobian(x[:3], site, site, np.eye(3))[0]
        sigma_rho = 0.5 * math.sqrt(max(hr @ p @ hr, 0.0))
        self.requests.append(DwellRequest(
            kind="confirm" if t.status == "tentative" else ("mimo" if len(rx) > 1 else "track"),
            earliest_s=now, aim_ecef=aim, transmitters=[TxOrder(tx, n)], receivers=rx,
            window_half_m=max(5.0 * sigma_rho, tr.cfg["min_window_half_m"]),
            predicted_snr=snr1 * n if len(rx) == 1 else None, tag=[t.id]))
        self.looked.add(slot)
        return self._account(t.id, tx, n, rx)

    def _account(self, tid: int, tx: str, n: int, rx: list) -> float:
        """A look at track ``tid`` ordered now: pending, time owed by every participant, energy
        (kJ, returned)."""
        now = self.now_s
        t = self.tracker.tracks.get(tid)
        if t is not None:
            t.pending_since_s = now
        self.due.pop(tid, None)
        self.last_look[tid] = now
        par = self.params[tx]
        d = par.dwell_duration_s(n)
        for r in rx:
            self.pending_time[r][tid] = d
            self.ta_time_by_radar_s[r] += d
            self.owed_s[r] += d
        e = par.dwell_energy_j(n) / 1e3
        self.step_energy_kj += e
        self.energy_kj += e
        self.energy_by_radar_kj[tx] += e
        return e

    def deferrable(self, transmitters: Optional[set] = None) -> list:
        """Indices of the rule's proposals (``tracker="builtin"``) that :meth:`defer` accepts: every
        one but looks at a track the agent gave a look at this decision point or that has a look
        of the agent's outstanding (the rule knows only of its own), with ``transmitters``, looks
        whose first transmitter is not one of them, and search orders when the agent ordered
        search."""
        held = {self.slots[i] for i in self.looked}
        tracks = self.tracker.tracks
        held.update(tid for tid, t in tracks.items() if t.pending_since_s is not None)
        out = []
        for i, p in enumerate(self.proposed):
            d = p.get("dwell")
            if d is not None:
                if transmitters is not None and d["transmitters"][0]["radar"] not in transmitters:
                    continue
                if not any(tid in held for tid in d["tag"]):
                    out.append(i)
            elif not ("search" in p and self.search_ordered):
                out.append(i)
        return out

    def defer(self, transmitters: Optional[set] = None) -> float:
        """Accept the built-in rule's proposals (:meth:`deferrable`) and wait, the search as it is:
        the default rule as the decision (docs/ta-protocol.md §7)."""
        accept = self.deferrable(transmitters)
        now = self.now_s
        for i in accept:
            d = self.proposed[i].get("dwell")
            if d is None:
                continue
            first, rest = d["tag"][0], d["tag"][1:]
            # The dwell's time and energy are counted once, on its first track.
            for j, tx in enumerate(d["transmitters"]):
                radar = tx["radar"]
                n = min(int(tx["n_pulses"]), self.params[radar].max_pulses)
                self._account(first, radar, n, d["receivers"] if j == 0 else [])
            for tid in rest:  # tracks riding along (docs/model.md §7.2)
                t = self.tracker.tracks.get(tid)
                if t is not None:
                    t.pending_since_s = now
                self.due.pop(tid, None)
                self.last_look[tid] = now
        return self.wait(accept)

    def order_search(self, share: float, radar: Optional[str] = None) -> None:
        for r in ([radar] if radar else self.radars):
            if self.share[r] != share:
                self.search_ordered = True
                self.share[r] = share
                self.requests.append(SearchOrder(SearchPlan(share=share) if share > 0 else SearchPlan.none(), r))

    def wait(self, accept: tuple = ()) -> float:
        """Send the decision (the looks ordered, the proposals accepted, a wake-up) and run to
        the next decision point. Returns the completeness share gained; the energy spent
        meanwhile is in ``step_energy_kj``."""
        tr = self.tracker
        now = self.now_s
        nxt = now + self.decision_period_s
        # With the built-in tracker, mimo makes the rule's wake-ups itself (docs/ta-protocol.md §7).
        for t in () if self.builtin else tr.tracks.values():
            if t.pending_since_s is not None:
                nxt = min(nxt, t.pending_since_s + PENDING_TIMEOUT_S)
            elif t.next_due_s > now + 1e-9:
                nxt = min(nxt, t.next_due_s)
            elif not any(self.visibility(i) for i, s in enumerate(self.slots) if s == t.id):
                t.next_due_s = now + 1.0  # nobody can see it now: due later (as SimpleTa.schedule)
        requests = list(self.requests)
        if nxt < self.duration_s and (nxt < self.next_wake_s - 1e-9 or self.next_wake_s <= now):
            self.next_wake_s = nxt
            requests.append(WakeAt(max(nxt, now)))
        self._send(self._reply(requests, accept))
        self.steps += 1
        return self.read_until_decision()


def _norms(x: np.ndarray, axis: int) -> np.ndarray:
    """``np.linalg.norm(x, axis=axis)`` of a real array, the same arithmetic without its checks."""
    return np.sqrt(np.add.reduce(x * x, axis=axis))


_HANDOFF = ("import socket,sys;s=socket.socket(socket.AF_UNIX);s.connect(sys.argv[1]);"
            "socket.send_fds(s,[b\"m\"],[0,1]);s.close()")
"""The test article mimo starts: hand its stdin and stdout to the environment and exit."""


def _kill_group(proc: subprocess.Popen) -> None:
    if proc.returncode is None:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(timeout=10)
        except (ProcessLookupError, PermissionError, subprocess.TimeoutExpired):
            pass


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        n = os.write(fd, view)
        view = view[n:]
