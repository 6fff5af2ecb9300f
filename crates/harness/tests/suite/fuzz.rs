//! Hostile files: mutations of the shipped `assets/suzanne.glb` and `assets/suzanne.toml` load
//! as a typed error or a valid scene, never a panic, and a valid one renders (G-buffer, a hard
//! shadow map, its evaluation) within [`CASE_SECONDS`].
//!
//! Mutations: a digit of the GLB's JSON changed, a JSON number replaced by an extreme one (the
//! GLB re-encoded with correct chunk lengths, so the change reaches glTF validation), a bit
//! flipped anywhere, the file truncated, a buffer view moved off alignment; and digit, number and
//! truncation mutations of the scene TOML. CI runs the same [`CI_CASES`] of each every time; a
//! long run draws new ones:
//!
//! `FUZZ_CASES=5000 cargo test --release --test suite fuzz`

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use shadow_frame::gltf::glb;
use shadow_maps::{Filter, ShadowMapBaseline};
use soft_shadow_core::ShadowTechnique;
use soft_shadow_reference::scenes::scene_file;
use std::path::Path;
use std::time::Instant;

/// Cases per mutation family in CI.
const CI_CASES: u32 = 48;

/// Longest a case may take, load and render together (seconds).
const CASE_SECONDS: f64 = 10.0;

/// Numbers a mutation puts in place of one in the file.
const NUMBERS: [&str; 14] = [
    "0",
    "-1",
    "1",
    "3",
    "5",
    "7",
    "255",
    "65536",
    "2147483648",
    "4294967296",
    "1e30",
    "1e999",
    "-0.0",
    "11611",
];

fn cases() -> u32 {
    std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(CI_CASES)
}

fn asset(name: &str) -> Vec<u8> {
    std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets")
            .join(name),
    )
    .unwrap()
}

/// The JSON text and the binary chunk (after its 8-byte header) of a GLB.
fn glb_split(glb: &[u8]) -> (String, Vec<u8>) {
    let u32_at = |o: usize| u32::from_le_bytes(glb[o..o + 4].try_into().unwrap()) as usize;
    let json_len = u32_at(12);
    let json = String::from_utf8(glb[20..20 + json_len].to_vec()).unwrap();
    let bin_at = 20 + json_len;
    let bin_len = u32_at(bin_at);
    (json, glb[bin_at + 8..bin_at + 8 + bin_len].to_vec())
}

/// Byte ranges of the numbers in `text`.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts =
            b[i].is_ascii_digit() || (b[i] == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit));
        if starts && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) {
            let s = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_digit() || b"+-.eE".contains(&b[i])) {
                i += 1;
            }
            out.push((s, i));
        } else {
            i += 1;
        }
    }
    out
}

/// `text` with digit `k` (modulo the count) replaced by `d`.
fn mutate_digit(text: &str, k: usize, d: u8) -> String {
    let digits: Vec<usize> = text
        .bytes()
        .enumerate()
        .filter(|(_, c)| c.is_ascii_digit())
        .map(|(i, _)| i)
        .collect();
    let mut b = text.as_bytes().to_vec();
    if !digits.is_empty() {
        b[digits[k % digits.len()]] = b'0' + d % 10;
    }
    String::from_utf8(b).unwrap()
}

/// `text` with number `k` (modulo the count) replaced by `NUMBERS[n]`.
fn mutate_number(text: &str, k: usize, n: usize) -> String {
    let nums = numbers(text);
    if nums.is_empty() {
        return text.to_string();
    }
    let (s, e) = nums[k % nums.len()];
    format!("{}{}{}", &text[..s], NUMBERS[n % NUMBERS.len()], &text[e..])
}

/// What a case came to.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
enum Outcome {
    /// A typed error.
    Refused,
    /// A typed error from a panic the import boundary caught.
    CaughtPanic,
    /// A valid scene, rendered.
    Rendered,
}

/// Loads the scene file in `dir` and, when it is valid, renders it; a typed error is fine.
fn load_and_render(dir: &Path, what: &str) -> Outcome {
    let start = Instant::now();
    let mut outcome = Outcome::Refused;
    let loaded = scene_file::load(&dir.join("scene.toml"));
    if let Err(e) = &loaded
        && e.to_string().contains("panicked")
    {
        outcome = Outcome::CaughtPanic;
    }
    if let Ok(spec) = loaded
        && let Ok((geometry, positions, normals)) =
            soft_shadow_reference::scenes::scene_receivers(&spec, 24)
    {
        outcome = Outcome::Rendered;
        let hard = ShadowMapBaseline::new(Filter::Hard);
        if let Ok(maps) = hard.generate_cpu(crate::common::cpu(), &geometry, &spec.light, 64) {
            let r = soft_shadow_core::Receivers::new(&positions, &normals);
            let v = hard.evaluate_cpu(&maps, &r).unwrap_or_default();
            assert!(v.iter().all(|x| x.is_finite()), "{what}: non-finite V");
        }
    }
    let s = start.elapsed().as_secs_f64();
    assert!(s < CASE_SECONDS, "{what}: took {s:.1} s");
    outcome
}

fn run(family: &str, strategy: impl Strategy<Value = (Vec<u8>, String)>) {
    let dir = std::env::temp_dir().join(format!("shadow-fuzz-{family}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let config = Config {
        cases: cases(),
        failure_persistence: None,
        ..Config::default()
    };
    // CI's cases are the same every run; a long run (`FUZZ_CASES`) draws new ones.
    let mut runner = if std::env::var_os("FUZZ_CASES").is_some() {
        TestRunner::new(config)
    } else {
        TestRunner::new_with_rng(
            config,
            proptest::test_runner::TestRng::deterministic_rng(
                proptest::test_runner::RngAlgorithm::ChaCha,
            ),
        )
    };
    let tally = std::sync::Mutex::new(std::collections::HashMap::<Outcome, usize>::new());
    let result = runner.run(&strategy, |(glb, toml)| {
        std::fs::write(dir.join("suzanne.glb"), &glb).unwrap();
        std::fs::write(dir.join("scene.toml"), &toml).unwrap();
        let o = load_and_render(&dir, family);
        *tally.lock().unwrap().entry(o).or_default() += 1;
        Ok(())
    });
    let _ = std::fs::remove_dir_all(&dir);
    if let Err(e) = result {
        panic!("{family}: {e}");
    }
    println!("{family}: {:?}", tally.into_inner().unwrap());
}

fn scene_toml() -> String {
    String::from_utf8(asset("suzanne.toml")).unwrap()
}

#[test]
fn mutated_glb_json_is_a_typed_error_or_a_valid_scene() {
    let (json, bin) = glb_split(&asset("suzanne.glb"));
    let toml = scene_toml();
    let (j1, b1, t1) = (json.clone(), bin.clone(), toml.clone());
    run(
        "glb-digit",
        (any::<usize>(), 0u8..10)
            .prop_map(move |(k, d)| (glb(&mutate_digit(&j1, k, d), &b1), t1.clone())),
    );
    run(
        "glb-number",
        (any::<usize>(), any::<usize>())
            .prop_map(move |(k, n)| (glb(&mutate_number(&json, k, n), &bin), toml.clone())),
    );
}

#[test]
fn damaged_glb_bytes_are_a_typed_error_or_a_valid_scene() {
    let glb = asset("suzanne.glb");
    let toml = scene_toml();
    let (g1, t1) = (glb.clone(), toml.clone());
    run(
        "glb-bitflip",
        (any::<usize>(), 0u8..8).prop_map(move |(k, bit)| {
            let mut g = g1.clone();
            let i = k % g.len();
            g[i] ^= 1 << bit;
            (g, t1.clone())
        }),
    );
    run(
        "glb-truncate",
        any::<usize>().prop_map(move |k| (glb[..k % glb.len()].to_vec(), toml.clone())),
    );
}

#[test]
fn mutated_scene_files_are_a_typed_error_or_a_valid_scene() {
    let glb = asset("suzanne.glb");
    let toml = scene_toml();
    let (g1, t1) = (glb.clone(), toml.clone());
    run(
        "toml-digit",
        (any::<usize>(), 0u8..10).prop_map(move |(k, d)| (g1.clone(), mutate_digit(&t1, k, d))),
    );
    run(
        "toml-number",
        (any::<usize>(), any::<usize>(), any::<usize>()).prop_map(move |(k, n, cut)| {
            let t = mutate_number(&toml, k, n);
            // Every fourth case also truncates the mutated file.
            let t = if cut % 4 == 0 {
                t[..cut / 4 % t.len()].to_string()
            } else {
                t
            };
            (glb.clone(), t)
        }),
    );
}

/// The hang: a view moved 5 bytes, so every float is read misaligned. Refused by name.
#[test]
fn a_misaligned_buffer_view_is_refused() {
    let (json, bin) = glb_split(&asset("suzanne.glb"));
    let moved = json.replace("\"byteOffset\":11616", "\"byteOffset\":11611");
    assert_ne!(moved, json, "suzanne.glb's second view starts at 11616");
    let e = shadow_frame::gltf::import_gltf_slice(&glb(&moved, &bin), "suzanne", None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("misaligned"), "{e}");
}

/// Coordinates beyond `MAX_COORDINATE` are a typed error, not a slow or meaningless render.
#[test]
fn absurd_coordinates_are_refused() {
    let toml = scene_toml().replace("translation = [2.5, 0.0, -4.0]", "scale = 1e7");
    let dir = std::env::temp_dir().join(format!("shadow-fuzz-absurd-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("suzanne.glb"), asset("suzanne.glb")).unwrap();
    std::fs::write(dir.join("scene.toml"), toml).unwrap();
    let spec = scene_file::load(&dir.join("scene.toml")).unwrap();
    let out = soft_shadow_reference::scenes::scene_receivers(&spec, 24);
    let _ = std::fs::remove_dir_all(&dir);
    match out {
        Err(e) => assert!(e.to_string().contains("beyond"), "{e}"),
        Ok(_) => panic!("a scene scaled 1e7 was accepted"),
    }
}
