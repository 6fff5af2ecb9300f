//! Bad input to techniques and to the CLI: typed errors, no panic.

use glam::Vec3;
use harness::baselines::{Filter, ShadowMapBaseline};
use harness::scenes::catalogue::build;
use shadow_core::gpu::testing::gpu_for_test;
use shadow_core::{Backend, DynTechnique, Light, ShadowError};

#[test]
fn resolution_zero_and_zero_size_light_are_typed_errors() {
    let spec = build("plane-occluder").unwrap();
    let geo = spec.to_scene().unwrap().geometry();
    let b = ShadowMapBaseline::new(Filter::Pcss);
    let ctx = gpu_for_test("resolution_zero_and_zero_size_light_are_typed_errors");
    let mut backends = vec![Backend::Cpu];
    if ctx.is_some() {
        backends.push(Backend::Gpu);
    }
    let zero = Light::Rect {
        center: Vec3::Y,
        u_half: Vec3::ZERO,
        v_half: Vec3::Z,
    };
    for be in backends {
        let r = b.generate(be, ctx.as_ref(), &geo, &spec.light, 0);
        assert!(
            matches!(r, Err(ShadowError::InvalidResolution { requested: 0, .. })),
            "{be:?}"
        );
        let r = b.generate(be, ctx.as_ref(), &geo, &spec.light, 1 << 20);
        assert!(
            matches!(r, Err(ShadowError::InvalidResolution { .. })),
            "{be:?}"
        );
        let r = b.generate(be, ctx.as_ref(), &geo, &zero, 64);
        assert!(matches!(r, Err(ShadowError::InvalidLight(_))), "{be:?}");
    }
    let r = b.generate(Backend::Gpu, None, &geo, &spec.light, 64);
    assert!(matches!(r, Err(ShadowError::NoAdapter(_))));
}

#[test]
fn cli_reports_bad_input_and_exits_nonzero() {
    let exe = env!("CARGO_BIN_EXE_harness");
    let dir = std::env::temp_dir().join(format!("harness-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad_toml = dir.join("bad.toml");
    std::fs::write(&bad_toml, "[light]\nkind = \"rect\"\ncenter = [0,3,0]\nu_half = [0,0,0]\nv_half = [0,0,0.4]\n[camera]\neye = [0,4,4]\ntarget = [0,0,0]\n").unwrap();
    let bad_glb = dir.join("broken.glb");
    std::fs::write(&bad_glb, b"glTF\x02\x00\x00\x00garbage").unwrap();
    let glb_toml = dir.join("glb.toml");
    std::fs::write(&glb_toml, "[[mesh]]\npath = \"broken.glb\"\n[light]\nkind = \"point\"\nposition = [0,3,0]\n[camera]\neye = [0,4,4]\ntarget = [0,0,0]\n").unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["--scenes".into(), "no-such-scene".into()],
            "unknown scene",
        ),
        (
            vec!["--resolutions".into(), "0".into()],
            "invalid resolution 0",
        ),
        (
            vec!["--scene-file".into(), bad_toml.display().to_string()],
            "invalid light",
        ),
        (
            vec!["--scene-file".into(), glb_toml.display().to_string()],
            "glTF import failed",
        ),
    ];
    for (args, expect) in cases {
        let out = std::process::Command::new(exe)
            .args(["report", "--quick", "--backend", "cpu", "--out"])
            .arg(dir.join("out"))
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(err.contains(expect), "{args:?}: stderr was {err}");
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    }
}
