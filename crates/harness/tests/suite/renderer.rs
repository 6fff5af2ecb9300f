//! The viewer's renderer against the CPU path, and what a static scene's frame costs in
//! transfers. Both run on lavapipe in CI (`crate::common::gpu_for_test`).

use crate::common::gpu_for_test;
use glam::Vec3;
use soft_shadow_core::gpu::raster::read_texture;
use soft_shadow_core::{Receivers, SceneGeometry, ShadowTechnique};
use viewer::shade::ShadeUniform;
use viewer::{Frame, FrameSettings, Renderer, Shadow, ViewMode, model_on_ground, moving_light};

const SIZE: u32 = 96;
const RESOLUTION: u32 = 512;

fn scene() -> (SceneGeometry, soft_shadow_core::Camera) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/stanford-bunny.glb"
    );
    let model = shadow_frame::gltf::import_gltf_file(std::path::Path::new(path)).unwrap();
    model_on_ground(&model)
}

pub(crate) fn renderer(test: &str) -> Option<(Renderer, SceneGeometry)> {
    let ctx = gpu_for_test(test)?;
    let (geometry, camera) = scene();
    let settings = FrameSettings {
        width: SIZE,
        height: SIZE,
        camera,
    };
    let r = Renderer::new(ctx.device.clone(), ctx.queue.clone(), &geometry, settings).unwrap();
    Some((r, geometry))
}

/// The shaded frame of `t` under `light`.
pub(crate) fn frame<'a>(
    t: &'a dyn soft_shadow_core::DynTechnique,
    light: &'a soft_shadow_core::Light,
) -> Frame<'a> {
    Frame {
        light,
        shadow: Shadow {
            technique: t,
            resolution: RESOLUTION,
        },
        compare: None,
        mode: ViewMode::Shaded,
    }
}

/// A frame drawn by the renderer's own passes with the technique's `visibility()` over its
/// G-buffer equals, within 1/255 rms, the same shading of the same pixels with `V` from the
/// technique's CPU path.
fn frame_matches_cpu<T: ShadowTechnique>(test: &str, t: T) {
    let Some((r, geometry)) = renderer(test) else {
        return;
    };
    let light = moving_light(1, 8);
    r.render(&frame(&t, &light)).unwrap();
    let image = r.read_color().unwrap();
    let (pt, nt) = r.gbuffer();
    let p: Vec<[f32; 4]> = read_texture(&r.gpu, pt, 0, wgpu::TextureAspect::All, 16).unwrap();
    let n: Vec<[f32; 4]> = read_texture(&r.gpu, nt, 0, wgpu::TextureAspect::All, 16).unwrap();
    let covered: Vec<usize> = (0..p.len()).filter(|&i| p[i][3] > 0.5).collect();
    assert!(
        covered.len() > p.len() / 2,
        "{test}: the model and ground fill the frame"
    );
    let positions: Vec<Vec3> = covered
        .iter()
        .map(|&i| Vec3::from_slice(&p[i][..3]))
        .collect();
    let normals: Vec<Vec3> = covered
        .iter()
        .map(|&i| Vec3::from_slice(&n[i][..3]))
        .collect();
    let maps = t
        .generate_cpu(crate::common::cpu(), &geometry, &light, RESOLUTION)
        .unwrap();
    let v = t
        .evaluate_cpu(&maps, &Receivers::new(&positions, &normals))
        .unwrap();
    let shade = ShadeUniform::new(&light).unwrap();
    // Squared error and count: all, ground (y = 0, facing up), model; penumbra (0 < V < 1).
    let mut sums = [(0.0f64, 0usize); 4];
    let mut shadowed = 0;
    for (k, &i) in covered.iter().enumerate() {
        let want = shade.radiance(positions[k], normals[k], v[k]);
        let got = image.as_raw()[i * 4] as f32 / 255.0;
        let e = ((got - want) as f64 * 255.0).powi(2);
        let ground = positions[k].y.abs() < 1e-4 && normals[k].y > 0.99;
        let penumbra = v[k] > 0.0 && v[k] < 1.0;
        for (s, on) in sums.iter_mut().zip([true, ground, !ground, penumbra]) {
            if on {
                *s = (s.0 + e, s.1 + 1);
            }
        }
        shadowed += (v[k] < 0.5) as usize;
    }
    let [rms, ground, model, penumbra] = sums.map(|(e, n)| (e / n.max(1) as f64).sqrt());
    println!(
        "{test}: {} covered pixels ({} ground, {} model, {} penumbra), {shadowed} with V < 0.5, \
         rms {rms:.3}/255 (ground {ground:.3}, model {model:.3}, penumbra {penumbra:.3})",
        covered.len(),
        sums[1].1,
        sums[2].1,
        sums[3].1
    );
    assert!(
        shadowed > covered.len() / 50,
        "{test}: the frame shows a shadow"
    );
    assert!(rms <= 1.0, "{test}: rms {rms:.3}/255 against the CPU path");
    for i in (0..p.len()).filter(|&i| p[i][3] <= 0.5) {
        let want = (viewer::shade::BACKGROUND * 255.0).round() as u8;
        assert_eq!(image.as_raw()[i * 4], want, "{test}: background pixel {i}");
    }
}

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn penumbra_limit_frame_matches_the_cpu_path() {
    frame_matches_cpu(
        "penumbra_limit_frame_matches_the_cpu_path",
        penumbra_limit::PenumbraLimit::new(penumbra_limit::Generator::Silhouette),
    );
}

#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn pcss_frame_matches_the_cpu_path() {
    frame_matches_cpu(
        "pcss_frame_matches_the_cpu_path",
        shadow_maps::ShadowMapBaseline::new(shadow_maps::Filter::Pcss),
    );
}

/// After the first frame, a static scene's frames upload no geometry (the casters stay on the
/// GPU, derived data such as silhouette edges is kept with them) and map no buffer.
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn a_static_scenes_second_frame_maps_uploads_and_allocates_nothing() {
    let test = "a_static_scenes_second_frame_maps_uploads_and_allocates_nothing";
    let Some((r, _)) = renderer(test) else {
        return;
    };
    let t = penumbra_limit::PenumbraLimit::new(penumbra_limit::Generator::Silhouette);
    let uploads = r.gpu.geometry_uploads();
    r.render(&frame(&t, &moving_light(0, 8))).unwrap();
    r.gpu.wait().unwrap();
    let counts = |g: &soft_shadow_core::GpuContext| {
        (
            g.geometry_uploads(),
            g.buffer_maps(),
            g.textures_created(),
            g.buffers_created(),
        )
    };
    let after_first = counts(&r.gpu);
    // The silhouette edges are derived from the casters on first use.
    assert_eq!(after_first.0, uploads + 1, "{test}: first frame");
    assert_eq!(after_first.1, 0, "{test}: the first frame maps no buffer");
    r.render(&frame(&t, &moving_light(1, 8))).unwrap();
    r.gpu.wait().unwrap();
    // The first frame's maps and scratch were recycled: the second reuses every one.
    assert!(after_first.2 > 0, "{test}: the first frame makes its maps");
    assert_eq!(counts(&r.gpu), after_first, "{test}: second frame");
}

/// Every line of the README's snippet under `heading`, in order, is a line of the file at
/// `path` (from the repository root), which the tests compile and run.
fn assert_readme_snippet_is(heading: &str, path: &str) {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let readme = std::fs::read_to_string(format!("{root}/README.md")).unwrap();
    let code = std::fs::read_to_string(format!("{root}/{path}")).unwrap();
    let section = readme.split(heading).nth(1).expect("README section");
    let snippet = section
        .split("```rust\n")
        .nth(1)
        .and_then(|s| s.split("```").next())
        .expect("README snippet");
    let mut lines = code.lines().map(str::trim);
    let mut checked = 0;
    for want in snippet.lines().map(str::trim) {
        if want.is_empty() || want.starts_with("//") {
            continue;
        }
        assert!(
            lines.any(|l| l == want),
            "README line {want:?} is not (in order) in {path}"
        );
        checked += 1;
    }
    assert!(checked >= 10, "{checked} lines checked");
}

/// The README's integration snippet is the example renderer's code (so it compiles and runs in
/// the tests above).
#[test]
fn the_readme_snippet_is_the_renderers_code() {
    assert_readme_snippet_is(
        "### In your own wgpu renderer",
        "crates/viewer/src/renderer.rs",
    );
}

/// The README's standalone snippet is the `standalone` example's code (built by the tests).
#[test]
fn the_readme_standalone_snippet_is_the_examples_code() {
    assert_readme_snippet_is("### Standalone", "crates/harness/examples/standalone.rs");
}

/// The views overlay colours each receiver by the view of the light it reads: on `room-lamp`
/// (a lamp among furniture, its cube faces) and `street-sun` (cascades down the street), every
/// pixel that one view holds whole shows that view's colour ([`viewer::view_colour`], scaled
/// by the shading), as `LightViews::weight` says on the CPU, and the frame shows several views.
#[test]
#[cfg_attr(
    no_gpu_adapter,
    ignore = "needs a GPU adapter: no Vulkan driver found (apt-get install mesa-vulkan-drivers)"
)]
fn the_views_overlay_colours_each_receiver_by_its_view() {
    let test = "the_views_overlay_colours_each_receiver_by_its_view";
    let Some(ctx) = gpu_for_test(test) else {
        return;
    };
    for (name, least) in [("room-lamp", 5), ("street-sun", 3)] {
        let spec = soft_shadow_reference::scenes::catalogue::build(name).unwrap();
        let geometry = spec.to_scene().unwrap().geometry();
        let (w, h) = (128, 96);
        let settings = FrameSettings {
            width: w,
            height: h,
            camera: spec.camera,
        };
        let r = Renderer::new(ctx.device.clone(), ctx.queue.clone(), &geometry, settings).unwrap();
        let pcss = shadow_maps::ShadowMapBaseline::new(shadow_maps::Filter::Pcss);
        let mut f = frame(&pcss, &spec.light);
        f.mode = ViewMode::Views;
        r.render(&f).unwrap();
        let image = r.read_color().unwrap();
        let (pt, _) = r.gbuffer();
        let p: Vec<[f32; 4]> = read_texture(&r.gpu, pt, 0, wgpu::TextureAspect::All, 16).unwrap();
        // The views the renderer plans for this camera.
        let views = soft_shadow_core::LightViews::plan(&spec.light, &geometry, r.seen().as_ref());
        let (mut whole, mut shown) = (0, std::collections::BTreeSet::new());
        for (i, t) in p.iter().enumerate().filter(|(_, t)| t[3] > 0.5) {
            let q = Vec3::from_slice(&t[..3]);
            let Some(view) = (0..views.len()).find(|&k| views.weight(k, q) >= 0.999) else {
                continue;
            };
            let px = &image.as_raw()[i * 4..i * 4 + 3];
            let got = Vec3::new(px[0] as f32, px[1] as f32, px[2] as f32);
            let want = viewer::view_colour(view);
            // The same colour up to the shading's grey factor (and 8-bit rounding).
            let scale = got.dot(want) / want.length_squared();
            let off = (got - want * scale).length();
            assert!(
                off <= 3.0 && scale > 0.3 * 255.0,
                "{name}: pixel {i} of view {view} shows {got} for {want} (off by {off:.1})"
            );
            whole += 1;
            shown.insert(view);
        }
        println!(
            "{name}: {} views ({}), {whole} pixels held whole by one, {} views shown",
            views.len(),
            views.kind_name(),
            shown.len()
        );
        assert!(whole > (w * h / 4) as usize, "{name}: {whole} pixels");
        assert!(shown.len() >= least, "{name}: {} views shown", shown.len());
    }
}
