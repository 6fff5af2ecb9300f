//! One registry of techniques. Every technique type is held behind one erased handle,
//! [`Technique`] (any [`ShadowTechnique`] with its parameters), and grouped in a [`Family`]: a
//! technique's name and its variants, the default first, each with the widest use it is meant
//! for ([`Tier`]). A technique crate hands out its families (`families()`); a [`Registry`] lists
//! them; the frame pipeline, `Auto`, the report, the viewer and the benches all take their
//! techniques from one.

use crate::technique::{DynTechnique, ShadowTechnique};
use crate::{LightKind, Result, ShadowError};
use std::sync::Arc;

/// A technique of any type with its parameters, erased: what a registry holds and every user
/// passes around ([`DynTechnique`] generates and evaluates on either backend).
pub type Technique = Arc<dyn DynTechnique>;

/// How widely a variant is run, narrowest first: each tier takes the variants of those before
/// it too.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum Tier {
    /// The quick report (`harness report --quick`).
    Quick,
    /// The full report, the benches, and what the frame pipeline's `Auto` picks from (among
    /// the configurations its profile holds).
    Report,
    /// Offered to pick by hand (the viewer's variant list, an explicit choice).
    Offered,
}

/// One technique's name and its variants, the default first.
#[derive(Clone)]
pub struct Family {
    name: &'static str,
    variants: Vec<(Technique, Tier)>,
    zero_size_path: bool,
}

impl std::fmt::Debug for Family {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let variants: Vec<String> = self
            .variants
            .iter()
            .map(|(t, tier)| format!("{} ({tier:?})", t.variant()))
            .collect();
        f.debug_struct("Family")
            .field("name", &self.name)
            .field("variants", &variants)
            .finish()
    }
}

impl Family {
    /// The family of `default`'s technique, with `default` as its default variant, run in
    /// `tier` and wider.
    pub fn new<T: ShadowTechnique>(default: T, tier: Tier) -> Self {
        Self {
            name: default.name(),
            variants: vec![(Arc::new(default), tier)],
            zero_size_path: false,
        }
    }

    /// `self` with variant `t`, run in `tier` and wider. A variant whose label the family holds
    /// already keeps its place and takes the narrower of the two tiers.
    ///
    /// # Panics
    ///
    /// Where `t` is another technique than the family's (its [`name`](crate::TechniqueInfo::name)
    /// differs): a registry is built by code, and that code is wrong.
    pub fn with<T: ShadowTechnique>(mut self, t: T, tier: Tier) -> Self {
        assert_eq!(
            t.name(),
            self.name,
            "variant {} of {} added to the family {}",
            t.variant(),
            t.name(),
            self.name
        );
        let label = t.variant();
        match self.variants.iter_mut().find(|(v, _)| v.variant() == label) {
            Some((_, old)) => *old = (*old).min(tier),
            None => self.variants.push((Arc::new(t), tier)),
        }
        self
    }

    /// `self` with every variant of `ts` ([`Family::with`]), in order.
    pub fn with_all<T: ShadowTechnique>(self, ts: impl IntoIterator<Item = T>, tier: Tier) -> Self {
        ts.into_iter().fold(self, |f, t| f.with(t, tier))
    }

    /// `self` marked as the technique a light of zero size takes in the frame pipeline (its
    /// default variant: the hard shadow map).
    pub fn zero_size_path(mut self) -> Self {
        self.zero_size_path = true;
        self
    }

    /// Whether the frame pipeline gives lights of zero size this family's default variant.
    pub fn is_zero_size_path(&self) -> bool {
        self.zero_size_path
    }

    /// The technique's name ([`crate::TechniqueInfo::name`]).
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// The default variant.
    pub fn default_variant(&self) -> &Technique {
        &self.variants[0].0
    }

    /// Every variant, the default first.
    pub fn variants(&self) -> impl Iterator<Item = &Technique> {
        self.variants.iter().map(|(t, _)| t)
    }

    /// The variants run in `tier` (those of `tier` and narrower tiers), the default first where
    /// it is one of them.
    pub fn variants_in(&self, tier: Tier) -> impl Iterator<Item = &Technique> {
        self.variants
            .iter()
            .filter(move |(_, t)| *t <= tier)
            .map(|(t, _)| t)
    }

    /// The variant labelled `label` ([`crate::TechniqueInfo::variant`]).
    pub fn variant(&self, label: &str) -> Option<&Technique> {
        self.variants().find(|v| v.variant() == label)
    }

    /// Whether the technique models lights of `kind`, and if not, why (the kinds it models).
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

/// Families of techniques, in the order users list them.
#[derive(Clone, Debug, Default)]
pub struct Registry {
    families: Vec<Family>,
}

impl Registry {
    /// No technique yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// `self` with `families` after those it holds (a technique crate's `families()`). A family
    /// named as one held already replaces it in its place.
    pub fn with(mut self, families: impl IntoIterator<Item = Family>) -> Self {
        for f in families {
            match self.families.iter_mut().find(|g| g.name == f.name) {
                Some(g) => *g = f,
                None => self.families.push(f),
            }
        }
        self
    }

    /// The families, in order.
    pub fn families(&self) -> &[Family] {
        &self.families
    }

    /// The family named `name`, or the one family whose name starts with `name` and a hyphen
    /// (`"hard"` for `"hard-shadow-map"`); anything else is [`ShadowError::InvalidParameter`]
    /// listing the names.
    pub fn family(&self, name: &str) -> Result<&Family> {
        if let Some(f) = self.families.iter().find(|f| f.name == name) {
            return Ok(f);
        }
        let prefix = format!("{name}-");
        let mut matching = self.families.iter().filter(|f| f.name.starts_with(&prefix));
        match (matching.next(), matching.next()) {
            (Some(f), None) => Ok(f),
            _ => {
                let names: Vec<&str> = self.families.iter().map(|f| f.name).collect();
                Err(ShadowError::InvalidParameter(format!(
                    "unknown technique {name:?}; one of {}",
                    names.join(", ")
                )))
            }
        }
    }

    /// Every variant run in `tier`, family by family, each family's default first.
    pub fn techniques(&self, tier: Tier) -> Vec<Technique> {
        self.families
            .iter()
            .flat_map(|f| f.variants_in(tier).cloned())
            .collect()
    }

    /// The variant `variant` of the technique named `name`, if registered.
    pub fn find(&self, name: &str, variant: &str) -> Option<&Technique> {
        self.families
            .iter()
            .filter(|f| f.name == name)
            .find_map(|f| f.variant(variant))
    }

    /// The default variant of the family marked [`Family::zero_size_path`], if any.
    pub fn zero_size_path(&self) -> Option<&Technique> {
        self.families
            .iter()
            .find(|f| f.zero_size_path)
            .map(Family::default_variant)
    }
}
