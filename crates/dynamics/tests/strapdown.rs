//! The strapdown family's physics (docs/model.md, "The strapdown family"): the attitude
//! convention's check values, the Jacobian from dual numbers against central differences, a
//! unit at rest that reads the Earth's rate and gravity and stays in place, and constant
//! rates relative to the ground that give the closed-form attitude.

use crate::common;

use navkf_dynamics::earth::{meridian_radius, normal_gravity, prime_vertical_radius, WIE};
use navkf_dynamics::strapdown::attitude::{body_to_nav, euler_of, rotate_back};
use navkf_dynamics::strapdown::partials_check::random_reading;
use navkf_dynamics::strapdown::rates::{nav_rate_jacobian, nav_rates, ImuReading};
use navkf_dynamics::strapdown::state::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn deg(d: f64) -> f64 {
    d.to_radians()
}

fn column(c: &[[f64; 3]; 3], j: usize) -> [f64; 3] {
    [c[0][j], c[1][j], c[2][j]]
}

fn close3(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

#[test]
fn the_attitude_convention_gives_the_check_values() {
    let east = column(&body_to_nav([0.0, 0.0, deg(90.0)]), 0);
    assert!(close3(east, [1.0, 0.0, 0.0], 1e-15), "{east:?}");
    let north = column(&body_to_nav([0.0, 0.0, 0.0]), 0);
    assert!(close3(north, [0.0, 1.0, 0.0], 1e-15), "{north:?}");
    let nose_up = column(&body_to_nav([0.0, deg(10.0), 0.0]), 0);
    assert!(close3(
        nose_up,
        [0.0, deg(10.0).cos(), deg(10.0).sin()],
        1e-15
    ));
    // Right side down: the left axis points partly up.
    let left = column(&body_to_nav([deg(10.0), 0.0, 0.0]), 1);
    assert!((left[2] - deg(10.0).sin()).abs() < 1e-15, "{left:?}");
    // Heading is clockwise from North: 30 deg is East of North.
    let h30 = column(&body_to_nav([0.0, 0.0, deg(30.0)]), 0);
    assert!(close3(h30, [deg(30.0).sin(), deg(30.0).cos(), 0.0], 1e-15));
    // Level, the up axis is up whatever the heading.
    let up = column(&body_to_nav([0.0, 0.0, 1.234]), 2);
    assert!(close3(up, [0.0, 0.0, 1.0], 1e-15));
}

#[test]
fn body_to_nav_is_a_rotation_and_euler_of_inverts_it() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..200 {
        let e = [
            rng.gen_range(-3.1..3.1),
            rng.gen_range(-1.5..1.5),
            rng.gen_range(-3.1..3.1),
        ];
        let c = body_to_nav(e);
        for i in 0..3 {
            for j in 0..3 {
                let dot: f64 = (0..3).map(|k| c[k][i] * c[k][j]).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((dot - want).abs() < 1e-14, "C^T C at {e:?}");
            }
        }
        let det = c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1])
            - c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0])
            + c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]);
        assert!((det - 1.0).abs() < 1e-14);
        let back = euler_of(&c);
        assert!(close3(back, e, 1e-12), "{e:?} -> {back:?}");
    }
}

fn random_state(rng: &mut ChaCha8Rng) -> [f64; BASE_DIM] {
    let mut x = [0.0; BASE_DIM];
    x[ROLL] = rng.gen_range(-0.5..0.5);
    x[PITCH] = rng.gen_range(-0.5..0.5);
    x[HEADING] = rng.gen_range(-3.1..3.1);
    x[V_E] = rng.gen_range(-40.0..40.0);
    x[V_N] = rng.gen_range(-40.0..40.0);
    x[LAT] = rng.gen_range(-1.3..1.3);
    x[LON] = rng.gen_range(-3.1..3.1);
    for i in 0..3 {
        x[BG_X + i] = rng.gen_range(-1e-3..1e-3);
        x[BA_X + i] = rng.gen_range(-0.1..0.1);
    }
    x
}

fn rates(x: &[f64], imu: &ImuReading) -> [f64; NAV_DIM] {
    let mut dx = [0.0; NAV_DIM];
    nav_rates(x, imu, &mut dx);
    dx
}

/// The dual-number Jacobian against central differences, entry by entry, each judged against
/// its own size plus the rounding of the difference quotient (the row's largest term over the
/// step).
#[test]
fn the_jacobian_from_dual_numbers_matches_central_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let steps = [
        1e-6, 1e-6, 1e-6, 1e-4, 1e-4, 1e-7, 1e-7, 1e-8, 1e-8, 1e-8, 1e-5, 1e-5, 1e-5,
    ];
    for _ in 0..50 {
        let x = random_state(&mut rng);
        let imu = random_reading(&mut rng);
        let mut jac = [f64::NAN; NAV_DIM * BASE_DIM];
        nav_rate_jacobian(&x, &imu, &mut jac);
        let scale: Vec<f64> = (0..NAV_DIM)
            .map(|r| {
                let terms: f64 = (0..BASE_DIM)
                    .map(|c| (jac[r * BASE_DIM + c] * x[c]).abs())
                    .sum();
                terms + rates(&x, &imu)[r].abs() + imu.f.iter().map(|f| f.abs()).sum::<f64>()
            })
            .collect();
        for c in 0..BASE_DIM {
            let (mut xp, mut xm) = (x, x);
            xp[c] += steps[c];
            xm[c] -= steps[c];
            let (fp, fm) = (rates(&xp, &imu), rates(&xm, &imu));
            for r in 0..NAV_DIM {
                let fd = (fp[r] - fm[r]) / (xp[c] - xm[c]);
                let a = jac[r * BASE_DIM + c];
                let tol = 1e-6 * a.abs().max(fd.abs()) + 64.0 * f64::EPSILON * scale[r] / steps[c];
                assert!(
                    (a - fd).abs() <= tol,
                    "d({})/d({}) at {x:?}: dual {a:e}, differences {fd:e}",
                    STATE_NAMES[r],
                    STATE_NAMES[c]
                );
            }
        }
    }
}

/// What an error-free unit at rest reads: the Earth's rate and the reaction to gravity, in
/// body axes.
fn at_rest_reading(x: &[f64]) -> ImuReading {
    let c = body_to_nav([x[ROLL], x[PITCH], x[HEADING]]);
    let l = x[LAT];
    ImuReading {
        w: rotate_back(&c, [0.0, WIE * l.cos(), WIE * l.sin()]),
        f: rotate_back(&c, [0.0, 0.0, normal_gravity(l.sin())]),
    }
}

fn rk4(x: &mut [f64; BASE_DIM], h: f64, steps: usize, imu: impl Fn(f64, &[f64]) -> ImuReading) {
    let mut t = 0.0;
    for _ in 0..steps {
        let f = |t: f64, x: &[f64; BASE_DIM]| {
            let mut dx = [0.0; BASE_DIM];
            nav_rates(x, &imu(t, x), &mut dx[..NAV_DIM]);
            dx
        };
        let add = |x: &[f64; BASE_DIM], k: &[f64; BASE_DIM], s: f64| {
            std::array::from_fn::<f64, BASE_DIM, _>(|i| x[i] + s * k[i])
        };
        let k1 = f(t, x);
        let k2 = f(t + h / 2.0, &add(x, &k1, h / 2.0));
        let k3 = f(t + h / 2.0, &add(x, &k2, h / 2.0));
        let k4 = f(t + h, &add(x, &k3, h));
        for i in 0..BASE_DIM {
            x[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        t += h;
    }
}

#[test]
fn a_unit_at_rest_reads_the_earth_and_stays_in_place() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..20 {
        let mut x = random_state(&mut rng);
        x[V_E] = 0.0;
        x[V_N] = 0.0;
        for i in 0..3 {
            x[BG_X + i] = 0.0;
            x[BA_X + i] = 0.0;
        }
        let imu = at_rest_reading(&x);
        // It reads the Earth's rate and gravity, in magnitude whatever its attitude.
        let w: f64 = imu.w.iter().map(|v| v * v).sum::<f64>().sqrt();
        let f: f64 = imu.f.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!((w - WIE).abs() < 1e-18 && (f - normal_gravity(x[LAT].sin())).abs() < 1e-14);
        // Every rate vanishes, to the rounding of its terms: ~1e-4 rad/s in the attitude rows,
        // gravity (turned into body axes and back) in the velocity rows.
        let dx = rates(&x, &imu);
        let rounding = [1e-19, 1e-19, 1e-19, 1e-14, 1e-14, 1e-21, 1e-21];
        for i in 0..NAV_DIM {
            assert!(
                dx[i].abs() <= rounding[i],
                "{}' = {:e} at {x:?}",
                STATE_NAMES[i],
                dx[i]
            );
        }
        // Integrated for ten minutes on its constant reading, it stays put.
        let start = x;
        rk4(&mut x, 1.0, 600, |_, _| imu);
        for i in 0..NAV_DIM {
            assert!(
                (x[i] - start[i]).abs() < 1e-11,
                "{} moved by {:e}",
                STATE_NAMES[i],
                x[i] - start[i]
            );
        }
    }
}

/// The reading of a unit that turns at `w_nb` (body axes) relative to the ground, at rest:
/// the turn plus the Earth's rate seen from its current attitude.
fn turning_reading(x: &[f64], w_nb: [f64; 3]) -> ImuReading {
    let earth = at_rest_reading(x);
    ImuReading {
        w: std::array::from_fn(|i| earth.w[i] + w_nb[i]),
        f: earth.f,
    }
}

#[test]
fn constant_turns_give_the_closed_form_attitude() {
    let lat = deg(48.0);
    let omega = deg(10.0);
    // Level, turning about the up axis: heading falls at omega (it counts clockwise).
    let mut x = [0.0; BASE_DIM];
    x[LAT] = lat;
    x[HEADING] = deg(20.0);
    rk4(&mut x, 0.05, 200, |_, x| {
        turning_reading(x, [0.0, 0.0, omega])
    });
    assert!(
        (x[HEADING] - (deg(20.0) - 10.0 * omega)).abs() < 1e-10,
        "{}",
        x[HEADING]
    );
    assert!(x[ROLL].abs() < 1e-12 && x[PITCH].abs() < 1e-12);
    // Rolling about the forward axis at a fixed pitch and heading: roll grows at omega.
    let mut x = [0.0; BASE_DIM];
    x[LAT] = lat;
    x[PITCH] = deg(5.0);
    x[HEADING] = deg(-60.0);
    rk4(&mut x, 0.05, 40, |_, x| {
        turning_reading(x, [omega, 0.0, 0.0])
    });
    assert!((x[ROLL] - 2.0 * omega).abs() < 1e-10, "{}", x[ROLL]);
    assert!((x[PITCH] - deg(5.0)).abs() < 1e-10 && (x[HEADING] - deg(-60.0)).abs() < 1e-10);
    // Pitching about the left axis, level and heading North: a positive rate about left
    // (right-handed, FLU) lowers the nose.
    let mut x = [0.0; BASE_DIM];
    x[LAT] = lat;
    rk4(&mut x, 0.05, 20, |_, x| {
        turning_reading(x, [0.0, omega, 0.0])
    });
    assert!((x[PITCH] + omega).abs() < 1e-10, "{}", x[PITCH]);
}

#[test]
fn the_velocity_follows_the_specific_force_and_the_position_the_velocity() {
    // Heading East, level, accelerating forward at 1 m/s^2 on top of gravity's reaction.
    let mut x = [0.0; BASE_DIM];
    x[LAT] = deg(30.0);
    x[HEADING] = deg(90.0);
    x[V_E] = 20.0;
    let mut imu = at_rest_reading(&x);
    imu.f[0] += 1.0;
    let dx = rates(&x, &imu);
    let (sl, cl) = x[LAT].sin_cos();
    let rn = prime_vertical_radius(sl);
    let rm = meridian_radius(sl);
    assert!((dx[V_E] - 1.0).abs() < 1e-12, "{}", dx[V_E]);
    // Coriolis and transport push an eastbound vehicle South.
    let turn = 2.0 * WIE * sl + 20.0 * sl / cl / rn;
    assert!((dx[V_N] + turn * 20.0).abs() < 1e-12, "{}", dx[V_N]);
    assert!((dx[LON] - 20.0 / (rn * cl)).abs() < 1e-18 && dx[LAT].abs() < 1e-18);
    let _ = rm;
}

/// One source, three number types: the value part of the dual evaluation is the `f64`
/// evaluation bit for bit; every lane of a batch is too, but for the reciprocals of the radii
/// and of cos L, which a batch takes with one division (`Real::reciprocals`) and which may
/// round one unit in the last place differently.
#[test]
fn dual_values_and_batches_are_the_scalar_rates_bit_for_bit() {
    use navkf_dynamics::dual::Dual;
    use navkf_dynamics::real::{Lanes, LANES};
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let imu = random_reading(&mut rng);
    let states: Vec<[f64; BASE_DIM]> = (0..LANES).map(|_| random_state(&mut rng)).collect();
    let batch: Vec<Lanes> = (0..BASE_DIM)
        .map(|i| Lanes::from_fn(|l| states[l][i]))
        .collect();
    let mut out = [Lanes::default(); NAV_DIM];
    nav_rates(&batch, &imu, &mut out);
    for (l, x) in states.iter().enumerate() {
        let want = rates(x, &imu);
        let xd: Vec<Dual<2>> = x.iter().map(|&v| Dual::variable(v, 0)).collect();
        let mut dual = [Dual::<2>::constant(0.0); NAV_DIM];
        nav_rates(&xd, &imu, &mut dual);
        for r in 0..NAV_DIM {
            let ulps = (out[r].0[l].to_bits() as i64 - want[r].to_bits() as i64).abs();
            assert!(ulps <= 4, "lane {l}, row {r}: {ulps} units apart");
            assert_eq!(dual[r].v.to_bits(), want[r].to_bits(), "dual, row {r}");
        }
    }
}

/// The batched propagation (eight points a block) lands where each point lands alone
/// (`propagate_generic`, the one-state RK4), noise held over the window included, for a
/// count of points that is not a multiple of the block: to the rounding the batch's one
/// division for three reciprocals allows. Twice: latitudes all over the globe (the batch
/// evaluates their sines in full) and latitudes as close as a filter's sigma points (it takes
/// them from a series about the first point's).
#[test]
fn batched_propagation_matches_one_point_at_a_time() {
    use navkf_dynamics::strapdown::model::StrapdownModel;
    use navkf_dynamics::strapdown::rates::input_of;
    use navkf_dynamics::{InputWindow, NoiseConfig, SystemModel};
    let model = StrapdownModel::base(&NoiseConfig {
        gyro_psd: 1e-10,
        accel_psd: 1e-6,
        ..NoiseConfig::default()
    });
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut w = InputWindow::with_capacity(11);
    for k in 0..=10 {
        w.push_linear(0.1 * k as f64, input_of(&random_reading(&mut rng)));
    }
    let count = 11;
    let nw = model.noise_channels().len();
    for near in [false, true] {
        let mut points: Vec<f64> = (0..count).flat_map(|_| random_state(&mut rng)).collect();
        if near {
            for p in 0..count {
                points[p * BASE_DIM + LAT] = 0.84 + rng.gen_range(-1e-5..1e-5);
            }
        }
        let noise: Vec<f64> = (0..count * nw)
            .map(|_| rng.gen_range(-1e-3..1e-3))
            .collect();
        let alone = common::batch_matches_one_point(&model, &points, &noise, &w);
        for p in 0..count {
            assert!(
                (alone[p * BASE_DIM + HEADING] - points[p * BASE_DIM + HEADING]).abs() > 1e-6,
                "it moved"
            );
        }
    }
}

/// The written-out Jacobian (the EKF's) against the dual-number one (the rates themselves,
/// differentiated exactly): every entry within rounding of its row's terms.
#[test]
fn the_written_out_jacobian_is_the_dual_numbers_one() {
    use navkf_dynamics::strapdown::jacobian::nav_rate_jacobian_analytic;
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    for _ in 0..200 {
        let x = random_state(&mut rng);
        let imu = random_reading(&mut rng);
        let mut dual = [f64::NAN; NAV_DIM * BASE_DIM];
        let mut written = [f64::NAN; NAV_DIM * BASE_DIM];
        nav_rate_jacobian(&x, &imu, &mut dual);
        nav_rate_jacobian_analytic(&x, &imu, &mut written);
        for r in 0..NAV_DIM {
            let row_scale = (0..BASE_DIM)
                .map(|c| dual[r * BASE_DIM + c].abs())
                .fold(0.0, f64::max);
            for c in 0..BASE_DIM {
                let (a, b) = (written[r * BASE_DIM + c], dual[r * BASE_DIM + c]);
                assert!(
                    (a - b).abs() <= 1e-12 * row_scale,
                    "d({})/d({}): written {a:e}, dual {b:e}",
                    STATE_NAMES[r],
                    STATE_NAMES[c]
                );
            }
        }
    }
}

/// The EKF's shared evaluation (`rates_and_jacobian`, one set of sines and cosines for both)
/// gives the rates and the Jacobian bit for bit, rows spread to the stride, padding zeroed.
#[test]
fn rates_and_jacobian_together_are_the_two_apart() {
    use navkf_dynamics::strapdown::model::StrapdownModel;
    use navkf_dynamics::strapdown::rates::input_of;
    use navkf_dynamics::{NoiseConfig, SystemModel};
    let model = StrapdownModel::base(&NoiseConfig::default());
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..20 {
        let x = random_state(&mut rng);
        let u = input_of(&random_reading(&mut rng));
        let mut dx = [0.0; NAV_DIM];
        let mut jac = [0.0; NAV_DIM * BASE_DIM];
        model.rates(&x, &u, &mut dx);
        model.rate_jacobian(&x, &u, &mut jac);
        let stride = BASE_DIM + 3;
        let mut dx2 = [f64::NAN; NAV_DIM];
        let mut jac2 = vec![f64::NAN; NAV_DIM * stride];
        model.rates_and_jacobian(&x, &u, &mut dx2, &mut jac2, stride);
        assert_eq!(dx.map(f64::to_bits), dx2.map(f64::to_bits));
        for r in 0..NAV_DIM {
            assert_eq!(
                &jac2[r * stride..r * stride + BASE_DIM],
                &jac[r * BASE_DIM..(r + 1) * BASE_DIM]
            );
            assert!(jac2[r * stride + BASE_DIM..(r + 1) * stride]
                .iter()
                .all(|v| *v == 0.0));
        }
    }
}
