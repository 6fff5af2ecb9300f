//! A renderer's own device (`GpuContext::from_device`): every technique runs on a device made
//! with WebGPU's default limits and no optional feature, and gives the same `V` as on the
//! harness's own context; a device below the defaults is refused with the limits it lacks.

use super::receivers;
use crate::common::gpu_for_test;
use harness::report::all_techniques;
use soft_shadow_core::{Context, GpuContext, Receivers as Recv, ShadowError};
use soft_shadow_reference::scenes::catalogue::build;
use soft_shadow_reference::scenes::relight::relight;

/// A device as a renderer would make it: the environment's adapter, WebGPU default limits, no
/// optional features; `None` without an adapter (then `gpu_for_test` has decided to skip).
fn renderer_device(limits: wgpu::Limits) -> Option<(wgpu::Device, wgpu::Queue)> {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter =
        pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
            .ok()?;
    pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("renderer"),
        required_features: wgpu::Features::empty(),
        required_limits: limits,
        ..Default::default()
    }))
    .ok()
}

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn every_technique_runs_on_a_renderers_default_limits_device() {
    let Some(reference_ctx) =
        gpu_for_test("every_technique_runs_on_a_renderers_default_limits_device")
    else {
        return;
    };
    let (device, queue) = renderer_device(wgpu::Limits::default()).expect("a default device");
    let own = GpuContext::from_device(device, queue).expect("default limits suffice");
    let spec = build("plane-occluder").unwrap();
    let r = receivers(&spec, 48);
    let recv = Recv {
        positions: &r.positions,
        normals: &r.normals,
    };
    for t in all_techniques(true) {
        let Some(light) = relight(&spec.light, &r.geometry.bounds, |k| t.models(k)) else {
            continue;
        };
        let run = |ctx: &GpuContext| {
            let maps = t
                .generate(Context::Gpu(ctx), &r.geometry, &light, 64)
                .unwrap();
            maps.evaluate(Some(ctx), &recv).unwrap()
        };
        let (a, b) = (run(&own), run(&reference_ctx));
        let worst = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f32, f32::max);
        assert!(
            worst <= 1e-6,
            "{} {}: own device differs by {worst}",
            t.name(),
            t.variant()
        );
    }
}

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn a_device_below_the_default_limits_is_refused_by_name() {
    if gpu_for_test("a_device_below_the_default_limits_is_refused_by_name").is_none() {
        return;
    }
    let (device, queue) =
        renderer_device(wgpu::Limits::downlevel_webgl2_defaults()).expect("a downlevel device");
    match GpuContext::from_device(device, queue) {
        Err(ShadowError::Gpu(m)) => {
            assert!(m.contains("max_storage_buffers_per_shader_stage"), "{m}")
        }
        other => panic!("expected a refusal, got {:?}", other.map(|c| c.describe())),
    }
}

/// A lost device (here destroyed by its renderer) turns every later generation and evaluation
/// into a typed `ShadowError::Gpu`, for every technique, instead of a panic.
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn a_lost_device_is_a_typed_error() {
    if gpu_for_test("a_lost_device_is_a_typed_error").is_none() {
        return;
    }
    let (device, queue) = renderer_device(wgpu::Limits::default()).expect("a default device");
    let ctx = GpuContext::from_device(device, queue).expect("default limits suffice");
    let spec = build("plane-occluder").unwrap();
    let r = receivers(&spec, 16);
    let recv = Recv {
        positions: &r.positions,
        normals: &r.normals,
    };
    let mut techniques = all_techniques(true);
    techniques.dedup_by_key(|t| t.name());
    // Maps made before the loss, evaluated after it.
    let before: Vec<_> = techniques
        .iter()
        .map(|t| {
            let light = relight(&spec.light, &r.geometry.bounds, |k| t.models(k)).unwrap();
            t.generate(Context::Gpu(&ctx), &r.geometry, &light, 32)
                .unwrap()
        })
        .collect();
    ctx.device.destroy();
    for (t, maps) in techniques.iter().zip(&before) {
        let light = relight(&spec.light, &r.geometry.bounds, |k| t.models(k)).unwrap();
        let generated = t.generate(Context::Gpu(&ctx), &r.geometry, &light, 32);
        assert!(
            matches!(generated, Err(ShadowError::Gpu(_))),
            "{}: generate on a lost device: {:?}",
            t.name(),
            generated.err()
        );
        let evaluated = maps.evaluate(Some(&ctx), &recv);
        assert!(
            matches!(evaluated, Err(ShadowError::Gpu(_))),
            "{}: evaluate on a lost device: {:?}",
            t.name(),
            evaluated.err()
        );
    }
}
