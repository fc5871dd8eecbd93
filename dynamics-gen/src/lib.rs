//! Generator.
pub mod expr;
pub mod expand;
