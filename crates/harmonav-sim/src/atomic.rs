//! Output files that appear whole or not at all: written under a temporary name unique to this
//! process and call, then renamed into place (a rename within one directory is atomic).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

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
}
