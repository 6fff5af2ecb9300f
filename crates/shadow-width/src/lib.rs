//! Kirsch & Döllner (2003), *Real-Time Soft Shadows Using a Single Light Sample*.
//!
//! This crate is a placeholder until its issue lands: it will hold the depth map, the shadow-width
//! map and the attenuation function `I(sd, sw)`.
