//! Eisemann & Décoret 2006, Figures 2, 3 and 6: occlusion textures.
//!
//! - Figures 2-3: several overlapping occluders at different heights under a square light; the
//!   three pre-filters (mipmap, N-Buffers, summed-area table) and the three ways of combining
//!   slices (maximum, sum, the paper's product).
//! - Figure 6: thin occluders (two wings of zero thickness, steep enough to cross several slices)
//!   leak light through the gaps between slices; the fix fills the next slice too.

use super::{Claim, Experiment, Row, measure_run, prepare, scene};
use crate::report::json::Run;
use glam::{Vec2, Vec3};
use occlusion_slices::{Combination, OcclusionSlices, Prefilter};
use soft_shadow_core::{Light, Result};
use soft_shadow_reference::scenes::shapes::{horizontal_rect, quad_grid};

/// Scene name of Figures 2-3.
pub const ID_FIG3: &str = "eisemann-fig3";
/// Scene name of Figure 6.
pub const ID_FIG6: &str = "eisemann-fig6";

/// Map resolution of both.
pub const RESOLUTION: u32 = 256;

/// Slices.
pub const SLICES: u32 = 8;

/// A receiver leaks when it comes out this much brighter than the reference.
pub const LEAK: f32 = 0.25;

fn light() -> Light {
    Light::Rect {
        center: Vec3::new(0.0, 3.0, 0.0),
        u_half: Vec3::X * 0.4,
        v_half: Vec3::Z * 0.4,
    }
}

/// Figures 2-3: three 0.8 m plates at 0.5, 1.0 and 1.5 m, each shifted 0.35 m along x.
pub fn spec_fig3() -> soft_shadow_reference::scenes::SceneSpec {
    let plate = |i: f32| {
        let x = -0.75 + 0.35 * i;
        horizontal_rect(
            &format!("plate-{i}"),
            Vec2::new(x, x + 0.8),
            Vec2::new(-0.4, 0.4),
            0.5 + 0.5 * i,
        )
    };
    scene(
        ID_FIG3,
        "Eisemann Fig. 2-3: overlapping occluders at three heights",
        vec![plate(0.0), plate(1.0), plate(2.0)],
        light(),
        Vec3::ZERO,
        1.8,
    )
}

/// Figure 6: two thin wings (open sheets) rising 60 degrees from a 0.9 m high spine.
pub fn spec_fig6() -> soft_shadow_reference::scenes::SceneSpec {
    let (s, c) = (60f32.to_radians().sin(), 60f32.to_radians().cos());
    let wing = |name: &str, dir: f32| {
        quad_grid(
            name,
            Vec3::new(0.0, 0.9, -0.5),
            Vec3::new(dir * 0.6 * c, 0.6 * s, 0.0),
            Vec3::Z,
            4,
        )
    };
    scene(
        ID_FIG6,
        "Eisemann Fig. 6: thin wings crossing several slices",
        vec![wing("wing-left", -1.0), wing("wing-right", 1.0)],
        light(),
        Vec3::ZERO,
        1.6,
    )
}

fn leaks(v: &[f32], reference: &[f32]) -> usize {
    v.iter()
        .zip(reference)
        .filter(|&(&x, &r)| x - r > LEAK)
        .count()
}

/// Runs both at G-buffer side `size`.
pub fn run(size: u32) -> Result<(Vec<Experiment>, Vec<Run>)> {
    let mut runs = Vec::new();
    let p = prepare(spec_fig3(), size)?;
    let mut filter_rows = Vec::new();
    let mut rms = std::collections::BTreeMap::new();
    for f in Prefilter::ALL {
        let t = OcclusionSlices::new(SLICES, f);
        let (r, _) = measure_run(ID_FIG3, &t, &p, RESOLUTION, None)?;
        rms.insert(f.name().to_string(), r.errors.rms_255);
        filter_rows.push(Row {
            label: format!("{} ({} slices, product)", f.name(), SLICES),
            published: vec![None, None],
            ours: vec![Some(r.errors.rms_255), Some(r.generate_ms)],
        });
        runs.push(r);
    }
    let mut comb = Vec::new();
    let mut comb_rows = Vec::new();
    for c in Combination::ALL {
        let t = OcclusionSlices::new(SLICES, Prefilter::Sat).with_combination(c);
        let (r, _) = measure_run(ID_FIG3, &t, &p, RESOLUTION, None)?;
        comb.push(r.errors.rms_255);
        comb_rows.push(Row {
            label: format!("{} (SAT, {} slices)", c.name(), SLICES),
            published: vec![None, None],
            ours: vec![Some(r.errors.rms_255), Some(r.errors.penumbra_rms_255)],
        });
        runs.push(r);
    }
    let (product, sum, max) = (comb[0], comb[1], comb[2]);
    let setup = format!(
        "Three 0.8 m plates at 0.5, 1.0 and 1.5 m, each shifted 0.35 m, under a 0.8 m square \
         light 3 m up; ground seen top-down ({size}²); {SLICES} slices of {RESOLUTION}². The \
         paper shows images: its claims are orderings."
    );
    let fig2 = Experiment {
        id: ID_FIG3.into(),
        paper: "Eisemann & Décoret 2006, occlusion textures".into(),
        figure: "Figure 2 (pre-filters)".into(),
        setup: setup.clone(),
        metric: "RMS of (V - V_ref) * 255 over the ground image; generation ms (CPU)".into(),
        columns: vec!["rms".into(), "generation ms".into()],
        rows: filter_rows,
        claims: vec![Claim::new(
            "N-Buffers and summed-area tables filter exact boxes, closer than mipmaps",
            rms["nbuffer"] <= rms["mipmap"] && rms["sat"] <= rms["mipmap"],
            format!(
                "nbuffer {:.2}, sat {:.2} vs mipmap {:.2}",
                rms["nbuffer"], rms["sat"], rms["mipmap"]
            ),
        )],
    };
    let fig3 = Experiment {
        id: ID_FIG3.into(),
        paper: "Eisemann & Décoret 2006, occlusion textures".into(),
        figure: "Figure 3 (combining slices)".into(),
        setup,
        metric: "RMS of (V - V_ref) * 255 over the ground image, and over its penumbra".into(),
        columns: vec!["rms".into(), "penumbra rms".into()],
        rows: comb_rows,
        claims: vec![Claim::new(
            "The product combines overlapping occluders better than the sum and the maximum",
            product < sum && product < max,
            format!("product {product:.2}, sum {sum:.2}, max {max:.2}"),
        )],
    };
    // Figure 6.
    let p = prepare(spec_fig6(), size)?;
    let reference = p.reference_v();
    let mut fix_rows = Vec::new();
    let mut leaked = Vec::new();
    for thin in [false, true] {
        let mut t = OcclusionSlices::new(SLICES, Prefilter::Sat);
        t.thin_fix = thin;
        let (r, v) = measure_run(ID_FIG6, &t, &p, RESOLUTION, None)?;
        let n = leaks(&v, &reference);
        leaked.push(n);
        fix_rows.push(Row {
            label: if thin { "with the fix" } else { "without" }.into(),
            published: vec![None, None],
            ours: vec![Some(n as f64), Some(r.errors.rms_255)],
        });
        runs.push(r);
    }
    let fig6 = Experiment {
        id: ID_FIG6.into(),
        paper: "Eisemann & Décoret 2006, occlusion textures".into(),
        figure: "Figure 6 (thin occluders)".into(),
        setup: format!(
            "Two zero-thickness wings rising 60 degrees from a spine 0.9 m up (a butterfly, \
             crossing several slices) under the same light; {SLICES} SAT slices of \
             {RESOLUTION}²; ground seen top-down ({size}²). A receiver leaks when it comes out \
             more than {LEAK} brighter than the reference."
        ),
        metric: "leaked receivers; RMS of (V - V_ref) * 255".into(),
        columns: vec!["leaked receivers".into(), "rms".into()],
        rows: fix_rows,
        claims: vec![Claim::new(
            "Filling the next slice removes the light leaks of thin occluders",
            leaked[1] < leaked[0],
            format!(
                "{} leaked receivers with the fix, {} without",
                leaked[1], leaked[0]
            ),
        )],
    };
    Ok((vec![fig2, fig3, fig6], runs))
}
