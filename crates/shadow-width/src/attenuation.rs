//! The attenuation function `I(sd, sw)` of Kirsch & Döllner (2003), section 3.
//!
//! `I(sd, sw) = 1` where `sd = 0` or `sw = 0`, otherwise `f(c_scale * sw / sd)` clamped to `[0, 1]`,
//! with `f` continuous, non-increasing and `f(0) = 1`. The paper's own choice is the linear
//! `f(x) = 1 + c_bias - x`. Because `I` depends on `sw / sd` only (its property 2), the
//! dependent-texture lookup the paper uses on GPUs is a 1D table here, indexed by
//! `t = x / (1 + x)`, which covers `x` in `[0, ∞]` without clamping (the paper indexes a 2D texture
//! by `(sd, sw)`; it holds the same function on a bounded domain).

use std::fmt;
use std::sync::Arc;

/// The falloff `f(x)` of the general form `I = f(c_scale * sw / sd)`.
pub trait Falloff: Send + Sync {
    /// `f(x)` for `x >= 0` (`x` may be `+∞`). Must be continuous, non-increasing, with `f(0) = 1`;
    /// results are clamped to `[0, 1]` where the falloff is evaluated.
    fn falloff(&self, x: f32) -> f32;
}

impl<F: Fn(f32) -> f32 + Send + Sync> Falloff for F {
    fn falloff(&self, x: f32) -> f32 {
        self(x)
    }
}

/// Which falloff `f` the technique uses.
#[derive(Clone)]
#[non_exhaustive]
pub enum FalloffKind {
    /// The paper's `f(x) = 1 + c_bias - x` (`c_bias >= 0`, default 0).
    Linear {
        /// `c_bias`, the paper's constant that lifts the outer border of the shadow.
        c_bias: f32,
    },
    /// Any user function; on the GPU it is evaluated through the lookup table.
    Custom(Arc<dyn Falloff>),
}

impl fmt::Debug for FalloffKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FalloffKind::Linear { c_bias } => write!(f, "Linear {{ c_bias: {c_bias} }}"),
            FalloffKind::Custom(_) => write!(f, "Custom"),
        }
    }
}

impl Default for FalloffKind {
    fn default() -> Self {
        FalloffKind::Linear { c_bias: 0.0 }
    }
}

impl Falloff for FalloffKind {
    fn falloff(&self, x: f32) -> f32 {
        match self {
            FalloffKind::Linear { c_bias } => linear_falloff(*c_bias, x),
            FalloffKind::Custom(f) => f.falloff(x),
        }
    }
}

/// The paper's linear falloff `1 + c_bias - x`, clamped to `[0, 1]` (`x = +∞` gives 0).
pub(crate) fn linear_falloff(c_bias: f32, x: f32) -> f32 {
    (1.0 + c_bias - x).clamp(0.0, 1.0)
}

/// `I(sd, sw)` for shadow depth `sd`, shadow width `sw` and softness `c_scale`, in `[0, 1]`.
///
/// `sd <= 0`, `sw <= 0` or a NaN argument give 1 (lit: the depth test says so, the paper's
/// property 1). `c_scale = +∞` gives the hard shadow (0 wherever `sd, sw > 0`). Finite for every
/// input, subnormals and `sd -> 0+` included.
pub(crate) fn attenuation(sd: f32, sw: f32, c_scale: f32, f: &dyn Falloff) -> f32 {
    if !(sd > 0.0 && sw > 0.0) {
        return 1.0;
    }
    let num = c_scale * sw;
    // x = num / sd, which overflows to +∞ for tiny sd: that is the right limit.
    let x = if num.is_nan() { 0.0 } else { num / sd };
    let v = f.falloff(if x.is_nan() { f32::INFINITY } else { x });
    if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) }
}

/// `t = x / (1 + x)` in `[0, 1]`, the table coordinate of `x = c_scale * sw / sd` (`+∞` gives 1),
/// computed as `num / (num + sd)` so that it never overflows.
pub(crate) fn table_coordinate(num: f32, sd: f32) -> f32 {
    if num.is_infinite() {
        return 1.0;
    }
    let t = num / (num + sd);
    if t.is_nan() { 1.0 } else { t.clamp(0.0, 1.0) }
}

/// The dependent lookup table: `f` sampled at `t_i = i / (n - 1)`, linearly interpolated.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct AttenuationTable {
    /// `f(x(t_i))`, clamped to `[0, 1]`.
    pub values: Vec<f32>,
}

/// Fewest and most table entries accepted.
pub const TABLE_SIZE_RANGE: std::ops::RangeInclusive<u32> = 2..=65536;

impl AttenuationTable {
    /// Samples `f` at `size` points of `t` (`size` is clamped to [`TABLE_SIZE_RANGE`]).
    pub(crate) fn new(f: &dyn Falloff, size: u32) -> Self {
        let n = size.clamp(*TABLE_SIZE_RANGE.start(), *TABLE_SIZE_RANGE.end());
        let values = (0..n)
            .map(|i| {
                let t = i as f64 / (n - 1) as f64;
                let x = if i + 1 == n {
                    f32::INFINITY
                } else {
                    (t / (1.0 - t)) as f32
                };
                let v = f.falloff(x);
                if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) }
            })
            .collect();
        Self { values }
    }

    /// The table at `t` in `[0, 1]`, linearly interpolated.
    pub(crate) fn lookup(&self, t: f32) -> f32 {
        let n = self.values.len();
        let s = t.clamp(0.0, 1.0) * (n - 1) as f32;
        let i = (s.floor() as usize).min(n - 2);
        let a = s - i as f32;
        self.values[i] * (1.0 - a) + self.values[i + 1] * a
    }

    /// `I(sd, sw)` through the table; the same special cases as [`attenuation`].
    #[cfg(test)]
    pub fn attenuation(&self, sd: f32, sw: f32, c_scale: f32) -> f32 {
        if !(sd > 0.0 && sw > 0.0) {
            return 1.0;
        }
        self.lookup(table_coordinate(c_scale * sw, sd))
    }
}
