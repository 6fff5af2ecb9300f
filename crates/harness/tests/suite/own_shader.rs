//! A renderer's own fragment shader calling a technique's `visibility()`, the two ways
//! docs/integration.md offers: importing the technique's module through the renderer's own
//! naga_oil `Composer` (`Library::add_to`, `#import <module> as technique`), and pasting the
//! flattened WGSL (`visibility_wgsl`). Each draws `V` over a G-buffer into an `R32Float` target
//! and must equal `record_visibility`'s compute pass over the same G-buffer and maps, for one
//! variant of every technique type, on lavapipe in CI.

use crate::common::{gpu_for_test, texture, upload};
use glam::Vec3;
use naga_oil::compose::{Composer, NagaModuleDescriptor, ShaderDefValue};
use soft_shadow_core::gpu::raster::read_texture;
use soft_shadow_core::gpu::visibility::{ReceiverTextures, pipelines};
use soft_shadow_core::{GpuContext, ShadowTechnique};
use soft_shadow_reference::scenes::catalogue::build;

/// G-buffer side.
const SIZE: u32 = 48;
/// Map side.
const RESOLUTION: u32 = 256;
/// The maps' bind group in the renderer's pipeline; its G-buffer is group 1.
const MAPS_AT: u32 = 0;

/// The renderer's shader after its imports: a full-screen triangle, and per pixel the
/// technique's `visibility()` of the G-buffer texel (1 where nothing covers it).
const USER_BODY: &str = r#"
@group(1) @binding(0) var positions: texture_2d<f32>;
@group(1) @binding(1) var normals: texture_2d<f32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let xy = vec2<i32>(frag.xy);
    let p = textureLoad(positions, xy, 0);
    if p.w < 0.5 {
        return vec4<f32>(1.0, 0.0, 0.0, 1.0);
    }
    let n = textureLoad(normals, xy, 0).xyz;
    return vec4<f32>(VISIBILITY(p.xyz, n), 0.0, 0.0, 1.0);
}
"#;

/// The shader as a renderer with its own naga_oil composer writes it: the technique's library
/// added to the composer, its module imported, `MAPS_GROUP` among the shader defs.
fn composed<T: ShadowTechnique>() -> naga::Module {
    let mut composer = Composer::default();
    T::VISIBILITY
        .library
        .add_to(&mut composer)
        .unwrap_or_else(|e| panic!("{}: {e}", T::VISIBILITY.module));
    let source = format!(
        "#import {} as technique\n{}",
        T::VISIBILITY.module,
        USER_BODY.replace("VISIBILITY(", "technique::visibility(")
    );
    composer
        .make_naga_module(NagaModuleDescriptor {
            source: &source,
            file_path: "renderer.wgsl",
            shader_defs: [(
                soft_shadow_core::gpu::shader::MAPS_GROUP.to_string(),
                ShaderDefValue::UInt(MAPS_AT),
            )]
            .into(),
            ..Default::default()
        })
        .unwrap_or_else(|e| panic!("{}: {}", T::VISIBILITY.module, e.emit_to_string(&composer)))
}

/// The shader as a renderer without naga_oil writes it: the flattened WGSL pasted before its
/// own code.
fn pasted<T: ShadowTechnique>() -> String {
    let flat = T::visibility_wgsl(MAPS_AT).unwrap();
    format!(
        "{flat}\n{}",
        USER_BODY.replace("VISIBILITY(", "visibility(")
    )
}

/// An `R32Float` target of `w x h` that a pass can write (`usage`) and the test can read.
fn target(gpu: &GpuContext, w: u32, h: u32, usage: wgpu::TextureUsages) -> wgpu::Texture {
    texture(gpu, "V", (w, h, 1), wgpu::TextureFormat::R32Float, usage)
}

/// `V` drawn by the renderer's own pipeline from `module`, with the maps bound at
/// [`MAPS_AT`] in the technique's layout.
fn draw(
    gpu: &GpuContext,
    module: wgpu::ShaderSource<'_>,
    maps_layout: &wgpu::BindGroupLayout,
    maps: &wgpu::BindGroup,
    gbuffer: (&wgpu::Texture, &wgpu::Texture),
) -> Vec<f32> {
    let (w, h) = (gbuffer.0.width(), gbuffer.0.height());
    let texture = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    };
    let gbuffer_layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("renderer G-buffer"),
            entries: &[texture(0), texture(1)],
        });
    let (pv, nv) = (
        gbuffer.0.create_view(&Default::default()),
        gbuffer.1.create_view(&Default::default()),
    );
    let gbuffer_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("renderer G-buffer"),
        layout: &gbuffer_layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&pv),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&nv),
            },
        ],
    });
    let layout = gpu
        .device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("renderer"),
            bind_group_layouts: &[Some(maps_layout), Some(&gbuffer_layout)],
            immediate_size: 0,
        });
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("renderer"),
            source: module,
        });
    let pipeline = gpu
        .device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("renderer"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::TextureFormat::R32Float.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
    let out = target(gpu, w, h, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let view = out.create_view(&Default::default());
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("renderer"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(MAPS_AT, maps, &[]);
        pass.set_bind_group(1, &gbuffer_group, &[]);
        pass.draw(0..3, 0..1);
    }
    gpu.queue.submit([enc.finish()]);
    read_texture(gpu, &out, 0, wgpu::TextureAspect::All, 4).unwrap()
}

/// On `scene` (one view of its light): `V` of the renderer's composed and pasted
/// shaders equals `record_visibility`'s on every G-buffer texel.
fn own_shader_matches_record_visibility<T: ShadowTechnique>(test: &str, scene: &str, t: T) {
    let Some(gpu) = gpu_for_test(test) else {
        return;
    };
    let spec = build(scene).unwrap();
    let r = crate::receivers(&spec, SIZE);
    let views = r.views(&spec.light);
    assert_eq!(views.len(), 1, "{test}: {scene}'s light has one view");
    let scene = soft_shadow_core::gpu::GpuScene::new(&gpu, &r.geometry).unwrap();
    let maps = t
        .generate_gpu_on(&gpu, &scene, &spec.light, &views, RESOLUTION)
        .unwrap();
    // The G-buffer: the receivers row by row, the rest of the last row uncovered.
    let n = r.positions.len() as u32;
    let (w, h) = (SIZE, n.div_ceil(SIZE));
    let texel = |i: usize, v: &[Vec3], w_covered: f32| {
        v.get(i).map_or([0.0; 4], |p| [p.x, p.y, p.z, w_covered])
    };
    let covered = (w * h) as usize;
    let positions: Vec<[f32; 4]> = (0..covered).map(|i| texel(i, &r.positions, 1.0)).collect();
    let normals: Vec<[f32; 4]> = (0..covered).map(|i| texel(i, &r.normals, 0.0)).collect();
    let pt = upload(&gpu, "positions", w, h, &positions);
    let nt = upload(&gpu, "normals", w, h, &normals);
    // The library's own pass.
    let binding = t.maps_bind_group(&gpu, &maps).unwrap();
    let expected_tex = target(&gpu, w, h, wgpu::TextureUsages::STORAGE_BINDING);
    let (pv, nv, vv) = (
        pt.create_view(&Default::default()),
        nt.create_view(&Default::default()),
        expected_tex.create_view(&Default::default()),
    );
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    t.record_visibility(
        &gpu,
        &mut enc,
        &binding,
        &ReceiverTextures {
            positions: &pv,
            normals: &nv,
            visibility: &vv,
            size: (w, h),
        },
    );
    gpu.queue.submit([enc.finish()]);
    let expected: Vec<f32> =
        read_texture(&gpu, &expected_tex, 0, wgpu::TextureAspect::All, 4).unwrap();
    let shadowed = expected[..n as usize].iter().filter(|&&v| v < 0.9).count();
    assert!(
        shadowed > 50,
        "{test}: {shadowed} receivers in shadow: the comparison would prove little"
    );
    let layout = &pipelines(&gpu, T::VISIBILITY).maps_layout;
    let maps_group = binding.maps(0).unwrap();
    for (how, source) in [
        (
            "naga_oil import",
            wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(composed::<T>())),
        ),
        (
            "pasted WGSL",
            wgpu::ShaderSource::Wgsl(std::borrow::Cow::Owned(pasted::<T>())),
        ),
    ] {
        let got = draw(&gpu, source, layout, maps_group, (&pt, &nt));
        let worst = got[..n as usize]
            .iter()
            .zip(&expected[..n as usize])
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        // The same function on the same texels; a fragment and a compute stage may round
        // differently by an ulp here and there.
        assert!(
            worst <= 1e-5,
            "{test} ({how}): V differs from record_visibility's by up to {worst}"
        );
        assert!(
            got[n as usize..].iter().all(|&v| v == 1.0),
            "{test} ({how}): an uncovered texel is not lit"
        );
    }
    t.recycle_gpu(&gpu, maps);
}

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn own_shader_shadow_maps() {
    own_shader_matches_record_visibility(
        "own_shader_shadow_maps",
        "bunny",
        shadow_maps::ShadowMapBaseline::new(shadow_maps::Filter::Pcss),
    );
}

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn own_shader_penumbra_limit() {
    own_shader_matches_record_visibility(
        "own_shader_penumbra_limit",
        "bunny",
        penumbra_limit::PenumbraLimit::new(penumbra_limit::Generator::Silhouette),
    );
}

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn own_shader_occlusion_slices() {
    own_shader_matches_record_visibility(
        "own_shader_occlusion_slices",
        "bunny",
        occlusion_slices::OcclusionSlices::new(8, occlusion_slices::Prefilter::NBuffer),
    );
}

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn own_shader_shadow_width() {
    own_shader_matches_record_visibility(
        "own_shader_shadow_width",
        "bunny",
        shadow_width::ShadowWidth::new(shadow_width::WidthMethod::Exact),
    );
}

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn own_shader_linear_light() {
    own_shader_matches_record_visibility(
        "own_shader_linear_light",
        "linear-bar",
        linear_light::LinearLight::new(3),
    );
}
