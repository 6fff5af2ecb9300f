//! Criterion benches live in `generation.rs`; this crate has no library code.
