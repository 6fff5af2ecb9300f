//! The techniques the viewer offers: every technique crate's standard variants, each technique's
//! default first, behind [`FrameTechnique`].

use crate::renderer::FrameTechnique;
use linear_light::LinearLight;
use occlusion_slices::{OcclusionSlices, Prefilter};
use penumbra_limit::{Generator, PenumbraLimit};
use shadow_maps::{Filter, SamplePattern, ShadowMapBaseline};
use shadow_width::{ShadowWidth, WidthMethod};
use soft_shadow_core::{LightKind, Result, ShadowError};
use std::sync::Arc;

/// A technique and its variants, the default first.
#[derive(Clone)]
pub struct TechniqueEntry {
    /// Technique name (`"pcss"`, `"occlusion-slices"`, ...).
    pub name: &'static str,
    /// Its variants, the default first.
    pub variants: Vec<Arc<dyn FrameTechnique>>,
}

impl TechniqueEntry {
    /// The default variant.
    pub fn default_variant(&self) -> &Arc<dyn FrameTechnique> {
        &self.variants[0]
    }

    /// The variant labelled `label` ([`soft_shadow_core::TechniqueInfo::variant`]).
    pub fn variant(&self, label: &str) -> Option<&Arc<dyn FrameTechnique>> {
        self.variants.iter().find(|v| v.variant() == label)
    }

    /// Whether it models lights of `kind`, and if not, why (the kinds it models).
    pub fn availability(&self, kind: LightKind) -> std::result::Result<(), String> {
        let t = self.default_variant();
        if t.models(kind) {
            return Ok(());
        }
        let kinds: Vec<&str> = LightKind::ALL
            .iter()
            .filter(|k| t.models(**k))
            .map(|k| k.name())
            .collect();
        Err(format!(
            "{} models {} lights, not {}",
            self.name,
            kinds.join(", "),
            kind.name()
        ))
    }
}

fn entry<T: FrameTechnique + 'static>(default: T, rest: Vec<T>) -> TechniqueEntry {
    let name = default.name();
    let mut variants: Vec<Arc<dyn FrameTechnique>> = vec![Arc::new(default)];
    for t in rest {
        if variants.iter().all(|v| v.variant() != t.variant()) {
            variants.push(Arc::new(t));
        }
    }
    TechniqueEntry { name, variants }
}

/// Every technique, in the order the panel lists them: the four baselines, then the four
/// papers' techniques.
pub fn registry() -> Vec<TechniqueEntry> {
    let baseline = |f| ShadowMapBaseline::new(f);
    vec![
        entry(baseline(Filter::Hard), vec![]),
        entry(
            baseline(Filter::Pcf { radius: 2 }),
            [1, 3, 4]
                .map(|radius| baseline(Filter::Pcf { radius }))
                .to_vec(),
        ),
        entry(baseline(Filter::Pcss), vec![]),
        entry(
            baseline(Filter::Accumulate { samples: 16 }),
            [4, 64, 256]
                .map(|samples| baseline(Filter::Accumulate { samples }))
                .into_iter()
                .chain([4, 16, 64].map(|samples| {
                    baseline(Filter::Accumulate { samples }).with_pattern(SamplePattern::Rotated)
                }))
                .collect(),
        ),
        entry(
            PenumbraLimit::new(Generator::Silhouette),
            PenumbraLimit::standard_set(),
        ),
        entry(
            OcclusionSlices::new(8, Prefilter::NBuffer),
            OcclusionSlices::standard_set(),
        ),
        entry(LinearLight::new(3), LinearLight::standard_set()),
        entry(
            ShadowWidth::new(WidthMethod::Exact),
            ShadowWidth::standard_set(),
        ),
    ]
}

/// The entry named `name` in `registry` (`"hard"` for `"hard-shadow-map"`; an unknown name is [`ShadowError::InvalidParameter`]
/// listing the names).
pub fn find<'a>(registry: &'a [TechniqueEntry], name: &str) -> Result<&'a TechniqueEntry> {
    let name = if name == "hard" {
        "hard-shadow-map"
    } else {
        name
    };
    registry.iter().find(|e| e.name == name).ok_or_else(|| {
        let names: Vec<&str> = registry.iter().map(|e| e.name).collect();
        ShadowError::InvalidParameter(format!(
            "unknown technique {name:?}; one of {}",
            names.join(", ")
        ))
    })
}
