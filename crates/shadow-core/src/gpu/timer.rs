//! Device time of GPU work from timestamp queries.
//!
//! While [`GpuContext::gpu_time`] runs its closure, every compute or render pass recorded with
//! [`GpuContext::pass_slot`] writes a timestamp at its beginning and end; the result is the sum of
//! those pass durations: the time the device spent executing the work's passes, without the
//! host's submit-and-wait round trips, allocations or idle gaps. Copies, clears and buffer writes
//! outside passes are not counted. Needs [`wgpu::Features::TIMESTAMP_QUERY`] (requested when the
//! adapter has it); without it, or when the work records more than [`MAX_TIMED_PASSES`] passes,
//! the time is `None` and callers fall back to wall time.

use super::GpuContext;
use crate::error::{Result, ShadowError};
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Duration;

/// Most passes one [`GpuContext::gpu_time`] call can time.
pub const MAX_TIMED_PASSES: u32 = 2048;

/// The query set of one timing and the next free query.
pub(super) struct TimerState {
    set: wgpu::QuerySet,
    next: AtomicU32,
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

    /// The timestamp queries for the next pass while [`gpu_time`](Self::gpu_time) runs on this
    /// context; `None` otherwise (the pass is then recorded without timestamps).
    pub fn pass_slot(&self) -> Option<PassSlot> {
        let state = self
            .timer
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()?;
        let index = state.next.fetch_add(2, Ordering::Relaxed);
        (index + 1 < MAX_TIMED_PASSES * 2).then_some(PassSlot { state, index })
    }

    /// A compute pass on `enc`, timed while [`gpu_time`](Self::gpu_time) runs.
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

    /// Runs `work` and returns its output with the device time of the passes it recorded on this
    /// context (see the module docs); `None` without timestamp support or past
    /// [`MAX_TIMED_PASSES`]. Work recorded by other threads on this context meanwhile is counted
    /// too: time one piece of work at a time.
    pub fn gpu_time<T>(&self, work: impl FnOnce() -> Result<T>) -> Result<(T, Option<Duration>)> {
        if !self.has_timestamps() {
            return work().map(|t| (t, None));
        }
        // One query set per context, reused by every timing.
        let state = self.cached(|c| TimerState {
            set: c.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: MAX_TIMED_PASSES * 2,
            }),
            next: AtomicU32::new(0),
        });
        state.next.store(0, Ordering::Relaxed);
        *self.timer.lock().unwrap_or_else(|e| e.into_inner()) = Some(state.clone());
        let out = work();
        *self.timer.lock().unwrap_or_else(|e| e.into_inner()) = None;
        let out = out?;
        let used = state.next.load(Ordering::Relaxed);
        if used == 0 {
            return Ok((out, Some(Duration::ZERO)));
        }
        if used > MAX_TIMED_PASSES * 2 {
            return Ok((out, None));
        }
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
        let period = f64::from(self.queue.get_timestamp_period());
        let ns: f64 = ticks
            .chunks_exact(2)
            .map(|p| p[1].saturating_sub(p[0]) as f64 * period)
            .sum();
        if !ns.is_finite() {
            return Err(ShadowError::Gpu(format!("timestamp sum {ns} ns")));
        }
        Ok((out, Some(Duration::from_nanos(ns as u64))))
    }
}
