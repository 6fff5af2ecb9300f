//! The README's picture: one scene's reference beside the best variant of each of the four
//! techniques and the four baselines, labelled, with the shaded image and its signed error
//! below each (`harness figure`).

use crate::error::{HarnessError, Result};
use crate::metrics::errors;
use crate::report::images::{STRIP_ROWS, scatter, strip_image};
use crate::report::{all_techniques, pareto::register_font};
use crate::setup::PreparedScene;
use image::RgbImage;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use soft_shadow_core::{Context, CpuContext, DynTechnique, Receivers};
use soft_shadow_reference::ground_truth::GroundTruthSettings;
use soft_shadow_reference::scenes::catalogue;
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
    labels: &[Labels],
) -> std::result::Result<RgbImage, String> {
    let (w, h) = (strip.width(), HEADER + STRIP_ROWS * size + FOOTER);
    let below = (HEADER + STRIP_ROWS * size + 4) as i32;
    let texts: Vec<_> = labels
        .iter()
        .enumerate()
        .map(|(i, l)| ((i as u32 * size + size / 2) as i32, 0, below, l))
        .collect();
    let mut img = canvas(w, h, &texts)?;
    image::imageops::replace(&mut img, strip, 0, HEADER as i64);
    Ok(img)
}

/// The label lines of one column or tile: two above it, one below.
type Labels = (String, String, String);

/// A dark `w` x `h` canvas with, for each `(x, top, below, (a, b, c))`, the lines `a` and `b`
/// centred on `x` from `top` and `c` centred on `x` at `below`.
fn canvas(
    w: u32,
    h: u32,
    texts: &[(i32, i32, i32, &Labels)],
) -> std::result::Result<RgbImage, String> {
    register_font();
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
        for &(x, top, below, (a, b, c)) in texts {
            for (text, y, px) in [(a, top + 4, 17), (b, top + 24, 15), (c, below, 15)] {
                root.draw(&Text::new(text.as_str(), (x, y), style(px)))
                    .map_err(|e| e.to_string())?;
            }
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(RgbImage::from_raw(w, h, buf).ok_or("label buffer size")?)
}

/// The configurations of the "as seen" figure: the baselines and the techniques' defaults that
/// model a disk light (`technique:variant`).
pub const AS_SEEN: [&str; 7] = [
    "hard-shadow-map:nearest",
    "pcf:r2",
    "pcss:7x7-9x9",
    "accumulation:n16",
    "shadow-width:edt",
    "penumbra-limit:silhouette-f32",
    "occlusion-slices:nbuffer-8-chain",
];

/// Pixels around the reference's shadow kept in the "as seen" crops.
const CROP_MARGIN: u32 = 24;

/// `harness figure --as-seen`: the bunny's shadow as a person sees it (the 1280 x 720 frame of
/// [`crate::as_seen`], maps at `resolution`), cropped around the reference's shadow, the
/// reference then each configuration of [`AS_SEEN`], four to a row, labelled, FLIP under each.
/// Returns each configuration's label and mean FLIP.
pub fn as_seen(out: &std::path::Path, resolution: u32) -> Result<Vec<(String, f32)>> {
    use crate::as_seen::{LIT_WEIGHT, flip, frame, shaded};
    let scene = frame(catalogue::build("bunny")?)?;
    let reference = scene.reference_v();
    let w = scene.gbuffer.width();
    // The crop: the lit receivers the reference shades, padded.
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for (k, &i) in scene.pixels.iter().enumerate() {
        if reference[k] < crate::metrics::PENUMBRA_HI && scene.shading.weight[k] >= LIT_WEIGHT {
            let (x, y) = (i as u32 % w, i as u32 / w);
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
    }
    if x0 > x1 {
        return Err(HarnessError::Usage(
            "the bunny casts no shadow in view".into(),
        ));
    }
    let h = scene.gbuffer.height();
    let (x0, y0) = (
        x0.saturating_sub(CROP_MARGIN),
        y0.saturating_sub(CROP_MARGIN),
    );
    let (x1, y1) = ((x1 + CROP_MARGIN).min(w - 1), (y1 + CROP_MARGIN).min(h - 1));
    let crop = |img: &RgbImage| {
        image::imageops::crop_imm(img, x0, y0, x1 - x0 + 1, y1 - y0 + 1).to_image()
    };
    let mut tiles = vec![(
        (
            "reference".to_string(),
            "ray traced".to_string(),
            "FLIP".to_string(),
        ),
        crop(&shaded(&scene, &reference)),
    )];
    let cpu = CpuContext::new();
    let all = all_techniques(false);
    let mut scores = Vec::new();
    for label in AS_SEEN {
        let t = all
            .iter()
            .find(|t| format!("{}:{}", t.name(), t.variant()) == label)
            .ok_or_else(|| HarnessError::Usage(format!("no configuration {label}")))?;
        let v = t
            .generate_in(
                Context::Cpu(&cpu),
                &scene.geometry,
                &scene.spec.light,
                &scene.views,
                resolution,
            )?
            .evaluate(None, &scene.receivers())?;
        let score = flip(&scene, &v).0;
        scores.push((label.to_string(), score.mean));
        tiles.push((
            (
                t.name().to_string(),
                t.variant(),
                format!("FLIP {:.4}", score.mean),
            ),
            crop(&shaded(&scene, &v)),
        ));
    }
    let img = grid(&tiles, 4).map_err(|e| HarnessError::write(out, e))?;
    img.save(out).map_err(|e| HarnessError::write(out, e))?;
    Ok(scores)
}

/// `tiles` (all of one size) `columns` to a row, each with two label lines above and one below.
fn grid(tiles: &[(Labels, RgbImage)], columns: u32) -> std::result::Result<RgbImage, String> {
    let (tw, th) = tiles.first().map_or((1, 1), |t| t.1.dimensions());
    let (cell_w, cell_h) = (tw + 8, HEADER + th + FOOTER);
    let rows = (tiles.len() as u32).div_ceil(columns);
    let corner = |i: usize| ((i as u32 % columns) * cell_w, (i as u32 / columns) * cell_h);
    let texts: Vec<_> = tiles
        .iter()
        .enumerate()
        .map(|(i, (l, _))| {
            let (cx, cy) = corner(i);
            (
                (cx + cell_w / 2) as i32,
                cy as i32,
                (cy + HEADER + th + 4) as i32,
                l,
            )
        })
        .collect();
    let mut img = canvas(columns * cell_w, rows * cell_h, &texts)?;
    for (i, (_, tile)) in tiles.iter().enumerate() {
        let (cx, cy) = corner(i);
        image::imageops::replace(&mut img, tile, (cx + 4) as i64, (cy + HEADER) as i64);
    }
    Ok(img)
}
