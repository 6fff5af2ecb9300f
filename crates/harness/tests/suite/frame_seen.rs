//! Culling by what the camera sees (`shadow_frame::tracking::mark_stale`): a caster that moves
//! where it can shadow nothing in view leaves a lamp's maps alone until the camera turns to
//! where it can.

use glam::{Mat4, Vec3};
use harness::animated::pipeline;
use shadow_frame::scene::Transform;
use shadow_frame::{FrameReceivers, FrameSettings, LightState, Scene, ShadowConfig, Shadows};
use soft_shadow_core::{DynTechnique, Light};
use soft_shadow_reference::scenes::shapes::{cuboid, ground};
use std::sync::Arc;

/// Receivers on a 1 m ground patch from `min` (x, z), 10 x 10.
fn patch(min: (f32, f32)) -> FrameReceivers {
    let positions: Vec<Vec3> = (0..100)
        .map(|i| {
            Vec3::new(
                min.0 + (i % 10) as f32 * 0.1,
                0.0,
                min.1 + (i / 10) as f32 * 0.1,
            )
        })
        .collect();
    FrameReceivers {
        normals: vec![Vec3::Y; positions.len()],
        positions,
        camera: None,
    }
}

/// A rect lamp 3 m up with a 5 m range over a box; the camera sees a patch on one side. A
/// second box moves on the other side, within the lamp's range but where it can shadow nothing
/// in view: the lamp keeps its maps (the region waits in `unseen_changes`). The camera turns to
/// the moved box's shadow: the maps are made again, and `V` there equals a frame made from
/// scratch (the box's shadow is there).
#[test]
fn a_caster_out_of_view_waits_until_the_camera_sees_where_it_shadows() {
    let mut scene = Scene::new();
    scene
        .add_mesh(
            Arc::new(ground(12.0, 0.0, 1)),
            Mat4::IDENTITY,
            Shadows::RECEIVE_ONLY,
        )
        .unwrap();
    let block = Arc::new(cuboid("box", Vec3::ZERO, Vec3::splat(0.3)));
    scene
        .add_mesh(
            block.clone(),
            Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)),
            Shadows::CAST_AND_RECEIVE,
        )
        .unwrap();
    let mover = scene
        .add_mesh(
            block,
            Mat4::from_translation(Vec3::new(2.5, 0.5, 2.5)),
            Shadows::CAST_AND_RECEIVE,
        )
        .unwrap();
    let lamp = scene
        .add_light(Light::Rect {
            center: Vec3::new(0.0, 3.0, 0.0),
            u_half: Vec3::X * 0.3,
            v_half: Vec3::Z * 0.3,
        })
        .unwrap();
    let pcf: Arc<dyn DynTechnique> = Arc::new(shadow_maps::ShadowMapBaseline::new(
        shadow_maps::Filter::Pcf { radius: 2 },
    ));
    scene
        .world
        .entity_mut(lamp)
        .insert(ShadowConfig::explicit(pcf, 256).with_range(5.0));
    scene.world.insert_resource(patch((-1.5, -1.5)));
    let mut p = pipeline();
    assert_eq!(p.run(&mut scene.world).maps_generated, 1);

    let moved = Mat4::from_translation(Vec3::new(2.5, 0.5, 2.0));
    scene.world.get_mut::<Transform>(mover).unwrap().0 = moved;
    let s = p.run(&mut scene.world);
    assert_eq!((s.maps_generated, s.maps_reused), (0, 1), "{}", s.summary());
    let state = scene.world.get::<LightState>(lamp).unwrap();
    assert_eq!(state.unseen_changes.len(), 2, "old and new bounds wait");

    // The moved box's shadow falls about (3, 0, 2.4): the camera turns there.
    scene.world.insert_resource(patch((2.5, 1.9)));
    let s = p.run(&mut scene.world);
    assert_eq!(s.maps_generated, 1, "{}", s.summary());
    let state = scene.world.get::<LightState>(lamp).unwrap();
    assert!(state.unseen_changes.is_empty());
    let culled = state.visibility.clone();
    assert!(
        culled.iter().filter(|&&v| v < 0.5).count() > 10,
        "the box's shadow is in view"
    );
    scene
        .world
        .insert_resource(FrameSettings::default().with_caching(false));
    p.run(&mut scene.world);
    assert_eq!(
        scene.world.get::<LightState>(lamp).unwrap().visibility,
        culled
    );

    // Without evaluated receivers (a GPU frame's G-buffer is the view, the frame's receivers
    // may be a few points), every change in range makes the maps again.
    scene.world.insert_resource(patch((-1.5, -1.5)));
    scene
        .world
        .insert_resource(FrameSettings::default().with_evaluate_receivers(false));
    p.run(&mut scene.world);
    scene.world.get_mut::<Transform>(mover).unwrap().0 =
        Mat4::from_translation(Vec3::new(2.5, 0.5, 2.5));
    assert_eq!(p.run(&mut scene.world).maps_generated, 1);
}

/// A lamp 3.6 m up with a 9 m range beside a car on a 200 m ground that casts (the night
/// street's): its maps hold only what lies within its range (the ground clipped to the range's
/// box), so the car's long shadow is drawn by penumbra-limit as by the reference (with the
/// whole ground in its maps, their depth range ran 100 m and most of the shadow was lost).
#[test]
fn a_lamps_maps_hold_only_what_lies_within_its_range() {
    const LAMP: Vec3 = Vec3::new(-4.0, 3.6, 4.35);
    use soft_shadow_reference::ground_truth::{GroundTruthSettings, RayTracer};
    let mut scene = Scene::new();
    scene
        .add_mesh(
            Arc::new(ground(200.0, 0.0, 1)),
            Mat4::IDENTITY,
            Shadows::CAST_AND_RECEIVE,
        )
        .unwrap();
    scene
        .add_mesh(
            Arc::new(cuboid(
                "car",
                Vec3::new(-1.5, 0.7, 3.2),
                Vec3::new(2.0, 0.7, 0.9),
            )),
            Mat4::IDENTITY,
            Shadows::CAST_AND_RECEIVE,
        )
        .unwrap();
    let lamp = scene
        .add_light(Light::Sphere {
            center: LAMP,
            radius: 0.15,
        })
        .unwrap();
    let pl: Arc<dyn DynTechnique> = Arc::new(penumbra_limit::PenumbraLimit::new(
        penumbra_limit::Generator::Silhouette,
    ));
    scene
        .world
        .entity_mut(lamp)
        .insert(ShadowConfig::explicit(pl, 1024).with_range(9.0));
    // Ground receivers beyond the car, in the lamp's range.
    let positions: Vec<Vec3> = (0..50 * 30)
        .map(|i| Vec3::new(0.5 + (i % 50) as f32 * 0.08, 0.0, (i / 50) as f32 * 0.1))
        .filter(|p| p.distance(LAMP) <= 9.0)
        .collect();
    let normals = vec![Vec3::Y; positions.len()];
    scene.world.insert_resource(FrameReceivers {
        positions: positions.clone(),
        normals: normals.clone(),
        camera: None,
    });
    pipeline().run(&mut scene.world);
    let v = scene
        .world
        .get::<LightState>(lamp)
        .unwrap()
        .visibility
        .clone();
    let light = scene
        .world
        .get::<shadow_frame::scene::LightSource>(lamp)
        .unwrap()
        .0;
    let truth = RayTracer::new(&scene.geometry().casters);
    let settings = GroundTruthSettings {
        strata_side: 4,
        replicates: 2,
        ..Default::default()
    };
    let refs = truth.references(&light, &positions, &normals, &settings);
    let dark: Vec<usize> = (0..positions.len())
        .filter(|&i| refs[i].is_some_and(|r| r.visibility < 0.25))
        .collect();
    let drawn = dark.iter().filter(|&&i| v[i] < 0.5).count();
    assert!(
        dark.len() > 50,
        "{} receivers in the car's umbra",
        dark.len()
    );
    assert!(
        drawn * 10 >= dark.len() * 9,
        "{drawn} of {} receivers in the car's umbra read dark",
        dark.len()
    );
}
