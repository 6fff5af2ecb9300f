//! The core systems that run before the techniques: caster tracking, technique resolution and
//! staleness. Work downstream is driven by what they find changed, nothing else.

use crate::TechniqueRegistry;
use crate::components::*;
use crate::profile::TechniqueProfile;
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

/// The technique of a light: the hard path for a zero-size light, the explicit one, or the
/// profile's pick within the budget.
fn resolve_one(
    light: &soft_shadow_core::Light,
    config: &ShadowConfig,
    registry: &TechniqueRegistry,
    profile: &TechniqueProfile,
    hard: &HardShadowPath,
    backend: &FrameBackend,
) -> Result<ResolvedTechnique, String> {
    let kind = light.kind();
    if light.size() == 0.0 {
        let t = hard
            .0
            .clone()
            .ok_or("a zero-size light needs the hard-shadow path, and none is registered")?;
        return Ok(ResolvedTechnique {
            technique: t,
            resolution: config.resolution.max(1),
            reason: format!("{} light of zero size: hard shadow map", kind.name()),
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
            })
        }
        TechniqueChoice::Auto { budget_ms } => {
            let find = |name: &str, variant: &str| {
                registry
                    .0
                    .iter()
                    .find(|t| t.name() == name && t.variant() == variant && t.models(kind))
                    .cloned()
            };
            let e = profile
                .pick(kind, backend.backend, *budget_ms, |n, v| {
                    find(n, v).is_some()
                })
                .ok_or_else(|| {
                    format!(
                        "no measured configuration for {} lights on {} fits {budget_ms} ms",
                        kind.name(),
                        backend.backend.name()
                    )
                })?;
            let candidates = profile
                .entries
                .iter()
                .filter(|c| c.light == kind && c.backend == backend.backend)
                .count();
            Ok(ResolvedTechnique {
                technique: find(&e.technique, &e.variant).ok_or("registry changed")?,
                resolution: e.resolution,
                reason: format!(
                    "auto: {} {} at {} has the lowest measured rms ({:.2}/255) of {candidates} \
                     {} configurations, in {:.2} ms <= {budget_ms} ms",
                    e.technique,
                    e.variant,
                    e.resolution,
                    e.rms_255,
                    kind.name(),
                    e.time_ms
                ),
            })
        }
    }
}

/// (Re)chooses the technique of every light whose light or settings changed, and marks it stale.
#[allow(clippy::type_complexity)]
pub fn resolve_techniques(
    mut commands: Commands,
    mut lights: Query<
        (Entity, &LightSource, &ShadowConfig, Option<&mut LightState>),
        Or<(Changed<LightSource>, Changed<ShadowConfig>)>,
    >,
    registry: Res<TechniqueRegistry>,
    profile: Res<TechniqueProfile>,
    hard: Res<HardShadowPath>,
    backend: Res<FrameBackend>,
) {
    for (e, light, config, state) in &mut lights {
        let resolved = resolve_one(&light.0, config, &registry, &profile, &hard, &backend);
        let error = resolved.as_ref().err().cloned();
        let mut ec = commands.entity(e);
        match resolved {
            Ok(r) => {
                ec.insert(r);
            }
            Err(_) => {
                ec.remove::<ResolvedTechnique>();
            }
        }
        match state {
            Some(mut s) => {
                s.stale = true;
                s.maps = None;
                s.error = error;
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

/// Marks stale every light that a changed caster region reaches ([`caster_reaches`]; every
/// light, with caching off).
pub fn mark_stale(
    index: Res<CasterIndex>,
    settings: Res<FrameSettings>,
    mut lights: Query<(&LightSource, &ShadowConfig, &mut LightState)>,
) {
    for (light, config, mut state) in &mut lights {
        if !settings.caching {
            state.stale = true;
            continue;
        }
        if index
            .changed
            .iter()
            .any(|b| caster_reaches(&light.0, config.range, b))
        {
            state.stale = true;
        }
    }
}
