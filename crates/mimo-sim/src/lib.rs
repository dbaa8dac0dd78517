//! mimo-sim
