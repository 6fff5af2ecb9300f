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
    /// Per stale light whose maps are not made yet: the regions of the casters that changed
    /// since they were (old and new), or `None` where something else made it stale too (every
    /// face is made again).
    changed: HashMap<Entity, Option<Vec<Aabb>>>,
}

impl FaceRefresh {
    /// Light `light`'s staleness after this frame's marking: `was` stale before it and `is`
    /// after, the casters changed in `regions` making it so (`None`: none did), `everything`
    /// where every light is (caching off, a new backend). A light stale from before keeps what
    /// made it so, its maps waiting (a frame's clock, `deadline`), and adds this frame's
    /// regions; a light that nothing accounts for (stale from before without a note, or made
    /// stale by something else) makes every face again.
    pub(crate) fn mark(
        &mut self,
        light: Entity,
        (was, is, everything): (bool, bool, bool),
        regions: Option<Vec<Aabb>>,
    ) {
        if !is {
            self.changed.remove(&light);
            return;
        }
        if everything {
            self.changed.insert(light, None);
            return;
        }
        let before = if was {
            // Stale from before: what made it so, or every face where nothing says.
            self.changed.remove(&light).unwrap_or(None)
        } else {
            Some(Vec::new())
        };
        let now = match (before, regions) {
            (Some(mut b), Some(r)) => {
                b.extend(r);
                Some(b)
            }
            // Stale from before, nothing new: what made it so stays.
            (Some(b), None) if was => Some(b),
            _ => None,
        };
        self.changed.insert(light, now);
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

    /// What made light `light` stale, taken as its maps are made (whichever way): the regions
    /// of the casters that changed since they were made, or `None` (every face).
    pub(crate) fn take(&mut self, light: Entity) -> Option<Vec<Aabb>> {
        self.changed.remove(&light).flatten()
    }

    /// The faces of light `light` (`source`, its maps made for the views `made`) to make again
    /// by `technique` at `resolution` over `geometry`, planned as `planned`, instead of every
    /// view: where the casters changed in `regions` (this frame's and those since its maps
    /// were made, [`FaceRefresh::take`], and the changes that waited out of view, `unseen`)
    /// made it stale alone, `technique`'s faces are local, and the technique, the side, the
    /// plan and the whole light's coverage are those the maps were made whole with. `None`:
    /// make every view.
    pub(crate) fn faces(
        &self,
        light: Entity,
        (technique, resolution): (&dyn TechniqueInfo, u32),
        (source, geometry): (&Light, &SceneGeometry),
        (planned, made): (&LightViews, &LightViews),
        (mut regions, unseen): (Vec<Aabb>, &[Aabb]),
    ) -> Option<Vec<usize>> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn at(x: f32) -> Aabb {
        Aabb {
            min: Vec3::splat(x),
            max: Vec3::splat(x + 1.0),
        }
    }

    /// What makes a light stale adds up while its maps wait, and anything but changed casters
    /// makes every face again until they are made.
    #[test]
    fn a_waiting_light_keeps_what_made_it_stale() {
        let e = World::new().spawn_empty().id();
        let mut f = FaceRefresh::default();
        let note = |f: &FaceRefresh| f.changed.get(&e).cloned();
        f.mark(e, (false, true, false), Some(vec![at(0.0)]));
        assert_eq!(note(&f), Some(Some(vec![at(0.0)])));
        // Its maps waited a frame: a second change adds its regions, and a frame without one
        // keeps them.
        f.mark(e, (true, true, false), Some(vec![at(2.0)]));
        f.mark(e, (true, true, false), None);
        assert_eq!(note(&f), Some(Some(vec![at(0.0), at(2.0)])));
        // Every light made stale (caching off, a new backend): every face, while it waits too.
        f.mark(e, (true, true, true), None);
        f.mark(e, (true, true, false), Some(vec![at(4.0)]));
        assert_eq!(note(&f), Some(None));
        // Its maps made (the note taken, whichever way they were made), then stale again in
        // the same frame's marking by something else first (a new pick in the Resolve set):
        // every face.
        assert_eq!(f.take(e), None);
        f.mark(e, (true, true, false), Some(vec![at(0.0)]));
        assert_eq!(note(&f), Some(None));
        // Made again; changed casters alone, a frame later: their regions.
        assert_eq!(f.take(e), None);
        f.mark(e, (false, false, false), None);
        f.mark(e, (false, true, false), Some(vec![at(6.0)]));
        assert_eq!(f.take(e), Some(vec![at(6.0)]));
        // Made without a note read (no maps to keep): a mark from anything else then finds none.
        f.mark(e, (false, true, false), Some(vec![at(8.0)]));
        f.take(e);
        f.mark(e, (true, true, false), None);
        assert_eq!(note(&f), Some(None));
    }
}
