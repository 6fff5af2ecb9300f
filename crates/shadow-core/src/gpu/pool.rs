//! Reuse of map textures and buffers across generations of one size on a device: the GPU side
//! of [`crate::pool`].
//!
//! Every map and scratch texture of a generation comes from [`GpuContext::texture`] and every
//! scratch buffer from [`GpuContext::buffer`]: a resource given back with
//! [`GpuContext::recycle_texture`] / [`GpuContext::recycle_buffer`] (or, for a technique's
//! maps, [`crate::ShadowTechnique::recycle_gpu`]) serves the next request with the same
//! descriptor (size, layers, mips, format and usage) instead of a new allocation. Work already
//! recorded that uses a recycled resource still runs first: the queue keeps submission order, so
//! a later pass that overwrites it sees the earlier reads done.
//!
//! That order holds within one thread, which records its work and then submits it. A resource
//! is often recycled while the work recorded with it is still in an encoder; another thread
//! could take it, submit first, and have the pending work overwrite its maps. So a resource
//! serves only requests from the thread that gave it back (several threads sharing one context,
//! as the stability suite's tests do, each reuse their own).
//!
//! At most [`MAX_KEPT`] resources are kept per kind, oldest given back first out; nothing is kept
//! past [`GpuContext::clear_pool`].

use super::GpuContext;
use std::collections::VecDeque;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::thread::ThreadId;

/// Most textures, and most buffers, a context keeps for reuse.
pub const MAX_KEPT: usize = 64;

/// Free resources of one kind, each with the thread that gave it back.
type FreeList<T> = Mutex<VecDeque<(ThreadId, T)>>;

/// The free textures and buffers of one context, with creation counters.
#[derive(Default)]
pub(super) struct GpuPool {
    textures: FreeList<wgpu::Texture>,
    buffers: FreeList<wgpu::Buffer>,
    textures_created: AtomicU64,
    buffers_created: AtomicU64,
}

fn keep<T>(list: &FreeList<T>, item: T) {
    let mut l = list.lock().unwrap_or_else(|e| e.into_inner());
    l.push_back((std::thread::current().id(), item));
    while l.len() > MAX_KEPT {
        l.pop_front();
    }
}

/// The newest resource this thread gave back that `fits`, removed from the list.
fn take<T>(list: &FreeList<T>, fits: impl Fn(&T) -> bool) -> Option<T> {
    let me = std::thread::current().id();
    let mut l = list.lock().unwrap_or_else(|e| e.into_inner());
    let i = l.iter().rposition(|(by, t)| *by == me && fits(t))?;
    l.remove(i).map(|(_, t)| t)
}

/// Whether `t` was made with `desc` (the label aside).
fn texture_fits(t: &wgpu::Texture, desc: &wgpu::TextureDescriptor) -> bool {
    t.size() == desc.size
        && t.mip_level_count() == desc.mip_level_count
        && t.sample_count() == desc.sample_count
        && t.dimension() == desc.dimension
        && t.format() == desc.format
        && t.usage() == desc.usage
}

impl GpuContext {
    /// A texture for `desc`: one this thread recycled, made with the same descriptor (its label
    /// and contents are the previous user's), else a new one.
    pub fn texture(&self, desc: &wgpu::TextureDescriptor) -> wgpu::Texture {
        if desc.view_formats.is_empty()
            && let Some(t) = take(&self.pool.textures, |t| texture_fits(t, desc))
        {
            return t;
        }
        self.pool.textures_created.fetch_add(1, Ordering::Relaxed);
        self.device.create_texture(desc)
    }

    /// A buffer for `desc` (never mapped at creation): one this thread recycled, of the same size
    /// and usage (its contents are the previous user's), else a new one.
    pub fn buffer(&self, desc: &wgpu::BufferDescriptor) -> wgpu::Buffer {
        if !desc.mapped_at_creation
            && let Some(b) = take(&self.pool.buffers, |b| {
                b.size() == desc.size && b.usage() == desc.usage
            })
        {
            return b;
        }
        self.pool.buffers_created.fetch_add(1, Ordering::Relaxed);
        self.device.create_buffer(desc)
    }

    /// Gives a texture back for reuse by a later [`GpuContext::texture`]; the caller no longer
    /// reads it (work already recorded with it is unaffected).
    pub fn recycle_texture(&self, texture: wgpu::Texture) {
        keep(&self.pool.textures, texture);
    }

    /// Gives a buffer back for reuse by a later [`GpuContext::buffer`] (as
    /// [`GpuContext::recycle_texture`]). Mappable buffers (readback staging) are not kept.
    pub fn recycle_buffer(&self, buffer: wgpu::Buffer) {
        let mappable = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::MAP_WRITE;
        if !buffer.usage().intersects(mappable) {
            keep(&self.pool.buffers, buffer);
        }
    }

    /// Frees every kept texture and buffer.
    pub fn clear_pool(&self) {
        self.pool
            .textures
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
        self.pool
            .buffers
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
    }

    /// Textures created through [`GpuContext::texture`] so far (not served from the pool).
    pub fn textures_created(&self) -> u64 {
        self.pool.textures_created.load(Ordering::Relaxed)
    }

    /// Buffers created through [`GpuContext::buffer`] so far (not served from the pool).
    pub fn buffers_created(&self) -> u64 {
        self.pool.buffers_created.load(Ordering::Relaxed)
    }
}
