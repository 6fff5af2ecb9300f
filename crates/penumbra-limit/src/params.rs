//! The technique's parameters and their validation.

use crate::storage::Storage;
use crate::table::{Profile, TABLE_SIZE_RANGE};
use soft_shadow_core::{
    Backend, Bias, DeviceLimits, Light, LightKind, Result, ShadowError, TechniqueInfo,
};

/// How the map is generated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Generator {
    /// Section 3.1: front geometry to `g`, silhouette edges extruded into soft-shadow ribbons
    /// that write `c` and `p_i` ("highest penumbra limit wins"), back faces to `b`.
    Silhouette,
    /// From a rasterized depth map: occluder edges are depth discontinuities, every texel takes
    /// its nearest edge (an exact nearest-seed map) inwards and outwards, `p_i = w s r`. For
    /// scenes whose silhouettes are not worth enumerating (foliage).
    DepthImage,
}

impl Generator {
    /// Both generators.
    pub const ALL: [Generator; 2] = [Generator::Silhouette, Generator::DepthImage];

    /// Short name used in variant labels.
    pub fn name(self) -> &'static str {
        match self {
            Generator::Silhouette => "silhouette",
            Generator::DepthImage => "depth-image",
        }
    }
}

/// Default table size (the paper's 512 entries).
pub(crate) const DEFAULT_TABLE_SIZE: u32 = 512;

/// Penumbra limit maps (Lawlor 2006) with their parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct PenumbraLimit {
    /// Generator.
    pub generator: Generator,
    /// Texel format of the map.
    pub storage: Storage,
    /// Light profile of the visibility-to-illumination table.
    pub profile: Profile,
    /// Entries of the table, in [`TABLE_SIZE_RANGE`].
    pub table_size: u32,
    /// Receiver biases against self-shadowing (texels).
    pub bias: Bias,
    /// Depth gap, in texels of world size, that separates layers: an occluder edge in the depth
    /// image needs a jump this much above the local slope; back faces within it of the edge
    /// depth `c` are thrown away (section 3.1, step 3).
    pub layer_gap: f32,
    /// Change of `c` between neighbouring texels, in texels of world size, that marks a
    /// transition between occluders; there `g` and `b` are brought together (Figure 7 C).
    pub transition_gap: f32,
}

impl PenumbraLimit {
    /// The technique with `generator`, f32 storage and the defaults.
    pub fn new(generator: Generator) -> Self {
        Self {
            generator,
            storage: Storage::F32,
            profile: Profile::Auto,
            table_size: DEFAULT_TABLE_SIZE,
            bias: Bias::default(),
            layer_gap: 2.0,
            transition_gap: 4.0,
        }
    }

    /// The same with `storage`.
    pub fn with_storage(mut self, storage: Storage) -> Self {
        self.storage = storage;
        self
    }

    /// The variants the report runs: both generators in every storage format.
    pub fn standard_set() -> Vec<PenumbraLimit> {
        Generator::ALL
            .iter()
            .flat_map(|&g| {
                Storage::ALL
                    .iter()
                    .map(move |&s| PenumbraLimit::new(g).with_storage(s))
            })
            .collect()
    }

    /// Variant label: generator and storage, plus the profile and table size when not default.
    pub fn label(&self) -> String {
        let mut s = format!("{}-{}", self.generator.name(), self.storage.name());
        match self.profile {
            Profile::Auto => {}
            Profile::UniformDisk => s.push_str("-disk"),
            Profile::LimbDarkened { u } => s.push_str(&format!("-limb{u}")),
            Profile::Line => s.push_str("-line"),
        }
        if self.table_size != DEFAULT_TABLE_SIZE {
            s.push_str(&format!("-table{}", self.table_size));
        }
        s
    }
}

/// Largest map side: packed seed coordinates of the depth-image generator are 16-bit.
pub const MAX_RESOLUTION: u32 = 65535;

impl TechniqueInfo for PenumbraLimit {
    /// The depth image's faces come from their depth maps of what lies in the face; the
    /// silhouettes' ribbons reach from edges outside a face into it.
    fn face_local(&self) -> bool {
        self.generator == Generator::DepthImage
    }

    fn name(&self) -> &'static str {
        "penumbra-limit"
    }

    fn variant(&self) -> String {
        self.label()
    }

    fn call(&self) -> String {
        let mut fields = Vec::new();
        match self.profile {
            Profile::Auto => {}
            Profile::UniformDisk => fields.push("profile = Profile::UniformDisk".to_string()),
            Profile::LimbDarkened { u } => {
                fields.push(format!("profile = Profile::LimbDarkened {{ u: {u:?} }}"))
            }
            Profile::Line => fields.push("profile = Profile::Line".to_string()),
        }
        if self.table_size != DEFAULT_TABLE_SIZE {
            fields.push(format!("table_size = {}", self.table_size));
        }
        soft_shadow_core::technique::call_with(
            format!(
                "PenumbraLimit::new(Generator::{:?}).with_storage(Storage::{:?})",
                self.generator, self.storage
            ),
            &fields,
        )
    }

    /// Every light but a segment (see the crate docs).
    fn models(&self, kind: LightKind) -> bool {
        kind != LightKind::Linear
    }

    /// Checks every parameter; the error names the first bad one.
    fn validate(&self) -> Result<()> {
        let bad = |what: String| Err(ShadowError::InvalidParameter(what));
        if !TABLE_SIZE_RANGE.contains(&self.table_size) {
            return bad(format!(
                "table_size {} is outside {TABLE_SIZE_RANGE:?}",
                self.table_size
            ));
        }
        if let Profile::LimbDarkened { u } = self.profile
            && !(0.0..=1.0).contains(&u)
        {
            return bad(format!("limb-darkening coefficient {u} is outside [0, 1]"));
        }
        for (name, v) in [
            ("layer_gap", self.layer_gap),
            ("transition_gap", self.transition_gap),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(format!("{name} must be finite and >= 0, got {v}"));
            }
        }
        self.bias.validate()
    }

    /// [`MAX_RESOLUTION`] at most.
    fn max_resolution(&self, backend: Backend, device: DeviceLimits) -> u32 {
        match backend {
            Backend::Cpu => soft_shadow_core::technique::MAX_CPU_RESOLUTION,
            // Its geometry and seed layers, one `u32` a texel, each in one storage buffer binding.
            Backend::Gpu => device.max_texture_side.min(device.storage_side(4)),
        }
        .min(MAX_RESOLUTION)
    }

    /// The stored map plus the depth, geometry, edge, lower-limit and seed layers.
    fn memory_estimate(&self, _light: &Light, resolution: u32) -> u64 {
        let stored = match self.storage {
            Storage::F32 => 16,
            Storage::F16 => 8,
            Storage::Rgba8 => 4,
        };
        soft_shadow_core::memory::maps(1, resolution, stored + 40)
    }

    /// Silhouette extrusion rasterizes a ribbon as wide as the penumbra per silhouette edge.
    fn cost_form(&self) -> soft_shadow_core::CostForm {
        match self.generator {
            Generator::Silhouette => soft_shadow_core::CostForm::Ribbons,
            Generator::DepthImage => soft_shadow_core::CostForm::Texels,
        }
    }
}
