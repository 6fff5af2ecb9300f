//! Every `.wgsl` file of the workspace parses and validates with naga, on any machine.
//! A file that starts with `// requires: light_space.wgsl [sibling.wgsl ...]` is validated as
//! the GPU code builds it: after `shadow_core::gpu::LIGHT_SPACE_WGSL` and the named siblings.

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
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{}: {}", f.display(), e.emit_to_string(&src)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {e:?}", f.display()));
    }
}
