//! CPU triangle rasterizer: the reference that the GPU render passes are checked against.
//!
//! It follows the rules a GPU applies, so the two agree texel for texel: vertices snapped to a
//! 1/256-pixel grid, coverage at pixel centres with the top-left fill rule, clipping to the
//! reversed-Z depth range, a `Greater` depth test on NDC depth in submission order, and
//! perspective-correct barycentrics. Rows are split into bands rasterized in parallel with rayon.

mod bins;
mod setup;
pub mod snapped;

use crate::map2d::Map2D;
use crate::pool::Pool;
use crate::view::View;
use bins::bins;
use glam::Vec3;
use rayon::prelude::*;
use setup::{Screen, ScreenTri, setup_world};
pub use snapped::{SUBPIXEL_BITS, SnappedTri};
use std::sync::Arc;

const BAND_ROWS: usize = 16;

/// What the rasterizer keeps per pixel: the nearest fragment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragment {
    /// Reversed-Z NDC depth (0 where empty).
    pub z_ndc: f32,
    /// Index of the triangle that covers the pixel, `u32::MAX` where empty.
    pub triangle: u32,
    /// Perspective-correct barycentric coordinates with respect to that triangle's vertices.
    pub bary: [f32; 3],
}

impl Fragment {
    /// An empty pixel.
    pub const EMPTY: Fragment = Fragment {
        z_ndc: 0.0,
        triangle: u32::MAX,
        bary: [0.0; 3],
    };

    /// True when a triangle covers the pixel.
    pub fn is_covered(&self) -> bool {
        self.triangle != u32::MAX
    }
}

/// The nearest triangle at a pixel: a [`Fragment`] without its barycentrics (8 bytes a texel
/// instead of 20), for a pass that only needs which triangle it sees and how deep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nearest {
    /// Reversed-Z NDC depth (0 where empty).
    pub z_ndc: f32,
    /// Index of the triangle that covers the pixel, `u32::MAX` where empty.
    pub triangle: u32,
}

impl Nearest {
    /// An empty pixel.
    pub const EMPTY: Nearest = Nearest {
        z_ndc: 0.0,
        triangle: u32::MAX,
    };

    /// True when a triangle covers the pixel.
    pub fn is_covered(&self) -> bool {
        self.triangle != u32::MAX
    }
}

/// Which fragment a depth pass keeps per texel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[non_exhaustive]
pub enum DepthTest {
    /// The surface nearest the view (`Greater` in reversed Z; cleared to the far plane).
    #[default]
    Nearest,
    /// The farthest surface (`Less` in reversed Z; cleared to the near plane), the paper's
    /// "z-greater" test (Kirsch & Döllner 2003, section 5).
    Farthest,
}

/// Which triangles a depth pass rasterizes, by their orientation in the view.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[non_exhaustive]
pub enum Faces {
    /// Every triangle (no culling).
    #[default]
    All,
    /// Only triangles whose back (clockwise in NDC) faces the view; front faces are culled, as
    /// `cull_mode: Front` with counter-clockwise front faces does on the GPU.
    Back,
}

/// A depth pass: the depth test and the faces it draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct DepthPass {
    /// Nearest or farthest surface.
    pub test: DepthTest,
    /// All faces or back faces only.
    pub faces: Faces,
}

impl DepthPass {
    /// The ordinary shadow-map pass: nearest surface, every face.
    pub const NEAREST: DepthPass = DepthPass {
        test: DepthTest::Nearest,
        faces: Faces::All,
    };
    /// The farthest surface of every face.
    pub const FARTHEST: DepthPass = DepthPass {
        test: DepthTest::Farthest,
        faces: Faces::All,
    };
    /// The nearest back face: the far side of the first closed caster along the ray
    /// (second-depth shadow maps).
    pub const NEAREST_BACK: DepthPass = DepthPass {
        test: DepthTest::Nearest,
        faces: Faces::Back,
    };
    /// The farthest back face.
    pub const FARTHEST_BACK: DepthPass = DepthPass {
        test: DepthTest::Farthest,
        faces: Faces::Back,
    };

    /// The reversed-Z NDC depth the pass clears to: 0 (far plane) or 1 (near plane).
    pub fn clear_depth(self) -> f32 {
        match self.test {
            DepthTest::Nearest => 0.0,
            DepthTest::Farthest => 1.0,
        }
    }

    /// Linear depth of a texel of this pass; the cleared value gives [`crate::view::NO_OCCLUDER`].
    pub fn linear_depth(self, view: &View, z_ndc: f32) -> f32 {
        match self.test {
            DepthTest::Nearest => view.linear_depth_from_ndc(z_ndc),
            DepthTest::Farthest if z_ndc >= 1.0 => crate::view::NO_OCCLUDER,
            DepthTest::Farthest => view.linear_depth_from_ndc(z_ndc),
        }
    }

    /// [`DepthPass::linear_depth`] of every texel of `depths` in place, bit for bit: the
    /// projection and the test are resolved once, so the loop has no branch and vectorizes, and
    /// runs of cleared texels are filled without the division.
    pub fn linearize(self, view: &View, depths: &mut [f32]) {
        use crate::view::ProjectionKind;
        let (n, f) = (view.near, view.far);
        // Cleared texels: `<= 0` always (the far plane), `>= 1` too for the farthest pass.
        let cleared_hi = match self.test {
            DepthTest::Nearest => f32::INFINITY,
            DepthTest::Farthest => 1.0,
        };
        let empty = |z: f32| z <= 0.0 || z >= cleared_hi;
        match view.kind {
            ProjectionKind::Perspective { .. } => {
                linearize_with(depths, empty, |z| n * f / (z * (f - n) + n))
            }
            ProjectionKind::Orthographic { .. } => {
                linearize_with(depths, empty, |z| f - z * (f - n))
            }
        }
    }

    fn passes(self, z: f32, stored: f32) -> bool {
        match self.test {
            DepthTest::Nearest => z > stored,
            DepthTest::Farthest => z < stored,
        }
    }
}

/// `depth(z)` of every texel of `depths` that is not `empty(z)`, [`crate::view::NO_OCCLUDER`]
/// where it is; a chunk of texels with no fragment (most of a map's background) is one fill.
#[inline]
fn linearize_with(depths: &mut [f32], empty: impl Fn(f32) -> bool, depth: impl Fn(f32) -> f32) {
    use crate::view::NO_OCCLUDER;
    for chunk in depths.chunks_mut(16) {
        if chunk.iter().fold(true, |all, &z| all & empty(z)) {
            chunk.fill(NO_OCCLUDER);
        } else {
            for z in chunk {
                let d = depth(*z);
                *z = if empty(*z) { NO_OCCLUDER } else { d };
            }
        }
    }
}

/// One row's covered texels of a triangle and how its depth and weights vary along them.
///
/// Coverage uses the snapped vertices (each row's covered texels are one span solved in
/// integers), interpolation the unsnapped ones (as GPUs set up their attribute planes);
/// degenerate float areas fall back to the snapped weights. Depth and weights are affine in the
/// pixel centre: each is its value at the span's first texel plus a per-pixel slope times the
/// offset (no division per pixel).
struct Span<'a> {
    t: &'a ScreenTri,
    /// The span's first texel's column.
    x0: i64,
    /// The row.
    y: i64,
    /// NDC depth at the span's first texel (planar triangles).
    z0: f64,
}

impl<'a> Span<'a> {
    fn new(t: &'a ScreenTri, x0: i64, y: i64) -> Self {
        // The depth plane through vertex 0, at the texel centre.
        let z0 =
            t.z[0] + (x0 as f64 + 0.5 - t.fx[0]) * t.dz[0] + (y as f64 + 0.5 - t.fy[0]) * t.dz[1];
        Span { t, x0, y, z0 }
    }

    /// Barycentric weights along the span: `at(j)` is the `j`-th texel's.
    #[inline]
    fn weights(&self) -> impl Fn(usize) -> [f64; 3] + '_ {
        let t = self.t;
        let (sub, cy) = (snapped::SUB, self.y * snapped::SUB + snapped::SUB / 2);
        let fe = |a: usize, b: usize, pxc: f64, pyc: f64| {
            (t.fx[b] - t.fx[a]) * (pyc - t.fy[a]) - (t.fy[b] - t.fy[a]) * (pxc - t.fx[a])
        };
        let (xc, yc) = (self.x0 as f64 + 0.5, self.y as f64 + 0.5);
        let l0 = [(1, 2), (2, 0), (0, 1)].map(|(a, b)| fe(a, b, xc, yc) / t.farea);
        move |j| {
            if t.planar {
                let k = j as f64;
                [0, 1, 2].map(|i| l0[i] + k * t.slope[i])
            } else {
                let c = (self.x0 + j as i64) * sub + sub / 2;
                [0, 1, 2].map(|i| t.snap.edge(i, c, cy) as f64 / t.snap.area as f64)
            }
        }
    }

    /// NDC depth at the span's `j`-th texel with weights `l` (which only the snapped fallback
    /// reads).
    #[inline]
    fn depth(&self, j: usize, l: [f64; 3]) -> f32 {
        if self.t.planar {
            (self.z0 + j as f64 * self.t.dz[0]) as f32
        } else {
            let z = &self.t.z;
            (l[0] * z[0] + l[1] * z[1] + l[2] * z[2]) as f32
        }
    }

    /// `update(texel, z)` for each of the span's `texels` with its depth `z`: the same depths
    /// as [`Span::depth`], without the weights where the triangle is planar (a loop without
    /// branches or calls, which vectorizes where `update` does).
    #[inline]
    fn each_depth<T>(&self, texels: &mut [T], update: impl Fn(&mut T, f32)) {
        if !self.t.planar {
            let at = self.weights();
            for (j, texel) in texels.iter_mut().enumerate() {
                update(texel, self.depth(j, at(j)));
            }
            return;
        }
        let (z0, dz) = (self.z0, self.t.dz[0]);
        for (j, texel) in texels.iter_mut().enumerate() {
            // Spans lie in the target, so `j` fits in 32 bits (which convert to f64 in vector
            // registers where 64-bit integers do not).
            update(texel, (z0 + (j as u32) as f64 * dz) as f32);
        }
    }
}

/// Rasterizes the triangles `order` names (indices into `tris`, its band's [`bins()`]) into the
/// rows `row0..` of a band; `write(texels, span)` merges each row's covered texels of a
/// triangle (`texels`, the row's texels from `span.x0`) in submission order.
fn raster_band<T>(
    tris: &Screen,
    order: &[u32],
    width: u32,
    row0: usize,
    rows: &mut [T],
    write: impl Fn(&mut [T], &Span),
) {
    let w = width as usize;
    let n_rows = rows.len() / w;
    for t in order.iter().map(|&i| tris.get(i)) {
        let (x0, x1, y0, y1) = t.texels;
        let (px0, px1) = (x0.max(0), x1.min(w as i64 - 1));
        let (py0, py1) = (y0.max(row0 as i64), y1.min((row0 + n_rows) as i64 - 1));
        if px0 > px1 || py0 > py1 {
            continue;
        }
        // py0 >= y0: the band's first row of the triangle is at or below its first row.
        let mut walk = t.rows.skipped((py0 - y0) as u32);
        for py in py0..=py1 {
            let Some((sx0, sx1)) = walk.span(px0, px1) else {
                continue;
            };
            let row = &mut rows[(py as usize - row0) * w..][..w];
            write(
                &mut row[sx0 as usize..=sx1 as usize],
                &Span::new(t, sx0, py),
            );
        }
    }
}

/// A [`raster_band`] writer that hands every covered texel to `write(texel, triangle,
/// barycentrics, ndc_depth, x, y)`, one at a time.
fn per_texel<T>(
    write: impl Fn(&mut T, &ScreenTri, [f64; 3], f32, usize, usize),
) -> impl Fn(&mut [T], &Span) {
    move |texels, span| {
        let at = span.weights();
        for (j, texel) in texels.iter_mut().enumerate() {
            let l = at(j);
            let (x, y) = (span.x0 as usize + j, span.y as usize);
            write(texel, span.t, l, span.depth(j, l), x, y);
        }
    }
}

fn fragment(t: &ScreenTri, l: [f64; 3], z: f32) -> Fragment {
    let pw = [l[0] * t.inv_w[0], l[1] * t.inv_w[1], l[2] * t.inv_w[2]];
    let s = pw[0] + pw[1] + pw[2];
    let b =
        (t.bary[0] * pw[0] as f32 + t.bary[1] * pw[1] as f32 + t.bary[2] * pw[2] as f32) / s as f32;
    Fragment {
        z_ndc: z,
        triangle: t.triangle,
        bary: b.to_array(),
    }
}

/// How one raster pass stores its texels: the cleared texel, its NDC depth, the texel of a
/// fragment, which fragments (pixel x, y, NDC depth) may enter the depth test at all, and what
/// becomes of the texels once their band is rasterized (while the band is still in cache; a
/// whole band at once, so that the pass can loop over it without a per-texel branch).
struct Target<T, Z, S, A, F> {
    empty: T,
    z_of: Z,
    shade: S,
    accept: A,
    finish: F,
}

/// Clears, rasterizes and finishes the map band by band in parallel (each band's texels are
/// written while they are in cache; the storage comes from `pool`).
fn rasterize_into<T, Z, S, A, F>(
    pool: &Arc<Pool>,
    screen: &Screen,
    width: u32,
    height: u32,
    pass: DepthPass,
    target: Target<T, Z, S, A, F>,
) -> Map2D<T>
where
    T: Clone + Send + Sync + 'static,
    Z: Fn(&T) -> f32 + Sync,
    S: Fn(&ScreenTri, [f64; 3], f32) -> T + Sync,
    A: Fn(usize, usize, f32) -> bool + Sync,
    F: Fn(&mut [T]) + Sync,
{
    let mut out = Map2D::for_overwrite(pool, width, height, target.empty.clone());
    raster_bands(
        screen,
        width,
        out.data_mut(),
        &target.empty,
        per_texel(
            |texel: &mut T, t: &ScreenTri, l: [f64; 3], z: f32, x: usize, y: usize| {
                if pass.passes(z, (target.z_of)(texel)) && (target.accept)(x, y, z) {
                    *texel = (target.shade)(t, l, z);
                }
            },
        ),
        &target.finish,
    );
    out
}

/// Rasterizes `screen` into `data` (row-major, `width` wide) band by band in parallel, each band
/// over its own triangles only ([`bins()`]): the band is cleared to `empty` (whatever `data` held),
/// `write` merges each row's span of a triangle as in [`raster_band`], then `finish` runs on the
/// band's texels, all while they are in cache.
///
/// `finish` must be per texel (what it makes of a texel depends on that texel alone): the
/// columns that no triangle's box reaches are written once, with `finish` of `empty`, and only
/// the others are cleared, rasterized and finished.
fn raster_bands<T: Clone + Send + Sync>(
    screen: &Screen,
    width: u32,
    data: &mut [T],
    empty: &T,
    write: impl Fn(&mut [T], &Span) + Sync,
    finish: impl Fn(&mut [T]) + Sync,
) {
    let w = width as usize;
    if w == 0 || data.is_empty() {
        return;
    }
    let done = {
        let mut texel = [empty.clone()];
        finish(&mut texel);
        let [done] = texel;
        done
    };
    let bins = bins(screen, width, (data.len() / w) as u32);
    data.par_chunks_mut(w * BAND_ROWS)
        .enumerate()
        // The band's column runs, found once per band (scratch kept per thread).
        .for_each_init(Vec::new, |runs, (band, rows)| {
            let bin = &bins[band];
            runs.clear();
            runs.extend(bin.runs(w));
            for row in rows.chunks_mut(w) {
                for (columns, reached) in runs.iter() {
                    row[columns.clone()].fill(if *reached { empty } else { &done }.clone());
                }
            }
            raster_band(screen, &bin.order, width, band * BAND_ROWS, rows, &write);
            for row in rows.chunks_mut(w) {
                for (columns, _) in runs.iter().filter(|(_, reached)| *reached) {
                    finish(&mut row[columns.clone()]);
                }
            }
        });
}

/// Rasterizes world-space triangles through `view` into a `width x height` map of nearest
/// fragments (storage from `pool`, as for every map here).
pub fn rasterize(
    pool: &Arc<Pool>,
    view: &View,
    width: u32,
    height: u32,
    tris: &[[Vec3; 3]],
) -> Map2D<Fragment> {
    nearest_of(
        pool,
        view,
        (width, height),
        tris,
        Fragment::EMPTY,
        |f| f.z_ndc,
        fragment,
    )
}

/// [`rasterize`]'s depth and triangle per pixel, without the barycentrics ([`Nearest`]).
pub fn rasterize_nearest(
    pool: &Arc<Pool>,
    view: &View,
    width: u32,
    height: u32,
    tris: &[[Vec3; 3]],
) -> Map2D<Nearest> {
    let shade = |t: &ScreenTri, _: [f64; 3], z_ndc: f32| Nearest {
        z_ndc,
        triangle: t.triangle,
    };
    nearest_of(
        pool,
        view,
        (width, height),
        tris,
        Nearest::EMPTY,
        |f| f.z_ndc,
        shade,
    )
}

/// The nearest fragment of every face per pixel, as `shade` stores it (`z_of` reads its NDC
/// depth back), `empty` where none.
fn nearest_of<T: Clone + Send + Sync + 'static>(
    pool: &Arc<Pool>,
    view: &View,
    (width, height): (u32, u32),
    tris: &[[Vec3; 3]],
    empty: T,
    z_of: impl Fn(&T) -> f32 + Sync,
    shade: impl Fn(&ScreenTri, [f64; 3], f32) -> T + Sync,
) -> Map2D<T> {
    let screen = setup_world(pool, view, width, height, tris, Faces::All);
    let target = Target {
        empty,
        z_of,
        shade,
        accept: |_, _, _| true,
        finish: |_: &mut [T]| {},
    };
    rasterize_into(pool, &screen, width, height, DepthPass::NEAREST, target)
}

/// A linear depth map (distance along the view axis; [`crate::view::NO_OCCLUDER`] where empty).
///
/// Depth-only: keeps 4 bytes per texel while rasterizing.
pub fn depth_map(pool: &Arc<Pool>, view: &View, resolution: u32, tris: &[[Vec3; 3]]) -> Map2D<f32> {
    depth_map_pass(pool, view, resolution, tris, DepthPass::NEAREST)
}

/// A linear depth map of the surfaces `pass` keeps ([`crate::view::NO_OCCLUDER`] where empty).
pub fn depth_map_pass(
    pool: &Arc<Pool>,
    view: &View,
    resolution: u32,
    tris: &[[Vec3; 3]],
    pass: DepthPass,
) -> Map2D<f32> {
    depth_map_pass_then(pool, view, resolution, tris, pass, |z| z)
}

/// [`depth_map_pass`] with `then` applied to every texel's linear depth (and to
/// [`crate::view::NO_OCCLUDER`] where empty) while its band is in cache: the map of
/// `then(depth)` without a second pass over the map, and without the depth map beside it.
pub fn depth_map_pass_then(
    pool: &Arc<Pool>,
    view: &View,
    resolution: u32,
    tris: &[[Vec3; 3]],
    pass: DepthPass,
    then: impl Fn(f32) -> f32 + Sync,
) -> Map2D<f32> {
    // [`depth_map_filtered`] accepting every fragment, with the depth test resolved once per
    // span so that the merge loop vectorizes.
    let screen = setup_world(pool, view, resolution, resolution, tris, pass.faces);
    let empty = pass.clear_depth();
    let mut out = Map2D::for_overwrite(pool, resolution, resolution, empty);
    raster_bands(
        &screen,
        resolution,
        out.data_mut(),
        &empty,
        |texels: &mut [f32], span: &Span| match pass.test {
            DepthTest::Nearest => span.each_depth(texels, |s, z| *s = if z > *s { z } else { *s }),
            DepthTest::Farthest => span.each_depth(texels, |s, z| *s = if z < *s { z } else { *s }),
        },
        |band: &mut [f32]| {
            pass.linearize(view, band);
            band.iter_mut().for_each(|z| *z = then(*z));
        },
    );
    out
}

/// [`depth_map_pass_then`] keeping only the fragments for which `accept(x, y, linear_depth)`
/// holds, as a fragment shader that discards: the others never enter the depth test. `then`
/// applies to every texel's linear depth as in [`depth_map_pass_then`] (`|z| z` for the linear
/// depth map itself).
pub fn depth_map_filtered(
    pool: &Arc<Pool>,
    view: &View,
    resolution: u32,
    tris: &[[Vec3; 3]],
    pass: DepthPass,
    accept: impl Fn(u32, u32, f32) -> bool + Sync,
    then: impl Fn(f32) -> f32 + Sync,
) -> Map2D<f32> {
    let screen = setup_world(pool, view, resolution, resolution, tris, pass.faces);
    let target = Target {
        empty: pass.clear_depth(),
        z_of: |z: &f32| *z,
        shade: |_: &ScreenTri, _: [f64; 3], z: f32| z,
        accept: |x: usize, y: usize, z: f32| {
            accept(x as u32, y as u32, view.linear_depth_from_ndc(z))
        },
        finish: |band: &mut [f32]| {
            pass.linearize(view, band);
            band.iter_mut().for_each(|z| *z = then(*z));
        },
    };
    rasterize_into(pool, &screen, resolution, resolution, pass, target)
}

/// The NDC depths (reversed Z; [`View::linear_depth_from_ndc`] turns them into linear depth) of
/// the texels one triangle covers in one row, in order along the row: what [`rasterize_fold`]
/// hands its update.
pub struct Depths<'a>(&'a Span<'a>);

impl Depths<'_> {
    /// NDC depth of the `j`-th texel of the span.
    pub fn at(&self, j: usize) -> f32 {
        let span = self.0;
        if span.t.planar {
            span.depth(j, [0.0; 3])
        } else {
            span.depth(j, span.weights()(j))
        }
    }

    /// Whether [`Depths::at`] is monotone along the span: true for every triangle of nonzero
    /// area (depth is one plane, evaluated in `f64` and rounded, both monotone), so a monotone
    /// function of depth that agrees at the span's two ends holds that value on all of it.
    pub fn monotone(&self) -> bool {
        self.0.t.planar
    }

    /// `update(texel, z)` for each of `texels` (the span's) with its depth `z`, in a loop that
    /// vectorizes where `update` does.
    pub fn each<T>(&self, texels: &mut [T], update: impl Fn(&mut T, f32)) {
        self.0.each_depth(texels, update)
    }
}

/// Rasterizes `tris` through `view` with no depth test: every row span a triangle covers calls
/// `update(texels, depths)` with the span's texels and their [`Depths`], in submission order,
/// starting from `empty` (as a render pass with an order-independent blend does, e.g. `Max`
/// into slice masks).
pub fn rasterize_fold<T: Clone + Send + Sync + 'static>(
    pool: &Arc<Pool>,
    view: &View,
    resolution: u32,
    tris: &[[Vec3; 3]],
    empty: T,
    update: impl Fn(&mut [T], &Depths) + Sync,
) -> Map2D<T> {
    let screen = setup_world(pool, view, resolution, resolution, tris, Faces::All);
    let mut out = Map2D::for_overwrite(pool, resolution, resolution, empty.clone());
    raster_bands(
        &screen,
        resolution,
        out.data_mut(),
        &empty,
        |texels: &mut [T], span: &Span| update(texels, &Depths(span)),
        |_| {},
    );
    out
}

/// One G-buffer texel: world position and unit normal facing the camera; `covered` false where empty.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GBufferTexel {
    /// World-space position.
    pub position: Vec3,
    /// Geometric normal, flipped to face the camera.
    pub normal: Vec3,
    /// Whether a receiver covers this pixel.
    pub covered: bool,
}

/// Face normal of a triangle, flipped to face `eye`; zero for degenerate triangles.
pub fn facing_normal(tri: &[Vec3; 3], eye: Vec3) -> Vec3 {
    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
    if n.dot(eye - tri[0]) < 0.0 { -n } else { n }
}

/// The camera G-buffer: per pixel the nearest receiver's world position and normal.
pub fn gbuffer(
    pool: &Arc<Pool>,
    view: &View,
    eye: Vec3,
    width: u32,
    height: u32,
    tris: &[[Vec3; 3]],
) -> Map2D<GBufferTexel> {
    let frags = rasterize(pool, view, width, height, tris);
    frags.map(|f| {
        if !f.is_covered() {
            return GBufferTexel {
                position: Vec3::ZERO,
                normal: Vec3::ZERO,
                covered: false,
            };
        }
        let t = &tris[f.triangle as usize];
        let position = t[0] * f.bary[0] + t[1] * f.bary[1] + t[2] * f.bary[2];
        GBufferTexel {
            position,
            normal: facing_normal(t, eye),
            covered: true,
        }
    })
}
