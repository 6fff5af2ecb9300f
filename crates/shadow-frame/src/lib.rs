#![doc = include_str!("../README.md")]

pub mod budget;
pub mod calibration;
pub mod components;
pub mod deadline;
mod faces;
#[cfg(feature = "gltf")]
pub mod gltf;
#[cfg(feature = "gpu")]
pub mod gpu_frame;
#[cfg(feature = "gpu")]
pub mod gpu_irradiance;
#[cfg(feature = "gpu")]
pub mod gpu_probe;
#[cfg(feature = "gpu")]
pub mod gpu_timing;
pub mod lighting;
pub mod profile;
mod recording;
pub mod scene;
pub mod stats;
pub mod technique_system;
#[cfg(test)]
mod tests;
pub mod tracking;

pub use budget::FrameBudget;
pub use calibration::Calibration;
pub use components::*;
#[cfg(feature = "gpu")]
pub use gpu_irradiance::SHADERS;
#[cfg(feature = "gpu")]
pub use gpu_probe::ShadowProbe;
#[cfg(feature = "gpu")]
pub use gpu_timing::GpuTiming;
pub use profile::{Calibrated, Pick, ProfileEntry, SceneSize, TechniqueProfile};
pub use scene::{Scene, Shadows};
pub use stats::{CoreStats, FrameStats, LightStats, TechniqueStats};

use crate::scene::ShadowCaster;
use bevy_ecs::prelude::*;
use soft_shadow_core::technique::DynTechnique;
use soft_shadow_core::{Family, Registry, Tier};
use std::sync::Arc;
use technique_system::{CasterQuery, LightQuery};

/// Every technique instance registered with the pipeline (what `Auto` may pick from).
#[derive(Resource, Clone, Default)]
pub struct TechniqueRegistry(pub Vec<Arc<dyn DynTechnique>>);

/// The core sets, in order; technique sets run after [`CoreSet::Stale`].
#[derive(SystemSet, Debug, Clone, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum CoreSet {
    /// Caster tracking.
    Track,
    /// Technique resolution.
    Resolve,
    /// Staleness.
    Stale,
}

/// The system set of one technique.
#[derive(SystemSet, Debug, Clone, PartialEq, Eq, Hash)]
pub struct TechniqueSet(pub &'static str);

/// The frame schedule and what is registered with it.
///
/// A `bevy_ecs` schedule belongs to the world it first ran on; running the pipeline on another
/// world rebuilds it for that world (its caches and change ticks live in the world).
pub struct FramePipeline {
    schedule: Schedule,
    world: Option<bevy_ecs::world::WorldId>,
    registry: TechniqueRegistry,
    hard: HardShadowPath,
    techniques: Vec<&'static str>,
    defaults: TechniqueProfile,
}

impl Default for FramePipeline {
    fn default() -> Self {
        Self::new()
    }
}

impl FramePipeline {
    /// The core systems, no technique yet.
    pub fn new() -> Self {
        Self {
            schedule: core_schedule(),
            world: None,
            registry: TechniqueRegistry::default(),
            hard: HardShadowPath::default(),
            techniques: Vec::new(),
            defaults: TechniqueProfile::builtin(),
        }
    }

    /// Registers every family of `registry` ([`FramePipeline::add_family`]).
    pub fn with_registry(mut self, registry: &Registry) -> Self {
        for family in registry.families() {
            self.add_family(family);
        }
        self
    }

    /// Registers `family`: its variants of [`Tier::Report`] (what `Auto` may pick from, among
    /// the configurations its profile holds; an explicit choice names any technique) and one
    /// system in
    /// [`TechniqueSet`]`(name)` that runs only when a light uses it and the scene has casters.
    /// A family marked [`Family::zero_size_path`] also becomes the technique lights of zero
    /// size take.
    pub fn add_family(&mut self, family: &Family) {
        let name = family.name();
        self.registry
            .0
            .extend(family.variants_in(Tier::Report).cloned());
        if family.is_zero_size_path() {
            self.hard = HardShadowPath(Some(Arc::clone(family.default_variant())));
        }
        if self.techniques.contains(&name) {
            return;
        }
        self.techniques.push(name);
        add_technique_system(&mut self.schedule, name);
    }

    /// The profile `Auto` picks from when the world holds no [`TechniqueProfile`]: the built-in
    /// one ([`TechniqueProfile::builtin`]).
    pub fn profile_defaults(&self) -> &TechniqueProfile {
        &self.defaults
    }

    /// The registered technique names.
    pub fn techniques(&self) -> &[&'static str] {
        &self.techniques
    }

    /// Runs one frame on `world` and returns its statistics (also left in the world as the
    /// [`FrameStats`] resource). Missing resources get their defaults; a [`TechniqueProfile`]
    /// defaults to [`FramePipeline::profile_defaults`].
    pub fn run(&mut self, world: &mut World) -> FrameStats {
        // An encoder a `run_into` that did not finish left in the world: this frame submits
        // its generations on its own.
        #[cfg(feature = "gpu")]
        world.remove_resource::<recording::FrameEncoder>();
        self.run_frame(world)
    }

    /// [`FramePipeline::run`]'s frame, its generations recorded into the world's
    /// `FrameEncoder` where [`FramePipeline::run_into`] put one there.
    fn run_frame(&mut self, world: &mut World) -> FrameStats {
        world
            .get_resource_or_insert_with(deadline::Deadline::default)
            .begin_frame(std::time::Instant::now());
        if self.world.is_some_and(|id| id != world.id()) {
            self.schedule = core_schedule();
            for name in &self.techniques {
                add_technique_system(&mut self.schedule, name);
            }
        }
        self.world = Some(world.id());
        world.insert_resource(self.registry.clone());
        world.insert_resource(self.hard.clone());
        world.init_resource::<CasterIndex>();
        world.init_resource::<FrameReceivers>();
        world.init_resource::<ReceiversError>();
        world.init_resource::<FrameBackend>();
        world.init_resource::<FrameSettings>();
        world.init_resource::<Calibration>();
        world.init_resource::<faces::FaceRefresh>();
        if !world.contains_resource::<TechniqueProfile>() {
            world.insert_resource(self.defaults.clone());
        }
        let frame = world.get_resource::<FrameStats>().map_or(0, |s| s.frame) + 1;
        let budget_ms = world.get_resource::<FrameBudget>().map(|b| b.ms);
        world.insert_resource(FrameStats {
            frame,
            budget_ms,
            ..Default::default()
        });
        // Built before the clock starts (a new schedule, technique or world rebuilds it), so the
        // core sets' times hold only their systems. A build error is `run`'s to report.
        let _ = self.schedule.initialize(world);
        let settings = *world.resource::<FrameSettings>();
        let on_gpu = world.resource::<FrameBackend>().backend == soft_shadow_core::Backend::Gpu;
        // The device times of earlier GPU frames that have come back, where they are timed.
        #[cfg(feature = "gpu")]
        let arrived = gpu_timing::begin_frame(world, frame);
        #[cfg(feature = "gpu")]
        gpu_timing::measured(world, &arrived);
        // The lights' `V` at the sampled receivers of an earlier GPU frame, where it is probed.
        #[cfg(feature = "gpu")]
        gpu_probe::begin_frame(world);
        world.insert_resource(CoreClock(std::time::Instant::now()));
        self.schedule.run(world);
        let stats = world.resource::<FrameStats>().clone();
        #[cfg(feature = "gpu")]
        if let Some(mut t) = world.get_resource_mut::<GpuTiming>() {
            t.end_run(&stats.lights);
        }
        #[cfg(feature = "gpu")]
        gpu_probe::end_frame(world, &stats);
        #[cfg(feature = "gpu")]
        gpu_timing::end_frame(world);
        // A GPU frame that reads nothing back times only its recording of the lights' work:
        // its lights calibrate by their device times, where a `GpuTiming` brings them.
        let timed = !on_gpu || settings.evaluate_receivers;
        #[cfg(feature = "gpu")]
        let measuring = timed || gpu_timing::timing(world);
        #[cfg(not(feature = "gpu"))]
        let measuring = timed;
        // A measuring frame whose budget bought no light its maps measures no generation; its
        // lights that keep their maps measure their evaluations.
        let priced_out = measuring && budget::priced_out(world);
        let measured = |lights: &[LightStats]| {
            lights
                .iter()
                .any(|l| l.receivers_evaluated > 0 && l.profile_ms.is_some())
        };
        let evaluated = timed && measured(&stats.lights);
        #[cfg(feature = "gpu")]
        let evaluated = evaluated || arrived.iter().any(|l| measured(l));
        if settings.calibrating {
            let mut calibration = world.resource_mut::<Calibration>();
            calibration.update(&stats, timed);
            #[cfg(feature = "gpu")]
            for lights in &arrived {
                calibration.update_gpu(lights);
            }
            if priced_out {
                calibration.relax(!evaluated);
            }
        }
        stats
    }
}

/// The core sets and systems.
fn core_schedule() -> Schedule {
    let mut schedule = Schedule::default();
    schedule.configure_sets((CoreSet::Track, CoreSet::Resolve, CoreSet::Stale).chain());
    schedule.add_systems((
        (tracking::track_casters, tracking::check_receivers).in_set(CoreSet::Track),
        (
            tracking::keep_budgets,
            tracking::resolve_techniques,
            budget::share_budget,
        )
            .chain()
            .in_set(CoreSet::Resolve),
        tracking::mark_stale_noting.in_set(CoreSet::Stale),
    ));
    // The core sets' own wall time, in `FrameStats::core` (the pipeline's cost beyond the
    // techniques' systems).
    schedule.add_systems((
        core_clock::<0>
            .in_set(CoreSet::Track)
            .after(tracking::track_casters)
            .after(tracking::check_receivers),
        core_clock::<1>
            .in_set(CoreSet::Resolve)
            .after(budget::share_budget),
        core_clock::<2>
            .in_set(CoreSet::Stale)
            .after(tracking::mark_stale_noting),
    ));
    schedule
}

/// When the last core set ended (or the frame's schedule started).
#[derive(Resource)]
struct CoreClock(std::time::Instant);

/// Records the wall time since the last core set ended (or the schedule started) as core set
/// `SET`'s ([`CoreSet`]'s order) in [`FrameStats::core`].
fn core_clock<const SET: usize>(clock: Option<ResMut<CoreClock>>, mut stats: ResMut<FrameStats>) {
    let Some(mut clock) = clock else { return };
    let now = std::time::Instant::now();
    let ms = (now - clock.0).as_secs_f64() * 1e3;
    let core = &mut stats.core;
    *[&mut core.track_ms, &mut core.resolve_ms, &mut core.stale_ms][SET] += ms;
    clock.0 = now;
}

/// Technique `name`'s system in its set, after the core sets, run only when used.
fn add_technique_system(schedule: &mut Schedule, name: &'static str) {
    schedule.configure_sets(TechniqueSet(name).after(CoreSet::Stale));
    let system = move |lights: LightQuery,
                       casters: CasterQuery,
                       index: Res<CasterIndex>,
                       frame: Res<FrameReceivers>,
                       receivers_error: Res<ReceiversError>,
                       backend: Res<FrameBackend>,
                       settings: Res<FrameSettings>,
                       stats: ResMut<FrameStats>,
                       (calibration, mut deadline, mut faces): (
        Res<Calibration>,
        Option<ResMut<deadline::Deadline>>,
        Option<ResMut<faces::FaceRefresh>>,
    ),
                       #[cfg(feature = "gpu")] mut timing: Option<ResMut<GpuTiming>>,
                       #[cfg(feature = "gpu")] mut encoder: Option<
        ResMut<recording::FrameEncoder>,
    >| {
        // A light's generation, its passes timed on the device where a `GpuTiming` is on.
        #[cfg(feature = "gpu")]
        let mut timed = |light: Entity, work: &mut dyn FnMut()| match (
            backend.gpu.as_deref(),
            timing.as_deref_mut(),
        ) {
            (Some(g), Some(t)) => t.time_generation(g, light, work),
            _ => work(),
        };
        #[cfg(not(feature = "gpu"))]
        let mut timed = |_: Entity, work: &mut dyn FnMut()| work();
        // In `run_into`, the generations go into the renderer's encoder.
        #[cfg(feature = "gpu")]
        let recording =
            recording::Recording::into_encoder(&backend, encoder.as_deref_mut().map(|e| &mut e.0));
        #[cfg(not(feature = "gpu"))]
        let recording = recording::Recording::in_context(&backend);
        technique_system::run_technique_timed(
            name,
            (lights, casters, index, frame, receivers_error),
            (
                &backend,
                &settings,
                deadline.as_deref_mut().map(|d| (d, &*calibration)),
            ),
            stats,
            &mut timed,
            (recording, faces.as_deref_mut()),
        )
    };
    let used = move |lights: Query<&ResolvedTechnique>, casters: Query<(), With<ShadowCaster>>| {
        !casters.is_empty() && lights.iter().any(|r| r.technique.name() == name)
    };
    schedule.add_systems(system.in_set(TechniqueSet(name)).run_if(used));
}
