//! Bad input to techniques and to the CLI: typed errors, no panic.

use crate::common::context;
use crate::common::gpu_for_test;
use glam::Vec3;
use shadow_maps::{Filter, ShadowMapBaseline};
use soft_shadow_core::{DynTechnique, Light, ShadowError};
use soft_shadow_reference::scenes::catalogue::build;

#[test]
fn resolution_zero_and_zero_size_light_are_typed_errors() {
    let spec = build("plane-occluder").unwrap();
    let geo = spec.to_scene().unwrap().geometry();
    let b = ShadowMapBaseline::new(Filter::Pcss);
    let ctx = gpu_for_test("resolution_zero_and_zero_size_light_are_typed_errors");
    let backends = crate::common::backends(ctx.as_ref());
    let zero = Light::Rect {
        center: Vec3::Y,
        u_half: Vec3::ZERO,
        v_half: Vec3::Z,
    };
    for be in backends {
        let r = b.generate(context(be, ctx.as_ref()), &geo, &spec.light, 0);
        assert!(
            matches!(r, Err(ShadowError::InvalidResolution { requested: 0, .. })),
            "{be:?}"
        );
        let r = b.generate(context(be, ctx.as_ref()), &geo, &spec.light, 1 << 20);
        assert!(
            matches!(r, Err(ShadowError::InvalidResolution { .. })),
            "{be:?}"
        );
        let r = b.generate(context(be, ctx.as_ref()), &geo, &zero, 64);
        assert!(matches!(r, Err(ShadowError::InvalidLight(_))), "{be:?}");
    }
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
            vec!["--size".into(), "0".into()],
            "--size (the G-buffer side in pixels) must be in 1..=4096, got 0",
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

/// A scene file named `name`: a 1 m plate 1 m over a receiver-only ground, under a point light.
fn plate_scene(name: &str) -> String {
    format!(
        "name = {name:?}\n[[mesh]]\nground = 8.0\n[[mesh]]\nground = 1.0\ncaster = true\n\
         translation = [0.0, 1.0, 0.0]\n[light]\nkind = \"point\"\nposition = [0.0, 3.0, 0.0]\n\
         [camera]\neye = [0.0, 4.0, 4.0]\ntarget = [0.0, 0.0, 0.0]\n"
    )
}

/// A scene whose caster shadows nothing the camera sees (the plate beside the light, not under
/// it) runs, and the report warns on stderr instead of writing a plausible, empty report
/// silently.
#[test]
fn a_scene_where_nothing_is_shadowed_is_warned_about() {
    let dir = std::env::temp_dir().join(format!("harness-noshadow-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = plate_scene("beside").replace(
        "translation = [0.0, 1.0, 0.0]",
        "translation = [0.0, 4.0, 0.0]",
    );
    let f = dir.join("beside.toml");
    std::fs::write(&f, scene).unwrap();
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_harness"))
        .args([
            "report",
            "--quick",
            "--backend",
            "cpu",
            "--techniques",
            "hard-shadow-map",
        ])
        .args(["--resolutions", "64", "--size", "24", "--scene-file"])
        .arg(&f)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{err}");
    assert!(
        err.contains("warning: beside: no caster shadows any receiver"),
        "{err}"
    );
}

/// Whatever a scene is named, every output stays inside `--out` (names are sanitised into file
/// stems); a run where every configuration is skipped exits non-zero and says why.
#[test]
fn hostile_scene_names_stay_inside_the_output_folder() {
    let exe = env!("CARGO_BIN_EXE_harness");
    let dir = std::env::temp_dir().join(format!("harness-names-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.join("nested").join("out");
    std::fs::create_dir_all(&out).unwrap();
    let names = ["../escaped", "../../escaped2", "a/b c", "/abs", ".."];
    let mut args: Vec<String> = vec![
        "report".into(),
        "--quick".into(),
        "--backend".into(),
        "cpu".into(),
        "--techniques".into(),
        "hard-shadow-map".into(),
        "--resolutions".into(),
        "64".into(),
        "--size".into(),
        "24".into(),
        "--out".into(),
        out.display().to_string(),
    ];
    for (i, n) in names.iter().enumerate() {
        let f = dir.join(format!("s{i}.toml"));
        std::fs::write(&f, plate_scene(n)).unwrap();
        args.push("--scene-file".into());
        args.push(f.display().to_string());
    }
    let run = std::process::Command::new(exe)
        .args(&args)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{err}");
    // Off a terminal (stderr piped) progress comes as plain lines: n of N, elapsed, time left.
    assert!(
        err.lines().any(|l| l.starts_with("[10 of 10] ")
            && l.contains(" elapsed, about ")
            && l.contains(" left: ")),
        "no progress lines on a piped stderr:\n{err}"
    );
    for n in names {
        let stem = harness::report::file_stem(n);
        assert!(
            !stem.contains('/') && !stem.starts_with('.'),
            "{n} -> {stem}"
        );
        assert!(
            out.join(format!("{stem}.png")).is_file(),
            "{n}: {stem}.png missing"
        );
        assert!(
            out.join("exr").join(&stem).is_dir(),
            "{n}: exr/{stem} missing"
        );
    }
    // Nothing outside `out`: its parents hold only what the test put there.
    let outside: Vec<_> = walk(&dir)
        .into_iter()
        .filter(|p| !p.starts_with(&out) && p.extension().is_none_or(|e| e != "toml"))
        .filter(|p| p.is_file())
        .collect();
    assert!(outside.is_empty(), "written outside --out: {outside:?}");
    let none = std::process::Command::new(exe)
        .args([
            "report",
            "--quick",
            "--backend",
            "cpu",
            "--scenes",
            "plane-occluder",
        ])
        .args([
            "--techniques",
            "hard-shadow-map",
            "--resolutions",
            "100000",
            "--size",
            "24",
        ])
        .arg("--out")
        .arg(dir.join("none"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&none.stderr);
    assert!(!none.status.success(), "nothing ran yet exit 0: {err}");
    assert!(
        err.contains("nothing ran") && err.contains("skipped plane-occluder"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

fn walk(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(walk(&p));
        }
        out.push(p);
    }
    out
}

/// `--techniques` takes `technique` or `technique:variant`; an unknown one is a typed parameter
/// error listing each technique once and every variant; `scale = 0` in a scene file is refused.
#[test]
fn technique_selection_and_scale_are_checked() {
    use harness::report::{BackendChoice, ReportOptions, run};
    let dir = std::env::temp_dir().join(format!("harness-select-{}", std::process::id()));
    let opts = |techniques: &str, files: Vec<std::path::PathBuf>| ReportOptions {
        quick: true,
        out: dir.join("out"),
        scenes: if files.is_empty() {
            Some(vec!["plane-occluder".into()])
        } else {
            None
        },
        techniques: Some(vec![techniques.into()]),
        registry: soft_shadow_techniques::registry(),
        resolutions: Some(vec![32]),
        backend: BackendChoice::Cpu,
        scene_files: files,
        as_seen: None,
        size: Some(16),
        memory: Default::default(),
    };
    let r = run(&opts("pcf:r2", Vec::new())).unwrap();
    assert!(
        r.runs
            .iter()
            .all(|x| x.technique == "pcf" && x.variant == "r2")
    );
    assert_eq!(r.runs.len(), 1);
    match run(&opts("no-such", Vec::new())) {
        Err(harness::error::HarnessError::Shadow(ShadowError::InvalidParameter(m))) => {
            assert!(m.contains("unknown technique \"no-such\""), "{m}");
            assert_eq!(m.matches("occlusion-slices,").count(), 1, "{m}");
            assert!(m.contains("pcf:r2"), "{m}");
        }
        other => panic!("{other:?}"),
    }
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("flat.toml");
    std::fs::write(
        &f,
        plate_scene("flat").replace("ground = 1.0\n", "ground = 1.0\nscale = 0.0\n"),
    )
    .unwrap();
    match run(&opts("pcf", vec![f])) {
        Err(harness::error::HarnessError::Shadow(ShadowError::InvalidScene(m))) => {
            assert!(m.contains("`scale`"), "{m}")
        }
        other => panic!("{other:?}"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `report --list` prints every built-in scene and every technique with its variants.
#[test]
fn report_list_names_scenes_techniques_and_variants() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(["report", "--list"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for name in soft_shadow_reference::scenes::catalogue::SCENE_NAMES {
        assert!(text.contains(name), "{name} missing:\n{text}");
    }
    assert!(
        text.contains("occlusion-slices") && text.contains("sat-8-max"),
        "{text}"
    );
    assert_eq!(text.matches("\n  pcf ").count(), 1, "{text}");
}

/// A configuration over the memory budget is refused before it allocates, naming the need and
/// the budget (accumulation n64 at 16384² asks for 64 GiB of maps).
#[test]
fn a_configuration_over_the_memory_budget_is_a_typed_error() {
    use soft_shadow_core::{CpuContext, ShadowTechnique, TechniqueInfo};
    let spec = soft_shadow_reference::scenes::catalogue::build("plane-occluder").unwrap();
    let geometry = spec.to_scene().unwrap().geometry();
    let t = shadow_maps::ShadowMapBaseline::new(shadow_maps::Filter::Accumulate { samples: 64 });
    assert_eq!(t.memory_estimate(&spec.light, 16384), 64 << 30);
    let cpu = CpuContext::with_memory_budget(6 << 30);
    let e = t
        .generate_cpu(&cpu, &geometry, &spec.light, 16384)
        .err()
        .expect("over the budget");
    assert!(
        matches!(e, soft_shadow_core::ShadowError::OverBudget { need, budget, .. } if need == 64 << 30 && budget == 6 << 30),
        "{e}"
    );
    assert!(
        e.to_string().contains("64.0 GiB") && e.to_string().contains("6.0 GiB"),
        "{e}"
    );
}
