//! shadow-core tests, one binary (each test binary links wgpu, which is slow on 2 cores).

mod bias;
mod feature_transform;
mod gpu_timer;
mod light_sampling;
mod rasterizer;
