//! The harness's own error: the library's, or a report that could not be written or measured
//! nothing.

use soft_shadow_core::ShadowError;
use thiserror::Error;

/// What can go wrong in a report, the papers' experiments or a profile.
#[derive(Debug, Error)]
pub enum HarnessError {
    /// A library error: bad input, an unsupported light, a GPU failure, ...
    #[error(transparent)]
    Shadow(#[from] ShadowError),
    /// An output file or folder could not be written.
    #[error("cannot write {path}")]
    Write {
        /// The path that failed.
        path: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A request the command cannot serve (a scene some technique does not model, a file that
    /// is not a report), with what to do instead.
    #[error("{0}")]
    Usage(String),
    /// A scene whose light's views would leave a caster that shadows what the camera sees out
    /// of every view (or a seen receiver out of its cascade's window): measuring it would
    /// report a silently missing shadow as a result.
    #[error(
        "{scene}: the {light} light's {views} views leave out {what}: its shadow would be \
         silently missing, so the scene is not measured"
    )]
    Uncovered {
        /// The scene.
        scene: String,
        /// The light's kind.
        light: String,
        /// How the views were chosen (`single`, `cube`, `cascades`).
        views: String,
        /// What is left out, named.
        what: String,
    },
    /// Every configuration a run asked for was skipped: nothing was measured.
    #[error("nothing ran: {0}")]
    NothingRan(String),
}

impl HarnessError {
    /// A write failure of `path` for `e`.
    pub fn write(path: &std::path::Path, e: impl std::fmt::Display) -> Self {
        HarnessError::Write {
            path: path.display().to_string(),
            source: std::io::Error::other(e.to_string()),
        }
    }
}

/// Shorthand for results of the harness.
pub type Result<T> = std::result::Result<T, HarnessError>;
