//! Reuse across generations of one size (`soft_shadow_core::gpu::pool`): for every technique, maps
//! recycled after a generation of another scene serve the next generation without a new texture
//! or buffer, and that generation's `V` is bit for bit the one from fresh resources (no kernel
//! reads what it did not write).

use super::receivers;
use crate::common::gpu_for_test;
use harness::report::all_techniques;
use soft_shadow_core::gpu::GpuScene;
use soft_shadow_core::{GpuContext, Receivers as Recv};
use soft_shadow_reference::scenes::catalogue::build;
use soft_shadow_reference::scenes::relight::relight;

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn recycled_maps_serve_the_next_generation_unchanged() {
    let test = "recycled_maps_serve_the_next_generation_unchanged";
    let Some(ctx) = gpu_for_test(test) else {
        return;
    };
    let (a_spec, b_spec) = (build("torus").unwrap(), build("plane-occluder").unwrap());
    let (a, b) = (receivers(&a_spec, 8), receivers(&b_spec, 48));
    let recv = Recv {
        positions: &b.positions,
        normals: &b.normals,
    };
    let counts = |g: &GpuContext| (g.textures_created(), g.buffers_created());
    for t in all_techniques(true) {
        let models = |k| t.models(k);
        let (Some(a_light), Some(b_light)) = (
            relight(&a_spec.light, &a.geometry.bounds, models),
            relight(&b_spec.light, &b.geometry.bounds, models),
        ) else {
            continue;
        };
        let (a_scene, b_scene) = (
            GpuScene::new(&ctx, &a.geometry).unwrap(),
            GpuScene::new(&ctx, &b.geometry).unwrap(),
        );
        let label = format!("{test}: {} {}", t.name(), t.variant());
        let a_views = soft_shadow_core::LightViews::plan(&a_light, &a.geometry, None);
        let b_views = soft_shadow_core::LightViews::plan(&b_light, &b.geometry, None);
        // Fresh resources.
        ctx.clear_pool();
        let fresh = t
            .generate_gpu_on(&ctx, &b_scene, &b_light, &b_views, 64)
            .unwrap();
        let want = fresh.evaluate(Some(&ctx), &recv).unwrap();
        drop(fresh);
        // Resources full of another scene's maps.
        let other = t
            .generate_gpu_on(&ctx, &a_scene, &a_light, &a_views, 64)
            .unwrap();
        other.recycle(Some(&ctx));
        let before = counts(&ctx);
        let reused = t
            .generate_gpu_on(&ctx, &b_scene, &b_light, &b_views, 64)
            .unwrap();
        assert_eq!(
            counts(&ctx),
            before,
            "{label}: allocated with its maps recycled"
        );
        let got = reused.evaluate(Some(&ctx), &recv).unwrap();
        let differ = want.iter().zip(&got).filter(|(x, y)| x != y).count();
        assert_eq!(
            differ, 0,
            "{label}: {differ} receivers differ from fresh resources"
        );
    }
}

/// A texture or buffer recycled on one thread is not served to another: the work recorded with
/// it may still sit in the recycling thread's encoder, and another thread's submission would
/// run first and have that work overwrite its maps (the race that once cleared a PCF depth map
/// in the stability suite, whose tests share one context). The recycling thread reuses it.
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn resources_recycled_on_one_thread_serve_only_that_thread() {
    let Some(ctx) = gpu_for_test("resources_recycled_on_one_thread_serve_only_that_thread") else {
        return;
    };
    let desc = wgpu::TextureDescriptor {
        label: Some("pool thread test"),
        size: wgpu::Extent3d {
            width: 4,
            height: 4,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    };
    let bdesc = wgpu::BufferDescriptor {
        label: Some("pool thread test"),
        size: 256,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    };
    ctx.recycle_texture(ctx.texture(&desc));
    ctx.recycle_buffer(ctx.buffer(&bdesc));
    let counts = || (ctx.textures_created(), ctx.buffers_created());
    let before = counts();
    std::thread::scope(|s| {
        s.spawn(|| {
            let (_t, _b) = (ctx.texture(&desc), ctx.buffer(&bdesc));
        });
    });
    assert_eq!(
        counts(),
        (before.0 + 1, before.1 + 1),
        "another thread was served resources recycled here"
    );
    let (_t, _b) = (ctx.texture(&desc), ctx.buffer(&bdesc));
    assert_eq!(counts(), (before.0 + 1, before.1 + 1), "not reused here");
}

/// Maps go back only to the pool of the context that made them, and follow only there: given
/// another context (a renderer that made a new device; here a second headless one, whose
/// device wgpu's ids do not tell from the first's), `recycle` drops them and `follow` leaves
/// them for a fresh generation (`None`), where they would have put one device's textures in
/// the other's pool (before, `follow` checked only the backend: `Some(0)`).
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn maps_serve_only_the_context_that_made_them() {
    let test = "maps_serve_only_the_context_that_made_them";
    let (Some(a), Some(b)) = (gpu_for_test(test), gpu_for_test(test)) else {
        return;
    };
    let spec = build("torus").unwrap();
    let r = receivers(&spec, 8);
    let t = shadow_maps::ShadowMapBaseline::new(shadow_maps::Filter::Hard);
    let t: &dyn soft_shadow_core::DynTechnique = &t;
    let views = soft_shadow_core::LightViews::plan(&spec.light, &r.geometry, None);
    let scene = GpuScene::new(&a, &r.geometry).unwrap();
    let mut maps = t
        .generate_gpu_on(&a, &scene, &spec.light, &views, 64)
        .unwrap();
    // In the other context nothing is made (`None`); in its own, the same views serve.
    for (ctx, want, what) in [
        (&b, None, "another context"),
        (&a, Some(0), "its own context"),
    ] {
        let followed = maps
            .follow(
                soft_shadow_core::Context::Gpu(ctx),
                &r.geometry,
                &spec.light,
                &views,
                64,
            )
            .unwrap();
        assert_eq!(followed, want, "{what}");
    }
    // Given to the other device's pool, they are dropped: its next generation makes its own.
    maps.recycle(Some(&b));
    let made = b.textures_created();
    let scene_b = GpuScene::new(&b, &r.geometry).unwrap();
    t.generate_gpu_on(&b, &scene_b, &spec.light, &views, 64)
        .unwrap()
        .evaluate(
            Some(&b),
            &Recv {
                positions: &r.positions,
                normals: &r.normals,
            },
        )
        .unwrap();
    assert!(
        b.textures_created() > made,
        "the other pool served a texture"
    );
}
