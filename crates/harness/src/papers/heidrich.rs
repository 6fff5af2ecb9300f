//! Heidrich, Brabec & Seidel 2000, Figures 8-9: soft shadow maps for linear lights.
//!
//! - Figure 9: one linear light, one blocker wide enough that the end samples' umbrae overlap,
//!   one receiver, 500² maps: the method with 2 samples against 10 uniformly spaced point
//!   samples (ray traced), both against a 200-sample ray-traced image and our Monte Carlo
//!   reference.
//! - Figure 8: two blockers whose penumbrae overlap; 2 light samples show the undersampling
//!   artefact of section 3.3, a third removes it; point-light approximations with as many
//!   samples for comparison.
//! - Figure 8 (right), section 4: the same blockers under a triangle light, as three linear
//!   lights along its edges, against point lights on the edges and the area reference.

use super::{Claim, Experiment, Row, measure_run, prepare, ray_traced_run, rms_where, scene};
use crate::report::json::Run;
use glam::{Vec2, Vec3};
use linear_light::LinearLight;
use soft_shadow_core::{Light, LightPoint, Result};
use soft_shadow_reference::scenes::shapes::horizontal_rect;

/// Scene name of Figure 9's runs.
pub const ID_FIG9: &str = "heidrich-fig9";
/// Scene name of Figure 8's runs.
pub const ID_FIG8: &str = "heidrich-fig8";
/// Scene name of the triangle light's runs (Figure 8, right).
pub const ID_TRIANGLE: &str = "heidrich-fig8-triangle";

/// The triangle light of section 4: about the segment's size, 3 m up, emitting downwards
/// (counter-clockwise seen from below).
pub fn triangle_light() -> Light {
    Light::Triangle {
        a: Vec3::new(-0.8, 3.0, -0.4),
        b: Vec3::new(0.8, 3.0, -0.4),
        c: Vec3::new(0.0, 3.0, 0.6),
    }
}

/// `n` evenly spaced points on each edge of [`triangle_light`], ends included, weighted by edge
/// length as linear-light weighs its edges.
pub fn edge_points(n: u32) -> Vec<(LightPoint, f32)> {
    let Light::Triangle { a, b, c } = triangle_light() else {
        unreachable!()
    };
    let v = [a, b, c];
    let len = |k: usize| (v[(k + 1) % 3] - v[k]).length();
    let total: f32 = (0..3).map(len).sum();
    (0..3)
        .flat_map(|k| {
            let w = len(k) / total / n as f32;
            (0..n).map(move |i| {
                let t = i as f32 / (n - 1) as f32;
                (LightPoint::Position(v[k].lerp(v[(k + 1) % 3], t)), w)
            })
        })
        .collect()
}

/// Figure 9's map resolution.
pub const RESOLUTION: u32 = 500;

/// The light of both figures: 1.6 m along x, 3 m up.
pub fn light() -> Light {
    Light::Linear {
        a: Vec3::new(-0.8, 3.0, 0.0),
        b: Vec3::new(0.8, 3.0, 0.0),
    }
}

/// `n` uniformly spaced points on the light, ends included, equal weights.
pub fn uniform_points(n: u32) -> Vec<(LightPoint, f32)> {
    let Light::Linear { a, b } = light() else {
        unreachable!()
    };
    (0..n)
        .map(|k| {
            let t = if n == 1 {
                0.5
            } else {
                k as f32 / (n - 1) as f32
            };
            (LightPoint::Position(a.lerp(b, t)), 1.0 / n as f32)
        })
        .collect()
}

/// Figure 9: a 1.2 m square plate 1 m above the ground: the ends' umbrae overlap over
/// x in [-0.5, 0.5].
pub fn spec_fig9() -> soft_shadow_reference::scenes::SceneSpec {
    scene(
        ID_FIG9,
        "Heidrich Fig. 9: one linear light, one wide blocker, one receiver",
        vec![horizontal_rect(
            "blocker",
            Vec2::new(-0.6, 0.6),
            Vec2::new(-0.6, 0.6),
            1.0,
        )],
        light(),
        Vec3::ZERO,
        2.2,
    )
}

/// Figure 8: two 0.3 m bars along z, 0.5 m apart, 1.2 m up: their penumbrae overlap between them.
pub fn spec_fig8() -> soft_shadow_reference::scenes::SceneSpec {
    scene(
        ID_FIG8,
        "Heidrich Fig. 8: two blockers whose penumbrae overlap under a linear light",
        bars(),
        light(),
        Vec3::ZERO,
        2.0,
    )
}

/// Figure 8's two bars.
fn bars() -> Vec<soft_shadow_core::TriangleMesh> {
    vec![
        horizontal_rect("bar-a", Vec2::new(-0.55, -0.25), Vec2::new(-1.0, 1.0), 1.2),
        horizontal_rect("bar-b", Vec2::new(0.25, 0.55), Vec2::new(-1.0, 1.0), 1.2),
    ]
}

/// Figure 8 (right): the two bars under [`triangle_light`].
pub fn spec_triangle() -> soft_shadow_reference::scenes::SceneSpec {
    scene(
        ID_TRIANGLE,
        "Heidrich Fig. 8 (right): two blockers under a triangle light",
        bars(),
        triangle_light(),
        Vec3::ZERO,
        2.0,
    )
}

/// Runs both figures at G-buffer side `size`.
pub fn run(size: u32) -> Result<(Vec<Experiment>, Vec<Run>)> {
    let mut runs = Vec::new();
    // Figure 9.
    let p = prepare(spec_fig9(), size)?;
    let mc = p.reference_v();
    let (r200, v200) = ray_traced_run(ID_FIG9, "200-uniform", &p, |_| uniform_points(200));
    let (r10, v10) = ray_traced_run(ID_FIG9, "10-uniform", &p, |_| uniform_points(10));
    let (rn2, vn2) = measure_run(ID_FIG9, &LinearLight::new(2), &p, RESOLUTION, None)?;
    runs.extend([r200, r10, rn2]);
    let all = |v: &[f32], r: &[f32]| rms_where(v, r, |_| true);
    let row = |label: &str, v: &[f32]| Row {
        label: label.into(),
        published: vec![None, None],
        ours: vec![Some(all(v, &v200)), Some(all(v, &mc))],
    };
    let rows9 = vec![
        row("ours, 2 samples (linear-light n2, 500² maps)", &vn2),
        row("ray traced, 10 uniformly spaced samples", &v10),
        row("ray traced, 200 uniformly spaced samples", &v200),
    ];
    let (ours, ten) = (all(&vn2, &v200), all(&v10, &v200));
    let fig9 = Experiment {
        id: ID_FIG9.into(),
        paper: "Heidrich, Brabec & Seidel 2000, soft shadow maps for linear lights".into(),
        figure: "Figure 9".into(),
        setup: format!(
            "A 1.6 m linear light 3 m up; a 1.2 m square plate 1 m up, wide enough that the two \
             end samples' umbrae overlap (x in [-0.5, 0.5]); the ground as the one receiver, \
             seen top-down ({size}²). Maps {RESOLUTION}², as the paper's. The paper shows \
             images, no numbers: its claim is the ordering."
        ),
        metric: "RMS of (V - V_ref) * 255 over the ground image".into(),
        columns: vec![
            "vs 200 ray-traced samples".into(),
            "vs our Monte Carlo reference".into(),
        ],
        rows: rows9,
        claims: vec![Claim::new(
            "2 samples with skins are closer to the reference than 10 point samples",
            ours < ten,
            format!("{ours:.2} vs {ten:.2} against 200 samples"),
        )],
    };
    // Figure 8.
    let p = prepare(spec_fig8(), size)?;
    let mc = p.reference_v();
    let mut rows8 = Vec::new();
    let mut ours = Vec::new();
    let mut points = Vec::new();
    for n in [2u32, 3] {
        let (rp, vp) = ray_traced_run(ID_FIG8, &format!("{n}-uniform"), &p, |_| uniform_points(n));
        let (ro, vo) = measure_run(ID_FIG8, &LinearLight::new(n), &p, RESOLUTION, None)?;
        runs.extend([rp, ro]);
        points.push(all(&vp, &mc));
        ours.push(all(&vo, &mc));
    }
    rows8.push(Row {
        label: "point lights, as many (ray traced)".into(),
        published: vec![None, None],
        ours: points.iter().map(|&x| Some(x)).collect(),
    });
    rows8.push(Row {
        label: "ours (linear-light, 500² maps)".into(),
        published: vec![None, None],
        ours: ours.iter().map(|&x| Some(x)).collect(),
    });
    let fig8 = Experiment {
        id: ID_FIG8.into(),
        paper: "Heidrich, Brabec & Seidel 2000, soft shadow maps for linear lights".into(),
        figure: "Figure 8 (left and centre)".into(),
        setup: format!(
            "The same light; two 0.3 m bars 1.2 m up, 0.5 m apart, whose penumbrae overlap \
             between them; ground seen top-down ({size}²), maps {RESOLUTION}²."
        ),
        metric: "RMS of (V - V_ref) * 255 over the ground image".into(),
        columns: vec!["2 samples".into(), "3 samples".into()],
        rows: rows8,
        claims: vec![
            Claim::new(
                "A third sample removes the overlap artefact of 2 samples",
                ours[1] < ours[0],
                format!("{:.2} with 3 samples vs {:.2} with 2", ours[1], ours[0]),
            ),
            Claim::new(
                "With as many samples, the method beats point lights",
                ours[0] < points[0] && ours[1] < points[1],
                format!(
                    "2: {:.2} vs {:.2}; 3: {:.2} vs {:.2}",
                    ours[0], points[0], ours[1], points[1]
                ),
            ),
        ],
    };
    // Figure 8 (right): the triangle light.
    let p = prepare(spec_triangle(), size)?;
    let mc = p.reference_v();
    let (mut ours, mut points) = (Vec::new(), Vec::new());
    for n in [2u32, 3] {
        let (rp, vp) = ray_traced_run(ID_TRIANGLE, &format!("{n}-per-edge"), &p, |_| {
            edge_points(n)
        });
        let (ro, vo) = measure_run(ID_TRIANGLE, &LinearLight::new(n), &p, RESOLUTION, None)?;
        runs.extend([rp, ro]);
        points.push(all(&vp, &mc));
        ours.push(all(&vo, &mc));
    }
    let tri = Experiment {
        id: ID_TRIANGLE.into(),
        paper: "Heidrich, Brabec & Seidel 2000, soft shadow maps for linear lights".into(),
        figure: "Figure 8 (right), section 4: a triangle light as three linear lights".into(),
        setup: format!(
            "Figure 8's bars under a triangle light (1.6 m base, 1 m high, 3 m up), its edges \
             shaded as three linear lights weighted by length (CPU and GPU; the catalogue's \
             `triangle-light` scene puts it in the report); ground seen top-down ({size}²), \
             maps {RESOLUTION}². The paper calls this 'a really crude approximation' (the \
             transition under an area light is quadratic) and gives no number: the reference \
             here is the area light's."
        ),
        metric: "RMS of (V - V_ref) * 255 over the ground image, against the area light".into(),
        columns: vec!["2 samples per edge".into(), "3 per edge".into()],
        rows: vec![
            Row {
                label: "point lights on the edges, as many (ray traced)".into(),
                published: vec![None, None],
                ours: points.iter().map(|&x| Some(x)).collect(),
            },
            Row {
                label: "ours (linear-light on the edges, 500² maps)".into(),
                published: vec![None, None],
                ours: ours.iter().map(|&x| Some(x)).collect(),
            },
        ],
        claims: vec![Claim::new(
            "Three linear lights beat point lights on the edges with as many samples",
            ours[0] < points[0] && ours[1] < points[1],
            format!(
                "2: {:.2} vs {:.2}; 3: {:.2} vs {:.2}",
                ours[0], points[0], ours[1], points[1]
            ),
        )],
    };
    Ok((vec![fig9, fig8, tri], runs))
}
