//! One registry: families hold a technique's variants, the default first, each run in its tier
//! and wider; a registry finds a family by name (or the one name it begins), lists every
//! variant of a tier in order, and a family added again replaces the old one.

use soft_shadow_core::{
    Checked, CpuContext, Family, Generation, LightKind, NoGpuMaps, Receivers, Registry, Result,
    ShadowTechnique, TechniqueInfo, Tier,
};

/// Lit everywhere; `Lit(n)` is variant `n<n>` of the technique `name`.
#[derive(Clone)]
struct Lit(&'static str, u32);

impl TechniqueInfo for Lit {
    fn name(&self) -> &'static str {
        self.0
    }
    fn variant(&self) -> String {
        format!("n{}", self.1)
    }
    fn call(&self) -> String {
        format!("Lit({:?}, {})", self.0, self.1)
    }
    fn models(&self, kind: LightKind) -> bool {
        kind == LightKind::Rect
    }
}

impl ShadowTechnique for Lit {
    type CpuMaps = ();
    type GpuMaps = NoGpuMaps;
    fn cpu_maps(&self, _: &CpuContext, _: Checked<Generation<'_>>) {}
    fn cpu_visibility(&self, _: &(), r: Checked<Receivers<'_>>) -> Result<Vec<f32>> {
        Ok(vec![1.0; r.positions.len()])
    }
}

fn labels<'a>(ts: impl Iterator<Item = &'a soft_shadow_core::Technique>) -> Vec<String> {
    ts.map(|t| format!("{} {}", t.name(), t.variant()))
        .collect()
}

fn lit_family() -> Family {
    Family::new(Lit("lit-test", 16), Tier::Quick)
        .with_all([4, 64].map(|n| Lit("lit-test", n)), Tier::Report)
        .with(Lit("lit-test", 256), Tier::Offered)
        // Again, narrower: keeps its place and takes the narrower tier.
        .with(Lit("lit-test", 64), Tier::Quick)
}

#[test]
fn a_family_runs_each_variant_in_its_tier_and_wider_default_first() {
    let f = lit_family();
    assert_eq!(f.name(), "lit-test");
    assert_eq!(f.default_variant().variant(), "n16");
    assert_eq!(
        labels(f.variants_in(Tier::Quick)),
        ["lit-test n16", "lit-test n64"]
    );
    assert_eq!(
        labels(f.variants_in(Tier::Report)),
        ["lit-test n16", "lit-test n4", "lit-test n64"]
    );
    assert_eq!(
        labels(f.variants()),
        [
            "lit-test n16",
            "lit-test n4",
            "lit-test n64",
            "lit-test n256"
        ]
    );
    assert_eq!(f.variant("n256").unwrap().call(), "Lit(\"lit-test\", 256)");
    assert!(f.variant("n8").is_none());
    assert!(f.availability(LightKind::Rect).is_ok());
    let why = f.availability(LightKind::Sphere).unwrap_err();
    assert!(why.contains("models rect lights, not sphere"), "{why}");
}

#[test]
#[should_panic(expected = "added to the family lit-test")]
fn a_family_refuses_another_techniques_variant() {
    let _ = lit_family().with(Lit("other", 1), Tier::Quick);
}

#[test]
fn a_registry_lists_finds_and_replaces_families() {
    let other = Family::new(Lit("other-test", 1), Tier::Quick).zero_size_path();
    let r = Registry::new().with([lit_family()]).with([other]);
    assert_eq!(
        labels(r.techniques(Tier::Quick).iter()),
        ["lit-test n16", "lit-test n64", "other-test n1"]
    );
    assert_eq!(r.techniques(Tier::Offered).len(), 5);
    assert_eq!(r.family("lit-test").unwrap().name(), "lit-test");
    // The one family a name begins.
    assert_eq!(r.family("other").unwrap().name(), "other-test");
    let err = r.family("nothing").unwrap_err().to_string();
    assert!(err.contains("one of lit-test, other-test"), "{err}");
    assert_eq!(r.find("lit-test", "n4").unwrap().variant(), "n4");
    assert!(r.find("lit-test", "n5").is_none());
    assert_eq!(r.zero_size_path().unwrap().name(), "other-test");
    // A family added again replaces the old one in its place.
    let r = r.with([Family::new(Lit("lit-test", 2), Tier::Quick)]);
    assert_eq!(
        labels(r.techniques(Tier::Offered).iter()),
        ["lit-test n2", "other-test n1"]
    );
    // Two families begin with the name: neither is meant.
    let r = r.with([Family::new(Lit("other-more", 1), Tier::Quick)]);
    assert!(r.family("other").is_err());
}
