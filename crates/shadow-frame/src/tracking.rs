//! The core systems that run before the techniques: caster tracking, technique resolution and
//! staleness. Work downstream is driven by what they find changed, nothing else.

use crate::TechniqueRegistry;
use crate::calibration::Calibration;
use crate::components::*;
use crate::profile::{Calibrated, SceneSize, TechniqueProfile};
use crate::scene::{LightSource, MeshHandle, ShadowCaster, Transform};
use bevy_ecs::prelude::*;
use soft_shadow_core::mesh::Aabb;
use std::sync::Arc;

/// World bounds of a caster instance.
fn caster_bounds(mesh: &MeshHandle, t: &Transform) -> Aabb {
    let mut b = Aabb::EMPTY;
    for p in mesh.0.world_triangles(t.0).flatten() {
        b.grow(p);
    }
    b
}

/// Casters whose transform or mesh changed, or that just became casters.
type ChangedCasters<'w, 's> = Query<
    'w,
    's,
    (Entity, &'static MeshHandle, &'static Transform),
    (
        With<ShadowCaster>,
        Or<(Changed<Transform>, Changed<MeshHandle>, Added<ShadowCaster>)>,
    ),
>;

/// Records the old and new bounds of every caster that moved, changed mesh, appeared or
/// disappeared since the last frame (`Changed`, `Added`, `RemovedComponents`).
pub fn track_casters(
    mut index: ResMut<CasterIndex>,
    changed: ChangedCasters,
    mut removed: RemovedComponents<ShadowCaster>,
) {
    let index = &mut *index;
    index.changed.clear();
    for (e, m, t) in &changed {
        let b = caster_bounds(m, t);
        if let Some(old) = index.bounds.insert(e, b) {
            index.changed.push(old);
        }
        index.changed.push(b);
    }
    for e in removed.read() {
        if let Some(old) = index.bounds.remove(&e) {
            index.changed.push(old);
        }
    }
}

/// Validates the frame receivers once per frame (equal lengths, finite values): bad receivers
/// become every light's error, and a NaN point never passes as "out of range".
pub fn check_receivers(frame: Res<FrameReceivers>, mut error: ResMut<ReceiversError>) {
    let e = soft_shadow_core::Receivers::new(&frame.positions, &frame.normals)
        .validate()
        .err()
        .map(|e| format!("FrameReceivers: {e}"));
    if error.0 != e {
        error.0 = e;
    }
}

/// Measured frames over the budget after which an `Auto` choice steps down.
pub const STEP_DOWN_FRAMES: u32 = 3;

/// Share of the budget a step-down aims for, below the budget itself so that a choice measured
/// just under it does not flip back and forth (hysteresis).
pub const STEP_DOWN_MARGIN: f64 = 0.8;

/// The casters of the scene (what `Auto` sizes a scene by).
pub type CasterMeshes<'w, 's> =
    Query<'w, 's, (Entity, &'static MeshHandle, &'static Transform), With<ShadowCaster>>;

/// The scene `light` sees within its influence radius `range`, as predictions size it: the
/// triangles of the casters that reach it ([`caster_reaches`], what its maps render), the frame's
/// receivers within its influence, those its views cover ([`SceneSize::with_views`], counted on
/// the frame's every `k`-th receiver, at most [`RECEIVER_SAMPLES`] of them, and
/// scaled to all), and the light's views as the pipeline plans them (a distant light's cascades
/// with the frame's camera, fitted to that sample of the receivers where `settings` fit them to
/// the receivers on `backend`: [`FrameSettings::cascade_fit`]).
fn scene_size(
    casters: &CasterMeshes,
    index: &CasterIndex,
    frame: &FrameReceivers,
    light: &soft_shadow_core::Light,
    range: f32,
    (backend, settings): (soft_shadow_core::Backend, &FrameSettings),
) -> SceneSize {
    let tris: Vec<[glam::Vec3; 3]> = casters
        .iter()
        .filter(|(e, ..)| {
            index
                .bounds
                .get(e)
                .is_some_and(|b| caster_reaches(light, range, b))
        })
        .flat_map(|(_, m, t)| m.0.world_triangles(t.0).collect::<Vec<_>>())
        .collect();
    // One pass over the frame's receivers: how many lie within the influence, their bounds, and
    // the evenly spread sample the covered count reads (the budget sizes every lamp each time
    // it is shared again; counting every receiver took most of that).
    let (c, r) = influence(light, range);
    let inside = |p: &glam::Vec3| !r.is_finite() || p.distance_squared(c) <= r * r;
    let step = FrameReceivers::sample_step(frame.positions.len());
    let (mut count, mut reach, mut sample) = (0, Aabb::EMPTY, Vec::new());
    for (i, p) in frame.positions.iter().enumerate() {
        if inside(p) {
            count += 1;
            reach.grow(*p);
            if i % step == 0 {
                sample.push(*p);
            }
        }
    }
    if sample.is_empty() && count > 0 {
        // A patch the samples step over: every receiver on it.
        sample = frame.positions.iter().copied().filter(inside).collect();
    }
    let mut geometry = soft_shadow_core::SceneGeometry::new(tris, Vec::new());
    if geometry.casters.is_empty() {
        return SceneSize {
            receivers: count,
            ..SceneSize::of(&geometry, light, &[])
        };
    }
    // The views as the pipeline plans them: over the casters with the bounds grown by the
    // receivers (`light_geometry`); only a distant light's read what the camera sees (its
    // cascades).
    // (The same geometry with its bounds grown, then given back: the single view's count is
    // over the casters' own bounds.)
    let bounds = geometry.bounds;
    if count > 0 {
        geometry.bounds.grow(reach.min);
        geometry.bounds.grow(reach.max);
    }
    let seen = match light.center() {
        soft_shadow_core::LightPoint::Direction(_) => frame.seen(),
        soft_shadow_core::LightPoint::Position(_) => None,
    };
    let fit = FrameReceivers::cascade_fit(&sample, backend, settings);
    let views = soft_shadow_core::LightViews::plan_seen(light, &geometry, seen.as_ref(), fit);
    geometry.bounds = bounds;
    let size = SceneSize::with_views(&geometry, light, &sample, &views);
    let covered = if sample.len() == count {
        size.covered
    } else {
        (size.covered as f64 * count as f64 / sample.len() as f64).round() as usize
    };
    SceneSize {
        receivers: count,
        covered: covered.min(count),
        ..size
    }
}

/// The largest map side each configuration of `registry` that models `kind` takes on
/// `backend` (`None`: not registered, or not for `kind`): what `Auto` picks among.
fn max_side<'a>(
    kind: soft_shadow_core::LightKind,
    registry: &'a TechniqueRegistry,
    backend: &'a FrameBackend,
) -> impl Fn(&str, &str) -> Option<u32> + 'a {
    let device = backend
        .gpu
        .as_ref()
        .map_or_else(Default::default, |g| g.device_limits());
    // Every configuration's side once: the profile asks for each of its entries.
    let sides: Vec<(&str, String, u32)> = registry
        .0
        .iter()
        .filter(|t| t.models(kind))
        .map(|t| {
            (
                t.name(),
                t.variant(),
                t.max_resolution(backend.backend, device),
            )
        })
        .collect();
    move |name: &str, variant: &str| {
        sides
            .iter()
            .find(|(n, v, _)| *n == name && v == variant)
            .map(|s| s.2)
    }
}

/// The registered configuration `name variant` that models `kind`.
fn find(
    registry: &TechniqueRegistry,
    kind: soft_shadow_core::LightKind,
    name: &str,
    variant: &str,
) -> Option<Arc<dyn soft_shadow_core::DynTechnique>> {
    registry
        .0
        .iter()
        .find(|t| t.name() == name && t.variant() == variant && t.models(kind))
        .cloned()
}

/// `Auto`'s pick for `kind` within `budget_ms`, as a resolved technique whose reason names the
/// predicted time and error (`None`: nothing is predicted to fit).
fn auto_pick(
    kind: soft_shadow_core::LightKind,
    budget_ms: f64,
    registry: &TechniqueRegistry,
    profile: Calibrated,
    backend: &FrameBackend,
    size: SceneSize,
) -> Option<ResolvedTechnique> {
    let p = profile.pick(
        kind,
        backend.backend,
        budget_ms,
        size,
        max_side(kind, registry, backend),
    )?;
    let e = p.entry;
    let stand_in = if p.stand_in {
        " (GPU time: a CPU measurement standing in, the profile has no GPU row)"
    } else {
        ""
    };
    let factors = [
        profile.calibration.generate_for(&e.technique, &e.variant),
        profile.calibration.evaluate_for(&e.technique, &e.variant),
    ];
    let calibrated = if factors == [1.0, 1.0] {
        String::new()
    } else {
        format!(
            " (the profile's generation x {:.2}, evaluation x {:.2}, as the frames measured)",
            factors[0], factors[1]
        )
    };
    Some(ResolvedTechnique {
        technique: find(registry, kind, &e.technique, &e.variant)?,
        resolution: p.resolution,
        reason: format!(
            "auto: {} {} at {}² predicts image error {:.2}/255 in {:.2} ms{stand_in}{calibrated} <= \
             {budget_ms} ms ({} triangles in {} views, {} receivers, {} in the light's map), the lowest \
             predicted error that fits",
            e.technique,
            e.variant,
            p.resolution,
            p.error_255,
            p.time_ms,
            size.triangles,
            size.views.max(1),
            size.receivers,
            size.covered
        ),
        auto: Some(AutoPrediction {
            budget_ms,
            time_ms: p.time_ms,
            profile_ms: p.profile_ms,
            error_255: p.error_255,
            margin: e.margin,
            measured_ms: None,
            frames_over: 0,
        }),
    })
}

/// What `Auto` reads to size a light's scene and pick its configuration: the casters, their
/// bounds, the frame's receivers, the registered techniques, the profile and its calibration,
/// the backend, the frame settings and the texels `V` is recorded over ([`RecordedTexels`]),
/// as one system parameter.
#[derive(bevy_ecs::system::SystemParam)]
pub struct AutoInputs<'w, 's> {
    casters: CasterMeshes<'w, 's>,
    index: Res<'w, CasterIndex>,
    /// The frame's receivers.
    pub frame: Res<'w, FrameReceivers>,
    registry: Res<'w, TechniqueRegistry>,
    profile: Res<'w, TechniqueProfile>,
    calibration: Option<Res<'w, Calibration>>,
    /// Where the frame runs.
    pub backend: Res<'w, FrameBackend>,
    settings: Option<Res<'w, FrameSettings>>,
    texels: Option<Res<'w, RecordedTexels>>,
    probed: Option<Res<'w, ProbedVisibility>>,
}

impl AutoInputs<'_, '_> {
    /// What the frames measured against the profile (the profile as fitted before any).
    pub fn calibration(&self) -> &Calibration {
        self.calibration
            .as_deref()
            .unwrap_or(&crate::calibration::IDENTITY)
    }

    /// The profile, its predictions scaled by [`AutoInputs::calibration`].
    fn profile(&self) -> Calibrated<'_> {
        self.profile.calibrated(self.calibration())
    }

    /// Light `light`'s `V` at the frame's receivers as a GPU frame's probe measured it
    /// ([`ProbedVisibility`]), where the receivers (their hash, `receivers`) are still those it
    /// was recorded for.
    pub(crate) fn probed(&self, light: Entity, receivers: u64) -> Option<&[f32]> {
        let p = self.probed.as_ref().filter(|p| p.receivers == receivers)?;
        p.lights.get(&light).map(Vec::as_slice)
    }

    /// Whether this frame's changed casters make the maps of `light` (influence radius
    /// `range`, changes out of view waiting in `unseen`) again, as [`mark_stale`] will decide
    /// after the share ([`caster_changes`]).
    pub(crate) fn casters_remake(
        &self,
        (light, range): (&soft_shadow_core::Light, f32),
        unseen: &[Aabb],
        settings: &FrameSettings,
    ) -> bool {
        caster_changes(
            (light, range),
            unseen,
            &self.index,
            (&self.frame, self.frame.is_changed()),
            settings,
        )
        .1
        .is_some()
    }

    /// Whether the texels `V` is recorded over changed since the last frame (their first
    /// count too): the predictions of [`AutoInputs::size`] changed with them.
    pub(crate) fn texels_changed(&self) -> bool {
        self.texels.as_ref().is_some_and(|t| t.is_changed())
    }

    /// The scene `light` with influence radius `range` sees, as predictions size it
    /// (the casters that reach it, the receivers within it, its views).
    ///
    /// Where the frame does not evaluate its receivers ([`FrameSettings::evaluate_receivers`]
    /// off) and `V` is recorded into a renderer's texture ([`RecordedTexels`]), the light's
    /// pass runs over every texel of it, each at the cost of a covered receiver: on lavapipe,
    /// eight lamps of one configuration (penumbra-limit silhouette-f16 128², 1000 x 720) took
    /// 180-230 ms each, whether their views covered 2% of the view or 60%.
    pub fn size(&self, light: &soft_shadow_core::Light, range: f32) -> SceneSize {
        let settings = self.settings.as_deref().copied().unwrap_or_default();
        let evaluated = settings.evaluate_receivers;
        let size = scene_size(
            &self.casters,
            &self.index,
            &self.frame,
            light,
            range,
            (self.backend.backend, &settings),
        );
        match &self.texels {
            Some(t) if !evaluated && size.triangles > 0 => SceneSize {
                receivers: t.0,
                covered: t.0,
                ..size
            },
            _ => size,
        }
    }

    /// `Auto`'s pick for `kind` within `budget_ms` on a scene of `size`, its reason naming the
    /// predicted time and error (`None`: nothing is predicted to fit).
    pub fn pick(
        &self,
        kind: soft_shadow_core::LightKind,
        budget_ms: f64,
        size: SceneSize,
    ) -> Option<ResolvedTechnique> {
        auto_pick(
            kind,
            budget_ms,
            &self.registry,
            self.profile(),
            &self.backend,
            size,
        )
    }

    /// Every configuration and side `Auto` may pick for `kind` on a scene of `size`
    /// ([`Calibrated::options`] over the registered techniques, calibrated).
    pub fn options(
        &self,
        kind: soft_shadow_core::LightKind,
        size: SceneSize,
    ) -> Vec<crate::profile::Pick<'_>> {
        self.profile().options(
            kind,
            self.backend.backend,
            size,
            max_side(kind, &self.registry, &self.backend),
        )
    }

    /// The options of [`AutoInputs::options`] worth buying, cheapest first
    /// ([`Calibrated::frontier`]).
    pub fn frontier(
        &self,
        kind: soft_shadow_core::LightKind,
        size: SceneSize,
    ) -> Vec<crate::profile::Pick<'_>> {
        self.profile().frontier(
            kind,
            self.backend.backend,
            size,
            max_side(kind, &self.registry, &self.backend),
        )
    }
}

/// The technique of a light: the hard path for a zero-size light, the explicit one, or the
/// profile's pick within the budget for the light's scene.
fn resolve_one(
    light: &soft_shadow_core::Light,
    config: &ShadowConfig,
    inputs: &AutoInputs,
    hard: &HardShadowPath,
) -> Result<ResolvedTechnique, String> {
    let kind = light.kind();
    if light.size() == 0.0 {
        let t = hard
            .0
            .clone()
            .ok_or("a zero-size light needs the hard-shadow path, and none is registered")?;
        return Ok(ResolvedTechnique {
            technique: t,
            resolution: match config.resolution {
                0 => ZERO_SIZE_SIDE,
                side => side,
            },
            reason: format!("{} light of zero size: hard shadow map", kind.name()),
            auto: None,
        });
    }
    match &config.choice {
        TechniqueChoice::Explicit(t) => {
            if !t.models(kind) {
                return Err(format!(
                    "{} {} does not model {} lights",
                    t.name(),
                    t.variant(),
                    kind.name()
                ));
            }
            Ok(ResolvedTechnique {
                technique: Arc::clone(t),
                resolution: config.resolution,
                reason: "explicit".into(),
                auto: None,
            })
        }
        TechniqueChoice::Shared => {
            Err("a shared choice is resolved with the frame budget's shares".into())
        }
        TechniqueChoice::Auto { budget_ms } => {
            let size = inputs.size(light, config.range);
            inputs.pick(kind, *budget_ms, size).ok_or_else(|| {
                format!(
                    "no configuration for {} lights on {} is predicted to fit {budget_ms} ms \
                     ({} triangles, {} receivers)",
                    kind.name(),
                    inputs.backend.backend.name(),
                    size.triangles,
                    size.receivers
                )
            })
        }
    }
}

/// (Re)chooses the technique of every light whose light or settings changed, and marks it stale.
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
pub fn resolve_techniques(
    mut commands: Commands,
    mut lights: Query<
        (Entity, &LightSource, &ShadowConfig, Option<&mut LightState>),
        Or<(Changed<LightSource>, Changed<ShadowConfig>)>,
    >,
    inputs: AutoInputs,
    hard: Res<HardShadowPath>,
) {
    for (e, light, config, state) in &mut lights {
        let mut ec = commands.entity(e);
        // A light that shares the frame budget is resolved by `share_budget`, after this.
        let error = if config.shares_budget(&light.0) {
            None
        } else {
            let resolved = resolve_one(&light.0, config, &inputs, &hard);
            let error = resolved.as_ref().err().cloned();
            match resolved {
                Ok(r) => {
                    ec.insert(r);
                }
                Err(_) => {
                    ec.remove::<ResolvedTechnique>();
                }
            }
            error
        };
        let shared = config.shares_budget(&light.0);
        match state {
            Some(mut s) => {
                s.stale = true;
                s.maps = None;
                // A shared light's error is the budget's to set (it shares again after this).
                if !shared {
                    s.error = error;
                }
                s.generated_ms = None;
            }
            None => {
                ec.insert(LightState {
                    stale: true,
                    error,
                    ..Default::default()
                });
            }
        }
    }
}

/// Holds `Auto` choices to their budgets with what the frames measured: the measured time
/// replaces the prediction, and a choice measured over the budget for [`STEP_DOWN_FRAMES`]
/// generating frames in a row steps down to the best configuration predicted to fit, its
/// predictions scaled by how far the measurement was off, aiming at [`STEP_DOWN_MARGIN`] of the
/// budget. It never steps up by itself (a changed light or config chooses afresh), so a choice
/// does not flip from frame to frame.
#[allow(clippy::type_complexity)]
pub fn keep_budgets(
    mut lights: Query<(
        &LightSource,
        &ShadowConfig,
        &mut ResolvedTechnique,
        &mut LightState,
    )>,
    inputs: AutoInputs,
) {
    for (light, config, mut resolved, mut state) in &mut lights {
        let Some(measured) = state.generated_ms.take() else {
            continue;
        };
        let Some(mut auto) = resolved.auto else {
            continue;
        };
        // A light that keeps its maps at the price of its evaluation makes none: a generation
        // measured now (a GPU frame's timestamps come back frames late) was bought before.
        if state.share.is_some_and(|s| s.kept) {
            continue;
        }
        auto.measured_ms = Some(measured);
        auto.frames_over = if measured > auto.budget_ms {
            auto.frames_over + 1
        } else {
            0
        };
        if auto.frames_over < STEP_DOWN_FRAMES {
            resolved.auto = Some(auto);
            continue;
        }
        // How far the measurement lies over the prediction as the frames calibrate it now
        // (which the next pick predicts with too).
        let calibration = inputs.calibration();
        let [g, e] = auto.profile_ms;
        let predicted = g * calibration
            .generate_for(resolved.technique.name(), &resolved.technique.variant())
            + e * calibration
                .evaluate_for(resolved.technique.name(), &resolved.technique.variant());
        let scale = (measured / predicted.max(1e-6)).max(1.0);
        let target = auto.budget_ms * STEP_DOWN_MARGIN / scale;
        let size = inputs.size(&light.0, config.range);
        let kind = light.0.kind();
        match inputs.pick(kind, target, size) {
            Some(mut next) => {
                let from = format!(
                    "{} {} at {}²",
                    resolved.technique.name(),
                    resolved.technique.variant(),
                    resolved.resolution
                );
                next.reason = format!(
                    "auto: stepped down from {from}, measured {measured:.2} ms over the {} ms \
                     budget for {STEP_DOWN_FRAMES} frames (predictions scaled by {scale:.2}); {}",
                    auto.budget_ms,
                    next.reason.trim_start_matches("auto: ")
                );
                if let Some(a) = next.auto.as_mut() {
                    a.budget_ms = auto.budget_ms;
                }
                *resolved = next;
                state.stale = true;
            }
            None => {
                auto.frames_over = 0;
                resolved.auto = Some(auto);
                resolved.reason = format!(
                    "{}; measured {measured:.2} ms over the budget, and nothing cheaper is \
                     predicted to fit",
                    resolved.reason
                );
            }
        }
    }
}

/// Marks stale every light that a changed caster region reaches ([`caster_reaches`]) where it
/// can shadow what the camera sees; every light, with caching off or when the frame's backend
/// changed (maps are made where the frame runs).
///
/// With [`FrameSettings::evaluate_receivers`] on (the frame's receivers are what the camera
/// sees), a local light's change counts only where the region meets [`seen_hull`]: the box
/// around the light and the frame's receivers within its range, padded (a caster can shadow a
/// receiver only between the two; the padding holds the filters' footprints, as an
/// approximation: a filter wider than it near the hull's edge could read a change beyond it).
/// A change outside waits in [`LightState::unseen_changes`] until a frame whose receivers bring
/// it into the hull (the camera turned towards it) or the light's maps are made again. Distant
/// lights, and every light when the receivers are not evaluated, take every change in range.
pub fn mark_stale(
    index: Res<CasterIndex>,
    settings: Res<FrameSettings>,
    backend: Res<FrameBackend>,
    frame: Res<FrameReceivers>,
    mut lights: Query<(&LightSource, &ShadowConfig, &mut LightState)>,
) {
    let everything = !settings.caching || backend.is_changed();
    for (light, config, mut state) in &mut lights {
        mark_one(
            everything,
            (light, config, &mut state),
            &index,
            &frame,
            &settings,
        );
    }
}

/// [`mark_stale`] as the pipeline schedules it, noting which lights only changed casters made
/// stale, and where they changed ([`crate::faces`]).
pub(crate) fn mark_stale_noting(
    index: Res<CasterIndex>,
    settings: Res<FrameSettings>,
    backend: Res<FrameBackend>,
    frame: Res<FrameReceivers>,
    mut lights: Query<(Entity, &LightSource, &ShadowConfig, &mut LightState)>,
    mut faces: ResMut<crate::faces::FaceRefresh>,
) {
    let everything = !settings.caching || backend.is_changed();
    let mut seen = std::collections::HashSet::new();
    for (entity, light, config, mut state) in &mut lights {
        let already = state.stale;
        let regions = mark_one(
            everything,
            (light, config, &mut state),
            &index,
            &frame,
            &settings,
        );
        faces.mark(entity, (already, state.stale, everything), regions);
        seen.insert(entity);
    }
    faces.keep_only(&seen);
}

/// [`mark_stale`] for one light; returns the changed regions where changed casters made it
/// stale this frame (`None` where every light is, or none made it).
fn mark_one(
    everything: bool,
    (light, config, state): (&LightSource, &ShadowConfig, &mut LightState),
    index: &CasterIndex,
    frame: &Res<FrameReceivers>,
    settings: &FrameSettings,
) -> Option<Vec<Aabb>> {
    if everything {
        state.stale = true;
        return None;
    }
    let (unseen, stale) = caster_changes(
        (&light.0, config.range),
        &state.unseen_changes,
        index,
        (frame, frame.is_changed()),
        settings,
    );
    state.unseen_changes = unseen;
    let regions = stale?;
    // What its shadow was missing was measured on the casters as they were.
    state.stale = true;
    forget_missing(state);
    Some(regions)
}

/// What this frame's changed caster regions ([`CasterIndex::changed`]) do to a light (`light`
/// with influence radius `range`) whose changes out of view wait in `unseen`
/// ([`LightState::unseen_changes`]), as [`mark_stale`] decides it (caching on, the backend
/// unchanged): the changes that wait after this frame, and, where its maps must be made
/// again, the changed regions that make them (with those that waited). `frame_changed`: the
/// frame's receivers changed this frame.
pub(crate) fn caster_changes(
    (light, range): (&soft_shadow_core::Light, f32),
    unseen: &[Aabb],
    index: &CasterIndex,
    (frame, frame_changed): (&FrameReceivers, bool),
    settings: &FrameSettings,
) -> (Vec<Aabb>, Option<Vec<Aabb>>) {
    let changed = index
        .changed
        .iter()
        .filter(|b| caster_reaches(light, range, b));
    // Without evaluated receivers (the GPU frame's G-buffer is the view) the frame's
    // receivers need not be what the camera sees: every change in range counts.
    let distant = matches!(light.center(), soft_shadow_core::LightPoint::Direction(_));
    if distant || !settings.evaluate_receivers {
        let changed: Vec<Aabb> = changed.copied().collect();
        return (unseen.to_vec(), (!changed.is_empty()).then_some(changed));
    }
    let mut waiting = unseen.to_vec();
    waiting.extend(changed);
    let fresh = waiting.len() > unseen.len();
    if waiting.len() > UNSEEN_CHANGES {
        // A caster that keeps moving out of view: one box over its regions.
        let mut all = Aabb::EMPTY;
        for b in waiting.drain(..) {
            all.grow(b.min);
            all.grow(b.max);
        }
        waiting.push(all);
    }
    if waiting.is_empty() || !(fresh || frame_changed) {
        return (waiting, None);
    }
    let hull = seen_hull(light, range, &frame.positions);
    if waiting.iter().any(|b| boxes_meet(b, &hull)) {
        (Vec::new(), Some(waiting))
    } else {
        (waiting, None)
    }
}

/// What a light's shadow was missing was measured on the casters as they were: a caster
/// within its range changed, so the budget takes the prior until its shadow is measured again.
fn forget_missing(state: &mut LightState) {
    if let Some(share) = state.share.as_mut() {
        share.missing_255 = None;
    }
}

/// Regions [`LightState::unseen_changes`] keeps before it merges them into one box.
pub const UNSEEN_CHANGES: usize = 8;

/// The box around a local light (the sphere around its centre that holds it,
/// [`soft_shadow_core::coverage::light_radius`]) and the `receivers` within its influence
/// radius `range` (a caster that shadows one of them meets the segment from it to a light
/// point, so lies in this box), grown by a tenth of its diagonal on every side.
pub fn seen_hull(light: &soft_shadow_core::Light, range: f32, receivers: &[glam::Vec3]) -> Aabb {
    let (c, r) = influence(light, range);
    let reach = glam::Vec3::splat(soft_shadow_core::coverage::light_radius(light, c));
    let mut hull = Aabb::EMPTY;
    hull.grow(c - reach);
    hull.grow(c + reach);
    for p in receivers {
        if !r.is_finite() || p.distance_squared(c) <= r * r {
            hull.grow(*p);
        }
    }
    // Filters read around a receiver's point (PCF's kernel, PCSS's blocker search, the width
    // and limit maps): a tenth of the diagonal more on every side.
    let pad = glam::Vec3::splat(0.1 * (hull.max - hull.min).length());
    hull.grow(hull.min - pad);
    hull.grow(hull.max + pad);
    hull
}

/// Whether two boxes overlap (touching counts).
fn boxes_meet(a: &Aabb, b: &Aabb) -> bool {
    a.min.cmple(b.max).all() && b.min.cmple(a.max).all()
}
