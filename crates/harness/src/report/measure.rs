//! Timing one configuration: median generation and evaluation times and the last `V`.

use crate::metrics::median;
use crate::setup::PreparedScene;
use shadow_core::gpu::GpuScene;
use shadow_core::{Backend, DynTechnique, GpuContext, Result};
use std::time::Instant;

/// Most repetitions of one configuration in the full run.
pub const MAX_REPS: usize = 3;
/// Most repetitions with `--quick`.
pub const QUICK_MAX_REPS: usize = 2;

/// No further repetition once a configuration has taken this long (seconds): slow
/// configurations are timed once, fast ones three times.
pub const REP_BUDGET_S: f64 = 0.4;

/// One configuration's timings (medians over the repetitions, ms) and visibilities.
pub struct Measured {
    /// Median generation time.
    pub generate_ms: f64,
    /// Median evaluation time.
    pub evaluate_ms: f64,
    /// `V` per receiver from the last repetition.
    pub v: Vec<f32>,
}

/// Generates and evaluates `t` on `p` at `res`, `reps` times or until
/// [`REP_BUDGET_S`] is spent. On the GPU the scene is uploaded once, untimed
/// ([`GpuScene`]), and generation is timed from it. One unmeasured generation always comes
/// first: the configuration before may have left storage of other sizes in the pools, and a
/// first CPU generation that faults in fresh pages measured 3-8x its steady time
/// (occlusion-slices sat-8 on `torus` at 2048²: 152 ms, then 18-22 ms). With `warm_up` (a
/// technique's first GPU use) that run evaluates too: pipelines compile on first use and are
/// cached per device. Maps are recycled after each generation ([`DynTechnique::recycle`]), so
/// every timed repetition reuses their textures and pages as a renderer's frames do.
pub fn measure(
    t: &dyn DynTechnique,
    backend: Backend,
    gpu: Option<&GpuContext>,
    p: &PreparedScene,
    res: u32,
    reps: usize,
    warm_up: bool,
) -> Result<Measured> {
    let light = &p.spec.light;
    let scene = match (backend, gpu) {
        (Backend::Gpu, Some(g)) => Some((g, GpuScene::new(g, &p.geometry)?)),
        _ => None,
    };
    let generate = || match &scene {
        Some((g, s)) => t.generate_gpu_on(g, s, light, res),
        None => t.generate(backend, gpu, &p.geometry, light, res),
    };
    repeat(
        generate,
        |maps| t.evaluate(gpu, maps, &p.receivers()),
        |maps| t.recycle(gpu, maps),
        reps,
        warm_up,
    )
}

/// The timing loop of [`measure`] over one frame's three steps: `generate` maps, `evaluate`
/// them, `recycle` them. One unmeasured generation comes first (evaluated too when `warm_up`),
/// then `reps` timed frames or as many as [`REP_BUDGET_S`] allows; the times are their medians.
pub fn repeat<M>(
    generate: impl Fn() -> Result<M>,
    evaluate: impl Fn(&M) -> Result<Vec<f32>>,
    recycle: impl Fn(M),
    reps: usize,
    warm_up: bool,
) -> Result<Measured> {
    // One unmeasured generation puts storage of this size in the pools; on a technique's first
    // GPU use its evaluation runs too, compiling its pipelines.
    let maps = generate()?;
    if warm_up {
        evaluate(&maps)?;
    }
    recycle(maps);
    let (mut gen_t, mut eval_t) = (Vec::new(), Vec::new());
    let start = Instant::now();
    let mut v = Vec::new();
    for _ in 0..reps.max(1) {
        let t0 = Instant::now();
        let maps = generate()?;
        let t1 = Instant::now();
        v = evaluate(&maps)?;
        let t2 = Instant::now();
        // The next repetition reuses the maps' storage, as a renderer's next frame does.
        recycle(maps);
        gen_t.push((t1 - t0).as_secs_f64() * 1e3);
        eval_t.push((t2 - t1).as_secs_f64() * 1e3);
        if start.elapsed().as_secs_f64() > REP_BUDGET_S {
            break;
        }
    }
    Ok(Measured {
        generate_ms: median(&gen_t),
        evaluate_ms: median(&eval_t),
        v,
    })
}
