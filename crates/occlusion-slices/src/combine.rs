//! Combining the occlusions of several slices (section 3.3).
//!
//! Each slice `k` between a point and the light hides a fraction `I_k` of the light. If the
//! slices are independent random occluders, a ray passes all of them with probability
//! `prod(1 - I_k)` (equation 5); the true answer lies between the maximum (overlapping
//! occluders) and the clamped sum (disjoint ones), and so does the product:
//! `max I_k <= 1 - prod(1 - I_k) <= min(1, sum I_k)`. The chain ([`Combination::Chain`])
//! replaces a slice's factor by the share of the light it lets through given that its
//! neighbour nearer the light let it through ([`Accumulator::add_given`]).

use crate::params::Combination;

/// A running combination of slice occlusions; [`Accumulator::visibility`] gives `V`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Accumulator {
    how: Combination,
    value: f32,
}

impl Accumulator {
    /// No occlusion yet.
    pub(crate) fn new(how: Combination) -> Self {
        let value = match how {
            Combination::Product | Combination::Chain => 1.0,
            Combination::Sum | Combination::Max => 0.0,
        };
        Self { how, value }
    }

    /// Adds a slice that hides the fraction `i` (clamped to [0, 1]) of the light.
    pub(crate) fn add(&mut self, i: f32) {
        let i = i.clamp(0.0, 1.0);
        match self.how {
            Combination::Product | Combination::Chain => self.value *= 1.0 - i,
            Combination::Sum => self.value += i,
            Combination::Max => self.value = self.value.max(i),
        }
    }

    /// A slice that hides the fraction `union` of the light together with its neighbour nearer
    /// the light, which alone hides `nearer` of it (both over this slice's kernel), read with
    /// weight `w` (the rest of its weight `1 - w` the share `slab` of [`Accumulator::add`]'s
    /// unfiltered read, as a fading slice is): the factor `w given(union, nearer) + (1 - w)
    /// (1 - slab)`, which at `w = 0` is the product's.
    pub(crate) fn add_given(&mut self, union: f32, nearer: f32, w: f32, slab: f32) {
        debug_assert!(self.how.chained(), "{:?} has no chain", self.how);
        self.value *= w * given(union, nearer) + (1.0 - w) * (1.0 - slab.clamp(0.0, 1.0));
    }

    /// The visible fraction of the light, in [0, 1].
    pub(crate) fn visibility(&self) -> f32 {
        match self.how {
            Combination::Product | Combination::Chain => self.value.clamp(0.0, 1.0),
            Combination::Sum | Combination::Max => 1.0 - self.value.clamp(0.0, 1.0),
        }
    }
}

/// The least share of the light [`given`] divides by: one step of the 8-bit filtered textures.
pub(crate) const CHAIN_EPSILON: f32 = 1.0 / 255.0;

/// The chain's factor: the share of the light that passes a slice among what passed its
/// neighbour, `1 - (union - nearer) / (1 - nearer)` from the union's occlusion and the
/// neighbour's, clamped to [0, 1]; exact where the neighbour lets at least [`CHAIN_EPSILON`]
/// through, and 1 where it hides everything the union does (`visibility.wgsl`'s `given`).
pub(crate) fn given(union: f32, nearer: f32) -> f32 {
    let (u, b) = (union.clamp(0.0, 1.0), nearer.clamp(0.0, 1.0));
    (1.0 - (u - b) / (1.0 - b).max(CHAIN_EPSILON)).clamp(0.0, 1.0)
}

/// `V` of a set of slice occlusions combined by `how`.
#[cfg(test)]
pub fn combine(how: Combination, occlusions: &[f32]) -> f32 {
    let mut a = Accumulator::new(how);
    for &i in occlusions {
        a.add(i);
    }
    a.visibility()
}
