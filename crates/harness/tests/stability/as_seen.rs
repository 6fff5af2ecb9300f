//! What a person sees (issue: full resolution): at 1280 x 720 with 1024² maps, the techniques a
//! user picks by default draw no more dark blotches than PCSS on the bunny and on low-poly meshes
//! (`harness::as_seen`; flat facets and interpenetrating parts, disk, rect and sphere lights):
//! receivers the reference sees at least half lit that a technique draws at less than half of
//! it, at most PCSS's count plus 0.1% of the frame's pixels, on both backends, which agree; and
//! their mean FLIP is no worse than the hard shadow map's, and their light leaks stay within
//! [`LEAKS_OVER_PCSS`] of PCSS's. occlusion-slices' default draws no lighter lines through the
//! umbra under a body (`occlusion_slices_draws_no_light_lines_through_the_umbra`).

use super::{gpu, techniques};
use harness::as_seen::{HEIGHT, WIDTH, artefacts, flip, frame};
use soft_shadow_core::{Backend, Context};
use soft_shadow_reference::scenes::catalogue::{AS_SEEN_NAMES, build};

/// The configurations checked: the viewer's defaults of the two techniques whose artefacts the
/// report's small G-buffers missed, and PCSS, the baseline they are held to.
const CHECKED: [(&str, &str); 3] = [
    ("penumbra-limit", "silhouette-f32"),
    ("penumbra-limit", "depth-image-f32"),
    ("occlusion-slices", "nbuffer-8-chain"),
];

/// Light leaks (receivers lighter than the reference by 1/4 of the light where it is umbra all
/// around, per million receivers) a checked configuration may draw beyond PCSS's on a scene.
/// Measured: penumbra-limit 0-19 (its depth image drew 819 on the bunny before inner edges took
/// their far side's depth as a lower limit: holes of light in the umbra under it);
/// occlusion-slices 0-47 with the product (1035 on the bunny and 486 on the rocks while it
/// skipped the receiver's own slice: a ring of light under a body on the ground), 0 chained.
const LEAKS_OVER_PCSS: f64 = 100.0;

#[test]
fn no_more_dark_blotches_than_pcss_at_viewing_resolution() {
    let allowance = (WIDTH * HEIGHT) as usize / 1000;
    let all = techniques();
    let find = |name: &str, variant: &str| {
        all.iter()
            .find(|t| t.name() == name && t.variant() == variant)
            .unwrap_or_else(|| panic!("{name} {variant} is in the technique list"))
    };
    let (pcss, hard) = (find("pcss", "7x7-9x9"), find("hard-shadow-map", "nearest"));
    let mut failures = Vec::new();
    for name in std::iter::once("bunny").chain(AS_SEEN_NAMES) {
        let scene = frame(build(name).unwrap()).unwrap();
        let light = &scene.spec.light;
        let darkened = |t: &dyn soft_shadow_core::DynTechnique, backend: Backend| {
            let ctx = match backend {
                Backend::Cpu => Context::Cpu(super::common::cpu()),
                Backend::Gpu => Context::Gpu(gpu()?),
            };
            let v = t
                .generate_in(ctx, &scene.geometry, light, &scene.views, 1024)
                .and_then(|m| m.evaluate(gpu(), &scene.receivers()))
                .unwrap();
            let a = artefacts(&scene, &v);
            let score = flip(&scene, &v).0;
            println!(
                "{name} {} {} {backend:?}: FLIP {:.4} (p95 {:.3}), darkened {}, false umbra \
                 {:.0}/M, leaks {:.0}/M ({:.0}/M on objects)",
                t.name(),
                t.variant(),
                score.mean,
                score.p95,
                a.darkened,
                a.per_million(a.false_umbra),
                a.per_million(a.leaks),
                a.per_million(a.object_leaks),
            );
            Some((a.darkened, score.mean, a.per_million(a.leaks)))
        };
        let (baseline, _, pcss_leaks) = darkened(pcss.as_ref(), Backend::Cpu).unwrap();
        let hard_flip = darkened(hard.as_ref(), Backend::Cpu).unwrap().1;
        for (t, v) in CHECKED {
            let t = find(t, v);
            if !t.models(light.kind()) {
                continue;
            }
            let (cpu, cpu_flip, leaks) = darkened(t.as_ref(), Backend::Cpu).unwrap();
            if leaks > pcss_leaks + LEAKS_OVER_PCSS {
                failures.push(format!(
                    "{name} {} {}: {leaks:.0} leaks per million against PCSS's {pcss_leaks:.0}",
                    t.name(),
                    t.variant()
                ));
            }
            if cpu_flip > hard_flip {
                failures.push(format!(
                    "{name} {} {}: mean FLIP {cpu_flip:.4} against the hard map's {hard_flip:.4}",
                    t.name(),
                    t.variant()
                ));
            }
            if cpu > baseline + allowance {
                failures.push(format!(
                    "{name} {} {}: {cpu} darkened against PCSS's {baseline}",
                    t.name(),
                    t.variant()
                ));
            }
            if let Some((gpu, ..)) = darkened(t.as_ref(), Backend::Gpu)
                && gpu.abs_diff(cpu) > allowance / 10
            {
                failures.push(format!(
                    "{name} {} {}: {gpu} darkened on the GPU, {cpu} on the CPU",
                    t.name(),
                    t.variant()
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Lighter lines through the umbra under a body (issue: full resolution): where a body crosses
/// a slice plane, the slices on either side of it hide complementary parts of the light, and
/// the product of their factors lets through a share that no ray finds (a faint arc under the
/// bunny). In the bunny's and the low-poly rocks' frames (1280 x 720, 1024² maps), the
/// receivers in the reference's umbra all around (`harness::as_seen::ISOLATION` pixels) that
/// occlusion-slices' default draws lighter than the reference by 1/16 of the light: at most
/// 0.5% of them, on both backends. Measured: the default (8 N-Buffer slices, chained) 0 of 6,900 and 9 of
/// 10,880 on both; the product, the default before, 466 and 340, which the test also checks so
/// that it can fail.
#[test]
fn occlusion_slices_draws_no_light_lines_through_the_umbra() {
    use harness::as_seen::{Around, LIT_WEIGHT};
    use harness::metrics::PENUMBRA_LO;
    use occlusion_slices::{Combination, OcclusionSlices, Prefilter};
    use soft_shadow_core::TechniqueInfo;
    let registry = soft_shadow_techniques::registry();
    let default = registry
        .family("occlusion-slices")
        .unwrap()
        .default_variant()
        .clone();
    let product: soft_shadow_core::Technique =
        std::sync::Arc::new(OcclusionSlices::new(8, Prefilter::NBuffer));
    assert_eq!(
        default.call(),
        OcclusionSlices::new(8, Prefilter::NBuffer)
            .with_combination(Combination::Chain)
            .call()
    );
    let mut failures = Vec::new();
    for name in ["bunny", "low-poly-rocks"] {
        let scene = frame(build(name).unwrap()).unwrap();
        let reference = scene.reference_v();
        let around = Around::new(&scene, &reference);
        let counted: Vec<usize> = (0..reference.len())
            .filter(|&k| {
                scene.shading.weight[k] >= LIT_WEIGHT
                    && around.all(scene.pixels[k], |r| r <= PENUMBRA_LO)
            })
            .collect();
        let lines = |t: &soft_shadow_core::Technique, backend: Backend| {
            let ctx = match backend {
                Backend::Cpu => Context::Cpu(super::common::cpu()),
                Backend::Gpu => Context::Gpu(gpu()?),
            };
            let v = t
                .generate_in(ctx, &scene.geometry, &scene.spec.light, &scene.views, 1024)
                .and_then(|m| m.evaluate(gpu(), &scene.receivers()))
                .unwrap();
            Some(
                counted
                    .iter()
                    .filter(|&&k| v[k] > reference[k] + 1.0 / 16.0)
                    .count(),
            )
        };
        let bound = counted.len() / 200;
        let before = lines(&product, Backend::Cpu).unwrap();
        println!(
            "{name}: {} umbra receivers, the product draws {before} lighter by 1/16",
            counted.len()
        );
        if before <= bound {
            failures.push(format!(
                "{name}: the product draws {before} of {} lighter, within the bound {bound}: \
                 the test no longer sees the lines",
                counted.len()
            ));
        }
        for backend in [Backend::Cpu, Backend::Gpu] {
            let Some(n) = lines(&default, backend) else {
                continue;
            };
            println!("{name}: the default on {backend:?} draws {n}");
            if n > bound {
                failures.push(format!(
                    "{name} {backend:?}: {n} of {} umbra receivers lighter by 1/16 (at most {bound})",
                    counted.len()
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
