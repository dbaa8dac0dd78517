//! The resource-manager role (docs/ta-protocol.md §7,
//! docs/decisions/0316-built-in-tracker-external-resource-manager.md): a built-in test article's
//! tracker keeps tracking, and a process in another language decides the looks.
//!
//! Each event goes first to the built-in test article ([`DefaultTa`]), whose tracker produces the
//! track rows and whose rule plans its requests. Then the event goes to the process, with two more
//! keys: `tracks` (the rows just produced) and `proposed` (the rule's requests, its wake-ups
//! left out). The process answers with `accept` (indices of the proposals to make as proposed) and
//! `requests` of its own. The rule's wake-ups are always made, so the rule is asked again when it
//! wants; the proposals not accepted are forgotten by the rule ([`DefaultTa::forget_proposals`]).
//! A process that accepts every proposal and asks nothing else gives exactly the built-in's run.

use crate::default_ta::DefaultTa;
use crate::process::{EventRef, ProcessTa, RuleView, parse_line};
use mimo_sim::messages::{DwellReport, DwellRequest, Reply, Request, StartInfo, Subscription};
use mimo_sim::test_article::{TaFault, TestArticle};
use serde::Deserialize;

/// A resource manager's reply (docs/ta-protocol.md §7): a reply of §3 whose track rows and
/// registration are the built-in tracker's, so it has neither, plus `accept`.
#[derive(Debug, Clone, PartialEq, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RmReplyMessage {
    /// Indices into the message's `proposed` of the proposals to make, each at most once.
    #[serde(default)]
    pub accept: Vec<usize>,
    /// Requests of its own, made after the accepted proposals.
    #[serde(default)]
    pub requests: Vec<Request>,
    /// Name recorded in the manifest (start reply only).
    #[serde(default)]
    pub name: Option<String>,
    /// Configuration recorded in the manifest (start reply only).
    #[serde(default)]
    pub config: Option<serde_json::Value>,
}

/// A built-in test article's tracker with an external resource manager.
pub struct ResourceManagerTa {
    cmd: String,
    builtin: String,
    rule: DefaultTa,
    child: ProcessTa,
    declared_name: Option<String>,
    declared_config: serde_json::Value,
}

impl ResourceManagerTa {
    /// The built-in `rule` (its tracker and its rule's proposals, recorded as `builtin`) with the
    /// resource manager `child`, started from the command line `cmd`.
    pub fn new(builtin: &str, rule: DefaultTa, cmd: &str, child: ProcessTa) -> ResourceManagerTa {
        ResourceManagerTa {
            cmd: cmd.to_string(),
            builtin: builtin.to_string(),
            rule,
            child,
            declared_name: None,
            declared_config: serde_json::Value::Null,
        }
    }

    /// Send the event with the built-in's reply `inner` as rows and proposals, and return what is
    /// made: the rule's wake-ups and the accepted proposals in the rule's order, then the
    /// resource manager's own requests.
    fn decide(&mut self, t_s: f64, event: EventRef<'_>, inner: Reply) -> Result<Reply, TaFault> {
        let is_start = matches!(event, EventRef::Start(_));
        let proposed: Vec<Request> =
            inner.requests.iter().filter(|r| !matches!(r, Request::WakeAt(_))).cloned().collect();
        let view = RuleView { tracks: &inner.tracks, proposed: &proposed };
        let line = self.child.send_line(t_s, vec![event], Some(view))?;
        let r: RmReplyMessage = parse_line(&line, t_s)?;
        if is_start {
            self.declared_name = r.name;
            self.declared_config = r.config.unwrap_or(serde_json::Value::Null);
        } else if r.name.is_some() || r.config.is_some() {
            return Err(TaFault::BadMessage(format!(
                "`name` and `config` belong in the reply to `start` only (message at t = {t_s} s)"
            )));
        }
        let mut accepted = vec![false; proposed.len()];
        for (i, &k) in r.accept.iter().enumerate() {
            match accepted.get_mut(k) {
                None => {
                    return Err(TaFault::InvalidRequest(format!(
                        "accept[{i}] = {k}: the message at t = {t_s} s proposed {} request(s)",
                        proposed.len()
                    )));
                }
                Some(true) => {
                    return Err(TaFault::InvalidRequest(format!(
                        "accept[{i}] = {k}: proposal {k} accepted twice (message at t = {t_s} s)"
                    )));
                }
                Some(a) => *a = true,
            }
        }
        let rejected: Vec<&DwellRequest> = proposed
            .iter()
            .zip(&accepted)
            .filter_map(|(p, &a)| match p {
                Request::Dwell(d) if !a => Some(d),
                _ => None,
            })
            .collect();
        self.rule.forget_proposals(rejected);
        let mut keep = accepted.into_iter();
        let mut requests: Vec<Request> = inner
            .requests
            .into_iter()
            .filter(|q| matches!(q, Request::WakeAt(_)) || keep.next().unwrap_or(false))
            .collect();
        requests.extend(r.requests);
        Ok(Reply { requests, tracks: inner.tracks, registration: inner.registration })
    }
}

impl TestArticle for ResourceManagerTa {
    /// The command line: what errors and the manifest name.
    fn name(&self) -> &str {
        &self.cmd
    }
    fn config(&self) -> serde_json::Value {
        serde_json::json!({
            "role": "resource-manager",
            "name": self.declared_name,
            "config": self.declared_config,
            "tracker": self.builtin,
            "tracker_config": self.rule.config(),
        })
    }
    /// The built-in's: the tracker needs what it is used to.
    fn subscription(&self) -> Subscription {
        self.rule.subscription()
    }
    fn on_start(&mut self, start: &StartInfo) -> Result<Reply, TaFault> {
        let inner = self.rule.on_start(start)?;
        self.decide(0.0, EventRef::Start(start), inner)
    }
    fn on_dwell(&mut self, report: &DwellReport) -> Result<Reply, TaFault> {
        let inner = self.rule.on_dwell(report)?;
        self.decide(report.end_s, EventRef::DwellEnded(report), inner)
    }
    fn on_wake(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        let inner = self.rule.on_wake(t_s)?;
        self.decide(t_s, EventRef::Wake { t_s }, inner)
    }
    fn on_finish(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        let inner = self.rule.on_finish(t_s)?;
        let view = RuleView { tracks: &inner.tracks, proposed: &[] };
        let line = self.child.send_line(t_s, vec![EventRef::Finish { t_s }], Some(view))?;
        // Requests in the reply to `finish` are ignored (docs/ta-protocol.md §3); it must still be
        // a reply.
        let _: RmReplyMessage = parse_line(&line, t_s)?;
        self.child.close_after_finish()?;
        Ok(inner)
    }
}
