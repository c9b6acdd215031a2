//! The strapdown diagnosis's error rates on simulated MEMS drives (the paper's 2400-s test,
//! IMU at 10 Hz, the study's constraint and zero-velocity readings kept): how often it names
//! an effect on clean data, on data whose noise is mis-stated, and on data with content
//! outside the catalogue, and how often it names a hidden effect of a random size.
//!
//! `cargo run --release -p navkf-diagnose --example strapdown_error_rates [-- PER_CLASS]`
//! (default 30 datasets per class; each draws its run, its biases and its sizes), or
//! `-- clean SEED` for one clean dataset's findings, or `-- study FILE INDEX` for the
//! findings and rounds of dataset INDEX of a diagnosis study file (what it hid, each
//! candidate's evidence, each named effect's stand-in test; `WITH=EFFECT,...` in the
//! environment adds effects to the model under test, as `--with` does), or
//! `-- records FILE INDEX...` for the study's record of each dataset listed, one JSON line
//! each, as `navkf study` writes them into `summary.json`: a change to the diagnosis can then
//! be measured on just the datasets it can act on, against the committed records; or
//! `-- wander FILE INDEX...` for how far each listed dataset's true biases moved over its
//! record (the standard deviation of each bias state about its mean, and its range): a bias
//! instability's signal is the wander its draw realised, not its steady sigma.

use navkf_diagnose::catalogue::strapdown::StrapdownCatalogue;
use navkf_diagnose::{diagnose, Options};
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
use navkf_dynamics::strapdown::effects::StrapdownRegistry;
use navkf_dynamics::strapdown::model::StrapdownModel;
use navkf_dynamics::strapdown::simulate::StrapdownSimulator;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{NoiseConfig, Trajectory, TrajectoryConfig};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

/// What a dataset hides.
#[derive(Debug, Clone)]
enum Content {
    Clean,
    /// The stated noise off by these factors in sigma (gyro, accel, odometer, GPS).
    MisStated([f64; 4]),
    /// A catalogued effect with its coefficients fixed (`name`, list, size in multiples of
    /// its typical one).
    Effect(&'static str, String, f64),
    /// The odometer reads `1 + gain a` times the speed while accelerating at `a` (slip).
    Slip(f64),
    /// The GPS jumps by `metres` north for `minutes` (multipath).
    Multipath(f64, f64),
}

fn simulate(content: &Content, seed: u64) -> Dataset {
    let unit = UnitClass::Mems.errors();
    let noise = unit.noise(NoiseConfig {
        nhc_m_s: Some(0.1),
        ..NoiseConfig::default()
    });
    let effects = match content {
        Content::Effect(_, list, _) => list.clone(),
        _ => String::new(),
    };
    let list = StrapdownEffectList::parse_entries(&[&effects], &StrapdownRegistry::catalogue())
        .unwrap_or_else(|(_, e)| panic!("{e}"));
    let model = Arc::new(
        StrapdownModel::base(&noise)
            .with_unit(unit)
            .with_effects(&list, UnitClass::Mems, 1.0)
            .unwrap(),
    );
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let sim =
        StrapdownSimulator::new(model, traj.clone(), 10.0, 1.0, unit, &list.fixed, noise).unwrap();
    let run = sim.run(seed, 0);
    let mut ds = sim.dataset_with_readings(
        "drive",
        seed,
        &run,
        unit.accel_bias / navkf_dynamics::earth::STANDARD_GRAVITY,
        0.035,
    );
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    match content {
        Content::MisStated(f) => {
            ds.noise.gyro_psd /= f[0] * f[0];
            ds.noise.accel_psd /= f[1] * f[1];
            ds.noise.odometer_rel /= f[2];
            ds.noise.odometer_floor /= f[2];
            ds.noise.gps_m /= f[3];
        }
        Content::Slip(gain) => {
            for m in &mut ds.measurements {
                let st = traj.state(m.t);
                // The acceleration along the track.
                let along = if st.speed > 0.0 {
                    (st.a[0] * st.v[0] + st.a[1] * st.v[1]) / st.speed
                } else {
                    0.0
                };
                if let (Some(s), true) = (m.speed.as_mut(), along > 0.05) {
                    *s *= 1.0 + gain * along;
                }
            }
        }
        Content::Multipath(metres, minutes) => {
            let start = rng.gen_range(300.0..2400.0 - 60.0 * minutes);
            for m in &mut ds.measurements {
                if (start..start + 60.0 * minutes).contains(&m.t) {
                    if let Some(p) = m.position_deg.as_mut() {
                        p[0] += (metres / 6.367e6f64).to_degrees();
                    }
                }
            }
        }
        _ => {}
    }
    ds
}

/// `effect`'s coefficients in the final model of `d`, as `name = value +- sigma`.
fn catalogue_coefficients(d: &navkf_diagnose::Diagnosis, effect: &str) -> String {
    let names = StrapdownRegistry::catalogue()
        .get(effect)
        .map(|e| e.coefficient_names())
        .unwrap_or_default();
    d.model
        .coefficients
        .iter()
        .filter(|c| names.contains(&c.name.as_str()))
        .map(|c| {
            format!(
                "{} = {:.3e} +- {:.1e} ({:+.1} sigma)",
                c.name,
                c.estimate,
                c.sigma,
                c.estimate / c.sigma
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The smallest size from which at least 90 % of the hidden effects of that size or larger
/// were named (at least five of them), as text; "-" when none is.
fn limit(sizes: &mut [(f64, bool)]) -> String {
    sizes.sort_by(|a, b| a.0.total_cmp(&b.0));
    (0..sizes.len())
        .find(|&i| {
            let above = &sizes[i..];
            above.len() >= 5
                && above.iter().filter(|s| s.1).count() as f64 >= 0.9 * above.len() as f64
        })
        .map_or("-".into(), |i| format!("{:.1}", sizes[i].0))
}

fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    (rng.gen_range(lo.ln()..hi.ln())).exp()
}

fn main() {
    let catalogue = StrapdownCatalogue::default();
    // `-- clean SEED`: one clean dataset's findings, to see why it was named.
    if std::env::args().nth(1).as_deref() == Some("clean") {
        let seed = std::env::args()
            .nth(2)
            .and_then(|s| s.parse().ok())
            .expect("clean SEED");
        let ds = simulate(&Content::Clean, seed);
        if let (Some(a), Some(t)) = (ds.initial, ds.truth.as_ref()) {
            let x0 = &t.states[0];
            println!(
                "initial attitude error: roll {:.3} deg, pitch {:.3} deg, heading {:.3} deg",
                a.roll_deg - x0[0].to_degrees(),
                a.pitch_deg - x0[1].to_degrees(),
                a.heading_deg - x0[2].to_degrees()
            );
        }
        let (d, _) = diagnose(&ds, &catalogue, &Options::default()).unwrap();
        for f in &d.findings {
            println!("- {f}");
        }
        return;
    }
    // `-- wander FILE INDEX...`: how far each dataset's true biases and departures moved.
    if std::env::args().nth(1).as_deref() == Some("wander") {
        use navkf_diagnose::diagnosis_study::{content, DiagnosisStudyConfig};
        let path = std::env::args().nth(2).expect("wander FILE INDEX...");
        let config = DiagnosisStudyConfig::load(std::path::Path::new(&path)).unwrap();
        let planned = content::plan(&config).unwrap();
        let trajectory = Arc::new(Trajectory::build(&config.trajectory).unwrap());
        for index in std::env::args().skip(3) {
            let i: usize = index.parse().expect("INDEX");
            let ds = content::simulate(&config, &trajectory, &planned[i]).unwrap();
            let truth = ds
                .truth
                .as_ref()
                .expect("a simulated dataset has its truth");
            let mut line = format!("{i}");
            for (k, name) in truth.names.iter().enumerate() {
                // The turn-on biases (constant) and, where a triad wanders, their
                // departures (docs/model.md eq. (69)).
                if !(name.starts_with('b') || name.starts_with("db")) {
                    continue;
                }
                let values: Vec<f64> = truth.states.iter().map(|x| x[k]).collect();
                let n = values.len() as f64;
                let mean = values.iter().sum::<f64>() / n;
                let sd = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
                let (lo, hi) = values
                    .iter()
                    .fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(*v), h.max(*v)));
                line += &format!(" {name} sd {sd:.3e} range {:.3e}", hi - lo);
            }
            println!("{line}");
        }
        return;
    }
    // `-- records FILE INDEX...`: the study's records of the datasets listed.
    if std::env::args().nth(1).as_deref() == Some("records") {
        use navkf_diagnose::diagnosis_study::{dataset_count, run, DiagnosisStudyConfig};
        let path = std::env::args().nth(2).expect("records FILE INDEX...");
        let config = DiagnosisStudyConfig::load(std::path::Path::new(&path)).unwrap();
        for index in std::env::args().skip(3) {
            let i: usize = index.parse().expect("INDEX");
            assert!(i < dataset_count(&config), "{path} has no dataset {i}");
            for record in run(&config, Some(i..i + 1), &|_| {}).unwrap() {
                println!("{}", serde_json::to_string(&record).unwrap());
            }
        }
        return;
    }
    // `-- study FILE INDEX...`: datasets of a diagnosis study, each as the study diagnosed it.
    if std::env::args().nth(1).as_deref() == Some("study") {
        use navkf_diagnose::diagnosis_study::{content, DiagnosisStudyConfig};
        let path = std::env::args().nth(2).expect("study FILE INDEX...");
        let indices: Vec<usize> = std::env::args()
            .skip(3)
            .map(|s| s.parse().expect("INDEX"))
            .collect();
        assert!(!indices.is_empty(), "study FILE INDEX...");
        let config = DiagnosisStudyConfig::load(std::path::Path::new(&path)).unwrap();
        let planned = content::plan(&config).unwrap();
        let trajectory = Arc::new(Trajectory::build(&config.trajectory).unwrap());
        for index in indices {
            let p = planned
                .get(index)
                .unwrap_or_else(|| panic!("{path} has no dataset {index}"));
            println!("dataset {index}, hidden: {:?}", p.hidden);
            let ds = content::simulate(&config, &trajectory, p).unwrap();
            let catalogue = navkf_diagnose::catalogue::of(&ds).unwrap();
            let mut o = config.options();
            // A misaligned platform is diagnosed with the attitude equations its class says, as
            // the study does.
            for h in &p.hidden {
                if let navkf_diagnose::diagnosis_study::hidden::Hidden::Misaligned {
                    attitude,
                    ..
                } = h
                {
                    o.filter.attitude = *attitude;
                }
            }
            if let Ok(w) = std::env::var("WITH") {
                o.with
                    .extend(w.split(',').filter(|e| !e.is_empty()).map(String::from));
            }
            let (d, _) = diagnose(&ds, &*catalogue, &o).unwrap();
            for r in &d.rounds {
                println!(
                    "round: model {:?}, NIS {:.3}, named {:?}",
                    r.model, r.nis.mean, r.named
                );
                for c in r.candidates.iter().take(12) {
                    let coefficients: Vec<String> = c
                        .coefficients
                        .iter()
                        .map(|k| format!("{} {:.2e}+-{:.1e}", k.name, k.estimate, k.sigma))
                        .collect();
                    println!(
                        "  {:24} bic {:8.1} (informed {:8.1}) k {} excess {:5.2} NIS {:.3} {:?} {}",
                        c.effect,
                        c.bic_gain,
                        navkf_diagnose::naming::effective_bic(c),
                        c.parameters,
                        c.excess_removed,
                        c.nis.mean,
                        c.outcome,
                        coefficients.join(", ")
                    );
                }
            }
            for (effect, c) in &d.constancy {
                println!("constancy of {effect}: {c:?}");
            }
            for f in &d.findings {
                println!("- {f}");
            }
        }
        return;
    }
    // `-- track SEED EFFECT`: EFFECT's first coefficient over the clean drive SEED, every 100 s.
    if std::env::args().nth(1).as_deref() == Some("track") {
        let seed: u64 = std::env::args()
            .nth(2)
            .and_then(|s| s.parse().ok())
            .expect("SEED");
        let effect = std::env::args().nth(3).expect("EFFECT");
        let opts = Options {
            with: vec![effect.clone()],
            max_rounds: 1,
            fit_noise: false,
            ..Options::default()
        };
        let (_, fits) = diagnose(&simulate(&Content::Clean, seed), &catalogue, &opts).unwrap();
        let f = &fits.model;
        let j = f.names.len() - f.nav_dim - 1;
        for k in (0..f.track.len()).step_by(100) {
            let (x, v) = f.track.at(k, j);
            println!(
                "t {:6.0}  {} = {x:.4e} +- {:.2e}",
                f.t[k],
                f.names[f.nav_dim + j],
                v.sqrt()
            );
        }
        return;
    }
    // `-- with EFFECT N`: EFFECT's fitted coefficients on N clean datasets, to see a bias.
    if std::env::args().nth(1).as_deref() == Some("with") {
        let effect = std::env::args().nth(2).expect("with EFFECT N");
        let n: u64 = std::env::args()
            .nth(3)
            .and_then(|s| s.parse().ok())
            .unwrap_or(10);
        let opts = Options {
            with: vec![effect.clone()],
            max_rounds: 1,
            ..Options::default()
        };
        for seed in 1001..1001 + n {
            let (d, _) = diagnose(&simulate(&Content::Clean, seed), &catalogue, &opts).unwrap();
            let coefficients = catalogue_coefficients(&d, &effect);
            println!("seed {seed}: {coefficients}");
        }
        return;
    }
    let per_class: usize = std::env::args()
        .nth(1)
        .map_or(30, |a| a.parse().expect("PER_CLASS: a count"));
    let mut rng = ChaCha8Rng::seed_from_u64(20261125);
    // Each identifiable effect with the coefficients it is drawn on (the others of the effect
    // at zero): name, coefficient, typical MEMS size.
    let singles: [(&str, &str, f64, &str); 6] = [
        ("odometer-scale", "kod", 2e-3, ""),
        ("odometer-misalignment", "a_y", 1e-2, ", a_p=0"),
        ("gps-latency", "tau", 0.1, ""),
        ("gyro-scale", "s_gz", 3e-3, ", s_gx=0, s_gy=0"),
        ("accel-scale", "s_ax", 3e-3, ", s_ay=0, s_az=0"),
        ("gps-lever-arm", "l_y", 0.5, ", l_x=0, l_z=0"),
    ];
    let mut classes: Vec<(String, Vec<Content>)> = vec![
        ("clean".into(), vec![Content::Clean; per_class]),
        (
            "noise mis-stated 0.3-3x".into(),
            (0..per_class)
                .map(|_| {
                    Content::MisStated(std::array::from_fn(|_| log_uniform(&mut rng, 0.3, 3.0)))
                })
                .collect(),
        ),
        (
            "odometer slip (outside)".into(),
            (0..per_class)
                .map(|_| Content::Slip(log_uniform(&mut rng, 0.005, 0.05)))
                .collect(),
        ),
        (
            "GPS multipath (outside)".into(),
            (0..per_class)
                .map(|_| {
                    Content::Multipath(log_uniform(&mut rng, 3.0, 15.0), rng.gen_range(2.0..10.0))
                })
                .collect(),
        ),
    ];
    for (name, coef, typical, rest) in singles {
        classes.push((
            format!("{name} ({coef} 0.2-10x typical)"),
            (0..per_class)
                .map(|_| {
                    let multiple = log_uniform(&mut rng, 0.2, 10.0);
                    let v = multiple * typical * if rng.gen_bool(0.5) { 1.0 } else { -1.0 };
                    Content::Effect(name, format!("{coef}={v}{rest}"), multiple)
                })
                .collect(),
        ));
    }
    println!(
        "| class | datasets | named the hidden effect | named another | suggested | named in 90 % \
         from (x typical) | verdicts |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut seed = 1000u64;
    for (label, contents) in &classes {
        let (mut right, mut wrong, mut suggested) = (0, 0, 0);
        // (size, named) of each hidden effect.
        let mut sizes: Vec<(f64, bool)> = Vec::new();
        let mut verdicts = std::collections::BTreeMap::new();
        for content in contents {
            seed += 1;
            let ds = simulate(content, seed);
            let (d, _) = diagnose(&ds, &catalogue, &Options::default()).unwrap();
            let hidden = match content {
                Content::Effect(name, _, _) => Some(*name),
                _ => None,
            };
            if let Content::Effect(name, _, multiple) = content {
                sizes.push((*multiple, d.effects.iter().any(|e| e == name)));
            }
            for e in &d.effects {
                if Some(e.as_str()) == hidden {
                    right += 1;
                } else {
                    wrong += 1;
                    eprintln!("{label}: named {e} ({content:?}, seed {seed})");
                }
            }
            suggested += d.suggested.len();
            *verdicts.entry(format!("{:?}", d.verdict)).or_insert(0) += 1;
        }
        println!(
            "| {label} | {} | {right} | {wrong} | {suggested} | {} | {verdicts:?} |",
            contents.len(),
            limit(&mut sizes)
        );
    }
}
