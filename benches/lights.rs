//! Frame time against the number of lights under one frame budget: `soft_shadow_reference::scenes::lamps::street`'s street
//! with 1, 4, 16 and 64 lamps of five kinds, every lamp a shared choice of a 16 ms
//! `FrameBudget`, 320 x 180 camera receivers. Two frames per light count and backend:
//!
//! - `uncached`: every lamp makes its maps again (the frame the budget is for);
//! - `swing`: one lamp swings, so it alone makes its maps again, and every lamp evaluates.
//!
//! Before timing, twelve frames (the lamp swinging) calibrate the predictions
//! (`shadow_frame::Calibration`); then each count prints how many lamps cast a shadow, how many
//! light nothing the camera sees, and the picks' predicted time against the budget. The timed
//! frames hold that calibration (`FrameSettings::calibrating` off), so they keep the picks and
//! make every map they are to make: no lamp's maps wait a frame (`shadow_frame::deadline`).
//!
//! `frame/gpu-recording/{run,run_into}/<lamps>` (on a GPU adapter) times the GPU frame's two
//! ways to make the maps, `FramePipeline::run` and `FramePipeline::run_into`, over the same
//! work ([`recording`]).
//!
//! `cargo bench -p shadow-benches --bench lights [-- <regex>]`; see `benches/README.md`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use harness::animated::pipeline;

use shadow_benches::gpu;
use shadow_frame::{FrameBackend, FrameSettings, LightState};
use soft_shadow_core::GpuContext;
use std::sync::Arc;

/// The frame budget, milliseconds.
const BUDGET_MS: f64 = 16.0;

/// Frames run before timing.
const WARM_UP: u32 = 12;

/// The light counts.
const LIGHTS: [usize; 4] = [1, 4, 16, 64];

fn lights(c: &mut Criterion) {
    let gpu: Option<Arc<GpuContext>> = gpu().map(Arc::new);
    let mut group = c.benchmark_group("frame/night-street");
    group.sample_size(10);
    let mut backends = vec![("cpu", None)];
    if let Some(g) = &gpu {
        backends.push(("gpu", Some(Arc::clone(g))));
    }
    for (backend, g) in backends {
        for n in LIGHTS {
            for caching in [false, true] {
                let mut street =
                    soft_shadow_reference::scenes::lamps::street::street(n, 320, 180, BUDGET_MS)
                        .expect("night street");
                if let Some(g) = &g {
                    street
                        .scene
                        .world
                        .insert_resource(FrameBackend::gpu(Arc::clone(g)));
                }
                street
                    .scene
                    .world
                    .insert_resource(FrameSettings::default().with_caching(caching));
                let mut p = pipeline();
                // The frames the calibration learns from (`shadow_frame::Calibration`), the
                // lamp swinging: the picks timed are those the measured frames settle on.
                let mut first = p.run(&mut street.scene.world);
                for f in 1..=WARM_UP {
                    street.swing(f);
                    first = p.run(&mut street.scene.world);
                }
                if !caching {
                    let idle = street
                        .lamps
                        .iter()
                        .filter(|&&e| {
                            street
                                .scene
                                .world
                                .get::<LightState>(e)
                                .is_some_and(|s| s.share.is_some_and(|s| s.contribution == 0.0))
                        })
                        .count();
                    eprintln!(
                        "{backend} {n} lamps: {} cast a shadow, {idle} light nothing in view; \
                         predicted {:.2} ms of {BUDGET_MS} ms (calibrated; {:.2} kept for the \
                         pipeline); {}",
                        first.lights.len(),
                        first.predicted_ms(),
                        street
                            .scene
                            .world
                            .resource::<shadow_frame::Calibration>()
                            .core_ms,
                        first
                            .lights
                            .iter()
                            .map(|l| format!("{} {}²", l.technique, l.resolution))
                            .collect::<Vec<_>>()
                            .join(", ")
                    );
                }
                // Timed with the calibration held: the same picks, every map made.
                street.scene.world.insert_resource(
                    FrameSettings::default()
                        .with_caching(caching)
                        .with_calibrating(false),
                );
                let id = format!("{backend}/{}", if caching { "swing" } else { "uncached" });
                let mut f = WARM_UP;
                group.bench_with_input(BenchmarkId::new(id, n), &n, |b, _| {
                    b.iter(|| {
                        f += 1;
                        street.swing(f);
                        p.run(&mut street.scene.world)
                    })
                });
            }
        }
    }
    group.finish();
}

/// The GPU frame's two ways to make the lamps' maps, over the same work: every lamp of the
/// night street (1, 4, 16) with PCSS at 256² (an explicit choice, so both make the same maps),
/// caching off (every lamp makes its maps every frame), nothing read back
/// (`FrameSettings::evaluate_receivers` off), `V` recorded into a layer per lamp over the
/// street's 320 x 180 G-buffer. `run`: the pipeline submits each lamp's generation and waits
/// for it, then the frame's encoder records `V`; `run_into`: the generations and `V` in one
/// encoder. Each frame is submitted and waited for.
fn recording(c: &mut Criterion) {
    use shadow_frame::gpu_frame::{FrameTextures, VisibilityLayer, record_visibility};
    let Some(gpu) = gpu().map(Arc::new) else {
        return;
    };
    let mut group = c.benchmark_group("frame/gpu-recording");
    group.sample_size(10);
    let pcss: Arc<dyn soft_shadow_core::DynTechnique> = Arc::new(
        shadow_maps::ShadowMapBaseline::new(shadow_maps::Filter::Pcss),
    );
    for n in [1, 4, 16] {
        for into in [false, true] {
            let mut street =
                soft_shadow_reference::scenes::lamps::street::street(n, 320, 180, BUDGET_MS)
                    .expect("night street");
            let world = &mut street.scene.world;
            world.insert_resource(FrameBackend::gpu(Arc::clone(&gpu)));
            world.insert_resource(
                FrameSettings::default()
                    .with_caching(false)
                    .with_evaluate_receivers(false),
            );
            for (k, &e) in street.lamps.iter().enumerate() {
                let range = world
                    .get::<shadow_frame::ShadowConfig>(e)
                    .map_or(f32::INFINITY, |c| c.range);
                world.entity_mut(e).insert((
                    shadow_frame::ShadowConfig::explicit(Arc::clone(&pcss), 256).with_range(range),
                    VisibilityLayer(k as u32),
                ));
            }
            let frame = world.resource::<shadow_frame::FrameReceivers>().clone();
            let (w, h) = (320u32, 180u32);
            let texels = |v: &[glam::Vec3]| -> Vec<[f32; 4]> {
                let mut t: Vec<[f32; 4]> = v.iter().map(|p| [p.x, p.y, p.z, 1.0]).collect();
                t.resize((w * h) as usize, [0.0; 4]);
                t
            };
            let upload = |label: &str, data: &[[f32; 4]]| {
                let t = gpu.device.create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: w,
                        height: h,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: wgpu::TextureFormat::Rgba32Float,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                    view_formats: &[],
                });
                gpu.queue.write_texture(
                    t.as_image_copy(),
                    bytemuck::cast_slice(data),
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(w * 16),
                        rows_per_image: Some(h),
                    },
                    t.size(),
                );
                t.create_view(&Default::default())
            };
            let positions = upload("positions", &texels(&frame.positions));
            let normals = upload("normals", &texels(&frame.normals));
            let visibility = gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("visibility"),
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: n as u32,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::R32Float,
                usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            let targets = FrameTextures {
                positions: &positions,
                normals: &normals,
                visibility: &visibility,
            };
            let mut p = pipeline();
            let mut frame = || {
                let mut enc = gpu.device.create_command_encoder(&Default::default());
                if into {
                    p.run_into(&mut street.scene.world, &mut enc)
                        .expect("a GPU frame");
                } else {
                    p.run(&mut street.scene.world);
                }
                record_visibility(&mut street.scene.world, &gpu, &mut enc, &targets)
                    .expect("the lamps' V");
                gpu.queue.submit([enc.finish()]);
                gpu.wait().expect("the frame");
            };
            for _ in 0..2 {
                frame();
            }
            let id = if into { "run_into" } else { "run" };
            group.bench_with_input(BenchmarkId::new(id, n), &n, |b, _| b.iter(&mut frame));
        }
    }
    group.finish();
}

criterion_group!(benches, lights, recording);
criterion_main!(benches);
