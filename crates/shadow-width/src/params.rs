//! The technique's parameters: how the width map is built, which depth the shadow depth is
//! measured from, the softness and the attenuation.

use crate::attenuation::FalloffKind;
use soft_shadow_core::{
    Backend, Bias, DeviceLimits, Light, LightKind, Result, ShadowError, TechniqueInfo,
};

/// How the shadow-width map is built from the inverted occlusion map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum WidthMethod {
    /// The paper's iterative propagation (section 4): each pass takes the minimum over the texel
    /// and its neighbours at distance `step`, plus `step` times the neighbour's offset length; the
    /// step doubles from 1 until it reaches the map size. Approximate (a chamfer distance).
    Propagate {
        /// 3, 4, 6 or 8 neighbours per pass.
        neighbours: Neighbours,
    },
    /// Exact Euclidean distance transform in linear time (Felzenszwalb & Huttenlocher 2012): a
    /// pass along columns, then the lower envelope of parabolas along rows.
    Exact,
    /// Jump flooding (Rong & Tan 2006) with steps `2^k .. 1` plus one extra step of 1 (JFA+1).
    JumpFlood,
}

/// Neighbourhood of [`WidthMethod::Propagate`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Neighbours {
    /// Three directions 120 degrees apart (the paper's GeForce3 loop: three shifted textures
    /// and the unshifted one fill its four texture units), each offset rounded to the nearest
    /// texel at every step.
    Three,
    /// Left, right, up, down.
    Four,
    /// Six directions 60 degrees apart (the paper's second hardware variant), rounded to the
    /// nearest texel at every step.
    Six,
    /// The four axis neighbours and the four diagonals (offset length √2).
    Eight,
}

impl Neighbours {
    /// 3, 4, 6 or 8.
    pub fn count(self) -> u32 {
        match self {
            Neighbours::Three => 3,
            Neighbours::Four => 4,
            Neighbours::Six => 6,
            Neighbours::Eight => 8,
        }
    }
}

/// Which surface the depth map holds, i.e. where the shadow depth `sd = z' - z` is measured from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[non_exhaustive]
pub enum DepthLayer {
    /// The nearest surface (the ordinary shadow map).
    #[default]
    Front,
    /// The back faces of the shadow casters (section 5): `sd` is measured from the far side of
    /// a closed caster, so the shadows a caster casts on itself come out harder (the paper's
    /// "visually more convincing" self-shadows). The paper renders the farthest back face
    /// ("z-greater"), assuming "shapes that are not both blocker and receiver"; on a caster that
    /// shadows itself (the bunny's ears and head on its body) the farthest back face lies beyond
    /// the shadowed surface. The nearest back face in front of the receiver is used instead, and
    /// the shadow test stays the nearest surface's: behind an open or single-sided caster (no
    /// back face before the receiver) `sd` is measured from that caster's front face.
    BackFaces,
}

/// The softness `c_scale` of `I = f(c_scale * sw / sd)`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Softness {
    /// A constant `c_scale >= 0` (the paper's form). Larger is harder.
    Constant(f32),
    /// Derived from the light's physical size `L` ([`soft_shadow_core::Light::size`]). The physical
    /// relation: a straight edge's true penumbra reaches the umbra a distance `L sd / 2` (distant
    /// light, world units) inside the hard shadow edge, so `I` reaches 0 there when
    /// - distant light (`sw` in world units, `L = 2 tan(angular_diameter / 2)`): `c_scale = 2 / L`;
    /// - local light (`sw` an angle at the light): `c_scale = 2 z_b z_r / L` per receiver, with
    ///   `z_b` the blocker's and `z_r` the receiver's depth along the light axis (the inner half
    ///   penumbra on the receiver is `L sd / (2 z_b)` wide, i.e. `L sd / (2 z_b z_r)` as an angle).
    ///
    /// Both are multiplied by a fit factor (2 for segment, rectangle and triangle lights, 2.5 for round ones): `I` starts at 1 on the hard edge where the truth is
    /// 1/2, so reaching 0 exactly at the umbra gives the same squared error as the hard shadow;
    /// the least-squares fit of the linear `I` to the straight-edge penumbra inside the hard
    /// shadow halves it. `L = 0` (point light) gives `c_scale = ∞`: the hard shadow.
    FromLight,
}

/// The factor [`Softness::FromLight`] applies to the physical `c_scale`: the `k` minimising
/// `∫₀¹ (max(0, 1 - k u) - V(u))² du` for the visibility `V(u)` of a straight edge at depth `u`
/// (in half-penumbra units) inside the hard shadow: 2.0 for a linear ramp (segment and rectangle
/// lights; triangles take it too), 2.5 for the circular-segment profile of round lights (disk,
/// sphere, distant).
pub(crate) fn fit_factor(kind: LightKind) -> f32 {
    match kind {
        LightKind::Disk | LightKind::Sphere | LightKind::Distant => 2.5,
        _ => 2.0,
    }
}

/// The light size the evaluation divides by: [`soft_shadow_core::Light::size`] over [`fit_factor`].
pub(crate) fn softness_size(light: &Light) -> f32 {
    light.size() / fit_factor(light.kind())
}

/// Kirsch & Döllner's single-sample soft shadows: parameters of one configuration.
#[derive(Clone, Debug)]
pub struct ShadowWidth {
    /// How the width map is built.
    pub method: WidthMethod,
    /// Which depth `sd` is measured from.
    pub depth: DepthLayer,
    /// `c_scale`.
    pub softness: Softness,
    /// `f` of `I = f(c_scale * sw / sd)`.
    pub falloff: FalloffKind,
    /// `Some(n)`: evaluate `I` through an `n`-entry dependent lookup table (the paper's GPU
    /// implementation); `None`: evaluate `f` directly (a custom `f` on the GPU always uses a table
    /// of [`DEFAULT_TABLE_SIZE`] entries).
    pub table: Option<u32>,
    /// Receiver biases against acne (shared with the baselines).
    pub bias: Bias,
}

/// Table size used when a custom falloff runs on the GPU without an explicit size.
pub const DEFAULT_TABLE_SIZE: u32 = 256;

impl ShadowWidth {
    /// A configuration with `method`, front depth, physical softness, the linear falloff with
    /// `c_bias = 0`, direct evaluation and the default biases.
    pub fn new(method: WidthMethod) -> Self {
        Self {
            method,
            depth: DepthLayer::Front,
            softness: Softness::FromLight,
            falloff: FalloffKind::default(),
            table: None,
            bias: Bias::default(),
        }
    }

    /// The configurations the report runs: every width method with front depth, plus the
    /// back-face depth and the lookup-table evaluation on the exact transform.
    pub fn standard_set() -> Vec<ShadowWidth> {
        let mut v: Vec<ShadowWidth> = [
            WidthMethod::Propagate {
                neighbours: Neighbours::Four,
            },
            WidthMethod::Propagate {
                neighbours: Neighbours::Eight,
            },
            WidthMethod::Exact,
            WidthMethod::JumpFlood,
        ]
        .into_iter()
        .map(ShadowWidth::new)
        .collect();
        let mut back = ShadowWidth::new(WidthMethod::Exact);
        back.depth = DepthLayer::BackFaces;
        v.push(back);
        let mut table = ShadowWidth::new(WidthMethod::Exact);
        table.table = Some(DEFAULT_TABLE_SIZE);
        v.push(table);
        v
    }

    /// The variant label: method, then `-back` for back-face depth, `-table{n}` for table lookup,
    /// `-custom` for a custom falloff, `-c{c_scale}` for a constant softness.
    pub fn label(&self) -> String {
        let mut s = match self.method {
            WidthMethod::Propagate { neighbours } => format!("propagate-{}", neighbours.count()),
            WidthMethod::Exact => "edt".to_string(),
            WidthMethod::JumpFlood => "jfa".to_string(),
        };
        if self.depth == DepthLayer::BackFaces {
            s.push_str("-back");
        }
        if let Some(n) = self.table {
            s.push_str(&format!("-table{n}"));
        }
        if matches!(self.falloff, FalloffKind::Custom(_)) {
            s.push_str("-custom");
        }
        if let Softness::Constant(c) = self.softness {
            s.push_str(&format!("-c{c}"));
        }
        s
    }
}

impl TechniqueInfo for ShadowWidth {
    /// Each face's maps come from its depth maps of what lies in the face.
    fn face_local(&self) -> bool {
        true
    }

    fn name(&self) -> &'static str {
        "shadow-width"
    }

    fn variant(&self) -> String {
        self.label()
    }

    fn call(&self) -> String {
        let method = match self.method {
            WidthMethod::Propagate { neighbours } => {
                format!("WidthMethod::Propagate {{ neighbours: Neighbours::{neighbours:?} }}")
            }
            WidthMethod::Exact => "WidthMethod::Exact".to_string(),
            WidthMethod::JumpFlood => "WidthMethod::JumpFlood".to_string(),
        };
        let mut fields = Vec::new();
        if self.depth == DepthLayer::BackFaces {
            fields.push("depth = DepthLayer::BackFaces".to_string());
        }
        if let Some(n) = self.table {
            fields.push(format!("table = Some({n})"));
        }
        if let FalloffKind::Custom(_) = self.falloff {
            fields.push("falloff = FalloffKind::Custom(/* your falloff */)".to_string());
        }
        if let Softness::Constant(c) = self.softness {
            fields.push(format!("softness = Softness::Constant({c:?})"));
        }
        soft_shadow_core::technique::call_with(format!("ShadowWidth::new({method})"), &fields)
    }

    /// Any light: one sample at its centre, softness from its size.
    fn models(&self, _kind: LightKind) -> bool {
        true
    }

    /// On the GPU, also a side whose two `f32` layers one storage buffer binding holds.
    fn max_resolution(&self, backend: Backend, device: DeviceLimits) -> u32 {
        match backend {
            Backend::Cpu => soft_shadow_core::technique::MAX_CPU_RESOLUTION,
            Backend::Gpu => device.max_texture_side.min(device.storage_side(8)),
        }
    }

    /// Checks the parameters: `c_scale` and `c_bias` finite and non-negative,
    /// and non-negative, biases finite, table size in range.
    fn validate(&self) -> Result<()> {
        let bad = |what: String| Err(ShadowError::InvalidParameter(what));
        if let Softness::Constant(c) = self.softness
            && !(c.is_finite() && c >= 0.0)
        {
            return bad(format!("c_scale must be finite and >= 0, got {c}"));
        }
        if let FalloffKind::Linear { c_bias } = self.falloff
            && !(c_bias.is_finite() && c_bias >= 0.0)
        {
            return bad(format!("c_bias must be finite and >= 0, got {c_bias}"));
        }
        self.bias.validate()?;
        if let Some(n) = self.table
            && !crate::attenuation::TABLE_SIZE_RANGE.contains(&n)
        {
            return bad(format!(
                "table size must be in {:?}, got {n}",
                crate::attenuation::TABLE_SIZE_RANGE
            ));
        }
        Ok(())
    }

    /// The depth layers, two width buffers, the mask and the jump-flood seeds.
    fn memory_estimate(&self, _light: &Light, resolution: u32) -> u64 {
        let depth = match self.depth {
            DepthLayer::Front => 4,
            DepthLayer::BackFaces => 8,
        };
        soft_shadow_core::memory::maps(1, resolution, depth + 20)
    }

    /// Jump flooding and the paper's propagation take one pass per doubling of the step.
    fn cost_form(&self) -> soft_shadow_core::CostForm {
        match self.method {
            WidthMethod::Exact => soft_shadow_core::CostForm::Texels,
            WidthMethod::JumpFlood | WidthMethod::Propagate { .. } => {
                soft_shadow_core::CostForm::TexelPasses
            }
        }
    }
}
