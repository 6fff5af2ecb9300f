//! Reuse of large CPU buffers across generations of one size: the pool a [`crate::CpuContext`]
//! owns, keyed by element type and length.
//!
//! A generation at 2048² writes maps of 4 M texels. Freshly allocated, every 4 KiB page of such
//! a map is faulted in and zeroed by the kernel on first touch (about 7 ms per 16 MiB map on a
//! 2-core server), which for the hard shadow map costs as much as rasterizing it. Maps made in a
//! context ([`crate::Map2D::pooled`]) therefore take their texels from its pool and give them
//! back when they are dropped, and scratch buffers ([`Pool::take`], [`Pool::give`]) do the
//! same: the second generation of one size touches no new page. A buffer whose every element
//! its caller writes comes from [`Pool::overwrite`], which skips clearing it (16 MiB of stores
//! at 2048²) when the pool has one.
//!
//! Buffers below [`MIN_BYTES`] are not kept (the allocator serves them from its own free lists).
//! At most [`Pool::limit`] bytes are kept, oldest given back first out; [`Pool::set_limit`]
//! changes it (0 turns the pool off) and [`Pool::clear`] frees everything kept.

use std::any::{Any, TypeId};
use std::collections::VecDeque;
use std::sync::Mutex;

/// Smallest buffer kept, in bytes (a 512² map of `f32` is 1 MiB).
pub const MIN_BYTES: usize = 256 << 10;

struct Entry {
    key: (TypeId, usize),
    bytes: usize,
    buffer: Box<dyn Any + Send>,
}

/// The kept buffers.
struct Kept {
    limit: usize,
    kept: usize,
    entries: VecDeque<Entry>,
}

/// A pool of large CPU buffers (module docs). Shared by the maps made from it, which give their
/// storage back when dropped.
pub struct Pool {
    state: Mutex<Kept>,
}

impl std::fmt::Debug for Pool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Pool")
            .field("limit", &self.limit())
            .field("kept_bytes", &self.kept_bytes())
            .finish()
    }
}

impl Kept {
    const fn new(limit: usize) -> Self {
        Self {
            limit,
            kept: 0,
            entries: VecDeque::new(),
        }
    }

    fn evict_to(&mut self, limit: usize) {
        while self.kept > limit {
            match self.entries.pop_front() {
                Some(e) => self.kept -= e.bytes,
                None => break,
            }
        }
    }

    /// The newest kept vector of `T` with capacity `len`, removed from the pool.
    fn take<T: Send + 'static>(&mut self, len: usize) -> Option<Vec<T>> {
        let key = (TypeId::of::<T>(), len);
        let i = self.entries.iter().rposition(|e| e.key == key)?;
        let e = self.entries.remove(i)?;
        self.kept -= e.bytes;
        e.buffer.downcast::<Vec<T>>().ok().map(|v| *v)
    }

    /// Keeps `v` unless it is small or over the limit (its elements dropped, unless they have
    /// no drop glue: then they stay, for [`overwrite`]); then frees the oldest buffers over the
    /// limit.
    fn give<T: Send + 'static>(&mut self, mut v: Vec<T>) {
        let bytes = v.capacity() * size_of::<T>();
        let limit = self.limit;
        if bytes < MIN_BYTES || bytes > limit {
            return;
        }
        if std::mem::needs_drop::<T>() {
            v.clear();
        }
        self.kept += bytes;
        self.entries.push_back(Entry {
            key: (TypeId::of::<T>(), v.capacity()),
            bytes,
            buffer: Box::new(v),
        });
        self.evict_to(limit);
    }
}

impl Pool {
    /// A pool that keeps at most `limit` bytes.
    pub fn new(limit: usize) -> Self {
        Self {
            state: Mutex::new(Kept::new(limit)),
        }
    }

    fn kept(&self) -> std::sync::MutexGuard<'_, Kept> {
        // A panic while the lock was held leaves only a list of free buffers behind: still valid.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// An empty vector with capacity for exactly `len` elements: a kept one when the pool has
    /// one of this type and length, else a new allocation.
    pub fn take<T: Send + 'static>(&self, len: usize) -> Vec<T> {
        if len * size_of::<T>() >= MIN_BYTES
            && let Some(mut v) = self.kept().take(len)
        {
            v.clear();
            return v;
        }
        Vec::with_capacity(len)
    }

    /// A vector of exactly `len` elements whose values are unspecified, for a caller that
    /// overwrites every one (in parallel, or band by band while in cache): a kept one of this
    /// type and length as it was given back (a type without drop glue keeps its elements
    /// there), without a clearing pass; else `len` clones of `fill` (an all-zero `fill` of a
    /// primitive type allocates zeroed pages, faulted in by whichever thread writes them first).
    pub fn overwrite<T: Clone + Send + 'static>(&self, len: usize, fill: T) -> Vec<T> {
        if len * size_of::<T>() >= MIN_BYTES
            && let Some(mut v) = self.kept().take(len)
        {
            if v.len() != len {
                v.clear();
                v.resize(len, fill);
            }
            return v;
        }
        vec![fill; len]
    }

    /// A vector of `len` copies of `value`, its storage from [`Pool::take`].
    pub fn filled<T: Clone + Send + 'static>(&self, len: usize, value: T) -> Vec<T> {
        let mut v = self.take(len);
        v.resize(len, value);
        v
    }

    /// Gives `v`'s storage back for a later [`Pool::take`] of the same type and capacity (its
    /// elements are dropped); small buffers, and buffers past the [`Pool::limit`], are freed
    /// instead.
    pub fn give<T: Send + 'static>(&self, v: Vec<T>) {
        if v.capacity() * size_of::<T>() >= MIN_BYTES {
            self.kept().give(v);
        }
    }

    /// Most bytes the pool keeps.
    pub fn limit(&self) -> usize {
        self.kept().limit
    }

    /// Keeps at most `bytes` from now on (0: keep nothing), freeing the oldest buffers over it.
    pub fn set_limit(&self, bytes: usize) {
        let mut p = self.kept();
        p.limit = bytes;
        p.evict_to(bytes);
    }

    /// Bytes kept now.
    pub fn kept_bytes(&self) -> usize {
        self.kept().kept
    }

    /// Frees every kept buffer.
    pub fn clear(&self) {
        let mut p = self.kept();
        p.entries.clear();
        p.kept = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn storage_is_reused_by_type_and_length() {
        let mut p = Kept::new(1 << 30);
        let n = MIN_BYTES / 4;
        let a = vec![1.0f32; n];
        let ptr = a.as_ptr();
        p.give(a);
        assert_eq!(p.kept, n * 4);
        // Another length or type does not get it.
        assert!(p.take::<f32>(n + 1).is_none());
        assert!(p.take::<u32>(n).is_none());
        // The same type and length does, elements and all (`f32` has no drop glue).
        let b = p.take::<f32>(n).unwrap();
        assert_eq!((b.as_ptr(), b.len(), b.capacity(), p.kept), (ptr, n, n, 0));
        assert!(b.iter().all(|&v| v == 1.0));
        // Small buffers are not kept.
        p.give(vec![0.0f32; 16]);
        assert_eq!(p.kept, 0);
    }

    #[test]
    fn the_oldest_buffers_go_first_past_the_limit() {
        let n = MIN_BYTES;
        let mut p = Kept::new(3 * n);
        p.give(Vec::<u8>::with_capacity(4 * n));
        assert_eq!(p.kept, 0, "a buffer over the limit is freed");
        for len in [n, n + 1, n + 2, n + 3] {
            p.give(Vec::<u8>::with_capacity(len));
        }
        assert!(p.take::<u8>(n).is_none(), "the oldest was freed");
        assert!(p.take::<u8>(n + 3).is_some());
        assert_eq!(p.kept, n + 2);
        p.limit = 0;
        p.evict_to(0);
        assert_eq!((p.kept, p.entries.len()), (0, 0));
    }

    /// `overwrite` hands a kept buffer back as it was given when its type has no drop glue (no
    /// clearing pass), and refilled when it has; `take` always hands it back empty.
    #[test]
    fn overwrite_keeps_elements_only_without_drop_glue() {
        let pool = Pool::new(1 << 30);
        #[derive(Clone, PartialEq, Debug)]
        struct Plain(u64);
        #[derive(Clone, PartialEq, Debug)]
        struct Owned(Option<Box<u64>>);
        let n = MIN_BYTES / 8;
        let mut a = pool.overwrite(n, Plain(7));
        assert!(a.iter().all(|v| *v == Plain(7)), "fresh storage is filled");
        a[0] = Plain(9);
        let ptr = a.as_ptr();
        pool.give(a);
        let b = pool.overwrite(n, Plain(1));
        assert_eq!(
            (b.as_ptr(), b.len(), &b[0], &b[1]),
            (ptr, n, &Plain(9), &Plain(7))
        );
        pool.give(b);
        let t = pool.take::<Plain>(n);
        assert_eq!((t.as_ptr(), t.len()), (ptr, 0));

        let mut a = pool.overwrite(n, Owned(None));
        a[0] = Owned(Some(Box::new(3)));
        let ptr = a.as_ptr();
        pool.give(a);
        let b = pool.overwrite(n, Owned(None));
        assert_eq!((b.as_ptr(), b.len()), (ptr, n));
        assert!(b.iter().all(|v| *v == Owned(None)), "dropped and refilled");
    }

    #[test]
    fn a_contexts_pool_serves_its_maps() {
        #[derive(Clone, Copy, PartialEq, Debug)]
        struct Probe(f32);
        let cpu = crate::CpuContext::new();
        let m = crate::Map2D::pooled(cpu.pool(), 512, 512, Probe(1.0));
        let ptr = m.data().as_ptr();
        drop(m);
        let again = crate::Map2D::pooled(cpu.pool(), 512, 512, Probe(2.0));
        assert_eq!(again.data().as_ptr(), ptr);
        assert!(again.data().iter().all(|t| *t == Probe(2.0)));
    }
}
