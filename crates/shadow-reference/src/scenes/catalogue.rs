//! The built-in scenes of the catalogue.

use super::shapes::*;
use super::{MeshInstance, SceneSpec};
use glam::{Mat4, Vec2, Vec3};
use shadow_frame::gltf::import_gltf_slice;
use soft_shadow_core::{Aabb, Camera, DistantProfile, Light, Result, ShadowError, TriangleMesh};
use std::sync::Arc;

/// The Stanford bunny (69,451 triangles), from the repository's assets (empty in a build
/// outside a checkout: see the crate's docs).
#[cfg(repository_models)]
pub const BUNNY_GLB: &[u8] = include_bytes!(concat!(
    env!("SHADOW_REFERENCE_ASSETS"),
    "/stanford-bunny.glb"
));
/// The Utah teapot (6,320 triangles), from the repository's assets, likewise.
#[cfg(repository_models)]
pub const TEAPOT_GLB: &[u8] =
    include_bytes!(concat!(env!("SHADOW_REFERENCE_ASSETS"), "/teapot.glb"));
/// Suzanne (968 triangles), from the repository's assets, likewise.
#[cfg(repository_models)]
pub const SUZANNE_GLB: &[u8] =
    include_bytes!(concat!(env!("SHADOW_REFERENCE_ASSETS"), "/suzanne.glb"));
/// The Stanford bunny: not in this build (see the crate's docs).
#[cfg(not(repository_models))]
pub const BUNNY_GLB: &[u8] = &[];
/// The Utah teapot: not in this build (see the crate's docs).
#[cfg(not(repository_models))]
pub const TEAPOT_GLB: &[u8] = &[];
/// Suzanne: not in this build (see the crate's docs).
#[cfg(not(repository_models))]
pub const SUZANNE_GLB: &[u8] = &[];

/// Imports one of the catalogue's models, or says that this build has none.
fn import_model(glb: &[u8], name: &str) -> Result<TriangleMesh> {
    if glb.is_empty() {
        return Err(ShadowError::InvalidScene(format!(
            "{name}: the catalogue's models ship with the repository only (the Stanford \
             bunny's licence allows no redistribution); build soft-shadow-reference from a \
             checkout that has assets/"
        )));
    }
    import_gltf_slice(glb, name, None)
}

/// Every built-in scene name, in report order.
pub const SCENE_NAMES: [&str; 19] = [
    "plane-occluder",
    "skewed-triangle",
    "linear-bar",
    "triangle-light",
    "torus",
    "overlap",
    "foliage",
    "bunny",
    "contact",
    "grazing",
    "light-plane",
    "tiny-light",
    "huge-depth-range",
    "degenerate",
    "acne",
    "thin",
    "room-lamp",
    "room-lamp-corner",
    "street-sun",
];

/// Scenes built by name that the report measures only as seen (the harness's `as_seen`): meshes
/// users bring (flat facets, interpenetrating parts), which no paper's experiment holds.
pub const AS_SEEN_NAMES: [&str; 3] = ["low-poly-animal", "low-poly-rocks", "low-poly-sphere-light"];

/// Names of the catalogue's grounds: receivers only, since nothing lies below them to shadow
/// (light-space maps cover what casts, not what only receives).
pub const GROUNDS: [&str; 2] = ["ground", "graded-strip"];

fn inst(mesh: TriangleMesh) -> MeshInstance {
    MeshInstance {
        caster: !GROUNDS.contains(&mesh.name.as_str()),
        mesh: Arc::new(mesh),
        transform: Mat4::IDENTITY,
        receiver: true,
    }
}

fn camera(eye: Vec3, target: Vec3) -> Camera {
    Camera {
        eye,
        target,
        fov_y: 50f32.to_radians(),
        near: 0.05,
        far: 100.0,
    }
}

fn camera_fov(eye: Vec3, target: Vec3, fov_y_deg: f32) -> Camera {
    Camera {
        fov_y: fov_y_deg.to_radians(),
        ..camera(eye, target)
    }
}

fn rect_down(center: Vec3, half: f32) -> Light {
    Light::Rect {
        center,
        u_half: Vec3::X * half,
        v_half: Vec3::Z * half,
    }
}

fn spec(
    name: &str,
    description: &str,
    hard_case: bool,
    meshes: Vec<TriangleMesh>,
    light: Light,
    camera: Camera,
) -> SceneSpec {
    SceneSpec {
        name: name.into(),
        description: description.into(),
        hard_case,
        meshes: meshes.into_iter().map(inst).collect(),
        light,
        camera,
    }
}

fn default_camera() -> Camera {
    camera(Vec3::new(0.0, 4.5, 3.5), Vec3::new(0.0, 0.0, 0.0))
}

/// The square occluder parallel to a square light, the closed-form test case.
pub fn plane_occluder(light_half: f32) -> SceneSpec {
    spec(
        "plane-occluder",
        "square occluder parallel to a square light above the ground",
        false,
        vec![
            ground(8.0, 0.0, 1),
            horizontal_rect("occluder", Vec2::new(-0.5, 0.5), Vec2::new(-0.5, 0.5), 1.0),
        ],
        rect_down(Vec3::new(0.0, 2.5, 0.0), light_half),
        default_camera(),
    )
}

/// The bunny, scaled to 1.4 m and standing on the ground at the origin.
pub fn bunny_mesh() -> Result<TriangleMesh> {
    let mut m = import_model(BUNNY_GLB, "stanford-bunny.glb")?;
    let mut b = Aabb::EMPTY;
    for p in &m.positions {
        b.grow(*p);
    }
    let s = 1.4 / (b.max.y - b.min.y).max(1e-9);
    let offset = Vec3::new(-b.center().x, -b.min.y, -b.center().z);
    for p in &mut m.positions {
        *p = (*p + offset) * s;
    }
    m.name = "bunny".into();
    Ok(m)
}

/// A model of the assets, scaled to `height`, turned by `yaw` (radians, around +Y) and standing
/// on the ground (y = `floor`) centred on `(x, z)`, named `name`.
fn model(
    glb: &[u8],
    name: &str,
    height: f32,
    x: f32,
    z: f32,
    floor: f32,
    yaw: f32,
) -> Result<TriangleMesh> {
    let mut m = import_model(glb, name)?;
    let mut b = Aabb::EMPTY;
    for p in &m.positions {
        b.grow(*p);
    }
    let s = height / (b.max.y - b.min.y).max(1e-9);
    let offset = Vec3::new(-b.center().x, -b.min.y, -b.center().z);
    let turn = glam::Quat::from_rotation_y(yaw);
    for p in &mut m.positions {
        *p = turn * ((*p + offset) * s) + Vec3::new(x, floor, z);
    }
    m.name = name.into();
    Ok(m)
}

/// A closed room of side `side` and height `height` around the origin: its floor (a receiver
/// only), four walls and a ceiling, which cast; every face looks into the room.
fn room(side: f32, height: f32) -> Vec<TriangleMesh> {
    let h = 0.5 * side;
    let (x, y, z) = (Vec3::X * side, Vec3::Y * height, Vec3::Z * side);
    vec![
        ground(side, 0.0, 8),
        quad_grid("ceiling", Vec3::new(-h, height, -h), x, z, 4),
        quad_grid("wall-north", Vec3::new(-h, 0.0, -h), x, y, 4),
        quad_grid("wall-south", Vec3::new(-h, 0.0, h), y, x, 4),
        quad_grid("wall-west", Vec3::new(-h, 0.0, -h), y, z, 4),
        quad_grid("wall-east", Vec3::new(h, 0.0, -h), z, y, 4),
    ]
}

/// `room-lamp`'s room: a 6 m room, a sphere lamp at table height in its middle, four pieces of
/// furniture around it whose tops rise above the lamp (a teapot and Suzanne on two of them),
/// seen by `camera`.
fn room_lamp(name: &str, description: &str, camera: Camera) -> Result<SceneSpec> {
    let mut meshes = room(6.0, 3.0);
    meshes.extend([
        cuboid(
            "cabinet",
            Vec3::new(1.5, 0.6, 0.3),
            Vec3::new(0.3, 0.6, 0.5),
        ),
        cuboid(
            "shelf",
            Vec3::new(-0.4, 0.75, -1.6),
            Vec3::new(0.6, 0.75, 0.2),
        ),
        cuboid("desk", Vec3::new(-1.4, 0.5, 0.6), Vec3::new(0.35, 0.5, 0.6)),
        cuboid(
            "crate",
            Vec3::new(0.5, 0.45, 1.5),
            Vec3::new(0.3, 0.45, 0.3),
        ),
        model(TEAPOT_GLB, "teapot", 0.25, 1.5, 0.3, 1.2, 0.4)?,
        model(SUZANNE_GLB, "suzanne", 0.3, -1.4, 0.6, 1.0, 1.2)?,
    ]);
    Ok(spec(
        name,
        description,
        false,
        meshes,
        Light::Sphere {
            center: Vec3::new(0.0, 0.75, 0.0),
            radius: 0.12,
        },
        camera,
    ))
}

/// `street-sun`: 100 blocks on a 10 x 10 grid over 200 m along a street, Suzannes and teapots
/// on its pavements near the camera, under the real sun (0.0093 rad), seen at eye height down
/// the street.
fn street_sun() -> Result<SceneSpec> {
    let mut meshes = vec![ground(460.0, 0.0, 16)];
    let mut seed = 0x5eed_u64;
    let mut next = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 33) as f32) / (1u64 << 31) as f32
    };
    for i in 0..10 {
        for j in 0..10 {
            let x = -90.0 + 20.0 * i as f32;
            let z = -12.0 - 21.0 * j as f32;
            let half = Vec3::new(3.0 + 2.0 * next(), 3.0 + 12.0 * next(), 3.0 + 2.0 * next());
            meshes.push(cuboid(
                &format!("block-{i}-{j}"),
                Vec3::new(x, half.y, z),
                half,
            ));
        }
    }
    for (k, z) in [-3.0f32, -6.0, -9.5, -14.0].into_iter().enumerate() {
        let x = if k % 2 == 0 { -3.5 } else { 3.2 };
        meshes.push(if k % 2 == 0 {
            model(
                SUZANNE_GLB,
                &format!("suzanne-{k}"),
                1.2,
                x,
                z,
                0.0,
                0.7 * k as f32,
            )?
        } else {
            model(
                TEAPOT_GLB,
                &format!("teapot-{k}"),
                0.9,
                x,
                z,
                0.0,
                0.5 * k as f32,
            )?
        });
    }
    Ok(spec(
        "street-sun",
        "100 blocks over 200 m along a street and models near the camera, the real sun, an eye-height camera",
        false,
        meshes,
        Light::Distant {
            direction: Vec3::new(0.55, 0.62, 0.25).normalize(),
            angular_diameter: 0.0093,
            profile: DistantProfile::UniformDisk,
        },
        Camera {
            eye: Vec3::new(0.0, 1.7, 0.0),
            target: Vec3::new(0.0, 0.9, -30.0),
            fov_y: 60f32.to_radians(),
            near: 0.1,
            far: 400.0,
        },
    ))
}

/// Builds a catalogue scene by name.
pub fn build(name: &str) -> Result<SceneSpec> {
    let g = || ground(8.0, 0.0, 1);
    Ok(match name {
        "plane-occluder" => plane_occluder(0.4),
        "skewed-triangle" => {
            let tri = TriangleMesh {
                name: "skewed-triangle".into(),
                positions: vec![
                    Vec3::new(-1.0, 0.0, -0.8),
                    Vec3::new(1.1, 0.08, -0.6),
                    Vec3::new(0.1, 1.6, 1.0),
                ],
                indices: vec![[0, 1, 2]],
            };
            spec(
                name,
                "one tilted triangle: one corner touching, one slightly raised, one far up; distant disk light",
                false,
                vec![g(), tri],
                Light::Distant {
                    direction: Vec3::new(0.15, 1.0, 0.1).normalize(),
                    angular_diameter: 0.12,
                    profile: DistantProfile::UniformDisk,
                },
                default_camera(),
            )
        }
        "linear-bar" => spec(
            name,
            "a bar under a linear light perpendicular to it",
            false,
            vec![
                g(),
                cuboid("bar", Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.1, 0.1, 1.5)),
            ],
            Light::Linear {
                a: Vec3::new(-0.8, 3.0, 0.0),
                b: Vec3::new(0.8, 3.0, 0.0),
            },
            default_camera(),
        ),
        // Heidrich et al., section 4: a triangle light (linear-light models it as its three
        // edges). Counter-clockwise seen from below, so it emits downwards.
        "triangle-light" => spec(
            name,
            "a plate and a bar under a triangle light",
            false,
            vec![
                g(),
                horizontal_rect("plate", Vec2::new(-0.7, -0.1), Vec2::new(-0.6, 0.0), 0.9),
                cuboid("bar", Vec3::new(0.5, 0.5, 0.3), Vec3::new(0.08, 0.5, 0.6)),
            ],
            Light::Triangle {
                a: Vec3::new(-0.6, 3.0, 0.4),
                b: Vec3::new(0.0, 3.0, -0.6),
                c: Vec3::new(0.6, 3.0, 0.5),
            },
            default_camera(),
        ),
        "torus" => spec(
            name,
            "torus over the ground, sphere light",
            false,
            vec![g(), torus(Vec3::new(0.0, 1.2, 0.0), 0.8, 0.25, 48, 16)],
            Light::Sphere {
                center: Vec3::new(0.3, 3.5, 0.2),
                radius: 0.35,
            },
            default_camera(),
        ),
        "overlap" => spec(
            name,
            "three blockers at different heights whose penumbrae overlap",
            false,
            vec![
                g(),
                horizontal_rect("low", Vec2::new(-0.9, -0.1), Vec2::new(-0.5, 0.5), 0.6),
                horizontal_rect("mid", Vec2::new(-0.4, 0.5), Vec2::new(-0.8, 0.1), 1.3),
                horizontal_rect("high", Vec2::new(0.0, 0.9), Vec2::new(-0.2, 0.8), 2.0),
            ],
            rect_down(Vec3::new(0.0, 3.2, 0.0), 0.5),
            default_camera(),
        ),
        "foliage" => spec(
            name,
            "3000 small random quads over the ground",
            false,
            vec![
                g(),
                random_quads(
                    3000,
                    Vec3::new(-1.5, 1.0, -1.5),
                    Vec3::new(1.5, 2.0, 1.5),
                    0.08,
                    7,
                ),
            ],
            rect_down(Vec3::new(0.0, 4.0, 0.0), 0.6),
            default_camera(),
        ),
        "bunny" => spec(
            name,
            "the Stanford bunny (69,451 triangles) under a disk light",
            false,
            vec![g(), bunny_mesh()?],
            Light::Disk {
                center: Vec3::new(0.5, 3.5, 0.5),
                normal: Vec3::NEG_Y,
                radius: 0.4,
            },
            camera(Vec3::new(0.0, 3.0, 3.5), Vec3::new(0.0, 0.5, 0.0)),
        ),
        "contact" => spec(
            name,
            "a box resting on the receiver: the shadow starts at the contact line",
            true,
            vec![
                g(),
                cuboid("box", Vec3::new(0.0, 0.4, 0.0), Vec3::splat(0.4)),
            ],
            rect_down(Vec3::new(0.8, 3.0, 0.0), 0.4),
            default_camera(),
        ),
        "grazing" => spec(
            name,
            "a post lit by a rect light 5.7 degrees above the horizon",
            true,
            vec![
                g(),
                cuboid("post", Vec3::new(0.0, 0.5, 0.0), Vec3::new(0.1, 0.5, 0.1)),
            ],
            Light::Rect {
                center: Vec3::new(6.0, 0.6, 0.0),
                u_half: Vec3::Z * 0.3,
                v_half: Vec3::Y * 0.3,
            },
            default_camera(),
        ),
        "light-plane" => spec(
            name,
            "a wall that crosses the plane of the light",
            true,
            vec![
                g(),
                quad_grid(
                    "wall",
                    Vec3::new(1.5, 0.0, -2.0),
                    Vec3::Z * 4.0,
                    Vec3::Y * 4.0,
                    1,
                ),
                horizontal_rect("occluder", Vec2::new(0.3, 1.0), Vec2::new(-0.4, 0.4), 1.2),
            ],
            rect_down(Vec3::new(0.0, 2.5, 0.0), 0.4),
            camera(Vec3::new(-3.0, 3.5, 3.5), Vec3::new(0.8, 1.0, 0.0)),
        ),
        "tiny-light" => {
            let mut s = plane_occluder(1e-4);
            s.name = name.into();
            s.description =
                "plane-occluder with a 0.2 mm light: every technique must give the hard shadow"
                    .into();
            s.hard_case = true;
            s
        }
        "huge-depth-range" => spec(
            name,
            "geometry from 1e-3 to 1e4 m from the camera: a 2 cm box near, a 200 m box far",
            true,
            vec![
                graded_strip(400.0, 1.0e4, 0.02, 64),
                cuboid("near-box", Vec3::new(0.0, 0.01, -0.15), Vec3::splat(0.01)),
                cuboid(
                    "far-box",
                    Vec3::new(0.0, 100.0, -5000.0),
                    Vec3::splat(100.0),
                ),
            ],
            Light::Distant {
                direction: Vec3::new(0.5, 1.0, 0.3).normalize(),
                angular_diameter: 0.05,
                profile: DistantProfile::UniformDisk,
            },
            Camera {
                eye: Vec3::new(0.0, 0.03, 0.0),
                target: Vec3::new(0.0, 0.0, -1.0),
                fov_y: 60f32.to_radians(),
                near: 1e-3,
                far: 1e4,
            },
        ),
        "degenerate" => {
            let junk = TriangleMesh {
                name: "degenerate".into(),
                positions: vec![
                    Vec3::new(-0.5, 1.0, 0.0),
                    Vec3::new(0.0, 1.0, 0.0),
                    Vec3::new(0.5, 1.0, 0.0),
                    Vec3::new(0.2, 0.7, 0.2),
                    Vec3::new(-0.6, 0.9, -0.6),
                    Vec3::new(0.1, 0.9, -0.6),
                    Vec3::new(0.1, 0.9, 0.1),
                ],
                // collinear, a point, and a duplicated triangle
                indices: vec![[0, 1, 2], [3, 3, 3], [4, 5, 6], [4, 5, 6], [6, 5, 4]],
            };
            spec(
                name,
                "zero-area and duplicate triangles, two coincident blockers",
                true,
                vec![
                    g(),
                    junk,
                    horizontal_rect("blocker-a", Vec2::new(0.0, 0.8), Vec2::new(0.0, 0.8), 1.2),
                    horizontal_rect("blocker-b", Vec2::new(0.0, 0.8), Vec2::new(0.0, 0.8), 1.2),
                ],
                rect_down(Vec3::new(0.0, 3.0, 0.0), 0.4),
                default_camera(),
            )
        }
        "acne" => spec(
            name,
            "unoccluded flat and convex curved receivers lit 15 degrees above the horizon: V must stay 1",
            true,
            vec![
                horizontal_rect("flat", Vec2::new(-3.0, 3.0), Vec2::new(0.0, 3.0), 0.0),
                cylinder_patch(
                    Vec3::new(0.0, -1.0, -1.75),
                    2.0,
                    -5f32.to_radians(),
                    60f32.to_radians(),
                    2.5,
                    48,
                ),
            ],
            Light::Distant {
                direction: Vec3::new(15f32.to_radians().cos(), 15f32.to_radians().sin(), 0.0),
                angular_diameter: 1f32.to_radians(),
                profile: DistantProfile::UniformDisk,
            },
            camera(Vec3::new(3.0, 4.0, 4.5), Vec3::new(0.0, 0.0, -0.5)),
        ),
        "thin" => spec(
            name,
            "a zero-thickness sheet and 6 mm wires: thinner than a texel",
            true,
            vec![
                g(),
                quad_grid(
                    "sheet",
                    Vec3::new(0.0, 0.5, -1.0),
                    Vec3::Y,
                    Vec3::Z * 2.0,
                    1,
                ),
                cuboid(
                    "wire-a",
                    Vec3::new(-0.7, 1.0, 0.0),
                    Vec3::new(0.003, 0.003, 1.2),
                ),
                cuboid(
                    "wire-b",
                    Vec3::new(0.7, 1.0, 0.0),
                    Vec3::new(0.003, 0.003, 1.2),
                ),
            ],
            rect_down(Vec3::new(0.3, 3.0, 0.0), 0.3),
            default_camera(),
        ),
        "room-lamp" => room_lamp(
            name,
            "a sphere lamp below the tops of the furniture in a closed 6 m room, seen from above",
            camera_fov(Vec3::new(0.3, 2.9, 0.2), Vec3::ZERO, 80.0),
        )?,
        "room-lamp-corner" => room_lamp(
            name,
            "room-lamp seen from a corner of the room",
            camera_fov(Vec3::new(2.7, 2.4, 2.7), Vec3::new(-0.5, 0.4, -0.5), 70.0),
        )?,
        "street-sun" => street_sun()?,
        "low-poly-animal" => spec(
            name,
            "a low-poly animal (faceted parts that interpenetrate) under a tilted disk light",
            false,
            vec![g(), low_poly_animal("animal", 0.0, 0.0)],
            Light::Disk {
                center: Vec3::new(0.8, 3.2, 0.6),
                normal: (Vec3::ZERO - Vec3::new(0.8, 3.2, 0.6)).normalize(),
                radius: 0.35,
            },
            camera(Vec3::new(-0.6, 2.6, 3.2), Vec3::new(0.0, 0.5, 0.0)),
        ),
        "low-poly-rocks" => spec(
            name,
            "faceted rocks (80 triangles each) on the ground under a rect light",
            false,
            vec![
                g(),
                merged(
                    "rocks",
                    vec![
                        faceted_rock("rock", Vec3::new(-0.6, 0.3, 0.0), 0.45, 7),
                        faceted_rock("rock", Vec3::new(0.5, 0.25, 0.4), 0.35, 11),
                        faceted_rock("rock", Vec3::new(0.3, 0.6, -0.5), 0.3, 23),
                    ],
                ),
            ],
            rect_down(Vec3::new(0.5, 2.8, 0.3), 0.3),
            camera(Vec3::new(0.0, 3.0, 3.2), Vec3::new(0.0, 0.3, 0.0)),
        ),
        "low-poly-sphere-light" => spec(
            name,
            "the low-poly animal beside a faceted rock under a sphere light",
            false,
            vec![
                g(),
                merged(
                    "animal-and-rock",
                    vec![
                        low_poly_animal("animal", -0.3, 0.2),
                        faceted_rock("rock", Vec3::new(0.9, 0.35, -0.6), 0.4, 5),
                    ],
                ),
            ],
            Light::Sphere {
                center: Vec3::new(-0.8, 2.6, -0.9),
                radius: 0.3,
            },
            camera(Vec3::new(0.4, 2.8, 3.4), Vec3::new(0.0, 0.4, 0.0)),
        ),
        other => {
            return Err(ShadowError::InvalidScene(format!(
                "unknown scene {other:?}; built-in scenes: {}, {}; scenes of many lamps (the \
                 frame pipeline's): {}",
                SCENE_NAMES.join(", "),
                AS_SEEN_NAMES.join(", "),
                super::lamps::names::LAMP_SCENES.map(|(n, _)| n).join(", ")
            )));
        }
    })
}
