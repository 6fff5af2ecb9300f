//! The technique's parameters and their validation.

use soft_shadow_core::{
    Backend, Bias, DeviceLimits, Light, LightKind, Result, ShadowError, TechniqueInfo,
};

/// Fewest and most point samples along the segment.
pub const SAMPLE_RANGE: std::ops::RangeInclusive<u32> = 2..=64;

/// Soft shadow maps for linear lights (Heidrich, Brabec & Seidel 2000) with their parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearLight {
    /// Point samples along the segment, both ends included, in [`SAMPLE_RANGE`].
    pub samples: u32,
    /// Depth-discontinuity threshold: a texel is an edge where the Laplacian of inverse depth
    /// exceeds this fraction of its inverse depth, and a grid triangle is a skin where its
    /// farthest vertex lies beyond its nearest by more than this fraction. Maps smaller than
    /// 64 texels use a larger one ([`LinearLight::edge_threshold_at`]).
    pub edge_threshold: f32,
    /// Receiver biases against self-shadowing (texels), as the shadow-map baselines use.
    pub bias: Bias,
}

/// Map side from which [`LinearLight::edge_threshold`] applies as given.
pub(crate) const THRESHOLD_REFERENCE_SIDE: u32 = 64;

impl LinearLight {
    /// The edge threshold used for maps of side `resolution`: [`edge_threshold`](Self::edge_threshold)
    /// scaled by `(64 / resolution)²` below 64 texels.
    ///
    /// The Laplacian of a smooth curved surface's inverse depth grows with the texel's area, while
    /// a true discontinuity's does not: on coarse maps curvature alone passes the base threshold
    /// and grows false skins over lit receivers. Measured on the `acne` scene (recast under a
    /// segment): with the base 0.02 a 16² map put 454 of 30,095 unoccluded receivers below
    /// `V = 0.98` for N = 2; scaled, none.
    pub fn edge_threshold_at(&self, resolution: u32) -> f32 {
        let r = resolution.clamp(1, THRESHOLD_REFERENCE_SIDE) as f32;
        self.edge_threshold * (THRESHOLD_REFERENCE_SIDE as f32 / r).powi(2)
    }

    /// `samples` samples with the default threshold (0.02) and biases.
    pub fn new(samples: u32) -> Self {
        Self {
            samples,
            edge_threshold: 0.02,
            bias: Bias::default(),
        }
    }

    /// The variants the report runs: the paper's 2 and 3 samples, and 5.
    pub fn standard_set() -> Vec<LinearLight> {
        [2, 3, 5].map(LinearLight::new).to_vec()
    }

    /// Variant label: `n<samples>`, plus the threshold when not default.
    pub fn label(&self) -> String {
        let mut s = format!("n{}", self.samples);
        if self.edge_threshold != 0.02 {
            s.push_str(&format!("-edge{}", self.edge_threshold));
        }
        s
    }
}

impl TechniqueInfo for LinearLight {
    fn name(&self) -> &'static str {
        "linear-light"
    }

    fn variant(&self) -> String {
        self.label()
    }

    fn call(&self) -> String {
        let mut fields = Vec::new();
        if self.edge_threshold != 0.02 {
            fields.push(format!("edge_threshold = {:?}", self.edge_threshold));
        }
        soft_shadow_core::technique::call_with(
            format!("LinearLight::new({})", self.samples),
            &fields,
        )
    }

    /// Segment lights, and triangles as three of them.
    fn models(&self, kind: LightKind) -> bool {
        matches!(kind, LightKind::Linear | LightKind::Triangle)
    }

    /// On the GPU, also a side whose skin list (one `u32` per quad, `(side - 1)²`) one storage
    /// buffer binding holds.
    fn max_resolution(&self, backend: Backend, device: DeviceLimits) -> u32 {
        match backend {
            Backend::Cpu => soft_shadow_core::technique::MAX_CPU_RESOLUTION,
            Backend::Gpu => device
                .max_texture_side
                .min(device.storage_side(4).saturating_add(1)),
        }
    }

    /// Checks every parameter; the error names the first bad one.
    fn validate(&self) -> Result<()> {
        let bad = |what: String| Err(ShadowError::InvalidParameter(what));
        if !SAMPLE_RANGE.contains(&self.samples) {
            return bad(format!(
                "samples {} is outside {SAMPLE_RANGE:?}",
                self.samples
            ));
        }
        if !(self.edge_threshold.is_finite() && self.edge_threshold > 0.0) {
            return bad(format!(
                "edge_threshold must be finite and > 0, got {}",
                self.edge_threshold
            ));
        }
        self.bias.validate()
    }

    /// Per sample of each segment: its depth, grid depth, channel and skin list; plus the
    /// two warped values and their depth.
    fn memory_estimate(&self, light: &Light, resolution: u32) -> u64 {
        let segments = if light.kind() == LightKind::Triangle {
            3
        } else {
            1
        };
        let layers = self.samples as u64 * segments;
        soft_shadow_core::memory::maps(1, resolution, layers * 16 + 12)
    }
}
