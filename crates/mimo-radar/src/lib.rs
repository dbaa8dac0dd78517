//! mimo-radar
