//! Never delete a user's file: every command that writes a folder refuses, before the work,
//! one that navkf did not make or that holds a file it did not write, and leaves it as it
//! was. One test per folder rule, each with the cases a careless user met.

use crate::common;

use common::{navkf, text, Scratch};
use std::fs;
use std::path::Path;
use std::process::Output;

const PAPER: &str = "../../studies/paper.toml";

/// A fresh, empty folder for one test, removed when it ends.
fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("folders-{name}"))
}

/// A short study: two runs of the paper's.
fn study(out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["study", PAPER, "--runs", "2", "--quiet", "--out"];
    let out = out.to_str().unwrap();
    args.push(out);
    args.extend_from_slice(extra);
    navkf(args)
}

/// A simulated dataset, short enough for the tests.
fn simulate(out: &Path) -> Output {
    navkf([
        "simulate",
        "--out",
        out.to_str().unwrap(),
        "--duration",
        "2400",
    ])
}

/// Asserts a refusal: exit 1, no panic, and every fragment in the message.
fn assert_refused(o: &Output, fragments: &[&str]) {
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for f in fragments {
        assert!(err.contains(f), "lacks {f:?}:\n{err}");
    }
}

/// The names in `dir` that navkf's staging and old folders would have.
fn leftovers(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".navkf-"))
        .collect()
}

#[test]
fn a_users_folder_is_never_replaced_whatever_it_holds() {
    let root = scratch("users");
    // A thesis folder holding some other tool's summary.json.
    let thesis = root.join("thesis");
    fs::create_dir_all(thesis.join("photos")).unwrap();
    fs::write(thesis.join("thesis.tex"), "x").unwrap();
    fs::write(thesis.join("summary.json"), "{}").unwrap();
    let o = study(&thesis, &[]);
    assert_refused(&o, &["thesis: a folder navkf did not make", "`thesis.tex`"]);
    assert!(thesis.join("thesis.tex").is_file() && thesis.join("photos").is_dir());
    // A source folder given as an absolute path, holding a draft named like a shard.
    let src = root.join("src");
    fs::create_dir_all(&src).unwrap();
    fs::write(src.join("main.c"), "int main;").unwrap();
    fs::write(src.join("partial-draft.json"), "{}").unwrap();
    let o = study(&src.canonicalize().unwrap(), &[]);
    assert_refused(&o, &["a folder navkf did not make", "`main.c`"]);
    assert!(src.join("main.c").is_file());
    // A results folder into which the user put a file of their own.
    let results = root.join("results");
    assert!(study(&results, &[]).status.success());
    assert!(results.join(".navkf-results").is_file());
    fs::write(results.join("notes.txt"), "mine").unwrap();
    let o = study(&results, &[]);
    assert_refused(&o, &["`notes.txt`, which navkf did not write"]);
    assert_eq!(
        fs::read_to_string(results.join("notes.txt")).unwrap(),
        "mine"
    );
    // Once it is gone, the rerun replaces its own folder.
    fs::remove_file(results.join("notes.txt")).unwrap();
    assert!(study(&results, &[]).status.success());
    assert!(leftovers(&root).is_empty(), "{:?}", leftovers(&root));
}

#[test]
fn a_dataset_is_never_an_output_folder() {
    let root = scratch("dataset");
    let ds = root.join("drive");
    assert!(simulate(&ds).status.success());
    // A recorder left a summary.json beside the data.
    fs::write(ds.join("summary.json"), "{}").unwrap();
    let o = navkf([
        "diagnose",
        ds.to_str().unwrap(),
        "--out",
        ds.to_str().unwrap(),
    ]);
    assert_refused(&o, &["drive: a dataset folder navkf simulated"]);
    let o = study(&ds, &[]);
    assert_refused(&o, &["a dataset folder navkf simulated"]);
    assert!(ds.join("inputs.csv").is_file() && ds.join("summary.json").is_file());
    // A user's recording (no marker) is refused by diagnose too.
    let own = root.join("recorded");
    fs::create_dir_all(&own).unwrap();
    for f in ["inputs.csv", "measurements.csv"] {
        fs::copy(ds.join(f), own.join(f)).unwrap();
    }
    let o = navkf([
        "diagnose",
        own.to_str().unwrap(),
        "--out",
        own.to_str().unwrap(),
    ]);
    assert_refused(
        &o,
        &["recorded: a folder navkf did not make", "`inputs.csv`"],
    );
}

#[test]
fn simulate_writes_only_a_new_folder_or_its_own_dataset() {
    let root = scratch("simulate");
    // Into a results folder: refused, and the results keep their marker.
    let results = root.join("results");
    assert!(study(&results, &[]).status.success());
    let o = simulate(&results);
    assert_refused(&o, &["a navkf results folder, not a dataset folder"]);
    assert!(!results.join("inputs.csv").exists());
    // Over a user's own inputs.csv: refused, the file untouched.
    let theirs = root.join("theirs");
    fs::create_dir_all(&theirs).unwrap();
    fs::write(theirs.join("inputs.csv"), "my data").unwrap();
    assert_refused(&simulate(&theirs), &["a folder navkf did not make"]);
    assert_eq!(
        fs::read_to_string(theirs.join("inputs.csv")).unwrap(),
        "my data"
    );
    // Its own dataset: replaced whole by a rerun, and marked as a dataset, not results.
    let ds = root.join("ds");
    assert!(simulate(&ds).status.success());
    assert!(simulate(&ds).status.success());
    assert!(ds.join(".navkf-dataset").is_file() && !ds.join(".navkf-results").exists());
    // A run index dataset.toml cannot record is refused before simulating.
    let o = navkf([
        "simulate",
        "--out",
        root.join("never").to_str().unwrap(),
        "--run",
        "18446744073709551615",
    ]);
    assert_refused(&o, &["--run 18446744073709551615: expected 0 to"]);
    assert!(!root.join("never").exists());
    assert!(leftovers(&root).is_empty(), "{:?}", leftovers(&root));
}

#[test]
fn shards_write_only_into_their_own_folder_and_merge_keeps_users_files() {
    let root = scratch("shards");
    let shard = |i: &str, out: &Path| {
        navkf([
            "study",
            PAPER,
            "--runs",
            "20",
            "--quiet",
            "--shard",
            i,
            "--out",
            out.to_str().unwrap(),
        ])
    };
    // A folder with other files and no shard marker.
    let theirs = root.join("theirs");
    fs::create_dir_all(&theirs).unwrap();
    fs::write(theirs.join("notes.txt"), "mine").unwrap();
    assert_refused(
        &shard("0/2", &theirs),
        &["shards write only into a new folder"],
    );
    // A refused shard creates no folder.
    let never = root.join("never");
    assert_refused(&shard("5/2", &never), &["--shard 5/2"]);
    assert_refused(
        &shard("0/18446744073709551615", &never),
        &["the study has 20 runs; expected at most one shard per run"],
    );
    assert!(!never.exists());
    // Shards fill a new folder; merge into it is refused while it holds the user's notes.
    let shards = root.join("shards");
    assert!(shard("0/2", &shards).status.success());
    assert!(shard("1/2", &shards).status.success());
    fs::write(shards.join("notes.txt"), "mine").unwrap();
    let parts = ["partial-0-of-2.json", "partial-1-of-2.json"].map(|p| shards.join(p));
    let merge = |out: &Path| {
        let mut args: Vec<&std::ffi::OsStr> = vec!["merge".as_ref()];
        args.extend(parts.iter().map(|p| p.as_os_str()));
        args.extend(["--out".as_ref(), out.as_os_str()]);
        navkf(args)
    };
    assert_refused(&merge(&shards), &["`notes.txt`, which navkf did not write"]);
    assert_eq!(
        fs::read_to_string(shards.join("notes.txt")).unwrap(),
        "mine"
    );
    // Without it, the results replace the shard folder and keep the shards.
    fs::remove_file(shards.join("notes.txt")).unwrap();
    let o = merge(&shards);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(shards.join("summary.json").is_file() && parts.iter().all(|p| p.is_file()));
    assert!(leftovers(&root).is_empty(), "{:?}", leftovers(&root));
}

#[cfg(unix)]
#[test]
fn links_are_followed_or_refused_before_the_work() {
    let root = scratch("links");
    let real = root.join("real");
    fs::create_dir_all(&real).unwrap();
    let link = root.join("link");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    assert!(study(&link, &[]).status.success());
    assert!(study(&link, &[]).status.success());
    assert!(fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(real.join("summary.json").is_file());
    assert!(leftovers(&root).is_empty(), "{:?}", leftovers(&root));
    // A link to nothing: refused at once (the 500-run study would take minutes).
    let dangling = root.join("dangling");
    std::os::unix::fs::symlink(root.join("nowhere"), &dangling).unwrap();
    let started = std::time::Instant::now();
    let o = navkf([
        "study",
        PAPER,
        "--quiet",
        "--out",
        dangling.to_str().unwrap(),
    ]);
    assert_refused(&o, &["a symbolic link to", "cannot be followed"]);
    assert!(started.elapsed().as_secs() < 20, "refused before the work");
}

#[test]
fn what_a_killed_run_left_does_not_survive_the_next_one() {
    let root = scratch("killed");
    // Left by processes that no longer run (Linux process ids stay below 2^22).
    for left in [".out.navkf-partial-4194999", ".out.navkf-old-4194999"] {
        fs::create_dir_all(root.join(left)).unwrap();
        fs::write(root.join(left).join("summary.json"), "half").unwrap();
    }
    assert!(study(&root.join("out"), &[]).status.success());
    if Path::new("/proc/self").exists() {
        assert!(leftovers(&root).is_empty(), "{:?}", leftovers(&root));
    }
}

#[test]
fn thread_counts_beyond_reason_are_refused_before_any_work() {
    let root = scratch("threads");
    for bad in ["0", "100000"] {
        let o = study(&root.join("out"), &["--threads", bad]);
        assert_refused(&o, &[&format!("--threads {bad}: expected 1 to")]);
    }
    assert!(!root.join("out").exists());
}

/// Runs navkf as the unprivileged user `nobody` (root ignores permissions, so a read-only
/// folder only shows as someone else); `None` where that cannot be done here.
#[cfg(unix)]
fn navkf_as_nobody(args: &[&str]) -> Option<Output> {
    let root = std::process::Command::new("id").arg("-u").output().ok()?;
    if text(&root.stdout).trim() != "0" {
        return None;
    }
    std::process::Command::new("setpriv")
        .args(["--reuid=65534", "--regid=65534", "--clear-groups"])
        .arg(env!("CARGO_BIN_EXE_navkf"))
        .args(args)
        .output()
        .ok()
}

#[cfg(unix)]
#[test]
fn a_folder_navkf_cannot_replace_is_refused_before_the_work() {
    use std::os::unix::fs::PermissionsExt;
    let root = scratch("read-only");
    fs::set_permissions(&root, fs::Permissions::from_mode(0o777)).unwrap();
    let out = root.join("res");
    let out_s = out.to_str().unwrap();
    let paper = Path::new(PAPER).canonicalize().unwrap();
    let paper = paper.to_str().unwrap();
    let args = ["study", paper, "--runs", "2", "--quiet", "--out", out_s];
    let Some(first) = navkf_as_nobody(&args) else {
        eprintln!("skipped: needs root and setpriv to run navkf as another user");
        return;
    };
    if !first.status.success() {
        eprintln!(
            "skipped: navkf cannot run as nobody here: {}",
            text(&first.stderr)
        );
        return;
    }
    // Its own results, made read-only: the old version got "Permission denied" after the
    // new results were in place, and left `.res.navkf-old-PID` for good.
    let before = fs::read(out.join("summary.json")).unwrap();
    fs::set_permissions(&out, fs::Permissions::from_mode(0o555)).unwrap();
    let o = navkf_as_nobody(&args).expect("ran before");
    // Writable again before any assertion, so that the scratch folder goes whatever follows.
    fs::set_permissions(&out, fs::Permissions::from_mode(0o755)).unwrap();
    assert_refused(&o, &["navkf made this folder, but cannot replace it"]);
    assert_eq!(fs::read(out.join("summary.json")).unwrap(), before);
    assert!(leftovers(&root).is_empty(), "{:?}", leftovers(&root));
}
