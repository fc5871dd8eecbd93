//! Robot model.
