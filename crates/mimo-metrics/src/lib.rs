//! mimo-metrics
