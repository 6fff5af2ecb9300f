//! The one error type of the library: every failure on user input names its problem.

use thiserror::Error;

/// Everything that can go wrong in generation, evaluation, import or GPU set-up.
///
/// Library code never panics on user input; it returns one of these instead.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ShadowError {
    /// A glTF/GLB file could not be parsed or holds something this library does not read.
    #[error("glTF import failed ({source_name}): {reason}")]
    Gltf {
        /// File name or label of the input.
        source_name: String,
        /// What is wrong with it.
        reason: String,
    },
    /// An I/O error while reading an input file.
    #[error("cannot read {path}")]
    Io {
        /// The path that failed.
        path: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A mesh holds a NaN or infinite coordinate, or an index out of range.
    #[error("invalid mesh {mesh}: {reason}")]
    InvalidMesh {
        /// Name of the mesh.
        mesh: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A light parameter is out of its domain (zero or negative size, NaN, zero direction, ...).
    #[error("invalid light: {0}")]
    InvalidLight(String),
    /// A map resolution of 0, or above what the device or the CPU path accepts.
    #[error("invalid resolution {requested}: must be in 1..={max}")]
    InvalidResolution {
        /// The resolution asked for.
        requested: u32,
        /// The largest accepted resolution.
        max: u32,
    },
    /// A configuration would allocate more than its context's memory budget
    /// ([`crate::memory`]).
    #[error(
        "{what} needs about {} of memory, over the {} budget of its context",
        crate::memory::human(*.need),
        crate::memory::human(*.budget)
    )]
    OverBudget {
        /// The configuration.
        what: String,
        /// Estimated bytes.
        need: u64,
        /// The budget in bytes.
        budget: u64,
    },
    /// A technique was asked for a light kind it does not model.
    #[error("technique {technique} does not model {light} lights")]
    UnsupportedLight {
        /// The technique's name.
        technique: String,
        /// The light kind asked for.
        light: &'static str,
    },
    /// The scene has no shadow casters, no receivers, or no camera where one is needed.
    #[error("invalid scene: {0}")]
    InvalidScene(String),
    /// Receiver positions and normals differ in length, or hold non-finite values.
    #[error("invalid receivers: {0}")]
    InvalidReceivers(String),
    /// A technique parameter is out of its documented range (names the parameter and the value).
    #[error("invalid parameter: {0}")]
    InvalidParameter(String),
    /// Maps handed to an evaluation step were produced for another backend or technique.
    #[error("maps mismatch: {0}")]
    MapsMismatch(String),
    /// No GPU adapter could be found (or none matches `WGPU_ADAPTER_NAME`).
    #[error("no GPU adapter: {0}")]
    NoAdapter(String),
    /// The device could not be created, or a GPU operation failed.
    #[error("GPU error: {0}")]
    Gpu(String),
}

/// Shorthand for results of this library.
pub type Result<T> = std::result::Result<T, ShadowError>;
