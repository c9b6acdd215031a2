//! One simulated run through the three filters: `cargo run --release --example one_run`.
use navkf_dynamics::prior::base_coefficient_sigma;
use navkf_dynamics::state::*;
use navkf_dynamics::*;
use navkf_filters::*;
use std::sync::Arc;

fn main() {
    let noise = NoiseConfig::default();
    let model = Arc::new(PlatformModel::base(&noise));
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let sim = Simulator::new(model.clone(), traj, TruthConfig::default(), noise).unwrap();
    let run = sim.run(1, 0);
    let n = model.dim();
    let truth0 = &run.truth.states[0];
    let mut x0 = vec![0.0; n];
    x0[LAT] = truth0[LAT];
    x0[LON] = truth0[LON];
    let mut p0 = vec![0.0; n * n];
    let tilt = sim.config().initial_tilt;
    let sig: Vec<f64> = (0..n)
        .map(|i| match i {
            PHI_X | PHI_Y => tilt.level_rad,
            PHI_Z => tilt.azimuth_rad,
            V_X | V_Y => 0.01,
            LAT => 3.0 / 6.4e6,
            LON => 3.0 / 4.4e6,
            _ => base_coefficient_sigma(i),
        })
        .collect();
    for i in 0..n {
        p0[i + i * n] = sig[i] * sig[i];
    }
    let mut filters: Vec<Box<dyn Filter>> = vec![
        Box::new(Ekf::new(model.clone())),
        Box::new(Ukf::standard(model.clone(), SigmaScaling::default()).unwrap()),
        Box::new(Ukf::simplified(model.clone(), SigmaScaling::default()).unwrap()),
    ];
    let last = run.truth.states.last().unwrap();
    for f in filters.iter_mut() {
        f.reset(&x0, &p0).unwrap();
        let mut runner = Runner::new(16);
        let (mut nis, mut cnt, mut ns) = (0.0, 0usize, Vec::new());
        let t = std::time::Instant::now();
        runner
            .run(
                &mut **f,
                0.0,
                sim.inputs(),
                &run.measurements,
                &noise,
                |v| {
                    nis += v.report.nis;
                    cnt += 1;
                    ns.push(v.step_ns);
                },
            )
            .unwrap();
        ns.sort();
        println!(
            "{:16} mean NIS {:.3} (4 expected)  median step {} ns  total {:?}",
            f.name(),
            nis / cnt as f64,
            ns[ns.len() / 2],
            t.elapsed()
        );
        let x = f.state();
        let p = f.covariance();
        for i in NAV_DIM..n {
            println!(
                "   {:6} true {:+.3e} est {:+.3e} err/sigma_post {:+.2} sigma_post/prior {:.3}",
                BASE_NAMES[i],
                last[i],
                x[i],
                (x[i] - last[i]) / p[i + i * n].sqrt(),
                p[i + i * n].sqrt() / sig[i]
            );
        }
    }
}
