//! The stability suite: hard cases stay numerically stable for every technique.
//!
//! - `catalogue`: every technique and variant (the baselines too) x every catalogue scene x map
//!   resolutions {16, 256, 2048} x both backends: no NaN or Inf, `V` in [0, 1], one value per
//!   receiver; image error and `V` rms no worse than the hard shadow map's plus 0.5/255 (named
//!   exceptions), and a shadow wherever the reference has one.
//! - `as_seen`: at 1280 x 720 with 1024² maps, on the bunny and low-poly meshes, penumbra-limit
//!   and occlusion-slices draw no more dark blotches than PCSS (plus 0.1% of the frame), CPU and
//!   GPU alike, and their mean FLIP is no worse than the hard shadow map's; occlusion-slices'
//!   default draws no lighter lines through the umbra under a body.
//! - `acne`: on `acne`, no receiver the reference sees lit comes out below 0.98, for every
//!   technique, resolution and backend (checked by `catalogue` on the maps it builds there).
//! - `low_resolution`: at 16² every technique draws a shadow on `plane-occluder` and
//!   `skewed-triangle` (maps cover the casters, not the ground).
//! - `convergence`: from 64² up, a finer map never raises a technique's image error by more than
//!   1/255 (every technique but PCF, on `torus`, `bunny`, `contact`, `overlap`).
//! - `tiny_light`: as the light shrinks to 0.2 mm every technique converges to the hard shadow.
//! - `sphere_spread`: a sphere lamp's penumbrae read at most 5.5/255 sharper off its cube faces'
//!   axes than near them (penumbra-limit's and occlusion-slices' defaults, on
//!   `room-lamp-corner`).
//! - `random_scenes`: proptest scenes of random triangles and lights at scales 1e-3..1e4, with
//!   the assertions of `catalogue`.
//!
//! A technique that does not model a scene's light kind runs under the nearest light it does
//! model (`soft_shadow_reference::scenes::relight`): occlusion-slices under a distant light's equal square,
//! linear-light under a rect's mid-line. With `CI` set a missing GPU adapter fails the suite;
//! elsewhere the GPU half is skipped with one line.
//!
//! `STABILITY_TIMES=1 cargo test --release --test stability -- --nocapture` prints
//! each configuration's generation and evaluation time (`TIME <ms> <configuration>`).

#[path = "../common/mod.rs"]
mod common;

mod acne;
mod as_seen;
mod catalogue;
mod convergence;
mod low_resolution;
mod near_field;
mod random_scenes;
mod resolved_gap;
mod seams;
mod sphere_spread;
mod tiny_light;

use crate::common::gpu_for_test;
use harness::report::all_techniques;
use soft_shadow_core::{Backend, DynTechnique, GpuContext};
use soft_shadow_reference::scenes::SceneSpec;
use std::sync::OnceLock;

/// Map resolutions of the hard cases.
pub const RESOLUTIONS: [u32; 3] = [16, 256, 2048];

/// Every technique and variant the report runs (accumulation with 16 samples).
pub fn techniques() -> Vec<soft_shadow_core::Technique> {
    all_techniques(true)
}

/// One GPU context for the whole binary (pipelines compile once), or `None` outside CI without
/// an adapter.
pub fn gpu() -> Option<&'static GpuContext> {
    static GPU: OnceLock<Option<GpuContext>> = OnceLock::new();
    GPU.get_or_init(|| gpu_for_test("stability suite")).as_ref()
}

/// The CPU backend, and the GPU one when there is an adapter.
pub fn backends() -> Vec<Backend> {
    common::backends(gpu())
}

/// `spec` itself when `t` models its light, else `spec` under the nearest light `t` models.
pub fn scene_for(t: &dyn DynTechnique, spec: &SceneSpec) -> SceneSpec {
    let bounds = spec.casting_bounds().expect("catalogue scene builds");
    spec.relit(&bounds, |k| t.models(k))
        .unwrap_or_else(|| spec.clone())
}

/// `label` of a configuration, for assertion messages.
pub fn label(t: &dyn DynTechnique, scene: &str, res: u32, backend: Backend) -> String {
    format!(
        "{scene} {} {} {res} {}",
        t.name(),
        t.variant(),
        backend.name()
    )
}

/// Generates `t`'s maps on `backend` and evaluates `V` for `r`; panics naming `what` on an error.
pub fn visibility(
    t: &dyn DynTechnique,
    backend: Backend,
    r: &common::Receivers,
    light: &soft_shadow_core::Light,
    res: u32,
    what: &str,
) -> Vec<f32> {
    let t0 = std::time::Instant::now();
    let maps = t
        .generate_in(
            common::context(backend, gpu()),
            &r.geometry,
            light,
            &r.views(light),
            res,
        )
        .unwrap_or_else(|e| panic!("{what}: generate: {e}"));
    let v = maps
        .evaluate(gpu(), &r.as_receivers())
        .unwrap_or_else(|e| panic!("{what}: evaluate: {e}"));
    if std::env::var_os("STABILITY_TIMES").is_some() {
        eprintln!("TIME {:.1} ms {what}", t0.elapsed().as_secs_f64() * 1e3);
    }
    v
}

/// The reference `V` of `r` under `light` (default settings); NaN where a receiver is unlit.
pub fn reference(light: &soft_shadow_core::Light, r: &common::Receivers) -> Vec<f32> {
    soft_shadow_reference::ground_truth::RayTracer::new(&r.geometry.casters)
        .references(
            light,
            &r.positions,
            &r.normals,
            &soft_shadow_reference::ground_truth::GroundTruthSettings::default(),
        )
        .iter()
        .map(|x| x.map_or(f32::NAN, |x| x.visibility))
        .collect()
}

/// Asserts the stability contract on `v`: one value per receiver, all finite, all in [0, 1].
pub fn assert_stable(v: &[f32], receivers: usize, what: &str) {
    assert_eq!(v.len(), receivers, "{what}: one V per receiver");
    let nonfinite = v.iter().filter(|x| !x.is_finite()).count();
    let out = v
        .iter()
        .filter(|x| x.is_finite() && !(0.0..=1.0).contains(*x))
        .count();
    assert_eq!(nonfinite, 0, "{what}: {nonfinite} non-finite outputs");
    assert_eq!(out, 0, "{what}: {out} outputs outside [0, 1]");
}
