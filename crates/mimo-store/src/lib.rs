//! mimo-store
