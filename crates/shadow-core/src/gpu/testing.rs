//! The GPU-test policy shared by every crate's tests.
//!
//! With `CI` set, a GPU test that cannot get an adapter fails; elsewhere it skips with one line.

use super::GpuContext;

/// A context for a GPU test, or `None` (after printing why) when no adapter exists outside CI.
///
/// # Panics
///
/// When `CI` is set and no adapter can be created: CI must run the GPU tests on lavapipe.
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
