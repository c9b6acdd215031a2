//! The dataset reader under random input: random bytes, and random mutations of a good
//! dataset, must give a dataset or an error, never a panic or a hang. 300 cases each here;
//! `NAVKF_FUZZ_CASES=100000 cargo test --release -p navkf-dynamics --test all fuzz::` runs longer.
//! Files stay small, so memory is bounded by construction; the reader's streaming and
//! regular-file checks are tested in tests/dataset.rs.

use navkf_dynamics::dataset::Dataset;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common::scratch;

use scratch::Scratch;

fn cases() -> usize {
    std::env::var("NAVKF_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(300)
}

fn folder(tag: &str) -> Scratch {
    Scratch::new(&format!("fuzz-{tag}"))
}

const GOOD_INPUTS: &str = "t,f_e,f_n,f_u\n0,0.001,-0.002,9.8\n0.5,0.001,-0.002,9.8\n1,0.002,0,9.81\n1.5,0,0,9.8\n2,0,0.001,9.79\n2.5,0,0,9.8\n3,0,0,9.8\n";
const GOOD_MEAS: &str =
    "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n2,0.5,0.1,,\n2.5,,,45.78001,126.63001\n3,0.4,0.1,45.78002,126.63002\n";
const GOOD_TOML: &str =
    "[noise]\ngps_m = 3.0\n[prior]\nlevel_rad = 5e-5\n[prior.coefficients]\nKg0x = 1e-7\n";
const GOOD_TRUTH: &str = "t,phi_x,Kg0x\n0,1e-5,1e-7\n3,1e-5,1e-7\n";

/// Bytes a CSV or TOML file is made of, and some that it should not hold.
const ALPHABET: &[u8] = b"0123456789.,-+eE\n\r \"'tfvlaLN[]=#\x00\xff\xfe\x1b";

fn random_bytes(rng: &mut ChaCha8Rng) -> Vec<u8> {
    let n = rng.gen_range(0..600);
    (0..n)
        .map(|_| {
            if rng.gen_bool(0.9) {
                ALPHABET[rng.gen_range(0..ALPHABET.len())]
            } else {
                rng.gen()
            }
        })
        .collect()
}

/// One random edit of `text`: a byte changed, inserted or deleted, a range removed or
/// repeated, a line swapped, or a cell replaced by an awkward token.
fn mutate(rng: &mut ChaCha8Rng, text: &[u8]) -> Vec<u8> {
    let mut t = text.to_vec();
    let tokens: [&[u8]; 10] = [
        b"",
        b"NaN",
        b"inf",
        b"-0",
        b"1e400",
        b"1e-400",
        b"99999999999999999999",
        b"\"",
        b",,",
        b"\r\n",
    ];
    for _ in 0..rng.gen_range(1..4) {
        let len = t.len().max(1);
        let i = rng.gen_range(0..len).min(t.len());
        match rng.gen_range(0..6) {
            0 if !t.is_empty() && i < t.len() => t[i] = rng.gen(),
            1 => t.insert(i, ALPHABET[rng.gen_range(0..ALPHABET.len())]),
            2 if i < t.len() => {
                let j = rng.gen_range(i..t.len().min(i + 40) + 1).min(t.len());
                t.drain(i..j);
            }
            3 if i < t.len() => {
                let j = rng.gen_range(i..t.len().min(i + 40) + 1).min(t.len());
                let piece = t[i..j].to_vec();
                t.splice(i..i, piece);
            }
            4 => {
                let tok = tokens[rng.gen_range(0..tokens.len())];
                t.splice(i..i, tok.iter().copied());
            }
            _ => {
                let mut lines: Vec<Vec<u8>> =
                    t.split(|b| *b == b'\n').map(<[u8]>::to_vec).collect();
                if lines.len() > 2 {
                    let a = rng.gen_range(0..lines.len());
                    let b = rng.gen_range(0..lines.len());
                    lines.swap(a, b);
                }
                t = lines.join(&b'\n');
            }
        }
    }
    t
}

fn read_does_not_panic(dir: &std::path::Path, files: &[(&str, Vec<u8>)]) {
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    // Ok or Err; a panic fails the test (the seeded generator makes the same files again).
    let _ = Dataset::read(dir);
}

#[test]
fn random_bytes_never_panic_the_reader() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let dir = folder("bytes");
    for _ in 0..cases() {
        let mut files = vec![
            ("inputs.csv", random_bytes(&mut rng)),
            ("measurements.csv", random_bytes(&mut rng)),
        ];
        if rng.gen_bool(0.5) {
            files.push(("dataset.toml", random_bytes(&mut rng)));
        }
        read_does_not_panic(&dir, &files);
    }
}

#[test]
fn mutations_of_a_good_dataset_never_panic_the_reader() {
    let dir = folder("mutations");
    let good = [
        ("inputs.csv", GOOD_INPUTS),
        ("measurements.csv", GOOD_MEAS),
        ("dataset.toml", GOOD_TOML),
        ("truth.csv", GOOD_TRUTH),
    ];
    let files: Vec<(&str, Vec<u8>)> = good
        .iter()
        .map(|(n, t)| (*n, t.as_bytes().to_vec()))
        .collect();
    read_does_not_panic(&dir, &files);
    Dataset::read(&dir).expect("the unmutated dataset reads");
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut refused = 0;
    for _ in 0..cases() {
        let k = rng.gen_range(0..good.len());
        let mut files: Vec<(&str, Vec<u8>)> = good
            .iter()
            .map(|(n, t)| (*n, t.as_bytes().to_vec()))
            .collect();
        files[k].1 = mutate(&mut rng, &files[k].1);
        read_does_not_panic(&dir, &files);
        refused += usize::from(Dataset::read(&dir).is_err());
    }
    // Most mutations break something the reader checks; some are harmless (a swapped pair
    // of equal lines, a digit changed): both kinds occur.
    assert!(
        refused > cases() / 4 && refused < cases(),
        "{refused} refused"
    );
}
