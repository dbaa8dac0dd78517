//! A test article in another process, in any language: the protocol of docs/ta-protocol.md over
//! the child's stdin and stdout, one JSON message per line.
//!
//! `mimo` writes one [`EventMessage`] line and waits for exactly one [`ReplyMessage`] line before
//! the simulation goes on, so the run stays a deterministic function of the seed and the test
//! article. The child's stderr is passed through. A reader thread feeds the child's stdout lines
//! to the adapter through a channel, so a child that stops answering is caught after
//! `--ta-timeout` seconds; a child that exits, writes something that is not a reply, or asks for
//! something impossible is a [`TaFault`] that stops the run.
//!
//! The child leads a process group of its own, and a child given up on (timed out, or dropped
//! before it exited) is killed with its whole group, so the processes a wrapper script started
//! go with it (docs/decisions/0325-test-article-process-group.md).

use mimo_core::records::TrackRow;
use mimo_sim::messages::{DwellReport, Reply, ReplyMessage, Request, StartInfo, Subscription, TaEvent};
use mimo_sim::test_article::{TaFault, TestArticle};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::os::unix::process::CommandExt;
use std::process::ExitStatus;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::Mutex;
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::time::Duration;

/// The process groups of the children not yet reaped, for [`kill_live_groups`]. A group leaves
/// the list under its lock before its leader is reaped, so the list never names a reused pid.
static LIVE_GROUPS: Mutex<Vec<u32>> = Mutex::new(Vec::new());

fn live_groups() -> std::sync::MutexGuard<'static, Vec<u32>> {
    LIVE_GROUPS.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// SIGKILL every process test article still running in this process, with its group: what an
/// interrupted `mimo` does before it exits (docs/decisions/0325-test-article-process-group.md).
/// A child in a group of its own no longer receives the terminal's Ctrl-C.
pub fn kill_live_groups() {
    for &pgid in live_groups().iter() {
        signal_group(pgid);
    }
}

/// `kill(-pgid, SIGKILL)`, never to pgid 0 or 1 (the caller's group, every process).
fn signal_group(pgid: u32) {
    if let Some(pid) = i32::try_from(pgid).ok().and_then(rustix::process::Pid::from_raw)
        && pid != rustix::process::Pid::INIT
    {
        let _ = rustix::process::kill_process_group(pid, rustix::process::Signal::KILL);
    }
}

/// One line from the child's stdout, or how its output ended.
enum Line {
    Text(String),
    Eof,
    Error(String),
}

/// An event as it is written, borrowing the engine's report (no copy of the measurements).
#[derive(Serialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub(crate) enum EventRef<'a> {
    Start(&'a StartInfo),
    DwellEnded(&'a DwellReport),
    Wake { t_s: f64 },
    Finish { t_s: f64 },
}

#[derive(Serialize)]
struct MessageRef<'a> {
    t_s: f64,
    events: Vec<EventRef<'a>>,
    /// The resource-manager role only (docs/ta-protocol.md §7): the built-in tracker's rows.
    #[serde(skip_serializing_if = "Option::is_none")]
    tracks: Option<&'a [TrackRow]>,
    /// The resource-manager role only: the built-in rule's proposed requests.
    #[serde(skip_serializing_if = "Option::is_none")]
    proposed: Option<&'a [Request]>,
}

/// What the resource-manager role adds to a message (docs/ta-protocol.md §7): the built-in
/// tracker's track rows for these events and the built-in rule's proposed requests.
#[derive(Clone, Copy)]
pub(crate) struct RuleView<'a> {
    pub tracks: &'a [TrackRow],
    pub proposed: &'a [Request],
}

impl<'a> From<&'a TaEvent> for EventRef<'a> {
    fn from(e: &'a TaEvent) -> EventRef<'a> {
        match e {
            TaEvent::Start(s) => EventRef::Start(s),
            TaEvent::DwellEnded(r) => EventRef::DwellEnded(r),
            TaEvent::Wake { t_s } => EventRef::Wake { t_s: *t_s },
            TaEvent::Finish { t_s } => EventRef::Finish { t_s: *t_s },
        }
    }
}

/// A command line split into words the way a POSIX shell would (quotes, escapes) without
/// running one; `None` when it is empty or its quotes do not balance.
pub fn split_command(cmd: &str) -> Option<Vec<String>> {
    shlex::split(cmd).filter(|w| !w.is_empty())
}

/// One line of a test article's output read as the reply to the message at `t_s`: a
/// [`ReplyMessage`] in JSON (trailing whitespace and line end ignored), or a
/// [`TaFault::BadMessage`] quoting at most 120 characters of it, on one line.
///
/// The reply must be a JSON object (docs/ta-protocol.md §3): serde would also read a struct
/// from an array of its fields in order, so `[]` would pass as an empty reply.
pub fn parse_reply(line: &str, t_s: f64) -> Result<ReplyMessage, TaFault> {
    parse_line(line, t_s)
}

/// [`parse_reply`] for any reply type (the resource-manager role reads its own,
/// [`crate::resource_manager::RmReplyMessage`]).
pub(crate) fn parse_line<T: DeserializeOwned>(line: &str, t_s: f64) -> Result<T, TaFault> {
    let text = line.trim_end();
    let fault = |why: String| {
        let shown: String = text.chars().take(120).filter(|c| !c.is_control()).collect();
        // A parser's message quotes the bad value whole (an unknown variant of megabytes).
        let why = mimo_core::quote::bounded(&why, 300);
        TaFault::BadMessage(format!("{why} in reply to the message at t = {t_s} s: `{shown}`"))
    };
    if !text.trim_start().starts_with('{') {
        return Err(fault("expected a JSON object".into()));
    }
    serde_json::from_str::<T>(text).map_err(|e| fault(e.to_string()))
}

/// A test article run as a child process.
pub struct ProcessTa {
    cmd: String,
    child: Child,
    stdin: Option<BufWriter<ChildStdin>>,
    lines: Receiver<Line>,
    timeout: Duration,
    declared_name: Option<String>,
    declared_config: serde_json::Value,
    subscription: Subscription,
    buf: Vec<u8>,
    messages: u64,
    /// Time of the last message sent.
    last_t_s: f64,
    /// The child was waited for: its pid, and so its group id, may name another process now.
    reaped: bool,
}

impl ProcessTa {
    /// Start `cmd` (split like a POSIX shell would, without running one). `timeout_s` bounds the
    /// wait for each reply.
    pub fn spawn(cmd: &str, timeout_s: f64) -> Result<ProcessTa, TaFault> {
        let words = split_command(cmd).ok_or_else(|| {
            TaFault::Crashed("cannot split the command line (unbalanced quotes?) or it is empty".into())
        })?;
        let (prog, args) = words.split_first().ok_or_else(|| TaFault::Crashed("empty command".into()))?;
        let mut child = Command::new(prog)
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            // Its own process group (pgid = its pid): the handle on whatever it starts.
            .process_group(0)
            .spawn()
            .map_err(|e| TaFault::Crashed(format!("cannot start it: {e}")))?;
        live_groups().push(child.id());
        let stdin = child.stdin.take().map(BufWriter::new);
        let stdout = child.stdout.take().ok_or_else(|| TaFault::Io("no stdout pipe".into()))?;
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            loop {
                let mut s = String::new();
                let line = match reader.read_line(&mut s) {
                    Ok(0) => Line::Eof,
                    Ok(_) => Line::Text(s),
                    Err(e) => Line::Error(e.to_string()),
                };
                let last = !matches!(line, Line::Text(_));
                if tx.send(line).is_err() || last {
                    return;
                }
            }
        });
        let timeout = if timeout_s.is_finite() && timeout_s > 0.0 {
            Duration::from_secs_f64(timeout_s)
        } else {
            Duration::from_secs(60)
        };
        Ok(ProcessTa {
            cmd: cmd.to_string(),
            child,
            stdin,
            lines: rx,
            timeout,
            declared_name: None,
            declared_config: serde_json::Value::Null,
            subscription: Subscription::default(),
            buf: Vec::with_capacity(1 << 16),
            messages: 0,
            last_t_s: 0.0,
            reaped: false,
        })
    }

    /// Kill the child and every process of its group (what a wrapper script started), then the
    /// child itself should the group signal fail. Only before the child is reaped: until then its
    /// pid (a zombie's too) still names its group and no other.
    fn kill_group(&mut self) {
        if self.reaped {
            return;
        }
        signal_group(self.child.id());
        let _ = self.child.kill();
    }

    /// `try_wait`, with the group out of [`LIVE_GROUPS`] before the child is reaped.
    fn try_reap(&mut self) -> std::io::Result<Option<ExitStatus>> {
        let mut live = live_groups();
        let waited = self.child.try_wait();
        if matches!(waited, Ok(Some(_))) {
            self.reaped = true;
            live.retain(|&g| g != self.child.id());
        }
        waited
    }

    /// Messages exchanged so far.
    pub fn messages(&self) -> u64 {
        self.messages
    }

    /// How the child ended, for a crash message.
    fn exit_note(&mut self) -> String {
        for _ in 0..50 {
            match self.try_reap() {
                Ok(Some(status)) => return format!("it exited ({status})"),
                Ok(None) => std::thread::sleep(Duration::from_millis(10)),
                Err(e) => return format!("it cannot be waited for ({e})"),
            }
        }
        "it closed its output".into()
    }

    /// A line that answers no message: the test article replied to the previous one (at
    /// `last_t_s`) with more than one line, which would shift every later reply by one.
    fn second_line(&self, line: &str) -> TaFault {
        let shown: String = line.trim_end().chars().take(120).collect();
        TaFault::BadMessage(format!(
            "a second line in reply to the message at t = {} s (exactly one line answers each message): `{shown}`",
            self.last_t_s
        ))
    }

    /// Before a message is sent, no line may be waiting.
    fn refuse_extra_line(&mut self) -> Result<(), TaFault> {
        match self.lines.try_recv() {
            Ok(Line::Text(s)) => Err(self.second_line(&s)),
            _ => Ok(()),
        }
    }

    /// After the child exited, its output up to the end must hold no further line (a process it
    /// left holding the output open is not waited for beyond a second).
    fn refuse_output_after_exit(&mut self) -> Result<(), TaFault> {
        match self.lines.recv_timeout(Duration::from_secs(1)) {
            Ok(Line::Text(s)) => Err(self.second_line(&s)),
            _ => Ok(()),
        }
    }

    fn send(&mut self, t_s: f64, events: Vec<EventRef<'_>>) -> Result<ReplyMessage, TaFault> {
        let line = self.send_line(t_s, events, None)?;
        parse_reply(&line, t_s)
    }

    /// Write one message (with `rule`'s additions in the resource-manager role) and return the
    /// reply line, unparsed.
    pub(crate) fn send_line(
        &mut self,
        t_s: f64,
        events: Vec<EventRef<'_>>,
        rule: Option<RuleView<'_>>,
    ) -> Result<String, TaFault> {
        if self.messages > 0 {
            self.refuse_extra_line()?;
        }
        self.last_t_s = t_s;
        self.buf.clear();
        let msg = MessageRef { t_s, events, tracks: rule.map(|r| r.tracks), proposed: rule.map(|r| r.proposed) };
        serde_json::to_writer(&mut self.buf, &msg).map_err(|e| TaFault::Io(format!("encoding a message: {e}")))?;
        self.buf.push(b'\n');
        let Some(w) = self.stdin.as_mut() else { return Err(TaFault::Io("its input is closed".into())) };
        if let Err(e) = w.write_all(&self.buf).and_then(|()| w.flush()) {
            let note = self.exit_note();
            return Err(TaFault::Crashed(format!("{note}; writing to it failed: {e}")));
        }
        self.messages += 1;
        let line = match self.lines.recv_timeout(self.timeout) {
            Ok(Line::Text(s)) => s,
            Ok(Line::Eof) | Err(RecvTimeoutError::Disconnected) => {
                let note = self.exit_note();
                return Err(TaFault::Crashed(format!("{note} before replying to the message at t = {t_s} s")));
            }
            Ok(Line::Error(e)) => return Err(TaFault::Io(format!("reading its output: {e}"))),
            Err(RecvTimeoutError::Timeout) => {
                self.kill_group();
                return Err(TaFault::Timeout(self.timeout.as_secs_f64()));
            }
        };
        Ok(line)
    }

    fn exchange(&mut self, t_s: f64, events: Vec<EventRef<'_>>) -> Result<Reply, TaFault> {
        let is_start = matches!(events.first(), Some(EventRef::Start(_)));
        let r = self.send(t_s, events)?;
        if is_start {
            self.declared_name = r.name;
            self.declared_config = r.config.unwrap_or(serde_json::Value::Null);
            self.subscription = r.subscribe.unwrap_or_default();
        } else if r.name.is_some() || r.config.is_some() || r.subscribe.is_some() {
            return Err(TaFault::BadMessage(format!(
                "`name`, `config` and `subscribe` belong in the reply to `start` only (message at t = {t_s} s)"
            )));
        }
        Ok(Reply { requests: r.requests, tracks: r.tracks, registration: r.registration })
    }
}

impl TestArticle for ProcessTa {
    /// The command line: what errors and the manifest name.
    fn name(&self) -> &str {
        &self.cmd
    }
    fn config(&self) -> serde_json::Value {
        serde_json::json!({"name": self.declared_name, "config": self.declared_config})
    }
    fn subscription(&self) -> Subscription {
        self.subscription
    }
    fn on_start(&mut self, start: &StartInfo) -> Result<Reply, TaFault> {
        self.exchange(0.0, vec![EventRef::Start(start)])
    }
    fn on_dwell(&mut self, report: &DwellReport) -> Result<Reply, TaFault> {
        self.exchange(report.end_s, vec![EventRef::DwellEnded(report)])
    }
    fn on_wake(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        self.exchange(t_s, vec![EventRef::Wake { t_s }])
    }
    fn on_finish(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        let reply = self.exchange(t_s, vec![EventRef::Finish { t_s }])?;
        self.close_after_finish().map(|()| reply)
    }
    fn on_events(&mut self, t_s: f64, events: &[TaEvent]) -> Result<Reply, TaFault> {
        if let [TaEvent::Finish { t_s }] = events {
            return self.on_finish(*t_s);
        }
        self.exchange(t_s, events.iter().map(EventRef::from).collect())
    }
}

impl ProcessTa {
    /// The run is over and the reply to `finish` read: close the child's input and wait for it
    /// to exit with status 0 within the timeout.
    pub(crate) fn close_after_finish(&mut self) -> Result<(), TaFault> {
        // The run is over: close its input and let it exit.
        self.stdin = None;
        let deadline = std::time::Instant::now() + self.timeout;
        loop {
            match self.try_reap() {
                // Whatever it wrote after its last reply is a line too many.
                Ok(Some(status)) if status.success() => return self.refuse_output_after_exit(),
                Ok(Some(status)) => return Err(TaFault::Crashed(format!("it exited with {status} after `finish`"))),
                Ok(None) if std::time::Instant::now() < deadline => std::thread::sleep(Duration::from_millis(2)),
                Ok(None) => {
                    self.kill_group();
                    return Err(TaFault::Timeout(self.timeout.as_secs_f64()));
                }
                Err(e) => return Err(TaFault::Io(e.to_string())),
            }
        }
    }
}

impl Drop for ProcessTa {
    fn drop(&mut self) {
        self.stdin = None;
        if !self.reaped {
            // Running, or exited and not yet waited for (a zombie still names its group).
            self.kill_group();
            live_groups().retain(|&g| g != self.child.id());
            self.reaped = true;
            let _ = self.child.wait();
        }
    }
}
