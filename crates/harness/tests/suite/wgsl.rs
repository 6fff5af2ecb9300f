//! Every `.wgsl` file of the workspace parses and validates with naga, on any machine.
//! A file that starts with `// requires: light_space.wgsl [sibling.wgsl ...]` is validated as
//! the GPU code builds it: after `shadow_core::gpu::LIGHT_SPACE_WGSL` and the named siblings.
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
    let mut files = Vec::new();
    wgsl_files(crates, &mut files);
    assert!(files.len() >= 2, "found {files:?}");
    for f in files {
        let mut src = std::fs::read_to_string(&f).unwrap();
        if src.starts_with("// tail:") {
            continue;
        }
        // `// requires: light_space.wgsl [sibling.wgsl ...]`: prepended in that order.
        if let Some(line) = src
            .lines()
            .next()
            .and_then(|l| l.strip_prefix("// requires:"))
        {
            let mut head = String::new();
            for dep in line.split_whitespace() {
                if dep == "light_space.wgsl" {
                    head.push_str(shadow_core::gpu::LIGHT_SPACE_WGSL);
                } else {
                    head.push_str(&std::fs::read_to_string(f.with_file_name(dep)).unwrap());
                }
                head.push('\n');
            }
            src = format!("{head}{src}");
        }
        validate(&f.display().to_string(), &src);
    }
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
    use shadow_core::gpu::visibility::{RECEIVER_TEXTURES_WGSL, RECEIVERS_WGSL, in_group};
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
