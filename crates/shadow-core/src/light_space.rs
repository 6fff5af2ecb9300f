//! Light-space projection shared by every depth-map technique: the per-map parameters that CPU
//! and GPU code read, the views of light samples, and the receiver biases against shadow acne.
//!
//! `gpu/light_space.wgsl` is the same code in WGSL (the module `soft_shadow_core::light_space`,
//! imported by the shaders that use it: [`crate::gpu::shader`]), so both backends project
//! receivers identically.

use crate::coverage::{Coverage, Region};
use crate::light::{Light, LightPoint};
use crate::view::{ProjectionKind, View};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3, Vec4};

/// Per-map parameters, laid out as `MapView` in `light_space.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct MapParams {
    /// World to clip, column-major.
    pub view_proj: [f32; 16],
    /// Linear depth of `p` is `dot(depth_row, (p, 1))`.
    pub depth_row: [f32; 4],
    /// Near plane.
    pub near: f32,
    /// Far plane.
    pub far: f32,
    /// Texel world size is `texel_a * z + texel_b`.
    pub texel_a: f32,
    /// See `texel_a`.
    pub texel_b: f32,
    /// 1 for orthographic maps.
    pub ortho: u32,
    /// Weight of this light sample.
    pub weight: f32,
    /// Map side in texels.
    pub resolution: u32,
    /// Padding to 16 bytes.
    pub _pad: f32,
    /// The light sample: eye position with w = 1 (perspective) or direction to the light with w = 0.
    pub light: [f32; 4],
}

impl MapParams {
    /// Linear depth (distance along the map's axis) of a world point.
    pub fn linear_depth(&self, p: Vec3) -> f32 {
        Vec4::from(self.depth_row).dot(p.extend(1.0))
    }

    /// World size of one texel at linear depth `z`.
    pub fn texel_size(&self, z: f32) -> f32 {
        self.texel_a * z + self.texel_b
    }

    /// Map position in texels (`x`, `y`; texel centres at +0.5) and linear depth (`z`) of a
    /// world point, or `None` at or behind the eye plane (`map_project` in WGSL).
    pub fn project(&self, q: Vec3) -> Option<Vec3> {
        let clip = Mat4::from_cols_array(&self.view_proj) * q.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let resolution = self.resolution as f32;
        Some(Vec3::new(
            (clip.x / clip.w * 0.5 + 0.5) * resolution,
            (0.5 - clip.y / clip.w * 0.5) * resolution,
            self.linear_depth(q),
        ))
    }
}

/// One light sample's view and weight.
#[derive(Clone, Copy, Debug)]
pub struct SampleView {
    /// The light-space view.
    pub view: View,
    /// Emission weight of the sample.
    pub weight: f32,
    /// Eye position (w = 1) or unit direction towards the light (w = 0).
    pub light: Vec4,
    /// The cell of the light's sample grid the sample stands for ([`Light::stratified_grid`]):
    /// its centre and its size in [`Light::sample`]'s unit square; size zero for a light's
    /// centre or a point light.
    pub cell: [Vec2; 2],
}

impl SampleView {
    /// The view of one light point, covering `coverage` and looking along `axis`.
    pub fn new(q: LightPoint, weight: f32, axis: Vec3, coverage: &Coverage) -> Self {
        Self {
            view: View::fit_light(q, axis, coverage),
            weight,
            light: match q {
                LightPoint::Position(p) => p.extend(1.0),
                LightPoint::Direction(d) => d.normalize().extend(0.0),
            },
            cell: [Vec2::ZERO; 2],
        }
    }

    /// The view of the light's centre, covering `coverage`.
    pub fn center(light: &Light, coverage: &Coverage) -> Self {
        Self::new(light.center(), 1.0, light.axis(coverage.center()), coverage)
    }

    /// The shader-side parameters for a `resolution`-wide map.
    pub fn params(&self, resolution: u32) -> MapParams {
        let (a, b) = self.view.texel_scale(resolution);
        let row: Vec4 = -self.view.view.row(2);
        MapParams {
            view_proj: self.view.view_projection().to_cols_array(),
            depth_row: row.to_array(),
            near: self.view.near,
            far: self.view.far,
            texel_a: a,
            texel_b: b,
            ortho: matches!(self.view.kind, ProjectionKind::Orthographic { .. }) as u32,
            weight: self.weight,
            resolution,
            _pad: 0.0,
            light: self.light.to_array(),
        }
    }
}

/// The views of `count` stratified light samples (1: the light's centre), covering `coverage`,
/// each with its [`SampleView::cell`], placed for the coverage's centre: at [`Light::sample`] of
/// each cell's centre, and in a cube face ([`Region::Face`]) at [`Light::map_sample`] of it
/// and [`map_sample_depth`]`(k, count)` for the `k`-th, which puts a sphere's samples inside
/// its ball.
///
/// A face's window is a fixed sixth of the directions around the light, whatever it holds, so
/// its penumbrae lie anywhere out to its seams, up to 57 degrees off its axis, where the disc
/// facing the axis is foreshortened to 0.55; a fitted view centres its window on its casters
/// and their shadows. Measured with the ball's samples (image error against the reference,
/// 128² G-buffer): in `room-lamp` and `room-lamp-corner` the grid's 4, 16 and 64 samples are
/// better at 512² and 2048² (16 samples: `room-lamp-corner` 0.311 to 0.228 and 0.193 to
/// 0.146, `room-lamp` 0.535 to 0.478 and 0.220 to 0.210), the rotated 4 worse at 2048² (0.365
/// to 0.425 on the corner); in one fitted view the few sample counts lost more to the ball's
/// scatter than the disc loses to foreshortening (`torus`, 4 samples, 3.52 to 4.40 at 2048²;
/// `teapot-sphere`, 16, 0.60 to 0.69), so fitted views keep the disc.
pub fn sample_views(light: &Light, coverage: &Coverage, count: u32) -> Vec<SampleView> {
    let center = coverage.center();
    let axis = light.axis(center);
    if count <= 1 {
        return vec![SampleView::center(light, coverage)];
    }
    let (cells, size) = light.stratified_grid(count);
    let face = matches!(coverage.region, Region::Face { .. });
    cells
        .into_iter()
        .enumerate()
        .map(|(k, u)| {
            let (q, w) = if face {
                light.map_sample(u, map_sample_depth(k as u32, count), center)
            } else {
                light.sample(u, center)
            };
            SampleView {
                cell: [u, size],
                ..SampleView::new(q, w, axis, coverage)
            }
        })
        .collect()
}

/// The third coordinate of [`Light::map_sample`] for the `k`-th of `n` samples of
/// [`sample_views`] in a cube face: the midpoint of stratum `k m mod n` of `[0, 1)`, `m` the
/// first integer from `n / phi` up that is coprime with `n`. Every stratum is used once, so
/// the lifts of a set cancel (up to their cells' weights) and a sphere's samples do not lean
/// towards either side, and consecutive samples (a row of the cells' grid) step by about
/// `1 / phi` of the range, so the lifts do not follow the grid's rows or columns.
pub fn map_sample_depth(k: u32, n: u32) -> f32 {
    let n = n.max(1);
    let gcd = |mut a: u32, mut b: u32| {
        while b != 0 {
            (a, b) = (b, a % b);
        }
        a
    };
    // The first multiplier from n / phi up that visits every stratum.
    let mut m = (f64::from(n) * 0.618_033_988_749_894_9).ceil() as u32;
    while gcd(m, n) != 1 {
        m += 1;
    }
    ((u64::from(k) * u64::from(m) % u64::from(n)) as f32 + 0.5) / n as f32
}

/// Half the diagonal of a texel, in texels: how far a receiver can lie from the centre of the
/// texel it reads, so its own surface spans at most `DEPTH_SPREAD * tan(theta)` texels of depth
/// there (`theta` the angle between its normal and the light).
pub const DEPTH_SPREAD: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// Receiver biases against self-shadowing, in world units per texel of the map at the receiver's
/// depth (so they shrink as the resolution grows).
///
/// The comparison depth of a tap at offset `d` texels is
/// `z(p + n * normal_offset * texel) - texel * (depth + slope * tan(theta) * (1 + |d|))`, with `theta`
/// the angle between the normal and the light (tan clamped to [`MAX_TAN`]): a normal offset, a constant, a
/// slope-scaled and a receiver-plane bias, as engines combine them against acne.
///
/// **Cap.** For a receiver facing the light sample, whatever the terms add up to, the centre's
/// comparison depth moves at most
/// `texel * (DEPTH_SPREAD * tan(theta) + max_push)` towards the light, measured from the
/// receiver's own tangent plane where the map is read (the normal offset moves the point off
/// that plane by `normal_offset / cos(theta)` texels along the light): the receiver's own depth
/// spread across the texel it reads, plus `max_push` texels. So a bias never pushes a receiver
/// through an occluder that lies more than that in front of it (a gap the map resolves), at any
/// angle and resolution; without the cap the defaults push by `1/cos + 1 + tan` texels, 21 at
/// grazing light. A receiver facing away from the sample is in its own attached shadow for it,
/// which visibility v2 leaves to the lighting, so the terms apply uncapped there. Laid out as
/// `Bias` in WGSL.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct Bias {
    /// Receiver offset along its normal, texels.
    pub normal_offset: f32,
    /// Constant depth bias, texels.
    pub depth: f32,
    /// Scale of the slope term.
    pub slope: f32,
    /// Largest push beyond the receiver's own depth spread, texels (see the cap above).
    pub max_push: f32,
}

impl Bias {
    /// A bias with the given normal offset, constant and slope terms and the default cap.
    pub fn new(normal_offset: f32, depth: f32, slope: f32) -> Self {
        Self {
            normal_offset,
            depth,
            slope,
            max_push: Self::MAX_PUSH,
        }
    }

    /// The default cap, texels beyond the receiver's own depth spread.
    pub const MAX_PUSH: f32 = 1.0;

    /// No bias at all: for receivers that cast nothing. No map holds them, so they cannot
    /// shadow themselves, and any push only moves contact shadows (the papers' grounds).
    pub const NONE: Bias = Bias {
        normal_offset: 0.0,
        depth: 0.0,
        slope: 0.0,
        max_push: 0.0,
    };

    /// The same terms with another cap (`f32::INFINITY`: uncapped).
    pub fn with_max_push(self, max_push: f32) -> Self {
        Self { max_push, ..self }
    }

    /// Checks every term is finite and `>= 0` (the cap may be `+inf`), naming the bad one.
    pub fn validate(&self) -> crate::Result<()> {
        let terms = [
            ("normal_offset", self.normal_offset),
            ("depth", self.depth),
            ("slope", self.slope),
        ];
        for (name, v) in terms {
            if !(v.is_finite() && v >= 0.0) {
                return Err(crate::ShadowError::InvalidParameter(format!(
                    "bias.{name} must be finite and >= 0, got {v}"
                )));
            }
        }
        if self.max_push.is_nan() || self.max_push < 0.0 {
            return Err(crate::ShadowError::InvalidParameter(format!(
                "bias.max_push must be >= 0, got {}",
                self.max_push
            )));
        }
        Ok(())
    }

    /// Depth the centre of a receiver moves towards the light, world units: the terms' sum
    /// `texel * (normal_offset / cos + depth + slope * tan)` (tan clamped to [`MAX_TAN`]), capped at
    /// `texel * (DEPTH_SPREAD * tan + max_push)`.
    pub fn push(&self, texel: f32, cos: f32) -> f32 {
        let (c, tan) = clamped_cos_tan(cos);
        let sum = texel * (self.normal_offset / c + self.depth + self.slope * tan);
        sum.min(texel * (DEPTH_SPREAD * tan + self.max_push))
    }
}

impl Default for Bias {
    /// One texel of each term, capped at one texel beyond the receiver's spread: no acne on the
    /// catalogue's `acne` scene at any resolution tested.
    fn default() -> Self {
        Self::new(1.0, 1.0, 1.0)
    }
}

/// A receiver in one map: position in texels, biased comparison depth, receiver-plane gradient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowCoord {
    /// Position in texels (texel centres at +0.5).
    pub st: Vec2,
    /// Biased linear depth to compare against the map.
    pub z: f32,
    /// Signed change of the receiver's own plane depth per texel of offset in `st`, at most
    /// [`MAX_TAN`] texels of depth per texel (see [`ShadowCoord::receiver_plane_depth`]).
    pub grad: Vec2,
    /// Unbiased linear depth of the receiver.
    pub z_receiver: f32,
    /// Whether the receiver faces this light sample (the sample is above its horizon).
    pub facing: bool,
}

impl ShadowCoord {
    /// The receiver's biased depth at offset `d` texels from `st` (a filter tap): moved along
    /// its own plane, `z + dot(grad, d)` (the signed receiver-plane bias). A receiver facing
    /// away from the sample is in its own attached shadow for it, the lighting's job: there the
    /// tap is pushed towards the light by the plane's full slope, `z - |grad| |d|`.
    pub fn receiver_plane_depth(&self, d: Vec2) -> f32 {
        if self.facing {
            self.z + self.grad.dot(d)
        } else {
            self.z - self.grad.length() * d.length()
        }
    }
}

/// Largest `tan(theta)` the biases use (the light 84 degrees from the normal).
pub const MAX_TAN: f32 = 10.0;

/// Whether the light sample of map `m` lies above the tangent plane of a receiver at `p` with
/// normal `n`. Visibility v2 counts only such samples: a technique that averages light samples
/// leaves the others out of both the sum and the weights (the horizon is the lighting's job).
pub fn above_horizon(m: &MapParams, p: Vec3, n: Vec3) -> bool {
    let l = Vec4::from(m.light);
    let to_light = if l.w == 1.0 {
        l.truncate() - p
    } else {
        l.truncate()
    };
    n.dot(to_light) > 0.0
}

/// Smallest cosine [`sphere_spread`] takes: it widens a kernel at most `1/sqrt(0.05)` = 4.5
/// times (a cube face's receivers lie within 57 degrees of its axis: 1.36 times).
pub const SPHERE_SPREAD_MIN_COS: f32 = 0.05;

/// How much wider a sphere light's penumbra is, for a receiver whose direction from the light's
/// centre makes an angle with cosine `cos_theta` with a perspective view's axis, than the
/// penumbra of the disc facing along that axis that a map-space kernel models.
///
/// A sphere shows every receiver its whole silhouette disc, facing the receiver. The map's plane
/// stretches what a disc facing the receiver occludes by `1 / cos` along the direction away
/// from the axis and leaves it as it is across that direction, so the facing disc's kernel is
/// `cos` too narrow one way (a room lamp's shadows read `+10` to `+25`/255 too sharp 35 to 50
/// degrees off its cube faces' axes). A kernel of one size takes the one of the same area:
/// `1 / sqrt(cos)`, with `cos` held to `[SPHERE_SPREAD_MIN_COS, 1]` (NaN gives the lower end on
/// the CPU). 1 on the axis.
pub fn sphere_spread(cos_theta: f32) -> f32 {
    // `max` then `min`, as the WGSL does (`clamp` would keep a NaN).
    #[allow(clippy::manual_clamp)]
    let c = cos_theta.max(SPHERE_SPREAD_MIN_COS).min(1.0);
    1.0 / c.sqrt()
}

/// [`sphere_spread`] at a receiver `p` of the perspective map `m`, whose eye is the light's
/// centre (its centre view, or one of its cube faces); 1 for an orthographic map.
pub fn sphere_spread_at(m: &MapParams, p: Vec3) -> f32 {
    if m.ortho == 1 {
        return 1.0;
    }
    let to = p - Vec4::from(m.light).truncate();
    let d = to.length();
    if d <= 0.0 {
        return 1.0;
    }
    sphere_spread(m.linear_depth(p) / d)
}

/// `|cos|` and `tan` of the angle between a normal and the light, `tan` clamped to [`MAX_TAN`].
fn clamped_cos_tan(cos: f32) -> (f32, f32) {
    let c = cos.abs().max(1.0 / (1.0 + MAX_TAN * MAX_TAN).sqrt());
    (c, (1.0 - c * c).max(0.0).sqrt() / c)
}

/// Signed depth change per texel of the plane through `p` with normal `n`, linearised over one
/// `texel` (world size), clamped to `MAX_TAN * texel`; zero where the plane is seen edge-on.
fn plane_gradient(m: &MapParams, p: Vec3, n: Vec3, texel: f32) -> Vec2 {
    // The same tangents as `plane_gradient` in WGSL, so both backends round alike.
    let t1 = n
        .cross(if n.x.abs() > 0.9 { Vec3::Y } else { Vec3::X })
        .normalize();
    let t2 = n.cross(t1);
    let (Some(a), Some(b), Some(c)) = (
        m.project(p),
        m.project(p + t1 * texel),
        m.project(p + t2 * texel),
    ) else {
        return Vec2::ZERO;
    };
    let (u, v) = (b - a, c - a);
    let det = u.x * v.y - v.x * u.y;
    if det.abs() < 1e-6 {
        return Vec2::ZERO;
    }
    let g = Vec2::new(u.z * v.y - v.z * u.y, v.z * u.x - u.z * v.x) / det;
    g.clamp_length_max(MAX_TAN * texel)
}

/// The receiver `p` with unit normal `n` in map `m`, or `None` outside the map (lit).
pub fn shadow_coord(m: &MapParams, bias: &Bias, p: Vec3, n: Vec3) -> Option<ShadowCoord> {
    let z = m.linear_depth(p);
    let texel = m.texel_size(z);
    let l = Vec4::from(m.light);
    let to_light = if l.w == 1.0 {
        l.truncate() - p
    } else {
        l.truncate()
    };
    let cos = n.dot(to_light) / to_light.length().max(1e-30);
    let (c, tan) = clamped_cos_tan(cos);
    let slope = bias.slope * texel * tan;
    let p2 = p + n * (bias.normal_offset * texel);
    let cap = texel * (DEPTH_SPREAD * tan + bias.max_push);
    let a = m.project(p2)?;
    let resolution = m.resolution as f32;
    if a.x < 0.0 || a.y < 0.0 || a.x > resolution || a.y > resolution {
        return None;
    }
    let z2 = a.z;
    let terms = z2 - bias.depth * texel - slope;
    // The receiver's own plane where the map is read lies `normal_offset / c` texels beyond the
    // offset point. A receiver facing away from this light sample is in its own attached
    // shadow for it, which visibility v2 leaves to the lighting: no cap, the terms clear it.
    let z_biased = if cos > 0.0 {
        terms.max(z2 + bias.normal_offset * texel / c - cap)
    } else {
        terms
    };
    Some(ShadowCoord {
        st: a.truncate(),
        z: z_biased,
        grad: plane_gradient(m, p2, n, texel),
        z_receiver: z,
        facing: cos > 0.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::View;

    /// The disc a sphere shows a receiver `theta` off the axis, stretched by `1 / cos` one way
    /// on the map, has the area of the facing disc widened by `sphere_spread` both ways; on the
    /// axis nothing widens. A map's receiver: the cosine is taken from the light's centre.
    #[test]
    fn sphere_spread_keeps_the_stretched_discs_area() {
        for deg in [0.0f32, 20.0, 45.0, 54.7, 80.0] {
            let cos = deg.to_radians().cos();
            let s = sphere_spread(cos);
            assert!((s * s - 1.0 / cos).abs() < 1e-4 * s * s, "{deg}: {s}");
        }
        assert_eq!(sphere_spread(1.0), 1.0);
        assert_eq!(sphere_spread(-1.0), sphere_spread(SPHERE_SPREAD_MIN_COS));
        assert_eq!(
            sphere_spread(f32::NAN),
            sphere_spread(SPHERE_SPREAD_MIN_COS)
        );
        let eye = Vec3::new(1.0, 2.0, 3.0);
        let m = SampleView {
            view: View::perspective(
                eye,
                Vec3::NEG_Y,
                std::f32::consts::FRAC_PI_2,
                1.0,
                0.1,
                10.0,
            ),
            weight: 1.0,
            light: eye.extend(1.0),
            cell: [Vec2::ZERO; 2],
        }
        .params(64);
        let off = eye + Vec3::new(1.0, -1.0, 0.0);
        assert!((sphere_spread_at(&m, eye + Vec3::NEG_Y) - 1.0).abs() < 1e-5);
        assert!((sphere_spread_at(&m, off) - sphere_spread(0.5f32.sqrt())).abs() < 1e-4);
    }
}
