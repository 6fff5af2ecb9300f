//! Finds the catalogue's models. They live in the repository's `assets/` folder and ship in no
//! published crate (the Stanford bunny's licence allows research use with acknowledgement, not
//! redistribution): built from a checkout, `cfg(repository_models)` is set and
//! `SHADOW_REFERENCE_ASSETS` names the folder the catalogue includes them from; built elsewhere,
//! the scenes that need a model return an error that says so.

use std::path::Path;

/// The models the catalogue's scenes place.
const MODELS: [&str; 3] = ["stanford-bunny.glb", "teapot.glb", "suzanne.glb"];

fn main() {
    println!("cargo::rustc-check-cfg=cfg(repository_models)");
    println!("cargo::rerun-if-changed=build.rs");
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let assets = Path::new(&manifest).join("../../assets");
    if assets.is_dir() {
        // The folder too: a model put back with its old time changes the folder's.
        println!("cargo::rerun-if-changed={}", assets.display());
    }
    if MODELS.iter().all(|m| assets.join(m).is_file()) {
        let assets = assets.canonicalize().expect("the assets folder exists");
        for m in MODELS {
            println!("cargo::rerun-if-changed={}", assets.join(m).display());
        }
        println!("cargo::rustc-cfg=repository_models");
        println!(
            "cargo::rustc-env=SHADOW_REFERENCE_ASSETS={}",
            assets.display()
        );
    }
}
