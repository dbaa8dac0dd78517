//! mimo-scenario
