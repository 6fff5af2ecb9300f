//! The technique's parameters and their validation.

pub use crate::filters::Prefilter;
use soft_shadow_core::{
    Backend, DeviceLimits, Light, LightKind, Result, ShadowError, TechniqueInfo,
};

/// How the occlusions `I_k` of the slices between a point and the light combine (section 3.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Combination {
    /// Equation 5: `V = prod(1 - I_k)`, slices as independent random occluders.
    Product,
    /// Additive, clamped: `V = 1 - min(1, sum I_k)` (shadow-volume wedges).
    Sum,
    /// The strongest slice only: `V = 1 - max I_k`.
    Max,
    /// Equation 5 with neighbouring slices chained: after the first, slice `k` lets through the
    /// share of the light that passes it among what passed slice `k - 1`,
    /// `1 - (U_k - I_{k-1}) / (1 - I_{k-1})`, with `U_k` the filtered union of slices `k - 1`
    /// and `k` and `I_{k-1}` both over slice `k`'s kernel (1 where slice `k - 1` already hides
    /// the kernel). Neighbours are where the product's independence fails most: a body that
    /// crosses a plane hides complementary parts of the light from either side of it (the
    /// product lets a lighter line through its umbra), and a shell's two faces in neighbouring
    /// slices hide the same part twice (the product darkens its penumbra). Over one kernel the
    /// chain counts both once; slice `k - 1`'s own factor is read over its own kernel, so the
    /// count is exact only where the two kernels see the same occluders. Slices further apart
    /// stay independent: a solid whose top and bottom faces lie slices apart is still counted
    /// twice, which the product's partial credit for neighbours used to offset (`torus` reads
    /// a darker penumbra chained). The unions are prefiltered beside the slices (twice the
    /// summed-area tables and levels, and their filtering); a chained slice reads two
    /// filtered lookups more.
    Chain,
}

impl Combination {
    /// Every combination.
    pub const ALL: [Combination; 4] = [
        Combination::Product,
        Combination::Sum,
        Combination::Max,
        Combination::Chain,
    ];

    /// Short name used in variant labels.
    pub fn name(self) -> &'static str {
        match self {
            Combination::Product => "product",
            Combination::Sum => "sum",
            Combination::Max => "max",
            Combination::Chain => "chain",
        }
    }

    /// Index shared with the shaders (`COMBINE_*` in `visibility.wgsl`).
    pub fn index(self) -> u32 {
        match self {
            Combination::Product => 0,
            Combination::Sum => 1,
            Combination::Max => 2,
            Combination::Chain => 3,
        }
    }

    /// Whether the maps hold the unions of neighbouring slices beside the slices.
    pub(crate) fn chained(self) -> bool {
        self == Combination::Chain
    }
}

/// Fewest and most slices (section 3.4: "4 to 16 slices is a good tradeoff").
pub const SLICE_RANGE: std::ops::RangeInclusive<u32> = 4..=16;

/// Occlusion textures (Eisemann & Décoret 2006) with their parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct OcclusionSlices {
    /// Number of slices, in [`SLICE_RANGE`].
    pub slices: u32,
    /// Box filter of the occlusion textures.
    pub filter: Prefilter,
    /// How the slices' occlusions combine.
    pub combination: Combination,
    /// Section 3.4's light-leak fix for thin occluders: a fragment also fills the next slice
    /// away from the light.
    pub thin_fix: bool,
    /// Receiver offset along its normal, in texels of the slice frustum at the receiver's depth,
    /// against self-occlusion on curved surfaces.
    pub normal_offset: f32,
    /// How far beyond a slice's lower plane its contribution fades in (section 3.4: "we linearly
    /// fade out the contribution of a slice depending on the distance of the shaded point to
    /// the slice's lower clipping plane"; the paper gives no distance), in texels of the slice
    /// frustum at the receiver's depth, and never more than one slice. While a slice fades in,
    /// the rest of its weight reads it unfiltered and depth-tested, as the receiver's own slice
    /// is read (`eval::slab_occlusion`), so a surface that crosses a plane has no step in its
    /// shadow. 0 is a step at the plane.
    pub fade_texels: f32,
}

/// [`OcclusionSlices::fade_texels`] of [`OcclusionSlices::new`].
pub const DEFAULT_FADE_TEXELS: f32 = 4.0;

impl OcclusionSlices {
    /// `slices` slices with `filter`, the product combination and no thin-occluder fix.
    pub fn new(slices: u32, filter: Prefilter) -> Self {
        Self {
            slices,
            filter,
            combination: Combination::Product,
            thin_fix: false,
            normal_offset: 1.0,
            fade_texels: DEFAULT_FADE_TEXELS,
        }
    }

    /// The same with `combination`.
    pub fn with_combination(mut self, combination: Combination) -> Self {
        self.combination = combination;
        self
    }

    /// The same with the thin-occluder fix on or off.
    pub fn with_thin_fix(mut self, on: bool) -> Self {
        self.thin_fix = on;
        self
    }

    /// The variants the report runs: every filter with 4, 8 and 16 slices (product), the sum,
    /// max and chain combinations with the exact filter (SAT) and 8 slices, for the Figure 3
    /// comparison, and the chain with 8 N-Buffer slices (the registry's default).
    pub fn standard_set() -> Vec<OcclusionSlices> {
        let mut set: Vec<OcclusionSlices> = Prefilter::ALL
            .iter()
            .flat_map(|&f| [4, 8, 16].map(|n| OcclusionSlices::new(n, f)))
            .collect();
        for c in [Combination::Sum, Combination::Max, Combination::Chain] {
            set.push(OcclusionSlices::new(8, Prefilter::Sat).with_combination(c));
        }
        set.push(OcclusionSlices::new(8, Prefilter::NBuffer).with_combination(Combination::Chain));
        set
    }

    /// Variant label: filter and slice count, plus the combination, the fix and the fade when not
    /// default.
    pub fn label(&self) -> String {
        let mut s = format!("{}-{}", self.filter.name(), self.slices);
        if self.combination != Combination::Product {
            s.push('-');
            s.push_str(self.combination.name());
        }
        if self.thin_fix {
            s.push_str("-thin");
        }
        if self.fade_texels != DEFAULT_FADE_TEXELS {
            s.push_str(&format!("-fade{}", self.fade_texels));
        }
        s
    }
}

/// Largest texture side: 8-bit prefiltered values are rounded from `u32` counts, exact up to
/// 4096² texels.
pub const MAX_RESOLUTION: u32 = 4096;

impl TechniqueInfo for OcclusionSlices {
    fn name(&self) -> &'static str {
        "occlusion-slices"
    }

    fn variant(&self) -> String {
        self.label()
    }

    fn call(&self) -> String {
        let mut c = format!(
            "OcclusionSlices::new({}, Prefilter::{:?})",
            self.slices, self.filter
        );
        if self.combination != Combination::Product {
            c.push_str(&format!(
                ".with_combination(Combination::{:?})",
                self.combination
            ));
        }
        if self.thin_fix {
            c.push_str(".with_thin_fix(true)");
        }
        let mut fields = Vec::new();
        if self.fade_texels != DEFAULT_FADE_TEXELS {
            fields.push(format!("fade_texels = {:?}", self.fade_texels));
        }
        soft_shadow_core::technique::call_with(c, &fields)
    }

    /// Rect lights, and disk, sphere and triangle lights through their equal-area square.
    fn models(&self, kind: LightKind) -> bool {
        matches!(
            kind,
            LightKind::Rect | LightKind::Disk | LightKind::Sphere | LightKind::Triangle
        )
    }

    /// Checks every parameter; the error names the first bad one.
    fn validate(&self) -> Result<()> {
        if !SLICE_RANGE.contains(&self.slices) {
            return Err(ShadowError::InvalidParameter(format!(
                "slices {} is outside {SLICE_RANGE:?}",
                self.slices
            )));
        }
        if !(self.normal_offset.is_finite() && self.normal_offset >= 0.0) {
            return Err(ShadowError::InvalidParameter(format!(
                "normal_offset must be finite and >= 0, got {}",
                self.normal_offset
            )));
        }
        if !(self.fade_texels.is_finite() && self.fade_texels >= 0.0) {
            return Err(ShadowError::InvalidParameter(format!(
                "fade_texels must be finite and >= 0, got {}",
                self.fade_texels
            )));
        }
        Ok(())
    }

    /// [`MAX_RESOLUTION`]; on the GPU also one texel below the device's largest texture side
    /// (the summed-area table is one texel wider than the map).
    fn max_resolution(&self, backend: Backend, device: DeviceLimits) -> u32 {
        match backend {
            Backend::Cpu => MAX_RESOLUTION,
            Backend::Gpu => device
                .max_texture_side
                .saturating_sub(1)
                .min(MAX_RESOLUTION),
        }
    }

    /// Per slice (and per union with [`Combination::Chain`]): its occupancy, the summed-area
    /// table and its row pass, and the prefiltered levels (one byte per level for N-Buffers, 4/3 for mipmaps); per texel, the CPU's 16 top
    /// codes.
    fn memory_estimate(&self, _light: &Light, resolution: u32) -> u64 {
        let levels = match self.filter {
            Prefilter::NBuffer => crate::filters::level_count(resolution) as u64,
            // The pyramid, 4/3 of level 0 rounded up to 2 bytes a texel, in a texture of the
            // next power of two on the GPU.
            Prefilter::Mipmap => {
                let pad = resolution.next_power_of_two() as f64 / resolution.max(1) as f64;
                (2.0 * pad * pad).ceil() as u64
            }
            Prefilter::Sat => 0,
        };
        // The chain prefilters each slice's union with its neighbour beside it.
        let filtered = self.slices as u64 * (1 + self.combination.chained() as u64);
        soft_shadow_core::memory::maps(filtered, resolution + 1, 9 + levels)
            + soft_shadow_core::memory::maps(1, resolution, crate::slicing::MAX_SLICES as u64)
    }

    /// N-Buffers write one full-resolution level per doubling of the box.
    fn cost_form(&self) -> soft_shadow_core::CostForm {
        match self.filter {
            Prefilter::NBuffer => soft_shadow_core::CostForm::TexelPasses,
            Prefilter::Mipmap | Prefilter::Sat => soft_shadow_core::CostForm::Texels,
        }
    }
}
