//! harness tests, one binary (each test binary links wgpu, which is slow on 2 cores); the
//! stability suite of issue 8 is its own target, `tests/stability`.

mod bad_input;
mod dependencies;
mod frame;
mod fuzz;
mod gpu_agreement;
mod ground_truth;
mod linear_light;
mod occlusion_slices;
mod own_device;
mod papers;
mod penumbra_limit;
mod pool;
mod report;
mod shadow_width;
mod wgsl;

#[path = "../common/mod.rs"]
mod common;

pub use common::{Receivers, receivers};
