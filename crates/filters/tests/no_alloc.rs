//! Filter steps allocate nothing: after construction and reset, 1000 predictions and updates
//! of each filter make no heap allocation, and neither does a `Runner` after its first step.
//!
//! A counting global allocator (this test binary only) wraps the system allocator and counts
//! allocations and reallocations made by the current thread while counting is switched on
//! (a thread-local flag and counter, so the test harness's other threads and the tests
//! running in parallel do not disturb the count).
//!
//! What it catches: a `Vec` built, grown or cloned in a step (a `to_vec`, a `collect`, a
//! `format!` on a success path, a buffer sized per call, nalgebra temporaries), in the EKF,
//! either UKF's prediction or either update path (linear and sigma-point), or in the runner's
//! loop.

mod common;

use navkf_dynamics::state::*;
use navkf_dynamics::*;
use navkf_filters::*;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::Arc;

struct Counting;

thread_local! {
    static ON: Cell<bool> = const { Cell::new(false) };
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

fn note() {
    // `try_with`: the allocator may run while a thread's locals are being torn down.
    if ON.try_with(|on| on.get()).unwrap_or(false) {
        let _ = COUNT.try_with(|c| c.set(c.get() + 1));
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note();
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note();
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note();
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made by this thread so far while counting.
fn allocations() -> usize {
    COUNT.with(|c| c.get())
}

/// Runs `f` with counting on; returns its value and the allocations it made.
fn counted<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let before = allocations();
    ON.with(|on| on.set(true));
    let v = f();
    ON.with(|on| on.set(false));
    (v, allocations() - before)
}

#[test]
fn the_counter_counts() {
    let (v, n) = counted(|| vec![1u8; 100]);
    assert_eq!(v.len(), 100);
    assert_eq!(n, 1, "the counting allocator does not see allocations");
}

fn filters(m: &std::sync::Arc<PlatformModel>) -> Vec<Box<dyn Filter>> {
    // Every filter the harness has: a new one cannot be missed.
    navkf_filters::FilterKind::ALL
        .iter()
        .map(|k| k.build(m.clone(), SigmaScaling::default()).unwrap())
        .collect()
}

/// `steps` predict + update steps at rest, everything built up front, counted.
fn steps_allocate_nothing(m: Arc<PlatformModel>, steps: usize) {
    let n = m.dim();
    let (x0, p0) = common::at_rest(n, |_| 1e-6);
    let mut window = InputWindow::with_capacity(11);
    for k in 0..=10 {
        window.push_linear(k as f64 * 0.1, [0.01, -0.02, 9.806]);
    }
    let z = [0.0, 0.0, x0[LAT], x0[LON]];
    let sigma = NoiseConfig::default().measurement_sigmas(0.0, x0[LAT]);
    let available = [true; 4];
    let obs = Observation {
        z: &z,
        sigma: &sigma,
        available: &available,
    };
    // Every other step has no GPS (a smaller update).
    let some = [true, true, false, false];
    let obs_vel = Observation {
        z: &z,
        sigma: &sigma,
        available: &some,
    };
    for mut f in filters(&m) {
        f.reset(&x0, &p0).unwrap();
        let (res, allocs) = counted(|| -> Result<(), FilterError> {
            for k in 0..steps {
                f.predict(&window)?;
                f.update(if k % 2 == 0 { &obs } else { &obs_vel })?;
            }
            Ok(())
        });
        res.unwrap_or_else(|e| panic!("{}: {e}", f.name()));
        assert_eq!(
            allocs,
            0,
            "{} ({} states): {steps} steps made {allocs} allocations",
            f.name(),
            n
        );
    }
}

#[test]
fn filter_steps_allocate_nothing_on_the_base_model() {
    steps_allocate_nothing(Arc::new(PlatformModel::base(&NoiseConfig::default())), 1000);
}

#[test]
fn filter_steps_allocate_nothing_with_a_nonlinear_measurement_and_coefficient_noise() {
    // odometer-scale and gps-latency make the measurement non-linear (the simplified UKF's
    // sigma-point update path); gyro-bias-walk puts noise on constant states.
    let noise = NoiseConfig::default();
    let fx = Registry::catalogue()
        .build_all(&["odometer-scale", "gps-latency", "gyro-bias-walk"])
        .unwrap();
    let m = Arc::new(PlatformModel::new(fx, &noise).unwrap());
    assert!(!m.measurement_is_linear());
    // Fewer steps here: the paths are the same from the second step on.
    steps_allocate_nothing(m, 100);
}

/// The runner over the first `steps` measurements of one run: allocations in the whole run,
/// and the running count after each step.
fn runner_counts(knots: usize, steps: usize) -> (usize, Vec<usize>) {
    let sim = common::base_simulator(600.0);
    let run = sim.run(9, 0);
    let (x0, p0) = common::initial_estimate(&sim, &run);
    let mut f = Ukf::simplified(sim.model().clone(), SigmaScaling::default()).unwrap();
    f.reset(&x0, &p0).unwrap();
    let mut runner = Runner::new(knots);
    let mut after_step = Vec::with_capacity(steps);
    let meas = &run.measurements[..steps];
    let before = allocations();
    let (res, total) = counted(|| {
        runner.run(&mut f, 0.0, sim.inputs(), meas, sim.noise(), |_| {
            after_step.push(allocations() - before)
        })
    });
    res.unwrap();
    assert_eq!(after_step.len(), steps);
    (total, after_step)
}

#[test]
fn runner_allocates_nothing_after_its_first_step() {
    // Room for the 11 knots of a 1 s window at 10 Hz: nothing at all.
    let (total, _) = runner_counts(16, 200);
    assert_eq!(
        total, 0,
        "runner with room for its windows made {total} allocations"
    );
    // No room: the window grows in the first step, then never again.
    let (total, after) = runner_counts(1, 200);
    assert!(
        after[0] > 0,
        "the window must have grown in the first step (else this tests nothing)"
    );
    assert_eq!(
        total,
        after[0],
        "allocations after the first step: {} (running count per step {:?}...)",
        total - after[0],
        &after[..10]
    );
}
