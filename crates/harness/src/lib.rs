//! The soft-shadow harness: metrics, the accuracy-vs-time report (`cargo run --release --bin
//! harness -- report`), the papers' experiments and the cost profile, over the ground truth and
//! the scene catalogue of `soft-shadow-reference`.

pub mod animated;
pub mod as_seen;
pub mod error;
pub mod figure;
mod files;
pub mod frames;
pub mod metrics;
pub mod papers;
pub mod profile;
pub mod report;
pub mod setup;
pub mod testing;

/// docs/integration.md, whose code examples compile as doc-tests.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/integration.md")]
pub struct IntegrationDoc;
