//! Every `.wgsl` file of the workspace parses and validates with naga, on any machine, as the
//! GPU code builds it: `soft_shadow_core::gpu::wgsl::resolve` puts the files its
//! `// requires: light_space.wgsl [sibling.wgsl ...]` header names first.
//! A file that starts with `// tail:` is an entry point appended to a technique's visibility
//! module; every technique's module is validated with each tail, as the pipelines build them.

use std::path::{Path, PathBuf};

fn wgsl_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            if p.file_name().is_some_and(|n| n != "target") {
                wgsl_files(&p, out);
            }
        } else if p.extension().is_some_and(|x| x == "wgsl") {
            out.push(p);
        }
    }
}

#[test]
fn every_wgsl_file_validates() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let mut checked = 0;
    for entry in std::fs::read_dir(crates).unwrap().flatten() {
        let mut files = Vec::new();
        wgsl_files(&entry.path(), &mut files);
        // The crate's files by name, as its `WGSL` list gives them to the resolver.
        let sources: Vec<(String, String)> = files
            .iter()
            .map(|f| {
                let name = f.file_name().unwrap().to_string_lossy().into_owned();
                (name, std::fs::read_to_string(f).unwrap())
            })
            .collect();
        let named: Vec<(&str, &str)> = sources
            .iter()
            .map(|(n, s)| (n.as_str(), s.as_str()))
            .collect();
        for (f, (name, text)) in files.iter().zip(&sources) {
            if text.starts_with("// tail:") {
                continue;
            }
            let src = soft_shadow_core::gpu::wgsl::resolve(name, &named)
                .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            validate(&f.display().to_string(), &src);
            checked += 1;
        }
    }
    assert!(checked >= 20, "{checked} files");
}

fn validate(name: &str, src: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(src)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(src)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    module
}

/// Every technique's `visibility()` module, alone, with each shared entry point, and moved to
/// another bind group: it declares `fn visibility(vec3<f32>, vec3<f32>) -> f32` and binds only
/// in the group it was given.
#[test]
fn every_visibility_module_validates_with_each_entry_point() {
    use soft_shadow_core::gpu::visibility::{RECEIVER_TEXTURES_WGSL, RECEIVERS_WGSL, in_group};
    let mut seen = std::collections::HashSet::new();
    for t in harness::report::options::all_techniques(false) {
        if !seen.insert(t.name()) {
            continue;
        }
        let src = t.visibility_wgsl();
        let module = validate(t.name(), &src);
        let f = module
            .functions
            .iter()
            .map(|(_, f)| f)
            .find(|f| f.name.as_deref() == Some("visibility"))
            .unwrap_or_else(|| panic!("{}: no fn visibility", t.name()));
        assert_eq!(f.arguments.len(), 2, "{}", t.name());
        assert!(f.result.is_some(), "{}", t.name());
        for tail in [RECEIVERS_WGSL, RECEIVER_TEXTURES_WGSL] {
            validate(t.name(), &format!("{src}\n{tail}"));
        }
        let moved = validate(t.name(), &in_group(&src, 2));
        for (_, g) in moved.global_variables.iter() {
            if let Some(b) = &g.binding {
                assert_eq!(b.group, 2, "{}: {:?}", t.name(), g.name);
            }
        }
    }
}

/// Every Rust struct the GPU reads as a uniform or storage element has the size naga gives the
/// WGSL struct it mirrors (a missing, extra or re-typed field changes it).
#[test]
fn uniform_structs_match_their_wgsl_layout() {
    use soft_shadow_core::gpu::wgsl::resolve;
    use std::mem::size_of;
    let files = |list: &[(&'static str, &'static str)]| list.to_vec();
    let core = files(&[]);
    // (crate, its WGSL files, file, WGSL struct, size of the Rust struct)
    type Case = (
        &'static str,
        Vec<(&'static str, &'static str)>,
        &'static str,
        &'static str,
        usize,
    );
    let cases: [Case; 11] = [
        (
            "shadow-core",
            core.clone(),
            "light_space.wgsl",
            "MapView",
            size_of::<soft_shadow_core::MapParams>(),
        ),
        (
            "shadow-core",
            core,
            "light_space.wgsl",
            "Bias",
            size_of::<soft_shadow_core::Bias>(),
        ),
        (
            "shadow-maps",
            files(shadow_maps::gpu::WGSL),
            "shadow_map_eval.wgsl",
            "Params",
            size_of::<shadow_maps::filters::EvalParams>(),
        ),
        (
            "shadow-width",
            files(shadow_width::gpu::WGSL),
            "evaluate.wgsl",
            "EvalParams",
            size_of::<shadow_width::eval::EvalParams>(),
        ),
        (
            "penumbra-limit",
            files(penumbra_limit::gpu::pipelines::WGSL),
            "evaluate.wgsl",
            "EvalParams",
            size_of::<penumbra_limit::eval::EvalParams>(),
        ),
        (
            "penumbra-limit",
            files(penumbra_limit::gpu::pipelines::WGSL),
            "warp.wgsl",
            "Warp",
            size_of::<penumbra_limit::warp::Warp>(),
        ),
        (
            "occlusion-slices",
            files(occlusion_slices::gpu::pipelines::WGSL),
            "frame.wgsl",
            "Frame",
            size_of::<occlusion_slices::Frame>(),
        ),
        (
            "occlusion-slices",
            files(occlusion_slices::gpu::pipelines::WGSL),
            "evaluate.wgsl",
            "EvalParams",
            size_of::<occlusion_slices::gpu::EvalParams>(),
        ),
        (
            "linear-light",
            files(linear_light::gpu::pipelines::WGSL),
            "evaluate.wgsl",
            "EvalParams",
            size_of::<linear_light::gpu::EvalParams>(),
        ),
        (
            "linear-light",
            files(linear_light::gpu::pipelines::WGSL),
            "sample.wgsl",
            "Sample",
            size_of::<linear_light::gpu::SampleGpu>(),
        ),
        (
            "example-renderer",
            vec![(
                "shade.wgsl",
                include_str!("../../../example-renderer/src/shade.wgsl"),
            )],
            "shade.wgsl",
            "Shade",
            size_of::<example_renderer::shade::ShadeUniform>(),
        ),
    ];
    for (krate, list, file, name, rust) in cases {
        let src = resolve(file, &list).unwrap();
        let module = naga::front::wgsl::parse_str(&src).unwrap();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let (handle, _) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("{krate}: no struct {name} in {file}"));
        let wgsl = layouter[handle].size as usize;
        assert_eq!(
            rust, wgsl,
            "{krate}: {name} in {file}: Rust {rust} bytes, WGSL {wgsl}"
        );
    }
}
