#![doc = include_str!("../README.md")]

pub mod coverage;
pub mod cpu;
pub mod error;
pub mod geometry;
#[cfg(feature = "gpu")]
pub mod gpu;
#[cfg(not(feature = "gpu"))]
#[path = "no_gpu.rs"]
pub mod gpu;
pub mod light;
pub mod light_space;
pub mod map2d;
pub mod memory;
pub mod mesh;
pub mod pool;
pub mod raster;
pub mod receivers;
pub mod registry;
pub mod rng;
pub mod seeds;
pub mod technique;
pub mod view;
pub mod views;

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
pub use registry::{Family, Registry, Technique, Tier};
pub use technique::{
    AnyMaps, Backend, Checked, Context, CostForm, DeviceLimits, DynTechnique, Generation,
    NoGpuMaps, ShadowTechnique, TechniqueInfo,
};
pub use view::{Camera, View};
pub use views::{LightViews, Region, SeenDepth, Uncovered, ViewMaps};
