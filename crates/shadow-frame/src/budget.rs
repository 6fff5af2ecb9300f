//! One frame budget shared among lights: every light whose choice is
//! [`TechniqueChoice::Shared`] gets a part of the [`FrameBudget`] that follows what it adds to
//! the image, and `Auto` picks its configuration within that part.
//!
//! A light's *contribution* is the unshadowed irradiance it brings the frame's receivers
//! ([`FrameReceivers`], what the camera sees) within its range, weighted by its
//! [`ShadowConfig::intensity`] ([`irradiance_estimate`]). The budget buys configurations as a
//! knapsack is filled: each light has a ladder of configurations worth buying (from the
//! [`crate::TechniqueProfile`], as `Auto` picks: the cheapest, then each one with a lower
//! predicted image error), and the budget buys, for each light, the rung (or no shadow) that
//! makes the lights' predicted image errors, each weighted by the light's part of the frame's
//! contribution, the least in sum ([`cheapest_error`], exact). No shadow costs what the light's own `V`
//! measured it missing while it had one ([`missing_shadow_255`]; a light whose shadow is
//! measured for the first time shares the budget again), and the catalogue's median,
//! [`NO_SHADOW_255`], before. A light that adds little gets a cheaper
//! configuration or a smaller map side, or no shadow where the milliseconds take more error off
//! on other lights (it says so). The picks' predicted times (with their margins, scaled by what the frames measured,
//! [`crate::Calibration`]) never add up to more than the budget less the pipeline's own time.
//! A light that brings nothing to any receiver (out of view, out of range, behind every
//! receiver) gets nothing and costs nothing: no maps, `V` = 1.
//!
//! Shares are kept while a light's proportional part stays within a factor
//! [`SHARE_HYSTERESIS`] of the one its pick was made for, or within [`SHARE_FLOOR`] of the
//! budget of it, so a camera that moves a little does
//! not make every light pick (and generate) again; a part that leaves that band, a changed
//! budget, a calibration that moved by more than the factor, or a light added, changed or
//! removed shares the whole budget again, and a light
//! keeps its configuration and its maps while it fits its new part and predicts no more than
//! [`KEEP_ERROR`] times the new pick's error. A pick measured over its part for
//! [`crate::tracking::STEP_DOWN_FRAMES`] frames steps down as `Auto` does.
//!
//! The configurations are bought at their full price, generation and evaluation, as if every
//! map were made again. A light whose maps stay as they are this frame (nothing that makes
//! them again changed) and that those prices would leave with no shadow, or with a
//! configuration at most [`KEEP_ERROR`] better than the one its maps hold, keeps its maps at
//! their evaluation's price where what the picks leave of the budget covers it
//! ([`LightShare::kept`], `hold_kept`), and what keeping saves buys the lights still without
//! a shadow; the first frame in which a kept light's maps must be made again (the light moved,
//! a caster in its range changed) shares the budget again, pricing it in full.

use crate::calibration::Calibration;
use crate::components::*;
use crate::scene::LightSource;
use crate::tracking::AutoInputs;
use bevy_ecs::prelude::*;
use glam::Vec3;
use soft_shadow_core::{Light, LightPoint};

/// The time one frame may spend on the shadows of the lights whose choice is
/// [`TechniqueChoice::Shared`] (generation + evaluation as the profile predicts them, scaled by
/// what the frames measured: [`crate::Calibration`]) and on the pipeline's own work (tracking,
/// sharing, staleness: the [`crate::Calibration::core_ms`] kept back, the most of the last
/// frames' [`crate::FrameStats::core`]), shared among the lights by what each adds to the image.
/// Lights with their own choice are outside it.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct FrameBudget {
    /// Milliseconds per frame.
    pub ms: f64,
}

/// A proportional share that moves by less than this factor (up or down) from the one the
/// budget was last shared with keeps every pick.
pub const SHARE_HYSTERESIS: f64 = 1.25;

/// A proportional share that moves by no more than this part of the budget keeps every pick,
/// whatever the factor, unless it starts or stops being 0 (a lamp the camera walks past, its part falling from 0.3 to 0.2 ms of
/// 16, buys nothing a re-share would change, and re-sharing costs the frame ~1.3 ms at 16
/// lamps).
pub const SHARE_FLOOR: f64 = 1.0 / 64.0;

/// When the budget is shared again, a light keeps its configuration (and its maps) while that
/// still fits its new part and its predicted image error is at most this factor over the new
/// pick's.
pub const KEEP_ERROR: f64 = 1.1;

/// The unshadowed irradiance `light` of `intensity` brings a receiver at `p` with unit normal
/// `n`, as engines weigh lights: a local light as a point of radiant intensity `intensity` at
/// its centre (`intensity cos / r²`, the distance kept at least the light's size so that a
/// receiver at the light does not dominate; a one-sided light also weighted by the cosine at its
/// emitting plane), a distant light as irradiance `intensity` at normal incidence
/// (`intensity cos`). 0 where the light does not reach `p` ([`Light::reaches_any`]).
pub fn irradiance_estimate(light: &Light, intensity: f32, p: Vec3, n: Vec3) -> f32 {
    if !light.reaches_any(p, n) {
        return 0.0;
    }
    match light.center() {
        LightPoint::Direction(d) => intensity * n.dot(d).max(0.0),
        LightPoint::Position(c) => {
            let d = c - p;
            let r2 = d
                .length_squared()
                .max(light.size() * light.size())
                .max(1e-6);
            let l = d / r2.sqrt();
            let at_light = light
                .front()
                .map_or(1.0, |(_, front)| (-front.normalize().dot(l)).max(0.0));
            intensity * n.dot(l).max(0.0) * at_light / r2
        }
    }
}

/// `light`'s contribution to the frame: [`irradiance_estimate`] summed over the frame's
/// receivers within its influence (at most [`RECEIVER_SAMPLES`] of them, evenly spread,
/// scaled back to the whole frame; every receiver where those samples read 0, so that a light
/// on a small patch is not taken for one that lights nothing).
pub fn contribution(light: &Light, config: &ShadowConfig, frame: &FrameReceivers) -> f64 {
    let n = frame.positions.len().min(frame.normals.len());
    if n == 0 {
        return 0.0;
    }
    let (c, r) = influence(light, config.range);
    let sum = |step: usize| -> f64 {
        (0..n)
            .step_by(step)
            .filter(|&i| !r.is_finite() || frame.positions[i].distance_squared(c) <= r * r)
            .map(|i| {
                f64::from(irradiance_estimate(
                    light,
                    config.intensity,
                    frame.positions[i],
                    frame.normals[i],
                ))
            })
            .sum::<f64>()
            * step as f64
    };
    let step = FrameReceivers::sample_step(n);
    match sum(step) {
        // A light that lights a patch the samples step over still counts: every receiver.
        0.0 if step > 1 => sum(1),
        s => s,
    }
}

/// What a shared light's shadow is worth to the frame, as the budget weighs it: its part of
/// the frame's light times the image error its missing shadow costs
/// ([`LightShare::missing_255`], [`NO_SHADOW_255`] before it is
/// measured). Where a frame runs over, the lights worth least wait first
/// ([`crate::deadline`]).
pub(crate) fn worth(state: &LightState) -> f64 {
    state.share.map_or(0.0, |s| {
        s.contribution * s.missing_255.unwrap_or(NO_SHADOW_255)
    })
}

/// The image error a light without a shadow is taken to cost, 1/255, until its own is measured
/// ([`missing_shadow_255`]): the median over the catalogue's scenes of the image error of
/// `V` = 1 against the reference (64² G-buffers: 14.85; 1.8 to 62 by scene).
pub const NO_SHADOW_255: f64 = 15.0;

/// The image error (1/255) `light` would have with no shadow, estimated from its `visibility`
/// over the frame's receivers (at most [`RECEIVER_SAMPLES`] of them, evenly spread): the rms of
/// `(1 - V) 255 w` over the receivers it lights within its influence, `w` its
/// [`irradiance_estimate`] over the largest (the report's image error, with `V` standing in for
/// the reference; every receiver where it lights none of those). Receivers whose `V` is not a
/// number are left out (a GPU frame's probe measures the sampled ones only). `None` where it
/// lights no receiver with a measurement or `visibility` is not the frame's.
pub fn missing_shadow_255(
    light: &Light,
    config: &ShadowConfig,
    frame: &FrameReceivers,
    visibility: &[f32],
) -> Option<f64> {
    let n = frame.positions.len().min(frame.normals.len());
    if n == 0 || visibility.len() != frame.positions.len() {
        return None;
    }
    let (c, r) = influence(light, config.range);
    let lit = |step: usize| -> Vec<(f64, f64)> {
        (0..n)
            .step_by(step)
            .filter(|&i| !r.is_finite() || frame.positions[i].distance_squared(c) <= r * r)
            .filter_map(|i| {
                let e = irradiance_estimate(
                    light,
                    config.intensity,
                    frame.positions[i],
                    frame.normals[i],
                );
                // A receiver without a measurement (NaN, a GPU probe's unsampled one) counts
                // for nothing.
                (e > 0.0 && visibility[i].is_finite())
                    .then(|| (f64::from(e), f64::from(1.0 - visibility[i])))
            })
            .collect()
    };
    let step = FrameReceivers::sample_step(n);
    let lit = match lit(step) {
        // A patch the samples step over: every receiver on it.
        l if l.is_empty() && step > 1 => lit(1),
        l => l,
    };
    let max = lit.iter().map(|p| p.0).fold(0.0, f64::max);
    if lit.is_empty() || max <= 0.0 {
        return None;
    }
    let sum: f64 = lit
        .iter()
        .map(|&(e, d)| (d * 255.0 * e / max).powi(2))
        .sum();
    Some((sum / lit.len() as f64).sqrt())
}

/// Whether a part `now` lies within [`SHARE_HYSTERESIS`] of the part `was`, either way.
fn in_band(now: f64, was: f64) -> bool {
    now <= was * SHARE_HYSTERESIS && now * SHARE_HYSTERESIS >= was
}

/// A shared light while the budget is shared.
pub(crate) struct Pick {
    pub(crate) entity: Entity,
    /// Its contribution.
    pub(crate) part: f64,
    pub(crate) kind: soft_shadow_core::LightKind,
    pub(crate) size: crate::SceneSize,
    pub(crate) proportional: f64,
    pub(crate) within: f64,
    /// The image error its missing shadow costs ([`LightShare::missing_255`], or the prior).
    pub(crate) missing: Option<f64>,
    /// Its cheapest configuration, `name variant side²`, and the budget it needs (with its
    /// margin), where it needs more than the whole frame budget.
    pub(crate) over_budget: Option<(String, f64)>,
    /// The budget its cheapest configuration within the frame budget needs and its predicted
    /// image error.
    pub(crate) cheapest: Option<(f64, f64)>,
    /// Its present pick (technique, variant, map side), where its maps are kept this frame
    /// ([`maps_kept`]).
    pub(crate) present: Option<(String, String, u32)>,
    /// Keeping that pick and its maps: the budget it needs for its evaluation alone
    /// ([`crate::profile::Pick::keeps_ms`]) and its predicted image error.
    pub(crate) keep: Option<(f64, f64)>,
    /// What the budget bought it at full price: the budget, the predicted image error, and
    /// whether it is its present pick.
    pub(crate) bought: Option<(f64, f64, bool)>,
    /// Whether it keeps its present pick and maps at their evaluation's price ([`hold_kept`]).
    pub(crate) keeps: bool,
}

/// The lights [`share_budget`] reads and updates.
type SharedLights<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        Ref<'static, LightSource>,
        Ref<'static, ShadowConfig>,
        Option<&'static ResolvedTechnique>,
        &'static mut LightState,
    ),
>;

/// Shares the [`FrameBudget`] among the lights whose choice is [`TechniqueChoice::Shared`] and
/// picks each one's configuration within its part (see the module's doc): runs after
/// [`crate::tracking::resolve_techniques`], which leaves shared lights to it.
#[allow(clippy::too_many_arguments)]
pub fn share_budget(
    mut commands: Commands,
    budget: Option<Res<FrameBudget>>,
    mut lights: SharedLights,
    mut removed: RemovedComponents<ShadowConfig>,
    inputs: AutoInputs,
    settings: Res<FrameSettings>,
    mut shared_with: Local<Option<Calibration>>,
    mut last_receivers: Local<Option<u64>>,
) {
    let frame = &inputs.frame;
    // Whether the receivers moved since the last frame, whose lights' `V` are over them.
    let receivers = fingerprint(frame);
    let receivers_moved = *last_receivers != Some(receivers);
    *last_receivers = Some(receivers);
    let config_removed = removed.read().count() > 0;
    let Some(budget) = budget else {
        for (e, l, config, _, mut state) in &mut lights {
            if config.shares_budget(&l.0) && (state.share.is_some() || state.error.is_none()) {
                state.error = Some(
                    "a shared choice takes its part of the FrameBudget resource, and the world \
                     holds none"
                        .into(),
                );
                state.share = None;
                state.maps = None;
                commands.entity(e).remove::<ResolvedTechnique>();
            }
        }
        return;
    };
    let idle_visibility = |state: &mut LightState| {
        let n = if settings.evaluate_receivers {
            frame.positions.len()
        } else {
            0
        };
        if state.visibility.len() != n || state.visibility.iter().any(|&v| v != 1.0) {
            state.visibility = vec![1.0; n];
        }
        state.evaluated = 0;
    };
    // A light that left the share (another choice, or zero size) hands its part back.
    let mut left_share = false;
    for (_, l, c, _, mut s) in &mut lights {
        if s.share.is_some() && !c.shares_budget(&l.0) {
            s.share = None;
            left_share = true;
        }
    }
    // A changed config (or a new light) shares again; a light that only moved keeps its pick
    // unless its part drifts out of the band (it makes its maps again all the same).
    let changed_config = left_share
        || lights
            .iter()
            .any(|(_, l, c, ..)| c.shares_budget(&l.0) && c.is_changed());
    let moved = lights
        .iter()
        .any(|(_, l, c, ..)| c.shares_budget(&l.0) && l.is_changed());
    // What the frames measured moved since the last share: a factor that grew or shrank by
    // more than the hysteresis. (The pipeline's own time is taken as it is at the next share:
    // a share's own cost would share again.)
    let calibration = inputs.calibration();
    let recalibrated = shared_with
        .as_ref()
        .is_some_and(|w| calibration.drift(w) > SHARE_HYSTERESIS)
        || lights.iter().any(|(e, l, c, _, s)| {
            // A light whose shadow can now be measured for the first time (from its `V`, or
            // from a GPU frame's probe of it).
            c.shares_budget(&l.0)
                && (unmeasured(s, settings.evaluate_receivers, receivers_moved)
                    || (probed_shadow(s, inputs.probed(e, receivers))
                        && s.share.is_some_and(|sh| sh.missing_255.is_none())))
        });
    // A light the last share priced at its evaluation alone whose maps must be made again
    // this frame: it is priced in full.
    let kept_remade = lights.iter().any(|(_, l, c, r, s)| {
        c.shares_budget(&l.0)
            && s.share.is_some_and(|sh| sh.kept)
            && !maps_kept((&l, &c, r, s), &inputs, &settings)
    });
    if !(budget.is_changed()
        || frame.is_changed()
        || changed_config
        || moved
        || config_removed
        || recalibrated
        || kept_remade
        || inputs.texels_changed()
        || settings.is_changed())
    {
        return;
    }
    // What the lights share: the budget less the pipeline's own time.
    let available = (budget.ms - calibration.core_ms).max(0.0);
    let frame_ms = if calibration.core_ms > 0.0 {
        format!(
            "{} ms (less {:.2} ms for the pipeline's own work)",
            budget.ms, calibration.core_ms
        )
    } else {
        format!("{} ms", budget.ms)
    };
    // The receivers' bounds: a light whose influence misses them brings nothing, unread.
    let mut seen = soft_shadow_core::mesh::Aabb::EMPTY;
    frame.positions.iter().for_each(|p| seen.grow(*p));
    // Each shared light's contribution, the lights in parallel.
    let shared: Vec<(Entity, &Light, &ShadowConfig)> = lights
        .iter()
        .filter(|(_, l, c, ..)| c.shares_budget(&l.0))
        .map(|(e, l, c, ..)| (e, &l.into_inner().0, c.into_inner()))
        .collect();
    let parts: Vec<(Entity, f64)> = {
        use rayon::prelude::*;
        shared
            .par_iter()
            .map(|&(e, l, c)| {
                let (centre, r) = influence(l, c.range);
                let near = !seen.is_empty() && box_in_sphere(&seen, centre, r);
                (e, if near { contribution(l, c, frame) } else { 0.0 })
            })
            .collect()
    };
    let total: f64 = parts.iter().map(|p| p.1).sum();
    let part = |e: Entity| parts.iter().find(|p| p.0 == e).map_or(0.0, |p| p.1);
    let fraction = |e: Entity| {
        if total > 0.0 { part(e) / total } else { 0.0 }
    };
    // Whether every share must be made again: anything but the receivers changed, or some
    // light's proportional share left its band (or it started or stopped contributing).
    let drifted = lights.iter().any(|(e, l, c, _, s)| {
        if !c.shares_budget(&l.0) {
            return false;
        }
        let now = available * fraction(e);
        match s.share {
            None => true,
            Some(sh) => {
                // A light that starts or stops bringing anything shares again, however
                // little: one that stopped must cost nothing.
                let started_or_stopped = (now > 0.0) != (sh.proportional_ms > 0.0);
                started_or_stopped
                    || (!in_band(now, sh.proportional_ms)
                        && (now - sh.proportional_ms).abs() > budget.ms * SHARE_FLOOR)
            }
        }
    });
    // What the predictions count changed: the texels `V` is recorded over, or whether the
    // receivers are evaluated.
    let texels = inputs.texels_changed() || settings.is_changed();
    if !(budget.is_changed()
        || changed_config
        || config_removed
        || drifted
        || recalibrated
        || kept_remade
        || texels)
    {
        for (e, l, c, _, mut s) in &mut lights {
            if !c.shares_budget(&l.0) {
                continue;
            }
            if let Some(sh) = s.share.as_mut() {
                sh.contribution = fraction(e);
            }
            if s.share.is_some_and(|sh| sh.budget_ms == 0.0) {
                idle_visibility(&mut s);
            }
        }
        return;
    }
    *shared_with = Some(calibration.clone());
    // The lights that bring something, sized in parallel.
    // Each one's missing shadow: measured from its `V` where it has a shadow now and the
    // receivers are those its `V` was evaluated on (a camera holding still), kept from the last
    // share while its part stays within the band and no caster changed in its range, the
    // prior otherwise.
    #[allow(clippy::type_complexity)]
    let bringing: Vec<(
        Entity,
        &Light,
        f32,
        Option<f64>,
        Option<(String, String, u32)>,
    )> = lights
        .iter()
        .filter(|(e, l, c, ..)| c.shares_budget(&l.0) && part(*e) > 0.0)
        .map(|(e, l, c, r, s)| {
            // Its present pick, where its maps are kept this frame.
            let present = r
                .filter(|&r| maps_kept((&l, &c, Some(r), s), &inputs, &settings))
                .map(|r| {
                    (
                        r.technique.name().to_string(),
                        r.technique.variant().to_string(),
                        r.resolution,
                    )
                });
            let kept = s.share.and_then(|sh| {
                let within = in_band(available * fraction(e), sh.proportional_ms);
                sh.missing_255.filter(|_| within)
            });
            // Its `V` over the frame's receivers: its own where it evaluated them, else a GPU
            // frame's probe of it at the sampled ones.
            let probed = inputs.probed(e, receivers);
            let visibility = if measurable(s, settings.evaluate_receivers, receivers_moved) {
                Some(s.visibility.as_slice())
            } else {
                probed.filter(|_| probed_shadow(s, probed))
            };
            let missing = if let Some(visibility) = visibility {
                // The one the last share took while the measurement stays within the band of
                // it: a shadow that changes a little does not move the shares.
                let now = missing_shadow_255(&l.0, &c, frame, visibility).unwrap_or(NO_SHADOW_255);
                match kept {
                    Some(was) if in_band(now.max(1.0), was.max(1.0)) => Some(was),
                    _ => Some(now),
                }
            } else {
                kept
            };
            (e, &l.into_inner().0, c.range, missing, present)
        })
        .collect();
    let sizes: Vec<crate::SceneSize> = {
        use rayon::prelude::*;
        bringing
            .par_iter()
            .map(|(_, l, range, ..)| inputs.size(l, *range))
            .collect()
    };
    let mut picks: Vec<Pick> = bringing
        .iter()
        .zip(sizes)
        .map(|((e, l, _, missing, present), size)| Pick {
            entity: *e,
            part: part(*e),
            kind: l.kind(),
            size,
            proportional: available * fraction(*e),
            within: 0.0,
            missing: *missing,
            over_budget: None,
            cheapest: None,
            present: present.clone(),
            keep: None,
            bought: None,
            keeps: false,
        })
        .collect();
    // Each light's configurations worth buying, cheapest first: every pick `Auto` makes at
    // some budget, with the budget it needs.
    // (With, for each rung, whether it is the light's present pick.)
    #[allow(clippy::type_complexity)]
    let (rungs, presents): (Vec<Vec<(f64, f64)>>, Vec<Vec<bool>>) = picks
        .iter_mut()
        .map(|p| {
            let frontier = inputs.frontier(p.kind, p.size);
            p.over_budget = frontier
                .first()
                .filter(|o| o.needs_ms() > available)
                .map(|o| {
                    (
                        format!(
                            "{} {} {}²",
                            o.entry.technique, o.entry.variant, o.resolution
                        ),
                        o.needs_ms(),
                    )
                });
            let is_present = |o: &crate::profile::Pick| {
                p.present.as_ref().is_some_and(|(t, v, side)| {
                    o.entry.technique == *t && o.entry.variant == *v && o.resolution == *side
                })
            };
            let (ladder, present): (Vec<(f64, f64)>, Vec<bool>) = frontier
                .iter()
                .filter(|o| o.needs_ms() <= available)
                .map(|o| ((o.needs_ms(), o.error_255), is_present(o)))
                .unzip();
            p.cheapest = ladder.first().copied();
            // Keeping its present pick and maps costs the frame their evaluation alone.
            p.keep = p.present.as_ref().and_then(|_| {
                inputs
                    .options(p.kind, p.size)
                    .into_iter()
                    .find(is_present)
                    .map(|o| (o.keeps_ms(), o.error_255))
            });
            (ladder, present)
        })
        .unzip();
    // The configurations bought: the least image error, weighted by what each light brings,
    // the budget can buy.
    let weights: Vec<(f64, f64)> = picks
        .iter()
        .map(|p| (p.part, p.missing.unwrap_or(NO_SHADOW_255)))
        .collect();
    let at = cheapest_error(&rungs, &weights, available);
    for (i, k) in at.into_iter().enumerate() {
        let p = &mut picks[i];
        p.bought = k.map(|k| (rungs[i][k].0, rungs[i][k].1, presents[i][k]));
        p.within = p.bought.map_or(0.0, |b| b.0);
    }
    let spare = hold_kept(&mut picks, available);
    // What keeping saves buys the lights left with nothing their shadows, at full price.
    let idle: Vec<usize> = (0..picks.len())
        .filter(|&i| picks[i].bought.is_none() && !picks[i].keeps)
        .collect();
    if spare > 0.0 && !idle.is_empty() {
        let idle_rungs: Vec<Vec<(f64, f64)>> = idle.iter().map(|&i| rungs[i].clone()).collect();
        let idle_weights: Vec<(f64, f64)> = idle.iter().map(|&i| weights[i]).collect();
        let at = cheapest_error(&idle_rungs, &idle_weights, spare);
        for (&i, k) in idle.iter().zip(at) {
            if let Some(k) = k {
                picks[i].bought = Some((rungs[i][k].0, rungs[i][k].1, presents[i][k]));
                picks[i].within = rungs[i][k].0;
            }
        }
    }
    for (e, l, c, resolved, mut state) in &mut lights {
        if !c.shares_budget(&l.0) {
            continue;
        }
        let Some(&Pick {
            kind,
            size,
            proportional,
            within,
            missing,
            ref over_budget,
            cheapest,
            keeps,
            ..
        }) = picks.iter().find(|p| p.entity == e)
        else {
            commands.entity(e).remove::<ResolvedTechnique>();
            state.maps = None;
            state.stale = false;
            state.error = None;
            state.share = Some(LightShare {
                contribution: 0.0,
                proportional_ms: 0.0,
                budget_ms: 0.0,
                missing_255: None,
                kept: false,
            });
            idle_visibility(&mut state);
            continue;
        };
        state.share = Some(LightShare {
            contribution: fraction(e),
            proportional_ms: proportional,
            budget_ms: within,
            missing_255: missing,
            kept: keeps,
        });
        // The present pick stays while it fits the new part and is nearly as good as the new
        // pick: its maps are kept.
        let proposed = inputs.pick(kind, within, size);
        let proposed_error = proposed.as_ref().and_then(|p| p.auto).map(|a| a.error_255);
        // The present pick, predicted again for the scene as it is now.
        let kept = resolved.and_then(|r| {
            let o = inputs.options(kind, size).into_iter().find(|o| {
                o.entry.technique == r.technique.name()
                    && o.entry.variant == r.technique.variant()
                    && o.resolution == r.resolution
            })?;
            // Bought at its evaluation's price, or in full where it fits and is nearly as good.
            let fits = keeps
                || (o.needs_ms() <= within
                    && proposed_error.is_some_and(|b| o.error_255 <= b * KEEP_ERROR));
            fits.then(|| {
                let mut r = r.clone();
                if let Some(a) = r.auto.as_mut() {
                    (a.time_ms, a.profile_ms, a.error_255) = (o.time_ms, o.profile_ms, o.error_255);
                    if keeps {
                        // What this frame spends on it: its evaluation.
                        (a.time_ms, a.frames_over) = (o.evaluate_ms, 0);
                    }
                }
                r
            })
        });
        match kept.or(proposed) {
            Some(mut next) => {
                let why = next
                    .reason
                    .split_once("; ")
                    .map_or(next.reason.as_str(), |w| w.1);
                next.reason = format!(
                    "shared: {:.1}% of the frame's light, {within:.2} of the frame's {frame_ms}{}; \
                     {}",
                    100.0 * fraction(e),
                    if keeps {
                        " for its evaluation, its maps kept"
                    } else {
                        ""
                    },
                    why.trim_start_matches("auto: ")
                );
                if let Some(a) = next.auto.as_mut() {
                    a.budget_ms = within;
                }
                let same = resolved.is_some_and(|r| {
                    r.technique.name() == next.technique.name()
                        && r.technique.variant() == next.technique.variant()
                        && r.resolution == next.resolution
                });
                if !same {
                    state.stale = true;
                    state.maps = None;
                }
                state.error = None;
                commands.entity(e).insert(next);
            }
            None if within == 0.0 => {
                commands.entity(e).remove::<ResolvedTechnique>();
                state.maps = None;
                idle_visibility(&mut state);
                state.error = Some(match over_budget {
                    Some((cheapest, needs)) => format!(
                        "its cheapest configuration, {cheapest}, is predicted to need \
                         {needs:.2} ms with its margin, over the frame's whole {frame_ms} \
                         ({:.2}% of the frame's light; {} triangles in {} views, {} receivers)",
                        100.0 * fraction(e),
                        size.triangles,
                        size.views,
                        size.receivers
                    ),
                    None => {
                        let none = missing.unwrap_or(NO_SHADOW_255);
                        match cheapest {
                            Some((_, error)) if error >= none => format!(
                                "its missing shadow costs {none:.2}/255 of image error, no more \
                                 than its cheapest configuration is predicted to leave \
                                 ({error:.2}; {:.2}% of the frame's light)",
                                100.0 * fraction(e)
                            ),
                            Some((needs, _)) => format!(
                                "the frame's {frame_ms} take more image error off on the other \
                                 lights than on this one's cheapest configuration ({needs:.2} \
                                 ms with its margin; {:.2}% of the frame's light)",
                                100.0 * fraction(e)
                            ),
                            None => format!(
                                "no configuration fits the frame's {frame_ms} ({:.2}% of the \
                                 frame's light)",
                                100.0 * fraction(e)
                            ),
                        }
                    }
                });
            }
            None => {
                commands.entity(e).remove::<ResolvedTechnique>();
                state.maps = None;
                idle_visibility(&mut state);
                state.error = Some(format!(
                    "no configuration for {} lights on {} is predicted to fit its {within:.2} ms \
                     of the frame's {frame_ms} ({:.1}% of the frame's light; {} triangles, {} \
                     receivers)",
                    kind.name(),
                    inputs.backend.backend.name(),
                    100.0 * fraction(e),
                    size.triangles,
                    size.receivers
                ));
            }
        }
    }
}

/// Where the configurations bought at full price ([`cheapest_error`]) would make a light
/// whose maps are kept this frame ([`maps_kept`]) lose them, the light keeps its present pick
/// and maps at their evaluation's price ([`crate::profile::Pick::keeps_ms`]), what a frame
/// that does not make them spends. (A light bought its present pick at full price keeps its
/// maps at that price.) First, a light bought another configuration that
/// predicts no less than its present pick's image error over [`KEEP_ERROR`], for no less than
/// keeping it needs, keeps it instead. Then the lights bought nothing keep theirs, worth most
/// first ([`worth`]), each where what the picks leave of the budget covers its evaluation and
/// their shadow is predicted to take error off. Returns what is left of the budget, which
/// [`share_budget`] spends on the lights still without a shadow, at full price. The
/// configurations bought first do not depend on what is kept: when a kept light must make its
/// maps again (it moved), the next share prices it in full and buys the rest as before, and
/// what it takes back costs only lights kept or bought with what keeping saved. (Keeping as a
/// rung of each light's ladder would buy the least error for one frame, and would let a kept
/// light's next move take back the maps of any light.)
pub(crate) fn hold_kept(picks: &mut [Pick], available: f64) -> f64 {
    let mut spare = available - picks.iter().map(|p| p.within).sum::<f64>();
    for p in picks.iter_mut() {
        if let (Some((keeps_ms, kept)), Some((ms, error, false))) = (p.keep, p.bought)
            && kept <= error * KEEP_ERROR
            && keeps_ms <= ms
        {
            spare += ms - keeps_ms;
            (p.within, p.keeps) = (keeps_ms, true);
        }
    }
    let worth = |p: &Pick| p.part * p.missing.unwrap_or(NO_SHADOW_255);
    let mut waiting: Vec<usize> = (0..picks.len())
        .filter(|&i| picks[i].bought.is_none() && picks[i].keep.is_some())
        .collect();
    waiting.sort_by(|&a, &b| worth(&picks[b]).total_cmp(&worth(&picks[a])));
    for i in waiting {
        let p = &mut picks[i];
        if let Some((keeps_ms, kept)) = p.keep
            && keeps_ms <= spare
            && kept < p.missing.unwrap_or(NO_SHADOW_255)
        {
            spare -= keeps_ms;
            (p.within, p.keeps) = (keeps_ms, true);
        }
    }
    spare
}

/// Steps the budget is divided into when [`cheapest_error`] buys configurations.
pub const BUDGET_STEPS: usize = 1024;

/// Whether the shared budget bought no light its maps at their full price while a light that
/// lights something in view has none: a frame that measures no generation, after which a
/// measuring frame relaxes the calibration ([`crate::Calibration::relax`]) rather than hold
/// the factors that priced it out. (A light whose maps wait a frame, [`crate::deadline`], was
/// not priced out; one that keeps its maps at its evaluation's price, [`LightShare::kept`],
/// was not bought them, and measures no generation either.)
pub(crate) fn priced_out(world: &mut World) -> bool {
    let waiting = world
        .get_resource::<crate::deadline::Deadline>()
        .map(|d| d.waiting().to_vec())
        .unwrap_or_default();
    let mut states = world.query::<(Entity, &LightState)>();
    let (mut bought, mut wanted) = (false, false);
    for (e, s) in states.iter(world) {
        let Some(share) = s.share else { continue };
        let waits = waiting.contains(&e);
        bought |= (s.maps.is_some() && !share.kept) || waits;
        wanted |= share.contribution > 0.0 && s.maps.is_none() && !waits;
    }
    !bought && wanted
}

/// The configurations a budget of `available` ms buys: for light `i`, a rung of `ladders[i]`
/// (`(ms, image error)`) or none (`None`), so that the lights' summed image error, each
/// weighted by its part (`weights[i]`: part, and the error it has with no shadow), is the least
/// any choice within the budget gives. Solved exactly as a multiple-choice knapsack over the
/// budget in [`BUDGET_STEPS`] steps, each rung's time rounded up to a whole step: the times
/// bought add up to no more than `available`, and a choice that fits only without the rounding
/// (within a step a light) is not seen. A light whose part is not a finite non-negative number,
/// or a rung whose time or error is not finite, buys nothing; an error with no shadow that is
/// not finite counts as [`NO_SHADOW_255`]. (A greedy by error taken off per millisecond can
/// spend a light's upgrades where the same milliseconds would have given a second light its
/// first shadow: the room at 16 ms gave its table lamp 15.4 ms and its ceiling panel, 45% of
/// the light, nothing.)
pub fn cheapest_error(
    ladders: &[Vec<(f64, f64)>],
    weights: &[(f64, f64)],
    available: f64,
) -> Vec<Option<usize>> {
    debug_assert_eq!(ladders.len(), weights.len());
    let n = ladders.len().min(weights.len());
    if !(available.is_finite() && available > 0.0) {
        return vec![None; ladders.len()];
    }
    let step = available / BUDGET_STEPS as f64;
    let steps = |ms: f64| (ms / step - 1e-9).ceil().max(0.0) as usize;
    // best[b]: the least weighted error of the lights so far within b steps; chose[i][b]: light
    // i's rung there (its index in the ladder), if any.
    let mut best = vec![0.0f64; BUDGET_STEPS + 1];
    let mut chose: Vec<Vec<Option<usize>>> = Vec::with_capacity(n);
    for i in 0..n {
        let (part, none) = weights[i];
        let part = if part.is_finite() { part.max(0.0) } else { 0.0 };
        let none = if none.is_finite() {
            none
        } else {
            NO_SHADOW_255
        };
        // (ladder index, steps, weighted error) of the rungs that can be bought.
        let rungs: Vec<(usize, usize, f64)> = ladders[i]
            .iter()
            .enumerate()
            .filter(|(_, (ms, e))| ms.is_finite() && *ms >= 0.0 && e.is_finite())
            .map(|(k, &(ms, e))| (k, steps(ms), part * e))
            .filter(|&(_, w, _)| w <= BUDGET_STEPS)
            .collect();
        let mut next = vec![f64::INFINITY; BUDGET_STEPS + 1];
        let mut pick = vec![None; BUDGET_STEPS + 1];
        for b in 0..=BUDGET_STEPS {
            let mut v = best[b] + part * none;
            let mut k = None;
            for &(j, w, e) in &rungs {
                if w <= b && best[b - w] + e < v {
                    v = best[b - w] + e;
                    k = Some(j);
                }
            }
            next[b] = v;
            pick[b] = k;
        }
        best = next;
        chose.push(pick);
    }
    // Back from the whole budget.
    let mut at = vec![None; ladders.len()];
    let mut b = BUDGET_STEPS;
    for i in (0..n).rev() {
        if let Some(k) = chose[i][b] {
            at[i] = Some(k);
            b -= steps(ladders[i][k].0);
        }
    }
    at
}

/// The frame's receivers in one number: their count and 64 of them, evenly spread, hashed
/// bit for bit (a renderer that sets the same G-buffer again gives the same number).
pub(crate) fn fingerprint(frame: &FrameReceivers) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    let n = frame.positions.len();
    n.hash(&mut h);
    for i in (0..n).step_by(n.div_ceil(64).max(1)) {
        frame.positions[i].to_array().map(f32::to_bits).hash(&mut h);
        if let Some(m) = frame.normals.get(i) {
            m.to_array().map(f32::to_bits).hash(&mut h);
        }
    }
    h.finish()
}

/// Whether a shared light's maps are kept this frame, so that its present pick costs the frame
/// its evaluation alone: it has maps, made for its present pick, and nothing makes them again
/// this frame: not the light or its config, not the frame's backend, not a caster change as
/// [`crate::tracking::mark_stale`] will judge it after the share, with caching on.
/// A distant light whose receivers moved is taken to make its cascades again (they follow
/// the camera and may make none: the share does not plan them).
fn maps_kept(
    (light, config, resolved, state): (
        &Ref<LightSource>,
        &Ref<ShadowConfig>,
        Option<&ResolvedTechnique>,
        &LightState,
    ),
    inputs: &AutoInputs,
    settings: &Res<FrameSettings>,
) -> bool {
    let distant = matches!(light.0.center(), LightPoint::Direction(_));
    resolved.is_some()
        && state.maps.is_some()
        && !state.stale
        && state.error.is_none()
        && settings.caching
        && !inputs.backend.is_changed()
        && !light.is_changed()
        && !config.is_changed()
        && !(distant && (inputs.frame.is_changed() || settings.is_changed()))
        && !inputs.casters_remake((&light.0, config.range), &state.unseen_changes, settings)
}

/// Whether a light's missing shadow can be measured from its `V`: it has maps and, with the
/// frame's receivers evaluated, a `V` for each of them as they are (`moved`: the receivers
/// changed since its `V` was evaluated).
fn measurable(state: &LightState, evaluated: bool, moved: bool) -> bool {
    evaluated && !moved && state.maps.is_some() && state.error.is_none() && state.evaluated > 0
}

/// Whether a light's shadow can be measured from a GPU frame's probe of its `V` (`probed`,
/// for the frame's receivers as they are): it has maps and the probe holds it.
fn probed_shadow(state: &LightState, probed: Option<&[f32]>) -> bool {
    probed.is_some() && state.maps.is_some() && state.error.is_none()
}

/// Whether a shared light has a shadow whose cost can be measured, and the budget was last
/// shared without it.
fn unmeasured(state: &LightState, evaluated: bool, moved: bool) -> bool {
    measurable(state, evaluated, moved) && state.share.is_some_and(|sh| sh.missing_255.is_none())
}
