//! Every configuration the report names is built by the Rust expression its `call()` prints:
//! each is written here as code, compiled, and its text (`stringify!`) compared with `call()`,
//! and what it builds has the configuration's name and variant label.

use harness::report::all_techniques;
use linear_light::LinearLight;
use occlusion_slices::{Combination, OcclusionSlices, Prefilter};
use penumbra_limit::{Generator, PenumbraLimit, Storage};
use shadow_maps::{Filter, SamplePattern, ShadowMapBaseline};
use shadow_width::{DepthLayer, Neighbours, ShadowWidth, WidthMethod};
use soft_shadow_core::DynTechnique;

/// `(built, the code that built it)` for each expression.
macro_rules! built {
    ($($e:expr),* $(,)?) => {
        vec![$((Box::new($e) as Box<dyn DynTechnique>, stringify!($e))),*]
    };
}

#[test]
fn every_configuration_is_built_by_its_call() {
    let cases = built![
        ShadowMapBaseline::new(Filter::Hard),
        ShadowMapBaseline::new(Filter::Pcf { radius: 2 }),
        ShadowMapBaseline::new(Filter::Pcss),
        ShadowMapBaseline::new(Filter::Accumulate { samples: 4 }),
        ShadowMapBaseline::new(Filter::Accumulate { samples: 16 }),
        ShadowMapBaseline::new(Filter::Accumulate { samples: 64 }),
        ShadowMapBaseline::new(Filter::Accumulate { samples: 4 })
            .with_pattern(SamplePattern::Rotated),
        ShadowMapBaseline::new(Filter::Accumulate { samples: 16 })
            .with_pattern(SamplePattern::Rotated),
        ShadowMapBaseline::new(Filter::Accumulate { samples: 64 })
            .with_pattern(SamplePattern::Rotated),
        ShadowWidth::new(WidthMethod::Propagate {
            neighbours: Neighbours::Four
        }),
        ShadowWidth::new(WidthMethod::Propagate {
            neighbours: Neighbours::Eight
        }),
        ShadowWidth::new(WidthMethod::Exact),
        ShadowWidth::new(WidthMethod::JumpFlood),
        {
            let mut t = ShadowWidth::new(WidthMethod::Exact);
            t.depth = DepthLayer::BackFaces;
            t
        },
        {
            let mut t = ShadowWidth::new(WidthMethod::Exact);
            t.table = Some(256);
            t
        },
        PenumbraLimit::new(Generator::Silhouette).with_storage(Storage::F32),
        PenumbraLimit::new(Generator::Silhouette).with_storage(Storage::F16),
        PenumbraLimit::new(Generator::Silhouette).with_storage(Storage::Rgba8),
        PenumbraLimit::new(Generator::DepthImage).with_storage(Storage::F32),
        PenumbraLimit::new(Generator::DepthImage).with_storage(Storage::F16),
        PenumbraLimit::new(Generator::DepthImage).with_storage(Storage::Rgba8),
        OcclusionSlices::new(4, Prefilter::Mipmap),
        OcclusionSlices::new(8, Prefilter::Mipmap),
        OcclusionSlices::new(16, Prefilter::Mipmap),
        OcclusionSlices::new(4, Prefilter::NBuffer),
        OcclusionSlices::new(8, Prefilter::NBuffer),
        OcclusionSlices::new(16, Prefilter::NBuffer),
        OcclusionSlices::new(4, Prefilter::Sat),
        OcclusionSlices::new(8, Prefilter::Sat),
        OcclusionSlices::new(16, Prefilter::Sat),
        OcclusionSlices::new(8, Prefilter::Sat).with_combination(Combination::Sum),
        OcclusionSlices::new(8, Prefilter::Sat).with_combination(Combination::Max),
        OcclusionSlices::new(8, Prefilter::Sat).with_combination(Combination::Chain),
        OcclusionSlices::new(8, Prefilter::NBuffer).with_combination(Combination::Chain),
        LinearLight::new(2),
        LinearLight::new(3),
        LinearLight::new(5),
    ];
    let strip = |s: &str| s.split_whitespace().collect::<String>();
    let mut registry = all_techniques(false);
    registry.extend(all_techniques(true));
    for t in &registry {
        let label = format!("{} {}", t.name(), t.variant());
        let (built, code) = cases
            .iter()
            .find(|(b, _)| b.name() == t.name() && b.variant() == t.variant())
            .unwrap_or_else(|| panic!("no expression here builds {label}"));
        assert_eq!(strip(&t.call()), strip(code), "{label}");
        assert_eq!(built.call(), t.call(), "{label}");
    }
    // Every expression here names a configuration the registry holds.
    for (b, code) in &cases {
        assert!(
            registry
                .iter()
                .any(|t| t.name() == b.name() && t.variant() == b.variant()),
            "{code} is not in the registry"
        );
    }
}
