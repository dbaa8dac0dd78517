//! mimo-report
