//! What the workspace's tests share: the GPU-test policy.

use soft_shadow_core::GpuContext;

/// A context for the GPU test named `test`, or `None` (after printing why) where no adapter
/// exists and `CI` is not set.
///
/// # Panics
///
/// Where `CI` is set and no adapter can be created: CI runs every GPU test (on lavapipe).
pub fn gpu_for_test(test: &str) -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(ctx) => Some(ctx),
        Err(e) if std::env::var_os("CI").is_some() => {
            panic!(
                "{test}: GPU tests are required in CI (CI is set) but no adapter is available: {e}"
            )
        }
        Err(e) => {
            eprintln!("skipping GPU test {test}: {e}");
            None
        }
    }
}
