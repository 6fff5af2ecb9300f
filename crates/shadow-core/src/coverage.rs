//! What a light's maps must cover ("maps cover what casts"): the casters that can
//! shadow a receiver, and the receivers their shadows and penumbrae can reach, never geometry
//! that only receives light where nothing can shadow it.
//!
//! From a light point `q`, a receiver `X` shadowed by caster point `Y` as seen from another light
//! point `q'` lies on `Y + t (Y - q')`, `t >= 0`, no deeper than the scene. Per `q'` these points
//! form the convex hull of the caster box's corners `C` and their extensions `C + t (C - q')` to
//! the scene's deepest depth, so the window of a perspective map from `q` (the range of `x/z`
//! and `y/z`, reached at vertices) only needs those points. For an
//! orthographic map (distant light) the caster box's window grows by the scene's depth below the
//! casters times the tangent of the light's cone. Both are then clipped to the window of the
//! whole scene, and get [`MARGIN`] for filter kernels.

use crate::geometry::SceneGeometry;
use crate::light::{Light, LightPoint};
use crate::mesh::Aabb;
use glam::Vec3;

/// Relative margin added to each window, so filter kernels near its edge read empty texels.
pub const MARGIN: f32 = 0.06;

/// The region a light's maps must cover.
#[derive(Clone, Debug, PartialEq)]
pub struct Coverage {
    /// Bounds of the shadow casters (empty when nothing casts).
    pub casters: Aabb,
    /// Bounds of all geometry, casters and receivers: caps every window and sets the depth range.
    pub scene: Aabb,
    /// A convex outline of the light whose penumbrae the maps must hold: positions for a local
    /// light (a sphere's bounding-box corners), directions for a distant one.
    pub light: Vec<LightPoint>,
}

impl Coverage {
    /// The coverage of `geometry`'s casters for `light`.
    pub fn new(geometry: &SceneGeometry, light: &Light) -> Self {
        let casters = Aabb::of_triangles(&geometry.casters);
        let light_outline = match *light {
            Light::Sphere { center, radius } => Aabb {
                min: center - Vec3::splat(radius),
                max: center + Vec3::splat(radius),
            }
            .corners()
            .into_iter()
            .map(LightPoint::Position)
            .collect(),
            _ => light.outline(casters_or(&casters, &geometry.bounds).center()),
        };
        Self {
            casters,
            scene: geometry.bounds,
            light: light_outline,
        }
    }

    /// Coverage of a whole box (every point of it may cast, no penumbra beyond it): for maps of
    /// a given region, such as tests of the rasterizer.
    pub fn whole(bounds: &Aabb) -> Self {
        Self {
            casters: *bounds,
            scene: *bounds,
            light: Vec::new(),
        }
    }

    /// The box the maps are fitted around: the casters' (the scene's when nothing casts).
    pub fn fit_box(&self) -> &Aabb {
        casters_or(&self.casters, &self.scene)
    }

    /// The point a light looks at (for lights without an emission normal): the casters' centre.
    pub fn center(&self) -> Vec3 {
        self.fit_box().center()
    }
}

fn casters_or<'a>(casters: &'a Aabb, scene: &'a Aabb) -> &'a Aabb {
    if casters.is_empty() { scene } else { casters }
}
