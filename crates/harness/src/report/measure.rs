//! Timing one configuration: median generation and evaluation times and the last `V`.

use crate::metrics::median;
use crate::setup::PreparedScene;
use soft_shadow_core::gpu::GpuScene;
use soft_shadow_core::{Context, DynTechnique, Result};
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
    /// With a technique timed beside it: that technique's median generation and evaluation
    /// times, timed just before the configuration's.
    pub beside_ms: Option<(f64, f64)>,
}

/// One frame's three steps: `generate` maps, `evaluate` them, `recycle` them.
pub struct Frame<'a, M> {
    /// Generates the maps.
    pub generate: &'a dyn Fn() -> Result<M>,
    /// `V` per receiver from the maps.
    pub evaluate: &'a dyn Fn(&M) -> Result<Vec<f32>>,
    /// Gives the maps' storage back for the next frame.
    pub recycle: &'a dyn Fn(M),
}

impl<'a, M> Frame<'a, M> {
    /// The frame of the three steps `(generate, evaluate, recycle)`.
    pub fn of<G, E, R>((generate, evaluate, recycle): &'a (G, E, R)) -> Self
    where
        G: Fn() -> Result<M>,
        E: Fn(&M) -> Result<Vec<f32>>,
        R: Fn(M),
    {
        Frame {
            generate,
            evaluate,
            recycle,
        }
    }
}

/// Generates and evaluates `t` on `p` at `resolution`, `reps` times or until
/// [`REP_BUDGET_S`] is spent. On the GPU the scene is uploaded once, untimed
/// ([`GpuScene`]), and generation is timed from it. One unmeasured generation always comes
/// first: the configuration before may have left storage of other sizes in the pools, and a
/// first CPU generation that faults in fresh pages measured 3-8x its steady time
/// (occlusion-slices sat-8 on `torus` at 2048²: 152 ms, then 18-22 ms). With `warm_up` (a
/// technique's first GPU use) that run evaluates too: pipelines compile on first use and are
/// cached per device. Maps are recycled after each generation ([`soft_shadow_core::AnyMaps::recycle`]), so
/// every timed repetition reuses their textures and pages as a renderer's frames do.
///
/// With `beside` (the report passes the hard shadow map at the resolution of its cost table),
/// that technique is timed on the same scene, backend and resolution just before `t` (each
/// with its own unmeasured frame, each run after run): a ratio of the two is measured side by
/// side, not against a run timed minutes apart on a machine whose load moves.
#[allow(clippy::too_many_arguments)]
pub fn measure<'t>(
    t: &'t dyn DynTechnique,
    ctx: Context<'_>,
    p: &PreparedScene,
    resolution: u32,
    reps: usize,
    warm_up: bool,
    beside: Option<&'t dyn DynTechnique>,
) -> Result<Measured> {
    let light = &p.spec.light;
    let gpu = ctx.gpu();
    let scene = match gpu {
        Some(g) => Some((g, GpuScene::new(g, &p.geometry)?)),
        None => None,
    };
    let generate_with = |t: &dyn DynTechnique| match &scene {
        Some((g, s)) => t.generate_gpu_on(g, s, light, &p.views, resolution),
        None => t.generate_in(ctx, &p.geometry, light, &p.views, resolution),
    };
    // A technique's three steps, for its `Frame`.
    let steps = |t: &'t dyn DynTechnique| {
        (
            move || generate_with(t),
            move |maps: &soft_shadow_core::AnyMaps| maps.evaluate(gpu, &p.receivers()),
            move |maps: soft_shadow_core::AnyMaps| maps.recycle(gpu),
        )
    };
    let own = steps(t);
    let beside = beside.map(steps);
    repeat(
        Frame::of(&own),
        beside.as_ref().map(Frame::of),
        reps,
        warm_up,
    )
}

/// The timing loop of [`measure`] over `frame`'s three steps. One unmeasured generation comes
/// first (evaluated too when `warm_up`), then `reps` timed frames or as many as
/// [`REP_BUDGET_S`] allows; the times are their medians. With `beside`, the same loop runs over
/// its frames first (its unmeasured frame evaluated too: it may not have run on this backend
/// yet), just before `frame`'s: each technique is timed in its own steady state, run after run,
/// and the two within a second of each other.
pub fn repeat<M>(
    frame: Frame<'_, M>,
    beside: Option<Frame<'_, M>>,
    reps: usize,
    warm_up: bool,
) -> Result<Measured> {
    let beside_ms = match &beside {
        Some(b) => {
            let (g, e, _) = timed_loop(b, reps, true)?;
            Some((g, e))
        }
        None => None,
    };
    let (generate_ms, evaluate_ms, v) = timed_loop(&frame, reps, warm_up)?;
    Ok(Measured {
        generate_ms,
        evaluate_ms,
        v,
        beside_ms,
    })
}

/// [`repeat`]'s loop over one technique's frames: median generation and evaluation times (ms)
/// and the last frame's `V`.
fn timed_loop<M>(f: &Frame<'_, M>, reps: usize, warm_up: bool) -> Result<(f64, f64, Vec<f32>)> {
    // One unmeasured generation puts storage of this size in the pools; on a technique's first
    // GPU use its evaluation runs too, compiling its pipelines.
    let maps = (f.generate)()?;
    if warm_up {
        (f.evaluate)(&maps)?;
    }
    (f.recycle)(maps);
    let (mut gen_t, mut eval_t) = (Vec::new(), Vec::new());
    let start = Instant::now();
    let mut v = Vec::new();
    for _ in 0..reps.max(1) {
        let t0 = Instant::now();
        let maps = (f.generate)()?;
        let t1 = Instant::now();
        v = (f.evaluate)(&maps)?;
        let t2 = Instant::now();
        // The next repetition reuses the maps' storage, as a renderer's next frame does.
        (f.recycle)(maps);
        gen_t.push((t1 - t0).as_secs_f64() * 1e3);
        eval_t.push((t2 - t1).as_secs_f64() * 1e3);
        if start.elapsed().as_secs_f64() > REP_BUDGET_S {
            break;
        }
    }
    Ok((median(&gen_t), median(&eval_t), v))
}
