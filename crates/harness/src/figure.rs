//! The README's picture: one scene's reference beside the best variant of each of the four
//! techniques and the four baselines, labelled, with the shaded image and its signed error
//! below each (`harness figure`).

use crate::error::{HarnessError, Result};
use crate::ground_truth::GroundTruthSettings;
use crate::metrics::errors;
use crate::report::images::{STRIP_ROWS, scatter, strip_image};
use crate::report::{all_techniques, pareto::register_font};
use crate::scenes::catalogue;
use crate::setup::PreparedScene;
use image::RgbImage;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use soft_shadow_core::{Context, CpuContext, DynTechnique, Receivers};
use std::path::PathBuf;

/// The four techniques, each shown at its best variant on the scene.
pub const TECHNIQUES: [&str; 4] = [
    "shadow-width",
    "penumbra-limit",
    "occlusion-slices",
    "linear-light",
];

/// The baselines shown, as `technique:variant`.
pub const BASELINES: [&str; 4] = [
    "hard-shadow-map:nearest",
    "pcf:r2",
    "pcss:7x7-9x9",
    "accumulation:n16",
];

/// Height of the label band above the strip, pixels.
const HEADER: u32 = 44;
/// Height of the error band below it, pixels.
const FOOTER: u32 = 24;

/// What `harness figure` draws.
#[derive(Clone, Debug)]
pub struct FigureOptions {
    /// A built-in scene whose light every technique models (`triangle-light`).
    pub scene: String,
    /// The PNG to write.
    pub out: PathBuf,
    /// Map resolution, texels per side.
    pub resolution: u32,
    /// G-buffer side, pixels.
    pub size: u32,
}

/// One column of the figure.
#[derive(Clone, Debug)]
pub struct Column {
    /// Technique name.
    pub technique: String,
    /// Variant label.
    pub variant: String,
    /// Image error, rms over the receivers, /255.
    pub image_rms_255: f64,
    /// Visibility error, rms, /255.
    pub rms_255: f64,
}

/// Measures every configuration on the CPU, keeps the best variant of each technique and the
/// baselines, and writes the labelled strip. Returns the columns after the reference.
pub fn run(opts: &FigureOptions) -> Result<Vec<Column>> {
    let spec = catalogue::build(&opts.scene)?;
    let p = PreparedScene::new(spec, opts.size, GroundTruthSettings::default())?;
    let reference = p.reference_v();
    let cpu = CpuContext::new();
    let light = p.spec.light;
    let receivers = Receivers::new(&p.positions, &p.normals);
    let measure = |t: &dyn DynTechnique| -> Result<(Column, Vec<f32>)> {
        let maps = t.generate_in(
            Context::Cpu(&cpu),
            &p.geometry,
            &light,
            &p.views_for(&light),
            opts.resolution,
        )?;
        let v = maps.evaluate(None, &receivers)?;
        let e = errors(&v, &reference, &p.shading);
        let column = Column {
            technique: t.name().into(),
            variant: t.variant(),
            image_rms_255: e.image_rms_255,
            rms_255: e.rms_255,
        };
        Ok((column, v))
    };
    let all = all_techniques(false);
    let mut shown: Vec<(Column, Vec<f32>)> = Vec::new();
    for name in TECHNIQUES {
        let mut best: Option<(Column, Vec<f32>)> = None;
        for t in all
            .iter()
            .filter(|t| t.name() == name && t.models(light.kind()))
        {
            let m = measure(t.as_ref())?;
            if best
                .as_ref()
                .is_none_or(|b| m.0.image_rms_255 < b.0.image_rms_255)
            {
                best = Some(m);
            }
        }
        shown.push(best.ok_or_else(|| {
            HarnessError::Usage(format!(
                "{name} does not model the {} light of `{}`: pick a scene every technique models \
                 (triangle-light)",
                light.kind().name(),
                opts.scene
            ))
        })?);
    }
    for b in BASELINES {
        let t = all
            .iter()
            .find(|t| format!("{}:{}", t.name(), t.variant()) == b)
            .ok_or_else(|| HarnessError::Usage(format!("no baseline {b}")))?;
        shown.push(measure(t.as_ref())?);
    }
    let runs: Vec<Vec<Option<f32>>> = shown
        .iter()
        .map(|(_, v)| scatter(opts.size, &p.pixels, v))
        .collect();
    let strip = strip_image(
        opts.size,
        &scatter(opts.size, &p.pixels, &reference),
        &scatter(opts.size, &p.pixels, &p.shading.weight),
        &runs,
        &p.unlit_pixels,
    );
    let mut labels = vec![(
        "reference".to_string(),
        "ray traced".to_string(),
        "image error /255".to_string(),
    )];
    labels.extend(shown.iter().map(|(c, _)| {
        (
            c.technique.clone(),
            c.variant.clone(),
            format!("{:.2}", c.image_rms_255),
        )
    }));
    let img =
        labelled(&strip, opts.size, &labels).map_err(|e| HarnessError::write(&opts.out, e))?;
    img.save(&opts.out)
        .map_err(|e| HarnessError::write(&opts.out, e))?;
    Ok(shown.into_iter().map(|(c, _)| c).collect())
}

/// `strip` with a band of two label lines above each column and one below.
fn labelled(
    strip: &RgbImage,
    size: u32,
    labels: &[(String, String, String)],
) -> std::result::Result<RgbImage, String> {
    register_font();
    let (w, h) = (strip.width(), HEADER + STRIP_ROWS * size + FOOTER);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&RGBColor(20, 20, 20))
            .map_err(|e| e.to_string())?;
        let style = |px: u32| {
            ("sans-serif", px as f64)
                .into_font()
                .color(&WHITE)
                .pos(Pos::new(HPos::Center, VPos::Top))
        };
        for (i, (a, b, c)) in labels.iter().enumerate() {
            let x = (i as u32 * size + size / 2) as i32;
            for (text, y, px) in [
                (a, 4, 17),
                (b, 24, 15),
                (c, (HEADER + STRIP_ROWS * size + 4) as i32, 15),
            ] {
                root.draw(&Text::new(text.as_str(), (x, y), style(px)))
                    .map_err(|e| e.to_string())?;
            }
        }
        root.present().map_err(|e| e.to_string())?;
    }
    let mut img = RgbImage::from_raw(w, h, buf).ok_or("label buffer size")?;
    image::imageops::replace(&mut img, strip, 0, HEADER as i64);
    Ok(img)
}
