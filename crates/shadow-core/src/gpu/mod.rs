//! GPU side: the headless wgpu context and the render passes shared by every technique.

mod context;
pub mod raster;
pub mod testing;

pub use context::GpuContext;
pub use raster::{GpuGBuffer, GpuRasterizer, GpuTriangles};
