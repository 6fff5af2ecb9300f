//! Error metrics on the 0-255 scale, as the report contract defines them.

use serde::{Deserialize, Serialize};

/// Lower bound of the penumbra band of the reference (exclusive).
pub const PENUMBRA_LO: f32 = 0.02;
/// Upper bound of the penumbra band of the reference (exclusive).
pub const PENUMBRA_HI: f32 = 0.98;

/// Receivers whose normal is within this cosine of perpendicular to the direction to the
/// light's centre (about 17 degrees): the terminator band, where the light adds little to the
/// image while `V` changes fast.
pub const TERMINATOR_COS: f32 = 0.3;

/// Receivers nearer the camera than this (metres) are *near*: the shadows a person looks at
/// in a deep scene, which one map over everything in view makes coarse.
pub const NEAR_M: f32 = 15.0;
/// Receivers farther from the camera than this (metres) are *far*; between the two, *mid*.
pub const FAR_M: f32 = 60.0;

/// How each receiver counts in the image error and the per-class split: its shading weight and
/// what it lies on.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Shading {
    /// `E0 / E0_max` per receiver, in `[0, 1]`: the light's unshadowed irradiance
    /// ([`soft_shadow_reference::ground_truth::irradiance`]) over the scene's brightest receiver's.
    pub weight: Vec<f32>,
    /// Per receiver: it lies on a caster (an object), not on geometry that only receives (the
    /// ground).
    pub object: Vec<bool>,
    /// Per receiver: in the terminator band ([`TERMINATOR_COS`]).
    pub terminator: Vec<bool>,
    /// Per receiver: its distance from the camera (metres; empty: every receiver near).
    pub distance: Vec<f32>,
}

impl Shading {
    /// Weights from irradiances (`E0 / E0_max`; all 1 when no receiver is lit), with the classes.
    pub fn new(irradiance: &[f32], object: Vec<bool>, terminator: Vec<bool>) -> Self {
        let max = irradiance.iter().copied().fold(0.0f32, f32::max);
        let weight = if max > 0.0 && max.is_finite() {
            irradiance
                .iter()
                .map(|e| (e / max).clamp(0.0, 1.0))
                .collect()
        } else {
            vec![1.0; irradiance.len()]
        };
        Self {
            weight,
            object,
            terminator,
            distance: Vec::new(),
        }
    }

    /// The same with each receiver's distance from the camera (for the near / mid / far split).
    pub fn with_distance(self, distance: Vec<f32>) -> Self {
        Self { distance, ..self }
    }

    /// Every receiver at weight 1 on the ground, out of the terminator band: the image error
    /// then equals the `V` error.
    pub fn uniform(n: usize) -> Self {
        Self {
            weight: vec![1.0; n],
            object: vec![false; n],
            terminator: vec![false; n],
            distance: Vec::new(),
        }
    }
}

/// Errors of one class of receivers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ClassErrors {
    /// Receivers of the class.
    pub pixels: u64,
    /// RMS of `(V - V_ref) * 255` over them.
    pub rms_255: f64,
    /// RMS of `(V - V_ref) * E0 / E0_max * 255` over them.
    pub image_rms_255: f64,
}

/// The errors split by where the receiver lies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Classes {
    /// Receivers on geometry that only receives (grounds, walls).
    pub ground: ClassErrors,
    /// Receivers on casters (the objects themselves).
    pub object: ClassErrors,
    /// Receivers in the terminator band ([`TERMINATOR_COS`]), on either.
    pub terminator: ClassErrors,
    /// Receivers nearer the camera than [`NEAR_M`].
    pub near: ClassErrors,
    /// Receivers between [`NEAR_M`] and [`FAR_M`] from the camera.
    pub mid: ClassErrors,
    /// Receivers farther from the camera than [`FAR_M`].
    pub far: ClassErrors,
}

/// Errors of one run against the reference.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Errors {
    /// RMS of `(V - V_ref) * 255` over all receivers with finite `V`.
    pub rms_255: f64,
    /// The same over receivers whose reference is in (0.02, 0.98).
    pub penumbra_rms_255: f64,
    /// RMS of `(V - V_ref) * E0 / E0_max * 255`: the error a white Lambertian scene lit by the
    /// light shows, what the summary, the Pareto fronts and `Auto` rank by.
    pub image_rms_255: f64,
    /// The image error over receivers whose reference is in (0.02, 0.98).
    pub image_penumbra_rms_255: f64,
    /// Largest `|V - V_ref| * 255`.
    pub max_abs_255: f64,
    /// Count of NaN or infinite outputs (must be 0).
    pub nonfinite: u64,
    /// Count of finite outputs outside [0, 1] (must be 0).
    pub out_of_range: u64,
    /// Number of receivers in the penumbra band.
    pub penumbra_pixels: u64,
    /// Receivers the reference sees lit (`V_ref >= 0.98`) that come out below 0.98: false
    /// shadows, shadow acne on the `acne` scene.
    pub false_shadow_pixels: u64,
    /// The same errors by where the receivers lie.
    pub classes: Classes,
}

/// Running sums of one RMS pair (V and image).
#[derive(Clone, Copy, Default)]
struct Sums {
    n: u64,
    v: f64,
    image: f64,
}

impl Sums {
    fn add(&mut self, d: f64, w: f64) {
        self.n += 1;
        self.v += d * d;
        self.image += (d * w).powi(2);
    }
    fn rms(s: f64, n: u64) -> f64 {
        if n > 0 { (s / n as f64).sqrt() } else { 0.0 }
    }
    fn class(&self) -> ClassErrors {
        ClassErrors {
            pixels: self.n,
            rms_255: Self::rms(self.v, self.n),
            image_rms_255: Self::rms(self.image, self.n),
        }
    }
}

/// Compares `v` with `reference` (same length), each receiver weighted and classed by
/// `shading`. A NaN reference marks an unlit receiver (visibility v2): it takes no part in any
/// metric.
pub fn errors(v: &[f32], reference: &[f32], shading: &Shading) -> Errors {
    let mut e = Errors::default();
    let (mut all, mut pen, mut ground, mut object, mut terminator) = (
        Sums::default(),
        Sums::default(),
        Sums::default(),
        Sums::default(),
        Sums::default(),
    );
    let mut bands = [Sums::default(); 3];
    for (i, (&x, &r)) in v.iter().zip(reference).enumerate() {
        if r.is_nan() {
            continue;
        }
        if !x.is_finite() {
            e.nonfinite += 1;
            continue;
        }
        if !(0.0..=1.0).contains(&x) {
            e.out_of_range += 1;
        }
        let d = (x as f64 - r as f64) * 255.0;
        let w = shading.weight.get(i).copied().unwrap_or(1.0) as f64;
        all.add(d, w);
        e.max_abs_255 = e.max_abs_255.max(d.abs());
        if r > PENUMBRA_LO && r < PENUMBRA_HI {
            pen.add(d, w);
        }
        if shading.object.get(i).copied().unwrap_or(false) {
            object.add(d, w);
        } else {
            ground.add(d, w);
        }
        if shading.terminator.get(i).copied().unwrap_or(false) {
            terminator.add(d, w);
        }
        let far = shading.distance.get(i).copied().unwrap_or(0.0);
        bands[usize::from(far >= NEAR_M) + usize::from(far >= FAR_M)].add(d, w);
        if r >= PENUMBRA_HI && x < PENUMBRA_HI {
            e.false_shadow_pixels += 1;
        }
    }
    let (a, p) = (all.class(), pen.class());
    e.rms_255 = a.rms_255;
    e.image_rms_255 = a.image_rms_255;
    e.penumbra_rms_255 = p.rms_255;
    e.image_penumbra_rms_255 = p.image_rms_255;
    e.penumbra_pixels = p.pixels;
    e.classes = Classes {
        ground: ground.class(),
        object: object.class(),
        terminator: terminator.class(),
        near: bands[0].class(),
        mid: bands[1].class(),
        far: bands[2].class(),
    };
    e
}

/// RMS of `(a - b) * 255 * w` over the pairs where `b` is not NaN, `w` from `weights` (the
/// image error of [`Shading::weight`]).
pub fn image_rms_255(a: &[f32], b: &[f32], weights: &[f32]) -> f64 {
    let (s, n) = a
        .iter()
        .zip(b)
        .zip(weights)
        .filter(|((_, y), _)| !y.is_nan())
        .fold((0.0f64, 0usize), |(s, n), ((x, y), w)| {
            (
                s + ((*x as f64 - *y as f64) * 255.0 * *w as f64).powi(2),
                n + 1,
            )
        });
    if n == 0 { 0.0 } else { (s / n as f64).sqrt() }
}

/// RMS of `(a - b) * 255` over the pairs where `b` is not NaN (NaN: unlit).
pub fn rms_255(a: &[f32], b: &[f32]) -> f64 {
    let (s, n) = a
        .iter()
        .zip(b)
        .filter(|(_, y)| !y.is_nan())
        .fold((0.0f64, 0usize), |(s, n), (x, y)| {
            (s + ((*x as f64 - *y as f64) * 255.0).powi(2), n + 1)
        });
    if n == 0 { 0.0 } else { (s / n as f64).sqrt() }
}

/// Median of a non-empty slice (0 for an empty one).
pub fn median(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v = values.to_vec();
    v.sort_by(|a, b| a.total_cmp(b));
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}
