//! The proof of drop-in use, live: a small wgpu renderer with its own device, G-buffer and
//! shading passes that shows any technique crate through the public drop-in API
//! ([`GpuContext::from_device`](soft_shadow_core::GpuContext::from_device),
//! [`GpuScene`](soft_shadow_core::gpu::GpuScene), `record_gpu_in`, `record_visibility`,
//! `recycle_gpu`), in a window with a panel (winit 0.30, egui 0.37); `--frames` and
//! `--screenshot` render a given number of frames and write the last for scripts.
//!
//! `cargo run --release --bin viewer -- --scene bunny --technique occlusion-slices`
//!
//! - [`renderer`]: the passes; a technique is any entry of a
//!   [`Registry`](soft_shadow_core::Registry) (`soft_shadow_techniques::registry()` by
//!   default, [`app::run_with`] for another), recorded through
//!   [`DynTechnique::record_frame`](soft_shadow_core::DynTechnique::record_frame).
//! - [`lamps`]: the scenes of many lamps, through the frame pipeline on the renderer's device
//!   (`shadow_frame::gpu_frame`), one frame budget shared by the lamps.
//! - [`shade`]: the shading, in WGSL and in Rust for the tests.
//! - [`state`]: the camera, the light and the choices, as plain data.
//! - [`scene`]: opening catalogue scenes, scene files and glTF models.
//! - [`reference`](mod@reference): the ray-traced reference on a worker thread.
//! - [`app`]: the window; its panel and view input are `ui.rs`.

pub mod app;
pub mod lamps;
pub mod reference;
pub mod renderer;
pub mod scene;
pub mod shade;
pub mod state;
mod ui;

pub use renderer::{
    Frame, FrameSettings, PassTimes, Renderer, SHADERS, Shadow, ViewMode, model_on_ground,
    moving_light, own_device, view_colour,
};
