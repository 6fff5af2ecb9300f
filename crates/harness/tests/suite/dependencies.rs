//! What cargo builds, read with `cargo tree` (offline, from the lock file):
//!
//! - a renderer takes one technique crate without the harness's weight: with default features
//!   off, no technique crate pulls in `bevy_ecs`, `gltf`, `clap`, `plotters` or `obvhs`, and
//!   none turns on a wgpu backend (the application chooses them);
//! - the README's two commands share one build: every package the report binary is built from
//!   has the same features under the report command as under the test command, so the report
//!   after the tests builds nothing and the tests after the report rebuild none of its crates
//!   (`-p harness` resolved features for the harness alone and rebuilt 14 crates, 57 s on 2
//!   cores, after the tests).

use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

/// `cargo tree --offline ARGS` from the workspace's root (as the README's commands run), its
/// lines.
fn cargo_tree(args: &[&str]) -> Vec<String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(&cargo)
        .args(["tree", "--offline"])
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo tree {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| l.trim_end_matches(" (*)").to_string())
        .collect()
}

/// Per package (`name vX.Y.Z`, with its path for a member), its feature sets under a
/// resolution (`cargo tree` arguments that select packages and edges): one set, or two where
/// build scripts and proc macros use it with other features than the code.
fn features(selection: &[&str]) -> BTreeMap<String, BTreeSet<String>> {
    let mut args = selection.to_vec();
    args.extend(["-f", "{p}|{f}", "--prefix", "none"]);
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for l in cargo_tree(&args) {
        if let Some((p, f)) = l.split_once('|') {
            out.entry(p.to_string()).or_default().insert(f.to_string());
        }
    }
    out
}

/// The fenced command of the README that starts with `start`, split into words.
fn readme_command(start: &str) -> Vec<String> {
    let readme = include_str!("../../../../README.md");
    let line = readme
        .lines()
        .find(|l| l.starts_with(start))
        .unwrap_or_else(|| panic!("README has no command starting {start:?}"));
    line.split_whitespace().map(str::to_string).collect()
}

/// The README's report command resolves every package the report binary is built from with the
/// features its test command gives it: cargo builds it once for both.
#[test]
fn the_readme_commands_share_one_build() {
    let run = readme_command("cargo run --release");
    assert!(run.contains(&"report".to_string()), "{run:?}");
    let test = readme_command("cargo test");
    // The packages cargo resolves features for: those named with -p, else every default member.
    let packages = |words: &[String]| -> Vec<String> {
        let mut out = Vec::new();
        let mut it = words.iter().take_while(|w| *w != "--");
        while let Some(w) = it.next() {
            match w.as_str() {
                "-p" | "--package" => out.extend(["-p".to_string(), it.next().unwrap().clone()]),
                "--workspace" => out.push(w.clone()),
                _ => {}
            }
        }
        out
    };
    let (run_sel, test_sel) = (packages(&run), packages(&test));
    let mut run_args: Vec<&str> = run_sel.iter().map(String::as_str).collect();
    run_args.extend(["-e", "normal"]);
    let mut test_args: Vec<&str> = test_sel.iter().map(String::as_str).collect();
    test_args.extend(["-e", "normal,dev"]);
    let (under_run, under_test) = (features(&run_args), features(&test_args));
    let binary: BTreeSet<String> = cargo_tree(&[
        "-p", "harness", "-e", "normal", "-f", "{p}", "--prefix", "none",
    ])
    .into_iter()
    .collect();
    let differ: Vec<String> = binary
        .iter()
        .filter(|p| under_run.get(*p) != under_test.get(*p))
        .map(|p| format!("{p}: {:?} vs {:?}", under_run.get(p), under_test.get(p)))
        .collect();
    assert!(
        differ.is_empty(),
        "{run:?} builds these with other features than {test:?} (so one rebuilds them):\n{}",
        differ.join("\n")
    );
}

/// The technique crates, and the registry of them all.
const TECHNIQUE_CRATES: [&str; 6] = [
    "shadow-maps",
    "occlusion-slices",
    "penumbra-limit",
    "shadow-width",
    "linear-light",
    "soft-shadow-techniques",
];

/// A technique crate with its default features builds wgpu with no backend (the application
/// that makes the device chooses them) and none of the harness's weight; for the CPU alone
/// (`--no-default-features --features cpu`) it builds no wgpu, naga or naga_oil either.
#[test]
fn technique_crates_stay_light_with_and_without_the_gpu() {
    for krate in TECHNIQUE_CRATES {
        let tree = cargo_tree(&["-e", "normal", "-p", krate]).join("\n");
        for heavy in ["bevy_ecs", "gltf", "clap", "plotters", "obvhs"] {
            assert!(
                !tree.contains(&format!("{heavy} v")),
                "{krate} with its default features depends on {heavy}:\n{tree}"
            );
        }
        assert!(tree.contains("wgpu v"), "{krate}: {tree}");
        let wgpu = features(&["-p", krate, "-e", "normal"])
            .into_iter()
            .find(|(p, _)| p.starts_with("wgpu v"))
            .map(|(_, f)| f)
            .unwrap_or_else(|| panic!("{krate} does not build wgpu"));
        for backend in ["vulkan", "metal", "dx12", "gles", "webgpu"] {
            assert!(
                wgpu.iter().all(|f| !f.split(',').any(|x| x == backend)),
                "{krate} turns on wgpu's {backend}: {wgpu:?}"
            );
        }
        let cpu = cargo_tree(&[
            "--no-default-features",
            "--features",
            "cpu",
            "-e",
            "normal",
            "-p",
            krate,
        ])
        .join("\n");
        for gpu in ["wgpu", "naga", "naga_oil", "pollster", "bevy_ecs"] {
            assert!(
                !cpu.contains(&format!(" {gpu} v")) && !cpu.starts_with(&format!("{gpu} v")),
                "{krate} for the CPU alone depends on {gpu}:\n{cpu}"
            );
        }
    }
}

/// The ground truth is for measuring any technique, on any machine: the reference crate builds
/// no GPU stack (no wgpu, naga or naga_oil), nor the harness's report and command-line weight.
#[test]
fn the_reference_builds_no_gpu_stack() {
    let tree = cargo_tree(&["-e", "normal", "-p", "soft-shadow-reference"]).join("\n");
    for heavy in [
        "wgpu", "naga", "naga_oil", "pollster", "clap", "plotters", "image",
    ] {
        assert!(
            !tree.contains(&format!(" {heavy} v")),
            "soft-shadow-reference depends on {heavy}:\n{tree}"
        );
    }
}

/// The CPU-only build of every technique crate compiles (`cargo check`, in a target folder of
/// its own so the workspace's artifacts are left alone), without a warning.
#[test]
fn technique_crates_build_for_the_cpu_alone() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let mut args = vec!["check", "--offline", "--no-default-features", "--features"];
    let features = TECHNIQUE_CRATES.map(|k| format!("{k}/cpu")).join(",");
    args.push(&features);
    for krate in TECHNIQUE_CRATES {
        args.extend(["-p", krate]);
    }
    let out = Command::new(&cargo)
        .args(&args)
        .env("CARGO_TARGET_DIR", format!("{root}/target/cpu-only"))
        .env("RUSTFLAGS", "-D warnings")
        .current_dir(root)
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}
