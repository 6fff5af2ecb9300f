//! Evaluation shared by both backends: the parameters `visibility.wgsl` reads and the per-receiver
//! shading on the CPU, which the shader repeats line for line: project the receiver, sample the
//! four channels bilinearly, equation 2 with each tap's lower limit, then the
//! visibility-to-illumination table; below a caster under another caster's edge, that caster's
//! own soft shadow ([`lower_shadow`]).

use crate::storage::{Storage, Texel};
use crate::table::IlluminationTable;
use crate::visibility::{limited_visibility, lower_visibility};
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

/// The four channels bilinearly interpolated over `taps`.
fn interpolate(taps: &[(&Texel, f32); 4]) -> Texel {
    taps.iter().fold(Texel::default(), |acc, (t, w)| Texel {
        c: acc.c + t.c * w,
        g: acc.g + t.g * w,
        b: acc.b + t.b * w,
        p: acc.p + t.p * w,
    })
}

/// Taps of [`lower_shadow`].
pub(crate) const LOWER_TAPS: usize = 32;

/// [`lower_shadow`]'s taps on a Vogel spiral: `(cos a, sin a, s)` of tap `i`, at the angle
/// `a = i * 2.399963` (the golden angle, `pi (3 - sqrt 5)`) and the fraction `s = sqrt((i + 1/2)
/// / 32)` of the radius, as `f32` computes them. `visibility.wgsl` holds the same table: a GPU's
/// `cos` and `sin` of angles up to 74 radians differ from the CPU's by up to 2^-11, which moves a
/// tap across a texel at a radius of a few hundred texels.
#[rustfmt::skip]
pub(crate) const LOWER_SPIRAL: [[f32; 3]; LOWER_TAPS] = [
    [1.0, 0.0, 0.125],
    [-0.73736864, 0.67549056, 0.21650635],
    [0.087425075, -0.9961711, 0.2795085],
    [0.6084396, 0.79360014, 0.3307189],
    [-0.98471373, -0.17418066, 0.375],
    [0.84375465, -0.53672904, 0.4145781],
    [-0.2596024, 0.9657156, 0.4506939],
    [-0.4609095, -0.8874472, 0.48412293],
    [0.9393222, 0.34303617, 0.5153882],
    [-0.9243446, 0.3815587, 0.5448624],
    [0.4238439, -0.90573525, 0.572822],
    [0.29928777, 0.9541629, 0.59947896],
    [-0.86521316, -0.50140417, 0.625],
    [0.976675, -0.21472313, 0.649519],
    [-0.5751249, 0.81806564, 0.6731456],
    [-0.12851603, -0.99170744, 0.69597054],
    [0.7646524, 0.644443, 0.7180703],
    [-0.99914587, 0.041322917, 0.73951],
    [0.70882595, -0.7053834, 0.76034534],
    [-0.046186656, 0.99893284, 0.78062475],
    [-0.64071274, -0.7677807, 0.80039054],
    [0.9910705, 0.13333875, 0.8196798],
    [-0.82085365, 0.57113856, 0.8385255],
    [0.21947356, -0.9756184, 0.85695684],
    [0.4971877, 0.867643, 0.875],
    [-0.95269513, -0.30392763, 0.89267856],
    [0.907788, -0.4194294, 0.91001374],
    [-0.38605073, 0.92247754, 0.9270248],
    [-0.3384627, -0.9409798, 0.9437293],
    [0.88519454, 0.46522108, 0.9601432],
    [-0.9669673, 0.2549006, 0.9762812],
    [0.54082876, -0.8411327, 0.99215674],
];

/// The soft shadow of the casters below the edge a receiver reads (a leg under a body's outer
/// penumbra, the lower blocker of `overlap`, a body under a head whose fold is the edge), which
/// one edge per texel cannot hold: the fraction of [`LOWER_TAPS`] taps (nearest texels on [`LOWER_SPIRAL`]) over the
/// disc of radius `(z - b) / p_per_texel` texels around `st` whose texel holds no caster above
/// the receiver's depth `z` (its geometry `g` inside a silhouette, its lower limit `b` outside
/// it). That radius is the half-width of the penumbra an edge at the lower caster's depth `b`
/// casts at `z` (equation 1), so this is the lower caster's penumbra as the light's area sees
/// it, through both of a thin caster's sides; at least one texel.
///
/// Outside the silhouette, the paper's step to 0 below `b` drew the lower caster's hard shadow:
/// black blotches where a low-poly animal's thin legs stand under its body's outer penumbra,
/// whose shadows on the ground are mostly penumbra. Inside it, the edge's inner penumbra alone
/// let light through a body the edge does not outline: light facets in the bunny's umbra under
/// the folds of its head and chest.
pub(crate) fn lower_shadow(map: &Map2D<Texel>, st: Vec2, z: f32, b: f32, ppt: f32) -> f32 {
    let radius = ((z - b) / ppt.max(f32::MIN_POSITIVE)).clamp(1.0, map.width() as f32);
    let lit = LOWER_SPIRAL
        .iter()
        .filter(|&&[cos, sin, s]| {
            let q = st + Vec2::new(cos, sin) * (radius * s);
            let t = map.get_clamped(q.x.floor() as i64, q.y.floor() as i64);
            (if t.p < 0.0 { t.g } else { t.b }) >= z
        })
        .count();
    lit as f32 / LOWER_TAPS as f32
}

/// `V` of one receiver `p` (normal `n`): the fraction `l_g` of the light's diameter it sees
/// (equation 2) through the visibility-to-illumination table; 1 outside the map. The four
/// channels are interpolated bilinearly; the lower limit is not:
///
/// - Inside the silhouette (interpolated `p_i < 0`), each tap's lower limit, weighted as the
///   taps are. `b` interpolated between a back face and a tap with none (depth 1) put a lower
///   limit a fraction of a texel above receivers along a contour where there is no surface:
///   dotted dark lines around a low-poly body's shadow, 0 where the reference reads 0.3-0.6.
/// - Then, where the edge leaves some light, no more than the [`lower_shadow`] of the casters
///   below the edge that the taps hold above the receiver (their mean `b`, weighted as the taps
///   are); outside the silhouette only the taps outside it (`p_i >= 0`) count: an inner tap's
///   `b` (a back face below its edge, or a covered texel's own geometry) would otherwise reach
///   up to a texel outwards and clamp lit receivers beyond the hard edge, false umbra a texel
///   wide around every shadow where the map's texels are wider than the penumbra.
pub(crate) fn shade(
    prm: &EvalParams,
    map: &Map2D<Texel>,
    table: &IlluminationTable,
    p: Vec3,
    n: Vec3,
) -> f32 {
    let Some(co) = shadow_coord(&prm.map, &prm.bias, p, n) else {
        return table.lookup(1.0);
    };
    let z = (prm.warp.receiver_depth(co.z) - prm.tolerance).min(DEPTH_SPAN);
    let taps = map.bilinear_taps(co.st);
    let mut t = interpolate(&taps);
    // A sphere's penumbra is wider here than the ribbons' (`Warp::spread_at`): the distance
    // from the edge, `p_i`, counts for less, and the lower casters' disc is wider. A covered
    // texel's `p_i` (`-MAX_P`) stays umbra: the spread is at most `MAX_SPREAD`.
    let spread = prm.warp.spread_at(&prm.map, p);
    t.p /= spread;
    let inside = t.p < 0.0;
    let edge = if inside {
        let lower = taps
            .iter()
            .map(|(x, w)| w * lower_visibility(z, x.b, t.p))
            .sum();
        table.lookup(limited_visibility(z, t.c, t.g, t.p, lower))
    } else {
        table.lookup(limited_visibility(z, t.c, t.g, t.p, 1.0))
    };
    let (b, w) = taps
        .iter()
        .filter(|(x, _)| (inside || x.p >= 0.0) && x.b < z)
        .fold((0.0f32, 0.0f32), |(b, s), (x, w)| (b + x.b * w, s + w));
    // Nothing to soften where the edge leaves no light (the umbra): no taps there.
    if w > 0.0 && z >= t.g && edge > 0.0 {
        return edge.min(lower_shadow(
            map,
            co.st,
            z,
            b / w,
            prm.warp.p_per_texel / spread,
        ));
    }
    edge
}
