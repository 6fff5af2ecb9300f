//! Memory budgets: what one generation may allocate, checked before it allocates.
//!
//! Every technique estimates the bytes of its maps and scratch for a light and a resolution
//! ([`crate::TechniqueInfo::memory_estimate`]); generation refuses a configuration over the
//! budget of the context it runs in ([`crate::CpuContext::memory_budget`],
//! [`crate::GpuContext::memory_budget`]) with [`crate::ShadowError::OverBudget`], naming both.
//!
//! A context starts with [`default_budget`]: [`CPU_SHARE`] of the memory this process may use,
//! the smallest of physical memory (`/proc/meminfo`), the cgroup limit
//! (`/sys/fs/cgroup/memory.max`) and the address-space limit (`/proc/self/limits`); 8 GiB where
//! none of them can be read. On the GPU it is the same share (wgpu does not report a device's
//! memory); the device's own limits (largest buffer, texture side and layers) are checked where
//! each resource is made. A caller sets its own with `with_memory_budget`.

/// Share of the usable memory one generation may take.
pub const CPU_SHARE: f64 = 0.5;

/// Budget where no limit can be read.
const FALLBACK: u64 = 8 << 30;

fn meminfo_total() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

fn cgroup_limit() -> Option<u64> {
    std::fs::read_to_string("/sys/fs/cgroup/memory.max")
        .ok()?
        .trim()
        .parse()
        .ok()
}

fn address_space_limit() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = text.lines().find(|l| l.starts_with("Max address space"))?;
    line.split_whitespace().nth(3)?.parse().ok()
}

/// The memory this process may use: the smallest limit that can be read (read once per
/// process: generation checks it on every call).
pub fn usable_memory() -> Option<u64> {
    static USABLE: std::sync::OnceLock<Option<u64>> = std::sync::OnceLock::new();
    *USABLE.get_or_init(|| {
        [meminfo_total(), cgroup_limit(), address_space_limit()]
            .into_iter()
            .flatten()
            .min()
    })
}

/// The budget a new context starts with (module docs).
pub fn default_budget() -> u64 {
    usable_memory().map_or(FALLBACK, |m| (m as f64 * CPU_SHARE) as u64)
}

/// `bytes` as MiB or GiB for messages.
pub fn human(bytes: u64) -> String {
    if bytes >= 1 << 30 {
        format!("{:.1} GiB", bytes as f64 / (1u64 << 30) as f64)
    } else {
        format!("{:.1} MiB", bytes as f64 / (1u64 << 20) as f64)
    }
}

/// Bytes of `layers` square maps of `resolution²` texels of `texel_bytes` each.
pub fn maps(layers: u64, resolution: u32, texel_bytes: u64) -> u64 {
    layers
        .saturating_mul(resolution as u64 * resolution as u64)
        .saturating_mul(texel_bytes)
}
