//! Generation cost per map resolution, CPU and GPU, for the baselines' depth maps
//! (one map for hard/PCF/PCSS, 16 for accumulation), on the `torus` and `bunny` scenes.
//!
//! `cargo bench -p shadow-benches`; GPU timings are submit-and-wait (the GPU path returns after
//! the device has finished). Without a GPU adapter the GPU group is skipped with a message.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use harness::baselines::{Filter, ShadowMapBaseline};
use harness::scenes::catalogue::build;
use shadow_core::{Backend, DynTechnique, GpuContext};

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

criterion_group!(benches, generation);
criterion_main!(benches);
