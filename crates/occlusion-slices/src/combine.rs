//! Combining the occlusions of several slices (section 3.3).
//!
//! Each slice `k` between a point and the light hides a fraction `I_k` of the light. If the
//! slices are independent random occluders, a ray passes all of them with probability
//! `prod(1 - I_k)` (equation 5); the true answer lies between the maximum (overlapping
//! occluders) and the clamped sum (disjoint ones), and so does the product:
//! `max I_k <= 1 - prod(1 - I_k) <= min(1, sum I_k)`.

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
            Combination::Product => 1.0,
            Combination::Sum | Combination::Max => 0.0,
        };
        Self { how, value }
    }

    /// Adds a slice that hides the fraction `i` (clamped to [0, 1]) of the light.
    pub(crate) fn add(&mut self, i: f32) {
        let i = i.clamp(0.0, 1.0);
        match self.how {
            Combination::Product => self.value *= 1.0 - i,
            Combination::Sum => self.value += i,
            Combination::Max => self.value = self.value.max(i),
        }
    }

    /// The visible fraction of the light, in [0, 1].
    pub(crate) fn visibility(&self) -> f32 {
        match self.how {
            Combination::Product => self.value.clamp(0.0, 1.0),
            Combination::Sum | Combination::Max => 1.0 - self.value.clamp(0.0, 1.0),
        }
    }
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
