//! The headless wgpu context.

use crate::error::{Result, ShadowError};
use std::any::{Any, TypeId};
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

type Cache = Mutex<HashMap<TypeId, Arc<dyn Any + Send + Sync>>>;

/// The serial number the next context takes.
static NEXT_SERIAL: AtomicU64 = AtomicU64::new(0);

/// A wgpu device and queue, with the pipelines built for them.
///
/// A renderer hands in its own with [`GpuContext::from_device`]. [`GpuContext::new`] makes a
/// headless one, its adapter chosen by the environment: `WGPU_BACKEND` (e.g. `vulkan`) restricts the backends,
/// `WGPU_ADAPTER_NAME` picks the first adapter whose name contains it (case-insensitive), and
/// `WGPU_POWER_PREF` (`low`/`high`) steers the default choice. Without any of them the first adapter
/// wgpu offers is used. No adapter gives [`ShadowError::NoAdapter`].
pub struct GpuContext {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Adapter name, backend and driver.
    pub info: wgpu::AdapterInfo,
    cache: Cache,
    /// The timing in progress ([`GpuContext::gpu_time`]), if any.
    pub(super) timer: Mutex<Option<Arc<super::timer::TimerState>>>,
    geometry_uploads: AtomicU64,
    buffer_maps: AtomicU64,
    waits: AtomicU64,
    memory_budget: AtomicU64,
    pub(super) pool: super::pool::GpuPool,
    /// This context among the process's ([`GpuContext::serial`]).
    serial: u64,
}

impl std::fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuContext")
            .field("adapter", &self.describe())
            .finish()
    }
}

impl GpuContext {
    /// Creates a context from the environment (see the type's docs).
    pub fn new() -> Result<Self> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = match std::env::var("WGPU_ADAPTER_NAME") {
            Ok(wanted) if !wanted.is_empty() => {
                let wanted_lc = wanted.to_lowercase();
                let adapters = instance.enumerate_adapters(wgpu::Backends::all()).await;
                let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
                adapters.into_iter().find(|a| a.get_info().name.to_lowercase().contains(&wanted_lc)).ok_or_else(|| {
                    ShadowError::NoAdapter(format!("no adapter name contains WGPU_ADAPTER_NAME={wanted:?}; found {names:?}"))
                })?
            }
            _ => instance
                .request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::from_env().unwrap_or(wgpu::PowerPreference::HighPerformance),
                    force_fallback_adapter: false,
                    compatible_surface: None,
                    apply_limit_buckets: false,
                })
                .await
                .map_err(|e| {
                    ShadowError::NoAdapter(format!(
                        "{e}; install a Vulkan driver (e.g. `apt-get install mesa-vulkan-drivers` for lavapipe)"
                    ))
                })?,
        };
        let info = adapter.get_info();
        let limits = adapter.limits();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("shadow-core"),
                // Timestamps where the adapter has them: GpuContext::gpu_time measures device time.
                required_features: adapter.features() & wgpu::Features::TIMESTAMP_QUERY,
                required_limits: limits,
                ..Default::default()
            })
            .await
            .map_err(|e| ShadowError::Gpu(format!("request_device on {}: {e}", info.name)))?;
        Self::from_device(device, queue)
    }

    /// Features every kernel needs: none beyond WebGPU's core (timestamps are used when the
    /// device has them).
    pub const REQUIRED_FEATURES: wgpu::Features = wgpu::Features::empty();

    /// Limits every kernel needs: WebGPU's defaults (`wgpu::Limits::defaults()`); the largest
    /// map side is the device's own `max_texture_dimension_2d`, checked per call.
    pub fn required_limits() -> wgpu::Limits {
        wgpu::Limits::defaults()
    }

    /// Wraps a renderer's own device and queue (handles: clones of the renderer's). The device
    /// must have [`GpuContext::REQUIRED_FEATURES`] and at least [`GpuContext::required_limits`];
    /// a missing one is [`ShadowError::Gpu`] naming every feature and limit that falls short.
    /// Pipelines are built on first use and cached in the context, so keep one per device.
    pub fn from_device(device: wgpu::Device, queue: wgpu::Queue) -> Result<Self> {
        let info = device.adapter_info();
        let mut missing = Vec::new();
        let features = Self::REQUIRED_FEATURES - device.features();
        if !features.is_empty() {
            missing.push(format!("features {features:?}"));
        }
        Self::required_limits().check_limits_with_fail_fn(
            &device.limits(),
            false,
            |name, need, have| missing.push(format!("{name} {have} (needs {need})")),
        );
        if !missing.is_empty() {
            return Err(ShadowError::Gpu(format!(
                "the device on {} lacks what the shadow kernels need: {}",
                info.name,
                missing.join(", ")
            )));
        }
        Ok(Self {
            device,
            queue,
            info,
            cache: Mutex::new(HashMap::new()),
            timer: Mutex::new(None),
            geometry_uploads: AtomicU64::new(0),
            buffer_maps: AtomicU64::new(0),
            waits: AtomicU64::new(0),
            memory_budget: AtomicU64::new(crate::memory::default_budget()),
            pool: Default::default(),
            serial: NEXT_SERIAL.fetch_add(1, Ordering::Relaxed),
        })
    }

    /// This context's number among the process's, which no other context shares: what tells
    /// two contexts apart (wgpu compares devices by their ids, which two devices of two
    /// instances can share).
    pub(crate) fn serial(&self) -> u64 {
        self.serial
    }

    /// Bytes one GPU generation may allocate: [`crate::memory::default_budget`] until
    /// [`GpuContext::set_memory_budget`].
    pub fn memory_budget(&self) -> u64 {
        self.memory_budget.load(Ordering::Relaxed)
    }

    /// Sets the bytes one GPU generation may allocate from now on.
    pub fn set_memory_budget(&self, bytes: u64) {
        self.memory_budget.store(bytes, Ordering::Relaxed);
    }

    /// One line naming the adapter, e.g. `"llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan, Cpu)"`.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.info.name, self.info.backend, self.info.device_type
        )
    }

    /// Per-device cache of pipelines and other resources, keyed by type: `init` runs once per
    /// context, later calls return the same value.
    pub fn cached<T: Any + Send + Sync>(&self, init: impl FnOnce(&GpuContext) -> T) -> Arc<T> {
        let key = TypeId::of::<T>();
        let hit = self
            .cache
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&key)
            .cloned();
        if let Some(t) = hit.and_then(|v| v.downcast::<T>().ok()) {
            return t;
        }
        let value = Arc::new(init(self));
        self.cache
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(key, value.clone());
        value
    }

    /// Runs `f` inside validation and out-of-memory error scopes: a wgpu error raised by the work
    /// `f` records becomes [`ShadowError::Gpu`] instead of wgpu's default panic.
    pub fn checked<T>(&self, what: &str, f: impl FnOnce() -> Result<T>) -> Result<T> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        let v = pollster::block_on(validation.pop());
        let m = pollster::block_on(oom.pop());
        if let Some(e) = v.or(m) {
            return Err(ShadowError::Gpu(format!("{what}: {e}")));
        }
        out
    }

    /// How many scenes were uploaded ([`super::GpuScene::new`] and `update`) through this
    /// context: a renderer's static scene uploads once.
    pub fn geometry_uploads(&self) -> u64 {
        self.geometry_uploads.load(Ordering::Relaxed)
    }

    pub(super) fn count_geometry_upload(&self) {
        self.geometry_uploads.fetch_add(1, Ordering::Relaxed);
    }

    /// How many buffers were mapped to read results back through this context (every blocking
    /// evaluation and readback maps one; recorded work maps none).
    pub fn buffer_maps(&self) -> u64 {
        self.buffer_maps.load(Ordering::Relaxed)
    }

    /// Largest 2D texture side of this device.
    pub fn max_texture_size(&self) -> u32 {
        self.device.limits().max_texture_dimension_2d
    }

    /// The limits that bound a map's side on this device
    /// ([`crate::TechniqueInfo::max_resolution`]).
    pub fn device_limits(&self) -> crate::technique::DeviceLimits {
        crate::technique::DeviceLimits::from_limits(&self.device.limits())
    }

    /// How many times [`GpuContext::wait`] blocked for the device (every generation that
    /// submits its own work and every readback waits; recorded work waits for nothing).
    pub fn waits(&self) -> u64 {
        self.waits.load(Ordering::Relaxed)
    }

    /// Blocks until all submitted work has finished.
    pub fn wait(&self) -> Result<()> {
        self.waits.fetch_add(1, Ordering::Relaxed);
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map(|_| ())
            .map_err(|e| ShadowError::Gpu(format!("poll: {e}")))
    }

    /// A buffer of `usage` (plus `COPY_DST`) holding `data`, written through the queue: unlike
    /// wgpu's `create_buffer_init`, which maps the buffer and panics when the device is lost,
    /// this raises a wgpu error that [`GpuContext::checked`] turns into [`ShadowError::Gpu`].
    /// Sizes are rounded up to 4 bytes (at least 4), the tail zeroed.
    pub fn buffer_with(&self, label: &str, data: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
        let size = (data.len() as u64)
            .max(4)
            .next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        if !data.is_empty() {
            let mut padded = data.to_vec();
            padded.resize(size as usize, 0);
            self.queue.write_buffer(&buffer, 0, &padded);
        }
        buffer
    }

    /// A storage buffer initialised with `data`.
    pub fn storage_buffer(&self, label: &str, data: &[u8]) -> wgpu::Buffer {
        self.buffer_with(
            label,
            data,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        )
    }

    /// A uniform buffer initialised with `data`.
    pub fn uniform_buffer(&self, label: &str, data: &[u8]) -> wgpu::Buffer {
        self.buffer_with(label, data, wgpu::BufferUsages::UNIFORM)
    }

    /// Copies `size` bytes of `buffer` (which needs `COPY_SRC`) back to the CPU.
    pub fn read_buffer(&self, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>> {
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        self.queue.submit([enc.finish()]);
        self.map_read(&staging, size)
    }

    /// Maps a `MAP_READ` buffer after the queue has finished and copies it out.
    pub fn map_read(&self, staging: &wgpu::Buffer, size: u64) -> Result<Vec<u8>> {
        self.buffer_maps.fetch_add(1, Ordering::Relaxed);
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, 0..size, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv()
            .map_err(|e| ShadowError::Gpu(format!("map callback lost: {e}")))?
            .map_err(|e| ShadowError::Gpu(format!("map_async: {e}")))?;
        let bytes = staging
            .get_mapped_range(0..size)
            .map_err(|e| ShadowError::Gpu(format!("get_mapped_range: {e}")))?
            .to_vec();
        staging.unmap();
        Ok(bytes)
    }
}
