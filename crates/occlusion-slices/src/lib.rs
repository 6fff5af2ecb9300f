//! Eisemann & Décoret (2006), *Plausible Image Based Soft Shadows Using Occlusion Textures*.
//!
//! This crate is a placeholder until its issue lands: it will hold the binary occlusion slices,
//! their prefiltering (mipmaps, N-Buffers, summed-area tables) and the product combination.
