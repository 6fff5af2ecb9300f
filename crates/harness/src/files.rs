//! Writing the commands' output files: a failure names the path.

use crate::error::{HarnessError, Result};
use std::path::Path;

/// Creates `path` and its parents.
pub(crate) fn create_dir(path: &Path) -> Result<()> {
    std::fs::create_dir_all(path).map_err(|source| HarnessError::Write {
        path: path.display().to_string(),
        source,
    })
}

/// Writes `text` to `path`.
pub(crate) fn write_text(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|source| HarnessError::Write {
        path: path.display().to_string(),
        source,
    })
}
