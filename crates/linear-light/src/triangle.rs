//! A triangle area light as three linear lights along its edges (section 4: "a really crude
//! approximation", since the transition under an area light is a quadratic rational function).
//!
//! The catalogue's light kinds have no triangle, so this is a separate entry point: one
//! [`LinearLight`] per edge, and `V` the average of the three edges' visibilities weighted by
//! edge length (each edge stands for the strip of the triangle it bounds).

use crate::cpu::{CpuLinearMaps, evaluate, generate};
use crate::params::LinearLight;
use glam::Vec3;
use shadow_core::{Receivers, Result, SceneGeometry, ShadowError, ShadowTechnique};

/// The maps of the three edges and their weights.
#[derive(Clone, Debug)]
pub struct TriangleMaps {
    /// One set of maps per edge.
    pub edges: Vec<CpuLinearMaps>,
    /// Edge lengths, normalised to sum to 1.
    pub weights: [f32; 3],
}

/// Builds the three edges' maps on the CPU for the triangle `vertices`.
pub fn generate_triangle(
    t: &LinearLight,
    geometry: &SceneGeometry,
    vertices: [Vec3; 3],
    resolution: u32,
) -> Result<TriangleMaps> {
    t.validate()?;
    if vertices.iter().any(|v| !v.is_finite()) {
        return Err(ShadowError::InvalidLight(
            "a triangle vertex is not finite".into(),
        ));
    }
    let normal = (vertices[1] - vertices[0]).cross(vertices[2] - vertices[0]);
    if normal.length() <= 0.0 || !normal.is_finite() {
        return Err(ShadowError::InvalidLight(
            "the triangle light has no area".into(),
        ));
    }
    let lens = [0, 1, 2].map(|k| (vertices[(k + 1) % 3] - vertices[k]).length());
    let total: f32 = lens.iter().sum();
    let mut edges = Vec::with_capacity(3);
    for k in 0..3 {
        let light = shadow_core::Light::Linear {
            a: vertices[k],
            b: vertices[(k + 1) % 3],
        };
        t.check_inputs(
            geometry,
            &light,
            resolution,
            shadow_core::technique::MAX_CPU_RESOLUTION,
        )?;
        let axis = light.axis(shadow_core::Coverage::new(geometry, &light).center());
        edges.push(generate(
            t,
            geometry,
            (vertices[k], vertices[(k + 1) % 3], axis),
            resolution,
        ));
    }
    Ok(TriangleMaps {
        edges,
        weights: lens.map(|l| l / total),
    })
}

/// `V` per receiver under the triangle light: the edge-length-weighted mean of the edges' `V`.
pub fn evaluate_triangle(
    t: &LinearLight,
    maps: &TriangleMaps,
    receivers: &Receivers,
) -> Result<Vec<f32>> {
    t.validate()?;
    receivers.validate()?;
    let mut v = vec![0.0f32; receivers.positions.len()];
    for (m, w) in maps.edges.iter().zip(maps.weights) {
        for (acc, e) in v.iter_mut().zip(evaluate(t, m, receivers)) {
            *acc += w * e;
        }
    }
    Ok(v.into_iter().map(|x| x.clamp(0.0, 1.0)).collect())
}
