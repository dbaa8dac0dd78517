//! Choosing and configuring the test article: the flags `mimo simulate` and `mimo track` share.

use crate::CliError;
use mimo_sim::World;
use mimo_sim::test_article::TestArticle;
use mimo_ta::overrides;
use mimo_ta::registry;
use serde_json::Value;
use std::path::PathBuf;

/// Which test article runs, and its configuration.
#[derive(Debug, Clone, clap::Args)]
pub struct TaArgs {
    /// Built-in test article: default (EKF tracker, GNN, adaptive revisit and energy, MIMO
    /// dwells), imm (the same with an IMM), cued (truth-cued fixed schedule, no tracking), none
    /// (background search only).
    #[arg(long, default_value = "default", value_name = "NAME")]
    pub tracker: String,
    /// TOML file of configuration overrides merged over the test article's defaults (the keys
    /// of `tracker.config` in a run's manifest.json, e.g. `[resource_manager]` `mimo = false`).
    #[arg(long, value_name = "FILE.toml")]
    pub ta_config: Option<PathBuf>,
    /// Override one configuration key, after --ta-config (repeatable), e.g.
    /// `--set resource_manager.mimo=false --set tracker.gate.probability=0.99`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// A resolved choice: a built-in and its checked configuration.
#[derive(Debug, Clone)]
pub struct TaChoice {
    /// Built-in name.
    pub name: String,
    /// Its merged configuration.
    pub config: Value,
    /// The overrides alone (passed on in the `start` event).
    pub overrides: Value,
}

fn config_err(a: &TaArgs, e: overrides::ConfigError) -> CliError {
    match (&a.ta_config, &e) {
        (_, overrides::ConfigError::File { .. } | overrides::ConfigError::UnknownTa { .. }) => {
            CliError::input(if matches!(e, overrides::ConfigError::UnknownTa { .. }) {
                format!("--tracker: {e}")
            } else {
                e.to_string()
            })
        }
        (Some(f), _) => CliError::input(format!("{} / --set: {e}", f.display())),
        (None, _) => CliError::input(format!("--set: {e}")),
    }
}

impl TaArgs {
    /// Check the name and the overrides before anything runs.
    pub fn resolve(&self) -> Result<TaChoice, CliError> {
        registry::builtin(&self.tracker).map_err(|e| config_err(self, e))?;
        let over = overrides::collect(self.ta_config.as_deref(), &self.set).map_err(|e| config_err(self, e))?;
        let config = registry::resolve_config(&self.tracker, &over).map_err(|e| config_err(self, e))?;
        Ok(TaChoice { name: self.tracker.clone(), config, overrides: over })
    }
}

impl TaChoice {
    /// A fresh test article for one run.
    pub fn build<'w>(&self, world: &'w World) -> Result<Box<dyn TestArticle + 'w>, CliError> {
        registry::build(&self.name, &self.config, world).map_err(|e| CliError::input(format!("--tracker: {e}")))
    }
}
