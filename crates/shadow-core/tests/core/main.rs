//! shadow-core tests, one binary (each test binary links wgpu, which is slow on 2 cores).

mod bias;
mod casting;
#[cfg(feature = "gpu")]
mod cpu_only;
mod light_sampling;
mod rasterizer;
mod registry;
mod view_fit;
mod views;

use soft_shadow_core::pool::Pool;
use std::sync::Arc;

/// A pool for one test's maps (nothing kept between calls).
pub fn pool() -> Arc<Pool> {
    Arc::new(Pool::new(0))
}
