//! Indexed triangle meshes and axis-aligned bounds.

use crate::error::{Result, ShadowError};
use glam::{Mat4, Vec3};

/// Largest coordinate magnitude a mesh or a scene may have, in metres (1000 km): f32 still
/// resolves millimetres at a tenth of it, and every stage's cost stays independent of
/// coordinates. Larger finite coordinates (a misread buffer, a unit mix-up) are a typed error.
pub const MAX_COORDINATE: f32 = 1.0e6;

/// An indexed triangle mesh in its own object space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// A name for error messages and reports.
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// One entry per triangle, indices into `positions`.
    pub indices: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// A mesh from positions and triangles, validated: every coordinate finite, every index in range.
    pub fn new(
        name: impl Into<String>,
        positions: Vec<Vec3>,
        indices: Vec<[u32; 3]>,
    ) -> Result<Self> {
        let mesh = Self {
            name: name.into(),
            positions,
            indices,
        };
        mesh.validate()?;
        Ok(mesh)
    }

    /// Checks that every coordinate is finite and within [`MAX_COORDINATE`], and every index is
    /// in range.
    pub fn validate(&self) -> Result<()> {
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(ShadowError::InvalidMesh {
                mesh: self.name.clone(),
                reason: format!("vertex {i} is not finite: {:?}", self.positions[i]),
            });
        }
        if let Some(i) = self
            .positions
            .iter()
            .position(|p| p.abs().max_element() > MAX_COORDINATE)
        {
            return Err(ShadowError::InvalidMesh {
                mesh: self.name.clone(),
                reason: format!(
                    "vertex {i} at {:?} lies beyond ±{MAX_COORDINATE} m (a misread buffer or a \
                     unit mix-up?)",
                    self.positions[i]
                ),
            });
        }
        let n = self.positions.len() as u32;
        if let Some(t) = self.indices.iter().position(|t| t.iter().any(|&i| i >= n)) {
            return Err(ShadowError::InvalidMesh {
                mesh: self.name.clone(),
                reason: format!(
                    "triangle {t} indexes past the {n} vertices: {:?}",
                    self.indices[t]
                ),
            });
        }
        Ok(())
    }

    /// The world-space triangles of this mesh under `transform`.
    pub fn world_triangles(&self, transform: Mat4) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        self.indices
            .iter()
            .map(move |t| t.map(|i| transform.transform_point3(self.positions[i as usize])))
    }
}

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// The empty box (min = +inf, max = -inf), the identity of [`Aabb::grow`].
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// Grows the box to contain `p`.
    pub fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// True when nothing was added.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    /// Centre of the box.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f32 {
        (self.max - self.min).length()
    }

    /// The eight corners.
    pub fn corners(&self) -> [Vec3; 8] {
        let (a, b) = (self.min, self.max);
        [
            Vec3::new(a.x, a.y, a.z),
            Vec3::new(b.x, a.y, a.z),
            Vec3::new(a.x, b.y, a.z),
            Vec3::new(b.x, b.y, a.z),
            Vec3::new(a.x, a.y, b.z),
            Vec3::new(b.x, a.y, b.z),
            Vec3::new(a.x, b.y, b.z),
            Vec3::new(b.x, b.y, b.z),
        ]
    }

    /// The box around a set of triangles.
    pub fn of_triangles(tris: &[[Vec3; 3]]) -> Aabb {
        let mut b = Aabb::EMPTY;
        for t in tris {
            for p in t {
                b.grow(*p);
            }
        }
        b
    }
}
