//! Output files that appear whole or not at all: written under a temporary name unique to this
//! process and call, then renamed into place (a rename within one directory is atomic), and
//! output *sets* ([`StagedDir`]): written into a fresh folder inside the output folder, then
//! moved into place together.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

/// A file being written under a temporary name: [`AtomicFile::commit`] renames it into place;
/// dropping it without a commit (an error, a panic) removes the temporary file.
pub struct AtomicFile {
    tmp: PathBuf,
    path: PathBuf,
}

/// `.<name>.<pid>.<n>.tmp` next to `path`: two runs writing into one folder never share it.
fn temporary(path: &Path) -> PathBuf {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.{}.{n}.tmp", std::process::id()))
}

impl AtomicFile {
    /// Starts writing `path` (through a temporary file in the same directory): the guard and
    /// the writer to write into.
    pub fn create(path: &Path) -> std::io::Result<(Self, BufWriter<File>)> {
        let tmp = temporary(path);
        let file = File::create(&tmp)?;
        let guard = Self {
            tmp,
            path: path.to_path_buf(),
        };
        Ok((guard, BufWriter::new(file)))
    }

    /// Flushes and syncs `writer` (the one [`AtomicFile::create`] returned) and renames the
    /// file into place.
    pub fn commit(self, writer: BufWriter<File>) -> std::io::Result<()> {
        let file = writer.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&self.tmp, &self.path)?;
        std::mem::forget(self);
        Ok(())
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // The temporary file of a write that did not complete; nothing to do if it is gone.
        let _ = std::fs::remove_file(&self.tmp);
    }
}

/// The staging folders of this process not yet committed or dropped. A commit holds the lock
/// while it moves its files, so [`abandon_staged`] (an interrupt handler) waits for a commit in
/// progress to finish and never sees half of one.
static STAGED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn staged() -> MutexGuard<'static, Vec<PathBuf>> {
    // A panic while the lock was held leaves the list itself intact.
    STAGED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// A set of output files written into a fresh folder `.<pid>.<n>.staging` inside the output
/// folder, then moved into place by [`StagedDir::commit`]; dropped without a commit (an error,
/// a panic), the folder and everything in it is removed.
pub struct StagedDir {
    stage: PathBuf,
    out: PathBuf,
}

impl StagedDir {
    /// A fresh staging folder inside `out` (which must exist).
    pub fn new(out: &Path) -> std::io::Result<Self> {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let stage = out.join(format!(".{}.{n}.staging", std::process::id()));
        let mut list = staged();
        std::fs::create_dir(&stage)?;
        list.push(stage.clone());
        Ok(Self {
            stage,
            out: out.to_path_buf(),
        })
    }

    /// Where to write the files of the set.
    pub fn path(&self) -> &Path {
        &self.stage
    }

    /// Moves `names` (in this order: put the file that marks a complete set last) from the
    /// staging folder into the output folder, removes the `stale` names there that are not in
    /// the set, and removes the staging folder. Renames within one file system; each is atomic,
    /// and [`abandon_staged`] cannot interrupt the sequence.
    pub fn commit(self, names: &[&str], stale: &[&str]) -> std::io::Result<()> {
        let mut list = staged();
        for name in names {
            std::fs::rename(self.stage.join(name), self.out.join(name))?;
        }
        for name in stale.iter().filter(|s| !names.contains(s)) {
            match std::fs::remove_file(self.out.join(name)) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e),
                _ => {}
            }
        }
        list.retain(|p| p != &self.stage);
        drop(list);
        // Only files of the set were there, and they have moved out.
        let _ = std::fs::remove_dir_all(&self.stage);
        std::mem::forget(self);
        Ok(())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        staged().retain(|p| p != &self.stage);
        let _ = std::fs::remove_dir_all(&self.stage);
    }
}

/// For an interrupt handler: removes every staging folder of this process not yet committed
/// (after waiting for a commit in progress), and returns the lock, which the caller holds until
/// it exits so that no new set starts. Whatever the moment of the interrupt, each output folder
/// then holds either its previous complete set or the new complete one, and no staging folder.
pub fn abandon_staged() -> MutexGuard<'static, Vec<PathBuf>> {
    let mut list = staged();
    for stage in list.drain(..) {
        // A file the main thread creates meanwhile can make one attempt fail.
        for _ in 0..10 {
            if std::fs::remove_dir_all(&stage).is_ok() || !stage.exists() {
                break;
            }
        }
    }
    list
}

/// Writes `contents` to `path` whole or not at all.
pub fn write_atomically(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    let (guard, mut writer) = AtomicFile::create(path)?;
    writer.write_all(contents)?;
    guard.commit(writer)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("harmonav-atomic-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_committed_file_replaces_the_old_one_and_leaves_no_temporary() {
        let d = dir("commit");
        let path = d.join("out.txt");
        std::fs::write(&path, "old").unwrap();
        write_atomically(&path, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn an_uncommitted_file_leaves_the_old_one_untouched() {
        let d = dir("drop");
        let path = d.join("out.txt");
        std::fs::write(&path, "old").unwrap();
        {
            let (f, mut w) = AtomicFile::create(&path).unwrap();
            w.write_all(b"half").unwrap();
            let (other, _) = AtomicFile::create(&path).unwrap();
            assert_ne!(f.tmp, other.tmp, "two writers never share a temporary file");
        }
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        std::fs::remove_dir_all(d).unwrap();
    }

    /// `abandon_staged` removes every staging folder of the process: the tests that stage sets
    /// take turns (no other unit test of this crate stages one).
    static SERIAL: Mutex<()> = Mutex::new(());

    fn names(d: &Path) -> Vec<String> {
        let mut n: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        n.sort();
        n
    }

    #[test]
    fn a_committed_set_replaces_the_old_one_and_drops_its_stale_files() {
        let _turn = SERIAL.lock().unwrap_or_else(|p| p.into_inner());
        let d = dir("set");
        for (name, text) in [("a.txt", "old a"), ("b.txt", "old b"), ("keep.txt", "mine")] {
            std::fs::write(d.join(name), text).unwrap();
        }
        let stage = StagedDir::new(&d).unwrap();
        assert!(stage.path().starts_with(&d) && stage.path().is_dir());
        std::fs::write(stage.path().join("a.txt"), "new a").unwrap();
        std::fs::write(stage.path().join("c.txt"), "new c").unwrap();
        stage
            .commit(&["a.txt", "c.txt"], &["a.txt", "b.txt"])
            .unwrap();
        assert_eq!(names(&d), ["a.txt", "c.txt", "keep.txt"]);
        assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "new a");
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn an_uncommitted_or_abandoned_set_leaves_the_old_one_and_no_staging_folder() {
        let _turn = SERIAL.lock().unwrap_or_else(|p| p.into_inner());
        let d = dir("abandon");
        std::fs::write(d.join("a.txt"), "old").unwrap();
        {
            let stage = StagedDir::new(&d).unwrap();
            std::fs::write(stage.path().join("a.txt"), "half").unwrap();
            let other = StagedDir::new(&d).unwrap();
            assert_ne!(stage.path(), other.path(), "two sets never share a folder");
        }
        assert_eq!(names(&d), ["a.txt"]);
        // An interrupt handler's clean-up: the folder goes, and a later commit finds it gone.
        let stage = StagedDir::new(&d).unwrap();
        std::fs::write(stage.path().join("a.txt"), "half").unwrap();
        drop(abandon_staged());
        assert_eq!(names(&d), ["a.txt"]);
        assert!(stage.commit(&["a.txt"], &[]).is_err());
        assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "old");
        std::fs::remove_dir_all(d).unwrap();
    }
}
