//! Scene geometry resident on the GPU across frames.

use super::GpuContext;
use super::raster::GpuTriangles;
use crate::error::Result;
use crate::geometry::SceneGeometry;
use std::any::{Any, TypeId};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// A scene's triangles kept on the GPU between frames: uploaded once by [`GpuScene::new`], again
/// only by [`GpuScene::update`]. Generation ([`crate::ShadowTechnique::record_gpu`]) draws from
/// these buffers, so a static scene uploads no geometry after its first frame.
///
/// It also keeps the CPU copy of the geometry the maps are planned from (the casters' box,
/// the scene's bounds, the light's coverage), and what techniques derive from the geometry
/// ([`GpuScene::derived`]: silhouette edges, every surface), built on first use.
pub struct GpuScene {
    geometry: SceneGeometry,
    casters: GpuTriangles,
    derived: Mutex<HashMap<TypeId, Arc<dyn Any + Send + Sync>>>,
}

/// Every surface of a scene on the GPU ([`SceneGeometry::surfaces`]).
pub struct GpuSurfaces(pub GpuTriangles);

impl GpuScene {
    /// Validates `geometry` and uploads its casters and its [surfaces](SceneGeometry::surfaces).
    pub fn new(ctx: &GpuContext, geometry: &SceneGeometry) -> Result<Self> {
        geometry.validate()?;
        let casters = ctx.checked("scene upload", || GpuTriangles::new(ctx, &geometry.casters))?;
        ctx.count_geometry_upload();
        Ok(Self {
            geometry: geometry.clone(),
            casters,
            derived: Mutex::new(HashMap::new()),
        })
    }

    /// Replaces the geometry (a moved or deformed mesh): one upload, whatever changed.
    pub fn update(&mut self, ctx: &GpuContext, geometry: &SceneGeometry) -> Result<()> {
        *self = Self::new(ctx, geometry)?;
        Ok(())
    }

    /// The CPU copy the maps are planned from.
    pub fn geometry(&self) -> &SceneGeometry {
        &self.geometry
    }

    /// The shadow casters.
    pub fn casters(&self) -> &GpuTriangles {
        &self.casters
    }

    /// GPU data a technique derives from this geometry, keyed by type: `init` runs (and counts
    /// as an upload in [`GpuContext::geometry_uploads`]) once per scene, later calls return the
    /// same value until [`GpuScene::update`].
    pub fn derived<T: Any + Send + Sync>(
        &self,
        ctx: &GpuContext,
        init: impl FnOnce(&GpuContext, &SceneGeometry) -> Result<T>,
    ) -> Result<Arc<T>> {
        let key = TypeId::of::<T>();
        let lock = || self.derived.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = lock()
            .get(&key)
            .cloned()
            .and_then(|v| v.downcast::<T>().ok())
        {
            return Ok(t);
        }
        let value = Arc::new(ctx.checked("scene upload", || init(ctx, &self.geometry))?);
        ctx.count_geometry_upload();
        lock().insert(key, value.clone());
        Ok(value)
    }

    /// Every surface: the casters and the receivers that do not cast (uploaded on first use).
    pub fn surfaces(&self, ctx: &GpuContext) -> Result<Arc<GpuSurfaces>> {
        self.derived(ctx, |c, g| {
            Ok(GpuSurfaces(GpuTriangles::new(c, &g.surfaces())?))
        })
    }
}
