//! The shared budget kept as the frame runs, on the CPU: a shared light whose maps must be made
//! waits a frame where what the frame has measured so far says they would take it past its
//! [`crate::FrameBudget`].
//!
//! The budget shares the frame by predictions ([`crate::budget`]), and a prediction can be
//! wrong where nothing has been measured yet: the first frame of a world runs on the profile
//! alone, and the profile, fitted on the catalogue's larger scenes measured warm, prices a
//! street's small lamps at half or a third of what their first maps take in a frame; nor is the
//! pipeline's own time known before a frame has measured it. Before it makes a shared light's
//! maps, the technique's system adds up what the frame has spent (its wall time so far, less
//! the lights outside the budget) and what it still has to do: this light's generation, the
//! evaluations of every shared light yet to run, and the generations of those of them whose
//! shadows are worth more (its part of the frame's light times what its missing shadow
//! costs), each prediction (calibrated) scaled by how far this frame's measured
//! generations and evaluations ran over theirs (as it is, before any was measured). Each
//! technique's system runs its shared lights worth most first. Where that sum passes the budget,
//! the light keeps its old maps (a frame late; its `V` then shows the shadow before the change
//! that made them stale) or, with none, has no shadow this frame ([`crate::LightState::error`]
//! and [`crate::LightStats::waited`] say so), and does not wait in the next frame: no light
//! waits two frames in a row. A light whose shadow was on screen in the last frame and whose
//! maps a new pick dropped does not wait: that would take its shadow off for a frame.
//!
//! GPU frames are not held (their passes run on the device after the frame's systems, so the
//! systems' clock does not measure them), nor frames that do not calibrate
//! ([`crate::FrameSettings::calibrating`] off: picks from predictions alone) or do not evaluate
//! the receivers ([`crate::FrameSettings::evaluate_receivers`] off). A cascade planned again
//! for a moved camera (or new settings: [`crate::FrameSettings::cascade_fit`]) does not wait
//! either. The clock starts with [`crate::FramePipeline::run`],
//! so the frame's spent time holds everything the call does before the light.

use bevy_ecs::prelude::*;
use std::time::Instant;

/// One frame's clock for the shared budget ([`crate::deadline`]).
#[derive(Resource, Debug, Default)]
pub(crate) struct Deadline {
    /// When the frame started.
    start: Option<Instant>,
    /// The lights that waited in the last frame: they do not wait in this one.
    waited: Vec<Entity>,
    /// The lights that wait in this frame.
    waiting: Vec<Entity>,
    /// Measured milliseconds of the lights outside the budget that ran in this frame.
    outside_ms: f64,
    /// This frame's generations of shared lights: measured and predicted (calibrated)
    /// milliseconds, summed.
    generations: [f64; 2],
    /// The same for their evaluations, each with its share of its system's own work.
    evaluations: [f64; 2],
}

/// A shared light yet to run in the frame, as the calibration predicts it (milliseconds).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pending {
    /// The light.
    pub light: Entity,
    /// Its generation, where its maps are to be made (0 otherwise).
    pub generate_ms: f64,
    /// Its evaluation.
    pub evaluate_ms: f64,
    /// What its shadow is worth to the frame ([`crate::budget::worth`]).
    pub worth: f64,
    /// Its maps are made this frame whatever the clock says (its shadow was on screen and a
    /// new pick dropped its maps).
    pub must: bool,
}

impl Deadline {
    /// Starts a frame at `now`: the lights that waited in the last one do not wait in it.
    pub(crate) fn begin_frame(&mut self, now: Instant) {
        self.start = Some(now);
        self.waited = std::mem::take(&mut self.waiting);
        self.outside_ms = 0.0;
        self.generations = [0.0; 2];
        self.evaluations = [0.0; 2];
    }

    /// What the frame has spent on the budget's work so far: its wall time less the lights
    /// outside the budget (milliseconds).
    pub(crate) fn spent_ms(&self) -> f64 {
        self.start
            .map_or(0.0, |s| s.elapsed().as_secs_f64() * 1e3 - self.outside_ms)
    }

    /// How far this frame's measured times ran over their predictions, for `[generation,
    /// evaluation]` (1 where none was measured yet).
    fn overrun(&self) -> [f64; 2] {
        [self.generations, self.evaluations].map(|[measured, predicted]| {
            if predicted > 0.0 {
                measured / predicted
            } else {
                1.0
            }
        })
    }

    /// Whether `light`, its maps to be made, waits, and if so what the frame would take with
    /// them: `spent_ms` ([`Deadline::spent_ms`]) and what is still to come would pass
    /// `budget_ms`. What is still to come: `light`'s generation and evaluation, the
    /// evaluations of the shared lights yet to run (`rest`), and the generations of those of
    /// them whose shadows are worth more ([`crate::budget::worth`]), whose maps are made for
    /// sure ([`Pending::must`]) or that waited in the last frame (their generations count
    /// first), each scaled by how far this frame's measured generations or evaluations ran
    /// over their predictions. A light never waits in two frames in a row.
    pub(crate) fn waits(
        &mut self,
        light: Pending,
        rest: &[Pending],
        budget_ms: f64,
        spent_ms: f64,
    ) -> Option<f64> {
        if self.waited.contains(&light.light) {
            return None;
        }
        let [g, e] = self.overrun();
        let first = |p: &Pending| p.worth > light.worth || p.must || self.waited.contains(&p.light);
        let need = spent_ms
            + std::iter::once(&light)
                .chain(rest)
                .map(|p| {
                    let generate_ms = if p.light == light.light || first(p) {
                        p.generate_ms
                    } else {
                        0.0
                    };
                    generate_ms * g + p.evaluate_ms * e
                })
                .sum::<f64>();
        (need > budget_ms).then(|| {
            self.waiting.push(light.light);
            need
        })
    }

    /// Takes in a shared light that ran: its measured generation and evaluation (with its
    /// share of its system's own work) against their predictions (milliseconds; a prediction
    /// of 0 where it did not generate or evaluate).
    pub(crate) fn ran(&mut self, measured: [f64; 2], predicted: [f64; 2]) {
        for (sums, (m, p)) in [&mut self.generations, &mut self.evaluations]
            .into_iter()
            .zip(measured.into_iter().zip(predicted))
        {
            if p > 0.0 {
                sums[0] += m;
                sums[1] += p;
            }
        }
    }

    /// The lights whose maps wait in this frame.
    pub(crate) fn waiting(&self) -> &[Entity] {
        &self.waiting
    }

    /// Takes in a light outside the budget that ran for `ms`.
    pub(crate) fn ran_outside(&mut self, ms: f64) {
        self.outside_ms += ms;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(i: u32) -> Entity {
        Entity::from_raw_u32(i).unwrap()
    }

    fn pending(i: u32, worth: f64) -> Pending {
        Pending {
            light: light(i),
            generate_ms: 2.0,
            evaluate_ms: 1.0,
            worth,
            must: false,
        }
    }

    /// Before anything of a frame is measured, each prediction counts as it is; after a
    /// generation that took twice its prediction, at that overrun: a light whose predicted rest
    /// fits the budget only at the predictions waits, and it does not wait in the next frame;
    /// the generations of the lights yet to run whose shadows are worth more count before its
    /// own.
    #[test]
    fn a_light_waits_when_the_measured_frame_would_pass_the_budget_and_only_once() {
        let mut d = Deadline::default();
        d.begin_frame(Instant::now());
        let rest = [pending(3, 0.1)];
        // 1 spent + 2 + 1 + 1 = 5.
        assert_eq!(d.waits(pending(0, 0.5), &rest, 5.0, 1.0), None);
        assert_eq!(d.waits(pending(5, 0.5), &rest, 4.5, 1.0), Some(5.0));
        d.ran([2.0, 1.0], [1.0, 1.0]);
        // 4 spent + 2 x 2 + 2 x 1 = 10 > 9; at the predictions, 4 + 2 + 2 = 8 would fit.
        assert_eq!(d.waits(pending(1, 0.5), &rest, 9.0, 4.0), Some(10.0));
        assert_eq!(d.waits(pending(2, 0.5), &rest, 10.5, 4.0), None);
        // Maps made for sure count whatever they are worth (10 + 2 x 2 = 14).
        let forced = Pending {
            must: true,
            ..pending(6, 0.01)
        };
        assert_eq!(d.waits(pending(7, 0.5), &[forced], 13.0, 4.0), Some(14.0));
        // Light 3's shadow is worth more than light 4's: its generation counts too (10 + 2 x 2 = 14).
        assert_eq!(d.waits(pending(4, 0.05), &rest, 13.0, 4.0), Some(14.0));
        d.begin_frame(Instant::now());
        d.ran([2.0, 1.0], [1.0, 1.0]);
        assert_eq!(d.waits(pending(1, 0.5), &rest, 9.0, 4.0), None);
        assert_eq!(d.waits(pending(2, 0.5), &rest, 9.0, 4.0), Some(10.0));
        // Light 4 waited in the last frame: its generation counts before light 2's, whatever
        // it brings (4 + 2 x 2 + 1 + 2 x 2 + 1 = 14).
        assert_eq!(
            d.waits(pending(2, 0.5), &[pending(4, 0.05)], 13.5, 4.0),
            Some(14.0)
        );
    }
}
