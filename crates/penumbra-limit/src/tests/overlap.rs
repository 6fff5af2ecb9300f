//! `overlap`'s three stacked blockers: one edge per texel, and what lies under another caster.

use crate::{Generator, PenumbraLimit};
use harness::setup::PreparedScene;
use soft_shadow_core::{CpuContext, ShadowTechnique};
use soft_shadow_reference::ground_truth::GroundTruthSettings;
use soft_shadow_reference::scenes::catalogue::build;

/// Where one blocker's outer ribbon wins a texel over another blocker, the receivers under that
/// other blocker are in its shadow, not in the edge's outer penumbra. Counted: receivers of the
/// 128² G-buffer lighter than the reference by more than 0.4, silhouette generator. Before
/// outer texels over another caster clamped below it: 138 at 256² and 145 at 2048² (a lit
/// streak on the ground inside the top blocker's umbra, under the middle blocker's edge), and
/// before that the bottom blocker's top read at least half lit under the higher edges too. Now
/// 43 and 70 (with the lower casters' shadow soft and limiting inside the silhouette too,
/// `eval::lower_shadow`), the penumbrae's own edges.
#[test]
fn no_light_under_another_blocker() {
    let p = PreparedScene::new(
        build("overlap").unwrap(),
        128,
        GroundTruthSettings::default(),
    )
    .unwrap();
    let reference = p.reference_v();
    let t = PenumbraLimit::new(Generator::Silhouette);
    let cpu = CpuContext::new();
    for resolution in [256, 2048] {
        let maps = t
            .generate_cpu(&cpu, &p.geometry, &p.spec.light, resolution)
            .unwrap();
        let v = t.evaluate_cpu(&maps, &p.receivers()).unwrap();
        let lighter = v
            .iter()
            .zip(&reference)
            .filter(|(v, r)| **v > **r + 0.4)
            .count();
        println!("{resolution}²: {lighter} lighter by 0.4");
        assert!(
            lighter <= 90,
            "{resolution}²: {lighter} of {} receivers lighter than the reference by 0.4",
            v.len()
        );
    }
}
