//! The depth-image generator on catalogue scenes.

/// The depth image's limits are step 3's of every texel's exact nearest seeds (the feature
/// transform, which its unit tests hold to the brute-force nearest seed; near-side ties to
/// the least depth), at every texel: the cut at [`ribbon_reach`] changes none.
/// On catalogue scenes at 256² (and `foliage` at 512²), every ribbon texel has both seeds
/// within the reach less one texel (the margin the cut keeps). Jump flooding, the generator's
/// propagation before, breaks ties between equidistant seeds of different depth its own way
/// and misses the nearest seed at rare texels: it fails here.
#[test]
fn depth_image_limits_come_from_the_nearest_seeds() {
    use crate::combine::NO_EDGE;
    use crate::depth_image::{limits, ribbon_reach, seeds, texel_limits};
    use crate::feature_transform::nearest;
    use crate::warp::Warp;
    use soft_shadow_core::raster::{DepthPass, depth_map_pass_then};
    use soft_shadow_core::seeds::dist2;
    use soft_shadow_core::{Coverage, SampleView};
    let layer_gap = crate::PenumbraLimit::new(crate::Generator::DepthImage).layer_gap;
    for (name, resolution) in [
        ("torus", 256),
        ("foliage", 512),
        ("overlap", 256),
        ("contact", 256),
        ("acne", 256),
        ("tiny-light", 256),
    ] {
        let spec = soft_shadow_reference::scenes::catalogue::build(name).unwrap();
        let geometry = spec.to_scene().unwrap().geometry();
        let view = SampleView::center(&spec.light, &Coverage::new(&geometry, &spec.light));
        let warp = Warp::new(&view.params(resolution), &spec.light);
        let geom = depth_map_pass_then(
            &std::sync::Arc::new(soft_shadow_core::pool::Pool::new(0)),
            &view.view,
            resolution,
            &geometry.casters,
            DepthPass::NEAREST,
            |z| warp.normalized(z),
        );
        let reach = ribbon_reach(&warp);
        assert!(
            reach < resolution / 2,
            "{name}: reach {reach} spans the map"
        );
        let (near, far) = seeds(
            &std::sync::Arc::new(soft_shadow_core::pool::Pool::new(0)),
            &geom,
            &warp,
            layer_gap,
        );
        let near = nearest(
            &std::sync::Arc::new(soft_shadow_core::pool::Pool::new(0)),
            near,
            resolution,
            Some(geom.data()),
        );
        let far = nearest(
            &std::sync::Arc::new(soft_shadow_core::pool::Pool::new(0)),
            far,
            resolution,
            None,
        );
        let (edge, lower) = limits(
            &std::sync::Arc::new(soft_shadow_core::pool::Pool::new(0)),
            &geom,
            &warp,
            layer_gap,
        );
        let mut ribbon = 0;
        for (i, (&a, &b)) in near.iter().zip(&far).enumerate() {
            let (x, y) = (i as u32 % resolution, i as u32 / resolution);
            let want = texel_limits(&geom, &warp, layer_gap, x, y, a, b);
            let got = (*edge.get(x, y), *lower.get(x, y));
            assert_eq!(got, want, "{name} ({x}, {y})");
            if want.0 != NO_EDGE {
                ribbon += 1;
                for seed in [a, b] {
                    let d = (dist2(x as i32, y as i32, seed) as f32).sqrt();
                    assert!(
                        d <= reach as f32 - 1.0,
                        "{name} ({x}, {y}): seed {d} texels away, reach {reach}"
                    );
                }
            }
        }
        assert!(ribbon > 0, "{name}: no ribbon");
    }
}
