//! A technique written for the CPU alone (as a technique crate is built without its `gpu`
//! feature) is a whole `ShadowTechnique` in a build whose core has the GPU side: the GPU items
//! have defaults, so features stay additive, and GPU work is refused with a typed error.

use glam::Vec3;
use soft_shadow_core::{
    Checked, CpuContext, DynTechnique, Generation, LightKind, NoGpuMaps, Receivers, Result,
    ShadowError, ShadowTechnique, TechniqueInfo,
};

/// Lit everywhere, on the CPU only.
#[derive(Clone)]
struct CpuOnly;

impl TechniqueInfo for CpuOnly {
    fn name(&self) -> &'static str {
        "cpu-only"
    }
    fn variant(&self) -> String {
        "lit".into()
    }
    fn call(&self) -> String {
        "CpuOnly".into()
    }
    fn models(&self, _: LightKind) -> bool {
        true
    }
}

impl ShadowTechnique for CpuOnly {
    type CpuMaps = ();
    type GpuMaps = NoGpuMaps;
    fn cpu_maps(&self, _: &CpuContext, _: Checked<Generation<'_>>) {}
    fn cpu_visibility(&self, _: &(), r: Checked<Receivers<'_>>) -> Result<Vec<f32>> {
        Ok(vec![1.0; r.positions.len()])
    }
}

#[test]
fn a_technique_without_a_gpu_path_refuses_gpu_work_with_a_typed_error() {
    let err = <CpuOnly as ShadowTechnique>::visibility_wgsl(1).unwrap_err();
    assert!(
        matches!(&err, ShadowError::Gpu(m) if m.contains("without its GPU path")),
        "{err}"
    );
    assert!(DynTechnique::visibility_wgsl(&CpuOnly, 1).is_err());
    // Its CPU path works as any technique's.
    let geometry = soft_shadow_core::SceneGeometry::new(
        vec![[Vec3::ZERO, Vec3::X, Vec3::Z]],
        vec![[Vec3::NEG_Y, Vec3::NEG_Y + Vec3::X, Vec3::NEG_Y + Vec3::Z]],
    );
    let light = soft_shadow_core::Light::Point {
        position: Vec3::Y * 3.0,
    };
    let cpu = CpuContext::new();
    let maps = CpuOnly.generate_cpu(&cpu, &geometry, &light, 16).unwrap();
    let p = [Vec3::new(0.2, -1.0, 0.2)];
    let v = CpuOnly
        .evaluate_cpu(&maps, &Receivers::new(&p, &[Vec3::Y]))
        .unwrap();
    assert_eq!(v, vec![1.0]);
}
