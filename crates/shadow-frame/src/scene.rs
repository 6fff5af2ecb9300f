//! The scene as a `bevy_ecs` world: meshes with transforms, caster/receiver markers, lights, a camera.
//!
//! Techniques never see the world: [`Scene::geometry`] flattens it into plain world-space triangles
//! ([`SceneGeometry`]), the data the kernels take.

use bevy_ecs::prelude::*;
use glam::{Mat4, Vec3};
use soft_shadow_core::error::{Result, ShadowError};
use soft_shadow_core::geometry::SceneGeometry;
use soft_shadow_core::light::Light;
use soft_shadow_core::mesh::{Aabb, TriangleMesh};
use soft_shadow_core::view::Camera;
use std::sync::Arc;

/// A mesh attached to an entity (shared, so many entities can instance one mesh).
#[derive(Component, Clone, Debug)]
pub struct MeshHandle(pub Arc<TriangleMesh>);

/// Object to world transform.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Transform(pub Mat4);

/// Marks a mesh that casts shadows (rendered into shadow maps, traced by the ground truth).
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct ShadowCaster;

/// Marks a mesh that receives shadows (rendered into the camera G-buffer).
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct ShadowReceiver;

/// A light source entity.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct LightSource(pub Light);

/// The camera entity.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct CameraComponent(pub Camera);

/// The order in which a mesh or light was added; flattening and listing follow it, so
/// results do not depend on how the ECS allocates entities.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct SpawnOrder(pub u64);

/// A scene: an ECS world plus convenience constructors.
pub struct Scene {
    /// The ECS world holding every entity.
    pub world: World,
    next: u64,
}

impl Default for Scene {
    fn default() -> Self {
        Self::new()
    }
}

/// One mesh instance of the scene.
struct Instance {
    order: (u64, Entity),
    mesh: Arc<TriangleMesh>,
    transform: Mat4,
    caster: bool,
    receiver: bool,
}

/// Whether a mesh instance casts shadows, receives them (appears in the G-buffer), or both.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shadows {
    /// Casts shadows: it lies in the light's maps.
    pub casts: bool,
    /// Receives shadows.
    pub receives: bool,
}

impl Shadows {
    /// Casts and receives: an object.
    pub const CAST_AND_RECEIVE: Shadows = Shadows {
        casts: true,
        receives: true,
    };
    /// Casts only: an occluder the camera does not shade (a light's housing).
    pub const CAST_ONLY: Shadows = Shadows {
        casts: true,
        receives: false,
    };
    /// Receives only: a ground that shadows nothing in view.
    pub const RECEIVE_ONLY: Shadows = Shadows {
        casts: false,
        receives: true,
    };
}

impl Scene {
    /// An empty scene.
    pub fn new() -> Self {
        Self {
            world: World::new(),
            next: 0,
        }
    }

    /// Adds a mesh instance that casts and receives as `shadows` says; it is validated (finite
    /// vertices, indices in range).
    pub fn add_mesh(
        &mut self,
        mesh: Arc<TriangleMesh>,
        transform: Mat4,
        shadows: Shadows,
    ) -> Result<Entity> {
        mesh.validate()?;
        if !transform.is_finite() {
            return Err(ShadowError::InvalidMesh {
                mesh: mesh.name.clone(),
                reason: "transform is not finite".into(),
            });
        }
        self.next += 1;
        let mut e = self.world.spawn((
            MeshHandle(mesh),
            Transform(transform),
            SpawnOrder(self.next),
        ));
        if shadows.casts {
            e.insert(ShadowCaster);
        }
        if shadows.receives {
            e.insert(ShadowReceiver);
        }
        Ok(e.id())
    }

    /// Adds a light after validating it.
    pub fn add_light(&mut self, light: Light) -> Result<Entity> {
        light.validate()?;
        self.next += 1;
        Ok(self
            .world
            .spawn((LightSource(light), SpawnOrder(self.next)))
            .id())
    }

    /// Sets the (single) camera, replacing any previous one.
    pub fn set_camera(&mut self, camera: Camera) -> Entity {
        let old: Vec<Entity> = self
            .world
            .query_filtered::<Entity, With<CameraComponent>>()
            .iter(&self.world)
            .collect();
        for e in old {
            self.world.despawn(e);
        }
        self.world.spawn(CameraComponent(camera)).id()
    }

    /// The camera, if one is set.
    pub fn camera(&mut self) -> Option<Camera> {
        self.world
            .query::<&CameraComponent>()
            .iter(&self.world)
            .next()
            .map(|c| c.0)
    }

    /// Every light, in the order added (entities spawned without [`SpawnOrder`] come last).
    pub fn lights(&mut self) -> Vec<Light> {
        let mut v: Vec<(u64, Entity, Light)> = self
            .world
            .query::<(Entity, &LightSource, Option<&SpawnOrder>)>()
            .iter(&self.world)
            .map(|(e, l, o)| (o.map_or(u64::MAX, |o| o.0), e, l.0))
            .collect();
        v.sort_by_key(|(o, e, _)| (*o, *e));
        v.into_iter().map(|(_, _, l)| l).collect()
    }

    /// The mesh instances in the order added (entities spawned without [`SpawnOrder`] last).
    fn instances(&mut self) -> Vec<Instance> {
        let mut items: Vec<Instance> = self
            .world
            .query::<(
                Entity,
                &MeshHandle,
                &Transform,
                Has<ShadowCaster>,
                Has<ShadowReceiver>,
                Option<&SpawnOrder>,
            )>()
            .iter(&self.world)
            .map(|(e, m, t, c, r, o)| Instance {
                order: (o.map_or(u64::MAX, |o| o.0), e),
                mesh: m.0.clone(),
                transform: t.0,
                caster: c,
                receiver: r,
            })
            .collect();
        items.sort_by_key(|i| i.order);
        items
    }

    /// The geometry `light`'s maps need to shadow the receiver points `seen` (what a camera
    /// sees; [`soft_shadow_core::coverage::casting_onto`]): the caster instances that can shadow
    /// one of them, in the order added, every receiver, and bounds over those casters and the
    /// receivers they can reach.
    pub fn casting_onto(&mut self, light: &Light, seen: &[Vec3]) -> SceneGeometry {
        let (mut casters, mut receivers) = (Vec::new(), Vec::new());
        for i in self.instances() {
            let tris: Vec<[Vec3; 3]> = i.mesh.world_triangles(i.transform).collect();
            if i.receiver {
                receivers.extend_from_slice(&tris);
            }
            if i.caster {
                casters.push(tris);
            }
        }
        soft_shadow_core::coverage::casting_onto(light, &casters, receivers, seen)
    }

    /// Flattens casters and receivers into world-space triangles, in the order added (entities
    /// spawned without [`SpawnOrder`] come last).
    pub fn geometry(&mut self) -> SceneGeometry {
        let items = self.instances();
        let mut g = SceneGeometry::default();
        for Instance {
            mesh,
            transform,
            caster,
            receiver,
            ..
        } in items
        {
            let tris: Vec<[Vec3; 3]> = mesh.world_triangles(transform).collect();
            if caster {
                g.casters.extend_from_slice(&tris);
            }
            if receiver {
                g.receivers.extend_from_slice(&tris);
            }
        }
        let mut b = Aabb::of_triangles(&g.casters);
        let r = Aabb::of_triangles(&g.receivers);
        if !r.is_empty() {
            b.grow(r.min);
            b.grow(r.max);
        }
        g.bounds = b;
        g
    }
}
