//! The output directory (`--out`): staged, then merged into the target so that a rerun
//! replaces only the files an earlier run wrote.
//!
//! A run writes everything into a staging directory `.<name>.partial-<pid>` beside the target
//! (on the target's file system: a symbolic link is followed first). Only when every file is
//! written does [`StagedDir::commit`] move them into the target; the files the earlier run
//! wrote there and this one did not are then removed. What a run wrote is listed in the
//! target's [`MANIFEST`]; any other file in the target (the problem file, the user's notes)
//! is never removed nor overwritten. The target may be:
//!
//! - missing or empty: it receives the outputs;
//! - a directory with a [`MANIFEST`]: the files it lists are replaced, every other is kept; a
//!   file that is not listed but has the name of an output of this run is refused
//!   ([`OutputError::InTheWay`]) before anything is moved;
//! - a directory without a manifest holding a run of an older version (its `summary.json`
//!   names the program): the outputs replace the files of the same names, every other file is
//!   kept (which of them the older run wrote is not known);
//! - anything else (a non-empty directory of the user's, a file, a link to nothing): refused.
//!
//! Staging directories of runs that ended without cleaning up (killed) are removed by the next
//! run into the same target once their process is gone (seen through `/proc`; where it is not
//! available they are left alone), and [`abandon_staging`] removes the live ones (the command
//! line calls it on SIGINT, SIGTERM and SIGHUP).

use super::OutputError;
use std::collections::BTreeSet;
use std::path::{Component, Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// The file, in the output directory, that lists the files the last run wrote there (relative
/// paths with `/`, one a line, after a `#` comment line).
pub const MANIFEST: &str = ".mlpg-contact-manifest";

/// The staging directories of the runs under way in this process.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Removes the staging directories of the runs under way in this process and keeps every
/// later run from starting or committing (for a process about to end on a signal: call it,
/// then end). A commit under way finishes first, so the target holds the earlier run or the
/// new one, never a part of one.
pub fn abandon_staging() {
    let mut guard = live();
    for dir in guard.drain(..) {
        let _ = std::fs::remove_dir_all(dir);
    }
    // Held until the process ends: no staging directory is created or committed after this.
    std::mem::forget(guard);
}

/// An output directory written as a whole: the files go into a staging directory beside the
/// target, and [`StagedDir::commit`] moves them into the target only when the run has written
/// them all, so that the earlier run is kept until the new one is complete (see the module
/// documentation for what is replaced and what is kept). Dropped without a commit (a failed
/// run), the staging directory is removed.
#[derive(Debug)]
pub struct StagedDir {
    staging: PathBuf,
    /// The target as given (the returned paths are under it).
    target: PathBuf,
    /// The target with its symbolic links resolved: where the files go.
    resolved: PathBuf,
    committed: bool,
}

impl StagedDir {
    /// Prepares a staging directory for `target`, after removing the staging directories that
    /// runs into the same target left behind when they were killed.
    ///
    /// # Errors
    /// [`OutputError::NotAnOutputDirectory`] when `target` exists, is not empty and holds no
    /// earlier run; [`OutputError::NotADirectory`] when it is a file or a link to nothing;
    /// [`OutputError::Io`] when the staging directory cannot be created.
    pub fn new(target: &Path) -> Result<Self, OutputError> {
        let resolved = resolve(target)?;
        match std::fs::symlink_metadata(&resolved) {
            Ok(m) if !m.is_dir() => {
                return Err(OutputError::NotADirectory { path: target.display().to_string() });
            }
            Ok(_)
                if !is_empty_dir(&resolved)
                    && !has_manifest(&resolved)
                    && !holds_a_run(&resolved) =>
            {
                return Err(OutputError::NotAnOutputDirectory {
                    path: target.display().to_string(),
                });
            }
            _ => {}
        }
        let (Some(parent), Some(name)) = (resolved.parent(), resolved.file_name()) else {
            return Err(OutputError::NotAnOutputDirectory { path: target.display().to_string() });
        };
        super::create_dir(parent)?;
        let prefix = format!(".{}.partial-", name.to_string_lossy());
        remove_stale_staging(parent, &prefix);
        let mut live = live();
        // `<pid>`, or `<pid>-<k>` while this process stages another run into the same target
        // (the Python package's threads may).
        let mut staging = parent.join(format!("{prefix}{}", std::process::id()));
        for k in 1.. {
            if !live.contains(&staging) {
                break;
            }
            staging = parent.join(format!("{prefix}{}-{k}", std::process::id()));
        }
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(super::io(&staging))?;
        }
        super::create_dir(&staging)?;
        live.push(staging.clone());
        Ok(Self { staging, target: target.to_path_buf(), resolved, committed: false })
    }

    /// Where to write.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// Moves the staged files into the target (creating it when missing), removes the files
    /// the earlier run wrote there that this one did not, and records this run's files in
    /// the target's [`MANIFEST`]; returns `files` (paths under [`Self::path`]) as paths under
    /// the target.
    ///
    /// # Errors
    /// [`OutputError::InTheWay`] when a file the earlier run did not write (or a directory,
    /// or a symbolic link) has the path of a file of this run: nothing is moved, the target
    /// stays as it was; [`OutputError::Io`] when a file cannot be moved.
    pub fn commit(mut self, files: Vec<PathBuf>) -> Result<Vec<PathBuf>, OutputError> {
        let mut live = live();
        let mut new = BTreeSet::new();
        walk(&self.staging, Path::new(""), &mut new).map_err(super::io(&self.staging))?;
        new.remove(Path::new(MANIFEST));
        let target = &self.resolved;
        if std::fs::symlink_metadata(target).is_err() {
            // A new directory: one rename.
            write_manifest(&self.staging.join(MANIFEST), &new)?;
            std::fs::rename(&self.staging, target).map_err(super::io(&self.target))?;
        } else {
            let old = read_manifest(target);
            self.check_in_the_way(&new, old.as_ref())?;
            // The manifest first lists both runs' files, so that a run killed while the files
            // are moved leaves a directory whose every file of ours the next run knows.
            let both: BTreeSet<PathBuf> = new.iter().chain(old.iter().flatten()).cloned().collect();
            self.replace_manifest(&both)?;
            // summary.json last: a directory with the new summary holds the whole new run.
            let (last, first): (Vec<&PathBuf>, Vec<&PathBuf>) =
                new.iter().partition(|rel| rel.as_path() == Path::new("summary.json"));
            for rel in first.into_iter().chain(last) {
                let to = target.join(rel);
                if let Some(dir) = to.parent() {
                    super::create_dir(dir)?;
                }
                std::fs::rename(self.staging.join(rel), &to).map_err(super::io(&to))?;
            }
            for rel in old.iter().flatten().filter(|rel| !new.contains(*rel)) {
                remove_output(target, rel);
            }
            self.replace_manifest(&new)?;
            let _ = std::fs::remove_dir_all(&self.staging);
        }
        live.retain(|d| d != &self.staging);
        self.committed = true;
        Ok(files
            .into_iter()
            .map(|f| match f.strip_prefix(&self.staging) {
                Ok(rel) => self.target.join(rel),
                Err(_) => f,
            })
            .collect())
    }

    /// Refuses a path of this run's files that holds something the earlier run did not write
    /// (with an older run that has no manifest: something that is not a file), or that
    /// passes through a symbolic link or a file.
    fn check_in_the_way(
        &self,
        new: &BTreeSet<PathBuf>,
        old: Option<&BTreeSet<PathBuf>>,
    ) -> Result<(), OutputError> {
        let refuse = |rel: &Path| OutputError::InTheWay {
            path: self.target.join(rel).display().to_string(),
        };
        for rel in new {
            let mut at = self.resolved.clone();
            let parts: Vec<Component<'_>> = rel.components().collect();
            for (k, part) in parts.iter().enumerate() {
                at.push(part);
                let Ok(meta) = std::fs::symlink_metadata(&at) else { break };
                let last = k + 1 == parts.len();
                let fits = if last {
                    meta.is_file() && old.is_none_or(|old| old.contains(rel))
                } else {
                    meta.is_dir()
                };
                if !fits {
                    return Err(refuse(at.strip_prefix(&self.resolved).unwrap_or(rel)));
                }
            }
        }
        Ok(())
    }

    /// Writes `files` as the target's manifest (written in the staging directory, then moved:
    /// a reader sees the old list or the new one).
    fn replace_manifest(&self, files: &BTreeSet<PathBuf>) -> Result<(), OutputError> {
        let staged = self.staging.join(MANIFEST);
        write_manifest(&staged, files)?;
        let to = self.resolved.join(MANIFEST);
        std::fs::rename(&staged, &to).map_err(super::io(&to))
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.committed {
            let mut live = live();
            let _ = std::fs::remove_dir_all(&self.staging);
            live.retain(|d| d != &self.staging);
        }
    }
}

/// `target` with its symbolic links resolved: the nearest existing ancestor canonicalised and
/// the missing rest appended (`..` in the missing rest drops the component before it, which
/// is no link since it does not exist).
///
/// # Errors
/// [`OutputError::NotADirectory`] when `target` (or an ancestor) is a link to nothing;
/// [`OutputError::Io`] when the working directory cannot be read.
fn resolve(target: &Path) -> Result<PathBuf, OutputError> {
    let absolute = if target.is_absolute() {
        target.to_path_buf()
    } else {
        std::env::current_dir().map_err(super::io(target))?.join(target)
    };
    let mut missing = Vec::new();
    let mut existing = absolute.as_path();
    loop {
        if let Ok(path) = existing.canonicalize() {
            let mut out = path;
            for part in missing.iter().rev() {
                match part {
                    Component::ParentDir => {
                        out.pop();
                    }
                    Component::Normal(name) => out.push(name),
                    _ => {}
                }
            }
            return Ok(out);
        }
        if std::fs::symlink_metadata(existing).is_ok() {
            // It exists but cannot be resolved: a link to nothing (or a loop of links).
            return Err(OutputError::NotADirectory { path: target.display().to_string() });
        }
        let (Some(parent), Some(last)) = (existing.parent(), existing.components().next_back())
        else {
            return Ok(absolute);
        };
        missing.push(last);
        existing = parent;
    }
}

fn is_empty_dir(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|mut entries| entries.next().is_none())
}

fn has_manifest(dir: &Path) -> bool {
    std::fs::symlink_metadata(dir.join(MANIFEST)).is_ok_and(|m| m.is_file())
}

/// Whether `dir` holds an earlier run of this program (its `summary.json`, or those of a
/// comparison's `mfvm/`, name the program).
fn holds_a_run(dir: &Path) -> bool {
    let ours = |summary: PathBuf| {
        std::fs::read_to_string(summary)
            .is_ok_and(|text| text.contains(&format!("\"name\": \"{}\"", env!("CARGO_PKG_NAME"))))
    };
    ours(dir.join("summary.json")) || ours(dir.join("mfvm").join("summary.json"))
}

/// The files under `root.join(rel)`, as paths relative to `root`, into `out`.
fn walk(root: &Path, rel: &Path, out: &mut BTreeSet<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(root.join(rel))? {
        let entry = entry?;
        let path = rel.join(entry.file_name());
        if entry.file_type()?.is_dir() {
            walk(root, &path, out)?;
        } else {
            out.insert(path);
        }
    }
    Ok(())
}

/// The manifest's text: a comment line, then the paths with `/`, sorted.
fn write_manifest(path: &Path, files: &BTreeSet<PathBuf>) -> Result<(), OutputError> {
    let mut text = format!(
        "# {}: the files the last run wrote into this directory; a rerun replaces these and keeps every other file\n",
        env!("CARGO_PKG_NAME")
    );
    for rel in files {
        let parts: Vec<String> =
            rel.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
        text.push_str(&parts.join("/"));
        text.push('\n');
    }
    super::write_text(path, &text)
}

/// The files a directory's manifest lists (`None` without a manifest). Only relative paths
/// of plain names are taken: an entry such as `../x` or `/x` is never one of ours.
fn read_manifest(dir: &Path) -> Option<BTreeSet<PathBuf>> {
    if !has_manifest(dir) {
        return None;
    }
    let text = std::fs::read_to_string(dir.join(MANIFEST)).ok()?;
    Some(
        text.lines()
            .filter(|l| !l.is_empty() && !l.starts_with('#'))
            .map(PathBuf::from)
            .filter(|p| {
                p.components().count() > 0
                    && p.components().all(|c| matches!(c, Component::Normal(_)))
                    && p != Path::new(MANIFEST)
            })
            .collect(),
    )
}

/// Removes the earlier run's file `rel` under `dir` (a file or a link, never a directory, and
/// never through a link), then its directories that became empty.
fn remove_output(dir: &Path, rel: &Path) {
    let mut at = dir.to_path_buf();
    let parts: Vec<Component<'_>> = rel.components().collect();
    for (k, part) in parts.iter().enumerate() {
        at.push(part);
        let Ok(meta) = std::fs::symlink_metadata(&at) else { return };
        let last = k + 1 == parts.len();
        if (last && meta.is_dir()) || (!last && !meta.is_dir()) {
            return;
        }
    }
    if std::fs::remove_file(&at).is_err() {
        return;
    }
    let mut parent = at.parent();
    while let Some(p) = parent.filter(|p| p.starts_with(dir) && *p != dir) {
        if std::fs::remove_dir(p).is_err() {
            break;
        }
        parent = p.parent();
    }
}

/// Removes the staging directories `<prefix><pid>` (and `<prefix><pid>-<k>`) in `parent` whose
/// process is gone.
fn remove_stale_staging(parent: &Path, prefix: &str) {
    let Ok(entries) = std::fs::read_dir(parent) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name.to_str().and_then(|n| n.strip_prefix(prefix)) else { continue };
        let Ok(pid) = pid.split_once('-').map_or(pid, |(pid, _)| pid).parse::<u32>() else {
            continue;
        };
        let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
        if is_dir && pid != std::process::id() && process_gone(pid) {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}

/// Whether no process `pid` runs on this machine (`false` when that cannot be told: without
/// `/proc`, a staging directory is never taken for stale).
fn process_gone(pid: u32) -> bool {
    Path::new("/proc/self").exists() && !Path::new("/proc").join(pid.to_string()).exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/outdir-tests").join(name);
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_manifest_entry_outside_the_directory_is_ignored() {
        let dir = scratch("manifest-entries");
        std::fs::write(
            dir.join(MANIFEST),
            "# comment\nnodes.csv\nplots/a.svg\n../escape\n/abs\n./x\n\nplots/../b\n",
        )
        .unwrap();
        let listed: Vec<PathBuf> = read_manifest(&dir).unwrap().into_iter().collect();
        assert_eq!(listed, vec![PathBuf::from("nodes.csv"), PathBuf::from("plots/a.svg")]);
    }

    #[test]
    fn a_missing_target_resolves_through_its_existing_ancestor() {
        let dir = scratch("resolve");
        std::fs::create_dir(dir.join("real")).unwrap();
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("real", dir.join("link")).unwrap();
            let got = resolve(&dir.join("link/new/../out")).unwrap();
            assert_eq!(got, dir.canonicalize().unwrap().join("real/out"));
            std::os::unix::fs::symlink("nowhere", dir.join("dangling")).unwrap();
            assert!(matches!(
                resolve(&dir.join("dangling")),
                Err(OutputError::NotADirectory { .. })
            ));
        }
    }

    #[test]
    fn removing_an_output_never_follows_a_link_or_removes_a_directory() {
        let dir = scratch("remove-output");
        std::fs::create_dir_all(dir.join("out/plots")).unwrap();
        std::fs::create_dir_all(dir.join("elsewhere")).unwrap();
        std::fs::write(dir.join("elsewhere/a.svg"), "keep").unwrap();
        std::fs::write(dir.join("out/plots/b.svg"), "ours").unwrap();
        std::fs::create_dir(dir.join("out/c.csv")).unwrap();
        #[cfg(unix)]
        std::os::unix::fs::symlink(dir.join("elsewhere"), dir.join("out/linked")).unwrap();
        let out = dir.join("out");
        remove_output(&out, Path::new("linked/a.svg"));
        remove_output(&out, Path::new("c.csv"));
        remove_output(&out, Path::new("plots/b.svg"));
        assert!(dir.join("elsewhere/a.svg").exists());
        assert!(out.join("c.csv").is_dir());
        assert!(!out.join("plots").exists(), "the emptied directory is removed");
    }
}
