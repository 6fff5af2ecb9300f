//! The receivers of an evaluation: world-space points with unit normals.

use crate::error::{Result, ShadowError};
use glam::Vec3;

/// A batch of world-space receiver points with unit normals, the input of evaluation.
#[derive(Clone, Copy, Debug)]
pub struct Receivers<'a> {
    /// World-space positions.
    pub positions: &'a [Vec3],
    /// Unit normals facing the viewer (same length as `positions`).
    pub normals: &'a [Vec3],
}

impl<'a> Receivers<'a> {
    /// The receivers at `positions` with `normals`.
    pub fn new(positions: &'a [Vec3], normals: &'a [Vec3]) -> Self {
        Receivers { positions, normals }
    }

    /// Checks equal lengths and finite values.
    pub fn validate(&self) -> Result<()> {
        if self.positions.len() != self.normals.len() {
            return Err(ShadowError::InvalidReceivers(format!(
                "{} positions but {} normals",
                self.positions.len(),
                self.normals.len()
            )));
        }
        if let Some(i) = self
            .positions
            .iter()
            .chain(self.normals)
            .position(|p| !p.is_finite())
        {
            return Err(ShadowError::InvalidReceivers(format!(
                "entry {i} is not finite"
            )));
        }
        Ok(())
    }
}
