//! The viewer: its view state (camera, light edits, technique and light-kind rules), and the
//! real window under Xvfb on lavapipe: a screenshot of two techniques split equals the offscreen
//! renderer's frame, and a malformed model on the command line exits cleanly with a message.

use glam::Vec3;
use soft_shadow_core::{Camera, Light, LightKind};
use soft_shadow_techniques::registry;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use viewer::state::{Choice, LightEdit, OrbitCamera, SIZE_RANGE, ViewState};

fn camera() -> Camera {
    Camera {
        eye: Vec3::new(0.0, 2.6, 4.2),
        target: Vec3::new(0.0, 0.6, 0.0),
        fov_y: 0.9,
        near: 0.1,
        far: 20.0,
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-4
}

/// The orbit reproduces the camera it starts from; orbiting keeps the distance to the target,
/// the pitch stops short of the pole, zoom stays within its range, and a pan moves eye and
/// target together.
#[test]
fn the_orbit_camera_keeps_its_target_and_distance() {
    let c = camera();
    let mut o = OrbitCamera::from_camera(&c);
    assert!(close(o.camera().eye, c.eye), "{:?}", o.camera().eye);
    let d = o.distance;
    o.orbit(120.0, 400.0);
    assert!(((o.camera().eye - o.target).length() - d).abs() < 1e-4);
    assert_eq!(o.pitch, OrbitCamera::MAX_PITCH);
    for _ in 0..200 {
        o.zoom(1.0, d);
    }
    assert!((o.distance - d * OrbitCamera::ZOOM_RANGE.0).abs() < 1e-5);
    let before = o.camera();
    o.pan(10.0, -5.0, 100.0);
    let after = o.camera();
    assert!(close(after.eye - before.eye, after.target - before.target));
    assert!((after.target - before.target).length() > 0.0);
}

/// Walking moves eye and target together along the camera's heading in the horizontal plane
/// (down a street, through a room): forward closes the horizontal distance to a point ahead,
/// a step aside keeps it, and neither turns the view nor changes the height.
#[test]
fn walking_moves_the_camera_along_its_heading() {
    let c = camera();
    let mut o = OrbitCamera::from_camera(&c);
    let before = o.camera();
    let heading = {
        let d = before.target - before.eye;
        Vec3::new(d.x, 0.0, d.z).normalize()
    };
    o.walk(2.0, 0.0);
    let after = o.camera();
    assert!(
        close(after.eye - before.eye, heading * 2.0),
        "{:?}",
        after.eye - before.eye
    );
    assert!(close(after.target - after.eye, before.target - before.eye));
    o.walk(0.0, 1.5);
    let aside = o.camera();
    let step = aside.eye - after.eye;
    assert!((step.length() - 1.5).abs() < 1e-4 && step.dot(heading).abs() < 1e-4 && step.y == 0.0);
    assert!(close(heading.cross(Vec3::Y) * 1.5, step), "{step:?}");
}

/// Every light kind built from an edit is valid, faces its target, keeps the edit's centre,
/// and changing the kind keeps the centre and size; a size outside its range is clamped and
/// a light on its target is an error.
#[test]
fn light_edits_give_valid_lights_facing_the_target() {
    let target = Vec3::new(0.0, 0.5, 0.0);
    let mut e = LightEdit {
        kind: LightKind::Rect,
        center: Vec3::new(1.0, 3.0, 0.5),
        target,
        size: 0.6,
    };
    for kind in LightKind::ALL {
        e.kind = kind;
        let light = e.light().unwrap_or_else(|err| panic!("{kind:?}: {err}"));
        assert_eq!(light.kind(), kind);
        if kind != LightKind::Distant {
            let back = LightEdit::from_light(&light, target);
            assert!(close(back.center, e.center), "{kind:?}: {:?}", back.center);
            if kind != LightKind::Point {
                assert!(
                    (back.size - 0.6).abs() < 1e-3,
                    "{kind:?}: size {}",
                    back.size
                );
            }
        }
        // Facing the target: the target receives light from the front.
        if let Light::Rect { u_half, v_half, .. } = light {
            assert!(u_half.cross(v_half).dot(target - e.center) > 0.0);
        }
        if let Light::Triangle { a, b, c } = light {
            assert!((b - a).cross(c - a).dot(target - e.center) > 0.0);
        }
    }
    e.kind = LightKind::Disk;
    e.size = 100.0;
    let Light::Disk { radius, .. } = e.light().unwrap() else {
        unreachable!()
    };
    assert!((2.0 * radius - SIZE_RANGE.1 * e.distance()).abs() < 1e-4);
    let mut d = e;
    d.set_distance(2.0);
    assert!((d.distance() - 2.0).abs() < 1e-5);
    let on_target = LightEdit {
        center: target,
        ..e
    };
    assert!(on_target.light().is_err());
    // The animation turns the light around the vertical through the target.
    let turned = e.animated(1.0);
    assert!((turned.distance() - e.distance()).abs() < 1e-4);
    assert!((turned.center.y - e.center.y).abs() < 1e-5);
    assert!(!close(turned.center, e.center));
}

/// A technique is offered only for the light kinds it models, and the refusal says which it
/// models; switching the light to a kind the chosen technique does not model replaces it and
/// says so.
#[test]
fn techniques_are_offered_only_for_the_lights_they_model() {
    let reg = registry();
    let light = Light::Rect {
        center: Vec3::new(0.0, 3.0, 0.0),
        u_half: Vec3::X * 0.3,
        v_half: Vec3::Z * 0.3,
    };
    let choice = Choice::new(&reg, "occlusion-slices", 512).unwrap();
    let mut s = ViewState::new(&camera(), &light, choice);
    // The scene's own light until the light is edited.
    assert_eq!(s.frame_light().unwrap(), light);
    let why = s.choose(false, "linear-light", &reg).unwrap_err();
    assert!(
        why.contains("linear, triangle") && why.contains("not rect"),
        "{why}"
    );
    assert_eq!(s.shadow.technique, "occlusion-slices");
    s.choose(true, "pcss", &reg).unwrap();
    let said = s.set_light_kind(LightKind::Linear, &reg);
    assert_eq!(s.frame_light().unwrap().kind(), LightKind::Linear);
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(said[0].contains("occlusion-slices models"), "{said:?}");
    let shown = reg.family(s.shadow.technique).unwrap();
    assert!(shown.availability(LightKind::Linear).is_ok());
    assert_eq!(s.shadow.resolution, 512);
    assert_eq!(s.compare.as_ref().unwrap().technique, "pcss");
    assert!(reg.family("no-such").is_err());
    for e in reg.families() {
        assert!(
            LightKind::ALL.iter().any(|&k| e.availability(k).is_ok()),
            "{}",
            e.name()
        );
    }
    assert_eq!(s.split_column(200), Some(100));
}

/// How to run the viewer in a window: directly where a display is set, under `xvfb-run`
/// otherwise; `None` (the test is skipped, or fails under CI) where neither is.
fn windowed(args: &[&str]) -> Option<Output> {
    let exe = env!("CARGO_BIN_EXE_viewer");
    let xvfb = Command::new("xvfb-run").arg("--help").output().is_ok();
    let mut cmd = if xvfb {
        let mut c = Command::new("xvfb-run");
        c.args(["-a", "-s", "-screen 0 1280x1024x24", exe]);
        c
    } else if std::env::var_os("DISPLAY").is_some() {
        Command::new(exe)
    } else {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI needs xvfb-run (apt-get install xvfb) for the window test"
        );
        eprintln!("skipped: no display and no xvfb-run");
        return None;
    };
    cmd.args(args);
    Some(cmd.output().expect("run the viewer"))
}

/// The viewer's stdout, once it exited successfully (its output in the message otherwise).
fn succeeded(out: &Output) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "viewer failed:\n{stdout}\n{stderr}");
    stdout
}

/// Where the view starts in the window, from the line "view WxH at X,Y in the window".
fn view_place(stdout: &str) -> (u32, u32) {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("view "))
        .expect("the view's place");
    let nums: Vec<u32> = line
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|s| s.parse().ok())
        .collect();
    (nums[2], nums[3])
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A real window (Xvfb, lavapipe) showing penumbra-limit left and PCSS right of the split:
/// the screenshot's view pixels equal the offscreen renderer's frame of the same scene, camera,
/// light and techniques within 1/255 rms, both halves show a shadow, and the window reports
/// its pass times.
#[test]
fn a_window_screenshot_of_two_techniques_matches_the_offscreen_frame() {
    let shot = scratch("window").join("shot.png");
    let (w, h, resolution) = (192u32, 128u32, 256u32);
    let size = format!("{w}x{h}");
    let res = resolution.to_string();
    let Some(out) = windowed(&[
        "--scene",
        "bunny",
        "--technique",
        "penumbra-limit",
        "--compare",
        "pcss",
        "--resolution",
        &res,
        "--size",
        &size,
        "--frames",
        "3",
        "--screenshot",
        shot.to_str().unwrap(),
    ]) else {
        return;
    };
    let stdout = succeeded(&out);
    let (x0, y0) = view_place(&stdout);
    assert!(stdout.contains("CPU recording, ms"), "{stdout}");
    let image = image::open(&shot).unwrap().to_rgba8();
    assert!(image.width() >= x0 + w && image.height() >= y0 + h);

    // The same frame offscreen.
    let Ok((device, queue)) = viewer::own_device() else {
        assert!(std::env::var_os("CI").is_none(), "CI needs an adapter");
        return;
    };
    let reg = registry();
    let scene =
        viewer::scene::load(&viewer::scene::SceneSource::Catalogue("bunny".into())).unwrap();
    let mut state = ViewState::new(
        &scene.camera,
        &scene.light,
        Choice::new(&reg, "penumbra-limit", resolution).unwrap(),
    );
    state.choose(true, "pcss", &reg).unwrap();
    let cam = state.camera.camera();
    let r = viewer::Renderer::new(
        device,
        queue,
        &scene.geometry,
        viewer::FrameSettings {
            width: w,
            height: h,
            camera: cam,
        },
    )
    .unwrap();
    let light = state.frame_light().unwrap();
    let a = reg
        .family("penumbra-limit")
        .unwrap()
        .default_variant()
        .clone();
    let pcss = reg.family("pcss").unwrap().default_variant().clone();
    assert_eq!(a.name(), "penumbra-limit");
    let split = state.split_column(w).unwrap();
    let frame = |mode| viewer::Frame {
        light: &light,
        shadow: viewer::Shadow {
            technique: a.as_ref(),
            resolution,
        },
        compare: Some((
            viewer::Shadow {
                technique: pcss.as_ref(),
                resolution,
            },
            split,
        )),
        mode,
    };
    r.render(&frame(viewer::ViewMode::Shaded)).unwrap();
    let want = r.read_color().unwrap();
    let positions: Vec<[f32; 4]> = soft_shadow_core::gpu::raster::read_texture(
        &r.gpu,
        r.gbuffer().0,
        0,
        wgpu::TextureAspect::All,
        16,
    )
    .unwrap();
    // The same frame's V, for where each half is in shadow.
    r.render(&frame(viewer::ViewMode::Visibility)).unwrap();
    let v = r.read_color().unwrap();
    let (mut sum, mut n) = (0.0f64, 0usize);
    // Covered pixels with V < 0.5 per half: each technique casts its shadow.
    let mut dark = [0usize; 2];
    for y in 0..h {
        for x in 0..w {
            let g = image.get_pixel(x0 + x, y0 + y).0;
            let o = want.get_pixel(x, y).0;
            for c in 0..3 {
                sum += (g[c] as f64 - o[c] as f64).powi(2);
                n += 1;
            }
            let covered = positions[(y * w + x) as usize][3] > 0.5;
            if covered && (x + 1 < split || x > split) && v.get_pixel(x, y).0[0] < 128 {
                dark[(x >= split) as usize] += 1;
            }
        }
    }
    let rms = (sum / n as f64).sqrt();
    println!("window against offscreen: rms {rms:.3}/255 over {w}x{h}; dark pixels {dark:?}");
    assert!(rms <= 1.0, "rms {rms:.3}/255");
    assert!(
        dark[0] > 50 && dark[1] > 50,
        "both halves show a shadow: {dark:?}"
    );
}

/// A real window on the night street: the frame pipeline shares the budget among its 16 lamps
/// (every lamp's pick printed, the lamps behind the camera without a shadow, at least two with
/// one: on lavapipe a lamp's passes take 15-40 ms of device time at this size and the
/// pipeline's own passes 10-15 ms, so the budget is 400 ms, which holds two lamps on a machine
/// twice as slow; at 16 ms whether any lamp fits depends on the machine), the view shows
/// lamp-lit ground beside dark, and
/// a budget that is not a positive number of milliseconds is refused with a message.
#[test]
fn a_window_shows_the_night_streets_lamps_under_one_budget() {
    let shot = scratch("lamps").join("shot.png");
    let Some(out) = windowed(&[
        "--scene",
        "night-street",
        "--size",
        "192x108",
        "--budget-ms",
        "400",
        "--frames",
        "3",
        "--screenshot",
        shot.to_str().unwrap(),
    ]) else {
        return;
    };
    let stdout = succeeded(&out);
    assert!(
        stdout.contains("16 lamps under a 400 ms budget"),
        "{stdout}"
    );
    let lamps: Vec<&str> = stdout
        .lines()
        .filter(|l| l.trim_start().starts_with("lamp "))
        .collect();
    let shadowed = lamps.iter().filter(|l| !l.contains("no shadow")).count();
    assert_eq!(lamps.len(), 16, "{stdout}");
    assert!(shadowed >= 2, "{shadowed} lamps with a shadow:\n{stdout}");
    assert!(
        lamps
            .iter()
            .any(|l| l.contains("no shadow: lights nothing in view")),
        "the lamps behind the camera: {stdout}"
    );
    let (x0, y0) = view_place(&stdout);
    let image = image::open(&shot).unwrap().to_rgba8();
    let (mut bright, mut dark) = (0, 0);
    for y in 0..108 {
        for x in 0..192 {
            let g = image.get_pixel(x0 + x, y0 + y).0[0];
            bright += (g > 150) as usize;
            dark += (g < 30) as usize;
        }
    }
    assert!(bright > 100 && dark > 100, "bright {bright}, dark {dark}");
    let Some(out) = windowed(&[
        "--scene",
        "night-street",
        "--budget-ms",
        "0",
        "--frames",
        "1",
    ]) else {
        return;
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("positive number of milliseconds"),
        "{stderr}"
    );
}

/// A malformed GLB on the command line: a message naming the file, exit code 1, no panic
/// and no window left behind.
#[test]
fn a_malformed_glb_exits_cleanly_with_a_message() {
    let bad = scratch("bad-glb").join("broken.glb");
    std::fs::write(&bad, b"glTF\x02\x00\x00\x00not really a model").unwrap();
    let Some(out) = windowed(&["--open", bad.to_str().unwrap(), "--frames", "1"]) else {
        return;
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("cannot open the scene"), "{stderr}");
    assert!(stderr.contains("broken.glb"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// The reference worker answers off the calling thread, in passes of growing size, and its last
/// pass equals the harness's tracer run directly on the same pixels; a reference asked for
/// again is served from the cache at once.
#[test]
fn the_reference_refines_off_thread_and_is_cached() {
    use soft_shadow_reference::ground_truth::{GroundTruthSettings, RayTracer};
    use viewer::reference::{LEVELS, ReferenceKey, References};
    let scene =
        viewer::scene::load(&viewer::scene::SceneSource::Catalogue("bunny".into())).unwrap();
    let (w, h) = (96u32, 64u32);
    let key = |light: Light| ReferenceKey {
        scene: 7,
        light,
        camera: scene.camera,
        width: w,
        height: h,
    };
    let mut refs = References::new();
    refs.set_scene(7, scene.geometry.clone());
    let asked = std::time::Instant::now();
    refs.request(key(scene.light));
    assert!(refs.current().is_none(), "nothing before the first pass");
    assert!(asked.elapsed().as_millis() < 50, "request does not wait");
    let mut levels = Vec::new();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    while levels.last() != Some(&(LEVELS.len() - 1)) {
        assert!(std::time::Instant::now() < deadline, "passes {levels:?}");
        if refs.poll() {
            let r = refs.current().unwrap();
            let (div, _, _) = LEVELS[r.level];
            assert_eq!((r.width, r.height), (w / div, h / div));
            levels.push(r.level);
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert!(levels.windows(2).all(|p| p[0] < p[1]), "{levels:?}");
    // The last pass against the tracer on the same pixels.
    let r = refs.current().unwrap().clone();
    let (_, strata_side, replicates) = LEVELS[r.level];
    let cpu = soft_shadow_core::CpuContext::new();
    let g = soft_shadow_core::raster::gbuffer(
        cpu.pool(),
        &scene.camera.view(r.width, r.height),
        scene.camera.eye,
        r.width,
        r.height,
        &scene.geometry.receivers,
    );
    let covered: Vec<usize> = (0..g.data().len())
        .filter(|&i| g.data()[i].covered)
        .collect();
    let ps: Vec<Vec3> = covered.iter().map(|&i| g.data()[i].position).collect();
    let ns: Vec<Vec3> = covered.iter().map(|&i| g.data()[i].normal).collect();
    let direct = RayTracer::new(&scene.geometry.casters).references(
        &scene.light,
        &ps,
        &ns,
        &GroundTruthSettings {
            strata_side,
            replicates,
            ..Default::default()
        },
    );
    let shadowed = direct
        .iter()
        .flatten()
        .filter(|d| d.visibility < 0.5)
        .count();
    assert!(shadowed > 20, "the view holds a shadow: {shadowed}");
    for (&i, d) in covered.iter().zip(&direct) {
        assert_eq!(r.data[i], d.map_or(-1.0, |d| d.visibility), "pixel {i}");
    }
    // Another light, then the first again: served from the cache without waiting.
    let moved = Light::Point {
        position: Vec3::new(0.0, 3.0, 0.0),
    };
    refs.request(key(moved));
    refs.request(key(scene.light));
    assert_eq!(refs.current().map(|r| r.level), Some(LEVELS.len() - 1));
    assert!(
        refs.status().starts_with("reference: current"),
        "{}",
        refs.status()
    );
}
