//! The scene, its flattening and glTF import: transforms and flags kept, bad input a typed error.

#[cfg(feature = "gltf")]
mod bad_input;
mod scene;
