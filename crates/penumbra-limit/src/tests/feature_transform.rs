//! The exact nearest-seed map: the GPU's (`GpuFeatureTransform`) equals the CPU's
//! (`feature_transform::nearest`), which a unit test holds to the brute-force nearest seed.

use crate::feature_transform::nearest;
use crate::gpu::feature_transform::GpuFeatureTransform;
use harness::testing::gpu_for_test;
use soft_shadow_core::rng::SplitMix;
use soft_shadow_core::seeds::{NONE, pack};

/// Seeds on a `side`² map: one texel in `every` at random (none when 0), a lattice of ties where
/// `lattice`, and the two far corners where `corners` (the longest distances of the map).
fn seeds(side: u32, every: u64, lattice: bool, corners: bool) -> Vec<u32> {
    let mut rng = SplitMix(u64::from(side) * 31 + every);
    let mut v: Vec<u32> = (0..side * side)
        .map(|i| {
            let (x, y) = (i % side, i / side);
            let on_lattice = lattice && x % 10 == 3 && y % 6 == 1;
            let random = every > 0 && rng.next_u64().is_multiple_of(every);
            if on_lattice || random {
                pack(x, y)
            } else {
                NONE
            }
        })
        .collect();
    if corners {
        v[0] = pack(0, 0);
        v[(side * side - 1) as usize] = pack(side - 1, side - 1);
    }
    v
}

/// The same seeds bit for bit, with and without keys (three values at random: ties between
/// equal and unequal keys), on sides that fill no workgroup, a row of workgroups and a part of
/// one, with ties, dense and sparse seeds, no seed at all, and at 2048² (the report's largest
/// maps) seeds only in the far corners and a few at random.
#[test]
fn gpu_feature_transform_equals_the_cpu() {
    let Some(ctx) = gpu_for_test("gpu_feature_transform_equals_the_cpu") else {
        return;
    };
    let ft = GpuFeatureTransform::new(&ctx);
    for (side, every, lattice, corners) in [
        (1, 1, false, false),
        (7, 3, false, false),
        (64, 0, false, false),
        (65, 2, false, true),
        (200, 0, true, false),
        (300, 500, true, true),
        (2048, 200_000, false, true),
    ] {
        let s = seeds(side, every, lattice, corners);
        let mut rng = SplitMix(u64::from(side));
        let keys: Vec<f32> = s.iter().map(|_| (rng.next_u64() % 3) as f32).collect();
        let bytes = (s.len() * 4) as u64;
        let key_buffer = ctx.storage_buffer("keys", bytemuck::cast_slice(&keys));
        for keyed in [false, true] {
            let a = ctx.storage_buffer("seeds", bytemuck::cast_slice(&s));
            let b = ctx.storage_buffer("scratch", &vec![0u8; bytes as usize]);
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            ft.encode(&ctx, &mut enc, [&a, &b], keyed.then_some(&key_buffer), side);
            ctx.queue.submit([enc.finish()]);
            let got = ctx.read_buffer(&a, bytes).expect("read back");
            let got: &[u32] = bytemuck::cast_slice(&got);
            let want = nearest(
                &soft_shadow_core::pool::Pool::new(0),
                s.clone(),
                side,
                keyed.then_some(&keys[..]),
            );
            let differ = got.iter().zip(&want).filter(|(g, w)| g != w).count();
            assert_eq!(
                differ, 0,
                "side {side} keyed {keyed}: {differ} texels differ"
            );
        }
    }
}
