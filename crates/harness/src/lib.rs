//! The soft-shadow harness: ray-traced ground truth, the scene catalogue, metrics and the
//! accuracy-vs-time report (`cargo run --release --bin harness -- report`).

pub mod animated;
pub mod as_seen;
pub mod error;
pub mod figure;
pub mod ground_truth;
pub mod metrics;
pub mod papers;
pub mod profile;
pub mod report;
pub mod scenes;
pub mod setup;
pub mod testing;

/// docs/integration.md, whose code examples compile as doc-tests.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/integration.md")]
pub struct IntegrationDoc;
