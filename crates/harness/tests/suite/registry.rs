//! One registry: a technique added with one line (`Registry::with`) appears in the report, in
//! `Auto`'s choices and in the viewer; and the checks a technique needs of a device happen in
//! `max_resolution`, before its kernels.

use glam::{Mat4, Vec3};
use harness::report::{BackendChoice, ReportOptions, run};
use shadow_frame::{
    FramePipeline, FrameReceivers, LightState, ProfileEntry, ResolvedTechnique, Scene,
    ShadowConfig, Shadows, TechniqueProfile,
};
use shadow_maps::{CpuShadowMaps, Filter, GpuShadowMaps, ShadowMapBaseline};
use soft_shadow_core::gpu::GpuScene;
use soft_shadow_core::gpu::shader::VisibilityShader;
use soft_shadow_core::{
    Backend, Checked, CostForm, CpuContext, DeviceLimits, Family, Generation, GpuContext, Light,
    LightKind, Receivers, Registry, Result, ShadowTechnique, TechniqueInfo, Tier,
};
use soft_shadow_reference::scenes::shapes::{cuboid, ground};
use std::sync::Arc;

/// A technique written in a test: the hard shadow map under another name.
#[derive(Clone)]
struct TestTechnique(ShadowMapBaseline);

impl TechniqueInfo for TestTechnique {
    fn name(&self) -> &'static str {
        "test-technique"
    }
    fn variant(&self) -> String {
        "only".into()
    }
    fn call(&self) -> String {
        "TestTechnique(ShadowMapBaseline::new(Filter::Hard))".into()
    }
    fn models(&self, kind: LightKind) -> bool {
        self.0.models(kind)
    }
}

impl ShadowTechnique for TestTechnique {
    type CpuMaps = CpuShadowMaps;
    type GpuMaps = GpuShadowMaps;
    fn cpu_maps(&self, cpu: &CpuContext, input: Checked<Generation<'_>>) -> CpuShadowMaps {
        self.0.cpu_maps(cpu, input)
    }
    fn cpu_visibility(&self, maps: &CpuShadowMaps, r: Checked<Receivers<'_>>) -> Result<Vec<f32>> {
        self.0.cpu_visibility(maps, r)
    }
    fn gpu_maps(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        input: Checked<Generation<'_>>,
    ) -> Result<GpuShadowMaps> {
        self.0.gpu_maps(gpu, enc, scene, input)
    }
    const VISIBILITY: &'static VisibilityShader = &shadow_maps::VISIBILITY;
    fn bind_maps(
        &self,
        gpu: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        maps: &GpuShadowMaps,
    ) -> Result<wgpu::BindGroup> {
        self.0.bind_maps(gpu, layout, maps)
    }
    fn recycle_maps(&self, gpu: &GpuContext, maps: GpuShadowMaps) {
        self.0.recycle_maps(gpu, maps)
    }
}

/// The workspace's registry and the test technique: the one line a technique takes.
fn registry() -> Registry {
    soft_shadow_techniques::registry().with([Family::new(
        TestTechnique(ShadowMapBaseline::new(Filter::Hard)),
        Tier::Quick,
    )])
}

/// The report runs the added technique beside the others, and, being the hard map under
/// another name, measures the hard map's errors.
#[test]
fn a_technique_added_with_one_line_is_in_the_report() {
    let dir = std::env::temp_dir().join(format!("harness-registry-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let opts = ReportOptions {
        quick: true,
        out: dir.clone(),
        scenes: Some(vec!["plane-occluder".into()]),
        techniques: Some(vec!["test-technique".into(), "hard-shadow-map".into()]),
        registry: registry(),
        resolutions: Some(vec![64]),
        backend: BackendChoice::Cpu,
        scene_files: Vec::new(),
        as_seen: None,
        size: Some(32),
        memory: Default::default(),
    };
    let report = run(&opts).expect("report runs");
    let errors = |technique: &str| {
        let run = report
            .runs
            .iter()
            .find(|r| r.technique == technique)
            .unwrap_or_else(|| panic!("{technique} ran"));
        (run.errors.rms_255, run.errors.image_rms_255)
    };
    assert_eq!(errors("test-technique"), errors("hard-shadow-map"));
    assert!(errors("test-technique").0 > 0.0, "a shadow with an error");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `Auto` picks the added technique where the profile says it is the best within the budget,
/// and its `V` is the hard map's.
#[test]
fn a_technique_added_with_one_line_is_one_auto_picks() {
    let mut scene = Scene::new();
    scene
        .add_mesh(
            Arc::new(ground(6.0, 0.0, 1)),
            Mat4::IDENTITY,
            Shadows::RECEIVE_ONLY,
        )
        .unwrap();
    scene
        .add_mesh(
            Arc::new(cuboid("box", Vec3::ZERO, Vec3::splat(0.3))),
            Mat4::from_translation(Vec3::new(0.0, 0.8, 0.0)),
            Shadows::CAST_ONLY,
        )
        .unwrap();
    let light = Light::Rect {
        center: Vec3::new(0.0, 3.0, 0.0),
        u_half: Vec3::X * 0.2,
        v_half: Vec3::Z * 0.2,
    };
    let auto = scene.add_light(light).unwrap();
    scene
        .world
        .entity_mut(auto)
        .insert(ShadowConfig::auto(50.0));
    let hard = scene.add_light(light).unwrap();
    scene.world.entity_mut(hard).insert(ShadowConfig::explicit(
        Arc::new(ShadowMapBaseline::new(Filter::Hard)),
        512,
    ));
    let positions: Vec<Vec3> = (0..64)
        .map(|i| Vec3::new(-1.6 + 0.05 * i as f32, 0.0, 0.1))
        .collect();
    scene.world.insert_resource(FrameReceivers {
        normals: vec![Vec3::Y; positions.len()],
        positions,
        camera: None,
    });
    let entry = |technique: &str, variant: &str, error_255: f64| ProfileEntry {
        technique: technique.into(),
        variant: variant.into(),
        backend: Backend::Cpu,
        form: CostForm::Texels,
        generate: [0.1, 0.0, 0.0, 0.0],
        evaluate: [0.0; 3],
        error: vec![(LightKind::Rect, [error_255, 0.0])],
        sides: (512, 512),
        margin: 1.0,
    };
    scene.world.insert_resource(TechniqueProfile {
        entries: vec![
            entry("hard-shadow-map", "nearest", 9.0),
            entry("test-technique", "only", 1.0),
        ],
    });
    let mut pipeline = FramePipeline::new().with_registry(&registry());
    pipeline.run(&mut scene.world);
    let picked = scene.world.get::<ResolvedTechnique>(auto).unwrap();
    assert_eq!(
        (picked.technique.name(), picked.resolution),
        ("test-technique", 512),
        "{}",
        picked.reason
    );
    let v = |e| scene.world.get::<LightState>(e).unwrap().visibility.clone();
    let (got, want) = (v(auto), v(hard));
    assert_eq!(got, want);
    assert!(got.contains(&0.0) && got.contains(&1.0));
}

/// The viewer offers the added technique (found by its name or the word it begins with) and
/// draws it through the same call as every technique: on the GPU its frame is the hard map's.
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn a_technique_added_with_one_line_is_in_the_viewer() {
    let reg = registry();
    let camera = soft_shadow_core::Camera {
        eye: Vec3::new(0.0, 2.6, 4.2),
        target: Vec3::new(0.0, 0.6, 0.0),
        fov_y: 0.9,
        near: 0.1,
        far: 20.0,
    };
    let light = viewer::moving_light(1, 8);
    let choice = viewer::state::Choice::new(&reg, "test", 512).unwrap();
    assert_eq!(
        (choice.technique, choice.variant.as_str()),
        ("test-technique", "only")
    );
    let state = viewer::state::ViewState::new(&camera, &light, choice);
    assert_eq!(state.shadow.technique, "test-technique");
    let Some((r, _)) =
        crate::renderer::renderer("a_technique_added_with_one_line_is_in_the_viewer")
    else {
        return;
    };
    let shown = reg.family("test-technique").unwrap().default_variant();
    let hard = reg.family("hard").unwrap().default_variant();
    r.render(&crate::renderer::frame(shown.as_ref(), &light))
        .unwrap();
    let a = r.read_color().unwrap();
    r.render(&crate::renderer::frame(hard.as_ref(), &light))
        .unwrap();
    let b = r.read_color().unwrap();
    assert_eq!(a.as_raw(), b.as_raw());
}

/// A map side a technique's generation would refuse on a device is above its
/// `max_resolution` there: with WebGPU's default limits (8192² textures, 128 MiB storage
/// bindings) the techniques that keep a map in storage buffers stop where one binding is full,
/// so the report, `Auto` and the viewer never offer a side the kernels cannot make.
#[test]
fn max_resolution_holds_the_devices_storage_limit() {
    let device = DeviceLimits {
        max_texture_side: 8192,
        max_storage_buffer_bytes: 128 << 20,
    };
    // sqrt(2^27 / 4) = 5792.6, sqrt(2^27 / 8) = 4096; linear-light's skin list holds
    // (side - 1)² entries.
    assert_eq!(device.storage_side(4), 5792);
    assert_eq!(device.storage_side(8), 4096);
    for family in soft_shadow_techniques::registry().families() {
        for t in family.variants() {
            let want = match t.name() {
                "penumbra-limit" => 5792,
                "linear-light" => 5793,
                "shadow-width" => 4096,
                "occlusion-slices" => 4096,
                _ => 8192,
            };
            assert_eq!(
                t.max_resolution(Backend::Gpu, device),
                want,
                "{} {}",
                t.name(),
                t.variant()
            );
        }
    }
}
