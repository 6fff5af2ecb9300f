//! Generation cost per map resolution (128..2048) for every technique, variant and baseline of
//! the report, each on a scene whose light it models (`shadow_benches::bench_scene`): CPU, GPU
//! wall time (record, submit and wait, from geometry already on the GPU) and GPU device time
//! (timestamp queries on every pass, where the adapter has them); the hard map also from cold
//! caches (`cpu-cold`). Plus writing a map's texels once (the hard map's floor) and the frame
//! pipeline with and without map caching.
//!
//! `cargo bench -p shadow-benches --bench generation [-- <regex>]`; see `benches/README.md`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use harness::animated::{self, AnimatedScene};
use harness::report::cost::{HARD, write_texels};
use shadow_benches::{EVICT_BYTES, RESOLUTIONS, configs, gpu, iter_cold, iter_device_time, timing};
use shadow_frame::FrameSettings;
use soft_shadow_core::gpu::GpuScene;
use soft_shadow_core::{Context, CpuContext, GpuContext};

fn generation(c: &mut Criterion) {
    let gpu: Option<GpuContext> = gpu();
    let cpu_ctx = CpuContext::new();
    for cfg in configs() {
        let (t, geo, light) = (&cfg.technique, &cfg.geometry, &cfg.spec.light);
        let views = soft_shadow_core::LightViews::plan(light, geo, None);
        let mut group = c.benchmark_group(format!("generate/{}/{}", cfg.spec.name, cfg.label()));
        timing(&mut group, 10);
        // The hard map also from cold caches, beside `write-once/cold` (its goal's floor).
        let mut evict = (t.name() == HARD).then(|| vec![0u8; EVICT_BYTES]);
        for res in RESOLUTIONS {
            let cpu = || {
                t.generate(Context::Cpu(&cpu_ctx), geo, light, res)
                    .expect("cpu generation")
            };
            group.bench_with_input(BenchmarkId::new("cpu", res), &res, |b, _| b.iter(cpu));
            if let Some(evict) = &mut evict {
                group.bench_with_input(BenchmarkId::new("cpu-cold", res), &res, |b, _| {
                    iter_cold(b, evict, cpu)
                });
            }
            let Some(g) = &gpu else { continue };
            let scene = GpuScene::new(g, geo).expect("gpu scene");
            group.bench_with_input(BenchmarkId::new("gpu-wall", res), &res, |b, &res| {
                b.iter(|| {
                    let maps = t
                        .generate_gpu_on(g, &scene, light, &views, res)
                        .expect("gpu generation");
                    maps.recycle(Some(g));
                })
            });
            if g.has_timestamps() {
                group.bench_with_input(BenchmarkId::new("gpu-device", res), &res, |b, &res| {
                    iter_device_time(b, g, || {
                        let maps = t.generate_gpu_on(g, &scene, light, &views, res)?;
                        maps.recycle(Some(g));
                        Ok(())
                    })
                });
            }
        }
        group.finish();
    }
}

/// Writing every texel of an `f32` map once on every thread, the floor the hard map's
/// generation is compared with (`harness::report::cost::write_texels`, into a map already
/// faulted in): `cpu` back to back, the map left in the cache by the write before, and `cold`
/// after evicting the caches ([`iter_cold`]), beside the hard map's `cpu-cold`.
fn write_once(c: &mut Criterion) {
    let mut group = c.benchmark_group("write-once");
    timing(&mut group, 20);
    let mut evict = vec![0u8; EVICT_BYTES];
    for res in RESOLUTIONS {
        let mut map = vec![0.0f32; res as usize * res as usize];
        group.bench_with_input(BenchmarkId::new("cpu", res), &res, |b, _| {
            b.iter(|| write_texels(&mut map, 1.0))
        });
        group.bench_with_input(BenchmarkId::new("cold", res), &res, |b, _| {
            iter_cold(b, &mut evict, || write_texels(&mut map, 1.0))
        });
    }
    group.finish();
}

/// The frame pipeline on `harness::animated` (96² receivers, maps of 128): 100 frames, the box
/// moving for the first 50, with map caching and without (every light regenerated each frame).
fn frame_caching(c: &mut Criterion) {
    let mut group = c.benchmark_group("frame/animated-100");
    group.sample_size(10);
    for caching in [true, false] {
        let id = if caching { "cached" } else { "uncached" };
        group.bench_function(id, |b| {
            b.iter(|| {
                let mut lab = AnimatedScene::new(96, 128).expect("animated scene");
                lab.scene
                    .world
                    .insert_resource(FrameSettings::default().with_caching(caching));
                let mut p = animated::pipeline();
                for f in 0..100 {
                    lab.step(f, 100);
                    p.run(&mut lab.scene.world);
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, generation, write_once, frame_caching);
criterion_main!(benches);
