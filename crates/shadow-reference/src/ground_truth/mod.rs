//! Ray-traced ground truth (the library's visibility): per receiver, the emission-weighted
//! fraction of the light points that *reach* it ([`Light::reaches`]: above its tangent plane, on
//! the light's emitting side) which it sees unoccluded, by stratified Monte Carlo shadow rays
//! against the real triangles through `obvhs`'s BVHs. A receiver that no light point reaches is
//! *unlit* and has no reference.
//!
//! No receiver is settled by a test that can miss a feature without its error counted:
//!
//! - **Proven lit** ([`certify`]): when no caster triangle crosses the hull of the ray origin and
//!   the light's outline, `V = 1` exactly, error 0.
//! - Every other receiver gets `replicates` independent stratified estimates of `strata_side²`
//!   reaching samples (more strata where the horizon clips the light, up to 4x per side). `V` is
//!   the ratio of their pooled sums; its error is the jackknife standard error over replicates.
//!   Where every ray agreed (umbra, or lit without proof) the spread is 0 but a feature smaller
//!   than the sample spacing may be missed: the stated error is then the 99% upper bound on the
//!   missed fraction, [`agree_bound`] (0.29/255 at the default 4096 rays). A receiver that fewer
//!   than [`MIN_REACHING`] samples reach (a sliver of the light above its horizon) is sampled
//!   again with more strata, and no stated error exceeds [`MAX_STD_ERROR`].
//!
//! A receiver's rays share its origin, so they are traced together ([`packet`]): the casters near
//! the hull of the origin and the light are found once and binned by direction, and each ray
//! tests its bin with `obvhs`'s own triangle test, giving the answer the BVH gives ray by ray.

pub mod certify;
pub mod irradiance;
pub mod packet;

use certify::Hull;
use glam::{Vec2, Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::builder::build_bvh2_from_tris;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::Ray;
use obvhs::triangle::Triangle;
use packet::OriginRays;
use rayon::prelude::*;
use soft_shadow_core::{Light, LightPoint};
use std::time::Duration;

/// Sampling settings of the reference.
#[derive(Clone, Copy, Debug)]
pub struct GroundTruthSettings {
    /// Strata per side of one replicate (a segment light uses `strata_side²` strata along it).
    pub strata_side: u32,
    /// Independent replicates for every receiver not proven lit.
    pub replicates: u32,
    /// Shadow-ray origin offset along the normal, relative to the receiver's largest coordinate
    /// (plus 0.01): `2e-5`. Tests move it by 0.5x and 2x to show the reference does not depend on it.
    pub ray_offset: f32,
}

impl GroundTruthSettings {
    /// Samples per receiver not proven lit (before the horizon's extra strata).
    pub fn samples_per_pixel(&self) -> u32 {
        self.strata_side * self.strata_side * self.replicates
    }
}

impl Default for GroundTruthSettings {
    fn default() -> Self {
        Self {
            strata_side: 32,
            replicates: 4,
            ray_offset: 2e-5,
        }
    }
}

/// Reference visibility of one receiver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reference {
    /// Visible fraction of the reaching part of the light.
    pub visibility: f32,
    /// Error of `visibility`: 0 when proven lit, the jackknife standard error over replicates, or
    /// where every ray agreed the 99% bound on a missed feature (see the module).
    pub std_error: f32,
}

/// The 99% upper bound on the fraction of the light a receiver's `rays` all missed when every
/// one of them agreed: the `p` with `(1 - p)^rays = 0.01` (binomial; about `4.6 / rays`).
pub fn agree_bound(rays: u64) -> f64 {
    1.0 - 0.01f64.powf(1.0 / rays.max(1) as f64)
}

/// Reaching samples below which a receiver is sampled again with more strata.
pub const MIN_REACHING: u64 = 256;

/// Most strata per side, as a multiple of `strata_side`, for a receiver few samples reach.
const MAX_STRATA_FACTOR: u32 = 16;

/// The largest standard error a visibility in `[0, 1]` can have (a fair coin's).
pub const MAX_STD_ERROR: f64 = 0.5;

/// A BVH over the scene's shadow casters.
pub struct RayTracer {
    bvh: CwBvh,
    bvh2: Bvh2,
    tris: Vec<Triangle>,
    /// The casters' bounds (min, max), for the reach of a distant light's hull.
    bounds: (Vec3, Vec3),
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

/// The point at offset `j` (in `[0, 1)²`) of stratum `k` of `side²`: a cell of a `side x side`
/// grid, or of `side²` intervals along a segment light.
fn stratum(light: &Light, k: u32, side: u32, j: Vec2) -> Vec2 {
    if light.sample_dimension() == 1 {
        Vec2::new((k as f32 + j.x) / (side * side) as f32, 0.5)
    } else {
        Vec2::new(
            ((k % side) as f32 + j.x) / side as f32,
            ((k / side) as f32 + j.y) / side as f32,
        )
    }
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
        let params = BvhBuildParams::medium_build();
        let bvh2 = build_bvh2_from_tris(&tris, params, &mut Duration::default());
        let bvh = build_cwbvh_from_tris(&tris, params, &mut Duration::default());
        let bounds = casters.iter().flatten().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), v| (lo.min(*v), hi.max(*v)),
        );
        Self {
            bvh,
            bvh2,
            tris,
            bounds,
        }
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

    /// Whether `p` (offset along `n` by the default relative offset) sees the light sample `q`.
    pub fn sees(&self, p: Vec3, n: Vec3, q: LightPoint) -> bool {
        self.sees_with(p, n, q, GroundTruthSettings::default().ray_offset)
    }

    /// Ray origin of receiver `p`: offset along `n` by `offset` times its scale.
    fn origin(p: Vec3, n: Vec3, offset: f32) -> (Vec3, f32) {
        let eps = offset * (p.abs().max_element() + 0.01);
        (p + n * eps, eps)
    }

    /// Whether `p`, offset along `n` by `offset` (relative), sees the light sample `q`.
    pub fn sees_with(&self, p: Vec3, n: Vec3, q: LightPoint, offset: f32) -> bool {
        let (o, eps) = Self::origin(p, n, offset);
        Self::shadow_ray(o, eps, q).is_none_or(|(dir, t_max)| self.unoccluded(o, dir, eps, t_max))
    }

    /// The shadow ray from origin `o` (offset `eps`) to `q`: unit direction and `t_max`
    /// (`None` when `q` lies within `eps`: seen).
    fn shadow_ray(o: Vec3, eps: f32, q: LightPoint) -> Option<(Vec3, f32)> {
        match q {
            LightPoint::Position(x) => {
                let d = x - o;
                let len = d.length();
                (len > eps).then(|| (d / len, len * (1.0 - 1e-5)))
            }
            LightPoint::Direction(dir) => Some((dir, f32::INFINITY)),
        }
    }

    /// Whether no caster crosses the hull of `p`'s ray origin and the light's outline: then
    /// every light point is visible and `V = 1` exactly.
    pub fn proven_lit(&self, light: &Light, p: Vec3, n: Vec3, offset: f32) -> bool {
        self.tris.is_empty()
            || self
                .hull_points(light, p, n, offset)
                .is_some_and(|(o, points)| Hull::new(o, &points).clear_of(&self.bvh2, &self.tris))
    }

    /// `p`'s shadow rays, traced together ([`OriginRays`]), or `None` where the light's outline
    /// does not bound them (a distant light's cone too wide, a receiver inside a sphere light).
    pub fn origin_rays(&self, light: &Light, p: Vec3, n: Vec3, offset: f32) -> Option<OriginRays> {
        let (o, points) = self.hull_points(light, p, n, offset)?;
        let (_, eps) = Self::origin(p, n, offset);
        (points.len() >= 2).then(|| OriginRays::new(o, eps, &points, &self.bvh2, &self.tris))
    }

    /// `p`'s ray origin and the points whose hull with it holds every shadow ray of `p`: the
    /// light's outline, or for a distant light its directions carried beyond the casters (`None`
    /// when its cone is too wide to bound).
    fn hull_points(
        &self,
        light: &Light,
        p: Vec3,
        n: Vec3,
        offset: f32,
    ) -> Option<(Vec3, Vec<Vec3>)> {
        let (o, _) = Self::origin(p, n, offset);
        let outline = light.outline(p);
        let points: Vec<Vec3> = match outline[0] {
            LightPoint::Position(_) => outline
                .iter()
                .map(|q| match q {
                    LightPoint::Position(x) => *x,
                    LightPoint::Direction(d) => *d,
                })
                .collect(),
            LightPoint::Direction(_) => {
                // Far enough along every direction to leave the casters' bounds.
                let (lo, hi) = self.bounds;
                let reach = (lo - o).abs().max((hi - o).abs()).length() * 1.01 + 1.0;
                let dirs: Vec<Vec3> = outline
                    .iter()
                    .map(|q| match q {
                        LightPoint::Position(x) | LightPoint::Direction(x) => *x,
                    })
                    .collect();
                let axis = dirs.iter().copied().sum::<Vec3>().normalize_or_zero();
                let cos = dirs.iter().fold(1.0f32, |m, d| m.min(d.dot(axis)));
                if cos < 0.05 {
                    return None;
                }
                // Every vertex on one plane across the axis, at least `reach` from `o`.
                dirs.iter().map(|d| o + *d * (reach / cos)).collect()
            }
        };
        Some((o, points))
    }

    /// One stratified estimate over `side²` strata: (visible weight, reaching weight, reaching
    /// samples); `sees(q)` says whether `p` sees the light point `q`.
    fn estimate(
        light: &Light,
        p: Vec3,
        n: Vec3,
        side: u32,
        seed: u64,
        sees: impl Fn(LightPoint) -> bool,
    ) -> (f64, f64, u64) {
        let (mut sum_w, mut sum_v, mut count_reach) = (0.0f64, 0.0f64, 0u64);
        let count = side * side;
        for k in 0..count {
            let s = seed.wrapping_mul(0x9E37_79B9).wrapping_add(k as u64);
            let j = Vec2::new(
                rand01(s.wrapping_mul(2).wrapping_add(1)),
                rand01(s.wrapping_mul(2).wrapping_add(2)),
            );
            let (q, w) = light.sample(stratum(light, k, side, j), p);
            if !light.reaches(q, p, n) {
                continue;
            }
            sum_w += w as f64;
            count_reach += 1;
            if sees(q) {
                sum_v += w as f64;
            }
        }
        (sum_v, sum_w, count_reach)
    }

    /// Fraction of a 16x16 grid of light points that reach `p` (cheap: no rays).
    fn reach_fraction(light: &Light, p: Vec3, n: Vec3) -> f32 {
        let side = 16u32;
        let hits = (0..side * side)
            .filter(|&k| {
                let u = stratum(light, k, side, Vec2::splat(0.5));
                light.reaches(light.sample(u, p).0, p, n)
            })
            .count();
        hits as f32 / (side * side) as f32
    }

    /// Reference visibility of one receiver, or `None` when it is unlit (no light point reaches
    /// it, or the reaching sliver escapes every sample); `seed` decorrelates receivers.
    pub fn reference(
        &self,
        light: &Light,
        p: Vec3,
        n: Vec3,
        settings: &GroundTruthSettings,
        seed: u64,
    ) -> Option<Reference> {
        if !light.reaches_any(p, n) {
            return None;
        }
        let offset = settings.ray_offset;
        if light.sample_dimension() == 0 {
            let v = if self.sees_with(p, n, light.center(), offset) {
                1.0
            } else {
                0.0
            };
            return Some(Reference {
                visibility: v,
                std_error: 0.0,
            });
        }
        if self.proven_lit(light, p, n, offset) {
            return Some(Reference {
                visibility: 1.0,
                std_error: 0.0,
            });
        }
        self.monte_carlo(light, p, n, settings, seed)
    }

    /// The Monte Carlo estimate of one receiver that [`RayTracer::reference`] makes when the
    /// receiver is not proven lit (`None`: unlit); tests call it to recompute proven receivers too.
    pub fn estimate_unproven(
        &self,
        light: &Light,
        p: Vec3,
        n: Vec3,
        settings: &GroundTruthSettings,
        seed: u64,
    ) -> Option<Reference> {
        if light.reaches_any(p, n) {
            self.monte_carlo(light, p, n, settings, seed)
        } else {
            None
        }
    }

    /// The replicated stratified estimate of a receiver some light point reaches.
    fn monte_carlo(
        &self,
        light: &Light,
        p: Vec3,
        n: Vec3,
        settings: &GroundTruthSettings,
        seed: u64,
    ) -> Option<Reference> {
        let offset = settings.ray_offset;
        // Where the horizon clips the light, more strata keep the reaching samples near the target.
        let f = Self::reach_fraction(light, p, n).max(1.0 / 16.0);
        let side = ((settings.strata_side as f32 / f.sqrt()).ceil() as u32)
            .clamp(settings.strata_side, 4 * settings.strata_side);
        let k = settings.replicates.max(2);
        // Every answer is the one `sees_with` gives; traced together where the outline bounds
        // the rays.
        let rays = self.origin_rays(light, p, n, offset);
        let sees = |q: LightPoint| match &rays {
            Some(rays) => rays.sees(q),
            None => self.sees_with(p, n, q, offset),
        };
        let run = |side: u32| -> Vec<(f64, f64, u64)> {
            (0..k)
                .map(|r| {
                    let seed = hash(seed.wrapping_mul(31).wrapping_add(r as u64 + 1));
                    Self::estimate(light, p, n, side, seed, sees)
                })
                .collect()
        };
        let pooled = |reps: &[(f64, f64, u64)]| {
            reps.iter()
                .fold((0.0, 0.0, 0u64), |a, r| (a.0 + r.0, a.1 + r.1, a.2 + r.2))
        };
        let mut reps = run(side);
        let (_, _, first) = pooled(&reps);
        // Few reaching samples (a sliver of the light above the horizon): more strata, so the
        // stated error stays a statement about this receiver rather than about the sampler.
        if first > 0 && first < MIN_REACHING {
            let more = ((side as f64) * (MIN_REACHING as f64 / first as f64).sqrt()).ceil() as u32;
            reps = run(more.min(MAX_STRATA_FACTOR * settings.strata_side));
        }
        let (sv, sw, count) = pooled(&reps);
        if sw <= 0.0 || count == 0 {
            // Only a sliver of the light reaches, missed by every stratum: counted unlit.
            return None;
        }
        let mean = sv / sw;
        let std_error = if sv <= 0.0 || sv >= sw {
            agree_bound(count)
        } else {
            // Jackknife over replicates of the ratio estimator.
            let loo: Vec<f64> = reps
                .iter()
                .filter(|r| sw - r.1 > 0.0)
                .map(|r| (sv - r.0) / (sw - r.1))
                .collect();
            let jackknife = if loo.len() < 2 {
                MAX_STD_ERROR
            } else {
                let m = loo.len() as f64;
                let avg = loo.iter().sum::<f64>() / m;
                ((m - 1.0) / m * loo.iter().map(|x| (x - avg).powi(2)).sum::<f64>()).sqrt()
            };
            // Still few samples after resampling: four replicates say little about their own
            // spread, so the binomial error of that many independent draws bounds it from below.
            if count < MIN_REACHING {
                jackknife.max((mean * (1.0 - mean) / count as f64).sqrt())
            } else {
                jackknife
            }
        };
        Some(Reference {
            visibility: mean.clamp(0.0, 1.0) as f32,
            // No estimate of a V in [0, 1] is more uncertain than a fair coin.
            std_error: std_error.min(MAX_STD_ERROR) as f32,
        })
    }

    /// References for a batch of receivers, in parallel (`None`: unlit).
    pub fn references(
        &self,
        light: &Light,
        positions: &[Vec3],
        normals: &[Vec3],
        settings: &GroundTruthSettings,
    ) -> Vec<Option<Reference>> {
        positions
            .par_iter()
            .zip(normals.par_iter())
            .enumerate()
            .map(|(i, (p, n))| self.reference(light, *p, *n, settings, i as u64))
            .collect()
    }
}
