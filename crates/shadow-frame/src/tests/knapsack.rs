//! `budget::cheapest_error`: the least weighted image error a budget buys, against every choice
//! tried, and the case a greedy by error per millisecond got wrong.

use crate::budget::{BUDGET_STEPS, cheapest_error};

/// The summed weighted error of `at` and the milliseconds it spends.
fn score(ladders: &[Vec<(f64, f64)>], weights: &[(f64, f64)], at: &[Option<usize>]) -> (f64, f64) {
    let mut error = 0.0;
    let mut ms = 0.0;
    for ((ladder, &(part, none)), k) in ladders.iter().zip(weights).zip(at) {
        match k {
            Some(k) => {
                error += part * ladder[*k].1;
                ms += ladder[*k].0;
            }
            None => error += part * none,
        }
    }
    (error, ms)
}

/// The room at 16 ms over 160 x 90 receivers, its ladders as the profile predicted them (ms
/// with margins, image error): a greedy by error per millisecond bought the table lamp's
/// upgrades (15.4 ms) and left the ceiling panel, 45% of the light, without a shadow; both
/// cheapest configurations fit together and take far more error off.
#[test]
fn the_budget_gives_two_lamps_their_first_shadows_before_one_its_upgrades() {
    let ladders = vec![
        vec![
            (8.21, 3.01),
            (9.63, 1.82),
            (9.67, 1.08),
            (11.00, 1.06),
            (11.70, 1.05),
            (15.38, 0.94),
        ],
        vec![(7.17, 7.08), (7.97, 7.00), (8.39, 3.81), (10.79, 3.08)],
        vec![(7.14, 5.28), (8.36, 2.80)],
    ];
    let weights = [(1224.0, 15.0), (1084.0, 15.0), (79.0, 15.0)];
    let at = cheapest_error(&ladders, &weights, 16.0);
    let (error, ms) = score(&ladders, &weights, &at);
    assert_eq!(
        at,
        vec![Some(0), Some(0), None],
        "error {error:.0}, {ms:.2} ms"
    );
    assert!(ms <= 16.0);
    // What the greedy bought: the table lamp's last rung alone.
    let (greedy, _) = score(&ladders, &weights, &[Some(5), None, None]);
    assert!(
        error < 0.7 * greedy,
        "{error:.0} against the greedy's {greedy:.0}"
    );
}

/// On 400 small random cases (up to 4 lights, up to 4 rungs each, times rounded to the
/// budget's steps), the choice is as good as the best of every choice within the budget, and
/// never spends more than it.
#[test]
fn the_budget_buys_the_least_error_any_choice_within_it_gives() {
    let mut seed = 0x5eed_u64;
    let mut next = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 33) as f64) / (1u64 << 31) as f64
    };
    let available = 16.0;
    let step = available / BUDGET_STEPS as f64;
    for case in 0..400 {
        let lights = 1 + (next() * 4.0) as usize;
        let mut ladders = Vec::new();
        let mut weights = Vec::new();
        for _ in 0..lights {
            let rungs = 1 + (next() * 4.0) as usize;
            let (mut ms, mut error) = (0.5 + next() * 8.0, 2.0 + next() * 10.0);
            let mut ladder = Vec::new();
            for _ in 0..rungs {
                // Whole steps, so that rounding decides nothing.
                ladder.push(((ms / step).ceil() * step, error));
                ms += 0.2 + next() * 5.0;
                error *= 0.3 + 0.6 * next();
            }
            ladders.push(ladder);
            weights.push((next() * 100.0, 15.0));
        }
        let at = cheapest_error(&ladders, &weights, available);
        let (error, ms) = score(&ladders, &weights, &at);
        assert!(ms <= available + 1e-9, "case {case}: {ms} ms");
        // Every choice: each light none or one of its rungs.
        let mut best = f64::INFINITY;
        let sizes: Vec<usize> = ladders.iter().map(|l| l.len() + 1).collect();
        let total: usize = sizes.iter().product();
        for mut code in 0..total {
            let choice: Vec<Option<usize>> = sizes
                .iter()
                .map(|&s| {
                    let k = code % s;
                    code /= s;
                    k.checked_sub(1)
                })
                .collect();
            let (e, t) = score(&ladders, &weights, &choice);
            if t <= available + 1e-9 {
                best = best.min(e);
            }
        }
        assert!(
            error <= best + 1e-9 * best.max(1.0),
            "case {case}: {error} against the best {best}"
        );
    }
}

/// No budget buys nothing; a rung over the whole budget is never bought.
#[test]
fn no_budget_buys_no_shadow() {
    let ladders = vec![vec![(1.0, 1.0)], vec![(20.0, 0.5)]];
    let weights = [(1.0, 15.0), (1.0, 15.0)];
    assert_eq!(cheapest_error(&ladders, &weights, 0.0), vec![None, None]);
    assert_eq!(
        cheapest_error(&ladders, &weights, f64::NAN),
        vec![None, None]
    );
    assert_eq!(
        cheapest_error(&ladders, &weights, 16.0),
        vec![Some(0), None]
    );
}

/// What cannot be weighed buys nothing and spoils no other light: a part or a rung that is
/// not finite, a missing shadow that is not (counted as the median); a ladder out of order is
/// answered with its own indices.
#[test]
fn bad_weights_buy_nothing_and_spoil_no_other_light() {
    let ladders = vec![
        vec![(2.0, 1.0)],
        vec![(2.0, f64::NAN), (f64::NAN, 0.5), (3.0, 2.0)],
        vec![(9.0, 0.5), (4.0, 3.0)],
        vec![(2.0, 1.0)],
    ];
    let weights = [(f64::NAN, 15.0), (1.0, f64::NAN), (1.0, 15.0), (1.0, 15.0)];
    let at = cheapest_error(&ladders, &weights, 16.0);
    assert_eq!(at[0], None, "{at:?}");
    assert_eq!(at[1], Some(2), "{at:?}");
    assert_eq!(at[2], Some(0), "{at:?}");
    assert_eq!(at[3], Some(0), "{at:?}");
}
