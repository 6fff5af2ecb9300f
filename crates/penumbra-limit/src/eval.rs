//! Evaluation shared by both backends: the parameters `visibility.wgsl` reads and the per-receiver
//! shading on the CPU, which the shader repeats line for line: project the receiver, sample the
//! four channels bilinearly, equation 2, then the visibility-to-illumination table.

use crate::storage::{Storage, Texel};
use crate::table::IlluminationTable;
use crate::visibility::clamped_visibility;
use crate::warp::{DEPTH_SPAN, Warp};
use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};
use soft_shadow_core::light_space::shadow_coord;
use soft_shadow_core::{Bias, Map2D, MapParams};

/// Evaluation parameters, laid out as `EvalParams` in `visibility.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub(crate) struct EvalParams {
    /// The light-space map.
    pub map: MapParams,
    /// Receiver biases.
    pub bias: Bias,
    /// Depth warp and normalisation.
    pub warp: Warp,
    /// Entries in the illumination table.
    pub table_size: u32,
    /// Padding.
    pub _reserved: u32,
    /// [`Storage::depth_tolerance`] of the map's format.
    pub tolerance: f32,
    /// Padding to 16 bytes.
    pub _pad: f32,
}

impl EvalParams {
    /// Parameters for a map stored as `storage`.
    pub(crate) fn new(
        map: MapParams,
        bias: Bias,
        warp: Warp,
        storage: Storage,
        table_size: u32,
    ) -> Self {
        Self {
            map,
            bias,
            warp,
            table_size,
            _reserved: 0,
            tolerance: storage.depth_tolerance(),
            _pad: 0.0,
        }
    }
}

/// The four channels bilinearly interpolated at texel coordinate `st`, and the lower limit `b`
/// the receiver takes: outside the silhouette (interpolated `p >= 0`), the mean of the taps
/// outside it (`p_i >= 0`), weighted as bilinear interpolation weights them; inside it the
/// interpolated `b`. An inner tap's `b` (a back face below its edge, or a covered texel's own
/// geometry) would otherwise reach up to a texel outwards and clamp lit receivers beyond the
/// hard edge to 0: false umbra a texel wide around every shadow where the map's texels are wider
/// than the penumbra. The four taps are read once.
pub(crate) fn bilinear_texel(map: &Map2D<Texel>, st: Vec2) -> (Texel, f32) {
    let taps = map.bilinear_taps(st);
    let t = taps.iter().fold(Texel::default(), |acc, (t, w)| Texel {
        c: acc.c + t.c * w,
        g: acc.g + t.g * w,
        b: acc.b + t.b * w,
        p: acc.p + t.p * w,
    });
    if t.p < 0.0 {
        return (t, t.b);
    }
    let (b, w) = taps
        .iter()
        .filter(|(t, _)| t.p >= 0.0)
        .fold((0.0f32, 0.0f32), |(b, s), (t, w)| (b + t.b * w, s + w));
    (t, if w > 0.0 { b / w } else { t.b })
}

/// The fraction `l_g` of the light's diameter visible from receiver `p` (normal `n`), before
/// the table; 1 outside the map.
pub(crate) fn visible_fraction(prm: &EvalParams, map: &Map2D<Texel>, p: Vec3, n: Vec3) -> f32 {
    let Some(co) = shadow_coord(&prm.map, &prm.bias, p, n) else {
        return 1.0;
    };
    let z = (prm.warp.receiver_depth(co.z) - prm.tolerance).min(DEPTH_SPAN);
    let (t, b) = bilinear_texel(map, co.st);
    clamped_visibility(z, t.c, t.g, b, t.p)
}

/// `V` of one receiver: the visible fraction through the illumination table.
pub(crate) fn shade(
    prm: &EvalParams,
    map: &Map2D<Texel>,
    table: &IlluminationTable,
    p: Vec3,
    n: Vec3,
) -> f32 {
    table.lookup(visible_fraction(prm, map, p, n))
}
