//! Accumulation's rotated sample pattern ([`crate::SamplePattern::Rotated`]): where each
//! receiver's point of a light sample's cell lies, and how far a move across the cell moves
//! the lookup in the sample's map. `visibility.wgsl` repeats `cell_point` and `moved`.

use bytemuck::{Pod, Zeroable};
use glam::{UVec2, Vec2, Vec3, Vec4};
use soft_shadow_core::light_space::map_sample_depth;
use soft_shadow_core::{Light, LightPoint, SampleView};

/// Where a sample's map is read when the sample moves across its cell (see
/// [`crate::SamplePattern::Rotated`]), per unit of the parallax factor (`filters::parallax`),
/// at the 8 points of a 3 x 3 grid over the cell other than its centre (rows `-1/2, 0, 1/2` of
/// the cell's second axis, each over the same of its first), interpolated quadratically
/// between them ([`moved`]), which follows the arcs a distant light's polar cells bend into
/// (0.016 off a closed form where a linearised cell was 0.049 off).
///
/// A perspective map's lookup moves by the move across the map's axis, less the move along it
/// times the receiver's offset from the principal point (the shift of the point where the
/// moved sample's ray crosses a depth is `g (d_across - d_along Y)`, `Y` the receiver's
/// tangent-plane position): the second term matters for a segment or a cell tilted towards
/// the axis. Laid out as `Stratum` in `visibility.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct Stratum {
    /// Texels per unit of parallax of the move across the axis, two points a `vec4`.
    shifts: [[f32; 4]; 4],
    /// The move along the axis (depth units; zero for an orthographic map), four points a
    /// `vec4`.
    along: [[f32; 4]; 2],
    /// The principal point in texels (`x, y`; the rest padding).
    centre: [f32; 4],
}

/// The 8 points of the 3 x 3 grid over a cell other than its centre, in [`Stratum`]'s order.
const NODES: [(f32, f32); 8] = [
    (-0.5, -0.5),
    (0.0, -0.5),
    (0.5, -0.5),
    (-0.5, 0.0),
    (0.5, 0.0),
    (-0.5, 0.5),
    (0.0, 0.5),
    (0.5, 0.5),
];

/// Every view's [`Stratum`] for `light` sampled as seen from `receiver` (the views' coverage
/// centre, as [`soft_shadow_core::light_space::sample_views`] samples it). A sample moves over
/// the points [`Light::sample`] maps its cell to, or, where `sample_views` put it inside a
/// sphere's ball (a cube face's samples), over those [`Light::map_sample`] maps it to at the
/// sample's own third coordinate, so that it stays in the ball.
pub(crate) fn texel_strata(
    light: &Light,
    receiver: Vec3,
    views: &[SampleView],
    resolution: u32,
) -> Vec<Stratum> {
    views
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let [centre, size] = v.cell;
            let depth = map_sample_depth(k as u32, views.len() as u32);
            let in_ball = placed_in_ball(light, receiver, v, depth);
            let point = |u: Vec2| {
                position(if in_ball {
                    light.map_sample(u, depth, receiver).0
                } else {
                    light.sample(u, receiver).0
                })
            };
            let m = v.params(resolution);
            let forward = Vec4::from(m.depth_row).truncate();
            let st = |q: Vec3| m.project(q).map_or(Vec2::ZERO, |s| s.truncate());
            // At unit depth in front of the eye (perspective maps).
            let ahead = v.light.truncate() + forward / forward.length_squared();
            // The texel change per unit of parallax of moving the sample by `d` across the
            // axis, linearised, and the move along it.
            let moves = |d: Vec3| -> (Vec2, f32) {
                if m.ortho == 1 {
                    // One unit of depth towards the light, along the direction moved by `t d`.
                    let reach = |t: f32| {
                        let dir = v.light.truncate() + t * d;
                        dir * (-1.0 / forward.dot(dir))
                    };
                    ((st(reach(0.01)) - st(reach(-0.01))) / 0.02, 0.0)
                } else {
                    let along = forward.dot(d) / forward.length_squared();
                    let across = d - along * forward;
                    (
                        (st(ahead + 0.01 * across) - st(ahead - 0.01 * across)) / 0.02,
                        along,
                    )
                }
            };
            let mut out = Stratum::default();
            if m.ortho == 0 {
                let c = st(ahead);
                out.centre = [c.x, c.y, 0.0, 0.0];
            }
            if size != Vec2::ZERO {
                let origin = point(centre);
                for (n, (i, j)) in NODES.into_iter().enumerate() {
                    let (shift, along) = moves(point(centre + Vec2::new(i, j) * size) - origin);
                    out.shifts[n / 2][2 * (n % 2)] = shift.x;
                    out.shifts[n / 2][2 * (n % 2) + 1] = shift.y;
                    out.along[n / 4][n % 4] = along;
                }
            }
            out
        })
        .collect()
}

/// A light point's position, or its direction's unit vector.
fn position(q: LightPoint) -> Vec3 {
    match q {
        LightPoint::Position(p) => p,
        LightPoint::Direction(d) => d.normalize(),
    }
}

/// Whether [`soft_shadow_core::light_space::sample_views`] placed `v`, the sample whose third
/// coordinate is `depth`, with [`Light::map_sample`] (a cube face's) rather than
/// [`Light::sample`], seen from `receiver`: both come from the same arguments by the same
/// code, so the view's eye is bit for bit the point of the one that placed it. Views passed
/// out of `sample_views`' order lose it (their samples then move over the disc, not the ball).
fn placed_in_ball(light: &Light, receiver: Vec3, v: &SampleView, depth: f32) -> bool {
    v.light.w == 1.0
        && position(light.map_sample(v.cell[0], depth, receiver).0) == v.light.truncate()
}

/// The texel change per unit of parallax for the point `cell` (in `[-1/2, 1/2)²`) of a sample's
/// cell, read by a receiver at texel `st`: the quadratic through the [`Stratum`]'s 3 x 3 points
/// (`moved` in WGSL, summed in the same order).
pub(crate) fn moved(stratum: &Stratum, cell: Vec2, st: Vec2) -> Vec2 {
    // Lagrange weights of the nodes -1/2, 0, 1/2 at 2 * cell.
    let weights = |t: f32| {
        let s = 2.0 * t;
        Vec3::new(0.5 * s * (s - 1.0), 1.0 - s * s, 0.5 * s * (s + 1.0))
    };
    let (wx, wy) = (weights(cell.x), weights(cell.y));
    let [a, b, c, d] = stratum.shifts.map(Vec4::from);
    let (xy, zw) = (|v: Vec4| Vec2::new(v.x, v.y), |v: Vec4| Vec2::new(v.z, v.w));
    let across = wy.x * (wx.x * xy(a) + wx.y * zw(a) + wx.z * xy(b))
        + wy.y * (wx.x * zw(b) + wx.z * xy(c))
        + wy.z * (wx.x * zw(c) + wx.y * xy(d) + wx.z * zw(d));
    let [p, q] = stratum.along.map(Vec4::from);
    let along = wy.x * (wx.x * p.x + wx.y * p.y + wx.z * p.z)
        + wy.y * (wx.x * p.w + wx.z * q.x)
        + wy.z * (wx.x * q.y + wx.y * q.z + wx.z * q.w);
    let centre = Vec2::new(stratum.centre[0], stratum.centre[1]);
    across - along * (st - centre)
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

#[cfg(test)]
mod tests {
    use super::*;
    use soft_shadow_core::light_space::sample_views;
    use soft_shadow_core::{Coverage, Region, SceneGeometry};

    /// A cube face's sphere samples are recognised as the ball's, a fitted view's as the disc's,
    /// whatever the sample count.
    #[test]
    fn a_faces_sphere_samples_are_told_from_a_fitted_views() {
        let light = Light::Sphere {
            center: Vec3::new(0.0, 0.75, 0.0),
            radius: 0.12,
        };
        let tri = |c: Vec3| [c, c + Vec3::X * 0.3, c + Vec3::Z * 0.3];
        let geometry = SceneGeometry::new(
            vec![
                tri(Vec3::new(1.0, 0.5, 0.0)),
                tri(Vec3::new(-1.0, 0.2, 0.4)),
            ],
            Vec::new(),
        );
        let whole = Coverage::new(&geometry, &light);
        let face = Coverage::new(&geometry, &light).within(
            Region::Face {
                axis: Vec3::X,
                up: Vec3::Y,
                half_angle: 50f32.to_radians(),
            },
            256,
        );
        for n in [4, 16, 64] {
            for (coverage, in_ball) in [(&whole, false), (&face, true)] {
                let views = sample_views(&light, coverage, n);
                for (k, v) in views.iter().enumerate() {
                    let depth = map_sample_depth(k as u32, n);
                    assert_eq!(
                        placed_in_ball(&light, coverage.center(), v, depth),
                        in_ball,
                        "{n} samples, sample {k}, {:?}",
                        coverage.region
                    );
                }
            }
        }
    }
}
