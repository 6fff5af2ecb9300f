//! Generation cost per map resolution, CPU and GPU, for the baselines' depth maps
//! (one map for hard/PCF/PCSS, 16 for accumulation), on the `torus` and `bunny` scenes, and for
//! shadow-width (width map alone and full generation, every width method) on `torus`, and for
//! penumbra-limit (both generators, f32 and RGBA8 storage) on `torus`, and for occlusion-slices
//! (slicing + prefiltering, every filter) on `foliage`, and for linear-light (N = 2, 3, 5) on
//! `linear-bar`; and the frame pipeline's 100-frame animated scene with and without map caching.
//!
//! `cargo bench -p shadow-benches`; GPU timings are submit-and-wait (the GPU path returns after
//! the device has finished). Without a GPU adapter the GPU group is skipped with a message.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use harness::animated::{self, AnimatedScene};
use harness::baselines::{Filter, ShadowMapBaseline};
use harness::scenes::catalogue::build;
use linear_light::LinearLight;
use occlusion_slices::{Filter as SliceFilter, OcclusionSlices};
use penumbra_limit::{PenumbraLimit, Storage};
use shadow_core::frame::FrameSettings;
use shadow_core::{Backend, DynTechnique, GpuContext};
use shadow_width::width::width_map;
use shadow_width::{DepthLayer, ShadowWidth, cpu};

const RESOLUTIONS: [u32; 5] = [128, 256, 512, 1024, 2048];

fn generation(c: &mut Criterion) {
    let gpu = match GpuContext::new() {
        Ok(g) => Some(g),
        Err(e) => {
            eprintln!("GPU benches skipped: {e}");
            None
        }
    };
    for scene in ["torus", "bunny"] {
        let spec = build(scene).expect("catalogue scene");
        let geo = spec.to_scene().expect("scene").geometry();
        for filter in [Filter::Hard, Filter::Accumulate { samples: 16 }] {
            let b = ShadowMapBaseline::new(filter);
            let mut group = c.benchmark_group(format!(
                "generate/{scene}/{}-{}",
                DynTechnique::name(&b),
                DynTechnique::variant(&b)
            ));
            group.sample_size(10);
            for res in RESOLUTIONS {
                group.bench_with_input(BenchmarkId::new("cpu", res), &res, |bch, &res| {
                    bch.iter(|| {
                        b.generate(Backend::Cpu, None, &geo, &spec.light, res)
                            .expect("cpu generation")
                    })
                });
                if let Some(g) = &gpu {
                    group.bench_with_input(BenchmarkId::new("gpu", res), &res, |bch, &res| {
                        bch.iter(|| {
                            b.generate(Backend::Gpu, Some(g), &geo, &spec.light, res)
                                .expect("gpu generation")
                        })
                    });
                }
            }
            group.finish();
        }
    }
}

/// shadow-width on `torus`: the width map alone from the occlusion mask (CPU builders, the step
/// the three methods differ in), then full generation (depth passes + mask + width) on CPU and GPU.
fn shadow_width_generation(c: &mut Criterion) {
    let gpu = GpuContext::new().ok();
    let spec = build("torus").expect("catalogue scene");
    let geo = spec.to_scene().expect("scene").geometry();
    for t in ShadowWidth::standard_set()
        .into_iter()
        .filter(|t| t.depth == DepthLayer::Front && t.table.is_none())
    {
        let mut group = c.benchmark_group(format!("shadow-width/torus/{}", t.label()));
        group.sample_size(10);
        for res in RESOLUTIONS {
            let maps = cpu::generate(&t, &geo, &spec.light, res);
            group.bench_with_input(BenchmarkId::new("width-map-cpu", res), &res, |bch, _| {
                bch.iter(|| width_map(&maps.occlusion, t.method))
            });
            group.bench_with_input(BenchmarkId::new("generate-cpu", res), &res, |bch, &res| {
                bch.iter(|| {
                    t.generate(Backend::Cpu, None, &geo, &spec.light, res)
                        .expect("cpu generation")
                })
            });
            if let Some(g) = &gpu {
                group.bench_with_input(BenchmarkId::new("generate-gpu", res), &res, |bch, &res| {
                    bch.iter(|| {
                        t.generate(Backend::Gpu, Some(g), &geo, &spec.light, res)
                            .expect("gpu generation")
                    })
                });
            }
        }
        group.finish();
    }
}

/// penumbra-limit on `torus`: full generation (depth pass, silhouette ribbons and back faces or
/// depth-image propagation, combine) per resolution, both generators, CPU and GPU; f32 and the
/// paper's RGBA8 storage.
fn penumbra_limit_generation(c: &mut Criterion) {
    let gpu = GpuContext::new().ok();
    let spec = build("torus").expect("catalogue scene");
    let geo = spec.to_scene().expect("scene").geometry();
    for t in PenumbraLimit::standard_set()
        .into_iter()
        .filter(|t| t.storage != Storage::F16)
    {
        let mut group = c.benchmark_group(format!("penumbra-limit/torus/{}", t.label()));
        group.sample_size(10);
        for res in RESOLUTIONS {
            group.bench_with_input(BenchmarkId::new("cpu", res), &res, |bch, &res| {
                bch.iter(|| {
                    t.generate(Backend::Cpu, None, &geo, &spec.light, res)
                        .expect("cpu generation")
                })
            });
            if let Some(g) = &gpu {
                group.bench_with_input(BenchmarkId::new("gpu", res), &res, |bch, &res| {
                    bch.iter(|| {
                        t.generate(Backend::Gpu, Some(g), &geo, &spec.light, res)
                            .expect("gpu generation")
                    })
                });
            }
        }
        group.finish();
    }
}

/// occlusion-slices on `foliage` (3000 quads under a rect light): slicing plus prefiltering per
/// resolution, every filter with 8 slices and N-Buffers with 16, CPU and GPU.
fn occlusion_slices_generation(c: &mut Criterion) {
    let gpu = GpuContext::new().ok();
    let spec = build("foliage").expect("catalogue scene");
    let geo = spec.to_scene().expect("scene").geometry();
    let mut set: Vec<OcclusionSlices> = SliceFilter::ALL
        .iter()
        .map(|&f| OcclusionSlices::new(8, f))
        .collect();
    set.push(OcclusionSlices::new(16, SliceFilter::NBuffer));
    for t in set {
        let mut group = c.benchmark_group(format!("occlusion-slices/foliage/{}", t.label()));
        group.sample_size(10);
        for res in RESOLUTIONS {
            group.bench_with_input(BenchmarkId::new("cpu", res), &res, |bch, &res| {
                bch.iter(|| {
                    t.generate(Backend::Cpu, None, &geo, &spec.light, res)
                        .expect("cpu generation")
                })
            });
            if let Some(g) = &gpu {
                group.bench_with_input(BenchmarkId::new("gpu", res), &res, |bch, &res| {
                    bch.iter(|| {
                        t.generate(Backend::Gpu, Some(g), &geo, &spec.light, res)
                            .expect("gpu generation")
                    })
                });
            }
        }
        group.finish();
    }
}

/// linear-light on `linear-bar`: the N depth maps, edge detection and skins per resolution and
/// per N (2, 3, 5), CPU and GPU.
fn linear_light_generation(c: &mut Criterion) {
    let gpu = GpuContext::new().ok();
    let spec = build("linear-bar").expect("catalogue scene");
    let geo = spec.to_scene().expect("scene").geometry();
    for t in LinearLight::standard_set() {
        let mut group = c.benchmark_group(format!("linear-light/linear-bar/{}", t.label()));
        group.sample_size(10);
        for res in RESOLUTIONS {
            group.bench_with_input(BenchmarkId::new("cpu", res), &res, |bch, &res| {
                bch.iter(|| {
                    t.generate(Backend::Cpu, None, &geo, &spec.light, res)
                        .expect("cpu generation")
                })
            });
            if let Some(g) = &gpu {
                group.bench_with_input(BenchmarkId::new("gpu", res), &res, |bch, &res| {
                    bch.iter(|| {
                        t.generate(Backend::Gpu, Some(g), &geo, &spec.light, res)
                            .expect("gpu generation")
                    })
                });
            }
        }
        group.finish();
    }
}

/// The frame pipeline on `harness::animated` (96² receivers, maps of 128): 100 frames, the box
/// moving for the first 50, with map caching and without (every light regenerated each frame).
fn frame_caching(c: &mut Criterion) {
    let mut group = c.benchmark_group("frame/animated-100");
    group.sample_size(10);
    for caching in [true, false] {
        let id = if caching { "cached" } else { "uncached" };
        group.bench_function(id, |bch| {
            bch.iter(|| {
                let mut lab = AnimatedScene::new(96, 128).expect("animated scene");
                lab.scene.world.insert_resource(FrameSettings { caching });
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

criterion_group!(
    benches,
    generation,
    shadow_width_generation,
    penumbra_limit_generation,
    occlusion_slices_generation,
    linear_light_generation,
    frame_caching
);
criterion_main!(benches);
