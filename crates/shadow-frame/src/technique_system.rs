//! The system one technique runs per frame, for the lights resolved to it: regenerate the maps
//! of stale lights (from the casters within the light's influence), reuse the others, and
//! evaluate the frame receivers within the influence.

use crate::budget::worth;
use crate::calibration::Calibration;
use crate::components::*;
use crate::deadline::{Deadline, Pending};
use crate::faces::FaceRefresh;
use crate::recording::Recording;
use crate::scene::{LightSource, MeshHandle, ShadowCaster, SpawnOrder, Transform};
use crate::stats::{FrameStats, LightStats};
use bevy_ecs::prelude::*;
use soft_shadow_core::mesh::Aabb;
use soft_shadow_core::{LightPoint, LightViews, Receivers, SceneGeometry};
use std::time::Instant;

/// The lights a technique system reads and updates.
pub type LightQuery<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static LightSource,
        &'static ShadowConfig,
        &'static ResolvedTechnique,
        &'static mut LightState,
    ),
>;

/// The caster instances.
pub type CasterQuery<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static MeshHandle,
        &'static Transform,
        Option<&'static SpawnOrder>,
    ),
    With<ShadowCaster>,
>;

/// The casters that reach `light` ([`caster_reaches`]), flattened in spawn order and clipped
/// to the box around its influence sphere, and their bounds grown by the receivers in range.
fn light_geometry(
    casters: &CasterQuery,
    index: &CasterIndex,
    light: &soft_shadow_core::Light,
    range: f32,
    receivers: &[glam::Vec3],
) -> SceneGeometry {
    let mut items: Vec<_> = casters
        .iter()
        .filter(|(e, ..)| {
            index
                .bounds
                .get(e)
                .is_some_and(|b| caster_reaches(light, range, b))
        })
        .map(|(e, m, t, o)| ((o.map_or(u64::MAX, |o| o.0), e), m, t))
        .collect();
    items.sort_by_key(|(k, ..)| *k);
    // Within a range, only the casters' parts inside the influence sphere's box can shadow a
    // receiver the light reaches (every point between the two lies within the range): a ground
    // that stretches 100 m past a 9 m lamp does not stretch its maps' depth range with it.
    let (c, r) = influence(light, range);
    let reach = Aabb {
        min: c - glam::Vec3::splat(r),
        max: c + glam::Vec3::splat(r),
    };
    let casters: Vec<[glam::Vec3; 3]> = items
        .iter()
        .flat_map(|(_, m, t)| m.0.world_triangles(t.0).collect::<Vec<_>>())
        .flat_map(|t| {
            if r.is_finite() {
                clip_to_box(&t, &reach)
            } else {
                vec![t]
            }
        })
        .collect();
    let mut bounds = Aabb::of_triangles(&casters);
    if !casters.is_empty() {
        for p in receivers {
            bounds.grow(*p);
        }
    }
    SceneGeometry {
        casters,
        receivers: Vec::new(),
        bounds,
    }
}

/// One light's line of the frame's statistics: it made `views_generated` of its `views` views,
/// started at `start`, and its evaluation at `evaluating` (`None`: it did not evaluate).
fn light_stats(
    light: Entity,
    resolved: &ResolvedTechnique,
    (views_generated, views): (usize, usize),
    receivers_evaluated: usize,
    start: Instant,
    evaluating: Option<Instant>,
) -> LightStats {
    let now = Instant::now();
    let ms = |from: Instant| (now - from).as_secs_f64() * 1e3;
    let evaluate_ms = evaluating.map_or(0.0, ms);
    LightStats {
        light,
        technique: format!(
            "{} {}",
            resolved.technique.name(),
            resolved.technique.variant()
        ),
        resolution: resolved.resolution,
        views_generated,
        receivers_evaluated,
        ms: ms(start),
        generate_ms: if views_generated > 0 {
            ms(start) - evaluate_ms
        } else {
            0.0
        },
        evaluate_ms,
        // Cascades that follow the camera make only the views that moved: the prediction of
        // those.
        profile_ms: resolved.auto.map(|a| {
            let [g, e] = a.profile_ms;
            match (views_generated, views) {
                (made, all) if made > 0 && made < all => [g * made as f64 / all as f64, e],
                _ => [g, e],
            }
        }),
        predicted_ms: resolved.auto.map(|a| a.time_ms),
        budget_ms: resolved.auto.map(|a| a.budget_ms),
        waited: false,
    }
}

/// Whether a light takes a part of the [`crate::FrameBudget`] this frame.
fn shared(state: &LightState) -> bool {
    state.share.is_some_and(|s| s.budget_ms > 0.0)
}

/// Whether a light showed a shadow in the last frame and has no maps now (a new pick dropped
/// them): its maps are made this frame, since waiting would take its shadow off for a frame.
fn dropped_a_shown_shadow(state: &LightState) -> bool {
    state.maps.is_none() && state.evaluated > 0 && state.error.is_none()
}

/// Keeps one light's `line` in the frame's statistics (`waited`: its maps waited a frame),
/// and, with the frame's clock, what a shared light spent against its predictions (its
/// generation as the calibration predicts it, and its evaluation as `evaluation_ms` predicts
/// it, to which its share of its system's own work, `overhead_ms`, is added).
fn keep(
    stats: &mut FrameStats,
    name: &str,
    mut line: LightStats,
    (waited, shared): (bool, bool),
    clock: Option<&mut ((&mut Deadline, &Calibration), f64)>,
    (evaluation_ms, overhead_ms): (f64, f64),
) {
    line.waited = waited;
    if let (Some(((deadline, calibration), _)), Some([g, _]), true) =
        (clock, line.profile_ms, shared)
    {
        let (t, v) = line
            .technique
            .split_once(' ')
            .unwrap_or((line.technique.as_str(), ""));
        let generation = if line.views_generated > 0 {
            g * calibration.generate_for(t, v)
        } else {
            0.0
        };
        let evaluation = if line.receivers_evaluated > 0 {
            evaluation_ms
        } else {
            0.0
        };
        deadline.ran(
            [line.generate_ms, line.evaluate_ms + overhead_ms],
            [generation, evaluation],
        );
    }
    stats.record(name, line);
}

/// One frame of technique `name`.
#[allow(clippy::too_many_arguments)]
pub fn run_technique(
    name: &str,
    lights: LightQuery,
    casters: CasterQuery,
    index: Res<CasterIndex>,
    frame: Res<FrameReceivers>,
    receivers_error: Res<ReceiversError>,
    backend: Res<FrameBackend>,
    settings: Res<FrameSettings>,
    stats: ResMut<FrameStats>,
) {
    run_technique_timed(
        name,
        (lights, casters, index, frame, receivers_error),
        (&backend, &settings, None),
        stats,
        &mut |_, work| work(),
        (Recording::in_context(&backend), None),
    );
}

/// What a technique's frame reads of the scene: its lights, the casters and their index, the
/// frame's receivers and why they cannot be shaded.
pub(crate) type TechniqueInputs<'w, 's> = (
    LightQuery<'w, 's>,
    CasterQuery<'w, 's>,
    Res<'w, CasterIndex>,
    Res<'w, FrameReceivers>,
    Res<'w, ReceiversError>,
);

/// [`run_technique`], each light's generation on the GPU backend run through `timed` (with
/// the light), which times its passes on the device where the frame asks for it, and made as
/// `recording` makes it; with a `clock`, a calibrating CPU frame's shared lights keep to the
/// [`crate::FrameBudget`] as it runs ([`crate::deadline`]).
pub(crate) fn run_technique_timed(
    name: &str,
    (mut lights, casters, index, frame, receivers_error): TechniqueInputs,
    (backend, settings, clock): (
        &FrameBackend,
        &Res<FrameSettings>,
        Option<(&mut Deadline, &Calibration)>,
    ),
    mut stats: ResMut<FrameStats>,
    timed: &mut dyn FnMut(Entity, &mut dyn FnMut()),
    (mut recording, mut faces): (Recording, Option<&mut FaceRefresh>),
) {
    let start = Instant::now();
    let gpu = backend.gpu.as_deref();
    let on_gpu = backend.backend == soft_shadow_core::Backend::Gpu;
    // The frame's clock for its shared lights, and the evaluations still to come: those of the
    // shared lights of this technique and of the techniques yet to run.
    let mut clock = clock
        .filter(|_| !on_gpu && settings.calibrating && settings.evaluate_receivers)
        .zip(stats.budget_ms);
    let mut pending: Vec<Pending> = match &clock {
        Some(((_, calibration), _)) => lights
            .iter()
            .filter(|(_, _, _, r, s)| {
                shared(s)
                    && (r.technique.name() == name
                        || !stats.system_ms.contains_key(r.technique.name()))
            })
            .filter_map(|(e, _, _, r, s)| {
                let a = r.auto?;
                let (t, v) = (r.technique.name(), r.technique.variant());
                let makes = s.stale || s.maps.is_none();
                Some(Pending {
                    light: e,
                    generate_ms: if makes {
                        a.profile_ms[0] * calibration.generate_for(t, &v)
                    } else {
                        0.0
                    },
                    evaluate_ms: a.profile_ms[1] * calibration.evaluate_for(t, &v),
                    worth: worth(s),
                    must: dropped_a_shown_shadow(s),
                })
            })
            .collect(),
        None => Vec::new(),
    };
    let mut timed = |light: Entity, work: &mut dyn FnMut()| {
        if on_gpu { timed(light, work) } else { work() }
    };
    // What the camera sees, for distant lights' cascades: computed once, and only when one
    // is served.
    let seen = std::cell::OnceCell::new();
    let seen = || seen.get_or_init(|| frame.seen()).as_ref();
    // This technique's lights, in the query's order; with the frame's clock, the shared ones
    // whose shadows are worth most first: where the frame runs over, those worth least wait.
    let mut order: Vec<(Entity, f64)> = lights
        .iter()
        .filter(|(.., r, _)| r.technique.name() == name)
        .map(|(e, .., s)| (e, worth(s)))
        .collect();
    if clock.is_some() {
        order.sort_by(|a, b| b.1.total_cmp(&a.1));
    }
    let mut outside: Option<Instant> = None;
    for (entity, _) in order {
        let iteration = Instant::now();
        // The light before, outside the budget, took until now (whichever way it left).
        if let (Some(since), Some(((deadline, _), _))) = (outside.take(), clock.as_mut()) {
            deadline.ran_outside(since.elapsed().as_secs_f64() * 1e3);
        }
        let Ok((entity, light, config, resolved, mut state)) = lights.get_mut(entity) else {
            continue;
        };
        let is_shared = shared(&state);
        if !is_shared {
            outside = Some(iteration);
        }
        // A shared light leaves what is still to come.
        let own = pending
            .iter()
            .position(|p| p.light == entity)
            .map(|i| pending.swap_remove(i));
        let own_evaluation = own.map_or(0.0, |p| p.evaluate_ms);
        // Read before the frame resets what it evaluated.
        let dropped = dropped_a_shown_shadow(&state);
        if let Some(m) = &receivers_error.0 {
            state.error = Some(m.clone());
            state.visibility.clear();
            continue;
        }
        let (c, r) = influence(&light.0, config.range);
        let inside: Vec<usize> = (0..frame.positions.len())
            .filter(|&i| !r.is_finite() || frame.positions[i].distance_squared(c) <= r * r)
            .collect();
        let positions: Vec<_> = inside.iter().map(|&i| frame.positions[i]).collect();
        let normals: Vec<_> = inside.iter().map(|&i| frame.normals[i]).collect();
        state.visibility = if settings.evaluate_receivers {
            vec![1.0; frame.positions.len()]
        } else {
            Vec::new()
        };
        state.evaluated = 0;
        let light_start = Instant::now();
        // A distant light seen by a camera has cascades, planned again in every frame whose
        // receivers, camera or settings changed: they follow the camera. Maps whose plan allows
        // it follow
        // the planned cascades, making again only the views whose windows moved (to other
        // texels); others regenerate.
        let distant = matches!(light.0.center(), LightPoint::Direction(_));
        let fit = FrameReceivers::cascade_fit(&positions, backend.backend, settings);
        let seen = || if distant { seen() } else { None };
        let cascaded = distant && seen().is_some() && (frame.is_changed() || settings.is_changed());
        let mut planned = None;
        let (mut views_generated, mut views_total) = (0, 0);
        if let (true, false, Some(maps)) = (cascaded, state.stale, state.maps.as_mut()) {
            let g = light_geometry(&casters, &index, &light.0, config.range, &positions);
            let views = LightViews::plan_seen(&light.0, &g, seen(), fit);
            let mut followed = Err(String::new());
            timed(entity, &mut || {
                followed = recording.follow(maps, &g, &light.0, &views, resolved.resolution);
            });
            match followed {
                Ok(Some(remade)) => (views_generated, views_total) = (remade, views.len()),
                Ok(None) => planned = Some((g, views)),
                Err(e) => {
                    state.error = Some(e);
                    state.maps = None;
                    continue;
                }
            }
        }
        let mut generated = state.stale || state.maps.is_none() || planned.is_some();
        let mut waited = false;
        // A light whose shadow was on screen and whose maps a new pick dropped makes them now:
        // waiting would take its shadow off for a frame. Cascades planned again for a moved
        // camera follow it now too: their maps are not stale, so a wait would keep the old
        // ones until the camera moved again.
        let may_wait = generated && is_shared && planned.is_none() && !dropped;
        if let (true, Some(((deadline, _), budget_ms)), Some(own)) = (may_wait, clock.as_mut(), own)
        {
            let spent = deadline.spent_ms();
            if let Some(need) = deadline.waits(own, &pending, *budget_ms, spent) {
                (generated, waited) = (false, true);
                if state.maps.is_none() {
                    state.error = Some(format!(
                        "its maps wait a frame: this frame, running over its predictions, would \
                         take {need:.2} ms of its {budget_ms} ms with them"
                    ));
                    let mut line = light_stats(entity, resolved, (0, 0), 0, Instant::now(), None);
                    line.waited = true;
                    stats.record_waiting(name, line);
                    continue;
                }
            }
        }
        if generated {
            // The maps are made from the casters as they are: nothing waits any more.
            let unseen = std::mem::take(&mut state.unseen_changes);
            let (g, views) = planned.unwrap_or_else(|| {
                let g = light_geometry(&casters, &index, &light.0, config.range, &positions);
                let views = LightViews::plan_seen(&light.0, &g, seen(), fit);
                (g, views)
            });
            // Only changed casters made it stale, and its faces are local: the faces they meet.
            // The note is taken however the maps are made.
            let note = faces.as_deref_mut().and_then(|f| f.take(entity));
            let only = match (faces.as_deref(), state.maps.as_ref(), note) {
                (Some(f), Some(maps), Some(regions)) => f.faces(
                    entity,
                    (resolved.technique.as_ref(), resolved.resolution),
                    (&light.0, &g),
                    (&views, maps.views()),
                    (regions, &unseen),
                ),
                _ => None,
            };
            if let (Some(only), Some(maps)) = (only, state.maps.as_mut()) {
                let mut made = Ok(());
                timed(entity, &mut || {
                    made = recording.remake_views(maps, &g, &light.0, resolved.resolution, &only);
                });
                if let Err(e) = made {
                    state.error = Some(e);
                    state.stale = false;
                    backend.retire(state.maps.take());
                    continue;
                }
                (views_generated, views_total) = (only.len(), views.len());
                state.error = None;
                state.stale = false;
            } else {
                backend.retire(state.maps.take());
                if g.casters.is_empty() {
                    state.stale = false;
                    // Nothing to cast: no shadow, and no wait it had to say.
                    state.error = None;
                    continue;
                }
                (views_generated, views_total) = (views.len(), views.len());
                let mut made = Err(String::new());
                timed(entity, &mut || {
                    made = recording.generate(
                        resolved.technique.as_ref(),
                        &g,
                        &light.0,
                        &views,
                        resolved.resolution,
                    );
                });
                match made {
                    Ok(m) => {
                        state.maps = Some(m);
                        state.error = None;
                        if let Some(f) = faces.as_deref_mut() {
                            f.made(
                                entity,
                                (resolved.technique.as_ref(), resolved.resolution),
                                (&light.0, &g, &views),
                            );
                        }
                    }
                    Err(e) => {
                        state.error = Some(e);
                        state.stale = false;
                        continue;
                    }
                }
                state.stale = false;
            }
        }
        let Some(maps) = state.maps.as_ref() else {
            continue;
        };
        if !settings.evaluate_receivers {
            state.visibility.clear();
            if views_generated > 0 {
                state.generated_ms = Some(light_start.elapsed().as_secs_f64() * 1e3);
            }
            let line = light_stats(
                entity,
                resolved,
                (views_generated, views_total),
                0,
                light_start,
                None,
            );
            // No clock keeps a frame that does not evaluate: nothing waited.
            stats.record(name, line);
            continue;
        }
        let recv = Receivers::new(&positions, &normals);
        let evaluating = Instant::now();
        match maps.evaluate(gpu, &recv) {
            Ok(v) => {
                for (&i, x) in inside.iter().zip(v) {
                    state.visibility[i] = x;
                }
                state.evaluated = inside.len();
            }
            Err(e) => state.error = Some(e.to_string()),
        }
        if views_generated > 0 {
            state.generated_ms = Some(light_start.elapsed().as_secs_f64() * 1e3);
        }
        let line = light_stats(
            entity,
            resolved,
            (views_generated, views_total),
            state.evaluated,
            light_start,
            Some(evaluating),
        );
        keep(
            &mut stats,
            name,
            line,
            (waited, is_shared),
            clock.as_mut(),
            (
                own_evaluation,
                (light_start - iteration).as_secs_f64() * 1e3,
            ),
        );
    }
    if let (Some(since), Some(((deadline, _), _))) = (outside, clock.as_mut()) {
        deadline.ran_outside(since.elapsed().as_secs_f64() * 1e3);
    }
    let ms = start.elapsed().as_secs_f64() * 1e3;
    *stats.system_ms.entry(name.to_string()).or_default() += ms;
    if let Some(t) = stats.techniques.get_mut(name) {
        t.ms += ms;
    }
}
