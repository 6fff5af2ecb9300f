//! Shared foundation of the soft-shadow workspace.
//!
//! - [`geometry`]: plain world-space triangles ([`SceneGeometry`]), what technique kernels take.
//! - `scene` (feature `ecs`): the `bevy_ecs` scene (meshes, transforms, casters, receivers,
//!   lights, camera) and its flattening into [`SceneGeometry`]; `frame` (feature `ecs`): the
//!   per-frame pipeline that schedules techniques.
//! - [`light`]: the light kinds, their validation and sampling; [`view`]: camera and light frusta;
//!   [`light_space`]: per-map parameters, light-sample views and receiver biases.
//! - [`map2d`]: row-major maps; [`raster`]: the CPU rasterizer (depth maps and G-buffers) and
//!   [`raster::snapped`], which texels a triangle covers under the GPU's fill rule;
//!   nearest-seed maps ([`seeds`]), exact ([`feature_transform`]) or by [`jump_flood`], CPU and
//!   GPU; [`pool`]: reuse of large CPU buffers;
//!   [`rng`]: the deterministic generator of procedural scenes and of tests' random cases.
//! - [`technique`]: the [`ShadowTechnique`] trait; [`gpu`]: the wgpu context and GPU rasterization.
//! - `gltf_import` (feature `gltf`): glTF/GLB meshes.
//!
//! Features: `ecs` (`bevy_ecs`) and `gltf` (the `gltf` crate), both on by default; a renderer that
//! only needs the techniques turns them off (`default-features = false`) and keeps wgpu, glam,
//! bytemuck and rayon.
//!
//! Conventions: right-handed, +Y up, metres; visibility `V` in `[0, 1]` (1 lit, 0 umbra).

pub mod coverage;
pub mod error;
pub mod feature_transform;
#[cfg(feature = "ecs")]
pub mod frame;
pub mod geometry;
#[cfg(feature = "gltf")]
pub mod gltf_import;
pub mod gpu;
pub mod jump_flood;
pub mod light;
pub mod light_space;
pub mod map2d;
pub mod memory;
pub mod mesh;
pub mod pool;
pub mod raster;
pub mod rng;
#[cfg(feature = "ecs")]
pub mod scene;
pub mod seeds;
pub mod technique;
pub mod view;

pub use coverage::Coverage;
pub use error::{Result, ShadowError};
pub use geometry::SceneGeometry;
pub use gpu::GpuContext;
pub use light::{DistantProfile, Light, LightKind, LightPoint};
pub use light_space::{Bias, MapParams, SampleView, ShadowCoord};
pub use map2d::Map2D;
pub use mesh::{Aabb, TriangleMesh};
#[cfg(feature = "ecs")]
pub use scene::Scene;
pub use technique::{AnyMaps, Backend, DynTechnique, Receivers, ShadowTechnique};
pub use view::{Camera, View};
