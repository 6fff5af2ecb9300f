//! What the criterion benches in `generation.rs` and `evaluation.rs` share: the configurations
//! (every technique, variant and baseline the report runs, each on a scene whose light it
//! models), the GPU context, and timing GPU work by its device time.

use criterion::measurement::Measurement;
use criterion::{Bencher, BenchmarkGroup, SamplingMode};
use harness::report::all_techniques;
use soft_shadow_core::{GpuContext, Result, SceneGeometry};
use soft_shadow_reference::scenes::SceneSpec;
use soft_shadow_reference::scenes::catalogue::build;
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
    pub technique: soft_shadow_core::Technique,
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

/// Bytes [`iter_cold`] writes between iterations to evict the caches: four times the largest
/// last-level cache of the machines these benches run on (32 MiB).
pub const EVICT_BYTES: usize = 128 << 20;

/// Benches `work` from cold caches, as a frame meets a map it regenerates after the rest of the
/// frame's work: before each timed call, one byte of every cache line of `evict` is written
/// (untimed), so the call starts with none of its own data cached. `work`'s output is dropped
/// outside the timing.
pub fn iter_cold<T>(b: &mut Bencher, evict: &mut [u8], mut work: impl FnMut() -> T) {
    b.iter_custom(|iters| {
        let mut total = Duration::ZERO;
        for i in 0..iters {
            evict_caches(evict, i as u8);
            let start = Instant::now();
            let out = std::hint::black_box(work());
            total += start.elapsed();
            drop(out);
        }
        total
    });
}

/// Writes `mark` to the first byte of every 64-byte line of `evict`.
pub fn evict_caches(evict: &mut [u8], mark: u8) {
    evict.iter_mut().step_by(64).for_each(|x| *x = mark);
    std::hint::black_box(&evict);
}

/// The environment variable that shortens every bench: its value in seconds is each bench's
/// measurement time (a fifth of it the warm-up), with the same number of samples taken flat
/// (each of the same iteration count), so a bench whose iteration outlasts a sample runs about
/// `samples` iterations, not criterion's linear ramp's 55. `benches/device.sh` sets it to fit
/// a lent device's minutes; unset, the benches take the times below.
pub const SECONDS_VAR: &str = "SHADOW_BENCH_SECONDS";

/// Sets `group`'s timing: `samples` samples after 1 s of warm-up over 2 s of measurement, or
/// the times [`SECONDS_VAR`] asks for. One place for every bench group's times.
pub fn timing<M: Measurement>(group: &mut BenchmarkGroup<'_, M>, samples: usize) {
    group.sample_size(samples);
    let quick = std::env::var(SECONDS_VAR)
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s > 0.0);
    match quick {
        Some(s) => group
            .warm_up_time(Duration::from_secs_f64(0.2 * s))
            .measurement_time(Duration::from_secs_f64(s))
            .sampling_mode(SamplingMode::Flat),
        None => group
            .warm_up_time(Duration::from_secs(1))
            .measurement_time(Duration::from_secs(2)),
    };
}

#[cfg(test)]
mod tests {
    use std::path::Path;
    use std::process::Command;

    /// The eviction before a cold iteration writes every cache line of a buffer four times the
    /// 32 MiB last-level cache, so none of the bench's own data survives it.
    #[test]
    fn eviction_writes_every_line_of_four_caches() {
        const { assert!(super::EVICT_BYTES >= 4 * (32 << 20)) };
        let mut evict = vec![0u8; super::EVICT_BYTES];
        super::evict_caches(&mut evict, 7);
        assert!(evict.chunks(64).all(|line| line[0] == 7));
    }

    /// `benches/device.sh summary` reads each bench's median (the middle of criterion's
    /// `[low median high]`) from a run's files, not the `change:` block's percentages that a
    /// second run prints under the same name, whether criterion puts the name on the line of
    /// its time or above it; evaluation's throughput becomes milliseconds per million receivers
    /// and at 1080p, and the GPU goals are marked.
    #[test]
    fn device_summary_takes_each_benchs_median() {
        let dir = std::env::temp_dir().join(format!("device-summary-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let write = |name: &str, text: &str| std::fs::write(dir.join(name), text).unwrap();
        write("gpu.txt", "GPU 0: NVIDIA H200\n");
        write(
            "tests.txt",
            "test result: ok. 13 passed; 0 failed\nexit status 0\n",
        );
        write(
            "generation.txt",
            "GPU benches on NVIDIA H200 (Vulkan, DiscreteGpu) (device time from timestamp queries: yes)
Benchmarking generate/torus/pcf-r2/gpu-wall/2048: Analyzing
generate/torus/pcf-r2/gpu-wall/2048
                        time:   [1.9000 ms 2.0000 ms 2.1000 ms]
                 change:
                        time:   [-2.1% +0.4% +3.5%] (p = 0.80 > 0.05)
generate/torus/pcf-r2/gpu-device/2048
                        time:   [400.00 µs 500.00 µs 600.00 µs]
generate/foliage/occlusion-slices-sat-4/gpu-device/2048 time:   [1.0 s 1.5 s 2.0 s]
exit status 0
",
        );
        write(
            "evaluation.txt",
            "evaluate/torus/pcf-r2/gpu-device
                        time:   [0.9 ms 1.0 ms 1.1 ms]
                        thrpt:  [3.0 Gelem/s 4.0 Gelem/s 5.0 Gelem/s]
                 change:
                        time:   [-23.7% -14.2% -4.9%] (p = 0.01 < 0.05)
                        thrpt:  [+5.1% +16.6% +31.1%]
",
        );
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("device.sh");
        let out = Command::new("bash")
            .arg(&script)
            .arg("summary")
            .arg(&dir)
            .output()
            .expect("bash runs");
        let summary = String::from_utf8_lossy(&out.stdout).to_string();
        std::fs::remove_dir_all(&dir).ok();
        assert!(
            out.status.success(),
            "{summary}{}",
            String::from_utf8_lossy(&out.stderr)
        );
        for row in [
            "| torus,pcf-r2,2048 | 2 | 0.5 | yes |",
            "| foliage,occlusion-slices-sat-4,2048 |  | 1500 | no |",
            // 4 Gelem/s: 0.25 ms per million receivers, 0.5184 ms for 2,073,600.
            "| pcf-r2 | gpu-device | 0.25 | 0.5184 | no |",
        ] {
            assert!(summary.contains(row), "no row {row} in:\n{summary}");
        }
        assert!(
            summary.contains("NVIDIA H200 (Vulkan, DiscreteGpu)"),
            "{summary}"
        );
    }
}
