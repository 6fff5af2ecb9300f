//! Shared foundation of the soft-shadow workspace.
//!
//! - [`scene`]: the `bevy_ecs` scene (meshes, transforms, casters, receivers, lights, camera) and
//!   its flattening into plain [`SceneGeometry`] for technique kernels.
//! - [`light`]: the light kinds, their validation and sampling; [`view`]: camera and light frusta;
//!   [`light_space`]: per-map parameters, light-sample views and receiver biases.
//! - [`map2d`]: row-major maps; [`raster`]: the CPU rasterizer (depth maps and G-buffers);
//!   [`jump_flood`]: nearest-seed maps (CPU and GPU).
//! - [`technique`]: the [`ShadowTechnique`] trait; [`gpu`]: the wgpu context and GPU rasterization.
//! - [`gltf_import`]: glTF/GLB meshes.
//!
//! Conventions: right-handed, +Y up, metres; visibility `V` in `[0, 1]` (1 lit, 0 umbra).

pub mod coverage;
pub mod error;
pub mod frame;
pub mod gltf_import;
pub mod gpu;
pub mod jump_flood;
pub mod light;
pub mod light_space;
pub mod map2d;
pub mod mesh;
pub mod raster;
pub mod scene;
pub mod technique;
pub mod view;

pub use coverage::Coverage;
pub use error::{Result, ShadowError};
pub use gpu::GpuContext;
pub use light::{DistantProfile, Light, LightKind, LightPoint};
pub use light_space::{Bias, MapParams, SampleView, ShadowCoord};
pub use map2d::Map2D;
pub use mesh::{Aabb, TriangleMesh};
pub use scene::{Scene, SceneGeometry};
pub use technique::{AnyMaps, Backend, DynTechnique, Receivers, ShadowTechnique};
pub use view::{Camera, View};
