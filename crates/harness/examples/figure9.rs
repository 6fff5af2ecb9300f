//! The paper's Figure 9 claim, measured: on `linear-bar` at map resolution 512, linear-light
//! with 2 samples against point-light accumulation with 10 samples, and against accumulation
//! with as many samples as fit in the same time (generation + evaluation, medians of 5 runs);
//! then linear-light with 3, 5 and 9 samples.
//!
//! `cargo run --release --example figure9 [-- gpu]`

use harness::metrics::{errors, median};
use harness::setup::PreparedScene;
use linear_light::LinearLight;
use shadow_maps::{Filter, ShadowMapBaseline};
use soft_shadow_core::{Context, CpuContext, DynTechnique, GpuContext};
use soft_shadow_reference::ground_truth::GroundTruthSettings;
use soft_shadow_reference::scenes::catalogue::build;
use std::time::Instant;

const RES: u32 = 512;

struct Row {
    label: String,
    ms: f64,
    rms: f64,
    penumbra: f64,
}

fn measure(
    t: &dyn DynTechnique,
    ctx: Context<'_>,
    prep: &PreparedScene,
    reference: &[f32],
) -> soft_shadow_core::Result<Row> {
    let mut times = Vec::new();
    let mut v = Vec::new();
    for _ in 0..5 {
        let start = Instant::now();
        let maps = t.generate_in(ctx, &prep.geometry, &prep.spec.light, &prep.views, RES)?;
        v = maps.evaluate(ctx.gpu(), &prep.receivers())?;
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    let e = errors(&v, reference, &prep.shading);
    Ok(Row {
        label: format!("{} {}", t.name(), t.variant()),
        ms: median(&times),
        rms: e.rms_255,
        penumbra: e.penumbra_rms_255,
    })
}

fn main() -> soft_shadow_core::Result<()> {
    let gpu_wanted = std::env::args().any(|a| a == "gpu");
    let gpu = if gpu_wanted {
        Some(GpuContext::new()?)
    } else {
        None
    };
    let cpu = CpuContext::new();
    let backend = match &gpu {
        Some(g) => Context::Gpu(g),
        None => Context::Cpu(&cpu),
    };
    let prep = PreparedScene::new(build("linear-bar")?, 256, GroundTruthSettings::default())?;
    let reference = prep.reference_v();
    let ours = measure(&LinearLight::new(2), backend, &prep, &reference)?;
    let mut rows = vec![measure(
        &ShadowMapBaseline::new(Filter::Accumulate { samples: 10 }),
        backend,
        &prep,
        &reference,
    )?];
    // The most accumulation samples that fit in linear-light's time.
    let mut equal = None;
    for n in 2..=64 {
        let r = measure(
            &ShadowMapBaseline::new(Filter::Accumulate { samples: n }),
            backend,
            &prep,
            &reference,
        )?;
        if r.ms > ours.ms {
            break;
        }
        equal = Some(r);
    }
    rows.extend(equal);
    // More samples along the segment, for context (section 3.3).
    for n in [3, 5, 9] {
        rows.push(measure(&LinearLight::new(n), backend, &prep, &reference)?);
    }
    println!(
        "linear-bar, map {RES}, 256² receivers, {} backend",
        backend.backend().name()
    );
    println!("| run | generate + evaluate (ms) | rms_255 | penumbra_rms_255 |");
    println!("|---|---|---|---|");
    for r in std::iter::once(&ours).chain(&rows) {
        println!(
            "| {} | {:.2} | {:.2} | {:.2} |",
            r.label, r.ms, r.rms, r.penumbra
        );
    }
    Ok(())
}
