//! Evaluation shared by both backends: the parameters `visibility.wgsl` reads and the per-receiver
//! shading `I(sd, sw)` on the CPU, which the shader repeats line for line.

use crate::attenuation::{AttenuationTable, Falloff, FalloffKind, attenuation, table_coordinate};
use crate::params::{DepthLayer, ShadowWidth, Softness};
use bytemuck::{Pod, Zeroable};
use glam::Vec2;
use soft_shadow_core::light_space::{shadow_coord, sphere_spread_at};
use soft_shadow_core::{Bias, Map2D, MapParams};

/// Largest `c_scale` used (beyond it `I` is a hard shadow to f32 precision; keeps products finite).
pub(crate) const MAX_C_SCALE: f32 = 1.0e30;

/// Evaluation parameters, laid out as `EvalParams` in `visibility.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub(crate) struct EvalParams {
    /// The light-space map.
    pub map: MapParams,
    /// Receiver biases.
    pub bias: Bias,
    /// 0: the linear falloff evaluated directly; 1: the lookup table.
    pub use_table: u32,
    /// 1 for a sphere light: its softness grows by [`sphere_spread_at`] off the map's axis.
    pub sphere: u32,
    /// 1 when `c_scale` comes from the light size ([`Softness::FromLight`]).
    pub from_light: u32,
    /// Constant `c_scale` (when `from_light == 0`).
    pub c_scale: f32,
    /// `c_bias` of the linear falloff.
    pub c_bias: f32,
    /// [`crate::params::softness_size`] of the light.
    pub light_size: f32,
    /// Entries in the table.
    pub table_size: u32,
    /// 1 with back faces: layer 1 of the depth texture holds the nearest back face, which `sd`
    /// is measured from where it lies in front of the receiver; 0: the nearest caster only.
    pub depth_layer: u32,
}

impl EvalParams {
    /// Parameters of `t` for a map `map` and a light of `light_size` (a sphere where `sphere`).
    pub(crate) fn new(
        t: &ShadowWidth,
        map: MapParams,
        light_size: f32,
        sphere: bool,
        table_size: u32,
    ) -> Self {
        let (from_light, c_scale) = match t.softness {
            Softness::FromLight => (1, 0.0),
            Softness::Constant(c) => (0, c),
        };
        let c_bias = match t.falloff {
            FalloffKind::Linear { c_bias } => c_bias,
            FalloffKind::Custom(_) => 0.0,
        };
        Self {
            map,
            bias: t.bias,
            use_table: (table_size > 0) as u32,
            sphere: sphere as u32,
            from_light,
            c_scale,
            c_bias,
            light_size,
            table_size,
            depth_layer: match t.depth {
                DepthLayer::Front => 0,
                DepthLayer::BackFaces => 1,
            },
        }
    }

    /// `c_scale` for a blocker at depth `z_b` and a receiver `p` at `z_r`; `None` for a hard
    /// shadow (a light of size 0 with physical softness). A sphere's size grows by
    /// [`sphere_spread_at`] of `p`.
    pub(crate) fn c_scale_at(&self, z_b: f32, z_r: f32, p: glam::Vec3) -> Option<f32> {
        if self.from_light == 0 {
            return Some(self.c_scale.min(MAX_C_SCALE));
        }
        if self.light_size <= 0.0 {
            return None;
        }
        let c = if self.map.ortho == 1 {
            2.0 / self.light_size
        } else {
            let spread = if self.sphere == 1 {
                sphere_spread_at(&self.map, p)
            } else {
                1.0
            };
            2.0 * z_b * z_r / (self.light_size * spread)
        };
        Some(c.min(MAX_C_SCALE))
    }

    /// World (distant light) or angular (local light) size of one texel of the width map.
    pub(crate) fn width_unit(&self) -> f32 {
        if self.map.ortho == 1 {
            self.map.texel_b
        } else {
            self.map.texel_a
        }
    }
}

/// Bilinear sample of a square map at texel coordinates `st` (centres at +0.5), clamped to the edge.
pub(crate) fn bilinear(map: &Map2D<f32>, st: Vec2) -> f32 {
    let u = st - Vec2::splat(0.5);
    let i = u.floor();
    let a = u - i;
    let (x, y) = (i.x as i64, i.y as i64);
    let t = |dx: i64, dy: i64| *map.get_clamped(x + dx, y + dy);
    let top = t(0, 0) * (1.0 - a.x) + t(1, 0) * a.x;
    let bottom = t(0, 1) * (1.0 - a.x) + t(1, 1) * a.x;
    top * (1.0 - a.y) + bottom * a.y
}

/// How `I` is computed on the CPU.
pub(crate) enum Shader<'a> {
    /// `f` called directly.
    Direct(&'a dyn Falloff),
    /// Through the lookup table.
    Table(&'a AttenuationTable),
}

/// `V` of one receiver: project, the shadow test against the nearest caster `depth`, shadow
/// depth from the nearest back face in `back` where one lies in front of the receiver (else from
/// `depth`: an open or single-sided caster has no back face before it), shadow width from
/// `width`, `I`.
pub(crate) fn shade(
    prm: &EvalParams,
    shader: &Shader,
    depth: &Map2D<f32>,
    back: Option<&Map2D<f32>>,
    width: &Map2D<f32>,
    p: glam::Vec3,
    n: glam::Vec3,
) -> f32 {
    let Some(c) = shadow_coord(&prm.map, &prm.bias, p, n) else {
        return 1.0;
    };
    let (x, y) = (c.st.x.floor() as i64, c.st.y.floor() as i64);
    let front = *depth.get_clamped(x, y);
    let z_b = match back.map(|b| *b.get_clamped(x, y)) {
        Some(z) if z < c.z => z,
        _ => front,
    };
    let sd = c.z - z_b;
    // NaN-safe: anything but a positive shadow depth is lit.
    if sd.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return 1.0;
    }
    let sw = bilinear(width, c.st) * prm.width_unit();
    let Some(cs) = prm.c_scale_at(z_b, c.z_receiver, p) else {
        return if sw > 0.0 { 0.0 } else { 1.0 };
    };
    match shader {
        Shader::Direct(f) => attenuation(sd, sw, cs, *f),
        Shader::Table(t) => {
            if sw > 0.0 {
                t.lookup(table_coordinate(cs * sw, sd))
            } else {
                1.0
            }
        }
    }
}
