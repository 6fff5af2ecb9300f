//! Lawlor (2006), *Interpolation-Friendly Soft Shadow Maps* (penumbra limit maps).
//!
//! This crate is a placeholder until its issue lands: it will hold the four-channel map
//! (c, g, b, p_i) and the visibility-to-illumination table for distant lights.
