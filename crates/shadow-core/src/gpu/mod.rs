//! GPU side: the headless wgpu context and the render passes shared by every technique.

pub mod compute;
mod context;
pub mod jump_flood;
pub mod raster;
pub mod resources;
mod scene;
pub mod testing;
pub mod timer;
pub mod visibility;

pub use context::GpuContext;
pub use jump_flood::GpuJumpFlood;
pub use raster::{GpuGBuffer, GpuRasterizer, GpuTriangles};
pub use scene::{GpuScene, GpuSurfaces};

/// WGSL of [`crate::light_space`]: `MapView`, `Bias`, `linear_depth`, `linear_from_ndc`,
/// `shadow_coord`.
pub const LIGHT_SPACE_WGSL: &str = include_str!("light_space.wgsl");

/// A shader module whose source is [`LIGHT_SPACE_WGSL`] followed by `source` (a file that starts
/// with `// requires: light_space.wgsl`).
pub fn light_space_shader<'a>(label: &'a str, source: &str) -> wgpu::ShaderModuleDescriptor<'a> {
    wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(format!("{LIGHT_SPACE_WGSL}\n{source}").into()),
    }
}
