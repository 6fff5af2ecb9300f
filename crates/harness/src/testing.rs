//! What the workspace's tests share: the GPU-test policy, and the viewer's bunny frame.

use soft_shadow_core::GpuContext;

/// A context for the GPU test named `test`, or `None` (after printing why) where no adapter
/// exists and `CI` is not set. (On Linux with no Vulkan driver at all, the harness's build
/// script sets `cfg(no_gpu_adapter)` and the tests that need only the GPU are `ignored` before
/// they run.)
///
/// # Panics
///
/// Where `CI` is set and no adapter can be created: CI runs every GPU test (on lavapipe).
pub fn gpu_for_test(test: &str) -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(ctx) => Some(ctx),
        Err(e) if std::env::var_os("CI").is_some() => {
            panic!(
                "{test}: GPU tests are required in CI (CI is set) but no adapter is available: {e}"
            )
        }
        Err(e) => {
            eprintln!("skipping GPU test {test}: {e}");
            None
        }
    }
}

/// The ground under the bunny in the viewer's default frame (the `bunny` scene under its disk
/// light turned to face the camera's target), for the tests that count false umbra and light
/// leaks against the ray-traced reference there.
pub struct ViewerBunnyGround {
    /// The casters and the ground.
    pub geometry: soft_shadow_core::SceneGeometry,
    /// The disk light as the viewer aims it.
    pub light: soft_shadow_core::Light,
    /// An `n` x `n` grid of ground points over x, z in [-2, 1], around the bunny's shadow.
    pub positions: Vec<glam::Vec3>,
    /// Their normals (up).
    pub normals: Vec<glam::Vec3>,
    /// The reference `V` of each point (8 x 8 strata, 2 replicates); `None` where the light
    /// does not reach it.
    pub references: Vec<Option<f32>>,
}

impl ViewerBunnyGround {
    /// The frame with an `n` x `n` grid of ground receivers.
    pub fn new(n: u32) -> Self {
        use glam::Vec3;
        let spec = soft_shadow_reference::scenes::catalogue::build("bunny")
            .expect("the catalogue has the bunny");
        let tris =
            |keep: fn(&soft_shadow_reference::scenes::MeshInstance) -> bool| -> Vec<[Vec3; 3]> {
                spec.meshes
                    .iter()
                    .filter(|m| keep(m))
                    .flat_map(|m| m.mesh.world_triangles(m.transform).collect::<Vec<_>>())
                    .collect()
            };
        let (casters, receivers) = (tris(|m| m.caster), tris(|m| m.receiver));
        let mut all = casters.clone();
        all.extend(receivers.iter().copied());
        let geometry = soft_shadow_core::SceneGeometry {
            bounds: soft_shadow_core::Aabb::of_triangles(&all),
            casters,
            receivers,
        };
        let light = soft_shadow_core::Light::Disk {
            center: Vec3::new(0.5, 3.5, 0.5),
            normal: Vec3::new(-0.162_221_42, -0.973_328_5, -0.162_221_42),
            radius: 0.4,
        };
        let (lo, hi) = (-2.0f32, 1.0f32);
        let positions: Vec<Vec3> = (0..n * n)
            .map(|i| {
                let (x, z) = ((i % n) as f32 + 0.5, (i / n) as f32 + 0.5);
                Vec3::new(
                    lo + (hi - lo) * x / n as f32,
                    0.0,
                    lo + (hi - lo) * z / n as f32,
                )
            })
            .collect();
        let normals = vec![Vec3::Y; positions.len()];
        let references = soft_shadow_reference::ground_truth::RayTracer::new(&geometry.casters)
            .references(
                &light,
                &positions,
                &normals,
                &soft_shadow_reference::ground_truth::GroundTruthSettings {
                    strata_side: 8,
                    replicates: 2,
                    ..Default::default()
                },
            )
            .iter()
            .map(|r| r.map(|r| r.visibility))
            .collect();
        Self {
            geometry,
            light,
            positions,
            normals,
            references,
        }
    }
}
