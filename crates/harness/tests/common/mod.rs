//! Helpers shared by the harness test binaries (`suite`, `stability`).

#![allow(dead_code)]

use glam::Vec3;
use harness::scenes::SceneSpec;
use soft_shadow_core::SceneGeometry;

/// Geometry and G-buffer receivers of a scene, without the reference (cheap).
pub struct Receivers {
    /// Flattened geometry.
    pub geometry: SceneGeometry,
    /// Receiver positions.
    pub positions: Vec<Vec3>,
    /// Receiver normals.
    pub normals: Vec<Vec3>,
    /// What the camera sees, for a distant light's cascades.
    pub seen: Option<soft_shadow_core::SeenDepth>,
}

/// Renders the CPU G-buffer of `spec` at `size²` and returns its receivers.
pub fn receivers(spec: &SceneSpec, size: u32) -> Receivers {
    let (geometry, positions, normals) =
        harness::setup::scene_receivers(spec, size).expect("catalogue scene builds");
    let seen = soft_shadow_core::SeenDepth::of_points(spec.camera.view(size, size), &positions);
    Receivers {
        geometry,
        positions,
        normals,
        seen,
    }
}

/// The same receivers as the techniques take them.
impl Receivers {
    /// Borrowed as [`soft_shadow_core::Receivers`].
    pub fn as_receivers(&self) -> soft_shadow_core::Receivers<'_> {
        soft_shadow_core::Receivers::new(&self.positions, &self.normals)
    }

    /// The views of `light` over the geometry and what the camera sees.
    pub fn views(&self, light: &soft_shadow_core::Light) -> soft_shadow_core::LightViews {
        soft_shadow_core::LightViews::plan(light, &self.geometry, self.seen.as_ref())
    }
}

pub use harness::testing::gpu_for_test;

/// One CPU context for the whole test binary (its pool shared by the tests running in it).
pub fn cpu() -> &'static soft_shadow_core::CpuContext {
    static CPU: std::sync::OnceLock<soft_shadow_core::CpuContext> = std::sync::OnceLock::new();
    CPU.get_or_init(soft_shadow_core::CpuContext::new)
}

/// The context `backend` runs in: [`cpu`], or `gpu` (which the GPU backend needs).
pub fn context(
    backend: soft_shadow_core::Backend,
    gpu: Option<&soft_shadow_core::GpuContext>,
) -> soft_shadow_core::Context<'_> {
    match (backend, gpu) {
        (soft_shadow_core::Backend::Gpu, Some(g)) => soft_shadow_core::Context::Gpu(g),
        (soft_shadow_core::Backend::Gpu, None) => panic!("the GPU backend without a GPU context"),
        (soft_shadow_core::Backend::Cpu, _) => soft_shadow_core::Context::Cpu(cpu()),
    }
}
