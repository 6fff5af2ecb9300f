//! The GPU's prefiltering against the CPU's.

use crate::filters::{NBuffer, Sat};
use crate::{OcclusionSlices, Prefilter};
use harness::testing::gpu_for_test;
use soft_shadow_core::ShadowTechnique;

/// The GPU's N-Buffer levels are the CPU's bit for bit (`filters::NBuffer` from the table of
/// the GPU's own slices: the slicing may differ by a fragment within rounding of a slice plane,
/// the prefiltering may not), every level of every slice, at a power-of-two and an odd size.
#[test]
fn gpu_nbuffer_levels_equal_the_cpu() {
    let Some(ctx) = gpu_for_test("gpu_nbuffer_levels_equal_the_cpu") else {
        return;
    };
    let spec = soft_shadow_reference::scenes::catalogue::build("overlap").unwrap();
    let geometry = spec.to_scene().unwrap().geometry();
    let t = OcclusionSlices::new(8, Prefilter::NBuffer);
    for resolution in [96, 256] {
        let gm = t
            .generate_gpu(&ctx, &geometry, &spec.light, resolution)
            .unwrap();
        let (slices, levels) = (
            gm.first().read_slices(&ctx).unwrap(),
            gm.first().read_nbuffer(&ctx).unwrap(),
        );
        assert_eq!(levels.len(), 8);
        let occupied = slices.iter().filter(|s| s.iter().any(|&o| o)).count();
        assert!(
            occupied >= 3,
            "overlap {resolution}: {occupied} slices hold a blocker"
        );
        for (k, (slice, gpu)) in slices.iter().zip(&levels).enumerate() {
            let pool = std::sync::Arc::new(soft_shadow_core::pool::Pool::new(0));
            let cpu = NBuffer::new(&pool, &Sat::new(&pool, resolution, slice));
            assert_eq!(
                gpu.len(),
                cpu.levels.len(),
                "{resolution}: slice {k}'s level count"
            );
            for (l, (g, c)) in gpu.iter().zip(&cpu.levels).enumerate() {
                let differ = g.iter().zip(c).filter(|(a, b)| a != b).count();
                assert_eq!(
                    differ, 0,
                    "{resolution}: slice {k} level {l}: {differ} texels differ"
                );
            }
        }
    }
}

/// The chain reads the unions of neighbouring slices: maps made for another combination are a
/// [`soft_shadow_core::ShadowError::MapsMismatch`] that names it, on both backends, and maps
/// made for the chain serve the product, which reads their slices alone, with the `V` of
/// its own maps, bit for bit.
#[test]
fn the_chain_reads_only_maps_made_for_it() {
    use crate::Combination;
    use soft_shadow_core::{CpuContext, Receivers, ShadowError};
    let spec = soft_shadow_reference::scenes::catalogue::build("overlap").unwrap();
    let geometry = spec.to_scene().unwrap().geometry();
    let product = OcclusionSlices::new(8, Prefilter::NBuffer);
    let chain = product.clone().with_combination(Combination::Chain);
    let points: Vec<glam::Vec3> = (0..64)
        .map(|i| glam::Vec3::new(-2.0 + i as f32 / 16.0, 0.0, 0.1))
        .collect();
    let receivers = Receivers::new(&points, &[glam::Vec3::Y; 64]);
    let cpu = CpuContext::new();
    let refused =
        |e: ShadowError| matches!(&e, ShadowError::MapsMismatch(m) if m.contains("chain"));
    let plain = product
        .generate_cpu(&cpu, &geometry, &spec.light, 128)
        .unwrap();
    let err = chain.evaluate_cpu(&plain, &receivers).unwrap_err();
    assert!(refused(err), "CPU");
    let unions = chain
        .generate_cpu(&cpu, &geometry, &spec.light, 128)
        .unwrap();
    assert_eq!(
        product.evaluate_cpu(&unions, &receivers).unwrap(),
        product.evaluate_cpu(&plain, &receivers).unwrap()
    );
    let Some(ctx) = gpu_for_test("the_chain_reads_only_maps_made_for_it") else {
        return;
    };
    let plain = product
        .generate_gpu(&ctx, &geometry, &spec.light, 128)
        .unwrap();
    let err = chain.evaluate_gpu(&ctx, &plain, &receivers).unwrap_err();
    assert!(refused(err), "GPU");
    let unions = chain
        .generate_gpu(&ctx, &geometry, &spec.light, 128)
        .unwrap();
    assert_eq!(
        product.evaluate_gpu(&ctx, &unions, &receivers).unwrap(),
        product.evaluate_gpu(&ctx, &plain, &receivers).unwrap()
    );
}

/// The chain on the GPU is the CPU's for every filter and for slice counts that leave channels
/// of the last RGBA layer empty (the unions' layers follow the slices'): on `overlap`'s ground at
/// 128², `V` within 1/255 rms and at most 1% of the receivers apart by more than 2/255 (a
/// fragment within rounding of a slice plane may fall in either slice).
#[test]
fn the_chain_agrees_between_cpu_and_gpu_for_every_filter() {
    use crate::Combination;
    use soft_shadow_core::{CpuContext, Receivers};
    let Some(ctx) = gpu_for_test("the_chain_agrees_between_cpu_and_gpu_for_every_filter") else {
        return;
    };
    let spec = soft_shadow_reference::scenes::catalogue::build("overlap").unwrap();
    let geometry = spec.to_scene().unwrap().geometry();
    let points: Vec<glam::Vec3> = (0..64 * 64)
        .map(|i| {
            glam::Vec3::new(
                -2.0 + (i % 64) as f32 / 16.0,
                0.0,
                -2.0 + (i / 64) as f32 / 16.0,
            )
        })
        .collect();
    let normals = vec![glam::Vec3::Y; points.len()];
    let receivers = Receivers::new(&points, &normals);
    let cpu = CpuContext::new();
    for (slices, filter) in [
        (5, Prefilter::Sat),
        (6, Prefilter::Mipmap),
        (7, Prefilter::NBuffer),
    ] {
        let t = OcclusionSlices::new(slices, filter).with_combination(Combination::Chain);
        let c = t.generate_cpu(&cpu, &geometry, &spec.light, 128).unwrap();
        let c = t.evaluate_cpu(&c, &receivers).unwrap();
        let g = t.generate_gpu(&ctx, &geometry, &spec.light, 128).unwrap();
        let g = t.evaluate_gpu(&ctx, &g, &receivers).unwrap();
        let shadowed = c.iter().filter(|&&v| v < 0.99).count();
        let rms = (c
            .iter()
            .zip(&g)
            .map(|(a, b)| ((a - b) * 255.0).powi(2))
            .sum::<f32>()
            / c.len() as f32)
            .sqrt();
        let apart = c
            .iter()
            .zip(&g)
            .filter(|(a, b)| (*a - *b).abs() > 2.0 / 255.0)
            .count();
        println!(
            "{}: {shadowed} shadowed, rms {rms:.3}/255, {apart} apart",
            t.label()
        );
        assert!(
            shadowed > 200,
            "{}: {shadowed} receivers in shadow",
            t.label()
        );
        assert!(
            rms <= 1.0 && apart * 100 <= c.len(),
            "{}: rms {rms}, {apart} apart",
            t.label()
        );
    }
}

/// Maps read by a technique of another filter or slice count are a
/// [`soft_shadow_core::ShadowError::MapsMismatch`] that names both, on both backends (the CPU
/// read them as if they were its own before).
#[test]
fn maps_of_another_filter_or_slice_count_are_refused() {
    use soft_shadow_core::{CpuContext, Receivers, ShadowError};
    let spec = soft_shadow_reference::scenes::catalogue::build("overlap").unwrap();
    let geometry = spec.to_scene().unwrap().geometry();
    let points = [glam::Vec3::ZERO];
    let receivers = Receivers::new(&points, &[glam::Vec3::Y]);
    let made = OcclusionSlices::new(8, Prefilter::NBuffer);
    let others = [
        OcclusionSlices::new(8, Prefilter::Sat),
        OcclusionSlices::new(4, Prefilter::NBuffer),
    ];
    let refused = |e: ShadowError| matches!(&e, ShadowError::MapsMismatch(m) if m.contains("nbuffer 8-slice"));
    let cpu = made
        .generate_cpu(&CpuContext::new(), &geometry, &spec.light, 64)
        .unwrap();
    for t in &others {
        let err = t.evaluate_cpu(&cpu, &receivers).unwrap_err();
        assert!(refused(err), "CPU, {}", t.label());
    }
    let Some(ctx) = gpu_for_test("maps_of_another_filter_or_slice_count_are_refused") else {
        return;
    };
    let gpu = made.generate_gpu(&ctx, &geometry, &spec.light, 64).unwrap();
    for t in &others {
        let err = t.evaluate_gpu(&ctx, &gpu, &receivers).unwrap_err();
        assert!(refused(err), "GPU, {}", t.label());
    }
}
