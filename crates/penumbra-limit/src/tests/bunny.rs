//! The bunny's shadow on the ground under a tilted disk light (the viewer's default frame),
//! against the ray-traced reference: no false umbra where the reference is lit.

use crate::{Generator, PenumbraLimit};
use harness::testing::ViewerBunnyGround;
use soft_shadow_core::{CpuContext, Receivers, ShadowTechnique};

/// Ground receivers (a grid of `n` x `n` points around the bunny's shadow, facing up) that the
/// reference sees lit (`V_ref > 0.9`) and `t` puts in umbra (`V < 0.25`), at map side `res`;
/// how many the reference sees lit; and how many of any reference value `t` reads darker by
/// more than 1/2.
fn false_umbra(t: &PenumbraLimit, res: u32, n: u32) -> (usize, usize, usize) {
    let f = ViewerBunnyGround::new(n);
    let (geometry, light, ps, ns, refs) = (
        &f.geometry,
        &f.light,
        &f.positions,
        &f.normals,
        &f.references,
    );
    let cpu = CpuContext::new();
    let maps = t.generate_cpu(&cpu, geometry, light, res).unwrap();
    let v = t.evaluate_cpu(&maps, &Receivers::new(ps, ns)).unwrap();
    let lit: Vec<usize> = (0..ps.len())
        .filter(|&i| refs[i].is_some_and(|r| r > 0.9))
        .collect();
    let umbra = lit.iter().filter(|&&i| v[i] < 0.25).count();
    // Receivers of every reference value read darker than it by more than 1/2.
    let darker = (0..ps.len())
        .filter(|&i| refs[i].is_some_and(|r| v[i] < r - 0.5))
        .count();
    (umbra, lit.len(), darker)
}

/// Occluder transitions (Figure 7 C) clamp the soft shadow to the hard shadow of the geometry
/// there. A texel outside every caster (no geometry, only a ribbon's outer strip) has no hard
/// shadow to clamp to: clamping it at its raised outer limit `c + p_i` turned every receiver
/// below that limit into umbra, radial streaks of false umbra outside the bunny's shadow where
/// ribbons of neighbouring edges at slightly different depths meet (1094 false-umbra pixels in
/// the viewer's 1000x720 frame, now 664: the rest is the thin ears' lower limit). Below the
/// ears' lower limit the paper's step to 0 read the ground as umbra where the reference reads
/// 0.64-0.68; the lower layer's own inner penumbra does not (ground receivers darker than the
/// reference by more than 1/2: 527 and 115 with the step, 100 and 15 without).
#[test]
fn the_bunnys_shadow_has_no_false_umbra_streaks() {
    for generator in Generator::ALL {
        let t = PenumbraLimit::new(generator);
        let (bad, lit, darker) = false_umbra(&t, 1024, 250);
        println!(
            "{}: {bad} of {lit} lit ground receivers in umbra, {darker} darker by 1/2",
            generator.name()
        );
        assert!(lit > 40_000, "{lit}");
        assert!(
            darker <= 200,
            "{}: {darker} receivers darker than the reference by 1/2",
            generator.name()
        );
        assert!(
            bad <= 20,
            "{}: {bad} of {lit} lit receivers in umbra",
            generator.name()
        );
    }
}
