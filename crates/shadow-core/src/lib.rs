//! Shared foundation of the soft-shadow workspace.
//!
//! - [`geometry`]: plain world-space triangles ([`SceneGeometry`]), what technique kernels take.
//! - [`light`]: the light kinds, their validation and sampling; [`view`]: camera and light frusta;
//!   [`light_space`]: per-map parameters, light-sample views and receiver biases.
//! - [`map2d`]: row-major maps; [`raster`]: the CPU rasterizer (depth maps and G-buffers) and
//!   [`raster::snapped`], which texels a triangle covers under the GPU's fill rule;
//!   the packing of nearest-seed maps ([`seeds`]); [`pool`]: reuse of large CPU buffers;
//!   [`rng`]: the deterministic generator of procedural scenes and of tests' random cases.
//! - [`technique`]: the [`ShadowTechnique`] trait; [`gpu`]: the wgpu context and GPU rasterization.
//!
//! The `bevy_ecs` scene, glTF import and the frame pipeline that schedules techniques are the
//! `shadow-frame` crate.
//!
//! Conventions: right-handed, +Y up, metres; visibility `V` in `[0, 1]` (1 lit, 0 umbra).

pub mod coverage;
pub mod cpu;
pub mod error;
pub mod geometry;
pub mod gpu;
pub mod light;
pub mod light_space;
pub mod map2d;
pub mod memory;
pub mod mesh;
pub mod pool;
pub mod raster;
pub mod receivers;
pub mod rng;
pub mod seeds;
pub mod technique;
pub mod view;

pub use coverage::Coverage;
pub use cpu::CpuContext;
pub use error::{Result, ShadowError};
pub use geometry::SceneGeometry;
pub use gpu::GpuContext;
pub use light::{DistantProfile, Light, LightKind, LightPoint};
pub use light_space::{Bias, MapParams, SampleView, ShadowCoord};
pub use map2d::Map2D;
pub use mesh::{Aabb, TriangleMesh};
pub use receivers::Receivers;
pub use technique::{
    AnyMaps, Backend, Checked, Context, DynTechnique, Generation, ShadowTechnique, TechniqueInfo,
};
pub use view::{Camera, View};
