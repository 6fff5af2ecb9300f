//! What a person sees: a scene's frame at a viewing resolution, and the artefacts a person sees in
//! it that an rms over a small G-buffer does not rank: false umbra (dark blotches and streaks
//! where the reference is lit) and leaks (light specks where it is in umbra).
//!
//! The frame is a [`PreparedScene`] with a `WIDTH` x `HEIGHT` G-buffer and a cheaper reference
//! ([`SETTINGS`]): an artefact here is a difference of more than 1/4 of the light, which a
//! reference within a few 1/255 of the truth decides.

use crate::metrics::{PENUMBRA_HI, PENUMBRA_LO};
use crate::setup::PreparedScene;
use soft_shadow_core::Result;
use soft_shadow_reference::ground_truth::GroundTruthSettings;
use soft_shadow_reference::scenes::SceneSpec;

/// Width of the viewing frame, pixels.
pub const WIDTH: u32 = 1280;
/// Height of the viewing frame, pixels.
pub const HEIGHT: u32 = 720;

/// The reference's sampling in a viewing frame: 8 x 8 strata, 2 replicates (128 shadow rays per
/// receiver not proven lit). Its standard error over a penumbra is 1.7-1.9/255 rms on the mesh
/// scenes (the full report's is below 1/255; the worst receiver's, where the horizon leaves few
/// rays, 9-128/255); an artefact counted here differs from it by 64/255.
pub const SETTINGS: GroundTruthSettings = GroundTruthSettings {
    strata_side: 8,
    replicates: 2,
    ray_offset: 2e-5,
};

/// How much darker (or lighter) than the reference a receiver must be to count as an artefact:
/// 1/4 of the light.
pub const ARTEFACT_STEP: f32 = 0.25;

/// Pixels around a receiver (a square of side `2 ISOLATION + 1`) in which the reference must have
/// no penumbra for a difference there to count as false umbra or a leak: a shadow edge drawn a
/// pixel or two off is an error the rms ranks, not an artefact.
pub const ISOLATION: i64 = 2;

/// Receivers the light lights at less than this fraction of the frame's brightest (grazing, or
/// far from a lamp) show no difference in `V` a person sees, and count in no artefact.
pub const LIT_WEIGHT: f32 = 0.1;

/// `spec`'s frame at the viewing resolution with its reference.
pub fn frame(spec: SceneSpec) -> Result<PreparedScene> {
    PreparedScene::sized(spec, WIDTH, HEIGHT, SETTINGS)
}

/// What a technique's `V` draws in a frame that the reference does not.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Artefacts {
    /// Receivers the reference sees at least half lit that are drawn at less than half of the
    /// reference's `V`: dark blotches, streaks and rings, wherever they are.
    pub darkened: usize,
    /// Receivers darker than the reference by more than [`ARTEFACT_STEP`] where the reference is
    /// lit all around them (no penumbra within [`ISOLATION`] pixels): false umbra.
    pub false_umbra: usize,
    /// Receivers lighter than the reference by more than [`ARTEFACT_STEP`] where the reference is
    /// umbra all around them: leaks.
    pub leaks: usize,
    /// The leaks on the casters' own surfaces (object pixels): light specks on a shadowed side,
    /// the receiver bias's failures.
    pub object_leaks: usize,
    /// Receivers in the frame (every one the light reaches, lit enough to count or not).
    pub receivers: usize,
}

impl Artefacts {
    /// `count` per million receivers of the frame.
    pub fn per_million(&self, count: usize) -> f64 {
        count as f64 * 1e6 / self.receivers.max(1) as f64
    }
}

/// The reference of `scene`'s frame around its receivers: whether every reference value within
/// [`ISOLATION`] pixels of a receiver satisfies a condition (pixels without a receiver, and
/// outside the frame, do).
pub struct Around {
    /// The reference over the frame, NaN where no receiver is.
    image: Vec<f32>,
    /// The frame's size.
    size: (i64, i64),
}

impl Around {
    /// `scene`'s reference, `reference` (one value per receiver), over its frame.
    pub fn new(scene: &PreparedScene, reference: &[f32]) -> Self {
        let (w, h) = (scene.gbuffer.width() as i64, scene.gbuffer.height() as i64);
        let mut image = vec![f32::NAN; (w * h) as usize];
        for (&i, &r) in scene.pixels.iter().zip(reference) {
            image[i] = r;
        }
        Self {
            image,
            size: (w, h),
        }
    }

    /// Whether every reference value within [`ISOLATION`] pixels of pixel `i` satisfies
    /// `keep`.
    pub fn all(&self, i: usize, keep: impl Fn(f32) -> bool) -> bool {
        let (w, h) = self.size;
        let (x, y) = (i as i64 % w, i as i64 / w);
        (y - ISOLATION..=y + ISOLATION).all(|yy| {
            (x - ISOLATION..=x + ISOLATION).all(|xx| {
                let r = if (0..w).contains(&xx) && (0..h).contains(&yy) {
                    self.image[(yy * w + xx) as usize]
                } else {
                    f32::NAN
                };
                r.is_nan() || keep(r)
            })
        })
    }
}

/// The artefacts of `v` (one value per receiver of `scene`) against the scene's reference.
pub fn artefacts(scene: &PreparedScene, v: &[f32]) -> Artefacts {
    let reference = scene.reference_v();
    let around = Around::new(scene, &reference);
    let mut a = Artefacts {
        receivers: v.len(),
        ..Default::default()
    };
    for (k, (&r, &got)) in reference.iter().zip(v).enumerate() {
        if scene.shading.weight[k] < LIT_WEIGHT {
            continue;
        }
        let i = scene.pixels[k];
        if r >= 0.5 && got < 0.5 * r {
            a.darkened += 1;
        }
        if got < r - ARTEFACT_STEP && around.all(i, |r| r >= PENUMBRA_HI) {
            a.false_umbra += 1;
        }
        if got > r + ARTEFACT_STEP && around.all(i, |r| r <= PENUMBRA_LO) {
            a.leaks += 1;
            if scene.shading.object[k] {
                a.object_leaks += 1;
            }
        }
    }
    a
}

/// `v` drawn over the frame at half its size (each tile pixel the top-left receiver of a 2 x 2
/// block): the shaded image `V E0 / E0_max` in grey as [`shaded`] encodes it, red where it is darker than the reference by
/// more than [`ARTEFACT_STEP`], blue where lighter; black where no receiver is. With `v` the
/// reference itself, the reference's shaded image.
pub fn picture(scene: &PreparedScene, v: &[f32]) -> image::RgbImage {
    let w = scene.gbuffer.width();
    let reference = scene.reference_v();
    let mut img = image::RgbImage::new(w.div_ceil(2), scene.gbuffer.height().div_ceil(2));
    for (k, &i) in scene.pixels.iter().enumerate() {
        let (x, y) = (i as u32 % w, i as u32 / w);
        if x % 2 != 0 || y % 2 != 0 {
            continue;
        }
        let d = v[k] - reference[k];
        let grey = srgb(v[k] * scene.shading.weight[k]);
        let px = if scene.shading.weight[k] >= LIT_WEIGHT && d < -ARTEFACT_STEP {
            [230, 30, 30]
        } else if scene.shading.weight[k] >= LIT_WEIGHT && d > ARTEFACT_STEP {
            [40, 80, 255]
        } else {
            [grey; 3]
        };
        img.put_pixel(x / 2, y / 2, image::Rgb(px));
    }
    img
}

/// FLIP (NVIDIA's perceptual difference between a render and its reference, LDR version, through
/// the `nv-flip` crate) of a technique's frame against the reference's: per pixel in [0, 1],
/// pooled over the frame's receivers (the pixels the light reaches; the background, equal in
/// both, would dilute it).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Flip {
    /// Mean over the receivers.
    pub mean: f32,
    /// 95th percentile over the receivers.
    pub p95: f32,
}

/// Pixels per degree of visual angle the frames are compared at: FLIP's default, a 0.7 m
/// viewing distance from a 24-inch 4K monitor.
pub const PIXELS_PER_DEGREE: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;

/// The 8-bit sRGB encoding of a linear value in [0, 1].
fn srgb(linear: f32) -> u8 {
    let l = linear.clamp(0.0, 1.0);
    let e = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (e * 255.0).round() as u8
}

/// The frame as a person sees it with `V = v` (one value per receiver): the light's shaded
/// image `V E0 / E0_max` (linear), sRGB-encoded, grey; black where no receiver is.
pub fn shaded(scene: &PreparedScene, v: &[f32]) -> image::RgbImage {
    let (w, h) = (scene.gbuffer.width(), scene.gbuffer.height());
    let mut img = image::RgbImage::new(w, h);
    for (k, &i) in scene.pixels.iter().enumerate() {
        let g = srgb(v[k] * scene.shading.weight[k]);
        img.put_pixel(i as u32 % w, i as u32 / w, image::Rgb([g; 3]));
    }
    img
}

/// FLIP of `v`'s shaded frame against the reference's, with its error map coloured (magma) at
/// the frame's size.
pub fn flip(scene: &PreparedScene, v: &[f32]) -> (Flip, image::RgbImage) {
    let image = |img: image::RgbImage| {
        nv_flip::FlipImageRgb8::with_data(img.width(), img.height(), img.as_raw())
    };
    let reference = image(shaded(scene, &scene.reference_v()));
    let test = image(shaded(scene, v));
    let error = nv_flip::flip(reference, test, PIXELS_PER_DEGREE);
    let all = error.to_vec();
    let mut at: Vec<f32> = scene.pixels.iter().map(|&i| all[i]).collect();
    let mean = at.iter().map(|&e| e as f64).sum::<f64>() / at.len().max(1) as f64;
    // Nearest rank: the smallest value at or above 95% of the receivers.
    let k = ((0.95 * at.len() as f64).ceil() as usize).saturating_sub(1);
    let p95 = if at.is_empty() {
        0.0
    } else {
        *at.select_nth_unstable_by(k, f32::total_cmp).1
    };
    let score = Flip {
        mean: mean as f32,
        p95,
    };
    let heat = error.apply_color_lut(&nv_flip::magma_lut());
    let heat =
        image::RgbImage::from_raw(heat.width(), heat.height(), heat.to_vec()).unwrap_or_default();
    (score, heat)
}
