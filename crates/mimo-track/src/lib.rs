//! mimo-track
