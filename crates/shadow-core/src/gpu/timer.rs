//! Device time of GPU work from timestamp queries.
//!
//! While [`GpuContext::gpu_time`] runs its closure, every compute or render pass recorded with
//! [`GpuContext::pass_slot`] writes a timestamp at its beginning and end; the result is the sum of
//! those pass durations: the time the device spent executing the work's passes, without the
//! host's submit-and-wait round trips, allocations or idle gaps. Copies, clears and buffer writes
//! outside passes are not counted. Needs [`wgpu::Features::TIMESTAMP_QUERY`] (requested when the
//! adapter has it); without it, or when the work records more than [`MAX_TIMED_PASSES`] passes,
//! the time is `None` and callers fall back to wall time.
//!
//! [`GpuContext::gpu_time`] waits for the device. A frame that must not wait writes its passes'
//! timestamps into its own [`PassTimestamps`] with [`GpuContext::time_passes_into`], resolves them
//! into its command encoder and reads them back frames later ([`pass_durations`] turns the ticks
//! into durations).

use super::GpuContext;
use crate::error::{Result, ShadowError};
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Duration;

/// Most passes one [`GpuContext::gpu_time`] call can time.
pub const MAX_TIMED_PASSES: u32 = 2048;

/// The query set of one timing, its size in queries, and the next free query.
pub(super) struct TimerState {
    set: wgpu::QuerySet,
    capacity: u32,
    next: AtomicU32,
}

impl TimerState {
    fn new(c: &GpuContext, label: &str, passes: u32) -> Self {
        TimerState {
            set: c.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some(label),
                ty: wgpu::QueryType::Timestamp,
                count: passes * 2,
            }),
            capacity: passes * 2,
            next: AtomicU32::new(0),
        }
    }
}

/// Timestamp queries, two per pass, that the passes recorded under
/// [`GpuContext::time_passes_into`] write, for a caller that resolves and reads them itself
/// (without waiting for the device, as [`GpuContext::gpu_time`] does).
pub struct PassTimestamps {
    state: Arc<TimerState>,
}

impl PassTimestamps {
    /// Queries for `passes` passes on `ctx`'s device; `None` where the device has no
    /// [`wgpu::Features::TIMESTAMP_QUERY`] or `passes` is 0 or more than [`MAX_TIMED_PASSES`].
    pub fn new(ctx: &GpuContext, label: &str, passes: u32) -> Option<Self> {
        (ctx.has_timestamps() && (1..=MAX_TIMED_PASSES).contains(&passes)).then(|| Self {
            state: Arc::new(TimerState::new(ctx, label, passes)),
        })
    }

    /// The query set, to resolve (`resolve_query_set(set, 0..used, ...)`).
    pub fn query_set(&self) -> &wgpu::QuerySet {
        &self.state.set
    }

    /// The queries written so far (an even count: every pass writes its beginning and end),
    /// at most the set's size.
    pub fn used(&self) -> u32 {
        self.state
            .next
            .load(Ordering::Relaxed)
            .min(self.state.capacity)
    }

    /// Starts again from the first query (once what was written is resolved).
    pub fn reset(&self) {
        self.state.next.store(0, Ordering::Relaxed);
    }
}

/// The durations of the passes whose timestamps `ticks` holds in pairs (beginning, end), in
/// nanoseconds: `period` nanoseconds per tick (`wgpu::Queue::get_timestamp_period`). A pair
/// whose end is before its beginning counts 0.
pub fn pass_durations(ticks: &[u64], period: f32) -> impl Iterator<Item = f64> + '_ {
    ticks
        .chunks_exact(2)
        .map(move |p| p[1].saturating_sub(p[0]) as f64 * f64::from(period))
}

/// The two timestamp queries of one pass: pass its writes to the pass descriptor.
pub struct PassSlot {
    state: Arc<TimerState>,
    index: u32,
}

impl PassSlot {
    /// Timestamp writes for a compute pass descriptor.
    pub fn compute_writes(&self) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.state.set,
            beginning_of_pass_write_index: Some(self.index),
            end_of_pass_write_index: Some(self.index + 1),
        }
    }

    /// Timestamp writes for a render pass descriptor.
    pub fn render_writes(&self) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.state.set,
            beginning_of_pass_write_index: Some(self.index),
            end_of_pass_write_index: Some(self.index + 1),
        }
    }
}

impl GpuContext {
    /// Whether this device records timestamps, so [`gpu_time`](Self::gpu_time) measures device
    /// time.
    pub fn has_timestamps(&self) -> bool {
        self.device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
    }

    /// The timestamp queries for the next pass while [`gpu_time`](Self::gpu_time) or
    /// [`time_passes_into`](Self::time_passes_into) runs on this
    /// context; `None` otherwise (the pass is then recorded without timestamps).
    pub fn pass_slot(&self) -> Option<PassSlot> {
        let state = self
            .timer
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()?;
        let index = state.next.fetch_add(2, Ordering::Relaxed);
        (index + 1 < state.capacity).then_some(PassSlot { state, index })
    }

    /// A compute pass on `enc`, timed while [`gpu_time`](Self::gpu_time) or
    /// [`time_passes_into`](Self::time_passes_into) runs.
    pub fn begin_compute_pass<'e>(
        &self,
        enc: &'e mut wgpu::CommandEncoder,
        label: &str,
    ) -> wgpu::ComputePass<'e> {
        let slot = self.pass_slot();
        enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: slot.as_ref().map(PassSlot::compute_writes),
        })
    }

    /// Runs `work` with every pass it records on this context ([`GpuContext::pass_slot`])
    /// writing its timestamps into `stamps`, after those written before; returns its output and
    /// the queries it wrote (`None` where the set ran out of queries: some passes went
    /// untimed). Nothing waits: resolve the queries after the passes are recorded. Work
    /// recorded by other threads on this context meanwhile writes into `stamps` too; one timing
    /// at a time (this or [`GpuContext::gpu_time`]): the context's passes are untimed after it.
    pub fn time_passes_into<T>(
        &self,
        stamps: &PassTimestamps,
        work: impl FnOnce() -> T,
    ) -> (T, Option<std::ops::Range<u32>>) {
        let start = stamps.state.next.load(Ordering::Relaxed);
        *self.timer.lock().unwrap_or_else(|e| e.into_inner()) = Some(stamps.state.clone());
        let out = work();
        *self.timer.lock().unwrap_or_else(|e| e.into_inner()) = None;
        let end = stamps.state.next.load(Ordering::Relaxed);
        (out, (end <= stamps.state.capacity).then_some(start..end))
    }

    /// Runs `work` and returns its output with the device time of the passes it recorded on this
    /// context (see the module docs); `None` without timestamp support or past
    /// [`MAX_TIMED_PASSES`]. Work recorded by other threads on this context meanwhile is counted
    /// too: time one piece of work at a time.
    pub fn gpu_time<T>(&self, work: impl FnOnce() -> Result<T>) -> Result<(T, Option<Duration>)> {
        if !self.has_timestamps() {
            return work().map(|t| (t, None));
        }
        // One query set per context, reused by every timing.
        let state = self.cached(|c| TimerState::new(c, "pass timestamps", MAX_TIMED_PASSES));
        state.next.store(0, Ordering::Relaxed);
        let stamps = PassTimestamps { state };
        let (out, used) = self.time_passes_into(&stamps, work);
        let out = out?;
        let Some(used) = used else {
            return Ok((out, None));
        };
        let used = used.end;
        if used == 0 {
            return Ok((out, Some(Duration::ZERO)));
        }
        let state = &stamps.state;
        let bytes = u64::from(used) * 8;
        let resolve = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps"),
            size: bytes,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.resolve_query_set(&state.set, 0..used, &resolve, 0);
        self.queue.submit([enc.finish()]);
        let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&self.read_buffer(&resolve, bytes)?);
        let ns: f64 = pass_durations(&ticks, self.queue.get_timestamp_period()).sum();
        if !ns.is_finite() {
            return Err(ShadowError::Gpu(format!("timestamp sum {ns} ns")));
        }
        Ok((out, Some(Duration::from_nanos(ns as u64))))
    }
}
