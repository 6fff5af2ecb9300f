//! Sets `cfg(no_gpu_adapter)` where the tests can tell before they run that no GPU adapter
//! exists: on Linux with no Vulkan driver installed (no ICD manifest where the Vulkan loader
//! looks, none named by `VK_ICD_FILENAMES` or `VK_DRIVER_FILES`), and `CI` unset (CI runs every
//! GPU test, and one without an adapter fails there). The tests that need nothing but the GPU are
//! then reported `ignored` by libtest, with the reason; elsewhere a test that finds no adapter at
//! run time still says so in one line and passes (`harness::testing::gpu_for_test`).

use std::path::Path;

/// Where the Vulkan loader looks for driver manifests on Linux.
const ICD_DIRS: [&str; 4] = [
    "/usr/share/vulkan/icd.d",
    "/usr/local/share/vulkan/icd.d",
    "/etc/vulkan/icd.d",
    "/usr/lib/x86_64-linux-gnu/vulkan/icd.d",
];

fn main() {
    println!("cargo::rustc-check-cfg=cfg(no_gpu_adapter)");
    println!("cargo::rerun-if-env-changed=CI");
    println!("cargo::rerun-if-env-changed=VK_ICD_FILENAMES");
    println!("cargo::rerun-if-env-changed=VK_DRIVER_FILES");
    println!("cargo::rerun-if-changed=build.rs");
    // A driver installed later adds a manifest: watch the folders that exist (a missing path
    // would rerun this script, and rebuild the harness, at every build).
    for dir in ICD_DIRS.iter().map(Path::new) {
        let watched = if dir.exists() {
            Some(dir)
        } else {
            dir.parent()
        };
        if let Some(d) = watched.filter(|d| d.exists()) {
            println!("cargo::rerun-if-changed={}", d.display());
        }
    }
    let linux = std::env::var("CARGO_CFG_TARGET_OS").is_ok_and(|os| os == "linux");
    if std::env::var_os("CI").is_some() || !linux {
        return;
    }
    let named = ["VK_ICD_FILENAMES", "VK_DRIVER_FILES"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()));
    let installed = ICD_DIRS.iter().any(|d| {
        std::fs::read_dir(d).is_ok_and(|entries| {
            entries
                .flatten()
                .any(|e| e.path().extension().is_some_and(|x| x == "json"))
        })
    });
    if !named && !installed {
        println!("cargo::rustc-cfg=no_gpu_adapter");
    }
}
