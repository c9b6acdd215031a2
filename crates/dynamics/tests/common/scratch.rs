//! Scratch folders for the tests, removed when the test that made one ends, passed or failed:
//! the tests must not litter /tmp. Shared through `#[path]` by the tests of every crate.
#![allow(dead_code)] // each test file uses a subset

use std::path::{Path, PathBuf};

/// A fresh, empty folder `navkf-<name>-<pid>` under the system temporary folder, removed with
/// all it holds when this guard drops, also when the test panics: the tests must not litter
/// /tmp. It reads as the folder's `&Path`. Bind it to a named variable (never `_`, which
/// drops it at once) that lives to the end of the test.
pub struct Scratch {
    path: PathBuf,
    /// Left in place when dropped, for a look at what the test wrote.
    keep: bool,
}

impl Scratch {
    /// Makes the folder, removing what an earlier process of the same id left there.
    pub fn new(name: &str) -> Scratch {
        let path = std::env::temp_dir().join(format!("navkf-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).expect("a scratch folder");
        Scratch { path, keep: false }
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
