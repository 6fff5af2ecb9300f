//! Heidrich, Brabec & Seidel (2000), *Soft Shadow Maps for Linear Lights*.
//!
//! This crate is a placeholder until its issue lands: it will hold the per-sample depth maps with
//! visibility channels built from depth-discontinuity skins, on CPU and GPU.
//! The paper is the specification: `shared/papers/heidrich2000-soft-shadow-maps-linear-lights.txt`.
