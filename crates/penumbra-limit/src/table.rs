//! The visibility-to-illumination table of appendix A: `f(l)`, the fraction of the light's
//! power that reaches a point seeing the fraction `l` of the light's diameter past a straight
//! edge, for a radially symmetric light.
//!
//! - [`Profile::UniformDisk`]: the circular-segment area, `f = (pi/2 + t sqrt(1 - t^2) + asin t) / pi`
//!   with `t = 2 l - 1`.
//! - [`Profile::LimbDarkened`]: the linear limb-darkening law `I(mu) = 1 - u (1 - mu)` on the
//!   disc (`mu = sqrt(1 - rho^2)`), integrated in closed form: the `mu` term over the part of the
//!   unit disc left of `t` is `pi/2 (t - t^3/3 + 2/3)`. The built-in sun uses `u = 0.6`
//!   ([`soft_shadow_core::light::SUN_LIMB_DARKENING_U`], the usual visible-band value).
//! - [`Profile::Line`]: the identity, exact for a uniform segment across the edge.
//!
//! Every profile is odd-symmetric about `(1/2, 1/2)` (Figure 12): `f(l) = 1 - f(1 - l)`. The
//! table stores `n` samples at `l = i / (n - 1)`, computes the lower half and mirrors it, so the
//! symmetry and the endpoints 0 and 1 hold exactly.

use soft_shadow_core::light::{DistantProfile, Light, SUN_LIMB_DARKENING_U};
use std::f64::consts::PI;

/// Table sizes accepted (the paper uses 512).
pub const TABLE_SIZE_RANGE: std::ops::RangeInclusive<u32> = 2..=65536;

/// Emission profile across the light, as the table integrates it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Profile {
    /// Chosen from the light: the limb-darkened sun for a [`DistantProfile::LimbDarkenedSun`],
    /// the uniform disk otherwise.
    Auto,
    /// A uniform disk.
    UniformDisk,
    /// A disk with the linear limb-darkening coefficient `u` in `[0, 1]`.
    LimbDarkened {
        /// Limb-darkening coefficient.
        u: f32,
    },
    /// A uniform line source across the edge: illumination equals visibility.
    Line,
}

impl Profile {
    /// The concrete profile for `light` (resolves [`Profile::Auto`]).
    pub fn for_light(self, light: &Light) -> Profile {
        match (self, light) {
            (
                Profile::Auto,
                Light::Distant {
                    profile: DistantProfile::LimbDarkenedSun,
                    ..
                },
            ) => Profile::LimbDarkened {
                u: SUN_LIMB_DARKENING_U,
            },
            (Profile::Auto, _) => Profile::UniformDisk,
            (p, _) => p,
        }
    }

    /// `f(l)` in closed form, in f64.
    pub fn illumination(self, l: f64) -> f64 {
        let t = (2.0 * l - 1.0).clamp(-1.0, 1.0);
        let disk = (0.5 * PI + t * (1.0 - t * t).max(0.0).sqrt() + t.asin()) / PI;
        match self {
            Profile::Line => l.clamp(0.0, 1.0),
            Profile::Auto | Profile::UniformDisk => disk,
            Profile::LimbDarkened { u } => {
                let u = u as f64;
                let mu_part = 0.5 * PI * (t - t * t * t / 3.0 + 2.0 / 3.0);
                let total = (1.0 - u) * PI + u * 2.0 * PI / 3.0;
                ((1.0 - u) * disk * PI + u * mu_part) / total
            }
        }
    }
}

/// `f` sampled at `n` evenly spaced `l`, linearly interpolated.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct IlluminationTable {
    /// `f(i / (n - 1))`.
    pub values: Vec<f32>,
}

impl IlluminationTable {
    /// The table of `profile` with `n` entries (`n` in [`TABLE_SIZE_RANGE`], checked by the caller).
    pub(crate) fn new(profile: Profile, n: u32) -> Self {
        let n = n.max(2) as usize;
        let mut values = vec![0.0f32; n];
        for i in 0..n.div_ceil(2) {
            let f = profile.illumination(i as f64 / (n - 1) as f64);
            values[i] = f as f32;
            values[n - 1 - i] = 1.0 - f as f32;
        }
        if n % 2 == 1 {
            values[n / 2] = 0.5;
        }
        values[0] = 0.0;
        values[n - 1] = 1.0;
        Self { values }
    }

    /// `f(l)`, linear between entries; `l` is clamped to `[0, 1]`.
    pub(crate) fn lookup(&self, l: f32) -> f32 {
        let n = self.values.len();
        let s = l.clamp(0.0, 1.0) * (n - 1) as f32;
        let i = (s.floor() as usize).min(n - 2);
        let a = s - i as f32;
        self.values[i] * (1.0 - a) + self.values[i + 1] * a
    }
}
