//! harness tests, one binary (each test binary links wgpu, which is slow on 2 cores).

mod bad_input;
mod frame;
mod gpu_agreement;
mod ground_truth;
mod linear_light;
mod occlusion_slices;
mod penumbra_limit;
mod report;
mod shadow_width;
mod stability;
mod wgsl;

use glam::Vec3;
use harness::scenes::SceneSpec;
use shadow_core::SceneGeometry;
use shadow_core::raster::gbuffer;

/// Geometry and G-buffer receivers of a scene, without the reference (cheap).
pub struct Receivers {
    /// Flattened geometry.
    pub geometry: SceneGeometry,
    /// Receiver positions.
    pub positions: Vec<Vec3>,
    /// Receiver normals.
    pub normals: Vec<Vec3>,
}

/// Renders the CPU G-buffer of `spec` at `size²` and returns its receivers.
pub fn receivers(spec: &SceneSpec, size: u32) -> Receivers {
    let mut scene = spec.to_scene().expect("catalogue scene builds");
    let geometry = scene.geometry();
    let cam = scene.camera().expect("camera");
    let gb = gbuffer(
        &cam.view(size, size),
        cam.eye,
        size,
        size,
        &geometry.receivers,
    );
    let (positions, normals) = gb
        .data()
        .iter()
        .filter(|t| t.covered && t.normal != Vec3::ZERO)
        .map(|t| (t.position, t.normal))
        .unzip();
    Receivers {
        geometry,
        positions,
        normals,
    }
}
