//! The last generation step, shared by both generators: per texel the nearest geometry, the
//! winning edge `(c, p_i)` and the lower limit become the stored `(c, g, b, p_i)`.
//!
//! - With an edge: `g` is the geometry depth inside the silhouette (`p_i < 0`); outside it is
//!   raised to the outer penumbra limit `c + p_i` where that lies above the geometry, so `g`
//!   does not clip the outer penumbra away (section 3.1, step 2). Outer texels beside an inner
//!   texel of the same edge (the silhouette runs between them) are raised only to `c`: `g` is
//!   interpolated bilinearly, and `c + p_i` there would lift it above receivers less than half a
//!   texel's penumbra depth below the edge, moving the edge of a contact shadow inwards by up to
//!   a texel (Lawlor Fig. 10's triangle at 32²: 18.4 rms without receiver bias, 3.2 with this).
//!   Not at occluder transitions (below): there `b = g` puts everything below `g` in that
//!   geometry's shadow, and
//!   `g = c` darkened lit ground beside a curved caster on `acne` at 16².
//! - Outer texels over another caster (`p_i >= 0` and geometry deeper or nearer than `c` by more
//!   than the transition gap): below that caster `b` is its depth, where its shadow begins. The paper
//!   keeps one edge per texel ("highest penumbra limit wins"), so where one blocker's outer
//!   ribbon wins over another blocker, the receivers under that other blocker read the edge's
//!   outer penumbra, at least half lit: on `overlap` at 2048², the bottom blocker's top under a
//!   higher edge (V rms 95.5 over 1650 receivers) and a lit streak on the ground inside the top
//!   blocker's umbra under the middle one's edge (124 receivers of the 128² G-buffer at 256²,
//!   V 0.69-0.81 against 0.00-0.05). The evaluation gives receivers below it that caster's
//!   soft shadow (`eval::lower_shadow`), not its hard shadow: where the covering caster is thin
//!   (an ear, a leg) its own penumbra reaches under the texel, and the hard shadow was false
//!   umbra (black blotches by a low-poly animal's feet at 1280 x 720).
//! - Without one (beyond every ribbon): the hard shadow, lit above the geometry and umbra below
//!   it: `c = g` and `p_i = -MAX_P` where there is geometry (so a receiver between the inner end
//!   of a ribbon and such a texel interpolates towards umbra, not towards "outside"), `c` =
//!   "none" and `p_i = MAX_P` where there is none.
//! - Occluder transitions (Figure 7 C): where `c` jumps between 4-neighbours by more than the
//!   transition gap, `b` is the geometry depth, which clamps the soft shadow there: below the
//!   geometry the lower layer's inner penumbra inside the silhouette, and on both sides no
//!   more than the geometry's own soft shadow (`eval::lower_shadow`). Not the raised `g` of an
//!   outer texel: where no geometry is,
//!   there is no hard shadow, and `b = c + p_i` made every receiver below the outer limit
//!   umbra, streaks of false umbra where ribbons of neighbouring edges meet (the bunny under a
//!   disk light at 1024²).
//!
//! `combine.wgsl` is the same per-texel code.

use crate::storage::{MAX_P, Storage, StoreScratch, Texel};
use crate::warp::{NONE_DEPTH, Warp};
use rayon::prelude::*;
use soft_shadow_core::Map2D;

/// The generators' output, before storage.
pub(crate) struct Layers {
    /// Normalised depth of the nearest geometry ([`NONE_DEPTH`] where empty).
    pub geom: Map2D<f32>,
    /// The winning edge: `[c, p_i]` normalised, `c =` [`NONE_DEPTH`] where no ribbon reaches.
    pub edge: Map2D<[f32; 2]>,
    /// Normalised lower limit ([`NONE_DEPTH`] where none).
    pub lower: Map2D<f32>,
}

/// The edge value of a texel no ribbon reaches.
pub(crate) const NO_EDGE: [f32; 2] = [NONE_DEPTH, MAX_P];

/// Whether an edge value is real.
pub(crate) fn has_edge(e: [f32; 2]) -> bool {
    e[0] < NONE_DEPTH
}

/// The stored texel from its geometry depth, lower limit, edge and its four neighbours' edges
/// (left, right, up, down; clamped to the map).
fn texel(
    geom: f32,
    lower: f32,
    e: [f32; 2],
    neighbours: [[f32; 2]; 4],
    warp: &Warp,
    transition_gap: f32,
) -> Texel {
    if !has_edge(e) {
        let solid = geom < NONE_DEPTH;
        return Texel {
            c: geom,
            g: geom,
            b: lower,
            p: if solid { -MAX_P } else { MAX_P },
        };
    }
    let [c, p] = e;
    let gap = warp.depth_gap(warp.linear(c), transition_gap);
    let transition = neighbours
        .iter()
        .any(|n| has_edge(*n) && (n[0] - c).abs() > gap);
    // An outer texel beside an inner texel of the same edge, away from occluder transitions:
    // the silhouette runs between them.
    let straddles = !transition
        && neighbours
            .iter()
            .any(|n| has_edge(*n) && n[1] < 0.0 && (n[0] - c).abs() <= gap);
    let g = if p < 0.0 {
        geom
    } else if straddles {
        geom.min(c)
    } else {
        geom.min(c + p)
    };
    // An outer texel over another caster (geometry deeper or nearer than the edge by more than
    // the gap): below that caster is its shadow (eval::lower_shadow), not this edge's outer
    // penumbra.
    let covered = p >= 0.0 && geom < NONE_DEPTH && (geom - c).abs() > gap;
    Texel {
        c,
        g,
        b: if transition || covered { geom } else { lower },
        p,
    }
}

/// The stored map: every texel combined, then quantised by `storage`.
pub(crate) fn combine(
    pool: &std::sync::Arc<soft_shadow_core::pool::Pool>,
    l: &Layers,
    warp: &Warp,
    transition_gap: f32,
    storage: Storage,
) -> Map2D<Texel> {
    let (w, h) = (l.geom.width(), l.geom.height());
    // Every texel is written below: no clearing pass.
    let mut data = pool.overwrite(w as usize * h as usize, Texel::default());
    data.par_chunks_mut(w.max(1) as usize)
        .enumerate()
        .for_each_init(StoreScratch::default, |scratch, (y, row)| {
            // Rows of the layers as slices: no per-texel index arithmetic or bounds clamping
            // beyond the two row ends.
            let (w, h) = (w as usize, h as usize);
            let at = |y: usize| y * w..(y + 1) * w;
            let edge = l.edge.data();
            let (up, here, down) = (
                &edge[at(y.saturating_sub(1))],
                &edge[at(y)],
                &edge[at((y + 1).min(h - 1))],
            );
            let (geom, lower) = (&l.geom.data()[at(y)], &l.lower.data()[at(y)]);
            for (x, t) in row.iter_mut().enumerate() {
                let neighbours = [
                    here[x.saturating_sub(1)],
                    here[(x + 1).min(w - 1)],
                    up[x],
                    down[x],
                ];
                *t = texel(geom[x], lower[x], here[x], neighbours, warp, transition_gap);
            }
            storage.store(row, scratch);
        });
    Map2D::from_vec(w, h, data)
        .unwrap_or_else(|| Map2D::new(0, 0, Texel::default()))
        .returning_to(pool)
}
