//! Properties from the paper: the probabilistic combination's bounds (section 3.3) and the box
//! filters of section 3.2 against brute-force box sums.

mod gpu;
mod halo;

use soft_shadow_core::CpuContext;
use soft_shadow_core::pool::Pool;
use std::sync::Arc;

/// A pool for one test's maps (nothing kept between calls).
fn pool() -> Arc<Pool> {
    Arc::new(Pool::new(0))
}

use crate::combine::{Accumulator, CHAIN_EPSILON, combine};
use crate::filters::mipmap::mip_size;
use crate::filters::{Mipmap, NBuffer, Sat, unorm8};
use crate::{Combination, OcclusionSlices, Prefilter};
use glam::Vec2;
use proptest::prelude::*;
use soft_shadow_core::{Light, SceneGeometry, ShadowError, ShadowTechnique};

fn occlusions() -> impl Strategy<Value = Vec<f32>> {
    prop::collection::vec(prop_oneof![Just(0.0f32), Just(1.0f32), 0.0f32..=1.0], 0..20)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// `max I_k <= 1 - prod(1 - I_k) <= min(1, sum I_k)`, and the result is in [0, 1].
    #[test]
    fn product_lies_between_max_and_sum(i in occlusions()) {
        let occluded = 1.0 - combine(Combination::Product, &i);
        let max = i.iter().cloned().fold(0.0f32, f32::max);
        let sum: f32 = i.iter().sum();
        // One f32 rounding per factor of the product.
        let eps = 1e-6 * (i.len() as f32 + 1.0);
        prop_assert!(max <= occluded + eps, "max {max} > {occluded}");
        prop_assert!(occluded <= sum.min(1.0) + eps, "{occluded} > min(1, {sum})");
        for how in Combination::ALL {
            let v = combine(how, &i);
            prop_assert!((0.0..=1.0).contains(&v));
        }
        prop_assert_eq!(combine(Combination::Max, &i), 1.0 - max);
        prop_assert_eq!(combine(Combination::Sum, &i), 1.0 - sum.min(1.0));
    }

    /// Order does not matter (up to rounding), `I_k = 0` changes nothing, any `I_k = 1`
    /// occludes the light entirely.
    #[test]
    fn product_ignores_order_and_zeros_and_saturates_on_one(
        i in occlusions(),
        seed in any::<u64>(),
        at in any::<prop::sample::Index>(),
    ) {
        let v = combine(Combination::Product, &i);
        let mut shuffled = i.clone();
        let mut s = seed;
        for k in (1..shuffled.len()).rev() {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            shuffled.swap(k, (s >> 33) as usize % (k + 1));
        }
        let eps = 1e-6 * (i.len() as f32 + 1.0);
        prop_assert!((combine(Combination::Product, &shuffled) - v).abs() <= eps);
        let mut with_zero = i.clone();
        with_zero.insert(at.index(i.len() + 1), 0.0);
        prop_assert_eq!(combine(Combination::Product, &with_zero), v);
        let mut with_one = i.clone();
        with_one.insert(at.index(i.len() + 1), 1.0);
        prop_assert_eq!(combine(Combination::Product, &with_one), 0.0);
    }

    /// Section 3.3's model holds for the product: slices are independent random occluders.
    #[test]
    fn product_treats_slices_as_independent_occluders(
        a in occlusions(),
        b in occlusions(),
        x in 0.01f32..0.99,
        y in 0.01f32..0.99,
    ) {
        prop_assert_eq!(independent(Combination::Product, &a, &b, x, y), Ok(()));
    }

    /// Over one kernel the chain is exact for two neighbouring slices however their occluders
    /// overlap: with `a`, `b` and `u` the shares of the kernel that slice `k - 1`, slice `k`
    /// and their union hide, the first slice's factor times the chain's leaves `1 - u` of the
    /// light (to rounding where `1 - a` is at least [`CHAIN_EPSILON`], within it below); the
    /// product assumes independence and leaves `(1 - a)(1 - b)`.
    #[test]
    fn chain_is_exact_for_two_neighbouring_slices(
        cells in prop::collection::vec((any::<bool>(), any::<bool>()), 1..300),
    ) {
        let n = cells.len() as f32;
        let a = cells.iter().filter(|c| c.0).count() as f32 / n;
        let b = cells.iter().filter(|c| c.1).count() as f32 / n;
        let u = cells.iter().filter(|c| c.0 || c.1).count() as f32 / n;
        let mut chain = Accumulator::new(Combination::Chain);
        chain.add(a);
        chain.add_given(u, a, 1.0, 0.0);
        let exact = 1.0 - u;
        let tolerance = if 1.0 - a >= CHAIN_EPSILON { 1e-6 } else { CHAIN_EPSILON };
        prop_assert!(
            (chain.visibility() - exact).abs() <= tolerance,
            "a {a} b {b} u {u}: chain {} against {exact}", chain.visibility()
        );
    }

    /// The summed-area table's box sums equal brute force exactly for random binary masks and
    /// random integer rectangles, including rectangles clipped by the border.
    #[test]
    fn sat_box_counts_equal_brute_force(
        resolution in 1u32..48,
        density in 0.0f64..=1.0,
        seed in any::<u64>(),
        rects in prop::collection::vec((-10i64..60, -10i64..60, -10i64..60, -10i64..60), 1..20),
    ) {
        let mask = random_mask(resolution, density, seed);
        let sat = Sat::new(&pool(), resolution, &mask);
        for (a, b, c, d) in rects {
            let (x0, x1) = (a.min(c), a.max(c));
            let (y0, y1) = (b.min(d), b.max(d));
            prop_assert_eq!(sat.count(x0, y0, x1, y1) as i64, brute(&mask, resolution, x0, y0, x1, y1));
        }
    }

    /// Every mipmap level holds each block's exact count rounded to 8 bits (the pyramid of 2x2
    /// sums equals counting each block, clipped to the slice, in the summed-area table), and a
    /// slice packed as bit `k` of the slicing masks builds the same table and pyramid as the
    /// slice alone, whether built on its own or together with its neighbouring slices.
    #[test]
    fn mipmap_levels_are_rounded_block_counts(
        resolution in 1u32..70,
        density in 0.0f64..=1.0,
        seed in any::<u64>(),
        k in 0u32..16,
    ) {
        let mask = random_mask(resolution, density, seed);
        let sat = Sat::new(&pool(), resolution, &mask);
        let mm = Mipmap::new(&pool(), resolution, &mask);
        for (l, level) in mm.levels.iter().enumerate() {
            let (s, n) = (1i64 << l, mip_size(resolution, l as u32) as i64);
            prop_assert_eq!(level.len() as i64, n * n);
            for y in 0..n {
                for x in 0..n {
                    let c = sat.count(x * s, y * s, x * s + s, y * s + s) as u32;
                    prop_assert_eq!(level[(y * n + x) as usize], unorm8(c, (s * s) as u64));
                }
            }
        }
        // Another slice's bit set wherever this one is empty.
        let other = (k + 1) % 16;
        let masks: Vec<u32> = mask.iter().map(|&b| ((b as u32) << k) | ((!b as u32) << other)).collect();
        prop_assert!(Sat::from_masks(&pool(), resolution, &masks, k) == sat);
        prop_assert!(Mipmap::from_masks(&pool(), resolution, &masks, k) == mm);
        let (lo, hi) = (k.min(other), k.max(other));
        let together = Mipmap::from_masks_together(&pool(), resolution, &masks, lo..hi + 1);
        prop_assert!(together[(k - lo) as usize] == mm);
        prop_assert!(together[(other - lo) as usize] == Mipmap::from_masks(&pool(), resolution, &masks, other));
    }

    /// Every N-Buffer level holds, at every texel, the exact count of the `2^l` box whose
    /// top-left texel it is (clipped to the slice) over the box's area, rounded to 8 bits, at
    /// every size, powers of two or not (before the boxes wider than the slice read no columns,
    /// every size that is no power of two panicked).
    #[test]
    fn nbuffer_levels_are_rounded_box_counts(
        resolution in 1u32..70,
        density in 0.0f64..=1.0,
        seed in any::<u64>(),
    ) {
        let mask = random_mask(resolution, density, seed);
        let sat = Sat::new(&pool(), resolution, &mask);
        let nb = NBuffer::new(&pool(), &sat);
        prop_assert_eq!(nb.levels.len() as u32, crate::filters::level_count(resolution));
        let n = resolution as i64;
        for (l, level) in nb.levels.iter().enumerate() {
            let s = 1i64 << l;
            prop_assert_eq!(level.len() as i64, n * n);
            for y in 0..n {
                for x in 0..n {
                    let c = sat.count(x, y, x + s, y + s) as u32;
                    prop_assert_eq!(level[(y * n + x) as usize], unorm8(c, (s * s) as u64));
                }
            }
        }
    }

    /// With fractional corners the SAT mean is the exact integral of the piecewise-constant
    /// slice over the box (brute force in f64) to f32 rounding (1e-4: the SAT sums up to 2,500
    /// texel weights in f32; 2e-5 failed once at 2.05e-5); a box under a texel wide is read as
    /// one texel wide.
    #[test]
    fn sat_mean_is_the_exact_box_integral(
        resolution in 1u32..40,
        density in 0.0f64..=1.0,
        seed in any::<u64>(),
        boxes in prop::collection::vec((-5.0f32..45.0, -5.0f32..45.0, 0.01f32..50.0), 1..20),
    ) {
        let mask = random_mask(resolution, density, seed);
        let sat = Sat::new(&pool(), resolution, &mask);
        for (cx, cy, size) in boxes {
            let exact = integral(&mask, resolution, cx, cy, size.max(1.0));
            let got = sat.mean(Vec2::new(cx, cy), size) as f64;
            prop_assert!((got - exact).abs() < 1e-4, "{got} vs {exact}");
        }
    }
}

/// Section 3.3's independence, which only the product has: the light two groups of slices let
/// through is the product of what each lets through (`V(a ++ b) = V(a) V(b)`), and two partial
/// occluders `x`, `y` in (0, 1) block strictly more than the stronger and strictly less than
/// their sum (`max < 1 - (1 - x)(1 - y) < x + y`). `Err` says which part fails.
fn independent(how: Combination, a: &[f32], b: &[f32], x: f32, y: f32) -> Result<(), String> {
    let joined: Vec<f32> = a.iter().chain(b).copied().collect();
    let (va, vb, vab) = (combine(how, a), combine(how, b), combine(how, &joined));
    // One f32 rounding per factor.
    let eps = 1e-6 * (joined.len() as f32 + 1.0);
    if (vab - va * vb).abs() > eps {
        return Err(format!("V(a ++ b) {vab} != V(a) V(b) {}", va * vb));
    }
    let occluded = 1.0 - combine(how, &[x, y]);
    // The margins are min(x, y) (1 - max(x, y)) and x y, at least 1e-4 here.
    if occluded <= x.max(y) + 1e-5 {
        return Err(format!(
            "{x} and {y} block {occluded}, no more than the stronger"
        ));
    }
    if occluded >= x + y - 1e-5 {
        return Err(format!("{x} and {y} block {occluded}, their sum"));
    }
    Ok(())
}

/// Where the product fails and the chain does not: complementary halves (a body that crosses a
/// slice plane, seen from under it) leave the product a quarter of the light, the chain none;
/// the same half hidden twice (a shell's two faces) leaves the product a quarter, the chain
/// half.
#[test]
fn the_chain_counts_complementary_and_repeated_neighbours_once() {
    let two = |how, a: f32, u: f32| {
        let mut acc = Accumulator::new(how);
        acc.add(a);
        if how == Combination::Chain {
            acc.add_given(u, a, 1.0, 0.0);
        } else {
            acc.add(a);
        }
        acc.visibility()
    };
    // Complementary: each hides half, together all of it.
    assert_eq!(two(Combination::Product, 0.5, 1.0), 0.25);
    assert_eq!(two(Combination::Chain, 0.5, 1.0), 0.0);
    // Repeated: each hides the same half.
    assert_eq!(two(Combination::Product, 0.5, 0.5), 0.25);
    assert!((two(Combination::Chain, 0.5, 0.5) - 0.5).abs() <= 1e-6);
    // A neighbour that hides the whole kernel leaves the chain's factor at 1.
    assert_eq!(crate::combine::given(1.0, 1.0), 1.0);
}

/// The independence property can fail: the strongest slice alone and the clamped sum break it
/// on two half-covered slices (Max lets half the light through where the product lets a
/// quarter, Sum none).
#[test]
fn max_and_sum_are_not_independent_occluders() {
    for how in [Combination::Max, Combination::Sum] {
        assert!(
            independent(how, &[0.5], &[0.5], 0.5, 0.5).is_err(),
            "{how:?} passes the product's property"
        );
    }
    assert_eq!(
        independent(Combination::Product, &[0.5], &[0.5], 0.5, 0.5),
        Ok(())
    );
}

fn random_mask(resolution: u32, density: f64, seed: u64) -> Vec<bool> {
    let mut rng = soft_shadow_core::rng::SplitMix(seed);
    (0..resolution * resolution)
        .map(|_| rng.next_f64() < density)
        .collect()
}

fn brute(mask: &[bool], resolution: u32, x0: i64, y0: i64, x1: i64, y1: i64) -> i64 {
    let r = resolution as i64;
    let mut n = 0;
    for y in y0.max(0)..y1.min(r) {
        for x in x0.max(0)..x1.min(r) {
            n += mask[(y * r + x) as usize] as i64;
        }
    }
    n
}

/// Exact mean over the square of side `size` at `(cx, cy)`, in f64 (outside empty).
fn integral(mask: &[bool], resolution: u32, cx: f32, cy: f32, size: f32) -> f64 {
    let h = 0.5 * size as f64;
    let (lx, hx) = (cx as f64 - h, cx as f64 + h);
    let (ly, hy) = (cy as f64 - h, cy as f64 + h);
    let r = resolution as i64;
    let mut sum = 0.0;
    for y in 0..r {
        let oy = (hy.min((y + 1) as f64) - ly.max(y as f64)).max(0.0);
        if oy == 0.0 {
            continue;
        }
        for x in 0..r {
            if mask[(y * r + x) as usize] {
                sum += oy * (hx.min((x + 1) as f64) - lx.max(x as f64)).max(0.0);
            }
        }
    }
    sum / ((hx - lx) * (hy - ly))
}

/// N-Buffers and mipmaps against the exact box filter on random masks and kernels: their mean
/// absolute error is bounded (and printed, for the closing note), N-Buffers beat mipmaps, and at
/// power-of-two kernels whose box starts on a texel corner the N-Buffer is exact to its 8-bit
/// rounding.
#[test]
fn nbuffer_and_mipmap_errors_against_brute_force() {
    let resolution = 64;
    let (mut err_n, mut err_m, mut count) = (0.0f64, 0.0f64, 0);
    let (mut max_n, mut max_m) = (0.0f64, 0.0f64);
    for seed in 1..=20u64 {
        let mask = random_mask(resolution, 0.05 * seed as f64, seed);
        let sat = Sat::new(&pool(), resolution, &mask);
        let (nb, mm) = (
            NBuffer::new(&pool(), &sat),
            Mipmap::new(&pool(), resolution, &mask),
        );
        let mut s = seed;
        for _ in 0..200 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = |shift: u32| ((s >> shift) & 0xffff) as f32 / 65535.0;
            let c = Vec2::new(8.0 + 48.0 * u(0), 8.0 + 48.0 * u(16));
            let size = 1.0 + 15.0 * u(32);
            let exact = integral(&mask, resolution, c.x, c.y, size);
            let (n, m) = (nb.mean(c, size) as f64, mm.mean(c, size) as f64);
            err_n += (n - exact).abs();
            err_m += (m - exact).abs();
            max_n = max_n.max((n - exact).abs());
            max_m = max_m.max((m - exact).abs());
            count += 1;
        }
        for l in 0..5u32 {
            let side = (1u32 << l) as f32;
            for (x, y) in [(3, 5), (20, 11), (40, 40)] {
                let c = Vec2::new(x as f32 + 0.5 * side, y as f32 + 0.5 * side);
                let exact = integral(&mask, resolution, c.x, c.y, side);
                let n = nb.mean(c, side) as f64;
                assert!(
                    (n - exact).abs() <= 0.5 / 255.0 + 1e-6,
                    "level {l}: {n} vs {exact}"
                );
            }
        }
    }
    let (mean_n, mean_m) = (err_n / count as f64, err_m / count as f64);
    println!(
        "box filter error vs brute force over {count} kernels of 1..16 texels: \
         N-Buffer mean {mean_n:.4} max {max_n:.4}; mipmap mean {mean_m:.4} max {max_m:.4}"
    );
    assert!(mean_n < 0.03, "N-Buffer mean error {mean_n}");
    assert!(mean_m < 0.08, "mipmap mean error {mean_m}");
    assert!(
        mean_n < mean_m,
        "N-Buffers {mean_n} should beat mipmaps {mean_m}"
    );
}

/// Bad parameters and lights get typed errors that name the problem.
#[test]
fn bad_input_gets_typed_errors() {
    let geometry = SceneGeometry::default();
    let rect = Light::Rect {
        center: glam::Vec3::Y,
        u_half: glam::Vec3::X,
        v_half: glam::Vec3::Z,
    };
    for slices in [0, 3, 17] {
        let t = OcclusionSlices::new(slices, Prefilter::Sat);
        match t.generate_cpu(&CpuContext::new(), &geometry, &rect, 64) {
            Err(ShadowError::InvalidParameter(m)) => assert!(m.contains("slices")),
            other => panic!("slices {slices}: {:?}", other.map(|_| ())),
        }
    }
    let mut t = OcclusionSlices::new(8, Prefilter::Sat);
    t.normal_offset = f32::NAN;
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &geometry, &rect, 64),
        Err(ShadowError::InvalidParameter(_))
    ));
    for fade in [f32::NAN, -1.0, f32::INFINITY] {
        let mut t = OcclusionSlices::new(8, Prefilter::Sat);
        t.fade_texels = fade;
        match t.generate_cpu(&CpuContext::new(), &geometry, &rect, 64) {
            Err(ShadowError::InvalidParameter(m)) => assert!(m.contains("fade_texels"), "{m}"),
            other => panic!("fade_texels {fade}: {:?}", other.map(|_| ())),
        }
    }
    let t = OcclusionSlices::new(8, Prefilter::Sat);
    let segment = Light::Linear {
        a: glam::Vec3::ZERO,
        b: glam::Vec3::X,
    };
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &geometry, &segment, 64),
        Err(ShadowError::UnsupportedLight { .. })
    ));
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &geometry, &rect, 0),
        Err(ShadowError::InvalidResolution { .. })
    ));
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &geometry, &rect, 8192),
        Err(ShadowError::InvalidResolution { .. })
    ));
}

/// A 1 mm square light 93 m above the ground and a 4 m triangle 30 m up and 30 m to the side:
/// the frustum must reach the triangle (its apex 2 mm behind the light), so the ground in its
/// shadow reads dark and the ground opposite lit. With the apex held at least 1e-4 of the
/// casters' depth behind the light (9 mm), the frustum was 4.6 m wide at the triangle and the
/// ground read lit everywhere (found by the seeded random scenes).
#[test]
fn a_tiny_light_far_above_keeps_casters_to_the_side() {
    use glam::Vec3;
    let light = Light::Rect {
        center: Vec3::new(0.0, 93.0, 0.0),
        u_half: Vec3::X * 5e-4,
        v_half: Vec3::Z * 5e-4,
    };
    let c = Vec3::new(30.0, 30.0, 0.0);
    let triangle = [
        c + Vec3::new(-2.0, 0.0, -2.0),
        c + Vec3::new(2.0, 0.0, -2.0),
        c + Vec3::new(0.0, 0.0, 2.0),
    ];
    let g = 100.0;
    let ground = [
        [
            Vec3::new(-g, 0.0, -g),
            Vec3::new(g, 0.0, g),
            Vec3::new(g, 0.0, -g),
        ],
        [
            Vec3::new(-g, 0.0, -g),
            Vec3::new(-g, 0.0, g),
            Vec3::new(g, 0.0, g),
        ],
    ];
    let mut all = ground.to_vec();
    all.push(triangle);
    let geometry = SceneGeometry {
        receivers: all.clone(),
        casters: vec![triangle],
        bounds: soft_shadow_core::Aabb::of_triangles(&all),
    };
    // The triangle's centre seen from the light, on the ground; and its mirror image.
    let shadow = Vec3::new(30.0 * 93.0 / 63.0, 0.0, 0.0);
    let positions = [shadow, -shadow];
    let normals = [Vec3::Y; 2];
    let receivers = soft_shadow_core::Receivers::new(&positions, &normals);
    let runs = every_prefilter(
        "a_tiny_light_far_above_keeps_casters_to_the_side",
        &geometry,
        &light,
        &receivers,
        256,
    );
    for (what, v) in runs {
        assert!(v[0] < 0.1, "{what}: V {} in the triangle's shadow", v[0]);
        assert!(v[1] > 0.99, "{what}: V {} opposite it", v[1]);
    }
}

/// `V` of `receivers` with 8 slices and each prefilter at map side `resolution`, on the CPU and (where
/// test `name` gets an adapter) the GPU, each labelled `variant backend`.
fn every_prefilter(
    name: &str,
    geometry: &SceneGeometry,
    light: &Light,
    receivers: &soft_shadow_core::Receivers,
    resolution: u32,
) -> Vec<(String, Vec<f32>)> {
    let cpu = CpuContext::new();
    let gpu = harness::testing::gpu_for_test(name);
    let mut runs = Vec::new();
    for prefilter in Prefilter::ALL {
        let t = OcclusionSlices::new(8, prefilter);
        let maps = t.generate_cpu(&cpu, geometry, light, resolution).unwrap();
        let v = t.evaluate_cpu(&maps, receivers).unwrap();
        runs.push((format!("{} cpu", t.label()), v));
        if let Some(ctx) = &gpu {
            let maps = t.generate_gpu(ctx, geometry, light, resolution).unwrap();
            let v = t.evaluate_gpu(ctx, &maps, receivers).unwrap();
            runs.push((format!("{} gpu", t.label()), v));
        }
    }
    runs
}

/// `V` has no step where a slice's fade ends (section 3.4's fade exists so that a surface that
/// crosses a plane has none): two neighbouring slices that hide the same half of the light,
/// a receiver moved down through the end of the second one's fade in steps of 1e-5, `V` never
/// jumps by more than 1e-3, for every combination. (The chain read the fading slice as the
/// product does before it was chained too: a jump from 0.5 to 1 there.)
#[test]
fn v_is_continuous_where_a_slice_fade_ends() {
    use crate::eval::visibility;
    use crate::frame::Frame;
    use bytemuck::Zeroable;
    use glam::Vec3;
    let frame = Frame {
        center: [0.0; 4],
        axis_x: [1.0, 0.0, 0.0, 0.0],
        axis_y: [0.0, 1.0, 0.0, 0.0],
        normal: [0.0, 0.0, 1.0, 0.0],
        d: 1.5,
        near: 0.4,
        spacing: 0.125,
        slices: 8,
        half_x: 0.5,
        half_y: 0.5,
        resolution: 512,
        occupied: 1,
        fade_texels: crate::DEFAULT_FADE_TEXELS,
        ..Frame::zeroed()
    };
    // Slices 2 and 3 hide the same half; each union with its neighbour nearer the light too.
    let half = |k: usize| if k == 2 || k == 3 { 0.5 } else { 0.0 };
    let union = |k: usize| if (2..=4).contains(&k) { 0.5 } else { 0.0 };
    let end = frame.plane(3) + frame.fade_length(frame.plane(3));
    for how in Combination::ALL {
        let t = OcclusionSlices::new(8, Prefilter::Sat).with_combination(how);
        let v = |h: f32| {
            visibility(
                &t,
                &frame,
                Vec3::new(0.0, 0.0, h),
                Vec3::NEG_Z,
                |k, _, _| half(k),
                |k, _, _| union(k),
                |_, _, _| 0,
            )
        };
        let (mut worst, mut at) = (0.0f32, 0.0f32);
        for i in 0..2000 {
            let h = end - 0.01 + i as f32 * 1e-5;
            let jump = (v(h + 1e-5) - v(h)).abs();
            if jump > worst {
                (worst, at) = (jump, h);
            }
        }
        assert!(
            worst <= 1e-3,
            "{how:?}: V jumps by {worst} at depth {at} (the fade ends at {end})"
        );
    }
}
