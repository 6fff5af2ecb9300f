//! GPU side: the headless wgpu context and the render passes shared by every technique.

pub mod compute;
mod context;
pub mod pool;
pub mod program;
pub mod raster;
pub mod resources;
mod scene;
pub mod shader;
pub mod timer;
pub mod visibility;

pub use context::GpuContext;
pub use program::{BuiltProgram, Kernel};
pub use raster::{GpuGBuffer, GpuRasterizer, GpuTriangles};
pub use scene::{GpuScene, GpuSurfaces};
