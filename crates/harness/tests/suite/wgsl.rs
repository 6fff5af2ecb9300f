//! Every WGSL module of the workspace composes and validates with naga_oil and naga, on any
//! machine, as the GPU code builds it; every binding a module declares matches its Rust
//! declaration (`soft_shadow_core::gpu::shader`): every program of every library, every
//! variant, and every technique's visibility module with both evaluation entry points.

use naga_oil::compose::{NagaModuleDescriptor, ShaderDefValue};
use soft_shadow_core::gpu::shader::{
    self, Library, MAPS_GROUP, Program, TECHNIQUE_ALIAS, check_bindings,
};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Every library of the workspace.
fn libraries() -> [&'static Library; 8] {
    [
        &soft_shadow_core::gpu::shader::SHADERS,
        &shadow_frame::SHADERS,
        &shadow_maps::SHADERS,
        &shadow_width::SHADERS,
        &penumbra_limit::SHADERS,
        &occlusion_slices::SHADERS,
        &linear_light::SHADERS,
        &viewer::SHADERS,
    ]
}

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

/// Every `.wgsl` file is a module of one library, under the import path it declares.
#[test]
fn every_wgsl_file_is_a_module_of_a_library() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let mut files = Vec::new();
    wgsl_files(crates, &mut files);
    assert!(files.len() >= 25, "{} files", files.len());
    let modules: Vec<_> = libraries().iter().flat_map(|l| l.modules.iter()).collect();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let path = text
            .lines()
            .next()
            .and_then(|l| l.strip_prefix("#define_import_path "))
            .unwrap_or_else(|| panic!("{}: no #define_import_path first", f.display()));
        let owners: Vec<_> = modules
            .iter()
            .filter(|m| m.source == text && m.path == path)
            .collect();
        assert_eq!(
            owners.len(),
            1,
            "{}: in {} libraries",
            f.display(),
            owners.len()
        );
        assert!(!text.contains("// requires:"), "{}", f.display());
    }
    assert_eq!(modules.len(), files.len(), "a library lists a module twice");
}

/// Every module composes on its own (its maps in group 0), except the two evaluation entry
/// points, which import the technique they evaluate (composed per technique below).
#[test]
fn every_module_composes() {
    for lib in libraries() {
        let mut c = shader::composer(lib, None).unwrap_or_else(|e| panic!("{e}"));
        for m in lib.modules {
            let (_, imports, _) = naga_oil::compose::get_preprocessor_data(m.source);
            if imports.iter().any(|i| i.import == TECHNIQUE_ALIAS) {
                continue;
            }
            shader::compose_in(&mut c, lib, m.path, &[(MAPS_GROUP, 0), ("STORAGE", 0)])
                .unwrap_or_else(|e| panic!("{e}"));
        }
    }
}

/// Every program of every library, every variant: it composes and validates, and every
/// binding matches its declaration (a uniform's size, a buffer's access and stride, a
/// texture's type and dimension, a storage texture's format).
#[test]
fn every_program_composes_with_the_bindings_it_declares() {
    let mut count = 0;
    for lib in libraries() {
        for p in lib.programs {
            assert!(
                std::ptr::eq(p.library, lib),
                "{} is not {}'s",
                p.module,
                lib.name
            );
            shader::compose(p).unwrap_or_else(|e| panic!("{e}"));
            count += 1;
        }
    }
    assert!(count >= 15, "{count} programs");
}

/// Every technique's visibility module with each evaluation entry point, and flattened for a
/// renderer into another group: `fn visibility(vec3<f32>, vec3<f32>) -> f32`, binding only in
/// that group, as the maps' layout declares.
#[test]
fn every_visibility_module_composes_with_each_entry_point() {
    let mut seen = std::collections::HashSet::new();
    for t in harness::report::all_techniques(false) {
        if !seen.insert(t.name()) {
            continue;
        }
        let v = t.visibility_shader();
        for (entry, groups) in soft_shadow_core::gpu::visibility::entry_points(v) {
            let mut c = shader::composer(&shader::SHADERS, Some(v)).unwrap();
            let m = shader::compose_in(&mut c, &shader::SHADERS, entry, &[(MAPS_GROUP, 0)])
                .unwrap_or_else(|e| panic!("{}: {e}", t.name()));
            check_bindings(&m, &groups).unwrap_or_else(|e| panic!("{}: {entry}: {e}", t.name()));
        }
        let src = t.visibility_wgsl(2).unwrap();
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{}: {}", t.name(), e.emit_to_string(&src)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {e:?}", t.name()));
        let f = module
            .functions
            .iter()
            .map(|(_, f)| f)
            .find(|f| f.name.as_deref() == Some("visibility"))
            .unwrap_or_else(|| panic!("{}: no fn visibility", t.name()));
        assert_eq!(f.arguments.len(), 2, "{}", t.name());
        assert!(f.result.is_some(), "{}", t.name());
        let mut groups = vec![shader::Group::compute(&[]); 2];
        groups.push(v.maps);
        check_bindings(&module, &groups).unwrap_or_else(|e| panic!("{}: {e}", t.name()));
    }
    assert_eq!(seen.len(), 8);
}

/// `program`'s entry module with its text edited by `edit`, composed with its library.
fn compose_edited(program: &Program, edit: impl Fn(&str) -> String) -> naga::Module {
    let mut c = shader::composer(program.library, None).unwrap();
    let source = program
        .library
        .module(program.module)
        .expect("the program's module")
        .source;
    let edited = edit(source);
    assert_ne!(
        edited, source,
        "{}: the edit changed nothing",
        program.module
    );
    let defs: HashMap<String, ShaderDefValue> = program
        .defs
        .iter()
        .map(|&(k, v)| (k.to_string(), ShaderDefValue::UInt(v)))
        .collect();
    c.make_naga_module(NagaModuleDescriptor {
        source: &edited,
        file_path: program.module,
        shader_defs: defs,
        ..Default::default()
    })
    .unwrap_or_else(|e| panic!("{}: {}", program.module, e.emit_to_string(&c)))
}

/// The check fails when one binding's type changes in the WGSL: a storage buffer made
/// writable, a storage texture's format changed, a uniform struct that grows, a binding moved.
#[test]
fn a_binding_changed_in_the_wgsl_fails_the_check() {
    let program = |lib: &'static Library, module: &str| -> &'static Program {
        lib.programs
            .iter()
            .copied()
            .find(|p| p.module == module)
            .unwrap_or_else(|| panic!("no program {module}"))
    };
    let jump = program(&shadow_width::SHADERS, "shadow_width::jump_flood");
    let sat_cols = program(&occlusion_slices::SHADERS, "occlusion_slices::sat_cols");
    /// A program and an edit of its entry module's text.
    type Case = (&'static Program, fn(&str) -> String);
    let cases: [Case; 4] = [
        (jump, |s| {
            s.replace(
                "var<storage, read> src: array<u32>",
                "var<storage, read_write> src: array<u32>",
            )
        }),
        (sat_cols, |s| {
            s.replace(
                "texture_storage_2d_array<rgba32uint, write>",
                "texture_storage_2d_array<rgba16uint, write>",
            )
        }),
        (jump, |s| {
            s.replace("_pad_b: u32,", "_pad_b: u32,\n    extra: vec4<f32>,")
        }),
        (jump, |s| s.replace("@binding(2)", "@binding(3)")),
    ];
    for (p, edit) in cases {
        let good = shader::compose(p).map(|_| ());
        assert_eq!(good, Ok(()), "{}", p.module);
        let bad = compose_edited(p, edit);
        let e = check_bindings(&bad, p.groups).expect_err("the edited binding must fail");
        assert!(e.contains("@group(0) @binding("), "{}: {e}", p.module);
    }
}
