//! The scene, its flattening and glTF import: transforms and flags kept, bad input a typed
//! error; the calibration's medians.

#[cfg(feature = "gltf")]
mod bad_input;
mod calibration;
mod kept;
mod knapsack;
mod scene;
