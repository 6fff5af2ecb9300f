//! Temporal stability (`flicker_255`): the light moves by small steps on `torus` and `overlap`,
//! and a technique's visibility should change from frame to frame no more than the reference's.
//!
//! Per receiver and pair of consecutive frames, the excess `max(0, |ΔV| - |ΔV_ref|)`; its mean
//! over receivers and pairs, times 255, is `flicker_255`. A technique whose shadow follows the
//! light exactly scores 0; shimmer from shadow-map texels snapping, from slices or from width
//! estimates jumping, adds to it. The reference is the same Monte Carlo estimator per frame
//! (deterministic per receiver), so its own noise difference lowers the score slightly rather
//! than raising it.

use crate::setup::PreparedScene;
use glam::Vec3;
use soft_shadow_core::{Context, DynTechnique, Light, Result};

/// Scenes on which the report measures flicker.
pub const SCENES: [&str; 2] = ["torus", "overlap"];

/// Frames per measurement in the full run (the light at its place, then `FRAMES - 1` steps).
pub const FRAMES: usize = 6;
/// Frames per measurement with `--quick`.
pub const QUICK_FRAMES: usize = 4;

/// Light step per frame, world units along +x: 1 cm, about two thirds of a texel of a 512² map
/// over these scenes, so texel snapping shows.
pub const STEP: f32 = 0.01;

/// The light of each of `frames` frames.
pub fn lights(light: &Light, frames: usize) -> Vec<Light> {
    (0..frames)
        .map(|k| light.translated(Vec3::X * STEP * k as f32))
        .collect()
}

/// The reference of each of `frames` frames, on the scene's receivers.
pub fn references(p: &PreparedScene, frames: usize) -> Vec<Vec<f32>> {
    lights(&p.spec.light, frames)
        .iter()
        .map(|l| p.reference_under(l))
        .collect()
}

/// Mean excess frame-to-frame change of `frames` over `references`, times 255 (see the module);
/// receivers unlit in either frame (NaN reference) are left out.
pub fn flicker_255(frames: &[Vec<f32>], references: &[Vec<f32>]) -> f64 {
    let (mut sum, mut n) = (0.0f64, 0u64);
    for (v, r) in frames.windows(2).zip(references.windows(2)) {
        for i in 0..v[0].len().min(r[0].len()) {
            let dv = (v[1][i] - v[0][i]).abs() as f64;
            let dr = (r[1][i] - r[0][i]).abs() as f64;
            if dv.is_finite() && dr.is_finite() {
                sum += (dv - dr).max(0.0);
                n += 1;
            }
        }
    }
    if n == 0 { 0.0 } else { 255.0 * sum / n as f64 }
}

/// Runs `t` over the frames of [`lights`] (as many as `references`) at `resolution` and scores
/// it against `references`.
pub fn measure(
    t: &dyn DynTechnique,
    ctx: Context<'_>,
    p: &PreparedScene,
    resolution: u32,
    references: &[Vec<f32>],
) -> Result<f64> {
    let frames = lights(&p.spec.light, references.len())
        .iter()
        .map(|l| {
            let maps = t.generate_in(ctx, &p.geometry, l, &p.views_for(l), resolution)?;
            maps.evaluate(ctx.gpu(), &p.receivers())
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(flicker_255(&frames, references))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn following_the_reference_exactly_scores_zero_and_noise_scores_its_excess() {
        let refs = vec![vec![0.0, 0.5], vec![0.1, 0.5], vec![0.2, 0.5]];
        assert_eq!(flicker_255(&refs, &refs), 0.0);
        // Receiver 1 toggles by 0.2 while the reference holds still; receiver 0 follows.
        let v = vec![vec![0.0, 0.5], vec![0.1, 0.7], vec![0.2, 0.5]];
        let expected = 255.0 * (0.2 + 0.2) / 4.0;
        assert!((flicker_255(&v, &refs) - expected).abs() < 1e-4);
    }
}
