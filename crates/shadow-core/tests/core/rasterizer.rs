//! The CPU rasterizer against closed forms: coverage rules and perspective-correct depth.

use crate::pool;
use glam::Vec3;
use soft_shadow_core::light::LightPoint;
use soft_shadow_core::raster::{
    DepthPass, depth_map, depth_map_filtered, depth_map_pass, depth_map_pass_then, gbuffer,
    rasterize, rasterize_nearest,
};
use soft_shadow_core::view::{NO_OCCLUDER, View};
use soft_shadow_core::{Aabb, Camera};

/// The light view from `light` along `axis` fitted to the box `min..max`.
fn fitted(light: LightPoint, axis: Vec3, min: Vec3, max: Vec3) -> View {
    View::fit_light(
        light,
        axis,
        &soft_shadow_core::Coverage::whole(&Aabb { min, max }),
    )
}

/// Two triangles sharing a diagonal cover a full-screen quad: with the top-left rule every pixel is
/// covered exactly once (no gap, no double coverage along the shared edge), whatever the diagonal.
#[test]
fn shared_edges_cover_each_pixel_once() {
    let (min, max) = (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, 1.0));
    let view = fitted(LightPoint::Direction(Vec3::Y), Vec3::NEG_Y, min, max);
    for (k, skew) in [0.0f32, 0.137, -0.31, 0.5].into_iter().enumerate() {
        // A fan of 6 triangles around an off-centre point: every edge is shared by two triangles.
        let c = Vec3::new(skew, 0.0, -skew * 0.7);
        let ring = [
            Vec3::new(-3.0, 0.0, -3.0),
            Vec3::new(0.3, 0.0, -3.0),
            Vec3::new(3.0, 0.0, -3.0),
            Vec3::new(3.0, 0.0, 3.0),
            Vec3::new(-0.2, 0.0, 3.0),
            Vec3::new(-3.0, 0.0, 3.0),
        ];
        let tris: Vec<[Vec3; 3]> = (0..6).map(|i| [c, ring[i], ring[(i + 1) % 6]]).collect();
        let mut counts = vec![0u32; 37 * 37];
        for t in &tris {
            let f = rasterize(&pool(), &view, 37, 37, std::slice::from_ref(t));
            for (i, frag) in f.data().iter().enumerate() {
                if frag.is_covered() {
                    counts[i] += 1;
                }
            }
        }
        assert!(
            counts.iter().all(|&c| c == 1),
            "case {k}: coverage counts {:?}",
            counts.iter().filter(|&&c| c != 1).count()
        );
    }
}

/// A tilted plane seen by a perspective view: every texel's depth equals the exact ray-plane
/// intersection depth through the texel centre (relative error 1e-5).
#[test]
fn perspective_depth_matches_ray_plane_intersection() {
    let eye = Vec3::new(0.3, 4.0, 0.2);
    let axis = Vec3::new(0.1, -1.0, 0.05).normalize();
    let normal = Vec3::new(0.3, 1.0, -0.2).normalize();
    let p0 = Vec3::new(0.0, 0.5, 0.0);
    // A large quad in the plane through p0 with that normal.
    let (t, b) = soft_shadow_core::light::orthonormal_basis(normal);
    let q = |s: f32, u: f32| p0 + t * s + b * u;
    let tris = vec![
        [q(-20., -20.), q(20., -20.), q(20., 20.)],
        [q(-20., -20.), q(20., 20.), q(-20., 20.)],
    ];
    let view = fitted(
        LightPoint::Position(eye),
        axis,
        Vec3::splat(-3.0),
        Vec3::new(3.0, 1.0, 3.0),
    );
    let res = 64;
    let map = depth_map(&pool(), &view, res, &tris);
    let inv = view.view_projection().inverse();
    let exact = |x: f32, y: f32| {
        let ndc = glam::Vec2::new(x / res as f32 * 2.0 - 1.0, 1.0 - y / res as f32 * 2.0);
        let far_pt = inv.project_point3(ndc.extend(0.5));
        let dir = (far_pt - eye).normalize();
        let tt = (p0 - eye).dot(normal) / dir.dot(normal);
        (tt, view.linear_depth(eye + dir * tt))
    };
    let mut checked = 0;
    for y in 0..res {
        for x in 0..res {
            let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
            let (tt, expect) = exact(cx, cy);
            // Vertices snap to 1/256 pixel as on a GPU, which moves the plane by at most the depth
            // gradient times 1/256 of a pixel; beyond that only f32 rounding (2e-6 relative) is allowed.
            let grad =
                (exact(cx + 1.0, cy).1 - expect).abs() + (exact(cx, cy + 1.0).1 - expect).abs();
            let tol = 2e-6 * expect + grad / 256.0;
            let got = *map.get(x, y);
            if tt > 0.0 && expect > view.near && expect < view.far {
                assert!(
                    (got - expect).abs() <= tol,
                    "texel ({x},{y}): {got} vs {expect} (tol {tol})"
                );
                checked += 1;
            }
        }
    }
    assert!(checked > res * res / 2, "only {checked} texels checked");
}

/// Orthographic depth of a tilted plane is affine in the texel centre: exact to 1e-5 of the range.
#[test]
fn orthographic_depth_matches_plane() {
    let dir = Vec3::new(0.2, 1.0, 0.1).normalize();
    let view = fitted(
        LightPoint::Direction(dir),
        -dir,
        Vec3::splat(-1.0),
        Vec3::ONE,
    );
    let normal = Vec3::new(0.1, 1.0, 0.3).normalize();
    let (t, b) = soft_shadow_core::light::orthonormal_basis(normal);
    let q = |s: f32, u: f32| t * s + b * u;
    let tris = vec![
        [q(-9., -9.), q(9., -9.), q(9., 9.)],
        [q(-9., -9.), q(9., 9.), q(-9., 9.)],
    ];
    let res = 48;
    let map = depth_map(&pool(), &view, res, &tris);
    let inv = view.view_projection().inverse();
    for y in 0..res {
        for x in 0..res {
            let ndc = glam::Vec2::new(
                (x as f32 + 0.5) / res as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / res as f32 * 2.0,
            );
            let o = inv.project_point3(ndc.extend(1.0));
            let tt = (-o).dot(normal) / (-dir).dot(normal);
            let expect = view.linear_depth(o - dir * tt);
            let got = *map.get(x, y);
            assert!(
                (got - expect).abs() <= 1e-5 * (view.far - view.near),
                "({x},{y}) {got} vs {expect}"
            );
        }
    }
}

/// A band's depths linearized in place equal `linear_depth` texel by texel, bit for bit, for both
/// projections and both depth tests (cleared values, the near and far planes, and between).
#[test]
fn linearize_is_linear_depth_per_texel() {
    use soft_shadow_core::raster::DepthPass;
    let dir = Vec3::new(0.2, 1.0, 0.1).normalize();
    let views = [LightPoint::Direction(dir), LightPoint::Position(dir * 4.0)]
        .map(|light| fitted(light, -dir, Vec3::splat(-1.0), Vec3::ONE));
    let mut z: Vec<f32> = (0..=1000).map(|i| i as f32 / 1000.0).collect();
    z.extend([-0.0, f32::MIN_POSITIVE, 1.0 - f32::EPSILON, 1.5, -1.0]);
    for view in &views {
        for pass in [DepthPass::NEAREST, DepthPass::FARTHEST] {
            let mut band = z.clone();
            pass.linearize(view, &mut band);
            for (&zi, &got) in z.iter().zip(&band) {
                let expect = pass.linear_depth(view, zi);
                assert_eq!(got.to_bits(), expect.to_bits(), "{pass:?} {view:?} z {zi}");
            }
        }
    }
}

/// Sparse small triangles, most of a map's columns beyond their boxes: the depth map holds
/// exactly the nearest fragment's linear depth per texel and [`NO_OCCLUDER`] elsewhere (the
/// fragment rasterizer's answer, whose depth and triangle [`rasterize_nearest`] gives alone),
/// [`depth_map_pass_then`] its function of them, and the farthest pass the same as a filtered
/// pass that accepts every fragment, bit for bit, at widths that end inside a 16-column block
/// and span several 64-block mask words.
#[test]
fn depth_maps_hold_the_fragments_beyond_the_triangles_boxes() {
    let dir = Vec3::new(0.2, 1.0, 0.1).normalize();
    let view = fitted(
        LightPoint::Direction(dir),
        -dir,
        Vec3::new(-1.0, 0.0, -1.0),
        Vec3::new(1.0, 1.0, 1.0),
    );
    let mut rng = soft_shadow_core::rng::SplitMix(3);
    let mut next = || rng.next_f32();
    let tris: Vec<[Vec3; 3]> = (0..40)
        .map(|_| {
            let c = Vec3::new(next() * 2.0 - 1.0, next(), next() * 2.0 - 1.0);
            let size = 0.002 + next() * 0.03;
            [0, 1, 2].map(|_| c + (Vec3::new(next(), next(), next()) - 0.5) * size)
        })
        .collect();
    for res in [37, 1100, 1201] {
        let near = depth_map_pass(&pool(), &view, res, &tris, DepthPass::NEAREST);
        let frags = rasterize(&pool(), &view, res, res, &tris);
        let nearest = rasterize_nearest(&pool(), &view, res, res, &tris);
        for (i, (n, f)) in nearest.data().iter().zip(frags.data()).enumerate() {
            assert_eq!(
                (n.z_ndc.to_bits(), n.triangle),
                (f.z_ndc.to_bits(), f.triangle),
                "{i}"
            );
        }
        let mut covered = 0;
        for (i, (z, f)) in near.data().iter().zip(frags.data()).enumerate() {
            let expect = if f.is_covered() {
                DepthPass::NEAREST.linear_depth(&view, f.z_ndc)
            } else {
                NO_OCCLUDER
            };
            assert_eq!(z.to_bits(), expect.to_bits(), "res {res} texel {i}");
            covered += f.is_covered() as usize;
        }
        // At 37² the small triangles may all fall between texel centres.
        assert!(
            (res < 100 || covered > 0) && covered < res as usize * res as usize / 4,
            "{covered}"
        );
        // The same map through a per-texel function, applied in the pass or after it.
        let then = |z: f32| (z.min(1e3) + 0.25).sqrt() * 3.0;
        let fused = depth_map_pass_then(&pool(), &view, res, &tris, DepthPass::NEAREST, then);
        for (i, (a, b)) in fused.data().iter().zip(near.data()).enumerate() {
            assert_eq!(a.to_bits(), then(*b).to_bits(), "res {res} texel {i}");
        }
        let far = depth_map_pass(&pool(), &view, res, &tris, DepthPass::FARTHEST);
        let filtered = depth_map_filtered(
            &pool(),
            &view,
            res,
            &tris,
            DepthPass::FARTHEST,
            |_, _, _| true,
            |z| z,
        );
        let filtered_then = depth_map_filtered(
            &pool(),
            &view,
            res,
            &tris,
            DepthPass::FARTHEST,
            |_, _, _| true,
            then,
        );
        for (i, (a, b)) in filtered_then.data().iter().zip(filtered.data()).enumerate() {
            assert_eq!(a.to_bits(), then(*b).to_bits(), "res {res} texel {i}");
        }
        for (i, (a, b)) in far.data().iter().zip(filtered.data()).enumerate() {
            assert_eq!(a.to_bits(), b.to_bits(), "res {res} texel {i}");
        }
    }
}

/// Empty texels hold the sentinel; a G-buffer pixel lies on the plane it shows, with the plane's normal.
#[test]
fn gbuffer_positions_lie_on_the_receiver() {
    let cam = Camera {
        eye: Vec3::new(0.0, 3.0, 3.0),
        target: Vec3::ZERO,
        fov_y: 0.9,
        near: 0.05,
        far: 50.0,
    };
    let tris = vec![[
        Vec3::new(-1., 0., -1.),
        Vec3::new(1., 0., -1.),
        Vec3::new(1., 0., 1.),
    ]];
    let gb = gbuffer(&pool(), &cam.view(40, 30), cam.eye, 40, 30, &tris);
    let covered: Vec<_> = gb.data().iter().filter(|t| t.covered).collect();
    assert!(covered.len() > 50);
    for t in covered {
        assert!(t.position.y.abs() < 1e-5, "{:?}", t.position);
        assert!(t.position.x >= -1.0 - 1e-4 && t.position.x <= 1.0 + 1e-4);
        assert!((t.normal - Vec3::Y).length() < 1e-6);
    }
    let dm = depth_map(&pool(), &cam.view(16, 16), 16, &[]);
    assert!(dm.data().iter().all(|&d| d == NO_OCCLUDER));
}
