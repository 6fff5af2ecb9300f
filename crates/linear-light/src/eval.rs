//! Shading one receiver: the `shade()` loop of section 3 over `N` samples, shared by the CPU
//! path (`visibility.wgsl` is the same on the GPU).
//!
//! For each sample: the receiver's depth against that sample's map and the visibility channel,
//! both read at the four bilinear taps around the receiver, so `V += sum_tap w_tap * lit_tap *
//! channel_tap`: the paper's per-sample test, antialiased like PCF over one texel. A receiver
//! outside a sample's map sees that sample fully (its lit share).

use glam::Vec3;
use soft_shadow_core::light_space::shadow_coord;
use soft_shadow_core::map2d::bilinear_texels;
use soft_shadow_core::{Bias, MapParams};

/// `V` at `p` (unit normal `n`): `depth(k, x, y)` and `channel(k, x, y)` read sample `k`'s
/// linear depth and visibility at clamped texel `(x, y)`.
pub(crate) fn visibility(
    params: &[MapParams],
    bias: &Bias,
    p: Vec3,
    n: Vec3,
    depth: impl Fn(usize, u32, u32) -> f32,
    channel: impl Fn(usize, u32, u32) -> f32,
) -> f32 {
    let mut v = 0.0f32;
    for (k, m) in params.iter().enumerate() {
        let Some(c) = shadow_coord(m, bias, p, n) else {
            v += m.weight;
            continue;
        };
        for (x, y, w) in bilinear_texels(c.st, m.resolution, m.resolution) {
            // The receiver's own plane at the tap's centre (receiver-plane bias).
            let d = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - c.st;
            if c.receiver_plane_depth(d) <= depth(k, x, y) {
                v += w * channel(k, x, y);
            }
        }
    }
    v.clamp(0.0, 1.0)
}
