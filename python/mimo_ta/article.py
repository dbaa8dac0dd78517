"""The base class of a test article and its stdin/stdout loop (docs/ta-protocol.md §1-§3).

Subclass :class:`TestArticle`, fill in ``on_start`` / ``on_dwell`` / ``on_wake`` / ``on_finish``,
and call ``MyTa().run()``. Inside a handler, :meth:`TestArticle.request_dwell`,
:meth:`TestArticle.wake_at`, :meth:`TestArticle.stop_local_tracking`, :meth:`TestArticle.order_search`,
:meth:`TestArticle.request_search_dwell` and
:meth:`TestArticle.emit_track` collect what goes into the reply to the current message; ``run``
sends it, one line per message, flushed. Log with :meth:`TestArticle.log` (stderr): stdout
belongs to the protocol.
"""

from __future__ import annotations

import json
import sys
from typing import IO, Optional

from .covariance import CovarianceError, checked_covariance
from .messages import (DwellReport, DwellRequest, Finish, ProtocolError, SearchOrder, SearchPlan, StartInfo,
                       StopLocalTracking, Subscription, TrackRow, TxOrder, Wake, WakeAt, parse_event)


class TestArticle:
    """A test article speaking the protocol. Class attributes a subclass may set:

    * ``name``: recorded in the run's manifest;
    * ``subscription``: which dwells it is sent (:class:`Subscription`);

    and override :meth:`config` to record its configuration. ``self.start`` holds the ``start``
    event once the run started and ``self.now_s`` the time of the message being handled.
    """

    __test__ = False  # not a unittest/pytest test case despite the name

    name: str = "python-test-article"
    subscription: Subscription = Subscription()

    def __init__(self) -> None:
        self.start: Optional[StartInfo] = None
        self.now_s: float = 0.0
        self._requests: list = []
        self._tracks: list = []
        self._registration: list = []
        #: Track rows whose covariance was slightly indefinite and was repaired before sending
        #: (:mod:`mimo_ta.covariance`); said in one line on stderr at the end of the run.
        self.repaired_covariances = 0

    # -- to override ----------------------------------------------------------------------------

    def config(self) -> dict:
        """The configuration recorded in the manifest (``start.config`` holds ``--ta-config`` /
        ``--set`` overrides)."""
        return {}

    def on_start(self, start: StartInfo) -> None:
        """The run starts (t = 0)."""

    def on_dwell(self, report: DwellReport) -> None:
        """A dwell the test article subscribed to ended (at ``report.end_s``)."""

    def on_wake(self, t_s: float) -> None:
        """A wake-up asked for with :meth:`wake_at`."""

    def on_finish(self, t_s: float) -> None:
        """The run ends: the last chance to emit track rows (a ``deleted`` row per live track)."""

    # -- what a handler may do -----------------------------------------------------------------

    def request_dwell(self, request: Optional[DwellRequest] = None, **kwargs) -> None:
        """Ask for a dwell: a :class:`DwellRequest`, or its fields as keywords, where
        ``transmitters`` may be ``[(radar, n_pulses), ...]``."""
        if request is None:
            tx = [t if isinstance(t, TxOrder) else TxOrder(*t) for t in kwargs.pop("transmitters")]
            request = DwellRequest(transmitters=tx, **kwargs)
        self._requests.append(request)

    def wake_at(self, t_s: float) -> None:
        """Be sent a ``wake`` event at ``t_s`` (not in the past)."""
        self._requests.append(WakeAt(t_s))

    def stop_local_tracking(self, radar: str) -> None:
        self._requests.append(StopLocalTracking(radar))

    def order_search(self, plan: SearchPlan, radar: Optional[str] = None) -> None:
        """Set the background search of ``radar`` (every radar when ``None``) from now on
        (docs/model.md §7.4). The plan is checked here (:class:`ProtocolError` naming the field)."""
        plan.check()
        self._requests.append(SearchOrder(plan, radar))

    def request_search_dwell(self, aim_ecef, transmitters, receivers=None, earliest_s: Optional[float] = None,
                             window_half_m: float = 225e3, tag=()) -> None:
        """Ask for a search beam of your own (kind ``search``, recorded with ``requested_by =
        ta``): aimed at ``aim_ecef``, ``transmitters`` as ``[(radar, n_pulses), ...]``,
        ``receivers`` the transmitters by default (monostatic) or any radars (multistatic
        search); the range window is ``±window_half_m`` about the aim point's range."""
        tx = [t if isinstance(t, TxOrder) else TxOrder(*t) for t in transmitters]
        rx = list(receivers) if receivers is not None else [t.radar for t in tx]
        t0 = self.now_s if earliest_s is None else earliest_s
        self._requests.append(DwellRequest("search", t0, aim_ecef, tx, rx, window_half_m, None, list(tag)))

    def emit_track(self, row: Optional[TrackRow] = None, **kwargs) -> None:
        """Write a row to the run's tracks table: a :class:`TrackRow` or its fields as keywords."""
        self._tracks.append(row if row is not None else TrackRow(**kwargs))

    def report_registration(self, radar: str, t_s: float, bias: dict, covariance: dict, looks: int = 0) -> None:
        """Report an estimate of ``radar``'s registration biases (docs/ta-protocol.md,
        ``registration``): ``bias`` holds ``range_m``, ``u``, ``v``, ``heading_deg``;
        ``covariance`` the variances ``var_range_m2``, ``var_u``, ``var_v``, ``var_heading_deg2`` and
        the covariances ``cov_range_u_m``, ``cov_range_v_m``, ``cov_range_heading_m_deg``,
        ``cov_u_v``, ``cov_u_heading_deg``, ``cov_v_heading_deg`` (missing ones are 0). With the
        scenario's biases on, ``mimo score`` compares the last estimate of each radar with the drawn
        biases."""
        row = {"t_s": float(t_s), "radar": radar, "looks": int(looks)}
        for k in ("range_m", "u", "v", "heading_deg"):
            row[k] = float(bias.get(k, 0.0))
        for k in ("var_range_m2", "var_u", "var_v", "var_heading_deg2", "cov_range_u_m", "cov_range_v_m",
                  "cov_range_heading_m_deg", "cov_u_v", "cov_u_heading_deg", "cov_v_heading_deg"):
            row[k] = float(covariance.get(k, 0.0))
        self._registration.append(row)

    @staticmethod
    def log(*args) -> None:
        """Print to stderr (passed through by ``mimo``)."""
        print(*args, file=sys.stderr, flush=True)

    # -- the loop -------------------------------------------------------------------------------

    def handle(self, message: dict) -> dict:
        """Process one message (a parsed JSON line) and return the reply as a dict."""
        self._requests, self._tracks, self._registration = [], [], []
        self.now_s = float(message["t_s"])
        is_start = False
        for raw in message["events"]:
            event = parse_event(raw)
            if isinstance(event, StartInfo):
                is_start = True
                self.start = event
                self.on_start(event)
            elif isinstance(event, DwellReport):
                self.on_dwell(event)
            elif isinstance(event, Wake):
                self.on_wake(event.t_s)
            elif isinstance(event, Finish):
                self.on_finish(event.t_s)
                self._requests = []  # ignored by mimo after finish
        reply: dict = {}
        if is_start:
            reply["name"] = self.name
            reply["config"] = self.config()
            reply["subscribe"] = self.subscription.to_json()
        if self._requests:
            reply["requests"] = [r.to_json() for r in self._requests]
        if self._tracks:
            for t in self._tracks:
                try:
                    self.repaired_covariances += int(checked_covariance(t.cov)[1])
                except CovarianceError:
                    pass  # refused by to_json, naming the track
            reply["tracks"] = [t.to_json() for t in self._tracks]
        if self._registration:
            reply["registration"] = self._registration
        if any(isinstance(raw, dict) and raw.get("event") == "finish" for raw in message["events"]) \
                and self.repaired_covariances:
            self.log(f"{self.name}: warning: {self.repaired_covariances} track covariance(s) slightly not positive "
                     "semi-definite were repaired before sending (mimo_ta.covariance)")
        return reply

    def run(self, stdin: IO[str] = None, stdout: IO[str] = None) -> int:
        """Read messages from stdin until it closes, answering each with one line. Returns 0."""
        stdin = stdin if stdin is not None else sys.stdin
        stdout = stdout if stdout is not None else sys.stdout
        for line in stdin:
            if not line.strip():
                continue
            try:
                message = json.loads(line)
            except json.JSONDecodeError as e:
                raise ProtocolError(f"a message that is not JSON: {e}") from e
            reply = self.handle(message)
            stdout.write(json.dumps(reply, allow_nan=False, separators=(",", ":")))
            stdout.write("\n")
            stdout.flush()
        return 0
