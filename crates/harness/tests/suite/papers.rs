//! The papers' own experiments (`harness papers`): each published claim our measurement
//! reproduces is asserted in its direction (an ordering, "removes leaks"), not its number.
//!
//! Claims the table marks "not reproduced" are not asserted; `papers.md` and the README say
//! which and why: Lawlor's flatness in resolution (ours matches his 11.3 at 16² and keeps
//! falling, to 1.7 at 128²), his Reeves filtering that worsens with resolution, beating 16
//! stochastic samples at 16² (10.6 vs 5.4); Kirsch's back faces (23.6 vs 22.1 front faces on a
//! closed box that does not receive). Kirsch's Table 1 claim (six neighbours
//! cost more than three) rests on one timing, so it is printed, not asserted.

use harness::papers::{Papers, run_all};
use std::sync::OnceLock;

/// Every experiment once, at the `papers` command's ground image (about 8 s).
fn papers() -> &'static Papers {
    static P: OnceLock<Papers> = OnceLock::new();
    P.get_or_init(|| run_all(harness::papers::DEFAULT_SIZE).expect("every experiment runs"))
}

fn holds(figure_id: &str, claim_prefix: &str) {
    let e = papers()
        .experiments
        .iter()
        .find(|e| e.id == figure_id && e.claim(claim_prefix).is_some())
        .unwrap_or_else(|| panic!("{figure_id}: no claim starting {claim_prefix:?}"));
    let c = e.claim(claim_prefix).unwrap();
    assert!(c.holds, "{figure_id}: {}: {}", c.claim, c.measured);
}

#[test]
fn lawlor_penumbra_limit_maps_beat_the_hard_shadow_map() {
    holds(
        "lawlor-fig10",
        "Penumbra limit maps beat the hard shadow map",
    );
    holds("lawlor-fig10", "The hard shadow map's error falls");
}

/// The paper's low-resolution numbers: 11.3 at 16² and 9.0 at 32² (ours within 1.5x or
/// below), and below Reeves filtering at every resolution. On the code before outer texels
/// beside the silhouette kept `g` at `c`, 32² measured 18.4 (the contact edge moved inwards).
#[test]
fn lawlor_penumbra_limit_maps_are_accurate_at_low_resolution() {
    holds("lawlor-fig10", "Penumbra limit maps at 16²");
    holds("lawlor-fig10", "Penumbra limit maps at 32²");
    holds("lawlor-fig10", "Penumbra limit maps beat Reeves filtering");
}

/// Section 2.2's 8-bit RGBA storage at or below the published 11.3 / 9.0 / 9.2 / 8.8 at every
/// resolution. With the map's depth range fitted to the scene's bounding sphere (16.3 m for a
/// 1.2 m triangle) it read 20.2 / 16.9 / 15.0 / 12.2.
#[test]
fn lawlor_penumbra_limit_maps_in_rgba8_match_the_published_numbers() {
    holds("lawlor-fig10", "Penumbra limit maps in 8-bit RGBA");
}

#[test]
fn heidrich_two_samples_with_skins_beat_ten_point_samples() {
    holds("heidrich-fig9", "2 samples with skins");
}

#[test]
fn heidrich_a_third_sample_removes_the_overlap_artefact() {
    holds("heidrich-fig8", "A third sample");
    holds("heidrich-fig8", "With as many samples");
}

#[test]
fn heidrich_a_triangle_lights_edges_beat_point_lights_on_them() {
    holds("heidrich-fig8-triangle", "Three linear lights");
}

#[test]
fn eisemann_product_beats_sum_and_max_and_exact_filters_beat_mipmaps() {
    holds("eisemann-fig3", "The product combines");
    holds("eisemann-fig3", "N-Buffers and summed-area tables");
}

#[test]
fn eisemann_the_thin_fix_removes_leaks() {
    holds("eisemann-fig6", "Filling the next slice");
}

#[test]
fn kirsch_low_resolution_hurts_only_where_blocker_and_receiver_are_close() {
    holds("kirsch-fig7", "At 64²");
}

#[test]
fn the_papers_files_are_written() {
    let dir = std::env::temp_dir().join(format!("harness-papers-{}", std::process::id()));
    harness::papers::write(papers(), &dir).unwrap();
    let md = std::fs::read_to_string(dir.join("papers.md")).unwrap();
    assert!(
        md.contains("| Penumbra Limit Maps (silhouette-f32) | 11.3 / "),
        "{md}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("papers.json")).unwrap()).unwrap();
    assert!(
        json["runs"]
            .as_array()
            .unwrap()
            .iter()
            .any(|r| r["scene"] == "lawlor-fig10" && r["rms_255"].is_number())
    );
    assert!(dir.join("papers.html").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_report_page_links_the_papers_page() {
    let html =
        harness::report::html::render("[Each paper's own experiment: papers.html](papers.html)\n");
    assert!(
        html.contains("<a href=\"papers.html\">Each paper's own experiment: papers.html</a>"),
        "{html}"
    );
}
