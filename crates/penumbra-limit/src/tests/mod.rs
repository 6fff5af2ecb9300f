//! penumbra-limit against the paper's equations and closed forms (no GPU needed).

mod as_seen;
mod bunny;
mod depth_image;
mod feature_transform;
mod overlap;

use soft_shadow_core::CpuContext;
use soft_shadow_core::pool::Pool;
use std::sync::Arc;

/// A pool for one test's maps (nothing kept between calls).
fn pool() -> Arc<Pool> {
    Arc::new(Pool::new(0))
}

use crate::silhouette::edges;
use crate::storage::MAX_P;
use crate::table::IlluminationTable;
use crate::visibility::{clamped_visibility, clamped_visibility_piecewise};
use crate::{Generator, PenumbraLimit, Profile, Storage, Texel};
use glam::Vec3;
use proptest::prelude::*;
use soft_shadow_core::{
    Aabb, Bias, DistantProfile, Light, Receivers, SceneGeometry, ShadowTechnique,
};

/// `x` moved by `k` ulps (towards +inf for k > 0).
fn ulps(x: f32, k: i32) -> f32 {
    let mut v = x;
    for _ in 0..k.abs() {
        v = if k > 0 { v.next_up() } else { v.next_down() };
    }
    v
}

/// A receiver depth that is often exactly on, or one ulp beside, one of the limits.
fn depth_near(c: f32, g: f32, b: f32, pick: u8, off: i32, free: f32) -> f32 {
    match pick % 4 {
        0 => ulps(c, off),
        1 => ulps(g, off),
        2 => ulps(b, off),
        _ => free,
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    /// Equation 2 equals the piecewise `l_g` for every input, including `z = c`, `z = g`,
    /// `z = b` and one ulp either side of each.
    #[test]
    fn equation_2_equals_the_piecewise_form(c in 0.0f32..1.0, g in 0.0f32..1.0, b in 0.0f32..1.0,
                                            p in -MAX_P..MAX_P, pick: u8, off in -1i32..=1,
                                            free in 0.0f32..1.0) {
        let z = depth_near(c, g, b, pick, off, free);
        let eq2 = clamped_visibility(z, c, g, b, p);
        let cases = clamped_visibility_piecewise(z, c, g, b, p);
        prop_assert_eq!(eq2, cases, "z {} c {} g {} b {} p {}", z, c, g, b, p);
        prop_assert!(eq2.is_finite() && (0.0..=1.0).contains(&eq2));
    }

    /// Storage keeps every channel to its format's precision and is idempotent; f32 is exact.
    #[test]
    fn storage_round_trips(c in 0.0f32..1.0, g in 0.0f32..1.0, b in 0.0f32..1.0, p in -MAX_P..MAX_P) {
        let t = Texel { c, g, b, p };
        for s in Storage::ALL {
            let r = t.stored(s);
            let (depth_step, p_step) = match s {
                Storage::F32 => (0.0, 0.0),
                Storage::F16 => (1.0 / 2048.0, 4.0 / 2048.0),
                Storage::Rgba8 => (0.5 / 255.0, 2.0 / 255.0),
            };
            // A value on a rounding tie (0.6333333 * 255 = 161.5) rounds half a step away;
            // the difference itself is then computed with f32 rounding, hence the ulps.
            for (a, e) in [(r.c, c), (r.g, g), (r.b, b)] {
                prop_assert!((a - e).abs() <= depth_step + 2.0 * f32::EPSILON, "{s:?}: {e} -> {a}");
            }
            // p goes through p / 4 + 1/2 and back: exact for f32 up to two roundings.
            prop_assert!((r.p - p).abs() <= p_step + 4.0 * f32::EPSILON, "{s:?}: p {p} -> {}", r.p);
            prop_assert_eq!(r.stored(s), r, "{:?} is not idempotent", s);
        }
    }

    /// Storing a row in bulk (`Storage::store`, the CPU generation's path) gives the bits of
    /// storing each texel alone, out-of-range channels and subnormal f16 values included.
    #[test]
    fn bulk_storage_equals_per_texel(values in prop::collection::vec(
        (-0.5f32..1.5, -1e-5f32..1e-5, 0.0f32..1.0, -3.0f32..3.0), 1..40)) {
        let texels: Vec<Texel> = values.iter().map(|&(c, g, b, p)| Texel { c, g, b, p }).collect();
        for s in Storage::ALL {
            let mut bulk = texels.clone();
            s.store(&mut bulk, &mut Default::default());
            for (a, t) in bulk.iter().zip(&texels) {
                let e = t.stored(s);
                prop_assert_eq!(
                    [a.c, a.g, a.b, a.p].map(f32::to_bits),
                    [e.c, e.g, e.b, e.p].map(f32::to_bits),
                    "{:?} {:?}", s, t
                );
            }
        }
    }

    /// The table: monotone, odd-symmetric about (1/2, 1/2), endpoints 0 and 1, for any size.
    /// No fragment of a ribbon has a key below its `key_floor` (what lets the CPU rasterizer skip
    /// blocks whose keys are already at or below it): ends at any depths, texels anywhere, on
    /// either strip, including the ends themselves and points beyond them.
    #[test]
    fn no_fragment_key_is_below_the_ribbon_floor(
        ax in -50.0f32..50.0, ay in -50.0f32..50.0, bx in -50.0f32..50.0, by in -50.0f32..50.0,
        ca in 0.0f32..=1.0, cb in 0.0f32..=1.0, qx in -80.0f32..80.0, qy in -80.0f32..80.0,
        ppt in 0.0f32..0.05, end: bool, outer: bool,
    ) {
        use glam::Vec2;
        let r = crate::silhouette::Ribbon {
            a: Vec2::new(ax, ay),
            b: Vec2::new(bx, by),
            ca,
            cb,
            out: Vec2::Y,
            ha: 4.0,
            hb: 4.0,
            grad: Vec2::ZERO,
            same: 0.0,
        };
        let q = match (end, outer) {
            (true, true) => r.a,
            (true, false) => r.b,
            _ => Vec2::new(qx, qy),
        };
        let (key, _, _) = r.fragment(q, ppt, if outer { 1.0 } else { -1.0 });
        // A zero-length edge's fragments are NaN, which never win a texel either.
        prop_assert!(key.is_nan() || key >= r.key_floor(), "{key} below {}", r.key_floor());
        // Not vacuous: the floor is within a few ulps of the nearer end's key.
        prop_assert!(r.key_floor() >= ca.min(cb) * crate::silhouette::KEY_SCALE - 1e-5);
    }

    #[test]
    fn table_is_monotone_and_odd_symmetric(n in 2u32..2000, u in 0.0f32..=1.0, which: u8) {
        let profile = match which % 3 {
            0 => Profile::UniformDisk,
            1 => Profile::LimbDarkened { u },
            _ => Profile::Line,
        };
        let t = IlluminationTable::new(profile, n);
        let v = &t.values;
        prop_assert_eq!(v[0], 0.0);
        prop_assert_eq!(v[v.len() - 1], 1.0);
        for i in 0..v.len() {
            // f(l) + f(1 - l) = 1 to the rounding of one f32 subtraction.
            let sum = v[i] + v[v.len() - 1 - i];
            prop_assert!((sum - 1.0).abs() <= f32::EPSILON, "not odd-symmetric at {i}: {sum}");
            if i > 0 {
                prop_assert!(v[i] > v[i - 1], "not increasing at {i}: {} {}", v[i - 1], v[i]);
            }
        }
    }
}

/// Fraction of the unit disc with `x < t`, under emission `I(mu)`, by the midpoint rule over a
/// fine grid: an independent check of the closed forms.
fn disc_fraction(t: f64, emission: impl Fn(f64) -> f64) -> f64 {
    let n = 800;
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..n {
        for j in 0..n {
            let x = -1.0 + (i as f64 + 0.5) * 2.0 / n as f64;
            let y = -1.0 + (j as f64 + 0.5) * 2.0 / n as f64;
            let r2 = x * x + y * y;
            if r2 < 1.0 {
                let w = emission((1.0 - r2).sqrt());
                den += w;
                if x < t {
                    num += w;
                }
            }
        }
    }
    num / den
}

/// The closed forms of appendix A against numerical integration over the disc.
#[test]
fn table_profiles_match_numerical_integration() {
    let u = soft_shadow_core::light::SUN_LIMB_DARKENING_U as f64;
    for k in 0..=20 {
        let l = k as f64 / 20.0;
        let t = 2.0 * l - 1.0;
        let disk = Profile::UniformDisk.illumination(l);
        let limb = Profile::LimbDarkened { u: u as f32 }.illumination(l);
        let disk_n = disc_fraction(t, |_| 1.0);
        let limb_n = disc_fraction(t, |mu| 1.0 - u * (1.0 - mu));
        assert!(
            (disk - disk_n).abs() < 2e-3,
            "disk f({l}) = {disk}, numeric {disk_n}"
        );
        assert!(
            (limb - limb_n).abs() < 2e-3,
            "limb f({l}) = {limb}, numeric {limb_n}"
        );
        assert_eq!(Profile::Line.illumination(l), l);
        let table = IlluminationTable::new(Profile::UniformDisk, 512);
        assert!((table.lookup(l as f32) as f64 - disk).abs() < 1e-3);
    }
}

fn quad(x0: f32, x1: f32, y: f32, z: f32) -> [[Vec3; 3]; 2] {
    let p = |x: f32, zz: f32| Vec3::new(x, y, zz);
    [
        [p(x0, -z), p(x0, z), p(x1, z)],
        [p(x0, -z), p(x1, z), p(x1, -z)],
    ]
}

/// A plate covering `x < edge` at height `h` over a 4 x 4 ground, both casting.
fn plate_scene(edge: f32, h: f32) -> SceneGeometry {
    let casters: Vec<[Vec3; 3]> = quad(-2.0, 2.0, 0.0, 2.0)
        .into_iter()
        .chain(quad(-2.0, edge, h, 2.0))
        .collect();
    SceneGeometry {
        bounds: Aabb::of_triangles(&casters),
        receivers: quad(-2.0, 2.0, 0.0, 2.0).to_vec(),
        casters,
    }
}

/// Height of the receivers above the ground: a receiver exactly on a caster is lit or not by
/// rounding (that is what biases are for); 2 mm above it is unambiguous and enters the closed
/// form exactly.
const LIFT: f32 = 0.002;

/// Visibility just above the ground beside the plate's edge, and the closed form: the fraction
/// of the light disc (radius `R = (h - LIFT) tan(a/2)` on the plate's plane) beyond the edge,
/// the circular-segment area of appendix A at `t = (x - edge) / R`.
fn straight_edge(t: &PenumbraLimit, resolution: u32, edge: f32) -> Vec<(f32, f32, f32)> {
    plate_edge(t, resolution, edge, plate_scene(edge, 1.0), 1.0)
}

/// [`straight_edge`] for the plate at height `h` in `g`.
fn plate_edge(
    t: &PenumbraLimit,
    resolution: u32,
    edge: f32,
    g: SceneGeometry,
    h: f32,
) -> Vec<(f32, f32, f32)> {
    let a = 0.3f32;
    let light = Light::Distant {
        direction: Vec3::Y,
        angular_diameter: a,
        profile: DistantProfile::UniformDisk,
    };
    let maps = t
        .generate_cpu(&CpuContext::new(), &g, &light, resolution)
        .unwrap();
    let r = (h - LIFT) * (0.5 * a).tan();
    let xs: Vec<f32> = (-40..=40).map(|i| edge + i as f32 * 0.005).collect();
    let positions: Vec<Vec3> = xs.iter().map(|&x| Vec3::new(x, LIFT, 0.13)).collect();
    let normals = vec![Vec3::Y; positions.len()];
    let receivers = Receivers::new(&positions, &normals);
    let v = t.evaluate_cpu(&maps, &receivers).unwrap();
    xs.iter()
        .zip(v)
        .map(|(&x, v)| {
            let s = ((x - edge) / r).clamp(-1.0, 1.0) as f64;
            (
                x,
                v,
                Profile::UniformDisk.illumination((s + 1.0) * 0.5) as f32,
            )
        })
        .collect()
}

/// The straight edge of section 2, silhouette generator, f32: within 1/255 of the closed form at
/// every resolution from 16 to 512 (the map is exact under bilinear interpolation), with the
/// edge at an arbitrary sub-texel offset.
#[test]
fn straight_edge_matches_the_closed_form_at_every_resolution() {
    let mut t = PenumbraLimit::new(Generator::Silhouette);
    t.bias = Bias::new(0.0, 0.0, 0.0);
    for resolution in [16, 32, 64, 128, 256, 512] {
        for (x, v, e) in straight_edge(&t, resolution, 0.0371) {
            assert!(
                (v - e).abs() <= 1.0 / 255.0,
                "resolution {resolution} x {x}: V {v}, closed form {e}"
            );
        }
    }
}

/// A contact shadow: the plate 5 cm over a ground that only receives (so no map holds it, as
/// in Lawlor's Figure 10), silhouette generator, f32, no bias: within 1/255 of the closed form at
/// every resolution, although at 16² a texel (25 cm) is five times the plate's height. Before
/// outer texels beside the silhouette kept their upper limit `g` at `c` (`combine`), the
/// interpolated `g` lifted above these receivers and the shadow's edge moved inwards by up to a
/// texel.
#[test]
fn contact_edge_stays_on_the_edge_at_every_resolution() {
    let mut t = PenumbraLimit::new(Generator::Silhouette);
    t.bias = Bias::NONE;
    let h = 0.05;
    let edge = 0.0371;
    let plate: Vec<[Vec3; 3]> = quad(-2.0, edge, h, 2.0).to_vec();
    let ground = quad(-2.0, 2.0, 0.0, 2.0).to_vec();
    let all: Vec<[Vec3; 3]> = plate.iter().chain(&ground).copied().collect();
    let g = SceneGeometry {
        bounds: Aabb::of_triangles(&all),
        receivers: ground,
        casters: plate,
    };
    for resolution in [16, 32, 64, 128, 256, 512] {
        for (x, v, e) in plate_edge(&t, resolution, edge, g.clone(), h) {
            assert!(
                (v - e).abs() <= 1.0 / 255.0,
                "resolution {resolution} x {x}: V {v}, closed form {e}"
            );
        }
    }
}

/// The depth-image generator places the edge on the texel grid: its error is bounded by the
/// closed form's change over half a texel, and is exact when the edge lies on a texel boundary
/// (the plate spans the map's left half).
#[test]
fn depth_image_edge_is_within_half_a_texel() {
    let mut t = PenumbraLimit::new(Generator::DepthImage);
    t.bias = Bias::new(0.0, 0.0, 0.0);
    let r = (1.0 - LIFT) * (0.15f32).tan();
    for resolution in [16, 64, 256] {
        let texel = 4.0 / resolution as f32;
        for (x, v, e) in straight_edge(&t, resolution, 0.0) {
            assert!(
                (v - e).abs() <= 1.0 / 255.0,
                "aligned, resolution {resolution} x {x}: V {v}, closed form {e}"
            );
        }
        let edge = 0.0371;
        for (x, v, e) in straight_edge(&t, resolution, edge) {
            let f = |x: f32| {
                let s = ((x - edge) / r).clamp(-1.0, 1.0) as f64;
                Profile::UniformDisk.illumination((s + 1.0) * 0.5) as f32
            };
            let bound = (f(x + 0.5 * texel) - e)
                .abs()
                .max((f(x - 0.5 * texel) - e).abs())
                + 1.0 / 255.0;
            assert!(
                (v - e).abs() <= bound,
                "resolution {resolution} x {x}: V {v}, closed form {e}, bound {bound}"
            );
        }
    }
}

/// The depth-image seeds are the texels step 1 defines, by [`near_side`] texel by texel: a
/// near-side seed is on the near side of an edge towards some 4-neighbour, a far-side seed has a
/// 4-neighbour on the near side towards it. Random maps of 1 to 24 texels a side with empty
/// texels, plateaus and steps (edges at the borders and beside empty texels), on an orthographic
/// and a perspective warp.
#[test]
fn depth_image_seeds_are_the_near_side_tests() {
    use crate::depth_image::{near_side, seeds};
    use crate::warp::{NONE_DEPTH, Warp};
    use soft_shadow_core::Map2D;
    use soft_shadow_core::seeds::{NONE, pack};
    let warp = |ortho: u32| Warp {
        ortho,
        zeta_near: if ortho == 1 { 0.1 } else { -10.0 },
        zeta_scale: if ortho == 1 { 0.1 } else { 1.0 / 9.9 },
        unit: 0.01,
        rate: 1.0,
        p_per_texel: 0.01,
        far_norm: 1.0,
        spread: 1.0,
    };
    let mut rng = soft_shadow_core::rng::SplitMix(5);
    let mut next = |n: u64| rng.below(n);
    let mut seeded = (0, 0);
    for case in 0..3000 {
        let (w, h) = (1 + next(24) as u32, 1 + next(24) as u32);
        let levels = [NONE_DEPTH, 0.2, 0.2, 0.5, 0.9, 0.95];
        let data: Vec<f32> = (0..w * h)
            .map(|_| match next(4) {
                0 => levels[next(levels.len() as u64) as usize],
                _ => next(1000) as f32 / 1000.0,
            })
            .collect();
        let geom = Map2D::from_vec(w, h, data).expect("map");
        let (warp, gap) = (warp((case % 2) as u32), 1.0 + (case % 3) as f32);
        let (near, far) = seeds(&pool(), &geom, &warp, gap);
        const NEIGHBOURS: [(i64, i64); 4] = [(-1, 0), (1, 0), (0, -1), (0, 1)];
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                let a = NEIGHBOURS
                    .iter()
                    .any(|&d| near_side(&geom, &warp, gap, x, y, d));
                let b = NEIGHBOURS
                    .iter()
                    .any(|&d| near_side(&geom, &warp, gap, x + d.0, y + d.1, (-d.0, -d.1)));
                let me = pack(x as u32, y as u32);
                let i = (y * w as i64 + x) as usize;
                assert_eq!(
                    near[i],
                    if a { me } else { NONE },
                    "case {case} near ({x}, {y})"
                );
                assert_eq!(
                    far[i],
                    if b { me } else { NONE },
                    "case {case} far ({x}, {y})"
                );
                seeded.0 += a as usize;
                seeded.1 += b as usize;
            }
        }
    }
    assert!(seeded.0 > 1000 && seeded.1 > 1000, "{seeded:?} seeds");
}

/// Both generators, every storage format: far from the plate lit, under its middle umbra.
#[test]
fn lit_and_umbra_for_every_variant() {
    let g = plate_scene(0.0, 1.0);
    let light = Light::Distant {
        direction: Vec3::Y,
        angular_diameter: 0.3,
        profile: DistantProfile::LimbDarkenedSun,
    };
    let positions = [
        Vec3::new(1.5, 0.0, 0.0),
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
    ];
    let normals = [Vec3::Y; 3];
    for t in PenumbraLimit::standard_set() {
        let maps = t.generate_cpu(&CpuContext::new(), &g, &light, 64).unwrap();
        let v = t
            .evaluate_cpu(&maps, &Receivers::new(&positions, &normals))
            .unwrap();
        assert_eq!(v, vec![1.0, 0.0, 1.0], "{}", t.label());
    }
}

/// Edge extraction: a closed tetrahedron has 6 two-faced edges; an open triangle 3 borders.
#[test]
fn edges_of_closed_and_open_meshes() {
    let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
    let tet = vec![
        [p[0], p[2], p[1]],
        [p[0], p[1], p[3]],
        [p[0], p[3], p[2]],
        [p[1], p[2], p[3]],
    ];
    let e = edges(&tet);
    assert_eq!(e.len(), 6);
    assert!(e.iter().all(|e| e.o1[3] == 1.0));
    let e = edges(&tet[..1]);
    assert_eq!(e.len(), 3);
    assert!(e.iter().all(|e| e.o1[3] == 0.0));
    // Zero-area faces are skipped.
    assert!(edges(&[[p[0], p[0], p[1]]]).is_empty());
    // A mesh given twice (coincident blockers) has the edges of one copy, whatever vertex each
    // copy's triangles start from; the same triangle wound the other way is its back side.
    let twice: Vec<[Vec3; 3]> = tet
        .iter()
        .copied()
        .chain(tet.iter().map(|t| [t[1], t[2], t[0]]))
        .collect();
    assert_eq!(edges(&twice), edges(&tet));
    let sheet = [[p[0], p[1], p[2]], [p[0], p[1], p[2]], [p[2], p[1], p[0]]];
    let e = edges(&sheet);
    assert_eq!(e.len(), 3, "one edge per side of the two-sided sheet");
    assert!(e.iter().all(|e| e.o1[3] == 1.0 && e.n0 != e.n1));
}

/// Bad parameters and inputs get typed errors naming the problem, never a panic.
#[test]
fn bad_input_gets_typed_errors() {
    use soft_shadow_core::ShadowError;
    let g = plate_scene(0.0, 1.0);
    let sun = Light::Distant {
        direction: Vec3::Y,
        angular_diameter: 0.1,
        profile: DistantProfile::UniformDisk,
    };
    let mut t = PenumbraLimit::new(Generator::Silhouette);
    t.table_size = 1;
    assert!(
        matches!(t.generate_cpu(&CpuContext::new(), &g, &sun, 64), Err(ShadowError::InvalidParameter(m)) if m.contains("table_size"))
    );
    let mut t = PenumbraLimit::new(Generator::DepthImage);
    t.profile = Profile::LimbDarkened { u: f32::NAN };
    assert!(
        matches!(t.generate_cpu(&CpuContext::new(), &g, &sun, 64), Err(ShadowError::InvalidParameter(m)) if m.contains("limb"))
    );
    let mut t = PenumbraLimit::new(Generator::DepthImage);
    t.layer_gap = -1.0;
    assert!(
        matches!(t.generate_cpu(&CpuContext::new(), &g, &sun, 64), Err(ShadowError::InvalidParameter(m)) if m.contains("layer_gap"))
    );
    let t = PenumbraLimit::new(Generator::Silhouette);
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &g, &sun, 0),
        Err(ShadowError::InvalidResolution { requested: 0, .. })
    ));
    let segment = Light::Linear {
        a: Vec3::new(-1.0, 3.0, 0.0),
        b: Vec3::new(1.0, 3.0, 0.0),
    };
    assert!(matches!(
        t.generate_cpu(&CpuContext::new(), &g, &segment, 64),
        Err(ShadowError::UnsupportedLight { .. })
    ));
    let maps = t.generate_cpu(&CpuContext::new(), &g, &sun, 16).unwrap();
    let bad = Receivers::new(&[Vec3::NAN], &[Vec3::Y]);
    assert!(matches!(
        t.evaluate_cpu(&maps, &bad),
        Err(ShadowError::InvalidReceivers(_))
    ));
}

/// `lower_shadow`'s spiral is the Vogel spiral its docs give, and the shader holds the same
/// numbers, so that both backends read the same texels.
#[test]
fn the_lower_shadows_spiral_is_one_table_on_both_backends() {
    use crate::eval::{LOWER_SPIRAL, LOWER_TAPS};
    for (i, &[cos, sin, s]) in LOWER_SPIRAL.iter().enumerate() {
        let a = i as f32 * 2.399_963;
        assert_eq!([cos, sin], [a.cos(), a.sin()], "tap {i}");
        assert_eq!(s, ((i as f32 + 0.5) / LOWER_TAPS as f32).sqrt(), "tap {i}");
    }
    let wgsl = include_str!("../visibility.wgsl");
    let table = wgsl
        .split("array<vec3<f32>, 32>(")
        .nth(1)
        .and_then(|t| t.split(");").next())
        .expect("the shader's LOWER_SPIRAL");
    let shader: Vec<[f32; 3]> = table
        .split("vec3<f32>(")
        .skip(1)
        .map(|v| {
            let n: Vec<f32> = v
                .split(')')
                .next()
                .unwrap()
                .split(',')
                .map(|x| x.trim().parse().unwrap())
                .collect();
            [n[0], n[1], n[2]]
        })
        .collect();
    assert_eq!(shader, LOWER_SPIRAL.to_vec());
}

/// A covered texel's umbra (`p_i` at `-MAX_P`) stays umbra where a sphere's penumbra widens
/// (`Warp::spread_at`): the widening is held to `MAX_SPREAD`, below which `-MAX_P` over the
/// deepest gap a stored map holds (a caster at depth 0, a receiver at `DEPTH_SPAN`) still reads
/// no light. A receiver 78 degrees off a 160-degree map's axis spreads 2.19 times, and read
/// 0.013 of the light through the umbra without the cap.
#[test]
fn a_spheres_spread_leaves_the_umbra_dark() {
    use crate::eval::{EvalParams, shade};
    use crate::warp::{NONE_DEPTH, Warp};
    use glam::{Vec2, Vec4};
    use soft_shadow_core::light_space::sphere_spread;
    use soft_shadow_core::view::View;
    use soft_shadow_core::{Map2D, SampleView};
    let m = SampleView {
        view: View::perspective(Vec3::ZERO, Vec3::NEG_Z, 160f32.to_radians(), 1.0, 0.1, 10.0),
        weight: 1.0,
        light: Vec4::W,
        cell: [Vec2::ZERO; 2],
    }
    .params(8);
    let light = Light::Sphere {
        center: Vec3::ZERO,
        radius: 0.1,
    };
    let warp = Warp::new(&m, &light);
    let receiver = Vec3::new(9.9 * 78f32.to_radians().tan(), 0.0, -9.9);
    assert!(sphere_spread(78f32.to_radians().cos()) > 2.1);
    assert!(warp.spread_at(&m, receiver) > 2.0);
    // A caster nearer than the warp's near plane, stored as every map stores it: at 0.
    let c = warp.normalized(0.01);
    let umbra = Texel {
        c,
        g: c,
        b: NONE_DEPTH,
        p: -MAX_P,
    }
    .stored(Storage::F32);
    assert_eq!(umbra.c, 0.0);
    let map = Map2D::new(8, 8, umbra);
    let prm = EvalParams::new(m, Bias::NONE, warp, Storage::F32, 64);
    let table = IlluminationTable::new(Profile::UniformDisk, 64);
    let v = shade(&prm, &map, &table, receiver, -receiver.normalize());
    assert_eq!(v, 0.0, "umbra read {v}");
}

/// Two coplanar plates at height 1 that overlap (a caster made of parts): `A` covers `x < 0`,
/// `B` covers `-0.5 < x < 1.5` for `z < 0`. `A`'s edge at `x = 0` outlines it for `z > 0`; for
/// `z < 0` its outer ribbon lies over `B` on the plane of `A`'s top, where no light passes.
/// Under a 0.3 rad sun overhead, and leaning 15, 30 and 45 degrees towards `+x` and 15 and 30
/// towards `+z` (the plates then tilt against the map's plane), every ground receiver under
/// `B`'s shadow at least 0.5 m from its far edge is in umbra (`V` at most 1/255; under a
/// leaning sun, at most 0.5 within a texel of `A`'s edge's shadow), and beside `A`'s edge
/// where it outlines `A`, beyond its outer penumbra, lit (at least 254/255): both generators,
/// CPU and GPU, 16² to 512². Before outer ribbon fragments kept off a caster on their edge's
/// lit plane, the silhouette generator read up to 28, 34, 42 and 43 receivers lit (2 cm
/// apart, overhead and leaning in `x`; 16² to 32²), 2, 6, 11 and 18 at 512².
#[test]
fn an_outer_ribbon_over_a_coplanar_caster_leaves_its_umbra_dark() {
    let plate = |x0: f32, x1: f32, z0: f32, z1: f32| {
        let p = |x: f32, z: f32| Vec3::new(x, 1.0, z);
        [
            [p(x0, z0), p(x0, z1), p(x1, z1)],
            [p(x0, z0), p(x1, z1), p(x1, z0)],
        ]
    };
    let casters: Vec<[Vec3; 3]> = plate(-2.0, 0.0, -2.0, 2.0)
        .into_iter()
        .chain(plate(-0.5, 1.5, -2.0, 0.0))
        .collect();
    let g = SceneGeometry {
        bounds: Aabb::of_triangles(&casters),
        receivers: quad(-3.0, 2.0, 0.0, 2.0).to_vec(),
        casters,
    };
    let gpu = harness::testing::gpu_for_test(
        "an_outer_ribbon_over_a_coplanar_caster_leaves_its_umbra_dark",
    );
    // tan of the sun's lean towards +x and +z: the shadows move by as much towards -x and -z
    // on the ground (along `z` the edge's depth varies along it).
    for (lean, lean_z) in [
        (0.0f32, 0.0f32),
        (0.27, 0.0),
        (0.58, 0.0),
        (1.0, 0.0),
        (0.0, 0.27),
        (0.0, 0.58),
    ] {
        let light = Light::Distant {
            direction: Vec3::new(lean, 1.0, lean_z).normalize(),
            angular_diameter: 0.3,
            profile: DistantProfile::UniformDisk,
        };
        // Under `B`'s shadow, from beside `A`'s edge's shadow; then beside it where `A`'s edge
        // outlines `A` (`z = 0.5`), beyond its outer penumbra (0.15 m overhead, 0.30 at 45
        // degrees).
        let under = 50;
        let positions: Vec<Vec3> = (0..under)
            .map(|i| Vec3::new(0.02 - lean + i as f32 * 0.02, LIFT, -1.0))
            .chain((0..30).map(|i| Vec3::new(0.7 - lean + i as f32 * 0.02, LIFT, 0.5)))
            .collect();
        let normals = vec![Vec3::Y; positions.len()];
        let receivers = Receivers::new(&positions, &normals);
        for generator in [Generator::Silhouette, Generator::DepthImage] {
            let t = PenumbraLimit::new(generator);
            for resolution in [16, 32, 64, 128, 256, 512] {
                let maps = t
                    .generate_cpu(&CpuContext::new(), &g, &light, resolution)
                    .unwrap();
                let mut runs = vec![("cpu", t.evaluate_cpu(&maps, &receivers).unwrap())];
                if let Some(ctx) = &gpu {
                    let maps = t.generate_gpu(ctx, &g, &light, resolution).unwrap();
                    runs.push(("gpu", t.evaluate_gpu(ctx, &maps, &receivers).unwrap()));
                }
                for (backend, v) in runs {
                    let what =
                        format!("{generator:?} {backend} {resolution}², lean {lean}, {lean_z}");

                    let (dark, light) = v.split_at(under);
                    // Under a leaning sun, a texel of the map (the plates' 4 m over
                    // `resolution` texels) as it lands on the ground beside `A`'s edge's
                    // shadow: there the edge's own inner penumbra, interpolated, reads up to
                    // 0.44. Overhead, none.
                    let texel = if lean > 0.0 {
                        4.0 / resolution as f32 * (1.0 + lean * lean).sqrt()
                    } else {
                        0.0
                    };
                    let lit: Vec<(f32, f32)> = positions
                        .iter()
                        .zip(dark)
                        .filter(|(p, v)| **v > if p.x + lean < texel { 0.5 } else { 1.0 / 255.0 })
                        .map(|(p, v)| (p.x, *v))
                        .collect();
                    assert!(
                        lit.is_empty(),
                        "{what}: lit under the plate at (x, V) = {lit:?}"
                    );
                    let shaded: Vec<f32> = positions[under..]
                        .iter()
                        .zip(light)
                        .filter(|(_, v)| **v < 254.0 / 255.0)
                        .map(|(p, _)| p.x)
                        .collect();
                    assert!(
                        shaded.is_empty(),
                        "{what}: shaded beside the edge at x = {shaded:?}"
                    );
                }
            }
        }
    }
}

/// The silhouette generator's constants that `silhouette.wgsl` repeats are the Rust ones.
#[test]
fn the_ribbon_shader_constants_are_the_cpus() {
    use crate::silhouette::{MIN_FACE_TEXELS, OUTLINE_PROBE, SAME_DEPTH};
    let wgsl = include_str!("../silhouette.wgsl");
    for (name, value) in [
        ("MIN_FACE_TEXELS", MIN_FACE_TEXELS),
        ("OUTLINE_PROBE", OUTLINE_PROBE),
        ("SAME_DEPTH", SAME_DEPTH),
    ] {
        let shader: f32 = wgsl
            .split(&format!("const {name}: f32 = "))
            .nth(1)
            .and_then(|t| t.split(';').next())
            .and_then(|t| t.trim().parse().ok())
            .unwrap_or_else(|| panic!("the shader's {name}"));
        assert_eq!(shader, value, "{name}");
    }
}
