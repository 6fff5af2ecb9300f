//! The CPU context: what CPU generations share across calls, owned by the caller.

use crate::pool::Pool;
use std::any::{Any, TypeId};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

type Cache = Mutex<HashMap<TypeId, Arc<dyn Any + Send + Sync>>>;

/// What CPU generations share: the [`Pool`] of large buffers their maps and scratch reuse, the
/// caches of data derived once per scene (a technique's `cached` state, such as silhouette
/// edges), and the memory budget every generation is checked against.
///
/// The CPU counterpart of [`crate::GpuContext`]: make one, keep it, and hand it to every
/// `generate_cpu`. Two contexts share nothing.
pub struct CpuContext {
    pool: Arc<Pool>,
    memory_budget: u64,
    cache: Cache,
}

impl std::fmt::Debug for CpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CpuContext")
            .field("pool", &self.pool)
            .field("memory_budget", &self.memory_budget)
            .finish()
    }
}

impl Default for CpuContext {
    fn default() -> Self {
        Self::new()
    }
}

impl CpuContext {
    /// A context with the default budget ([`crate::memory::default_budget`]) and a pool that
    /// keeps the smaller of 1 GiB and a quarter of it.
    pub fn new() -> Self {
        Self::with_memory_budget(crate::memory::default_budget())
    }

    /// A context whose generations may allocate at most `bytes` each, with a pool that keeps
    /// the smaller of 1 GiB and a quarter of it.
    pub fn with_memory_budget(bytes: u64) -> Self {
        Self {
            pool: Arc::new(Pool::new((bytes / 4).min(1 << 30) as usize)),
            memory_budget: bytes,
            cache: Mutex::new(HashMap::new()),
        }
    }

    /// Bytes one generation may allocate.
    pub fn memory_budget(&self) -> u64 {
        self.memory_budget
    }

    /// The buffers maps and scratch reuse.
    pub fn pool(&self) -> &Arc<Pool> {
        &self.pool
    }

    /// State kept across generations, keyed by type: `init` runs once per context, later calls
    /// return the same value.
    pub fn cached<T: Any + Send + Sync>(&self, init: impl FnOnce() -> T) -> Arc<T> {
        let key = TypeId::of::<T>();
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = cache.get(&key).and_then(|v| v.clone().downcast::<T>().ok()) {
            return t;
        }
        let value = Arc::new(init());
        cache.insert(key, value.clone());
        value
    }
}
