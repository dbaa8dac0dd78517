//! Choosing and configuring the test article: the flags `mimo simulate` and `mimo track` share.

use crate::CliError;
use mimo_sim::World;
use mimo_sim::test_article::TestArticle;
use mimo_ta::overrides;
use mimo_ta::process::ProcessTa;
use mimo_ta::registry;
use mimo_ta::resource_manager::ResourceManagerTa;
use serde_json::Value;
use std::path::PathBuf;

/// Which test article runs, and its configuration.
#[derive(Debug, Clone, clap::Args)]
pub struct TaArgs {
    /// Built-in test article: default (IMM tracker, JPDA with second returns, adaptive revisit
    /// and energy, MIMO dwells), gnn (the former default: EKF tracker, GNN),
    /// imm (gnn with an IMM), jpda and imm-jpda (gnn and imm with JPDA association), cued
    /// (truth-cued fixed schedule, no tracking), none (background search only). With --ta-cmd,
    /// only in --ta-role resource-manager: the built-in whose tracker keeps tracking. [default:
    /// default]
    #[arg(long, value_name = "NAME")]
    pub tracker: Option<String>,
    /// Run a test article in another process, in any language: the command is started once per
    /// Monte Carlo run and speaks the protocol of docs/ta-protocol.md (JSON lines) over its
    /// stdin and stdout, e.g. --ta-cmd "python3 python/examples/simple_ta.py".
    #[arg(long, value_name = "CMD")]
    pub ta_cmd: Option<String>,
    /// What the --ta-cmd process is: test-article (the whole test article, tracker and resource
    /// manager) or resource-manager (the built-in tracker of --tracker keeps tracking, its rule
    /// proposes looks, and the process decides the looks and the search; docs/ta-protocol.md §7).
    #[arg(long, value_enum, default_value = "test-article", value_name = "ROLE")]
    pub ta_role: TaRole,
    /// Seconds to wait for each reply of a --ta-cmd test article before giving up.
    #[arg(long, default_value_t = 60.0, value_name = "SECONDS")]
    pub ta_timeout: f64,
    /// TOML file of configuration overrides merged over the test article's defaults (the keys
    /// of `tracker.config` in a run's manifest.json, e.g. `[resource_manager]` `mimo = false`).
    /// With --ta-cmd the table is passed to the test article in its `start` event.
    #[arg(long, value_name = "FILE.toml")]
    pub ta_config: Option<PathBuf>,
    /// Override one configuration key, after --ta-config (repeatable), e.g.
    /// `--set resource_manager.mimo=false --set tracker.gate.probability=0.99`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// What a `--ta-cmd` process is (docs/ta-protocol.md §7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum TaRole {
    /// The whole test article: tracker and resource manager.
    TestArticle,
    /// The resource manager only: a built-in's tracker keeps tracking.
    ResourceManager,
}

/// A resolved choice of test article.
#[derive(Debug, Clone)]
pub enum TaChoice {
    /// A built-in, with its merged and checked configuration.
    Builtin {
        /// Built-in name.
        name: String,
        /// Its merged configuration.
        config: Value,
        /// The overrides alone (passed on in the `start` event).
        overrides: Value,
    },
    /// A built-in's tracker with a child process as its resource manager.
    ResourceManager {
        /// Built-in name.
        name: String,
        /// Its merged configuration.
        config: Value,
        /// The overrides alone (passed on in the `start` event).
        overrides: Value,
        /// The command line.
        cmd: String,
        /// Seconds per reply.
        timeout_s: f64,
    },
    /// A child process.
    Process {
        /// The command line.
        cmd: String,
        /// Seconds per reply.
        timeout_s: f64,
        /// The overrides, passed on in the `start` event.
        overrides: Value,
    },
}

fn config_err(a: &TaArgs, e: overrides::ConfigError) -> CliError {
    match (&a.ta_config, &e) {
        (_, overrides::ConfigError::File { .. }) => CliError::input(e.to_string()),
        (_, overrides::ConfigError::UnknownTa { .. }) => CliError::input(format!("--tracker: {e}")),
        (Some(f), _) => CliError::input(format!("{} / --set: {e}", f.display())),
        (None, _) => CliError::input(format!("--set: {e}")),
    }
}

impl TaArgs {
    /// Check the choice and the overrides before anything runs.
    pub fn resolve(&self) -> Result<TaChoice, CliError> {
        let over = overrides::collect(self.ta_config.as_deref(), &self.set).map_err(|e| config_err(self, e))?;
        let tracker = self.tracker.as_deref().unwrap_or("default");
        if self.ta_role == TaRole::ResourceManager && self.ta_cmd.is_none() {
            return Err(CliError::input(
                "--ta-role: resource-manager needs the resource manager's command (--ta-cmd CMD)".to_string(),
            ));
        }
        if let Some(cmd) = &self.ta_cmd {
            if mimo_ta::process::split_command(cmd).is_none() {
                return Err(CliError::input(format!(
                    "--ta-cmd: '{cmd}' is not a command (empty or unbalanced quotes)"
                )));
            }
            if !(self.ta_timeout.is_finite() && self.ta_timeout > 0.0 && self.ta_timeout <= 86_400.0) {
                return Err(CliError::input(format!(
                    "--ta-timeout: expected seconds in (0, 86400], got {}",
                    self.ta_timeout
                )));
            }
            if self.ta_role == TaRole::ResourceManager {
                registry::builtin(tracker).map_err(|e| config_err(self, e))?;
                if !registry::builtin(tracker).is_ok_and(|b| b.tracks) {
                    return Err(CliError::input(format!(
                        "--tracker: '{tracker}' has no tracker for --ta-role resource-manager (expected one of: default, gnn, imm, jpda, imm-jpda)"
                    )));
                }
                let config = registry::resolve_config(tracker, &over).map_err(|e| config_err(self, e))?;
                return Ok(TaChoice::ResourceManager {
                    name: tracker.to_string(),
                    config,
                    overrides: over,
                    cmd: cmd.clone(),
                    timeout_s: self.ta_timeout,
                });
            }
            if self.tracker.is_some() {
                return Err(CliError::input(
                    "--tracker: a --ta-cmd process is the whole test article; --tracker goes with --ta-cmd only in --ta-role resource-manager".to_string(),
                ));
            }
            return Ok(TaChoice::Process { cmd: cmd.clone(), timeout_s: self.ta_timeout, overrides: over });
        }
        registry::builtin(tracker).map_err(|e| config_err(self, e))?;
        let config = registry::resolve_config(tracker, &over).map_err(|e| config_err(self, e))?;
        Ok(TaChoice::Builtin { name: tracker.to_string(), config, overrides: over })
    }
}

impl TaChoice {
    /// A fresh test article for one run (for a child process: the process, started).
    pub fn build<'w>(&self, world: &'w World) -> Result<Box<dyn TestArticle + 'w>, CliError> {
        match self {
            TaChoice::Builtin { name, config, .. } => {
                registry::build(name, config, world).map_err(|e| CliError::input(format!("--tracker: {e}")))
            }
            TaChoice::Process { cmd, timeout_s, .. } => match ProcessTa::spawn(cmd, *timeout_s) {
                Ok(ta) => Ok(Box::new(ta)),
                Err(e) => Err(CliError::Other(format!("test article '{cmd}': {e}"))),
            },
            TaChoice::ResourceManager { name, config, cmd, timeout_s, .. } => {
                let rule =
                    registry::build_rule(name, config).map_err(|e| CliError::input(format!("--tracker: {e}")))?;
                match ProcessTa::spawn(cmd, *timeout_s) {
                    Ok(child) => Ok(Box::new(ResourceManagerTa::new(name, rule, cmd, child))),
                    Err(e) => Err(CliError::Other(format!("test article '{cmd}': {e}"))),
                }
            }
        }
    }

    /// The overrides passed on in the `start` event.
    pub fn overrides(&self) -> &Value {
        match self {
            TaChoice::Builtin { overrides, .. }
            | TaChoice::Process { overrides, .. }
            | TaChoice::ResourceManager { overrides, .. } => overrides,
        }
    }

    /// The name for messages and the manifest (the command line for a process).
    pub fn label(&self) -> &str {
        match self {
            TaChoice::Builtin { name, .. } => name,
            TaChoice::Process { cmd, .. } | TaChoice::ResourceManager { cmd, .. } => cmd,
        }
    }

    /// Whether it forms tracks (so that `mimo track` may re-run it). A process is assumed to.
    pub fn tracks(&self) -> bool {
        match self {
            TaChoice::Builtin { name, .. } => registry::builtin(name).is_ok_and(|b| b.tracks),
            TaChoice::Process { .. } | TaChoice::ResourceManager { .. } => true,
        }
    }

    /// How the dwell schedule is made, for the manifest.
    pub fn schedule(&self) -> String {
        match self {
            TaChoice::Builtin { name, .. } => registry::schedule_description(name),
            TaChoice::Process { cmd, .. } => {
                format!("closed loop: background search plus dwells requested by the test article process `{cmd}`")
            }
            TaChoice::ResourceManager { name, cmd, .. } => format!(
                "closed loop: background search plus dwells decided by the resource manager process `{cmd}` over the '{name}' test article's tracker and proposals"
            ),
        }
    }
}
