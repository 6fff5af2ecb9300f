//! The baselines' filters on the CPU. `visibility.wgsl` is the same code in WGSL, line for
//! line, so that both backends compute the same function.

use crate::maps::CpuShadowMaps;
use crate::strata::{cell_point, moved};
use crate::{Filter, PCSS_FILTER_MAX, PCSS_SEARCH_MAX, SamplePattern, ShadowMapBaseline};
use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use soft_shadow_core::light_space::{above_horizon, shadow_coord};
use soft_shadow_core::{Bias, Light, Map2D, MapParams, Receivers, ShadowCoord};

/// Filter modes as the shader numbers them.
pub(crate) const MODE_HARD: u32 = 0;
/// PCF.
pub(crate) const MODE_PCF: u32 = 1;
/// PCSS.
pub(crate) const MODE_PCSS: u32 = 2;
/// Accumulation.
pub(crate) const MODE_ACCUMULATE: u32 = 3;

/// Evaluation parameters, laid out as `Params` in `visibility.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub(crate) struct EvalParams {
    /// Number of maps.
    pub map_count: u32,
    /// One of the `MODE_*` constants.
    pub mode: u32,
    /// 1 where accumulation rotates its samples per receiver ([`SamplePattern::Rotated`]).
    pub rotated: u32,
    /// PCF radius in texels.
    pub pcf_radius: i32,
    /// [`soft_shadow_core::Light::size`].
    pub light_size: f32,
    /// Largest blocker-search radius (texels): [`PCSS_SEARCH_MAX`] of the map side.
    pub search_max: f32,
    /// Largest PCSS filter radius (texels): [`PCSS_FILTER_MAX`] of the map side.
    pub filter_max: f32,
    /// 1 where PCSS's taps lie in discs ([`disc_kernel`]), 0 in squares.
    pub disc: u32,
    /// Receiver biases.
    pub bias: Bias,
}

impl EvalParams {
    /// Parameters of `b` for `map_count` maps of side `resolution` of `light` (its
    /// [`Light::size`] and [`disc_kernel`]).
    pub(crate) fn new(
        b: &ShadowMapBaseline,
        map_count: u32,
        resolution: u32,
        light: &Light,
    ) -> Self {
        let side = resolution as f32;
        let (mode, radius) = match b.filter {
            Filter::Hard => (MODE_HARD, 0),
            Filter::Pcf { radius } => (MODE_PCF, radius as i32),
            Filter::Pcss => (MODE_PCSS, 0),
            Filter::Accumulate { .. } => (MODE_ACCUMULATE, 0),
        };
        Self {
            map_count,
            mode,
            rotated: (b.pattern == SamplePattern::Rotated) as u32,
            pcf_radius: radius,
            light_size: light.size(),
            search_max: (PCSS_SEARCH_MAX * side).max(16.0),
            filter_max: (PCSS_FILTER_MAX * side).max(32.0),
            disc: disc_kernel(light) as u32,
            bias: b.bias,
        }
    }
}

/// The depth stored at the texel under `st + d` (clamped to the edge) and the receiver's own
/// biased depth there: `c.z` moved along the receiver's plane to that texel's centre.
fn tap(map: &Map2D<f32>, c: &ShadowCoord, d: Vec2) -> (f32, f32) {
    let clamp = |v: f32, n: u32| (v.floor() as i64).clamp(0, n as i64 - 1);
    let (x, y) = (
        clamp(c.st.x + d.x, map.width()),
        clamp(c.st.y + d.y, map.height()),
    );
    let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
    (
        *map.get_clamped(x, y),
        c.receiver_plane_depth(centre - c.st),
    )
}

fn lit(map: &Map2D<f32>, c: &ShadowCoord, d: Vec2) -> f32 {
    let (stored, receiver) = tap(map, c, d);
    if receiver <= stored { 1.0 } else { 0.0 }
}

/// Penumbra (or search) radius in texels for light size `l` between depths `z_block` and `z_recv`.
fn cone_radius(m: &MapParams, l: f32, z_block: f32, z_recv: f32) -> f32 {
    let world = 0.5 * l * (z_recv - z_block);
    if m.ortho == 1 {
        world / m.texel_b
    } else {
        world / (m.texel_a * z_block * z_recv)
    }
}

/// The parallax factor of a sample's move between an occluder at depth `z_block` and a
/// receiver at `z_recv`: the lookup moves by the stratum's texels ([`texel_strata`]) times it.
fn parallax(m: &MapParams, z_block: f32, z_recv: f32) -> f32 {
    let g = if m.ortho == 1 {
        z_recv - z_block
    } else {
        1.0 / z_block - 1.0 / z_recv
    };
    g.max(0.0)
}

/// Visibility of a light sample moved across its cell (see [`SamplePattern::Rotated`]), its map
/// read through `step`, the lookup's move per unit of parallax (`strata::moved`): the occluder's depth from the centre tap, or, where that is lit,
/// from a tap as far as an occluder at the near plane would move the lookup; then the map at
/// the moved sample's lookup for that depth.
fn rotated(map: &Map2D<f32>, m: &MapParams, prm: &EvalParams, c: &ShadowCoord, step: Vec2) -> f32 {
    let capped = |d: Vec2| d * (prm.search_max / d.length().max(prm.search_max));
    let (stored, receiver) = tap(map, c, Vec2::ZERO);
    let block = if stored < receiver {
        stored
    } else {
        let (probe, receiver) = tap(map, c, capped(step * parallax(m, m.near, c.z_receiver)));
        if probe >= receiver {
            return 1.0;
        }
        probe
    };
    lit(map, c, capped(step * parallax(m, block, c.z_receiver)))
}

fn visibility(
    maps: &CpuShadowMaps,
    params: &[MapParams],
    prm: &EvalParams,
    p: Vec3,
    n: Vec3,
) -> f32 {
    let m0 = params[0];
    match prm.mode {
        MODE_ACCUMULATE => {
            let (mut sum, mut wsum) = (0.0f32, 0.0f32);
            for (k, m) in params.iter().enumerate() {
                // Visibility v2: samples below the receiver's horizon do not reach it.
                if !above_horizon(m, p, n) {
                    continue;
                }
                let v = match shadow_coord(m, &prm.bias, p, n) {
                    None => 1.0,
                    Some(c) if prm.rotated == 1 => {
                        let step = moved(&maps.strata[k], cell_point(p, k as u32), c.st);
                        rotated(&maps.maps[k], m, prm, &c, step)
                    }
                    Some(c) => lit(&maps.maps[k], &c, Vec2::ZERO),
                };
                sum += m.weight * v;
                wsum += m.weight;
            }
            if wsum > 0.0 { sum / wsum } else { 1.0 }
        }
        _ => {
            let Some(c) = shadow_coord(&m0, &prm.bias, p, n) else {
                return 1.0;
            };
            let map = &maps.maps[0];
            match prm.mode {
                MODE_HARD => lit(map, &c, Vec2::ZERO),
                MODE_PCF => {
                    let r = prm.pcf_radius;
                    let mut s = 0.0;
                    for j in -r..=r {
                        for i in -r..=r {
                            s += lit(map, &c, Vec2::new(i as f32, j as f32));
                        }
                    }
                    s / ((2 * r + 1) * (2 * r + 1)) as f32
                }
                _ => pcss(map, &m0, prm, &c),
            }
        }
    }
}

/// Whether PCSS's search and filter for `light` are discs rather than squares: where the light
/// is a disc (a disk, a sphere's silhouette, the sun) or a triangle, whose size
/// ([`Light::size`]) is the disc of its area. The disc's taps are the grid's within its
/// inscribed circle ([`pcss_tap`]), as engines sample discs (Poisson or spiral), and over a
/// straight edge they draw the disc's share beyond each chord: an eighth of the penumbra 0.016
/// off that closed form, where the 9 x 9 square's straight ramp, over 1.125 times the radius
/// each side, was 0.086 off. A rectangle keeps the square (its own shape): the disc of its
/// area measured worse there (`plane-occluder` 2048² image error 3.01 -> 3.57), as did a
/// segment's (`linear-bar` 5.03 -> 5.51).
pub(crate) fn disc_kernel(light: &Light) -> bool {
    matches!(
        light,
        Light::Disk { .. } | Light::Sphere { .. } | Light::Distant { .. } | Light::Triangle { .. }
    )
}

/// Whether the tap `(i, j)` of a grid of half-side `n` is PCSS's (`disc`: within the grid's
/// inscribed circle, radius `n` taps; otherwise every tap of the square).
fn pcss_tap(i: i32, j: i32, n: i32, disc: u32) -> bool {
    disc == 0 || i * i + j * j <= n * n
}

/// PCSS: a blocker search over the light's cone from the near plane, then a filter of the
/// penumbra's width at the blockers' mean depth, both over the taps [`pcss_tap`] keeps.
fn pcss(map: &Map2D<f32>, m: &MapParams, prm: &EvalParams, c: &ShadowCoord) -> f32 {
    // One loop per kernel shape, the square's without a test per tap.
    if prm.disc == 0 {
        pcss_kernel::<0>(map, m, prm, c)
    } else {
        pcss_kernel::<1>(map, m, prm, c)
    }
}

/// [`pcss`] over the kernels of shape `DISC` (as [`EvalParams::disc`]).
#[inline(always)]
fn pcss_kernel<const DISC: u32>(
    map: &Map2D<f32>,
    m: &MapParams,
    prm: &EvalParams,
    c: &ShadowCoord,
) -> f32 {
    let z = c.z;
    let search = cone_radius(m, prm.light_size, m.near, z).clamp(1.0, prm.search_max);
    let (mut sum, mut count) = (0.0f32, 0.0f32);
    for j in -3..=3 {
        for i in -3..=3 {
            if !pcss_tap(i, j, 3, DISC) {
                continue;
            }
            let off = Vec2::new(i as f32, j as f32) * (search / 3.0);
            let (d, receiver) = tap(map, c, off);
            if d < receiver {
                sum += d;
                count += 1.0;
            }
        }
    }
    if count == 0.0 {
        return 1.0;
    }
    let blocker = sum / count;
    let radius = cone_radius(m, prm.light_size, blocker, z).clamp(0.5, prm.filter_max);
    let (mut s, mut taps) = (0.0, 0.0);
    for j in -4..=4 {
        for i in -4..=4 {
            if !pcss_tap(i, j, 4, DISC) {
                continue;
            }
            s += lit(map, c, Vec2::new(i as f32, j as f32) * (radius / 4.0));
            taps += 1.0;
        }
    }
    s / taps
}

/// Visibility of every receiver from CPU maps.
pub(crate) fn evaluate_cpu(prm: &EvalParams, maps: &CpuShadowMaps, r: &Receivers) -> Vec<f32> {
    let params: Vec<MapParams> = maps
        .views
        .iter()
        .map(|v| v.params(maps.resolution))
        .collect();
    r.positions
        .par_iter()
        .zip(r.normals.par_iter())
        .map(|(p, n)| visibility(maps, &params, prm, *p, *n))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// PCSS's discs hold 29 and 49 taps (as `visibility.wgsl`'s `pcss_tap` keeps them), their
    /// areas in taps (9 pi and 16 pi) to within 3%; its squares the 49 and 81.
    #[test]
    fn pcss_kernels_hold_their_areas_in_taps() {
        let count = |n: i32, disc: u32| {
            (-n..=n)
                .flat_map(|j| (-n..=n).map(move |i| (i, j)))
                .filter(|(i, j)| pcss_tap(*i, *j, n, disc))
                .count()
        };
        assert_eq!((count(3, 1), count(4, 1)), (29, 49));
        assert_eq!((count(3, 0), count(4, 0)), (49, 81));
        for n in [3, 4] {
            let area = std::f32::consts::PI * (n * n) as f32;
            assert!((count(n, 1) as f32 / area - 1.0).abs() < 0.03);
        }
    }
}
