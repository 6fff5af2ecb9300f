//! Pictures and raw data: a PNG strip per scene (reference | runs, signed error below) and OpenEXR
//! files of the G-buffer, the reference and every run's `V`.

use crate::error::{HarnessError, Result};
use image::{Rgb, RgbImage};
use std::path::Path;

const BACKGROUND: Rgb<u8> = Rgb([40, 44, 60]);

fn io_err(path: &Path, e: impl std::fmt::Display) -> HarnessError {
    HarnessError::write(path, e)
}

/// Scatters per-receiver values back into a `size²` image; `None` where no receiver is.
pub fn scatter(size: u32, pixels: &[usize], values: &[f32]) -> Vec<Option<f32>> {
    let mut img = vec![None; (size * size) as usize];
    for (&p, &v) in pixels.iter().zip(values) {
        img[p] = Some(v);
    }
    img
}

fn gray(v: Option<f32>) -> Rgb<u8> {
    match v {
        Some(v) if v.is_finite() => {
            let g = (v.clamp(0.0, 1.0) * 255.0).round() as u8;
            Rgb([g, g, g])
        }
        Some(_) => Rgb([255, 0, 255]),
        None => BACKGROUND,
    }
}

/// Signed error colour: red where the run is darker than the reference, blue where brighter;
/// full saturation at `|error| >= 64/255`.
fn signed(v: Option<f32>, r: Option<f32>) -> Rgb<u8> {
    match (v, r) {
        (Some(v), Some(r)) if v.is_finite() => {
            let e = ((v - r) * 4.0).clamp(-1.0, 1.0);
            let k = (255.0 * (1.0 - e.abs())) as u8;
            if e < 0.0 {
                Rgb([255, k, k])
            } else {
                Rgb([k, k, 255])
            }
        }
        (Some(_), Some(_)) => Rgb([255, 0, 255]),
        _ => BACKGROUND,
    }
}

/// Colour of an unlit receiver (no light point reaches it): brown diagonal hatching, apart
/// from every value of `V` and from the background.
fn unlit(x: u32, y: u32) -> Rgb<u8> {
    if ((x + y) / 3).is_multiple_of(2) {
        Rgb([110, 84, 30])
    } else {
        Rgb([60, 46, 18])
    }
}

/// Rows of a strip: `V`, the shaded image, its signed error.
pub const STRIP_ROWS: u32 = 3;

/// The strip, one column for the reference then one per run, [`STRIP_ROWS`] rows: `V`;
/// the shaded image `weight * V` (what a white Lambertian scene lit by the light shows, `weight`
/// = `E0 / E0_max` per pixel); and below each run its signed image error `(V - V_ref) * weight`.
/// `unlit_pixels` (receivers no light point reaches) are hatched in every cell.
pub fn strip_image(
    size: u32,
    reference: &[Option<f32>],
    weight: &[Option<f32>],
    runs: &[Vec<Option<f32>>],
    unlit_pixels: &[usize],
) -> RgbImage {
    let cols = 1 + runs.len() as u32;
    let mut img = RgbImage::from_pixel(cols * size, STRIP_ROWS * size, Rgb([20, 20, 20]));
    let mut is_unlit = vec![false; (size * size) as usize];
    for &i in unlit_pixels {
        is_unlit[i] = true;
    }
    let put = |img: &mut RgbImage, col: u32, row: u32, f: &dyn Fn(usize) -> Rgb<u8>| {
        for y in 0..size {
            for x in 0..size {
                let i = (y * size + x) as usize;
                let c = if is_unlit[i] { unlit(x, y) } else { f(i) };
                img.put_pixel(col * size + x, row * size + y, c);
            }
        }
    };
    let shaded = |v: Option<f32>, i: usize| v.zip(weight[i]).map(|(v, w)| v * w);
    put(&mut img, 0, 0, &|i| gray(reference[i]));
    put(&mut img, 0, 1, &|i| gray(shaded(reference[i], i)));
    for (k, run) in runs.iter().enumerate() {
        let col = k as u32 + 1;
        put(&mut img, col, 0, &|i| gray(run[i]));
        put(&mut img, col, 1, &|i| gray(shaded(run[i], i)));
        put(&mut img, col, 2, &|i| {
            signed(shaded(run[i], i), shaded(reference[i], i))
        });
    }
    img
}

/// Writes [`strip_image`] to `path` as PNG.
pub fn write_strip(
    path: &Path,
    size: u32,
    reference: &[Option<f32>],
    weight: &[Option<f32>],
    runs: &[Vec<Option<f32>>],
    unlit_pixels: &[usize],
) -> Result<()> {
    strip_image(size, reference, weight, runs, unlit_pixels)
        .save(path)
        .map_err(|e| io_err(path, e))
}

/// Writes named 32-bit float channels of a `size²` image as OpenEXR: one layer, ZIP
/// compression in blocks of 16 scan lines ([`EXR_ENCODING`]).
pub fn write_exr_channels(path: &Path, size: u32, channels: Vec<(&str, Vec<f32>)>) -> Result<()> {
    use exr::prelude::*;
    let n = (size * size) as usize;
    if channels.iter().any(|(_, v)| v.len() != n) {
        return Err(io_err(path, "EXR buffer size"));
    }
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> = channels
        .into_iter()
        .map(|(name, v)| AnyChannel::new(name, FlatSamples::F32(v)))
        .collect();
    let layer = Layer::new(
        (size as usize, size as usize),
        LayerAttributes::default(),
        EXR_ENCODING,
        AnyChannels::sort(list),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|e| io_err(path, e))
}

/// How every EXR file is encoded: ZIP, 16 scan lines per block.
pub const EXR_ENCODING: exr::prelude::Encoding = exr::prelude::Encoding::SMALL_LOSSLESS;

/// Writes a 3-vector per pixel as channels `X`, `Y`, `Z`.
pub fn write_exr_xyz(path: &Path, size: u32, xyz: &[[f32; 3]]) -> Result<()> {
    let axis = |k: usize| xyz.iter().map(|v| v[k]).collect::<Vec<f32>>();
    write_exr_channels(
        path,
        size,
        vec![("X", axis(0)), ("Y", axis(1)), ("Z", axis(2))],
    )
}

/// Writes a scalar image as one channel `V`; pixels without receiver are NaN.
pub fn write_exr_scalar(path: &Path, size: u32, values: &[Option<f32>]) -> Result<()> {
    let v = values.iter().map(|v| v.unwrap_or(f32::NAN)).collect();
    write_exr_channels(path, size, vec![("V", v)])
}

/// Writes a scene's raw data: G-buffer positions and normals (NaN where uncovered), the
/// reference `V` and its standard error.
pub fn write_scene_exr(dir: &Path, size: u32, p: &crate::setup::PreparedScene) -> Result<()> {
    let texels = p.gbuffer.data();
    let pos: Vec<[f32; 3]> = texels
        .iter()
        .map(|t| {
            if t.covered {
                t.position.to_array()
            } else {
                [f32::NAN; 3]
            }
        })
        .collect();
    let nrm: Vec<[f32; 3]> = texels
        .iter()
        .map(|t| {
            if t.covered {
                t.normal.to_array()
            } else {
                [f32::NAN; 3]
            }
        })
        .collect();
    write_exr_xyz(&dir.join("gbuffer-position.exr"), size, &pos)?;
    write_exr_xyz(&dir.join("gbuffer-normal.exr"), size, &nrm)?;
    write_exr_scalar(
        &dir.join("reference.exr"),
        size,
        &scatter(size, &p.pixels, &p.reference_v()),
    )?;
    let se: Vec<f32> = p.reference.iter().map(|r| r.std_error).collect();
    write_exr_scalar(
        &dir.join("reference-std-error.exr"),
        size,
        &scatter(size, &p.pixels, &se),
    )
}
