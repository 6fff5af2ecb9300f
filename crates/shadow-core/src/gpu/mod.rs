//! GPU side: the headless wgpu context and the render passes shared by every technique.

pub mod compute;
mod context;
pub mod feature_transform;
pub mod jump_flood;
pub mod pool;
pub mod raster;
pub mod resources;
mod scene;
pub mod timer;
pub mod visibility;
pub mod wgsl;

pub use context::GpuContext;
pub use feature_transform::GpuFeatureTransform;
pub use jump_flood::GpuJumpFlood;
pub use raster::{GpuGBuffer, GpuRasterizer, GpuTriangles};
pub use scene::{GpuScene, GpuSurfaces};

/// WGSL of [`crate::light_space`]: `MapView`, `Bias`, `linear_depth`, `linear_from_ndc`,
/// `shadow_coord`.
pub const LIGHT_SPACE_WGSL: &str = include_str!("light_space.wgsl");
