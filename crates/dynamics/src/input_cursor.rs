//! Recorded inputs cut into the windows between measurements: the one place that decides
//! which input samples a prediction integrates over (docs/model.md eq. (15)).
//!
//! A window runs from the last measurement's time to the next one's. Its ends are the inputs
//! linearly interpolated at those times (or the sample itself when one falls on the instant),
//! and between them lie the samples strictly inside. The filters' runner, the Monte Carlo's
//! bound recursion and the diagnosis (which classifies each step's motion from the same
//! window) all cut their windows here, so they cannot drift apart.

use crate::dataset::InputSample;
use crate::integrate::InputWindow;
use crate::kinematics::Input;

/// Times closer than this are the same instant (input and measurement clocks printed with
/// finite digits).
pub const SAME_TIME: f64 = 1e-9;

/// Where a walk through recorded inputs stands: the time reached and the first sample after
/// it. Cheap to copy; it holds no samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputCursor {
    t_now: f64,
    /// Index of the first sample with `t > t_now` (beyond [`SAME_TIME`]).
    next: usize,
}

impl InputCursor {
    /// A cursor at time `t` of `inputs` (sorted by time).
    pub fn at(inputs: &[InputSample], t: f64) -> Self {
        InputCursor {
            t_now: t,
            next: inputs.partition_point(|s| s.t <= t + SAME_TIME),
        }
    }

    /// The time reached.
    pub fn time(&self) -> f64 {
        self.t_now
    }

    /// Fills `window` (cleared first) with the knots from the time reached to `t_end`, and
    /// moves there. `t_end` should be later than [`InputCursor::time`]; an earlier one gives
    /// a window that runs backwards, which a caller skips instead.
    pub fn advance(&mut self, inputs: &[InputSample], t_end: f64, window: &mut InputWindow) {
        window.clear();
        window.push_linear(self.t_now, interpolate(inputs, self.next, self.t_now));
        let mut next = self.next;
        while next < inputs.len() && inputs[next].t < t_end - SAME_TIME {
            window.push_linear(inputs[next].t, inputs[next].f);
            next += 1;
        }
        let f_end = if next < inputs.len() && (inputs[next].t - t_end).abs() <= SAME_TIME {
            inputs[next].f
        } else {
            interpolate(inputs, next, t_end)
        };
        window.push_linear(t_end, f_end);
        while next < inputs.len() && inputs[next].t <= t_end + SAME_TIME {
            next += 1;
        }
        self.t_now = t_end;
        self.next = next;
    }
}

/// The input at `t`, interpolated between the samples around it (`next` is the first one
/// after `t`); the nearest sample beyond either end of the record.
fn interpolate(inputs: &[InputSample], next: usize, t: f64) -> Input {
    match (
        next.checked_sub(1).and_then(|i| inputs.get(i)),
        inputs.get(next),
    ) {
        (Some(a), Some(b)) => lerp(a, b, t),
        (Some(a), None) => a.f,
        (None, Some(b)) => b.f,
        (None, None) => [0.0; crate::kinematics::INPUT_WIDTH],
    }
}

fn lerp(a: &InputSample, b: &InputSample, t: f64) -> Input {
    let u = if b.t > a.t {
        (t - a.t) / (b.t - a.t)
    } else {
        0.0
    };
    std::array::from_fn(|i| a.f[i] + u * (b.f[i] - a.f[i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(ts: &[f64]) -> Vec<InputSample> {
        ts.iter()
            .map(|&t| InputSample {
                t,
                f: crate::kinematics::platform_input([t, 2.0 * t, -t]),
            })
            .collect()
    }

    #[test]
    fn windows_on_the_sample_grid_hold_the_samples_themselves() {
        let inputs = samples(&[0.0, 0.1, 0.2, 0.3, 0.4]);
        let mut cursor = InputCursor::at(&inputs, 0.0);
        let mut w = InputWindow::with_capacity(8);
        cursor.advance(&inputs, 0.2, &mut w);
        assert_eq!(w.t, vec![0.0, 0.1, 0.2]);
        assert_eq!(w.f, vec![inputs[0].f, inputs[1].f, inputs[2].f]);
        cursor.advance(&inputs, 0.4, &mut w);
        assert_eq!(w.t, vec![0.2, 0.3, 0.4]);
        assert_eq!(cursor.time(), 0.4);
    }

    #[test]
    fn ends_between_samples_are_interpolated_and_beyond_the_record_held() {
        let inputs = samples(&[0.0, 1.0, 2.0]);
        let mut cursor = InputCursor::at(&inputs, 0.25);
        let mut w = InputWindow::with_capacity(8);
        cursor.advance(&inputs, 1.5, &mut w);
        assert_eq!(w.t, vec![0.25, 1.0, 1.5]);
        assert_eq!(w.f[0][..3], [0.25, 0.5, -0.25]);
        assert_eq!(w.f[2][..3], [1.5, 3.0, -1.5]);
        cursor.advance(&inputs, 3.0, &mut w);
        assert_eq!(w.t, vec![1.5, 2.0, 3.0]);
        assert_eq!(w.f[2], inputs[2].f, "held at the last sample");
    }

    #[test]
    fn a_measurement_a_clock_tick_off_a_sample_takes_that_sample() {
        let inputs = samples(&[0.0, 1.0, 2.0]);
        let mut cursor = InputCursor::at(&inputs, 0.0);
        let mut w = InputWindow::with_capacity(8);
        cursor.advance(&inputs, 1.0 + 1e-12, &mut w);
        assert_eq!(w.t.len(), 2, "no knot 1e-12 s before the end");
        assert_eq!(w.f[1], inputs[1].f);
        cursor.advance(&inputs, 2.0, &mut w);
        assert_eq!(w.t.len(), 2, "the sample at 1 s is behind the cursor");
    }
}
