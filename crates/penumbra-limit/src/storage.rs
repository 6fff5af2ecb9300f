//! Storage of the four channels: `r = c`, `g = g`, `b = b`, `a = p_i / 4 + 1/2` (the paper's
//! packing, section 2.2), each a normalised depth in `[0, 1]`, as f32, f16 or 8-bit unorm.
//!
//! The CPU map keeps decoded f32 values that went through the same quantisation the GPU texture
//! format applies, so both backends read the same numbers.

use half::f16;

/// Largest |p_i| stored (normalised depth units): the alpha packing covers `[-2, 2]`, and
/// `|z - c| <= 1`, so clamping there changes no visibility.
pub(crate) const MAX_P: f32 = 2.0;

/// Texel format of a penumbra limit map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Storage {
    /// `Rgba32Float`.
    F32,
    /// `Rgba16Float`.
    F16,
    /// `Rgba8Unorm`, the paper's cheapest option.
    Rgba8,
}

impl Storage {
    /// Every format, cheapest last.
    pub const ALL: [Storage; 3] = [Storage::F32, Storage::F16, Storage::Rgba8];

    /// Short name used in variant labels.
    pub fn name(self) -> &'static str {
        match self {
            Storage::F32 => "f32",
            Storage::F16 => "f16",
            Storage::Rgba8 => "rgba8",
        }
    }

    /// The wgpu format of the map texture.
    #[cfg(feature = "gpu")]
    pub fn texture_format(self) -> wgpu::TextureFormat {
        match self {
            Storage::F32 => wgpu::TextureFormat::Rgba32Float,
            Storage::F16 => wgpu::TextureFormat::Rgba16Float,
            Storage::Rgba8 => wgpu::TextureFormat::Rgba8Unorm,
        }
    }

    /// Depth tolerance (normalised units) for comparing a receiver with a stored depth: one
    /// quantisation step of the format just below 1 (0 for f32, whose rounding the receiver
    /// biases already cover).
    pub fn depth_tolerance(self) -> f32 {
        match self {
            Storage::F32 => 0.0,
            Storage::F16 => 1.0 / 2048.0,
            Storage::Rgba8 => 1.0 / 255.0,
        }
    }

    /// Stores one channel value (already in `[0, 1]`) and reads it back: to nearest, ties to
    /// even (`combine.wgsl` rounds the same way before the hardware conversion).
    #[inline]
    pub fn round_trip(self, v: f32) -> f32 {
        match self {
            Storage::F32 => v,
            Storage::F16 => f16::from_f32(v).to_f32(),
            Storage::Rgba8 => unorm8(v),
        }
    }
}

/// The four decoded channels of one texel.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Texel {
    /// Occluder edge depth `c`.
    pub c: f32,
    /// Geometry upper limit `g`.
    pub g: f32,
    /// Lower limit `b`.
    pub b: f32,
    /// Signed penumbra limit `p_i`.
    pub p: f32,
}

impl Texel {
    /// The raw channels `(c, g, b, p/4 + 1/2)`, each clamped to `[0, 1]`.
    pub fn encode(self) -> [f32; 4] {
        let u = |v: f32| v.clamp(0.0, 1.0);
        [
            u(self.c),
            u(self.g),
            u(self.b),
            u(self.p.clamp(-MAX_P, MAX_P) * 0.25 + 0.5),
        ]
    }

    /// The texel from raw channels.
    pub fn decode(raw: [f32; 4]) -> Self {
        Self {
            c: raw[0],
            g: raw[1],
            b: raw[2],
            p: (raw[3] - 0.5) * 4.0,
        }
    }

    /// The texel as `storage` keeps it: encoded, quantised, decoded.
    pub fn stored(self, storage: Storage) -> Self {
        Self::decode(self.encode().map(|v| storage.round_trip(v)))
    }
}

/// A value in `[0, 1]` through 8-bit unorm and back, to nearest, ties to even.
fn unorm8(v: f32) -> f32 {
    (v.clamp(0.0, 1.0) * 255.0).round_ties_even() / 255.0
}

/// Scratch of [`Storage::store`]: the encoded channels and their f16 form.
#[derive(Default)]
pub struct StoreScratch {
    raw: Vec<f32>,
    half: Vec<f16>,
}

impl Storage {
    /// [`Texel::stored`] for every texel of `texels`, the f16 conversions in bulk (the `half`
    /// crate's slice conversions use the processor's F16C instructions where it has them;
    /// one value at a time they cost a feature check and a call each). The same bits.
    pub fn store(self, texels: &mut [Texel], scratch: &mut StoreScratch) {
        match self {
            Storage::F32 => {
                texels
                    .iter_mut()
                    .for_each(|t| *t = Texel::decode(t.encode()));
            }
            // Per format rather than through `round_trip`: its match per value measured 40%
            // slower (torus silhouette-f32 at 2048, 75-85 ms against 52-55).
            Storage::Rgba8 => {
                texels
                    .iter_mut()
                    .for_each(|t| *t = Texel::decode(t.encode().map(unorm8)));
            }
            Storage::F16 => {
                use half::slice::HalfFloatSliceExt;
                let StoreScratch { raw, half } = scratch;
                raw.clear();
                raw.extend(texels.iter().flat_map(|t| t.encode()));
                half.clear();
                half.resize(raw.len(), f16::ZERO);
                half.convert_from_f32_slice(raw);
                half.convert_to_f32_slice(raw);
                for (t, c) in texels.iter_mut().zip(raw.chunks_exact(4)) {
                    *t = Texel::decode([c[0], c[1], c[2], c[3]]);
                }
            }
        }
    }
}
