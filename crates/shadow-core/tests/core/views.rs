//! A light's views (`soft_shadow_core::views`): which views a plan chooses, how receivers pick
//! them, that a cascade's window moves by whole texels, and that no caster is left out.

use glam::{Vec3, Vec4};
use soft_shadow_core::view::ProjectionKind;
use soft_shadow_core::{
    Camera, Coverage, Light, LightPoint, LightViews, Region, SceneGeometry, SeenDepth, View,
};

/// An axis-aligned box's 12 triangles.
fn cuboid(center: Vec3, half: Vec3) -> Vec<[Vec3; 3]> {
    let c = |x: f32, y: f32, z: f32| center + half * Vec3::new(x, y, z);
    let p = [
        c(-1., -1., -1.),
        c(1., -1., -1.),
        c(1., 1., -1.),
        c(-1., 1., -1.),
        c(-1., -1., 1.),
        c(1., -1., 1.),
        c(1., 1., 1.),
        c(-1., 1., 1.),
    ];
    [
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [3, 6, 2],
        [3, 7, 6],
        [0, 4, 7],
        [0, 7, 3],
        [1, 2, 6],
        [1, 6, 5],
    ]
    .iter()
    .map(|t: &[usize; 3]| t.map(|i| p[i]))
    .collect()
}

/// A 6 m room's walls and ceiling (casters) around a floor (receiver), and four boxes around the
/// middle whose tops rise to 1.2 m: the casters surround a lamp at 0.75 m.
fn room() -> (SceneGeometry, Vec<Vec<[Vec3; 3]>>) {
    let shell: Vec<[Vec3; 3]> = cuboid(Vec3::new(0.0, 1.5, 0.0), Vec3::new(3.0, 1.5, 3.0))
        .into_iter()
        .filter(|t| t.iter().any(|v| v.y > 0.0))
        .collect();
    let floor: Vec<[Vec3; 3]> = cuboid(Vec3::new(0.0, 1.5, 0.0), Vec3::new(3.0, 1.5, 3.0))
        .into_iter()
        .filter(|t| t.iter().all(|v| v.y == 0.0))
        .collect();
    let mut instances = vec![shell];
    for (x, z) in [(1.5, 0.0), (-1.5, 0.0), (0.0, 1.5), (0.0, -1.5)] {
        instances.push(cuboid(Vec3::new(x, 0.6, z), Vec3::new(0.3, 0.6, 0.3)));
    }
    let casters = instances.concat();
    (SceneGeometry::new(casters, floor), instances)
}

fn lamp() -> Light {
    Light::Sphere {
        center: Vec3::new(0.0, 0.75, 0.0),
        radius: 0.12,
    }
}

/// Points on a sphere of radius `r` around `c` (a Fibonacci lattice).
fn around(c: Vec3, r: f32, n: usize) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let s = (1.0 - y * y).sqrt();
            let a = golden * i as f32;
            c + r * Vec3::new(s * a.cos(), y, s * a.sin())
        })
        .collect()
}

#[test]
fn a_lamp_among_its_casters_gets_the_faces_that_hold_them_and_a_lamp_above_one_view() {
    let (geometry, _) = room();
    let views = LightViews::plan(&lamp(), &geometry, None);
    assert_eq!(views.kind_name(), "cube");
    // Walls, ceiling and furniture on every side; below, within 45 degrees and the guard of
    // straight down, only the floor, which casts nothing.
    assert_eq!(views.len(), 5);
    for r in views.regions() {
        let Region::Face { axis, .. } = *r else {
            panic!("not a face: {r:?}");
        };
        assert_ne!(
            axis,
            Vec3::NEG_Y,
            "a face for the floor, which casts nothing"
        );
    }
    // Above a single box, one frustum holds it.
    let one = SceneGeometry::new(
        cuboid(Vec3::new(0.0, 1.0, 0.0), Vec3::splat(0.4)),
        Vec::new(),
    );
    let above = Light::Sphere {
        center: Vec3::new(0.0, 3.0, 0.0),
        radius: 0.2,
    };
    let views = LightViews::plan(&above, &one, None);
    assert_eq!(views.kind_name(), "single");
    assert_eq!(views.regions(), &[Region::Whole]);
    // Casters on one side only: the faces that hold them, not six.
    let side = SceneGeometry::new(
        cuboid(Vec3::new(0.5, 0.75, 0.0), Vec3::new(0.05, 2.0, 3.0)),
        Vec::new(),
    );
    let views = LightViews::plan(&lamp(), &side, None);
    assert_eq!(views.kind_name(), "cube");
    assert!(
        (1..6).contains(&views.len()),
        "{} faces for a wall on one side",
        views.len()
    );
}

#[test]
fn a_one_sided_light_gets_no_face_behind_it() {
    let (geometry, _) = room();
    let disk = Light::Disk {
        center: Vec3::new(0.0, 0.75, 0.0),
        normal: Vec3::NEG_Y,
        radius: 0.12,
    };
    let views = LightViews::plan(&disk, &geometry, None);
    assert_eq!(views.kind_name(), "cube");
    // The four sides: nothing casts straight below it, and nothing is lit above.
    assert_eq!(views.len(), 4);
    for r in views.regions() {
        let Region::Face { axis, .. } = *r else {
            panic!("not a face: {r:?}");
        };
        assert!(axis.dot(Vec3::NEG_Y) > -0.5, "a face looks behind the disk");
    }
}

#[test]
fn every_direction_takes_its_face_and_blends_at_seams() {
    let (geometry, _) = room();
    let c = Vec3::new(0.0, 0.75, 0.0);
    let views = LightViews::plan(&lamp(), &geometry, None);
    let b = soft_shadow_core::views::FACE_BLEND;
    let mut blended = 0;
    for p in around(c, 1.3, 2000) {
        let weights: Vec<f32> = (0..views.len()).map(|i| views.weight(i, p)).collect();
        let total = views.total_weight(p);
        assert!((weights.iter().sum::<f32>() - total).abs() < 1e-6, "{p}");
        assert!(
            weights.iter().all(|w| (0.0..=1.0).contains(w)),
            "{p}: {weights:?}"
        );
        // Below, the floor's face holds no caster: V is 1 there, from no view.
        let d = p - c;
        let side = d.x.abs().max(d.z.abs());
        if -d.y > side / (1.0 - b) {
            assert_eq!(total, 0.0, "{p}");
        } else if -d.y < side * (1.0 - b) {
            assert!((total - 1.0).abs() < 1e-6, "{p}: {total}");
        }
        // Away from every seam one face takes it whole; near one, two (three at a corner)
        // share it.
        let mut m = [d.x.abs(), d.y.abs(), d.z.abs()];
        m.sort_by(f32::total_cmp);
        if m[1] < m[2] * (1.0 - b) && total == 1.0 {
            assert!(weights.contains(&1.0), "{p}: {weights:?}");
        } else if m[1] > m[2] * (1.0 - 0.5 * b) && total == 1.0 {
            blended += 1;
            assert!(
                weights.iter().filter(|w| **w > 0.0).count() >= 2,
                "{p}: {weights:?}"
            );
        }
    }
    assert!(blended > 10, "{blended} directions near a seam");
    // On a seam, half and half.
    let seam = c + Vec3::new(1.0, 0.2, 1.0);
    let w: Vec<f32> = (0..views.len()).map(|i| views.weight(i, seam)).collect();
    assert_eq!(
        w.iter().filter(|w| (**w - 0.5).abs() < 1e-6).count(),
        2,
        "{w:?}"
    );
}

/// A camera at eye height looking down a 200 m street and the depth range it sees.
fn street() -> (SceneGeometry, SeenDepth) {
    let mut casters = Vec::new();
    for k in 0..10 {
        let z = -10.0 - 20.0 * k as f32;
        casters.extend(cuboid(Vec3::new(-8.0, 5.0, z), Vec3::new(3.0, 5.0, 3.0)));
        casters.extend(cuboid(Vec3::new(8.0, 5.0, z), Vec3::new(3.0, 5.0, 3.0)));
    }
    let ground = vec![
        [
            Vec3::new(-50.0, 0.0, 10.0),
            Vec3::new(50.0, 0.0, 10.0),
            Vec3::new(50.0, 0.0, -210.0),
        ],
        [
            Vec3::new(-50.0, 0.0, 10.0),
            Vec3::new(50.0, 0.0, -210.0),
            Vec3::new(-50.0, 0.0, -210.0),
        ],
    ];
    let camera = street_camera().view(256, 256);
    let seen = SeenDepth {
        camera,
        near: 2.5,
        far: 200.0,
    };
    (SceneGeometry::new(casters, ground), seen)
}

/// The street's camera at eye height, looking down it.
fn street_camera() -> Camera {
    Camera {
        eye: Vec3::new(0.0, 1.7, 0.0),
        target: Vec3::new(0.0, 1.0, -30.0),
        fov_y: 60f32.to_radians(),
        near: 0.1,
        far: 400.0,
    }
}

fn sun() -> Light {
    Light::Distant {
        direction: Vec3::new(0.5, 0.7, 0.3).normalize(),
        angular_diameter: 0.0093,
        profile: soft_shadow_core::DistantProfile::UniformDisk,
    }
}

#[test]
fn cascades_split_the_seen_depth_and_blend_continuously() {
    let (geometry, seen) = street();
    let views = LightViews::plan(&sun(), &geometry, Some(&seen));
    assert_eq!(views.kind_name(), "cascades");
    // 200 / 2.5 = 80: four cascades of at most a factor 4 each.
    assert_eq!(views.len(), 4);
    let select = views.gpu_select(0);
    let splits = &select.splits[..5];
    assert!((splits[0] - 2.5).abs() < 1e-4 && (splits[4] - 200.0).abs() < 1e-2);
    assert!(splits.windows(2).all(|w| w[0] < w[1]), "{splits:?}");
    // The first cascade holds the near field (under 15 m).
    assert!(splits[1] < 15.0, "{splits:?}");
    // Weights sum to 1 at every depth and change continuously, also across the blend bands.
    let depth_row = Vec4::from(select.depth_row);
    let forward = -seen.camera.view.row(2).truncate();
    let eye = Vec3::new(0.0, 1.7, 0.0);
    let mut last: Option<Vec<f32>> = None;
    let steps = 40000;
    for k in 0..=steps {
        let z = 2.5 + (200.0 - 2.5) * k as f32 / steps as f32;
        let p = eye + forward * z;
        assert!((depth_row.dot(p.extend(1.0)) - z).abs() < 1e-3 * z);
        let w: Vec<f32> = (0..views.len()).map(|i| views.weight(i, p)).collect();
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-5, "{z}: {w:?}");
        if let Some(l) = &last {
            let step = w
                .iter()
                .zip(l)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f32::max);
            assert!(step < 0.05, "a weight jumps by {step} at depth {z}");
        }
        last = Some(w);
    }
    // Without a camera, or over a shallow range, one view.
    assert_eq!(LightViews::plan(&sun(), &geometry, None).len(), 1);
    let shallow = SeenDepth {
        near: 10.0,
        far: 30.0,
        ..seen
    };
    assert_eq!(LightViews::plan(&sun(), &geometry, Some(&shallow)).len(), 1);
}

#[test]
fn a_cascade_window_moves_by_whole_texels() {
    let (geometry, _) = street();
    let light = sun();
    let res = 512;
    let fixed = Vec3::new(3.3, 0.0, -7.7);
    let mut fraction = None;
    for k in 0..20 {
        let region = Region::Cascade {
            center: Vec3::new(0.37 * k as f32, 0.0, -8.0 - 0.53 * k as f32),
            half_extent: 12.0,
            heights: [-1.0, 20.0],
        };
        let coverage = Coverage::new(&geometry, &light).within(region, res);
        let view = View::for_light_center(&light, &coverage);
        let ProjectionKind::Orthographic { half_extent } = view.kind else {
            panic!("a cascade is orthographic");
        };
        assert_eq!(half_extent, 12.0, "the window keeps its size");
        let (u, v, _) = view.project(fixed).expect("in front");
        let texels = glam::Vec2::new(u, v) * res as f32;
        let f = texels - texels.floor();
        match fraction {
            None => fraction = Some(f),
            Some(f0) => assert!(
                (f - f0).abs().max_element() < 2e-2,
                "a fixed point moved by a fraction of a texel: {f} against {f0}"
            ),
        }
    }
}

#[test]
fn every_caster_lies_in_a_view() {
    let (geometry, instances) = room();
    let light = lamp();
    let views = LightViews::plan(&light, &geometry, None);
    assert_eq!(views.uncovered(&light, &geometry, &instances, &[]), vec![]);
    // One frustum, clamped to 2 x 80 degrees, leaves casters out: what the room's lamp had.
    let single = LightViews::single();
    let missing = single.uncovered(&light, &geometry, &instances, &[]);
    assert!(
        missing.len() >= 4,
        "one frustum holds the room: {missing:?}"
    );
    // A distant light's cascades over the street hold every receiver the camera sees in the
    // window of the cascade it reads.
    let (geometry, seen) = street();
    let views = LightViews::plan(&sun(), &geometry, Some(&seen));
    let mut points = Vec::new();
    for i in 0..64 {
        for j in 0..64 {
            let (x, y) = ((i as f32 + 0.5) / 32.0 - 1.0, (j as f32 + 0.5) / 32.0 - 1.0);
            let dir = seen.camera.view.inverse().transform_vector3(Vec3::new(
                x * 30f32.to_radians().tan(),
                y * 30f32.to_radians().tan(),
                -1.0,
            ));
            if dir.y < -1e-3 {
                let t = -1.7 / dir.y;
                let p = Vec3::new(0.0, 1.7, 0.0) + dir * t;
                if p.z > -205.0 && seen.camera.linear_depth(p) <= 200.0 {
                    points.push(p);
                }
            }
        }
    }
    assert!(points.len() > 1000);
    let blocks: Vec<Vec<[Vec3; 3]>> = geometry.casters.chunks(12).map(|c| c.to_vec()).collect();
    assert_eq!(views.uncovered(&sun(), &geometry, &blocks, &points), vec![]);
    let _ = LightPoint::Direction(Vec3::Y);
}

/// Cascades planned for a camera that moved a little (its seen depths quantized) are served by
/// the maps of the first plan: the same split depths, windows on the same texels; a camera
/// 20 m down the street, a map side that puts the windows on other texels, or a cube plan of
/// another light are not.
#[test]
fn cascades_a_small_step_keeps_are_served_by_the_first_plan() {
    let (geometry, seen) = street();
    let at = |dz: f32, near: f32, far: f32| {
        let camera = Camera {
            eye: Vec3::new(0.0, 1.7, dz),
            target: Vec3::new(0.0, 1.0, dz - 30.0),
            fov_y: 60f32.to_radians(),
            near: 0.1,
            far: 400.0,
        }
        .view(256, 256);
        let seen = SeenDepth { camera, near, far }.quantized();
        LightViews::plan(&sun(), &geometry, Some(&seen))
    };
    // Maps made for `a` at side `r` serve `b` as they are.
    let serves = |a: &LightViews, b: &LightViews, r| a.moved(b, r).is_some_and(|m| m.is_empty());
    let first = at(0.0, seen.near, seen.far);
    assert_eq!(first.kind_name(), "cascades");
    // Seen depths that moved within a quantization step plan the same splits.
    let step = at(-0.001, seen.near * 1.0004, seen.far - 0.001);
    assert_ne!(first, step, "the windows' centres moved");
    assert!(serves(&first, &step, 1024));
    assert!(serves(&first, &first, 1024));
    let far_on = at(-20.0, seen.near, seen.far - 20.0);
    assert!(!serves(&first, &far_on, 1024));
    let (room, _) = room();
    let cube = LightViews::plan(&lamp(), &room, None);
    assert!(
        serves(&cube, &cube, 256) && !serves(&first, &cube, 256) && !serves(&cube, &first, 256)
    );
    // Quantized depths: near down and far up to whole steps of 2^(1/8), near not below the
    // camera's near plane.
    let q = seen.quantized();
    assert!(q.near <= seen.near && q.near > seen.near / 2f32.powf(0.125));
    assert!(q.far >= seen.far && q.far < seen.far * 2f32.powf(0.125));
    assert_eq!(q.quantized(), q);
}

/// A cube face's depth range starts just before the nearest caster it holds, as a distant
/// light's window does, so that an 8-bit or 16-bit map spends its steps on what casts: in the
/// room, from the lamp's centre and from points of the lamp 0.12 m off it, every caster point
/// inside a face's window lies at or beyond its near plane, and the nearest within 20% of it
/// (the faces are fitted around the lamp's 0.12 m radius, then 5% nearer).
/// With the range from the scene's box, which holds the lamp, every face started at 1e-5 of its
/// far plane.
#[test]
fn a_cube_face_starts_at_the_nearest_caster_it_holds() {
    let (geometry, _) = room();
    let light = lamp();
    let views = LightViews::plan(&light, &geometry, None);
    assert_eq!(views.kind_name(), "cube");
    // Points over every caster triangle (barycentric grid).
    let n = 60;
    let points: Vec<Vec3> = geometry
        .casters
        .iter()
        .flat_map(|t| {
            (0..=n).flat_map(move |i| {
                (0..=n - i).map(move |j| {
                    let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                    t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v
                })
            })
        })
        .collect();
    let centre = Vec3::new(0.0, 0.75, 0.0);
    for region in views.regions() {
        let Region::Face { axis, .. } = *region else {
            panic!("not a face: {region:?}");
        };
        let coverage = soft_shadow_core::technique::Generation {
            geometry: &geometry,
            light: &light,
            region: *region,
            resolution: 256,
        }
        .coverage();
        let offsets = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::Z,
            Vec3::NEG_Z,
        ];
        for offset in offsets.map(|d| d * 0.12) {
            let view = View::fit_light(LightPoint::Position(centre + offset), axis, &coverage);
            let nearest = points
                .iter()
                .filter_map(|&p| view.project(p))
                .filter(|&(x, y, z)| {
                    (0.0..=1.0).contains(&x) && (0.0..=1.0).contains(&y) && z > 0.0
                })
                .map(|(_, _, z)| z)
                .fold(f32::INFINITY, f32::min);
            assert!(nearest.is_finite(), "face {axis} holds no caster");
            assert!(
                view.near <= nearest && view.near >= 0.8 * nearest,
                "face {axis} from {offset}: near plane {} against the nearest caster at {nearest}",
                view.near
            );
        }
    }
}

/// The ground points the street's camera sees through a `side`² grid of its pixels (the blocks
/// left out: a ray meets the ground plane), what its G-buffer would hold there.
fn seen_ground(camera: &Camera, side: u32) -> Vec<Vec3> {
    let forward = (camera.target - camera.eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let t = (0.5 * camera.fov_y).tan();
    let mut points = Vec::new();
    for j in 0..side {
        for i in 0..side {
            let (x, y) = (
                (2.0 * (i as f32 + 0.5) / side as f32 - 1.0) * t,
                (1.0 - 2.0 * (j as f32 + 0.5) / side as f32) * t,
            );
            let d = forward + right * x + up * y;
            if d.y < 0.0 {
                let p = camera.eye + d * (-camera.eye.y / d.y);
                if p.x.abs() <= 50.0 && (-210.0..=10.0).contains(&p.z) {
                    points.push(p);
                }
            }
        }
    }
    points
}

/// Each cascade is fitted to the receivers the camera sees in its depth range (the
/// sample-distribution idea): its window and depth range hold every receiver that reads it,
/// and they span at
/// least 0.7 of it across the light (the rest: the penumbra's reach, the window's steps and
/// margin; measured 0.74-0.87), where a window fitted to the frustum's slice within the scene's
/// bounds (what `plan` fits without receivers) spans 0.52 of the nearest one.
#[test]
fn cascades_fit_the_receivers_the_camera_sees() {
    let (geometry, seen) = street();
    let receivers = seen_ground(&street_camera(), 96);
    let seen = SeenDepth::of_points(seen.camera, &receivers).unwrap();
    let light = sun();
    let fitted = LightViews::plan_seen(&light, &geometry, Some(&seen), &receivers);
    let slices = LightViews::plan(&light, &geometry, Some(&seen));
    assert_eq!(fitted.kind_name(), "cascades");
    assert_eq!(fitted.gpu_select(0).splits, slices.gpu_select(0).splits);
    let res = 1024;
    let spans = |views: &LightViews| -> Vec<f32> {
        (0..views.len())
            .map(|i| {
                let coverage = Coverage::new(&geometry, &light).within(views.regions()[i], res);
                let view = View::for_light_center(&light, &coverage);
                let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::NEG_INFINITY);
                for p in receivers.iter().filter(|p| views.weight(i, **p) > 0.0) {
                    let (u, v, z) = view.project(*p).unwrap();
                    assert!(
                        z >= view.near && z <= view.far,
                        "cascade {i}: a receiver at depth {z}, the map from {} to {}",
                        view.near,
                        view.far
                    );
                    let q = Vec3::new(u, v, z);
                    (lo, hi) = (lo.min(q), hi.max(q));
                }
                if views == &fitted {
                    assert!(
                        lo.x >= 0.0 && lo.y >= 0.0 && hi.x <= 1.0 && hi.y <= 1.0,
                        "cascade {i}: receivers at {lo} to {hi}"
                    );
                }
                (hi.x - lo.x).max(hi.y - lo.y)
            })
            .collect()
    };
    let (fit, slice) = (spans(&fitted), spans(&slices));
    println!("receivers span, fitted: {fit:.3?}; slices of the frustum: {slice:.3?}");
    assert!(fit.iter().all(|s| *s >= 0.7), "{fit:?}");
    assert!(slice[0] < 0.6, "{slice:?}");
}
