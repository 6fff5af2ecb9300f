//! A local light's cube faces made again one by one: where only changed casters made a light's
//! maps stale, its technique's faces are local ([`TechniqueInfo::face_local`]), its views are
//! planned as before and the coverage of the whole light is the one its maps were made over,
//! the frame makes again only the faces the changed casters meet
//! ([`LightViews::faces_meeting`]); the others hold what a new generation would make.

use bevy_ecs::prelude::*;
use soft_shadow_core::coverage::Coverage;
use soft_shadow_core::mesh::Aabb;
use soft_shadow_core::technique::TechniqueInfo;
use soft_shadow_core::{Light, LightViews, SceneGeometry};
use std::collections::HashMap;

/// What a light's cube faces were last made whole with: its technique (name and variant), the
/// map side and the coverage of the whole light.
#[derive(PartialEq)]
struct Made {
    technique: String,
    resolution: u32,
    coverage: Coverage,
}

impl Made {
    fn new(technique: &dyn TechniqueInfo, resolution: u32, coverage: Coverage) -> Self {
        Self {
            technique: format!("{} {}", technique.name(), technique.variant()),
            resolution,
            coverage,
        }
    }
}

/// What the frame keeps to make faces again one by one.
#[derive(Resource, Default)]
pub(crate) struct FaceRefresh {
    /// Per light whose technique's faces are local and whose maps are cube faces: what they
    /// were last made whole with.
    made_over: HashMap<Entity, Made>,
    /// Per light that only changed casters made stale this frame: their regions, old and new.
    changed: HashMap<Entity, Vec<Aabb>>,
}

impl FaceRefresh {
    /// Light `light` was made stale this frame by the casters changed in `regions` alone
    /// (`None`: by something else too, or not at all).
    pub(crate) fn stale_by(&mut self, light: Entity, regions: Option<Vec<Aabb>>) {
        match regions {
            Some(r) => self.changed.insert(light, r),
            None => self.changed.remove(&light),
        };
    }

    /// Light `light`'s maps were made whole by `technique` at `resolution` over `geometry`, for
    /// the views `views`.
    pub(crate) fn made(
        &mut self,
        light: Entity,
        (technique, resolution): (&dyn TechniqueInfo, u32),
        (source, geometry, views): (&Light, &SceneGeometry, &LightViews),
    ) {
        // Cube faces: `faces_meeting` answers for them alone.
        if technique.face_local() && views.faces_meeting(source, &[]).is_some() {
            let made = Made::new(technique, resolution, Coverage::new(geometry, source));
            self.made_over.insert(light, made);
        } else {
            self.made_over.remove(&light);
        }
    }

    /// Forgets the lights not in `lights` (despawned, or no longer lights).
    pub(crate) fn keep_only(&mut self, lights: &std::collections::HashSet<Entity>) {
        self.made_over.retain(|e, _| lights.contains(e));
        self.changed.retain(|e, _| lights.contains(e));
    }

    /// The faces of light `light` (`source`, its maps made for the views `made`) to make again
    /// by `technique` at `resolution` over `geometry`, planned as `planned`, instead of every
    /// view: where the casters changed this frame (and the changes that waited out of view,
    /// `unseen`) made it stale alone, `technique`'s faces are local, and the technique, the
    /// side, the plan and the whole light's coverage are those the maps were made whole with.
    /// `None`: make every view.
    pub(crate) fn faces(
        &mut self,
        light: Entity,
        (technique, resolution): (&dyn TechniqueInfo, u32),
        (source, geometry): (&Light, &SceneGeometry),
        (planned, made): (&LightViews, &LightViews),
        unseen: &[Aabb],
    ) -> Option<Vec<usize>> {
        let mut regions = self.changed.remove(&light)?;
        if !technique.face_local() || planned != made {
            return None;
        }
        let kept = self.made_over.get(&light)?;
        if *kept != Made::new(technique, resolution, Coverage::new(geometry, source)) {
            return None;
        }
        regions.extend_from_slice(unseen);
        planned.faces_meeting(source, &regions)
    }
}
