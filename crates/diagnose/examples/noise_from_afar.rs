//! The noise check started far from the truth: platform tests whose noise is drawn far from
//! the navigation-grade levels navkf assumes, diagnosed with those defaults, as a user with a
//! MEMS recording and no `[noise]` table would. How often does each fitted level land within
//! 20 % of the truth, how often is a level left unresolved, and is the final NIS within its
//! bounds?
//!
//! `cargo run --release -p navkf-diagnose --example noise_from_afar [-- COUNT [CLASS]]`
//! (default 40 datasets; CLASS `mems`: gyro and accelerometer noise 100-1000x in sigma, the
//! odometer's and GPS's as stated; `all`: every source off by 1/1000-1000x, each drawn
//! log-uniformly; `one`: one source off by 1/1000-1000x).

use navkf_diagnose::noise::{NoiseVerdict, SOURCES};
use navkf_diagnose::{diagnose, Options};
use navkf_dynamics::{NoiseConfig, PlatformModel, Simulator, Trajectory, TrajectoryConfig};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::sync::Arc;

/// The truth's noise: the stated defaults with each source's sigma times `factor`.
fn truth_noise(factor: [f64; 4]) -> NoiseConfig {
    let d = NoiseConfig::default();
    NoiseConfig {
        gyro_psd: d.gyro_psd * factor[0] * factor[0],
        accel_psd: d.accel_psd * factor[1] * factor[1],
        odometer_rel: d.odometer_rel * factor[2],
        odometer_floor: d.odometer_floor * factor[2],
        gps_m: d.gps_m * factor[3],
        ..d
    }
}

fn draw(class: &str, i: u64) -> [f64; 4] {
    let mut rng = ChaCha8Rng::seed_from_u64(0x_7e57 + i);
    let log_uniform = |rng: &mut ChaCha8Rng, lo: f64, hi: f64| {
        (lo.ln() + rng.gen::<f64>() * (hi.ln() - lo.ln())).exp()
    };
    match class {
        "mems" => [
            log_uniform(&mut rng, 100.0, 1000.0),
            log_uniform(&mut rng, 100.0, 1000.0),
            1.0,
            1.0,
        ],
        "all" => std::array::from_fn(|_| log_uniform(&mut rng, 1e-3, 1e3)),
        _ => {
            let j = rng.gen_range(0..4);
            let mut f = [1.0; 4];
            f[j] = log_uniform(&mut rng, 1e-3, 1e3);
            f
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let count: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(40);
    let class = args.get(2).cloned().unwrap_or_else(|| "mems".into());
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let only: Option<u64> = args.get(3).and_then(|s| s.parse().ok());
    let rows: Vec<String> = (0..count)
        .into_par_iter()
        .filter(|i| only.is_none_or(|o| o == *i))
        .map(|i| {
            let factor = draw(&class, i);
            let noise = truth_noise(factor);
            let model = Arc::new(PlatformModel::base(&noise));
            let sim = match Simulator::new(model, traj.clone(), Default::default(), noise) {
                Ok(s) => s,
                Err(e) => return format!("{i}: {factor:?}: simulator refused: {e}"),
            };
            let mut ds = sim.dataset("afar", i, &sim.run(i, 0));
            ds.noise = NoiseConfig::default();
            ds.noise_stated = false;
            ds.truth = None;
            let registry = navkf_dynamics::Registry::catalogue();
            let d = match diagnose(&ds, &registry, &Options::default()) {
                Ok((d, _)) => d,
                Err(e) => return format!("{i}: {factor:?}: error {e}"),
            };
            let mut line = format!(
                "{i:3} verdict {:<18} named {:<22} NIS {:8.3} ({:.3}-{:.3}) |",
                d.verdict.to_string(),
                d.best.clone().unwrap_or("-".into()),
                d.model.nis.mean,
                d.model.nis.bounds[0],
                d.model.nis.bounds[1]
            );
            if only.is_some() {
                for f in &d.findings {
                    eprintln!("  {f}");
                }
                for c in &d.noise_checks {
                    eprintln!(
                        "  check on {:?}: theta {:?} se {:?} passes {}",
                        c.model, c.theta, c.theta_se, c.passes
                    );
                }
            }
            let Some(fit) = &d.noise else {
                return line + " no noise check";
            };
            for (j, s) in fit.sources.iter().enumerate().take(4) {
                let truth = factor[j];
                let used = fit.used_theta.get(j).map_or(1.0, |t| (t / 2.0).exp());
                let ok = ((used / truth) - 1.0).abs() < 0.2;
                let tag = match s.verdict {
                    NoiseVerdict::Unresolved => "unres",
                    _ if ok => "ok",
                    _ => "OFF",
                };
                line += &format!(
                    " {}: true {truth:9.3e} used {used:9.3e} [{:9.3e},{:9.3e}] {tag} |",
                    SOURCES[j].label(),
                    s.sigma_ratio_interval[0],
                    s.sigma_ratio_interval[1]
                );
            }
            line
        })
        .collect();
    for r in rows {
        println!("{r}");
    }
}
