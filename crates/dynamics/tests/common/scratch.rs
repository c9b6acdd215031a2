//! Scratch folders for the tests, removed when the test that made one ends, passed or failed:
//! the tests must not litter /tmp. Shared through `#[path]` by the tests of every crate.
#![allow(dead_code)] // each test file uses a subset

use std::path::{Path, PathBuf};

/// A fresh, empty folder `navkf-<name>-<pid>-<k>` under the system temporary folder, removed with
/// all it holds when this guard drops, also when the test panics: the tests must not litter
/// /tmp. It reads as the folder's `&Path`. Bind it to a named variable (never `_`, which
/// drops it at once) that lives to the end of the test.
pub struct Scratch {
    path: PathBuf,
    /// Left in place when dropped, for a look at what the test wrote.
    keep: bool,
}

impl Scratch {
    /// Makes the folder: the first `k` whose folder this call creates itself. A crate's tests
    /// share one process (its `tests/all.rs`), and may each include this file, so neither the
    /// process id nor a counter of one copy makes a name unique; creating the folder does.
    pub fn new(name: &str) -> Scratch {
        let pid = std::process::id();
        for k in 0.. {
            let path = std::env::temp_dir().join(format!("navkf-{name}-{pid}-{k}"));
            match std::fs::create_dir(&path) {
                Ok(()) => return Scratch { path, keep: false },
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => panic!("a scratch folder {}: {e}", path.display()),
            }
        }
        unreachable!("a free scratch name")
    }

    /// The same folder, left in place when the guard drops (its path printed then).
    pub fn kept(mut self) -> Scratch {
        self.keep = true;
        self
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if self.keep {
            eprintln!("kept {}", self.path.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}
