//! `plan` predicts, from one bound recursion, what the Monte Carlo RMS of the same study is,
//! and on a test with a closed-form information matrix it predicts exactly that.

use crate::common;

use common::{run_all, short_config, PAPER};
use nalgebra::{DMatrix, DVector};
use navkf_dynamics::earth::{meridian_radius, prime_vertical_radius, WIE};
use navkf_dynamics::Prior;
use navkf_study::plan::plan;
use navkf_study::summary::summarize;
use navkf_study::{Study, StudyConfig};

const RUNS: usize = 200;

#[test]
fn the_plan_agrees_with_a_200_run_monte_carlo() {
    let mut c = short_config(RUNS);
    c.study.filters = vec!["ekf".into()];
    let study = Study::new(c).unwrap();
    let p = plan(&study).unwrap();
    let s = summarize(&study, &run_all(&study));
    let ekf = &s.filters["ekf"];
    assert_eq!(ekf.diverged, 0);
    assert_eq!(p.coefficients.len(), 13);
    // The RMS over N runs has a standard error of RMS / sqrt(2 N). Each coefficient within
    // 3 of them, and on average (z^2) no further than chance allows.
    let mut z2 = 0.0;
    for c in &p.coefficients {
        let rms = ekf.final_rms[&c.name];
        let se = rms / (2.0 * RUNS as f64).sqrt();
        let z = (c.final_sigma - rms) / se;
        assert!(
            z.abs() < 3.0,
            "{}: plan {:e}, Monte Carlo {rms:e} ({z:+.2} SE)",
            c.name,
            c.final_sigma
        );
        z2 += z * z;
    }
    assert!(z2 / 13.0 < 2.0, "mean z^2 = {}", z2 / 13.0);
    // On this test the constant drifts are learnt and the level-platform confusions show.
    let ka0x = p.coefficients.iter().find(|c| c.name == "Ka0x").unwrap();
    assert!(!ka0x.identified);
    assert!(
        ka0x.confounded
            .iter()
            .any(|k| k.with == "phi_y" && k.correlation > 0.99),
        "{:?}",
        ka0x.confounded
    );
    assert!(p.identified().contains(&"Kg0x"));
    // The series start at the prior and end at the final sigma.
    for (c, series) in p.coefficients.iter().zip(&p.sigma_over_prior) {
        assert_eq!(series.len(), p.t.len());
        assert!((series.last().unwrap() - c.ratio).abs() < 1e-12);
    }
}

#[test]
fn at_rest_the_plan_is_the_closed_form_information() {
    // A constant input: a vehicle at rest whose true coefficients and tilt are zero stays at
    // rest, so the model linearised along it is one constant matrix A
    // (docs/model.md eqs. (8)-(10) at v = 0, f = [0, 0, g]). With no process noise the state
    // at a measurement time t_k is exp(A t_k) x0, and the covariance after the measurements at
    // t_1..t_N is the batch least-squares one: P0 - P0 G^T (G P0 G^T + R)^-1 G P0, with G the
    // rows H exp(A t_k). At rest the drifts per unit fx, fy and the scale factors multiply a
    // zero input: they must stay exactly at their prior.
    const N: usize = 240;
    let mut c = StudyConfig::parse(PAPER).unwrap();
    c.trajectory = toml::from_str(&format!(
        "duration_s = {N}.0\n[[segment]]\nkind = \"hold\"\nduration_s = {N}.0\n"
    ))
    .unwrap();
    c.truth.initial_tilt.level_rad = 0.0;
    c.truth.initial_tilt.azimuth_rad = 0.0;
    // Process noise negligible (a PSD must be > 0): 1e-30 against priors of 1e-7 and more.
    c.noise.gyro_psd = 1e-30;
    c.noise.accel_psd = 1e-30;
    let names: Vec<String> = Study::new(c.clone())
        .unwrap()
        .sim
        .truth_model()
        .state_names()[7..]
        .to_vec();
    assert_eq!(names.len(), 13);
    for name in &names {
        c.truth.coefficients.insert(name.clone(), Prior::fixed(0.0));
    }
    let study = Study::new(c.clone()).unwrap();
    let p = plan(&study).unwrap();
    assert_eq!(p.t.len(), N);

    let lat = c.trajectory.start_lat_deg.to_radians();
    let (s, co) = lat.sin_cos();
    let (rm, rn) = (meridian_radius(s), prime_vertical_radius(s));
    let inputs = study.sim.run(c.study.seed, 0).inputs;
    let g = inputs[0].f[2];
    assert!(
        inputs
            .iter()
            .all(|i| i.f == navkf_dynamics::kinematics::platform_input([0.0, 0.0, g])),
        "not a constant input"
    );

    // A, from docs/model.md eqs. (5)-(10) at rest (index: docs/model.md, "The state").
    let mut a = DMatrix::<f64>::zeros(20, 20);
    let (ws, wc) = (WIE * s, WIE * co);
    a[(0, 1)] = ws;
    a[(0, 2)] = -wc;
    a[(1, 0)] = -ws;
    a[(2, 0)] = wc;
    for axis in 0..3 {
        a[(axis, 7 + 3 * axis)] = 1.0; // eps = Kg0 (+ Kg11 fx + Kg12 fy = 0)
    }
    a[(3, 4)] = 2.0 * ws;
    a[(3, 1)] = -g;
    a[(3, 16)] = 1.0; // nab_x = Ka0x (+ Ka1x fx = 0)
    a[(4, 3)] = -2.0 * ws;
    a[(4, 0)] = g;
    a[(4, 18)] = 1.0;
    a[(5, 4)] = 1.0 / rm;
    a[(6, 3)] = 1.0 / (rn * co);

    // Every measurement row, H exp(A t_k), and its variance.
    let prior = study.bound_prior_sigma();
    let p0 = DMatrix::from_diagonal(&DVector::from_iterator(20, prior.iter().map(|s| s * s)));
    let floor = c.noise.odometer_floor;
    let sigma = [floor, floor, c.noise.gps_m / rm, c.noise.gps_m / (rn * co)];
    let step = a.exp(); // exp(A * 1 s)
    let mut phi = DMatrix::<f64>::identity(20, 20);
    let mut gm = DMatrix::<f64>::zeros(4 * N, 20);
    let mut r = DMatrix::<f64>::zeros(4 * N, 4 * N);
    for k in 0..N {
        phi = &step * &phi;
        assert!(
            (p.t[k] - (k + 1) as f64).abs() < 1e-9,
            "measurement {k} at {}",
            p.t[k]
        );
        for (row, state) in [3, 4, 5, 6].into_iter().enumerate() {
            gm.row_mut(4 * k + row).copy_from(&phi.row(state));
            r[(4 * k + row, 4 * k + row)] = sigma[row] * sigma[row];
        }
    }
    let s_mat = &gm * &p0 * gm.transpose() + r;
    let gain = s_mat.cholesky().unwrap().solve(&(&gm * &p0));
    let exact = &p0 - &p0 * gm.transpose() * gain;

    for (i, cp) in p.coefficients.iter().enumerate() {
        let want = exact[(7 + i, 7 + i)].sqrt();
        let rel = (cp.final_sigma - want).abs() / want;
        assert!(
            rel < 1e-9,
            "{}: plan {:e}, closed form {want:e} (relative {rel:e})",
            cp.name,
            cp.final_sigma
        );
    }
    // The terms multiplied by the zero fx and fy learn nothing; the constant drifts and
    // biases do (the tilt is known here, so nothing hides the accelerometer biases).
    for cp in &p.coefficients {
        let multiplies_input = cp.name.starts_with("Kg1") || cp.name.starts_with("Ka1");
        assert_eq!(
            cp.ratio == 1.0,
            multiplies_input,
            "{}: {}",
            cp.name,
            cp.ratio
        );
    }
}
