//! This build has no GPU side (the `gpu` feature is off): the GPU context and scene exist only
//! as names without values, so the signatures that mention them (`Context::Gpu`,
//! `Option<&GpuContext>`) read the same in both builds, and no GPU value can ever be made.

/// A GPU context, which this build cannot make (feature `gpu` off): no value of it exists.
#[derive(Debug)]
pub enum GpuContext {}

/// A scene on the GPU, which this build cannot make (feature `gpu` off).
#[derive(Debug)]
pub enum GpuScene {}

impl GpuContext {
    /// The largest texture side: never called, no context exists.
    pub fn max_texture_size(&self) -> u32 {
        match *self {}
    }

    /// The limits that bound a map's side: never called, no context exists.
    pub fn device_limits(&self) -> crate::technique::DeviceLimits {
        match *self {}
    }

    /// The memory budget: never called, no context exists.
    pub fn memory_budget(&self) -> u64 {
        match *self {}
    }
}
