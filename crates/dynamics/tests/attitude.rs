//! The exact-attitude variant (docs/model.md eqs. (45)-(48)): the three checks of
//! docs/model.md, "Variant: exact attitude", its Jacobian against finite differences at large
//! angles with every rate effect, and its batched propagation against the one-state path.

use crate::common;

use common::*;
use navkf_dynamics::attitude::{Attitude, Rotation};
use navkf_dynamics::state::*;
use navkf_dynamics::{
    Kinematics, NoiseConfig, PlatformModel, PropagationScratch, Registry, SystemModel,
};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

fn exact(names: &[&str]) -> PlatformModel {
    let effects = Registry::catalogue().build_all(names).unwrap();
    PlatformModel::new(effects, &NoiseConfig::default())
        .unwrap()
        .with_attitude(Attitude::Exact)
}

/// Euler angles far from small: level errors up to 0.4 rad, azimuth anywhere in (-pi, pi).
fn large_angles(rng: &mut ChaCha8Rng) -> [f64; 3] {
    [
        rng.gen_range(-0.4..0.4),
        rng.gen_range(-0.4..0.4),
        rng.gen_range(-3.1..3.1),
    ]
}

fn rates<U: navkf_dynamics::kinematics::IntoInput + Copy>(
    model: &PlatformModel,
    x: &[f64],
    u: &U,
) -> Vec<f64> {
    let mut dx = vec![0.0; model.dim()];
    model.rates(x, &u.into_input(), &mut dx);
    dx
}

/// `[a x]`.
fn skew(a: [f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]]
}

#[test]
fn euler_angle_rates_reproduce_om_cross_c() {
    // Along the Euler rates of any Om, dC/dt (central differences of C(phi + t phi')) equals
    // [Om x] C.
    let mut rng = rng(1);
    for _ in 0..50 {
        let phi = large_angles(&mut rng);
        let om: [f64; 3] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
        let rate = Rotation::new(phi).euler_rates(om);
        let h = 1e-5;
        let at = |t: f64| Rotation::new(std::array::from_fn(|i| phi[i] + t * rate[i])).c;
        let (cp, cm, c) = (at(h), at(-h), Rotation::new(phi).c);
        let s = skew(om);
        for i in 0..3 {
            for j in 0..3 {
                let numeric = (cp[i][j] - cm[i][j]) / (2.0 * h);
                let want: f64 = (0..3).map(|m| s[i][m] * c[m][j]).sum();
                assert!(
                    (numeric - want).abs() < 1e-9,
                    "phi {phi:?}, Om {om:?}: dC/dt[{i}][{j}] = {numeric}, [Om x] C = {want}"
                );
            }
        }
    }
}

#[test]
fn at_small_angles_the_exact_rates_equal_the_base_models_to_second_order() {
    let base = PlatformModel::base(&NoiseConfig::default());
    let exact = exact(&[]);
    let mut rng = rng(2);
    for _ in 0..50 {
        let mut x = random_state(&base, &mut rng);
        let u = random_input(&mut rng);
        // The difference must shrink as the angles squared: compare at 1e-5 and 2e-5 rad.
        let mut diffs = [[0.0; NAV_DIM]; 2];
        let dir: [f64; 3] = std::array::from_fn(|_| signed(&mut rng, 1.0));
        for (d, size) in diffs.iter_mut().zip([1e-5, 2e-5]) {
            for i in 0..3 {
                x[PHI_X + i] = size * dir[i];
            }
            let (a, b) = (rates(&base, &x, &u), rates(&exact, &x, &u));
            for s in 0..NAV_DIM {
                d[s] = b[s] - a[s];
            }
            // Second order: angle^2 times the largest rate the angles multiply (|f| ~ 10 for
            // the velocities, |w_in| < 1e-4 for the angles), plus angle times the coefficient
            // terms E and C^T rotate (gyro drifts ~1e-7, accelerometer errors ~1e-3).
            let bound = [
                4.0 * size * size * 1e-4 + 4.0 * size * 1e-7,
                4.0 * size * size * 1e-4 + 4.0 * size * 1e-7,
                4.0 * size * size * 1e-4 + 4.0 * size * 1e-7,
                4.0 * size * size * 10.0 + 4.0 * size * 1e-3,
                4.0 * size * size * 10.0 + 4.0 * size * 1e-3,
                0.0,
                0.0,
            ];
            for s in 0..NAV_DIM {
                assert!(
                    d[s].abs() <= bound[s],
                    "state {s} at {size:e} rad: exact - base = {:e} > {:e}",
                    d[s],
                    bound[s]
                );
            }
        }
        // And the first-order parts agree: the velocity difference is the nab x phi term
        // plus phi^2 f, well below the f x phi term itself (~1e-4).
        assert!(diffs[0][V_X].abs() < 1e-7 && diffs[0][V_Y].abs() < 1e-7);
    }
}

#[test]
fn a_pure_azimuth_error_rotates_the_horizontal_specific_force_exactly() {
    let model = exact(&[]);
    let mut rng = rng(3);
    for _ in 0..50 {
        let mut x = vec![0.0; BASE_DIM];
        x[LAT] = rng.gen_range(-1.2..1.2);
        x[LON] = rng.gen_range(-3.0..3.0);
        let psi = rng.gen_range(-3.1..3.1);
        x[PHI_Z] = psi;
        let u = [rng.gen_range(-3.0..3.0), rng.gen_range(-3.0..3.0), 9.8];
        let r = rates(&model, &x, &u);
        // At rest the Coriolis and transport terms vanish; what is left is C_p^n f.
        let (s, c) = psi.sin_cos();
        let want = [c * u[0] + s * u[1], -s * u[0] + c * u[1]];
        for (got, want) in [r[V_X], r[V_Y]].into_iter().zip(want) {
            assert!(
                (got - want).abs() <= 4.0 * f64::EPSILON * 3.0,
                "{got} vs {want}"
            );
        }
    }
}

#[test]
fn exact_rate_jacobian_matches_finite_differences_at_large_angles() {
    let reg = Registry::catalogue();
    let all = reg.names();
    let all: Vec<&str> = all.iter().map(|s| s.as_str()).collect();
    let mut configs: Vec<Vec<&str>> = vec![vec![]];
    configs.extend(all.iter().map(|n| vec![*n]));
    configs.push(all.clone());
    let mut rng = rng(4);
    for names in configs {
        let model = exact(&names);
        for k in 0..8 {
            let mut x = random_state(&model, &mut rng);
            x[..3].copy_from_slice(&large_angles(&mut rng));
            // One state also at rest, where the velocity partials' terms vanish.
            if k == 0 {
                x[V_X] = 0.0;
                x[V_Y] = 0.0;
            }
            let u = random_input(&mut rng);
            if let Err(e) = check_rate_jacobian(&model, &x, &u) {
                panic!("exact model with {names:?}, state #{k} (x = {x:?}):\n{e}");
            }
        }
    }
}

#[test]
fn effects_reach_the_state_through_the_rotation() {
    // torquer-scale adds a gyro error, accel-cross-axis an accelerometer error: with a pure
    // azimuth error, the latter turns with the specific force.
    let model = exact(&["accel-cross-axis"]);
    let mut x = vec![0.0; model.dim()];
    x[LAT] = 0.8;
    let psi = 0.7;
    x[PHI_Z] = psi;
    let ka12 = 1e-3;
    x[BASE_DIM] = ka12; // Ka12x: nab_x += Ka12x fy
    let u = [0.0, 2.0, 9.8];
    let r = rates(&model, &x, &u);
    let a = [ka12 * u[1], u[1]];
    let (s, c) = psi.sin_cos();
    assert!((r[V_X] - (c * a[0] + s * a[1])).abs() < 1e-14);
    assert!((r[V_Y] - (-s * a[0] + c * a[1])).abs() < 1e-14);
    let k = Kinematics::new(&x, &navkf_dynamics::kinematics::platform_input(u));
    assert_eq!(k.phi[2], psi);
}

#[test]
fn exact_batched_propagation_agrees_with_the_one_state_path() {
    // Every catalogued effect, large angles, process noise on: the batch (called directly,
    // so it cannot step aside) against the generic RK4 one point at a time.
    let reg = Registry::catalogue();
    let model = exact(&reg.names().iter().map(|s| s.as_str()).collect::<Vec<_>>());
    let n = model.dim();
    let mut rng = rng(5);
    // Five blocks: a group of four and one more (the batch takes effects four blocks at a time).
    let count = 37;
    let mut start = Vec::new();
    for _ in 0..count {
        let mut x = random_state(&model, &mut rng);
        x[..3].copy_from_slice(&large_angles(&mut rng));
        x[LAT] = 0.8 + rng.gen_range(-1e-5..1e-5);
        start.extend(x);
    }
    let noise: Vec<f64> = (0..count * model.noise_channels().len())
        .map(|_| rng.gen_range(-1e-4..1e-4))
        .collect();
    let w = window();
    for noise in [None, Some(&noise[..])] {
        let mut batched = start.clone();
        navkf_dynamics::batch_propagation::propagate(
            &model,
            &mut batched,
            noise,
            &w,
            &mut PropagationScratch::default(),
        );
        let generic = one_by_one(&model, &start, noise, &w);
        for (p, ((b, x0), g)) in batched
            .chunks_exact(n)
            .zip(start.chunks_exact(n))
            .zip(generic.chunks_exact(n))
            .enumerate()
        {
            let scale = [1.0, 1.0, 1.0, 20.0, 20.0, 1.0, 1.0];
            for s in 0..NAV_DIM {
                let d = (b[s] - g[s]).abs() / scale[s];
                assert!(d < 1e-13, "point {p}, state {s}: {} vs {}", b[s], g[s]);
            }
            // The large angles moved the velocity far from the small-angle model's.
            assert!((b[V_X] - x0[V_X]).abs() > 1e-3);
        }
    }
}
