//! CLI errors: input errors exit with status 2, everything else with 1.

use std::fmt;

/// An error of a command.
#[derive(Debug)]
pub enum CliError {
    /// Bad input or usage: a file, a field or a flag value (exit status 2).
    Input(String),
    /// Anything else (exit status 1).
    Other(String),
}

impl CliError {
    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::Input(_) => 2,
            CliError::Other(_) => 1,
        }
    }
    pub fn input(msg: impl Into<String>) -> CliError {
        CliError::Input(msg.into())
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            CliError::Input(s) | CliError::Other(s) => s,
        };
        // One line, always.
        write!(f, "{}", s.replace('\n', " "))
    }
}

impl std::error::Error for CliError {}

impl From<mimo_store::StoreError> for CliError {
    fn from(e: mimo_store::StoreError) -> CliError {
        if e.is_input_error() { CliError::Input(e.to_string()) } else { CliError::Other(e.to_string()) }
    }
}

impl From<mimo_metrics::MetricsError> for CliError {
    fn from(e: mimo_metrics::MetricsError) -> CliError {
        if e.is_bad_input() { CliError::Input(e.to_string()) } else { CliError::Other(e.to_string()) }
    }
}

impl From<mimo_scenario::ScenarioError> for CliError {
    fn from(e: mimo_scenario::ScenarioError) -> CliError {
        CliError::Input(e.to_string())
    }
}

impl From<mimo_sim::EngineError> for CliError {
    fn from(e: mimo_sim::EngineError) -> CliError {
        // A test article that fails, or a sink that cannot write, is not the user's input.
        CliError::Other(e.to_string())
    }
}

impl From<mimo_ta::replay::ReplayError> for CliError {
    fn from(e: mimo_ta::replay::ReplayError) -> CliError {
        use mimo_ta::replay::ReplayError as R;
        match e {
            R::UnknownDwell { .. } | R::UnknownFace { .. } => CliError::Input(e.to_string()),
            R::Run(_) => CliError::Other(e.to_string()),
            // The store's own error, with its class (input or system).
            R::DwellRows(e) => match e.downcast::<mimo_store::StoreError>() {
                Ok(store) => CliError::from(*store),
                Err(e) => CliError::Other(e.to_string()),
            },
        }
    }
}
