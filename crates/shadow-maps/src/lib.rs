#![doc = include_str!("../README.md")]

mod filters;
#[cfg(feature = "gpu")]
mod gpu;
mod maps;
mod strata;

#[cfg(feature = "gpu")]
pub use gpu::{GpuShadowMaps, SHADERS, VISIBILITY};
pub use maps::CpuShadowMaps;

#[cfg(feature = "gpu")]
use soft_shadow_core::GpuContext;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::GpuScene;
#[cfg(feature = "gpu")]
use soft_shadow_core::gpu::shader::VisibilityShader;
use soft_shadow_core::light_space::sample_views;
use soft_shadow_core::{
    Bias, Checked, CpuContext, Family, Generation, Light, LightKind, Receivers, Result,
    ShadowError, ShadowTechnique, TechniqueInfo, Tier,
};

/// Which baseline filter.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Filter {
    /// One nearest depth test on the light centre's map.
    Hard,
    /// Percentage-closer filtering over `(2 radius + 1)²` texels.
    Pcf {
        /// Kernel radius in texels.
        radius: u32,
    },
    /// Percentage-closer soft shadows: a 7x7 blocker search and a 9x9 variable PCF, each kept
    /// to its grid's inscribed disc for a light that is a disc or a triangle (29 and 49 taps).
    Pcss,
    /// Average of `samples` hard shadow maps from stratified light samples.
    Accumulate {
        /// Number of light samples (and maps).
        samples: u32,
    },
}

/// Where accumulation's light samples lie for each receiver ([`Filter::Accumulate`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum SamplePattern {
    /// Every receiver sees the light through the same samples, the centres of the cells of a
    /// grid over the light: a penumbra drawn in as many flat steps as there are sample rows (the
    /// accumulation the papers compare against).
    #[default]
    Grid,
    /// Each receiver moves every sample to its own point of the sample's cell, the grid's
    /// pattern rotated (Cranley-Patterson) by a hash of the receiver's position: the steps of
    /// [`Grid`](Self::Grid) become noise, each receiver's expected visibility being that of the
    /// cells the samples stand for (the whole light where `samples` fills the grid: a square,
    /// or `n (n + 1)`). The map of each sample is read where the moved sample's ray meets its
    /// occluder, found by a parallax step (one or two more taps a sample): the occluder's depth
    /// from the centre tap or from one probe as far as an occluder at the near plane would
    /// move the lookup; exact for an occluder at one depth whose edge that probe reaches, an
    /// estimate where thin or overlapping occluders lie between.
    Rotated,
}

/// A shadow-map baseline: a filter plus biases.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowMapBaseline {
    /// The filter.
    pub filter: Filter,
    /// The receiver biases (one texel of each term by default).
    pub bias: Bias,
    /// Where accumulation's samples lie per receiver ([`SamplePattern::Grid`] by default);
    /// other filters take no light samples and accept only the default.
    pub pattern: SamplePattern,
}

/// Largest PCSS blocker-search radius, as a fraction of the map side (16 texels at 512²; never
/// under 16 texels). A cap in texels would stop the search and the filter from following the
/// penumbra as the map grows: PCSS would harden towards the hard map at fine maps (on `overlap`,
/// image error 2.5 at 128² and 5.0 at 2048² with caps of 16 and 32 texels).
pub const PCSS_SEARCH_MAX: f32 = 1.0 / 32.0;
/// Largest PCSS filter radius, as a fraction of the map side (32 texels at 512²; never under 32
/// texels).
pub const PCSS_FILTER_MAX: f32 = 1.0 / 16.0;

impl ShadowMapBaseline {
    /// A baseline with default biases.
    pub fn new(filter: Filter) -> Self {
        Self {
            filter,
            bias: Bias::default(),
            pattern: SamplePattern::Grid,
        }
    }

    /// The same baseline with accumulation's samples placed per receiver as `pattern` says.
    pub fn with_pattern(mut self, pattern: SamplePattern) -> Self {
        self.pattern = pattern;
        self
    }

    /// The baselines the report runs by default: hard, PCF r=2, PCSS, and accumulation of
    /// `accumulation` samples for each entry.
    pub fn standard_set(accumulation: &[u32]) -> Vec<ShadowMapBaseline> {
        let mut v = vec![
            Self::new(Filter::Hard),
            Self::new(Filter::Pcf { radius: 2 }),
            Self::new(Filter::Pcss),
        ];
        v.extend(
            accumulation
                .iter()
                .map(|&n| Self::new(Filter::Accumulate { samples: n })),
        );
        v
    }

    /// The light-sample views of its maps for one view of the light, fitted to what it covers
    /// ([`Generation::coverage`]).
    pub fn views(&self, input: &Generation<'_>) -> Vec<soft_shadow_core::SampleView> {
        self.views_of(input.light, &input.coverage())
    }

    /// [`ShadowMapBaseline::views`] over a coverage already computed.
    fn views_of(
        &self,
        light: &Light,
        coverage: &soft_shadow_core::Coverage,
    ) -> Vec<soft_shadow_core::SampleView> {
        sample_views(light, coverage, self.map_count())
    }

    /// Number of depth maps this baseline renders.
    pub fn map_count(&self) -> u32 {
        match self.filter {
            Filter::Accumulate { samples } => samples.max(1),
            _ => 1,
        }
    }
}

impl TechniqueInfo for ShadowMapBaseline {
    /// Each face's maps are depth maps of what lies in the face, seen from points of the light.
    fn face_local(&self) -> bool {
        true
    }

    fn name(&self) -> &'static str {
        match self.filter {
            Filter::Hard => "hard-shadow-map",
            Filter::Pcf { .. } => "pcf",
            Filter::Pcss => "pcss",
            Filter::Accumulate { .. } => "accumulation",
        }
    }

    fn variant(&self) -> String {
        match self.filter {
            Filter::Hard => "nearest".into(),
            Filter::Pcf { radius } => format!("r{radius}"),
            Filter::Pcss => "7x7-9x9".into(),
            Filter::Accumulate { samples } => match self.pattern {
                SamplePattern::Grid => format!("n{samples}"),
                SamplePattern::Rotated => format!("n{samples}-rotated"),
            },
        }
    }

    fn call(&self) -> String {
        let filter = match self.filter {
            Filter::Hard => "Filter::Hard".to_string(),
            Filter::Pcf { radius } => format!("Filter::Pcf {{ radius: {radius} }}"),
            Filter::Pcss => "Filter::Pcss".to_string(),
            Filter::Accumulate { samples } => {
                format!("Filter::Accumulate {{ samples: {samples} }}")
            }
        };
        let mut constructor = format!("ShadowMapBaseline::new({filter})");
        if self.pattern != SamplePattern::Grid {
            constructor.push_str(&format!(".with_pattern(SamplePattern::{:?})", self.pattern));
        }
        let mut fields = Vec::new();
        if self.bias != Bias::default() {
            fields.push(format!("bias = {:?}", self.bias));
        }
        soft_shadow_core::technique::call_with(constructor, &fields)
    }

    fn validate(&self) -> Result<()> {
        match (self.filter, self.pattern) {
            (_, SamplePattern::Grid) | (Filter::Accumulate { .. }, _) => Ok(()),
            (filter, pattern) => Err(ShadowError::InvalidParameter(format!(
                "pattern {pattern:?} places accumulation's light samples; {filter:?} takes none"
            ))),
        }
    }

    fn models(&self, _kind: LightKind) -> bool {
        // Every light has a centre and samples; a point light makes all of them hard shadows.
        true
    }

    /// One `f32` depth map per light sample.
    fn memory_estimate(&self, _light: &Light, resolution: u32) -> u64 {
        soft_shadow_core::memory::maps(self.map_count() as u64, resolution, 4)
    }
}

impl ShadowTechnique for ShadowMapBaseline {
    type CpuMaps = CpuShadowMaps;
    #[cfg(feature = "gpu")]
    type GpuMaps = gpu::GpuShadowMaps;
    #[cfg(not(feature = "gpu"))]
    type GpuMaps = soft_shadow_core::NoGpuMaps;

    fn cpu_maps(&self, cpu: &CpuContext, input: Checked<Generation<'_>>) -> CpuShadowMaps {
        let coverage = input.coverage();
        let views = self.views_of(input.light, &coverage);
        CpuShadowMaps::render(
            cpu,
            input.light,
            coverage.center(),
            &views,
            &input.geometry.casters,
            input.resolution,
        )
    }

    fn cpu_visibility(
        &self,
        maps: &CpuShadowMaps,
        receivers: Checked<Receivers<'_>>,
    ) -> Result<Vec<f32>> {
        let params =
            filters::EvalParams::new(self, maps.views.len() as u32, maps.resolution, &maps.light);
        Ok(filters::evaluate_cpu(&params, maps, &receivers))
    }

    #[cfg(feature = "gpu")]
    fn gpu_maps(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        input: Checked<Generation<'_>>,
    ) -> Result<gpu::GpuShadowMaps> {
        let coverage = input.coverage();
        let views = self.views_of(input.light, &coverage);
        gpu::GpuShadowMaps::record(
            gpu,
            enc,
            input.light,
            coverage.center(),
            &views,
            scene,
            input.resolution,
        )
    }

    #[cfg(feature = "gpu")]
    const VISIBILITY: &'static VisibilityShader = &gpu::VISIBILITY;

    #[cfg(feature = "gpu")]
    fn recycle_maps(&self, gpu: &GpuContext, maps: gpu::GpuShadowMaps) {
        gpu.recycle_texture(maps.texture);
    }

    #[cfg(feature = "gpu")]
    fn bind_maps(
        &self,
        gpu: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        maps: &gpu::GpuShadowMaps,
    ) -> Result<wgpu::BindGroup> {
        let params =
            filters::EvalParams::new(self, maps.views.len() as u32, maps.resolution, &maps.light);
        Ok(gpu::bind_maps(gpu, layout, &params, maps))
    }
}

/// The baselines for a [`Registry`](soft_shadow_core::Registry), each a family of its own: the
/// hard shadow map (the frame pipeline's path for lights of zero size), PCF (radius 2; 1, 3
/// and 4 offered), PCSS, and accumulation (16 samples; 4 and 64 in the full report, 256
/// offered; each also in the [`SamplePattern::Rotated`] pattern but 256).
pub fn families() -> Vec<Family> {
    let new = ShadowMapBaseline::new;
    let accumulate = |samples| new(Filter::Accumulate { samples });
    let rotated = |samples| accumulate(samples).with_pattern(SamplePattern::Rotated);
    vec![
        Family::new(new(Filter::Hard), Tier::Quick).zero_size_path(),
        Family::new(new(Filter::Pcf { radius: 2 }), Tier::Quick).with_all(
            [1, 3, 4].map(|radius| new(Filter::Pcf { radius })),
            Tier::Offered,
        ),
        Family::new(new(Filter::Pcss), Tier::Quick),
        Family::new(accumulate(16), Tier::Quick)
            .with_all([4, 64].map(accumulate), Tier::Report)
            .with(accumulate(256), Tier::Offered)
            .with(rotated(4), Tier::Report)
            .with(rotated(16), Tier::Quick)
            .with(rotated(64), Tier::Report),
    ]
}
