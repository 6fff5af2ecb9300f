//! The viewer's scenes of many lamps: the frame pipeline on the renderer's device, each lamp's
//! `V` in its layer, the lamps' shading against its Rust mirror, and the drawn lighting against
//! the ray-traced reference. On lavapipe in CI (`crate::common::gpu_for_test`).

use crate::common::gpu_for_test;
use glam::Vec3;
use shadow_frame::budget::irradiance_estimate;
use shadow_frame::lighting::range_window;
use shadow_frame::scene::LightSource;
use shadow_frame::{LightState, ShadowConfig};
use soft_shadow_core::gpu::raster::read_texture;
use soft_shadow_reference::ground_truth::{GroundTruthSettings, RayTracer};
use viewer::lamps::LampsView;
use viewer::scene::{SceneSource, load};
use viewer::{FrameSettings, Renderer, ViewMode};

const SIZE: (u32, u32) = (128, 72);

/// The night street in the viewer, 128 x 72, under a 24 ms budget (each lamp's `V` predicted
/// over all 9,216 texels), two frames of a still camera: the second makes no
/// map; the frame equals the Rust shading of the same G-buffer and layers within 1/255 rms (2
/// at most: 8-bit rounding of values computed in another order); the lamps' weights equal the
/// budget's (`irradiance_estimate`) faded by `range_window` within their range; and the drawn lighting (every lamp's
/// weight times its `V`) is within a quarter of the no-shadow lighting's error from the
/// reference's.
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn the_night_streets_lamps_draw_their_shadows_in_the_viewer() {
    lamps_draw_their_shadows(
        "the_night_streets_lamps_draw_their_shadows_in_the_viewer",
        "night-street",
        24.0,
        4,
    );
}

/// The same for the room's three lamps under a 40 ms budget, which buys each a shadow.
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn the_rooms_lamps_draw_their_shadows_in_the_viewer() {
    lamps_draw_their_shadows(
        "the_rooms_lamps_draw_their_shadows_in_the_viewer",
        "room-lamps",
        40.0,
        3,
    );
}

/// Scene of lamps `name` under `budget_ms`, at least `shadowed` lamps of it with maps.
fn lamps_draw_their_shadows(test: &str, name: &str, budget_ms: f64, shadowed: usize) {
    let Some(ctx) = gpu_for_test(test) else {
        return;
    };
    let scene = load(&SceneSource::Catalogue(name.into())).unwrap();
    let settings = FrameSettings {
        width: SIZE.0,
        height: SIZE.1,
        camera: scene.camera,
    };
    let r = Renderer::new(
        ctx.device.clone(),
        ctx.queue.clone(),
        &scene.geometry,
        settings,
    )
    .unwrap();
    let mut view = LampsView::new(&r, name, budget_ms).unwrap();
    for frame in 0..2 {
        let mut enc = r.gpu.device.create_command_encoder(&Default::default());
        view.encode(&r, &mut enc, ViewMode::Shaded, None, None)
            .unwrap();
        r.gpu.queue.submit([enc.finish()]);
        let stats = view.stats.as_ref().unwrap();
        if frame == 1 {
            assert_eq!(stats.maps_generated, 0, "{}", stats.summary());
        }
    }
    let image = r.read_color().unwrap();
    let (pt, nt) = r.gbuffer();
    let p: Vec<[f32; 4]> = read_texture(&r.gpu, pt, 0, wgpu::TextureAspect::All, 16).unwrap();
    let n: Vec<[f32; 4]> = read_texture(&r.gpu, nt, 0, wgpu::TextureAspect::All, 16).unwrap();
    let casters = view.lamps.scene.geometry().casters;
    let world = &view.lamps.scene.world;
    let lamps = view.lamps.lamps.clone();
    let layers: Vec<Vec<f32>> = (0..lamps.len() as u32)
        .map(|k| read_texture(&r.gpu, view.visibility(), k, wgpu::TextureAspect::All, 4).unwrap())
        .collect();
    let covered: Vec<usize> = (0..p.len()).filter(|&i| p[i][3] > 0.5).collect();
    let at = |i: usize| (Vec3::from_slice(&p[i][..3]), Vec3::from_slice(&n[i][..3]));
    // The shading against its mirror.
    let shade = view.shade();
    let (mut sq, mut worst) = (0.0f64, 0.0f32);
    for &i in &covered {
        let (pos, nor) = at(i);
        let want = shade.radiance(pos, nor, |k| layers[k][i]);
        let got = image.as_raw()[i * 4] as f32 / 255.0;
        sq += ((got - want) as f64 * 255.0).powi(2);
        worst = worst.max((got - want).abs() * 255.0);
    }
    let rms = (sq / covered.len().max(1) as f64).sqrt();
    // The weights against the budget's.
    for (k, &e) in lamps.iter().enumerate() {
        let light = world.get::<LightSource>(e).unwrap().0;
        let config = world.get::<ShadowConfig>(e).unwrap();
        let (c, range) = shadow_frame::influence(&light, config.range);
        for &i in covered.iter().step_by(7) {
            let (pos, nor) = at(i);
            let x = pos.distance_squared(c) / (range * range);
            let want = if x <= 1.0 {
                irradiance_estimate(&light, config.intensity, pos, nor) * range_window(x)
            } else {
                0.0
            };
            let got = shade.lamps[k].irradiance(pos, nor);
            assert!(
                (got - want).abs() <= 1e-5 * want.max(1e-3),
                "lamp {k} at {pos}: {got} against the budget's {want}"
            );
        }
    }
    // The lighting against the reference, on every third covered pixel.
    let truth = RayTracer::new(&casters);
    let sample: Vec<usize> = covered.iter().copied().step_by(3).collect();
    let (pos, nor): (Vec<Vec3>, Vec<Vec3>) = sample.iter().map(|&i| at(i)).unzip();
    let settings = GroundTruthSettings {
        strata_side: 8,
        replicates: 1,
        ..Default::default()
    };
    let (mut drawn, mut unshadowed, mut reference) = (
        vec![0.0f64; sample.len()],
        vec![0.0f64; sample.len()],
        vec![0.0f64; sample.len()],
    );
    let mut with_maps = 0;
    for (k, &e) in lamps.iter().enumerate() {
        let light = world.get::<LightSource>(e).unwrap().0;
        with_maps += world.get::<LightState>(e).unwrap().maps.is_some() as usize;
        let refs = truth.references(&light, &pos, &nor, &settings);
        for (j, &i) in sample.iter().enumerate() {
            let w = shade.lamps[k].irradiance(pos[j], nor[j]) as f64;
            if w == 0.0 {
                continue;
            }
            let v_ref = refs[j].as_ref().map_or(1.0, |r| r.visibility) as f64;
            drawn[j] += w * layers[k][i] as f64;
            unshadowed[j] += w;
            reference[j] += w * v_ref;
        }
    }
    let top = unshadowed.iter().copied().fold(0.0f64, f64::max);
    let err = |a: &[f64]| {
        let s: f64 = a.iter().zip(&reference).map(|(x, r)| (x - r).powi(2)).sum();
        255.0 * (s / a.len() as f64).sqrt() / top
    };
    let (e_drawn, e_none) = (err(&drawn), err(&unshadowed));
    println!(
        "{test}: {} covered pixels, {with_maps} of {} lamps with maps; shading against the Rust \
         mirror rms {rms:.3}/255, worst {worst:.1}; lighting against the reference {e_drawn:.2}/255 \
         (no shadow {e_none:.2}) over {} pixels",
        covered.len(),
        lamps.len(),
        sample.len()
    );
    assert!(covered.len() > p.len() / 2, "the scene fills the frame");
    assert!(with_maps >= shadowed, "{with_maps} lamps with maps");
    assert!(
        rms <= 1.0 && worst <= 2.0,
        "shading: rms {rms:.3}, worst {worst:.1}"
    );
    assert!(
        e_drawn <= 0.25 * e_none,
        "lighting {e_drawn:.2}/255 from the reference against {e_none:.2} with no shadow"
    );
}

/// The frame's pixels against the Rust mirror: the shaded value, or in `V` mode the lamps' `V`
/// weighed by their light; returns the rms and the worst difference, 1/255.
fn against_the_mirror(r: &Renderer, view: &LampsView, mode: ViewMode) -> (f64, f32) {
    let image = r.read_color().unwrap();
    let (pt, nt) = r.gbuffer();
    let p: Vec<[f32; 4]> = read_texture(&r.gpu, pt, 0, wgpu::TextureAspect::All, 16).unwrap();
    let n: Vec<[f32; 4]> = read_texture(&r.gpu, nt, 0, wgpu::TextureAspect::All, 16).unwrap();
    let layers: Vec<Vec<f32>> = (0..view.lamps.lamps.len() as u32)
        .map(|k| read_texture(&r.gpu, view.visibility(), k, wgpu::TextureAspect::All, 4).unwrap())
        .collect();
    let shade = view.shade();
    let (mut sq, mut worst, mut count) = (0.0f64, 0.0f32, 0);
    for i in (0..p.len()).filter(|&i| p[i][3] > 0.5) {
        let (pos, nor) = (Vec3::from_slice(&p[i][..3]), Vec3::from_slice(&n[i][..3]));
        let want = match mode {
            ViewMode::Visibility => {
                let (lit, shadowed) = shade.lighting(pos, nor, |k| layers[k][i]);
                if lit > 0.0 { shadowed / lit } else { 1.0 }
            }
            _ => shade.radiance(pos, nor, |k| layers[k][i]),
        };
        let got = image.as_raw()[i * 4] as f32 / 255.0;
        sq += ((got - want) as f64 * 255.0).powi(2);
        worst = worst.max((got - want).abs() * 255.0);
        count += 1;
    }
    assert!(count > 0, "no covered pixel");
    ((sq / count as f64).sqrt(), worst)
}

/// A view that is not 16:9 gets receivers of its own shape (a square view, 90 x 90), a resize
/// there and back without a frame between draws into the renderer's new targets (the lamps'
/// pass bound to the old ones drew nothing on them), and `V` mode shows the lamps' `V` weighed
/// by their light; each frame equals its Rust mirror within 1/255 rms (2 at most).
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn the_lamps_follow_the_views_shape_and_size() {
    let test = "the_lamps_follow_the_views_shape_and_size";
    let Some(ctx) = gpu_for_test(test) else {
        return;
    };
    let scene = load(&SceneSource::Catalogue("night-street".into())).unwrap();
    let settings = FrameSettings {
        width: 96,
        height: 96,
        camera: scene.camera,
    };
    let mut r = Renderer::new(
        ctx.device.clone(),
        ctx.queue.clone(),
        &scene.geometry,
        settings,
    )
    .unwrap();
    let mut view = LampsView::new(&r, "night-street", 16.0).unwrap();
    assert_eq!(view.lamps.size(), (90, 90));
    let draw = |r: &Renderer, view: &mut LampsView, mode| {
        let mut enc = r.gpu.device.create_command_encoder(&Default::default());
        view.encode(r, &mut enc, mode, None, None).unwrap();
        r.gpu.queue.submit([enc.finish()]);
        against_the_mirror(r, view, mode)
    };
    let square = draw(&r, &mut view, ViewMode::Shaded);
    r.resize(128, 72).unwrap();
    r.resize(96, 96).unwrap();
    let again = draw(&r, &mut view, ViewMode::Shaded);
    r.resize(160, 60).unwrap();
    let wide = draw(&r, &mut view, ViewMode::Visibility);
    let receivers = view.lamps.size();
    println!(
        "{test}: against the mirror (rms, worst, 1/255): square {square:?}, resized there and \
         back {again:?}, 160 x 60 in V mode {wide:?}; receivers {receivers:?}"
    );
    assert_eq!(receivers, (240, 90));
    for (what, (rms, worst)) in [("square", square), ("back", again), ("wide, V", wide)] {
        assert!(
            rms <= 1.0 && worst <= 2.0,
            "{what}: rms {rms:.3}, worst {worst:.1}"
        );
    }
}
