//! The staging folders this process is writing, so that Ctrl-C can remove them.
//!
//! A command that is stopped at once (a second Ctrl-C, or one during a command that
//! does not stop cooperatively) exits from the signal handler's thread, where no `Drop`
//! runs. Before exiting, the handler calls [`abandon_all`], which removes every staging
//! folder still registered. A commit holds the same lock while it swaps folders, so an
//! interrupt never lands between its two renames: the handler sees the folder either
//! before the commit (old results in place, staging removed) or after it (new results in
//! place, nothing registered).

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// `(staging, target)` of every folder being written.
static LIVE: Mutex<Vec<(PathBuf, PathBuf)>> = Mutex::new(Vec::new());

/// The registry, locked. A panic while it was held cannot leave it inconsistent (every
/// update is one push or one removal), so a poisoned lock is used as it is.
pub(super) fn lock() -> MutexGuard<'static, Vec<(PathBuf, PathBuf)>> {
    LIVE.lock().unwrap_or_else(|p| p.into_inner())
}

/// Registers a staging folder for `target`.
pub(super) fn register(staging: &Path, target: &Path) {
    lock().push((staging.to_path_buf(), target.to_path_buf()));
}

/// Forgets a staging folder (committed, or removed by its owner), with the lock held.
pub(super) fn forget_locked(live: &mut Vec<(PathBuf, PathBuf)>, staging: &Path) {
    live.retain(|(s, _)| s != staging);
}

/// Removes every staging folder this process is writing and returns the output folders
/// they were for, each left as it was. For the interrupt handler, just before it exits; the
/// lock stays held (leaked) so that no commit starts after it.
pub fn abandon_all() -> Vec<PathBuf> {
    let mut live = lock();
    let targets = live
        .drain(..)
        .map(|(staging, target)| {
            let _ = std::fs::remove_dir_all(&staging);
            target
        })
        .collect();
    std::mem::forget(live);
    targets
}
