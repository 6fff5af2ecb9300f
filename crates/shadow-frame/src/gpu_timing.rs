//! The GPU frame's device time, read back a few frames late without waiting.
//!
//! On the GPU backend the lights' work runs on the device: the wall time the pipeline can
//! measure is only the recording of it. With a [`GpuTiming`] in the world, every pass a light
//! records (its maps' generation in [`crate::FramePipeline::run`], its `V` in
//! [`crate::gpu_frame::record_visibility`]) writes timestamps; `record_visibility` resolves them
//! into your encoder, [`crate::gpu_frame::submitted`] (after you submit it) asks for them back, and a
//! later frame's `run` takes what has arrived: the lights' device times
//! ([`GpuTiming::latest`]), which then calibrate `Auto` and the shared budget
//! ([`crate::Calibration`]) in device milliseconds, as the CPU frames calibrate in wall time.
//!
//! The cost: two timestamps per pass, one resolve and one copy of at most
//! `16 * TIMED_PASSES` bytes per frame, and one small buffer mapped per frame (the only
//! readback; without a [`GpuTiming`] the GPU frame reads nothing back). Nothing waits: a frame
//! whose times have not arrived is read by a later `run`, and when all [`TIMING_FRAMES`] slots
//! are still on their way a frame goes untimed. Needs [`wgpu::Features::TIMESTAMP_QUERY`]; on a
//! device without it nothing is timed and [`GpuTiming::latest`] stays `None`.

use crate::stats::LightStats;
use bevy_ecs::prelude::*;
use soft_shadow_core::GpuContext;
use soft_shadow_core::gpu::timer::{PassTimestamps, pass_durations};
use std::ops::Range;
use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

/// Frames whose timestamps can be on their way back at once.
pub const TIMING_FRAMES: usize = 3;

/// Passes one frame can time (all its lights' generation and `V` passes together); a frame that
/// records more goes untimed ([`GpuTiming::untimed`]).
pub const TIMED_PASSES: u32 = 2048;

/// One light's device time in a frame, milliseconds: the sum of its passes' durations (copies
/// and clears outside passes are not counted).
#[derive(Clone, Debug, PartialEq)]
pub struct GpuLightTimes {
    /// The light entity.
    pub light: Entity,
    /// Its technique's name and variant, `name variant`.
    pub technique: String,
    /// Its maps' generation (`None`: it made none that frame, or they went untimed).
    pub generate_ms: Option<f64>,
    /// Its `V` over your G-buffer (`None`: not recorded that frame, or untimed).
    pub evaluate_ms: Option<f64>,
}

/// The device times of one frame's lights.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GpuFrameTimes {
    /// The frame they were measured in ([`crate::FrameStats::frame`]).
    pub frame: u64,
    /// Every light the frame ran, in the order it ran them.
    pub lights: Vec<GpuLightTimes>,
}

/// Times the GPU frame's lights on the device (see the module docs): insert one into the world
/// to turn it on, and call [`crate::gpu_frame::submitted`] after each submission of the encoder
/// [`crate::gpu_frame::record_visibility`] recorded into.
#[derive(Resource, Default)]
pub struct GpuTiming {
    /// The slots, made on the first GPU frame (empty without timestamps).
    slots: Vec<Slot>,
    /// The device they were made on.
    device: Option<wgpu::Device>,
    /// The slot this frame records into.
    current: Option<usize>,
    /// The newest frame whose times arrived.
    latest: Option<GpuFrameTimes>,
    /// Frames that went untimed (every slot on its way back, or too many passes).
    untimed: u64,
}

/// Where a slot is between its frame and its times.
#[derive(Default)]
enum SlotState {
    /// Ready for a frame.
    #[default]
    Free,
    /// Its frame's passes are writing into it.
    Recording,
    /// Resolved into an encoder not yet submitted (as far as it knows).
    Resolved,
    /// Its readback asked for: 0 on the way, 1 mapped, 2 failed.
    Mapping(Arc<AtomicU8>),
}

/// One frame's timestamps, the buffers they come back through, and whose passes they are.
struct Slot {
    stamps: PassTimestamps,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    state: SlotState,
    /// The frame it holds.
    frame: u64,
    /// The queries each light's generation and `V` wrote.
    generate: Vec<(Entity, Range<u32>)>,
    evaluate: Vec<(Entity, Range<u32>)>,
    /// The frame's lights as the pipeline saw them, and the texels a `V` pass covered.
    lights: Vec<LightStats>,
    texels: usize,
    /// Some pass went untimed.
    overflow: bool,
}

impl Slot {
    fn new(gpu: &GpuContext, stamps: PassTimestamps) -> Self {
        let bytes = 16 * u64::from(TIMED_PASSES);
        let buffer = |label: &str, usage| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            stamps,
            resolve: buffer(
                "frame timestamps",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: buffer(
                "frame timestamps readback",
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            state: SlotState::Free,
            frame: 0,
            generate: Vec::new(),
            evaluate: Vec::new(),
            lights: Vec::new(),
            texels: 0,
            overflow: false,
        }
    }

    /// The lights' times from the mapped readback, as frame statistics lines (device times
    /// in place of wall times) and as [`GpuFrameTimes`].
    fn read(&mut self, period: f32) -> (Vec<LightStats>, GpuFrameTimes) {
        let used = self.stamps.used();
        let ticks: Vec<u64> = match self.readback.get_mapped_range(0..8 * u64::from(used)) {
            Ok(bytes) => bytemuck::pod_collect_to_vec(&bytes),
            Err(_) => Vec::new(),
        };
        self.readback.unmap();
        let ms = |ranges: &[(Entity, Range<u32>)], light: Entity| -> Option<f64> {
            let mut found = false;
            let mut ns = 0.0;
            for (_, r) in ranges.iter().filter(|(e, _)| *e == light) {
                let r = r.start as usize..r.end as usize;
                ns += pass_durations(ticks.get(r)?, period).sum::<f64>();
                found = true;
            }
            (found && ns.is_finite()).then_some(ns * 1e-6)
        };
        let mut stats = Vec::new();
        let mut times = GpuFrameTimes {
            frame: self.frame,
            lights: Vec::new(),
        };
        for l in &self.lights {
            let generate_ms = if l.views_generated > 0 {
                ms(&self.generate, l.light)
            } else {
                None
            };
            let evaluate_ms = ms(&self.evaluate, l.light);
            times.lights.push(GpuLightTimes {
                light: l.light,
                technique: l.technique.clone(),
                generate_ms,
                evaluate_ms,
            });
            let mut s = l.clone();
            s.generate_ms = generate_ms.unwrap_or(0.0);
            s.evaluate_ms = evaluate_ms.unwrap_or(0.0);
            s.ms = s.generate_ms + s.evaluate_ms;
            if generate_ms.is_none() {
                s.views_generated = 0;
            }
            s.receivers_evaluated = if evaluate_ms.is_some() {
                self.texels
            } else {
                0
            };
            stats.push(s);
        }
        (stats, times)
    }
}

impl GpuTiming {
    /// The newest frame whose device times have come back (`None` before any, or on a device
    /// without timestamps).
    pub fn latest(&self) -> Option<&GpuFrameTimes> {
        self.latest.as_ref()
    }

    /// Frames that went untimed: every slot was still on its way back (call
    /// [`crate::gpu_frame::submitted`] after each submission), or a frame recorded more than
    /// [`TIMED_PASSES`] passes.
    pub fn untimed(&self) -> u64 {
        self.untimed
    }

    /// The timing half of [`crate::gpu_frame::submitted`], which calls it with the probe's.
    #[deprecated(
        note = "call `gpu_frame::submitted(world)`, which asks back the timestamps and the \
                probe's `V` together"
    )]
    pub fn submitted(&mut self) {
        self.ask_back();
    }

    /// After a submission of an encoder [`crate::gpu_frame::record_visibility`] recorded into:
    /// asks for the oldest resolved frame's timestamps back (mapped when the device is done
    /// with them; a later [`crate::FramePipeline::run`] takes them). A frame never reported
    /// submitted holds its slot: with every slot held, frames go untimed
    /// ([`GpuTiming::untimed`]).
    pub(crate) fn ask_back(&mut self) {
        let oldest = self
            .slots
            .iter_mut()
            .filter(|s| matches!(s.state, SlotState::Resolved))
            .min_by_key(|s| s.frame);
        if let Some(slot) = oldest {
            let bytes = 8 * u64::from(slot.stamps.used().max(2));
            slot.state = SlotState::Mapping(map_read(&slot.readback, 0..bytes));
        }
    }

    /// Whether this frame's passes are being timed.
    pub fn timing(&self) -> bool {
        self.current
            .and_then(|i| self.slots.get(i))
            .is_some_and(|s| matches!(s.state, SlotState::Recording))
    }

    /// Starts frame `frame` on `gpu`: takes the times that have arrived (each frame's as
    /// statistics lines for the calibration, the newest frame's also as
    /// [`GpuTiming::latest`]) and, where `timed`, picks the slot this frame records into.
    fn begin(&mut self, gpu: &GpuContext, frame: u64, timed: bool) -> Vec<Vec<LightStats>> {
        self.current = None;
        if timed && self.device.as_ref() != Some(&gpu.device) {
            self.slots = (0..TIMING_FRAMES)
                .map_while(|_| PassTimestamps::new(gpu, "frame timestamps", TIMED_PASSES))
                .map(|s| Slot::new(gpu, s))
                .collect();
            self.device = Some(gpu.device.clone());
        }
        if self.slots.is_empty() || self.device.as_ref() != Some(&gpu.device) {
            return Vec::new();
        }
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        let period = gpu.queue.get_timestamp_period();
        let mut arrived = Vec::new();
        for slot in &mut self.slots {
            match &slot.state {
                // A frame recorded but never resolved (no `record_visibility`): nothing of it
                // reaches the device's timestamps in order.
                SlotState::Recording => slot.state = SlotState::Free,
                SlotState::Mapping(flag) => match flag.load(Ordering::Acquire) {
                    0 => {}
                    1 => {
                        let (stats, times) = slot.read(period);
                        arrived.push((slot.frame, stats, times));
                        slot.state = SlotState::Free;
                    }
                    _ => slot.state = SlotState::Free,
                },
                SlotState::Free | SlotState::Resolved => {}
            }
        }
        arrived.sort_by_key(|(f, ..)| *f);
        let mut lines = Vec::new();
        for (f, stats, times) in arrived {
            if self.latest.as_ref().is_none_or(|l| l.frame < f) {
                self.latest = Some(times);
            }
            // The first frame allocates every map and warms every cache: as on the CPU, it
            // calibrates nothing.
            if f > 1 {
                lines.push(stats);
            }
        }
        if !timed {
            return lines;
        }
        self.current = self
            .slots
            .iter()
            .position(|s| matches!(s.state, SlotState::Free));
        match self.current {
            Some(i) => {
                let slot = &mut self.slots[i];
                slot.stamps.reset();
                slot.state = SlotState::Recording;
                slot.frame = frame;
                slot.generate.clear();
                slot.evaluate.clear();
                slot.lights.clear();
                slot.texels = 0;
                slot.overflow = false;
            }
            None => self.untimed += 1,
        }
        lines
    }

    /// The slot this frame records into, while it does.
    fn recording(&mut self) -> Option<&mut Slot> {
        let slot = self.slots.get_mut(self.current?)?;
        matches!(slot.state, SlotState::Recording).then_some(slot)
    }

    /// Runs `work` (light `light`'s generation) with its passes timed into this frame's slot.
    pub(crate) fn time_generation<T>(
        &mut self,
        gpu: &GpuContext,
        light: Entity,
        work: impl FnOnce() -> T,
    ) -> T {
        self.time(gpu, light, work, false)
    }

    /// Runs `work` (light `light`'s `V` pass) with its passes timed into this frame's slot.
    pub(crate) fn time_visibility<T>(
        &mut self,
        gpu: &GpuContext,
        light: Entity,
        work: impl FnOnce() -> T,
    ) -> T {
        self.time(gpu, light, work, true)
    }

    fn time<T>(
        &mut self,
        gpu: &GpuContext,
        light: Entity,
        work: impl FnOnce() -> T,
        evaluate: bool,
    ) -> T {
        let Some(slot) = self.recording() else {
            return work();
        };
        let (out, used) = gpu.time_passes_into(&slot.stamps, work);
        match used {
            Some(r) if evaluate => slot.evaluate.push((light, r)),
            Some(r) => slot.generate.push((light, r)),
            None => slot.overflow = true,
        }
        out
    }

    /// Keeps the frame's lights as the pipeline saw them (their predictions), for when their
    /// times arrive.
    pub(crate) fn end_run(&mut self, lights: &[LightStats]) {
        if let Some(slot) = self.recording() {
            slot.lights = lights.to_vec();
        }
    }

    /// Records the resolve of this frame's timestamps into `enc`, after its `V` passes over
    /// `texels` texels each.
    pub(crate) fn resolve(&mut self, enc: &mut wgpu::CommandEncoder, texels: usize) {
        let Some(slot) = self.recording() else {
            return;
        };
        let used = slot.stamps.used();
        if slot.overflow {
            slot.state = SlotState::Free;
            self.untimed += 1;
            return;
        }
        if used > 0 {
            enc.resolve_query_set(slot.stamps.query_set(), 0..used, &slot.resolve, 0);
            enc.copy_buffer_to_buffer(&slot.resolve, 0, &slot.readback, 0, 8 * u64::from(used));
        }
        slot.texels = texels;
        slot.state = SlotState::Resolved;
    }
}

/// Starts frame `frame` of `world` for its [`GpuTiming`], if it holds one: the lines of the
/// frames whose times arrived, one list per frame, for the calibration. The frame is timed
/// on the GPU backend with [`crate::FrameSettings::evaluate_receivers`] off and a device that
/// has timestamps; otherwise (the receivers evaluated: their wall time calibrates, as on the
/// CPU) nothing of it is.
pub(crate) fn begin_frame(world: &mut World, frame: u64) -> Vec<Vec<LightStats>> {
    let backend = world.resource::<crate::FrameBackend>();
    let Some(gpu) = backend
        .gpu
        .clone()
        .filter(|_| backend.backend == soft_shadow_core::Backend::Gpu)
    else {
        // A CPU frame records into no slot.
        if let Some(mut t) = world.get_resource_mut::<GpuTiming>() {
            t.current = None;
        }
        return Vec::new();
    };
    let timed = !world.resource::<crate::FrameSettings>().evaluate_receivers;
    match world.get_resource_mut::<GpuTiming>() {
        Some(mut t) => t.begin(&gpu, frame, timed),
        None => Vec::new(),
    }
}

/// The lights of the frames whose device times arrived (`arrived`) that made their maps then:
/// their device time (generation and `V`) becomes what `Auto` holds to its budget
/// ([`crate::LightState::generated_ms`], read by [`crate::tracking::keep_budgets`]).
pub(crate) fn measured(world: &mut World, arrived: &[Vec<LightStats>]) {
    for l in arrived.iter().flatten().filter(|l| l.views_generated > 0) {
        if let Some(mut state) = world.get_mut::<crate::LightState>(l.light) {
            state.generated_ms = Some(l.generate_ms + l.evaluate_ms);
        }
    }
}

/// Whether this frame's passes are timed on the device.
pub(crate) fn timing(world: &World) -> bool {
    world
        .get_resource::<GpuTiming>()
        .is_some_and(GpuTiming::timing)
}

/// After a frame whose passes are timed on the device: the wall time the lights' generation
/// took there is only its recording, not what `Auto` holds to its budget; the device's comes
/// with its timestamps ([`measured`]).
pub(crate) fn end_frame(world: &mut World) {
    if world
        .get_resource::<GpuTiming>()
        .is_some_and(GpuTiming::timing)
    {
        forget_wall_times(world);
    }
}

/// Forgets the wall times the frame's lights measured for their generation
/// ([`crate::LightState::generated_ms`]): on the GPU, where the frame only recorded it, they
/// are not what `Auto` holds to its budget.
pub(crate) fn forget_wall_times(world: &mut World) {
    let mut states = world.query::<&mut crate::LightState>();
    for mut s in states.iter_mut(world) {
        s.generated_ms = None;
    }
}

/// Asks for `range` of `buffer` to be mapped for reading, without waiting: the flag turns 1
/// once it is mapped, 2 if the mapping failed (0 while on its way; a later poll of the device
/// moves it).
pub(crate) fn map_read(buffer: &wgpu::Buffer, range: Range<u64>) -> Arc<AtomicU8> {
    let flag = Arc::new(AtomicU8::new(0));
    let f = flag.clone();
    buffer.map_async(wgpu::MapMode::Read, range, move |r| {
        f.store(if r.is_ok() { 1 } else { 2 }, Ordering::Release);
    });
    flag
}
