//! Error metrics on the 0-255 scale, as the report contract defines them.

use serde::Serialize;

/// Lower bound of the penumbra band of the reference (exclusive).
pub const PENUMBRA_LO: f32 = 0.02;
/// Upper bound of the penumbra band of the reference (exclusive).
pub const PENUMBRA_HI: f32 = 0.98;

/// Errors of one run against the reference.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Errors {
    /// RMS of `(V - V_ref) * 255` over all receivers with finite `V`.
    pub rms_255: f64,
    /// The same over receivers whose reference is in (0.02, 0.98).
    pub penumbra_rms_255: f64,
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
}

/// Compares `v` with `reference` (same length). A NaN reference marks an unlit receiver
/// (visibility v2): it takes no part in any metric.
pub fn errors(v: &[f32], reference: &[f32]) -> Errors {
    let mut e = Errors::default();
    let (mut sum, mut n, mut psum, mut pn) = (0.0f64, 0u64, 0.0f64, 0u64);
    for (&x, &r) in v.iter().zip(reference) {
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
        sum += d * d;
        n += 1;
        e.max_abs_255 = e.max_abs_255.max(d.abs());
        if r > PENUMBRA_LO && r < PENUMBRA_HI {
            psum += d * d;
            pn += 1;
        }
        if r >= PENUMBRA_HI && x < PENUMBRA_HI {
            e.false_shadow_pixels += 1;
        }
    }
    e.rms_255 = if n > 0 { (sum / n as f64).sqrt() } else { 0.0 };
    e.penumbra_rms_255 = if pn > 0 {
        (psum / pn as f64).sqrt()
    } else {
        0.0
    };
    e.penumbra_pixels = pn;
    e
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
