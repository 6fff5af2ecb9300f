//! Ray-traced ground truth: per receiver, the visible fraction of the light by stratified Monte
//! Carlo shadow rays against the real triangles, through `obvhs`'s compressed wide BVH.
//!
//! Each receiver first gets a pilot of 8x8 stratified rays. When they all agree (fully lit or
//! umbra) that value is kept with a standard error of 0 (documented bias: a feature smaller than a
//! pilot stratum can be missed). Otherwise it gets `replicates` independent stratified estimates of
//! `strata` samples each; `V` is their mean and the standard error is their spread / sqrt(replicates),
//! an unbiased estimate of the stratified estimator's own error.

use glam::{Vec2, Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::Ray;
use obvhs::triangle::Triangle;
use rayon::prelude::*;
use shadow_core::{Light, LightPoint};
use std::time::Duration;

/// Sampling settings of the reference.
#[derive(Clone, Copy, Debug)]
pub struct GroundTruthSettings {
    /// Strata per side of one replicate (a segment light uses `strata_side²` strata along it).
    pub strata_side: u32,
    /// Independent replicates for receivers in penumbra.
    pub replicates: u32,
}

impl GroundTruthSettings {
    /// Samples per receiver in penumbra.
    pub fn samples_per_pixel(&self) -> u32 {
        self.strata_side * self.strata_side * self.replicates
    }
}

impl Default for GroundTruthSettings {
    fn default() -> Self {
        Self {
            strata_side: 32,
            replicates: 4,
        }
    }
}

/// Reference visibility of one receiver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reference {
    /// Visible fraction of the light.
    pub visibility: f32,
    /// Standard error of `visibility`.
    pub std_error: f32,
}

/// A BVH over the scene's shadow casters.
pub struct RayTracer {
    bvh: CwBvh,
    tris: Vec<Triangle>,
}

fn hash(mut x: u64) -> u64 {
    x ^= x >> 33;
    x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
    x ^= x >> 33;
    x = x.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    x ^ (x >> 33)
}

fn rand01(seed: u64) -> f32 {
    (hash(seed) >> 40) as f32 / (1u64 << 24) as f32
}

impl RayTracer {
    /// Builds the BVH over `casters` (degenerate triangles are kept: they never report a hit).
    pub fn new(casters: &[[Vec3; 3]]) -> Self {
        let tris: Vec<Triangle> = casters
            .iter()
            .map(|t| Triangle {
                v0: Vec3A::from(t[0]),
                v1: Vec3A::from(t[1]),
                v2: Vec3A::from(t[2]),
            })
            .collect();
        let bvh = build_cwbvh_from_tris(
            &tris,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        Self { bvh, tris }
    }

    /// True when the segment from `origin` along unit `dir` up to `t_max` hits no triangle.
    pub fn unoccluded(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> bool {
        if self.tris.is_empty() {
            return true;
        }
        let ray = Ray::new(Vec3A::from(origin), Vec3A::from(dir), t_min, t_max);
        self.bvh.ray_traverse_miss(ray, |r, id| {
            self.tris[self.bvh.primitive_indices[id] as usize].intersect(r)
        })
    }

    /// Whether `p` (offset along `n`) sees the light sample `q`.
    pub fn sees(&self, p: Vec3, n: Vec3, q: LightPoint) -> bool {
        let eps = 2e-5 * (p.abs().max_element() + 0.01);
        let o = p + n * eps;
        match q {
            LightPoint::Position(x) => {
                let d = x - o;
                let len = d.length();
                if len <= eps {
                    return true;
                }
                self.unoccluded(o, d / len, eps, len * (1.0 - 1e-5))
            }
            LightPoint::Direction(dir) => self.unoccluded(o, dir, eps, f32::INFINITY),
        }
    }

    fn estimate(&self, light: &Light, p: Vec3, n: Vec3, side: u32, seed: u64) -> f32 {
        let (mut sum_w, mut sum_v) = (0.0f64, 0.0f64);
        let count = side * side;
        for k in 0..count {
            let s = seed.wrapping_mul(0x9E37_79B9).wrapping_add(k as u64);
            let j = Vec2::new(
                rand01(s.wrapping_mul(2).wrapping_add(1)),
                rand01(s.wrapping_mul(2).wrapping_add(2)),
            );
            let u = if light.sample_dimension() == 1 {
                Vec2::new((k as f32 + j.x) / count as f32, 0.5)
            } else {
                Vec2::new(
                    ((k % side) as f32 + j.x) / side as f32,
                    ((k / side) as f32 + j.y) / side as f32,
                )
            };
            let (q, w) = light.sample(u, p);
            sum_w += w as f64;
            if self.sees(p, n, q) {
                sum_v += w as f64;
            }
        }
        if sum_w > 0.0 {
            (sum_v / sum_w) as f32
        } else {
            0.0
        }
    }

    /// Reference visibility of one receiver; `seed` decorrelates receivers.
    pub fn reference(
        &self,
        light: &Light,
        p: Vec3,
        n: Vec3,
        settings: &GroundTruthSettings,
        seed: u64,
    ) -> Reference {
        if light.sample_dimension() == 0 {
            let v = if self.sees(p, n, light.center()) {
                1.0
            } else {
                0.0
            };
            return Reference {
                visibility: v,
                std_error: 0.0,
            };
        }
        let pilot = self.estimate(light, p, n, 8, hash(seed ^ 0xA5A5));
        if pilot == 0.0 || pilot == 1.0 {
            return Reference {
                visibility: pilot,
                std_error: 0.0,
            };
        }
        let k = settings.replicates.max(2);
        let reps: Vec<f64> = (0..k)
            .map(|r| {
                self.estimate(
                    light,
                    p,
                    n,
                    settings.strata_side,
                    hash(seed.wrapping_mul(31).wrapping_add(r as u64 + 1)),
                ) as f64
            })
            .collect();
        let mean = reps.iter().sum::<f64>() / k as f64;
        let var =
            reps.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (k as f64 * (k as f64 - 1.0));
        Reference {
            visibility: mean.clamp(0.0, 1.0) as f32,
            std_error: var.sqrt() as f32,
        }
    }

    /// References for a batch of receivers, in parallel.
    pub fn references(
        &self,
        light: &Light,
        positions: &[Vec3],
        normals: &[Vec3],
        settings: &GroundTruthSettings,
    ) -> Vec<Reference> {
        positions
            .par_iter()
            .zip(normals.par_iter())
            .enumerate()
            .map(|(i, (p, n))| self.reference(light, *p, *n, settings, i as u64))
            .collect()
    }
}
