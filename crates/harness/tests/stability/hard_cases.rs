//! Every technique x every hard-case scene x {16, 256, 2048} x both backends: finite `V` in
//! [0, 1]. One test per scene, so the test runner spreads them over the cores.

use super::common::receivers;
use super::{RESOLUTIONS, assert_stable, backends, label, scene_for, techniques, visibility};
use harness::scenes::catalogue::{SCENE_NAMES, build};

/// G-buffer side of the receivers.
const SIZE: u32 = 48;

fn hard_case(name: &str) {
    let spec = build(name).unwrap();
    assert!(spec.hard_case, "{name} is a hard case");
    let mut runs = 0;
    for t in techniques() {
        let scene = scene_for(t.as_ref(), &spec);
        let r = receivers(&scene, SIZE);
        for res in RESOLUTIONS {
            for be in backends() {
                let what = label(t.as_ref(), &scene.name, res, be);
                let v = visibility(t.as_ref(), be, &r, &scene.light, res, &what);
                assert_stable(&v, r.positions.len(), &what);
                runs += 1;
            }
        }
    }
    let expected = techniques().len() * RESOLUTIONS.len() * backends().len();
    assert_eq!(runs, expected);
}

#[test]
fn the_catalogue_has_the_guides_hard_cases() {
    let hard: Vec<&str> = SCENE_NAMES
        .iter()
        .copied()
        .filter(|n| build(n).unwrap().hard_case)
        .collect();
    assert_eq!(
        hard,
        [
            "contact",
            "grazing",
            "light-plane",
            "tiny-light",
            "huge-depth-range",
            "degenerate",
            "acne",
            "thin"
        ]
    );
}

#[test]
fn contact() {
    hard_case("contact");
}

#[test]
fn grazing() {
    hard_case("grazing");
}

#[test]
fn light_plane() {
    hard_case("light-plane");
}

#[test]
fn tiny_light() {
    hard_case("tiny-light");
}

#[test]
fn huge_depth_range() {
    hard_case("huge-depth-range");
}

#[test]
fn degenerate() {
    hard_case("degenerate");
}

#[test]
fn acne() {
    hard_case("acne");
}

#[test]
fn thin() {
    hard_case("thin");
}
