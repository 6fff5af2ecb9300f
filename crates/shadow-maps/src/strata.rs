//! Accumulation's rotated sample pattern ([`crate::SamplePattern::Rotated`]): where each
//! receiver's point of a light sample's cell lies, and how far a move across the cell moves
//! the lookup in the sample's map. `visibility.wgsl` repeats `cell_point` and `moved`.

use glam::{UVec2, Vec2, Vec3, Vec4};
use soft_shadow_core::{Light, LightPoint, SampleView};

/// Where a sample's map is read when the sample moves across its cell (see
/// [`SamplePattern::Rotated`]), per unit of the parallax factor the parallax factor (`filters::parallax`): the texel change
/// of the point where the moved sample's ray crosses a given depth, at the 8 points of a 3 x 3
/// grid over the cell other than its centre (rows `-1/2, 0, 1/2` of the cell's second axis,
/// each over the same of its first), interpolated quadratically between them ([`moved`]):
/// exact for a cell the light's sample map bends into an arc (a distant light's polar cells).
/// Laid out as 4 `vec4` per map in `visibility.wgsl`.
pub(crate) type Stratum = [[f32; 4]; 4];

/// Every view's [`Stratum`] for `light` sampled as seen from `receiver` (the views' coverage
/// centre, as [`soft_shadow_core::light_space::sample_views`] samples it).
pub(crate) fn texel_strata(
    light: &Light,
    receiver: Vec3,
    views: &[SampleView],
    resolution: u32,
) -> Vec<Stratum> {
    let point = |u: Vec2| match light.sample(u, receiver).0 {
        LightPoint::Position(p) => p,
        LightPoint::Direction(d) => d.normalize(),
    };
    views
        .iter()
        .map(|v| {
            let m = v.params(resolution);
            let forward = Vec4::from(m.depth_row).truncate();
            let st = |q: Vec3| m.project(q).map_or(Vec2::ZERO, |s| s.truncate());
            // The texel change per unit of parallax of moving the sample by `d`, linearised.
            let along = |d: Vec3| -> Vec2 {
                if m.ortho == 1 {
                    // One unit of depth towards the light, along the direction moved by `t d`.
                    let reach = |t: f32| {
                        let dir = v.light.truncate() + t * d;
                        dir * (-1.0 / forward.dot(dir))
                    };
                    (st(reach(0.01)) - st(reach(-0.01))) / 0.02
                } else {
                    // At unit depth in front of the eye, moved by `t d`.
                    let ahead = v.light.truncate() + forward / forward.length_squared();
                    (st(ahead + 0.01 * d) - st(ahead - 0.01 * d)) / 0.02
                }
            };
            let [centre, size] = v.cell;
            let mut shifts = [Vec2::ZERO; 8];
            if size != Vec2::ZERO {
                let origin = point(centre);
                let mut k = 0;
                for j in [-0.5f32, 0.0, 0.5] {
                    for i in [-0.5f32, 0.0, 0.5] {
                        if i == 0.0 && j == 0.0 {
                            continue;
                        }
                        shifts[k] = along(point(centre + Vec2::new(i, j) * size) - origin);
                        k += 1;
                    }
                }
            }
            let s = shifts.map(|v| v.to_array()).concat();
            [0, 4, 8, 12].map(|i| [s[i], s[i + 1], s[i + 2], s[i + 3]])
        })
        .collect()
}

/// The texel change per unit of parallax for the point `cell` (in `[-1/2, 1/2)²`) of a sample's
/// cell: the quadratic through the [`Stratum`]'s 3 x 3 points (`moved` in WGSL).
pub(crate) fn moved(stratum: &Stratum, cell: Vec2) -> Vec2 {
    // Lagrange weights of the nodes -1/2, 0, 1/2 at 2 * cell.
    let weights = |t: f32| {
        let s = 2.0 * t;
        [0.5 * s * (s - 1.0), 1.0 - s * s, 0.5 * s * (s + 1.0)]
    };
    let (wx, wy) = (weights(cell.x), weights(cell.y));
    let mut sum = Vec2::ZERO;
    let mut k = 0;
    for (j, wj) in wy.iter().enumerate() {
        for (i, wi) in wx.iter().enumerate() {
            if i == 1 && j == 1 {
                continue;
            }
            let [a, b, c, d] = stratum[k / 2];
            let p = if k % 2 == 0 {
                Vec2::new(a, b)
            } else {
                Vec2::new(c, d)
            };
            sum += p * (wi * wj);
            k += 1;
        }
    }
    sum
}

/// A receiver's point in each sample's cell, in `[-1/2, 1/2)²`: one hash of the receiver's
/// position (its bits), rotated by the R2 sequence per sample, in 24-bit fixed point so both
/// backends compute the same values.
pub(crate) fn cell_point(p: Vec3, k: u32) -> Vec2 {
    // pcg3d (Jarzynski and Olano, "Hash Functions for GPU Rendering", 2020).
    let [mut x, mut y, mut z] = p
        .to_array()
        .map(|c| c.to_bits().wrapping_mul(1664525).wrapping_add(1013904223));
    x = x.wrapping_add(y.wrapping_mul(z));
    y = y.wrapping_add(z.wrapping_mul(x));
    z = z.wrapping_add(x.wrapping_mul(y));
    (x, y, z) = (x ^ (x >> 16), y ^ (y >> 16), z ^ (z >> 16));
    x = x.wrapping_add(y.wrapping_mul(z));
    y = y.wrapping_add(z.wrapping_mul(x));
    // The R2 sequence's step (0.75488, 0.56984) in 24 bits.
    let u = UVec2::new(
        (x >> 8).wrapping_add(k.wrapping_mul(12664746)) & 0xff_ffff,
        (y >> 8).wrapping_add(k.wrapping_mul(9560334)) & 0xff_ffff,
    );
    u.as_vec2() / 16_777_216.0 - Vec2::splat(0.5)
}
