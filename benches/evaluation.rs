//! Evaluation cost per receiver for every technique, variant and baseline of the report: `V` for
//! the receivers of a 512² G-buffer of its bench scene, from maps of 1024², on the CPU, the GPU
//! by wall time (upload, dispatch, read back) and the GPU by device time (the evaluation pass,
//! from timestamp queries). Criterion prints the throughput in elements (receivers) per second:
//! the cost per million receivers is 10^6 divided by it.
//!
//! `cargo bench -p shadow-benches --bench evaluation [-- <regex>]`; see `benches/README.md`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use shadow_benches::{configs, gpu, iter_device_time, timing};
use soft_shadow_core::{Context, CpuContext, Receivers};
use soft_shadow_reference::scenes::scene_receivers;

/// G-buffer side: the receivers.
const SIZE: u32 = 512;
/// Map resolution the receivers are evaluated against.
const RESOLUTION: u32 = 1024;

fn evaluation(c: &mut Criterion) {
    let gpu = gpu();
    let cpu = CpuContext::new();
    for cfg in configs() {
        let (_, positions, normals) = scene_receivers(&cfg.spec, SIZE).expect("receivers");
        let recv = Receivers::new(&positions, &normals);
        let (t, geo, light) = (&cfg.technique, &cfg.geometry, &cfg.spec.light);
        let mut group = c.benchmark_group(format!("evaluate/{}/{}", cfg.spec.name, cfg.label()));
        timing(&mut group, 10);
        group.throughput(Throughput::Elements(positions.len() as u64));
        let maps = t
            .generate(Context::Cpu(&cpu), geo, light, RESOLUTION)
            .expect("cpu generation");
        group.bench_function("cpu", |b| {
            b.iter(|| maps.evaluate(None, &recv).expect("cpu evaluation"))
        });
        if let Some(g) = &gpu {
            let maps = t
                .generate(Context::Gpu(g), geo, light, RESOLUTION)
                .expect("gpu generation");
            group.bench_function("gpu-wall", |b| {
                b.iter(|| maps.evaluate(Some(g), &recv).expect("gpu evaluation"))
            });
            if g.has_timestamps() {
                group.bench_function("gpu-device", |b| {
                    iter_device_time(b, g, || maps.evaluate(Some(g), &recv))
                });
            }
        }
        group.finish();
    }
}

criterion_group!(benches, evaluation);
criterion_main!(benches);
