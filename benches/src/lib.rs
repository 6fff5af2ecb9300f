//! What the criterion benches in `generation.rs` and `evaluation.rs` share: the configurations
//! (every technique, variant and baseline the report runs, each on a scene whose light it
//! models), the GPU context, and timing GPU work by its device time.

use criterion::Bencher;
use harness::report::all_techniques;
use harness::scenes::SceneSpec;
use harness::scenes::catalogue::build;
use shadow_core::{DynTechnique, GpuContext, Result, SceneGeometry};
use std::time::{Duration, Instant};

/// Map resolutions of the generation benches.
pub const RESOLUTIONS: [u32; 5] = [128, 256, 512, 1024, 2048];

/// The scene a technique is benched on: `foliage` (3000 quads, rect light) for occlusion-slices,
/// `linear-bar` for linear-light, `torus` (sphere light) for the rest.
pub fn bench_scene(technique: &str) -> &'static str {
    match technique {
        "occlusion-slices" => "foliage",
        "linear-light" => "linear-bar",
        _ => "torus",
    }
}

/// One benched configuration: a technique variant and its scene.
pub struct Config {
    /// The technique.
    pub technique: Box<dyn DynTechnique>,
    /// Its scene.
    pub spec: SceneSpec,
    /// The scene's flattened geometry.
    pub geometry: SceneGeometry,
}

impl Config {
    /// `<technique>-<variant>`.
    pub fn label(&self) -> String {
        format!("{}-{}", self.technique.name(), self.technique.variant())
    }
}

/// Every technique, variant and baseline of the full report, on its bench scene.
pub fn configs() -> Vec<Config> {
    all_techniques(false)
        .into_iter()
        .map(|technique| {
            let spec = build(bench_scene(technique.name())).expect("catalogue scene");
            let geometry = spec.to_scene().expect("scene").geometry();
            Config {
                technique,
                spec,
                geometry,
            }
        })
        .collect()
}

/// The GPU context, or `None` after one line saying why the GPU benches are skipped.
pub fn gpu() -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(g) => {
            eprintln!(
                "GPU benches on {} (device time from timestamp queries: {})",
                g.describe(),
                if g.has_timestamps() { "yes" } else { "no" }
            );
            Some(g)
        }
        Err(e) => {
            eprintln!("GPU benches skipped: {e}");
            None
        }
    }
}

/// Benches `work` by the device time of its passes ([`GpuContext::gpu_time`]); the wall time of
/// an iteration stands in where the device gives no timestamps.
pub fn iter_device_time<T>(b: &mut Bencher, gpu: &GpuContext, mut work: impl FnMut() -> Result<T>) {
    b.iter_custom(|iters| {
        let mut total = Duration::ZERO;
        for _ in 0..iters {
            let start = Instant::now();
            let (out, device) = gpu.gpu_time(&mut work).expect("GPU work");
            total += device.unwrap_or_else(|| start.elapsed());
            drop(out);
        }
        total
    });
}
