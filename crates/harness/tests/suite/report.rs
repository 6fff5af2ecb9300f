//! The report on a few scenes: files written, contract fields present, numbers sane.

use harness::report::{BackendChoice, ReportOptions, run, summary};

/// `--scenes room-lamps`: the report walks the room's three lamps under one budget (no other
/// scene runs): `frames-room-lamps.md`, `report.json`'s `frames` (8 frames, every lamp of each
/// with its pick and errors), the table in `report.md` linking the document; the lamps'
/// shadows take a good part of the error no shadow would leave. The budget is in wall time, so
/// how many shadows it buys depends on the machine's load: alone the walk read 4.88/255
/// against 13.20 with no shadow, amid the rest of this suite on 2 cores 7.19.
#[test]
fn the_report_walks_the_scenes_of_many_lamps() {
    let dir = std::env::temp_dir().join(format!("harness-report-lamps-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let opts = ReportOptions {
        quick: true,
        out: dir.clone(),
        scenes: Some(vec!["room-lamps".into()]),
        techniques: None,
        registry: soft_shadow_techniques::registry(),
        resolutions: None,
        backend: BackendChoice::Cpu,
        scene_files: Vec::new(),
        as_seen: None,
        size: None,
        memory: Default::default(),
    };
    let report = run(&opts).expect("report runs");
    assert!(report.runs.is_empty(), "only the walk runs");
    assert_eq!(report.frames.len(), 1);
    let walk = &report.frames[0];
    assert_eq!((walk.scene.as_str(), walk.lamps), ("room-lamps", 3));
    assert_eq!(walk.frames.len(), 8);
    for f in &walk.frames {
        assert_eq!(f.lamps.len(), 3);
        assert!(f.ms > 0.0 && f.image_255.is_finite() && f.no_shadow_255 > 0.0);
    }
    let mean = |g: fn(&harness::frames::FrameMeasure) -> f64| {
        walk.frames.iter().map(g).sum::<f64>() / walk.frames.len() as f64
    };
    let (with, without) = (mean(|f| f.image_255), mean(|f| f.no_shadow_255));
    println!("room-lamps walk: frame image error {with:.2}/255, no shadow {without:.2}");
    assert!(
        with < 0.75 * without,
        "{with:.2} against {without:.2} with no shadow"
    );
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("## Scenes of many lamps"), "{md}");
    assert!(md.contains("[frames-room-lamps.md](frames-room-lamps.md)"));
    let doc = std::fs::read_to_string(dir.join("frames-room-lamps.md")).unwrap();
    assert!(
        doc.contains("harness frames --scene room-lamps --budget-ms 33"),
        "{doc}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    let frames = json["frames"][0]["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 8);
    for key in [
        "ms",
        "core_ms",
        "predicted_ms",
        "maps_generated",
        "image_255",
        "no_shadow_255",
    ] {
        assert!(frames[0][key].is_number(), "frames[].{key}");
    }
    for key in ["kind", "pick", "contribution", "image_255", "no_shadow_255"] {
        assert!(
            !frames[0]["lamps"][0][key].is_null(),
            "frames[].lamps[].{key}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn quick_report_writes_the_contract() {
    let dir = std::env::temp_dir().join(format!("harness-report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let opts = ReportOptions {
        quick: true,
        out: dir.clone(),
        scenes: Some(vec!["plane-occluder".into(), "linear-bar".into()]),
        techniques: None,
        registry: soft_shadow_techniques::registry(),
        resolutions: Some(vec![64, 256, 512]),
        backend: BackendChoice::Cpu,
        scene_files: Vec::new(),
        as_seen: None,
        size: Some(64),
        memory: Default::default(),
    };
    let report = run(&opts).expect("report runs");
    // The page reads offline: every image, sprite and link it names is a file of the report,
    // nothing is fetched from the network, and each scene's strip is a grid of labelled tiles
    // with filters.
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let mut targets = Vec::new();
    for (open, close) in [("src=\"", '"'), ("href=\"", '"'), ("url('", '\'')] {
        for part in html.split(open).skip(1) {
            targets.push(part.split(close).next().unwrap().to_string());
        }
    }
    assert!(targets.len() > 10, "{targets:?}");
    for t in &targets {
        assert!(!t.contains("://"), "the page fetches {t}");
        assert!(
            dir.join(t).is_file(),
            "the page names {t}, which is not in the report"
        );
    }
    assert!(
        html.contains("<figure class=\"tile\" data-technique=\"pcf\""),
        "no tiles"
    );
    assert!(
        html.contains("data-key=\"res\" value=\"512\""),
        "no resolution filter"
    );
    // The EXR files hold what the README says: one float channel `V` for scalars, X, Y, Z for
    // the G-buffer, ZIP-compressed, 64² pixels, NaN where no receiver is.
    for (f, names) in [
        ("exr/linear-bar/reference.exr", vec!["V"]),
        ("exr/linear-bar/gbuffer-position.exr", vec!["X", "Y", "Z"]),
        ("exr/plane-occluder/pcf-r2-cpu-256.exr", vec!["V"]),
    ] {
        use exr::prelude::*;
        let image = read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .all_layers()
            .all_attributes()
            .from_file(dir.join(f))
            .unwrap_or_else(|e| panic!("{f}: {e}"));
        let layer = &image.layer_data[0];
        let got: Vec<String> = layer
            .channel_data
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        assert_eq!(got, names, "{f}");
        assert_eq!(layer.size, Vec2(64, 64), "{f}");
        assert_eq!(layer.encoding.compression, Compression::ZIP16, "{f}");
        let v = &layer.channel_data.list[0].sample_data;
        assert!(v.values_as_f32().any(|x| x.is_finite()), "{f}: no data");
    }
    for f in [
        "report.json",
        "report.md",
        "index.html",
        "pareto.png",
        "plane-occluder.png",
        "pareto-linear-bar.png",
        "exr/linear-bar/reference.exr",
        "exr/linear-bar/gbuffer-position.exr",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(json["version"], 1);
    for key in ["cpu", "threads", "gpu_adapter"] {
        assert!(!json["machine"][key].is_null(), "machine.{key}");
    }
    let runs = json["runs"].as_array().unwrap();
    // Hard, PCF, PCSS, and the quick report's 16-sample accumulation in both sample patterns.
    let techniques = 5 + shadow_width::ShadowWidth::standard_set().len();
    let penumbra = penumbra_limit::PenumbraLimit::standard_set().len();
    // The quick report's occlusion-slices: its family's quick tier (the chained SAT slices run
    // in the full report only).
    let slices = occlusion_slices::families()[0]
        .variants_in(soft_shadow_core::Tier::Quick)
        .count();
    let linear = linear_light::LinearLight::standard_set().len();
    assert_eq!(
        runs.len(),
        (2 * techniques + penumbra + slices + linear) * 3,
        "2 scenes x (5 baselines + shadow-width variants) x 3 resolutions, plus penumbra-limit \
         and occlusion-slices on plane-occluder only (both report a segment light as unsupported) \
         and linear-light on linear-bar only (segments only)"
    );
    assert!(
        runs.iter()
            .any(|r| r["technique"] == "linear-light" && r["scene"] == "linear-bar"),
        "no linear-light rows"
    );
    assert!(
        runs.iter()
            .any(|r| r["technique"] == "occlusion-slices" && r["scene"] == "plane-occluder"),
        "no occlusion-slices rows"
    );
    assert!(
        runs.iter()
            .any(|r| r["technique"] == "penumbra-limit" && r["scene"] == "plane-occluder"),
        "no penumbra-limit rows"
    );
    assert!(
        !runs
            .iter()
            .any(|r| r["technique"] == "penumbra-limit" && r["scene"] == "linear-bar"),
        "penumbra-limit does not model segment lights"
    );
    assert!(
        runs.iter().any(|r| r["technique"] == "shadow-width"),
        "no shadow-width rows"
    );
    for r in runs {
        for key in [
            "scene",
            "technique",
            "variant",
            "backend",
            "resolution",
            "generate_ms",
            "evaluate_ms",
            "rms_255",
            "penumbra_rms_255",
            "image_rms_255",
            "image_penumbra_rms_255",
            "max_abs_255",
            "false_shadow_pixels",
            "nonfinite",
        ] {
            assert!(!r[key].is_null(), "run field {key}");
        }
        assert_eq!(r["nonfinite"], 0);
        for class in ["ground", "object", "terminator"] {
            for key in ["pixels", "rms_255", "image_rms_255"] {
                assert!(!r["classes"][class][key].is_null(), "classes.{class}.{key}");
            }
        }
    }
    // Weights are E0 / E0_max <= 1, so the image error never exceeds the V error, and the
    // ground and object classes partition the receivers.
    for r in &report.runs {
        let e = &r.errors;
        assert!(e.image_rms_255 <= e.rms_255 + 1e-9, "{r:?}");
        assert!(e.image_rms_255 > 0.0 || e.rms_255 == 0.0, "{r:?}");
    }
    for r in &report.references {
        assert!(
            r.std_error_255 < 1.0,
            "{}: reference std error {}",
            r.scene,
            r.std_error_255
        );
        assert!(r.penumbra_receivers > 0, "{} has a penumbra", r.scene);
    }
    // Accumulation of 16 samples beats the hard shadow map on the soft plane-occluder scene.
    let rms = |t: &str| {
        report
            .runs
            .iter()
            .find(|r| r.scene == "plane-occluder" && r.technique == t && r.resolution == 256)
            .unwrap()
            .errors
            .rms_255
    };
    assert!(rms("accumulation") < rms("hard-shadow-map"));
    // The summary: per light kind and budget, the best configuration fits the budget, is the
    // minimum error among those that fit, and is never worse than the best baseline.
    let configs = summary::configs(&report);
    assert_eq!(
        configs.keys().cloned().collect::<Vec<_>>(),
        vec!["linear".to_string(), "rect".to_string()]
    );
    for l in summary::lines(&report) {
        let fits: Vec<_> = configs[&l.light]
            .iter()
            .filter(|c| c.time_ms <= l.budget_ms)
            .collect();
        match &l.best {
            None => assert!(fits.is_empty()),
            Some(b) => {
                assert!(b.time_ms <= l.budget_ms);
                assert!(fits.iter().all(|c| b.image_rms_255 <= c.image_rms_255));
                if let Some(base) = &l.baseline {
                    assert!(b.image_rms_255 <= base.image_rms_255);
                    assert!(summary::BASELINES.contains(&base.technique.as_str()));
                }
            }
        }
    }
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        md.contains("## Summary") && md.contains("| rect | 2 |"),
        "{md}"
    );
    assert!(md.contains("## Scaling"));
    let exps = summary::scaling_exponents(&report);
    assert!(!exps.is_empty() && exps.iter().all(|(_, e, n)| e.is_finite() && *n == 2));
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(html.contains("<table>") && html.contains("url('plane-occluder.png')"));
    // The overall chart is shown; the papers page is named with the command that writes it
    // (linked once it is there: no dead link).
    assert!(html.contains("<img src=\"pareto.png\"") && !html.contains("href=\"papers.html\""));
    assert!(md.contains("papers --out` this folder writes `papers.html`"));
    assert_eq!(
        html.matches("<table>").count(),
        md.matches("\n|---").count()
    );
}

/// The image error weights each receiver's `V` error by `E0 / E0_max`, and splits it by class.
#[test]
fn image_error_weights_each_receiver_by_its_irradiance() {
    use harness::metrics::{Shading, errors};
    // E0 of 4, 2, 1 and 0 (an unlit-looking receiver at the horizon): weights 1, 0.5, 0.25, 0.
    let shading = Shading::new(
        &[4.0, 2.0, 1.0, 0.0],
        vec![false, true, true, false],
        vec![false, false, true, true],
    );
    assert_eq!(shading.weight, [1.0, 0.5, 0.25, 0.0]);
    let reference = [1.0, 0.5, 0.5, 1.0];
    let v = [0.8, 0.3, 0.1, 0.0];
    let e = errors(&v, &reference, &shading);
    let d = [0.2 * 255.0, 0.2 * 255.0, 0.4 * 255.0, 255.0];
    let image = [d[0], d[1] * 0.5, d[2] * 0.25, 0.0];
    let rms = |x: &[f64]| (x.iter().map(|x| x * x).sum::<f64>() / x.len() as f64).sqrt();
    assert!((e.rms_255 - rms(&d)).abs() < 1e-3);
    assert!((e.image_rms_255 - rms(&image)).abs() < 1e-3);
    // Penumbra: the two receivers at 0.5.
    assert!((e.image_penumbra_rms_255 - rms(&image[1..3])).abs() < 1e-3);
    assert_eq!(e.classes.object.pixels, 2);
    assert!((e.classes.object.image_rms_255 - rms(&image[1..3])).abs() < 1e-3);
    assert!((e.classes.ground.rms_255 - rms(&[d[0], d[3]])).abs() < 1e-3);
    assert_eq!(e.classes.terminator.pixels, 2);
    assert!((e.classes.terminator.image_rms_255 - rms(&[image[2], image[3]])).abs() < 1e-3);
}

/// False shadows (the acne measure): receivers the reference sees lit (>= 0.98) that come out
/// below 0.98; penumbra and umbra receivers never count.
#[test]
fn false_shadow_pixels_count_only_lit_receivers_made_dark() {
    let reference = [1.0, 1.0, 0.5, 0.99, 0.0, 0.98];
    let v = [0.97, 1.0, 0.1, 0.5, 0.9, 0.979];
    let e = harness::metrics::errors(&v, &reference, &harness::metrics::Shading::uniform(v.len()));
    assert_eq!(e.false_shadow_pixels, 3);
}

/// Hard cases recast for the techniques that do not model their light, flicker on the flicker
/// scenes only, and the stability sections of `report.md`.
#[test]
fn report_recasts_hard_cases_and_measures_flicker() {
    let dir = std::env::temp_dir().join(format!("harness-report-relit-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let opts = ReportOptions {
        quick: true,
        out: dir.clone(),
        scenes: Some(vec!["acne".into(), "overlap".into()]),
        techniques: Some(vec![
            "pcf".into(),
            "occlusion-slices".into(),
            "linear-light".into(),
        ]),
        registry: soft_shadow_techniques::registry(),
        resolutions: Some(vec![64]),
        backend: BackendChoice::Cpu,
        scene_files: Vec::new(),
        as_seen: None,
        size: Some(48),
        memory: Default::default(),
    };
    let report = run(&opts).expect("report runs");
    let names: Vec<(&str, Option<&str>)> = report
        .references
        .iter()
        .map(|r| (r.scene.as_str(), r.relit_from.as_deref()))
        .collect();
    assert_eq!(
        names,
        [
            ("acne", None),
            ("acne@rect", Some("acne")),
            ("acne@linear", Some("acne")),
            ("overlap", None),
        ],
        "overlap is no hard case: nothing is recast there"
    );
    let techniques_on = |scene: &str| -> Vec<String> {
        let mut t: Vec<String> = report
            .runs
            .iter()
            .filter(|r| r.scene == scene)
            .map(|r| r.technique.clone())
            .collect();
        t.dedup();
        t
    };
    assert_eq!(techniques_on("acne"), ["pcf"]);
    assert_eq!(techniques_on("acne@rect"), ["occlusion-slices"]);
    assert_eq!(techniques_on("acne@linear"), ["linear-light"]);
    for r in &report.runs {
        match r.scene.as_str() {
            "overlap" => {
                let f = r.flicker_255.expect("flicker on overlap");
                assert!(f.is_finite() && f >= 0.0, "{f}");
            }
            _ => assert_eq!(r.flicker_255, None, "{}: no flicker", r.scene),
        }
        if r.scene.starts_with("acne") {
            assert_eq!(
                r.errors.false_shadow_pixels,
                0,
                "{} {}",
                r.scene,
                r.series()
            );
        }
    }
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for section in [
        "## Summary",
        "## Temporal stability",
        "## Acne",
        "## Pareto fronts",
        "## acne@rect",
    ] {
        assert!(md.contains(section), "report.md lacks {section}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The report times a renderer's steady state: one unmeasured generation precedes the timed
/// ones, since a first CPU generation that faults in fresh pages measured 3-8x the steady
/// time (occlusion-slices sat-8 on `torus` at 2048²: 152 ms, then 18-22 ms) and configurations
/// slower than the repetition budget are timed once. One timed repetition therefore costs two
/// generations and one evaluation; a technique timed beside runs the same loop first.
#[test]
fn cpu_timings_follow_an_unmeasured_generation() {
    use harness::report::all_techniques;
    use harness::report::measure::{Frame, repeat};
    use harness::setup::PreparedScene;
    use soft_shadow_reference::ground_truth::GroundTruthSettings;
    use soft_shadow_reference::scenes::catalogue::build;
    use std::cell::Cell;

    let t = all_techniques(false)
        .into_iter()
        .find(|t| t.name() == "hard-shadow-map")
        .expect("the hard shadow map is registered");
    let settings = GroundTruthSettings {
        strata_side: 2,
        replicates: 2,
        ..GroundTruthSettings::default()
    };
    let p = PreparedScene::new(build("plane-occluder").unwrap(), 16, settings).unwrap();
    let (generated, evaluated) = (Cell::new(0), Cell::new(0));
    // The report's own call on the CPU: no warm-up evaluation (that is the GPU's first use).
    let m = repeat(
        Frame {
            generate: &|| {
                generated.set(generated.get() + 1);
                t.generate(
                    soft_shadow_core::Context::Cpu(crate::common::cpu()),
                    &p.geometry,
                    &p.spec.light,
                    64,
                )
            },
            evaluate: &|maps: &soft_shadow_core::AnyMaps| {
                evaluated.set(evaluated.get() + 1);
                maps.evaluate(None, &p.receivers())
            },
            recycle: &|maps: soft_shadow_core::AnyMaps| maps.recycle(None),
        },
        None,
        1,
        false,
    )
    .unwrap();
    assert_eq!(m.v.len(), p.positions.len());
    assert_eq!(generated.get(), 2, "one unmeasured, one timed");
    assert_eq!(evaluated.get(), 1, "only the timed one evaluated");
    assert!(m.beside_ms.is_none());

    // With the hard map timed beside (as the report does at its cost table's resolution): its
    // own unmeasured frame (evaluated: it may be its first use) and timed frames first, then
    // the configuration's, each technique run after run.
    let steps = std::cell::RefCell::new(Vec::new());
    // The hard map at `res`, logging its steps as `generate` and `evaluate`.
    let logged = |generate: &'static str, evaluate: &'static str, res: u32| {
        let steps = &steps;
        let (t, p) = (&t, &p);
        (
            move || {
                steps.borrow_mut().push(generate);
                t.generate(
                    soft_shadow_core::Context::Cpu(crate::common::cpu()),
                    &p.geometry,
                    &p.spec.light,
                    res,
                )
            },
            move |maps: &soft_shadow_core::AnyMaps| {
                steps.borrow_mut().push(evaluate);
                maps.evaluate(None, &p.receivers())
            },
            move |maps: soft_shadow_core::AnyMaps| maps.recycle(None),
        )
    };
    let (own, beside) = (
        logged("generate", "evaluate", 64),
        logged("beside generate", "beside evaluate", 32),
    );
    let m = repeat(Frame::of(&own), Some(Frame::of(&beside)), 2, false).unwrap();
    assert_eq!(
        steps.into_inner(),
        [
            "beside generate",
            "beside evaluate",
            "beside generate",
            "beside evaluate",
            "beside generate",
            "beside evaluate",
            "generate",
            "generate",
            "evaluate",
            "generate",
            "evaluate",
        ]
    );
    let (g, e) = m.beside_ms.expect("times of the technique beside");
    assert!(g >= 0.0 && e >= 0.0);
}

/// `--as-seen` measures any scene asked for at viewing resolution, built-in or from a scene
/// file (here a scene file alone, which measures none by default), with its image error beside
/// FLIP; a name that is no scene is a usage error that names it, and nothing is written.
#[test]
fn as_seen_measures_any_scene_asked_for() {
    let dir = std::env::temp_dir().join(format!("harness-report-seen-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/suzanne.toml");
    let spec = soft_shadow_reference::scenes::scene_file::load(&file).unwrap();
    let opts = |as_seen: Vec<String>| ReportOptions {
        quick: true,
        out: dir.clone(),
        scenes: None,
        techniques: Some(vec!["pcss".into()]),
        registry: soft_shadow_techniques::registry(),
        resolutions: Some(vec![128]),
        backend: BackendChoice::Cpu,
        scene_files: vec![file.clone()],
        as_seen: Some(as_seen),
        size: Some(32),
        memory: Default::default(),
    };
    let report = run(&opts(vec![spec.name.clone()])).expect("report runs");
    assert_eq!(report.as_seen.len(), 1, "{:?}", report.as_seen);
    let r = &report.as_seen[0];
    assert_eq!(
        (r.scene.as_str(), r.technique.as_str()),
        (spec.name.as_str(), "pcss")
    );
    assert!(r.receivers > 100_000, "{r:?}");
    // PCSS at 128² is not the reference: an error, but a small one.
    assert!(r.image_rms_255 > 0.0 && r.image_rms_255 < 20.0, "{r:?}");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains(&format!("### {} as seen", spec.name)), "{md}");
    assert!(
        dir.join(harness::report::seen::picture_file(&spec.name))
            .is_file()
    );

    let _ = std::fs::remove_dir_all(&dir);
    let e = run(&opts(vec!["no-such-scene".into()])).expect_err("an unknown name");
    assert!(e.to_string().contains("\"no-such-scene\""), "{e}");
    assert!(!dir.exists(), "nothing is written");
}
