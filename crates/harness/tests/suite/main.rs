//! harness tests, one binary (each test binary links wgpu, which is slow on 2 cores); the
//! stability suite of issue 8 is its own target, `tests/stability`.

mod accumulation;
mod bad_input;
mod calls;
mod dependencies;
mod frame;
mod frame_budget;
mod frame_gpu_probe;
mod frame_gpu_timing;
mod frame_seen;
mod fuzz;
mod gpu_agreement;
mod gpu_timer;
mod ground_truth;
mod lamps_view;
mod linear_light;
mod occlusion_slices;
mod own_device;
mod own_shader;
mod papers;
mod penumbra_limit;
mod pool;
mod registry;
mod renderer;
mod report;
mod shadow_width;
mod shipped_text;
mod wgsl;

#[path = "../common/mod.rs"]
mod common;

pub use common::{Receivers, receivers};

/// Map resolutions at which every technique's GPU path is held to its CPU path on every
/// catalogue scene: one that is no power of two (96: the CPU N-Buffers panicked there and the
/// GPU mip chain was a level short, while every agreement test ran at 64 and 256) and 256.
pub const AGREEMENT_RESOLUTIONS: [u32; 2] = [96, 256];
