//! A scene made ready for measurement: geometry, the camera G-buffer, its receivers, the reference.

use crate::metrics::{Shading, TERMINATOR_COS};
use glam::Vec3;
use soft_shadow_core::coverage;
use soft_shadow_core::pool::Pool;
use soft_shadow_core::raster::{GBufferTexel, gbuffer, rasterize_nearest};
use soft_shadow_core::{
    Light, LightPoint, LightViews, Map2D, Receivers, Result, SceneGeometry, SeenDepth, ShadowError,
    Uncovered,
};
use soft_shadow_reference::ground_truth::irradiance::irradiance;
use soft_shadow_reference::ground_truth::{GroundTruthSettings, RayTracer, Reference};
use soft_shadow_reference::scenes::SceneSpec;
use std::collections::HashSet;
use std::sync::Arc;
use std::time::Instant;

/// A triangle's coordinates as bits, to find the same triangle in another list.
fn bits(t: &[Vec3; 3]) -> [u32; 9] {
    let f = [t[0], t[1], t[2]].map(|v| v.to_array());
    std::array::from_fn(|i| f[i / 3][i % 3].to_bits())
}

/// What `views` of `light` over `geometry` leave out of the scene `spec` whose camera sees
/// `seen`, named: the caster instances that shadow a seen point ([`coverage::casting_instances`])
/// and lie partly in no view, and the seen points outside their cascade's window.
pub(crate) fn uncovered(
    spec: &SceneSpec,
    light: &Light,
    geometry: &SceneGeometry,
    views: &LightViews,
    seen: &[Vec3],
) -> Vec<String> {
    let casters: Vec<(&str, Vec<[Vec3; 3]>)> = spec
        .meshes
        .iter()
        .filter(|m| m.caster)
        .map(|m| {
            (
                m.mesh.name.as_str(),
                m.mesh.world_triangles(m.transform).collect(),
            )
        })
        .collect();
    let all: Vec<Vec<[Vec3; 3]>> = casters.iter().map(|(_, t)| t.clone()).collect();
    let kept = coverage::casting_instances(light, &all, seen);
    let instances: Vec<Vec<[Vec3; 3]>> = kept.iter().map(|&i| all[i].clone()).collect();
    views
        .uncovered(light, geometry, &instances, seen)
        .into_iter()
        .map(|u| match u {
            Uncovered::Caster(i) => format!("caster `{}`", casters[kept[i]].0),
            Uncovered::Receiver(k) => format!("the receiver at {:.3}", seen[k]),
            _ => "a part of the scene".to_string(),
        })
        .collect()
}

/// A scene with its G-buffer and reference visibilities.
pub struct PreparedScene {
    /// The description.
    pub spec: SceneSpec,
    /// What the techniques' maps cover ([`shadow_frame::Scene::casting_onto`]): the casters
    /// that can shadow a receiver in view, bounds over them and the receivers they reach.
    pub geometry: SceneGeometry,
    /// What the camera sees: its view and the depth range of the receivers, for cascades.
    pub seen: Option<SeenDepth>,
    /// The light's views ([`LightViews::plan_seen`] over `geometry`, `seen` and the G-buffer's
    /// positions): every technique generates its maps for these.
    pub views: LightViews,
    /// What the views leave out ([`LightViews::uncovered`]): the names of the casters that
    /// shadow what the camera sees in no view, or the receivers outside their cascade's window.
    /// Empty where the views hold everything; the report refuses a scene where they do not.
    pub uncovered: Vec<String>,
    /// The camera G-buffer.
    pub gbuffer: Map2D<GBufferTexel>,
    /// Index into the G-buffer of every covered pixel the light reaches, in row-major order.
    pub pixels: Vec<usize>,
    /// Index into the G-buffer of every covered pixel no light point reaches (visibility v2:
    /// unlit; not evaluated, in no error metric, drawn apart in the strips).
    pub unlit_pixels: Vec<usize>,
    /// Receiver positions (covered pixels the light reaches).
    pub positions: Vec<Vec3>,
    /// Receiver normals (covered pixels the light reaches).
    pub normals: Vec<Vec3>,
    /// Reference per receiver.
    pub reference: Vec<Reference>,
    /// The light's unshadowed irradiance `E0` per receiver
    /// ([`soft_shadow_reference::ground_truth::irradiance`]).
    pub irradiance: Vec<f32>,
    /// Image-error weights and classes per receiver.
    pub shading: Shading,
    /// Sampling used for the reference.
    pub settings: GroundTruthSettings,
    /// Wall time of the reference, milliseconds.
    pub reference_ms: f64,
}

impl PreparedScene {
    /// Builds the ECS scene, renders the G-buffer (`size²` on the CPU rasterizer) and traces the reference.
    pub fn new(spec: SceneSpec, size: u32, settings: GroundTruthSettings) -> Result<Self> {
        Self::sized(spec, size, size, settings)
    }

    /// [`PreparedScene::new`] with a `width` x `height` G-buffer (a viewing resolution, say).
    pub fn sized(
        spec: SceneSpec,
        width: u32,
        height: u32,
        settings: GroundTruthSettings,
    ) -> Result<Self> {
        let mut scene = spec.to_scene()?;
        let geometry = scene.geometry();
        geometry.validate()?;
        let camera = scene
            .camera()
            .ok_or_else(|| ShadowError::InvalidScene("no camera".into()))?;
        let view = camera.view(width, height);
        // One-off maps: nothing to keep for a later call.
        let pool = Arc::new(Pool::new(0));
        let gb = gbuffer(&pool, &view, camera.eye, width, height, &geometry.receivers);
        let covered: Vec<usize> = gb
            .data()
            .iter()
            .enumerate()
            .filter(|(_, t)| t.covered && t.normal != Vec3::ZERO)
            .map(|(i, _)| i)
            .collect();
        if covered.is_empty() {
            return Err(ShadowError::InvalidScene(format!(
                "{}: the camera sees no receiver",
                spec.name
            )));
        }
        // Which covered pixels lie on a caster (an object) rather than on receiving-only geometry.
        let caster_set: HashSet<[u32; 9]> = geometry.casters.iter().map(bits).collect();
        let nearest = rasterize_nearest(&pool, &view, width, height, &geometry.receivers);
        let all_object: Vec<bool> = covered
            .iter()
            .map(|&i| {
                let t = nearest.data()[i].triangle as usize;
                geometry
                    .receivers
                    .get(t)
                    .is_some_and(|t| caster_set.contains(&bits(t)))
            })
            .collect();
        let all_positions: Vec<Vec3> = covered.iter().map(|&i| gb.data()[i].position).collect();
        let all_normals: Vec<Vec3> = covered.iter().map(|&i| gb.data()[i].normal).collect();
        let t = Instant::now();
        let tracer = RayTracer::new(&geometry.casters);
        let all = tracer.references(&spec.light, &all_positions, &all_normals, &settings);
        let reference_ms = t.elapsed().as_secs_f64() * 1e3;
        let (mut pixels, mut unlit_pixels) = (Vec::new(), Vec::new());
        let (mut positions, mut normals, mut reference) = (Vec::new(), Vec::new(), Vec::new());
        let mut object = Vec::new();
        for (k, r) in all.into_iter().enumerate() {
            match r {
                Some(r) => {
                    pixels.push(covered[k]);
                    positions.push(all_positions[k]);
                    normals.push(all_normals[k]);
                    reference.push(r);
                    object.push(all_object[k]);
                }
                None => unlit_pixels.push(covered[k]),
            }
        }
        if pixels.is_empty() {
            return Err(ShadowError::InvalidScene(format!(
                "{}: the light reaches none of the {} receivers the camera sees (all unlit: \
                 check the light's position and direction)",
                spec.name,
                covered.len()
            )));
        }
        let light = spec.light;
        let irradiance: Vec<f32> = positions
            .iter()
            .zip(&normals)
            .map(|(p, n)| irradiance(&light, *p, *n))
            .collect();
        let terminator = positions
            .iter()
            .zip(&normals)
            .map(|(p, n)| {
                let towards = match light.center() {
                    LightPoint::Position(c) => (c - *p).normalize_or_zero(),
                    LightPoint::Direction(d) => d,
                };
                n.dot(towards) < TERMINATOR_COS
            })
            .collect();
        let shading = Shading::new(&irradiance, object, terminator)
            .with_distance(positions.iter().map(|p| p.distance(camera.eye)).collect());
        // What the techniques' maps cover: the casters that can shadow a receiver in view (the
        // reference above traced every caster).
        let geometry = scene.casting_onto(&light, &positions);
        let seen = SeenDepth::of_points(view, &positions);
        let views = LightViews::plan_seen(&light, &geometry, seen.as_ref(), &positions);
        let uncovered = uncovered(&spec, &light, &geometry, &views, &positions);
        Ok(Self {
            spec,
            geometry,
            seen,
            views,
            uncovered,
            gbuffer: gb,
            pixels,
            unlit_pixels,
            positions,
            normals,
            reference,
            irradiance,
            shading,
            settings,
            reference_ms,
        })
    }

    /// The views of `light` (the scene's light moved, say) over the scene's maps' geometry and
    /// what the camera sees (its depth range and the G-buffer's positions).
    pub fn views_for(&self, light: &Light) -> LightViews {
        LightViews::plan_seen(light, &self.geometry, self.seen.as_ref(), &self.positions)
    }

    /// The receivers as the techniques take them.
    pub fn receivers(&self) -> Receivers<'_> {
        Receivers::new(&self.positions, &self.normals)
    }

    /// Reference visibilities of the same receivers under another light (same sampling
    /// settings); NaN where that light leaves a receiver unlit.
    pub fn reference_under(&self, light: &Light) -> Vec<f32> {
        RayTracer::new(&self.geometry.casters)
            .references(light, &self.positions, &self.normals, &self.settings)
            .iter()
            .map(|r| r.map_or(f32::NAN, |r| r.visibility))
            .collect()
    }

    /// Reference visibilities.
    pub fn reference_v(&self) -> Vec<f32> {
        self.reference.iter().map(|r| r.visibility).collect()
    }

    /// RMS over penumbra receivers of the reference's standard error, times 255
    /// (0 when the scene has no penumbra).
    pub fn std_error_255(&self) -> f64 {
        let pen: Vec<f64> = self
            .reference
            .iter()
            .filter(|r| {
                r.visibility > crate::metrics::PENUMBRA_LO
                    && r.visibility < crate::metrics::PENUMBRA_HI
            })
            .map(|r| (r.std_error as f64 * 255.0).powi(2))
            .collect();
        if pen.is_empty() {
            0.0
        } else {
            (pen.iter().sum::<f64>() / pen.len() as f64).sqrt()
        }
    }

    /// Largest per-receiver standard error, times 255.
    pub fn max_std_error_255(&self) -> f64 {
        self.reference
            .iter()
            .map(|r| r.std_error as f64 * 255.0)
            .fold(0.0, f64::max)
    }
}
