//! What the frames measure against what the profile predicts, on the machine that runs them.
//!
//! A [`crate::TechniqueProfile`] is fitted on one machine, from one scene per run; a frame runs
//! elsewhere, several lights at once, with cube faces and cascades. The pipeline keeps, in the
//! [`Calibration`] resource, how long the lights' generation and evaluation took against what
//! the profile predicted for them, and how long its own work took, and `Auto` and the shared
//! [`crate::FrameBudget`] scale every prediction by it: on a machine (or a backend, or a
//! scene) where the profile's predictions run short, the picks get cheaper within a few frames,
//! and where they run long, better.

use crate::stats::{FrameStats, LightStats};
use bevy_ecs::prelude::*;
use std::collections::{BTreeMap, VecDeque};

/// The frames whose measured-over-predicted ratios (and pipeline times) the calibration
/// holds: its factors are their medians, so one frame's jitter (a page fault, another process)
/// moves nothing, and a change of machine load shows within half of them.
pub const CALIBRATION_FRAMES: usize = 9;

/// The generations (one light's maps made, any configuration) whose measured-over-predicted
/// ratios [`Calibration::generate`] is the median of: a frame makes few maps, and one
/// configuration the profile misjudges (its own factor, [`Calibration::generate_for`]) must
/// not move every other's.
pub const CALIBRATION_GENERATIONS: usize = 16;

/// Until this many ratios are measured, the missing ones count as the prior (1 for
/// [`Calibration::generate`] and [`Calibration::evaluate`], `generate` for a configuration's
/// own factor): one slow first generation (a cold cache, a new configuration's first maps)
/// must not rescale the whole frame.
pub const CALIBRATION_MIN_SAMPLES: usize = 3;

/// A frame's ratio counts only where the predictions it compares add up to at least this many
/// milliseconds: a frame that made (or evaluated) next to nothing measures mostly its clock.
pub const CALIBRATION_MIN_MS: f64 = 0.1;

/// A frame's ratio is clamped to within this factor of 1 before it counts.
pub const CALIBRATION_MAX_FACTOR: f64 = 16.0;

/// [`CALIBRATION_MAX_FACTOR`] for the device times of a GPU frame
/// (the device times of [`crate::GpuTiming`]): a GPU may run the CPU profile's stand-in rows orders of
/// magnitude faster, and a software rasterizer slower.
pub const CALIBRATION_MAX_GPU_FACTOR: f64 = 16384.0;

/// A frame that measures its lights (a CPU frame, or a GPU frame read back or timed on the
/// device) in which the shared budget bought no light its maps measures no generation: it moves
/// every measured ratio (and every factor set by [`Calibration::new`] and not measured since)
/// this share of the way to 1, in log scale (the evaluation's not, where lights that keep their
/// maps measured it). A budget that a slow machine or device (or a heavy
/// view, or a hitch that inflated the factors) priced out thus buys the most valuable light its
/// cheapest shadow again within tens of frames, which measures it once more, and follows a
/// machine that got faster.
pub const CALIBRATION_RELAX: f64 = 1.0 / 32.0;

/// How the frames' measured times compare with the profile's predictions, kept by
/// [`crate::FramePipeline::run`] after every frame ([`Calibration::update`]): `Auto` and the
/// shared budget multiply a configuration's predicted generation by its
/// [`Calibration::generate_for`] and its evaluation by its [`Calibration::evaluate_for`] (before
/// its margin), and the shared budget
/// keeps [`Calibration::core_ms`] of the [`crate::FrameBudget`] for the pipeline's own work.
/// Remove or reset it to start again from the profile as fitted.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct Calibration {
    /// Measured over predicted generation time, the median over the last
    /// [`CALIBRATION_GENERATIONS`] lights that made their maps (1: as the profile predicts):
    /// the factor of a configuration that has made none yet.
    pub generate: f64,
    /// Measured over predicted evaluation time of the lights that evaluated, the median over
    /// the last [`CALIBRATION_FRAMES`] frames where they did.
    pub evaluate: f64,
    /// The pipeline's own time (tracking, sharing the budget, staleness;
    /// [`crate::FrameStats::core`]), the most of the last [`CALIBRATION_FRAMES`] frames,
    /// milliseconds.
    pub core_ms: f64,
    /// The last generations' ratios, and the last frames' evaluation ratios and pipeline
    /// times, the newest last.
    recent: [VecDeque<f64>; 3],
    /// Per configuration (`name variant`), the generation ratios of its last
    /// [`CALIBRATION_FRAMES`] generations.
    per_configuration: BTreeMap<String, VecDeque<f64>>,
    /// Per configuration, the evaluation ratios of its last [`CALIBRATION_FRAMES`] timed
    /// evaluations on the device ([`Calibration::evaluate_for`]).
    per_configuration_eval: BTreeMap<String, VecDeque<f64>>,
}

impl Default for Calibration {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// [`Calibration::IDENTITY`] as a place to borrow from.
pub(crate) static IDENTITY: Calibration = Calibration::IDENTITY;

impl Calibration {
    /// Nothing measured: the profile as fitted.
    pub const IDENTITY: Calibration = Calibration {
        generate: 1.0,
        evaluate: 1.0,
        core_ms: 0.0,
        recent: [VecDeque::new(), VecDeque::new(), VecDeque::new()],
        per_configuration: BTreeMap::new(),
        per_configuration_eval: BTreeMap::new(),
    };

    /// A calibration of these factors and pipeline time, as if measured: until frames are
    /// (with [`crate::FrameSettings::calibrating`] on), the picks follow it; measured frames
    /// then replace it.
    /// Factors are held to within [`CALIBRATION_MAX_FACTOR`] of 1, and the time to at least
    /// 0 (what is not a finite number counts as 1 and 0).
    pub fn new(generate: f64, evaluate: f64, core_ms: f64) -> Self {
        let factor = |x: f64| {
            if x.is_finite() {
                x.clamp(1.0 / CALIBRATION_MAX_FACTOR, CALIBRATION_MAX_FACTOR)
            } else {
                1.0
            }
        };
        Self {
            generate: factor(generate),
            evaluate: factor(evaluate),
            core_ms: if core_ms.is_finite() {
                core_ms.max(0.0)
            } else {
                0.0
            },
            ..Self::IDENTITY
        }
    }

    /// Takes in one frame's statistics: the lights that `Auto` or the shared budget chose
    /// ([`crate::LightStats::profile_ms`]) give a measured-over-predicted ratio for generation
    /// (those that made their maps; also per configuration, [`Calibration::generate_for`]) and
    /// for evaluation (those that evaluated), and the frame's pipeline time joins
    /// [`Calibration::core_ms`]'s window. The first frame is left out: it allocates every map
    /// and warms every cache. With `lights_timed` false (a GPU frame that reads nothing back,
    /// whose lights' times are only the recording of their work) the lights calibrate nothing.
    pub fn update(&mut self, stats: &FrameStats, lights_timed: bool) {
        if stats.frame <= 1 {
            return;
        }
        if lights_timed {
            self.take_lights(
                &stats.lights,
                CALIBRATION_MAX_FACTOR,
                CALIBRATION_MIN_MS,
                false,
            );
        }
        let core = stats.core.total_ms();
        if core.is_finite() {
            push(&mut self.recent[2], core, CALIBRATION_FRAMES);
        }
        self.core_ms = self.recent[2].iter().copied().fold(0.0, f64::max);
    }

    /// Takes in the device times of a GPU frame's lights ([`crate::gpu_timing`]), as
    /// [`Calibration::update`] takes a CPU frame's wall times: one frame's lines, measured in
    /// device milliseconds. The GPU stands in the CPU profile's rows where it has none, so its
    /// ratios may lie further from 1: each is clamped to within [`CALIBRATION_MAX_GPU_FACTOR`].
    /// Timestamps do not measure a clock's overhead, so a prediction under
    /// [`CALIBRATION_MIN_MS`] counts too; and each light's own time is its own, so its
    /// evaluation also calibrates its configuration's ([`Calibration::evaluate_for`]): on the
    /// device one technique's `V` pass may run far slower against its CPU row than another's.
    #[cfg_attr(not(feature = "gpu"), allow(dead_code))]
    pub(crate) fn update_gpu(&mut self, lights: &[LightStats]) {
        self.take_lights(lights, CALIBRATION_MAX_GPU_FACTOR, 0.0, true);
    }

    /// One frame's lights' measured-over-predicted ratios, each clamped to within `max` of 1,
    /// where the predictions compared add up to at least `min_ms`; with `own_evaluation`,
    /// each light's evaluation ratio also joins its configuration's.
    fn take_lights(&mut self, lights: &[LightStats], max: f64, min_ms: f64, own_evaluation: bool) {
        let ratio = |measured: f64, predicted: f64| {
            (predicted >= min_ms && predicted > 0.0 && measured > 0.0)
                .then(|| (measured / predicted).clamp(1.0 / max, max))
        };
        let mut generations = Vec::new();
        let (mut eval_measured, mut eval_predicted) = (0.0, 0.0);
        for l in lights {
            let Some([g, e]) = l.profile_ms else { continue };
            if l.views_generated > 0
                && let Some(r) = ratio(l.generate_ms, g)
            {
                generations.push(r);
                push(
                    self.per_configuration
                        .entry(l.technique.clone())
                        .or_default(),
                    r,
                    CALIBRATION_FRAMES,
                );
            }
            if l.receivers_evaluated > 0 {
                eval_measured += l.evaluate_ms;
                eval_predicted += e;
                if own_evaluation && let Some(r) = ratio(l.evaluate_ms, e) {
                    push(
                        self.per_configuration_eval
                            .entry(l.technique.clone())
                            .or_default(),
                        r,
                        CALIBRATION_FRAMES,
                    );
                }
            }
        }
        for r in generations {
            push(&mut self.recent[0], r, CALIBRATION_GENERATIONS);
        }
        if let Some(r) = ratio(eval_measured, eval_predicted) {
            push(&mut self.recent[1], r, CALIBRATION_FRAMES);
            if !own_evaluation {
                // Evaluations timed together again (the receivers evaluated, or the CPU): the
                // device's own factors no longer describe them.
                self.per_configuration_eval.clear();
            }
        }
        // Until a ratio is measured, a factor set by hand ([`Calibration::new`]) holds.
        if !self.recent[0].is_empty() {
            self.generate = median(&self.recent[0], 1.0);
        }
        if !self.recent[1].is_empty() {
            self.evaluate = median(&self.recent[1], 1.0);
        }
    }

    /// Moves every measured ratio [`CALIBRATION_RELAX`] of the way to 1 in log scale (a ratio
    /// `r` becomes `r^(1 - CALIBRATION_RELAX)`), the factors with them: what a measuring frame
    /// whose budget bought no light's maps does in place of a measurement of their generation.
    /// With `evaluation` false (the frame measured its lights' evaluations: lights that keep
    /// their maps, [`crate::LightShare::kept`]) the evaluation's ratios stay as measured.
    pub(crate) fn relax(&mut self, evaluation: bool) {
        let toward_one = |r: &mut f64| *r = r.powf(1.0 - CALIBRATION_RELAX);
        let windows = self.recent[..1 + evaluation as usize]
            .iter_mut()
            .chain(self.per_configuration.values_mut())
            .chain(
                self.per_configuration_eval
                    .values_mut()
                    .filter(|_| evaluation),
            );
        for w in windows {
            w.iter_mut().for_each(toward_one);
        }
        // A factor set without measurements ([`Calibration::new`]) relaxes itself.
        let factors = [&mut self.generate, &mut self.evaluate];
        for (factor, window) in factors
            .into_iter()
            .zip(&self.recent)
            .take(1 + evaluation as usize)
        {
            if window.is_empty() {
                toward_one(factor);
            } else {
                *factor = median(window, 1.0);
            }
        }
    }

    /// The factor on configuration `technique variant`'s predicted generation: the median of
    /// its last [`CALIBRATION_FRAMES`] generations' ratios (short of
    /// [`CALIBRATION_MIN_SAMPLES`], [`Calibration::generate`] stands in for the rest), and
    /// [`Calibration::generate`] for a configuration that has made none.
    pub fn generate_for(&self, technique: &str, variant: &str) -> f64 {
        self.per_configuration
            .get(&format!("{technique} {variant}"))
            .map_or(self.generate, |r| median(r, self.generate))
    }

    /// The factor on configuration `technique variant`'s predicted evaluation: the median of
    /// its last [`CALIBRATION_FRAMES`] evaluations timed on the device
    /// (by [`crate::GpuTiming`]; short of [`CALIBRATION_MIN_SAMPLES`],
    /// [`Calibration::evaluate`] stands in for the rest), and [`Calibration::evaluate`] for a
    /// configuration without (every configuration on the CPU, where one frame's evaluations
    /// are timed together).
    pub fn evaluate_for(&self, technique: &str, variant: &str) -> f64 {
        self.per_configuration_eval
            .get(&format!("{technique} {variant}"))
            .map_or(self.evaluate, |r| median(r, self.evaluate))
    }

    /// The largest factor by which a factor differs from `other`'s: `generate`, `evaluate`, or
    /// a configuration's own ([`Calibration::generate_for`], [`Calibration::evaluate_for`])
    /// that either has measured.
    pub fn drift(&self, other: &Calibration) -> f64 {
        let f = |a: f64, b: f64| (a / b).max(b / a);
        // The most a configuration's own factor drifted, over the configurations `ratios` of
        // either holds.
        let own = |ratios: fn(&Calibration) -> &BTreeMap<String, VecDeque<f64>>,
                   factor: fn(&Calibration, &str, &str) -> f64| {
            ratios(self)
                .keys()
                .chain(ratios(other).keys())
                .map(|k| {
                    let (t, v) = k.split_once(' ').unwrap_or((k, ""));
                    f(factor(self, t, v), factor(other, t, v))
                })
                .fold(1.0, f64::max)
        };
        f(self.generate, other.generate)
            .max(f(self.evaluate, other.evaluate))
            .max(own(|c| &c.per_configuration, Calibration::generate_for))
            .max(own(
                |c| &c.per_configuration_eval,
                Calibration::evaluate_for,
            ))
    }
}

/// The median of `v` (of the middle two, their geometric mean), `prior` standing in for the
/// values short of [`CALIBRATION_MIN_SAMPLES`].
fn median(v: &VecDeque<f64>, prior: f64) -> f64 {
    let mut v: Vec<f64> = v.iter().copied().collect();
    v.resize(v.len().max(CALIBRATION_MIN_SAMPLES), prior);
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] * v[n / 2]).sqrt()
    }
}

/// `x` at the end of `recent`, which keeps its last `n`.
fn push(recent: &mut VecDeque<f64>, x: f64, n: usize) {
    recent.push_back(x);
    while recent.len() > n {
        recent.pop_front();
    }
}
