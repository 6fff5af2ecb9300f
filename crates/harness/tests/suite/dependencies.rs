//! A renderer takes one technique crate without the harness's weight: with default features off,
//! no technique crate pulls in `bevy_ecs`, `gltf`, `clap`, `plotters` or `obvhs`
//! (`cargo tree`, offline, from the lock file).

use std::process::Command;

#[test]
fn technique_crates_without_default_features_stay_light() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    for krate in [
        "shadow-maps",
        "occlusion-slices",
        "penumbra-limit",
        "shadow-width",
        "linear-light",
    ] {
        let out = Command::new(&cargo)
            .args([
                "tree",
                "--offline",
                "--no-default-features",
                "-e",
                "normal",
                "-p",
                krate,
            ])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .expect("cargo runs");
        assert!(
            out.status.success(),
            "cargo tree -p {krate}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let tree = String::from_utf8_lossy(&out.stdout);
        for heavy in ["bevy_ecs", "gltf", "clap", "plotters", "obvhs"] {
            assert!(
                !tree.contains(&format!("{heavy} v")),
                "{krate} without default features depends on {heavy}:\n{tree}"
            );
        }
        assert!(tree.contains("wgpu v"), "{krate}: {tree}");
    }
}
