//! Plain world-space geometry: the triangles technique kernels take, with their bounds.

use crate::error::{Result, ShadowError};
use crate::mesh::{Aabb, MAX_COORDINATE};
use glam::Vec3;

/// Plain world-space geometry, what technique kernels consume: built by hand, or flattened from
/// a `Scene` (`Scene::geometry`, feature `ecs`).
#[derive(Clone, Debug, Default)]
pub struct SceneGeometry {
    /// Shadow-casting triangles, world space.
    pub casters: Vec<[Vec3; 3]>,
    /// Receiving triangles, world space.
    pub receivers: Vec<[Vec3; 3]>,
    /// The region the maps cover: the bounds of casters and receivers together
    /// ([`SceneGeometry::new`]), or of the casters that shadow what a camera sees and the
    /// receivers they reach ([`crate::coverage::casting_onto`]).
    pub bounds: Aabb,
}

impl SceneGeometry {
    /// Geometry of `casters` and `receivers`, with their bounds.
    pub fn new(casters: Vec<[Vec3; 3]>, receivers: Vec<[Vec3; 3]>) -> Self {
        let mut bounds = Aabb::of_triangles(&casters);
        for p in receivers.iter().flatten() {
            bounds.grow(*p);
        }
        SceneGeometry {
            casters,
            receivers,
            bounds,
        }
    }

    /// Checks that there is something to shadow: non-empty bounds, finite coordinates within
    /// [`MAX_COORDINATE`], and an extent f32 can resolve where the scene lies (at least a
    /// millionth of its distance from the origin).
    pub fn validate(&self) -> Result<()> {
        if self.bounds.is_empty() {
            return Err(ShadowError::InvalidScene(
                "the scene holds no triangles".into(),
            ));
        }
        if !self.bounds.min.is_finite() || !self.bounds.max.is_finite() {
            return Err(ShadowError::InvalidScene(
                "the scene bounds are not finite".into(),
            ));
        }
        let reach = self
            .bounds
            .min
            .abs()
            .max(self.bounds.max.abs())
            .max_element();
        if reach > MAX_COORDINATE {
            return Err(ShadowError::InvalidScene(format!(
                "the scene reaches {reach:e} m from the origin, beyond ±{MAX_COORDINATE} m"
            )));
        }
        let extent = self.bounds.diagonal();
        if extent <= reach * 1.0e-6 {
            return Err(ShadowError::InvalidScene(format!(
                "every triangle lies within {extent:e} m of the others, {reach:e} m from the \
                 origin: f32 cannot resolve maps of it"
            )));
        }
        Ok(())
    }

    /// Every surface once: the casters, then the receivers that are not also casters (compared
    /// bit for bit). Techniques that follow an occluder edge to the surface behind it read these
    /// (linear-light's skins); shadow tests read the casters only.
    pub fn surfaces(&self) -> Vec<[Vec3; 3]> {
        let key = |t: &[Vec3; 3]| t.map(|p| p.to_array().map(f32::to_bits));
        let casters: std::collections::HashSet<_> = self.casters.iter().map(key).collect();
        self.casters
            .iter()
            .chain(self.receivers.iter().filter(|t| !casters.contains(&key(t))))
            .copied()
            .collect()
    }
}
