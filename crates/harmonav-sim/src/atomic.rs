//! Output files that appear whole or not at all: written under a temporary name unique to this
//! process and call, then renamed into place (a rename within one directory is atomic).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// A file being written: [`AtomicFile::commit`] renames it into place; dropping it without a
/// commit (an error, a panic) removes the temporary file.
pub struct AtomicFile {
    writer: Option<BufWriter<File>>,
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
    /// Starts writing `path` (through a temporary file in the same directory).
    pub fn create(path: &Path) -> std::io::Result<Self> {
        let tmp = temporary(path);
        let file = File::create(&tmp)?;
        Ok(Self {
            writer: Some(BufWriter::new(file)),
            tmp,
            path: path.to_path_buf(),
        })
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        self.writer.as_mut().expect("present until commit")
    }

    /// Takes the writer out (for a consumer that owns it, such as the MCAP sink); give it
    /// back with [`AtomicFile::commit_with`].
    pub fn take_writer(&mut self) -> BufWriter<File> {
        self.writer.take().expect("present until commit")
    }

    /// Flushes, syncs and renames the file into place.
    pub fn commit(mut self) -> std::io::Result<()> {
        let writer = self.take_writer();
        self.commit_with(writer)
    }

    /// [`AtomicFile::commit`] with the writer taken by [`AtomicFile::take_writer`].
    pub fn commit_with(self, writer: BufWriter<File>) -> std::io::Result<()> {
        let file = writer.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&self.tmp, &self.path)?;
        std::mem::forget(self);
        Ok(())
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        drop(self.writer.take());
        let _ = std::fs::remove_file(&self.tmp);
    }
}

/// Writes `contents` to `path` whole or not at all.
pub fn write_atomically(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    let mut f = AtomicFile::create(path)?;
    f.writer().write_all(contents)?;
    f.commit()
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
            let mut f = AtomicFile::create(&path).unwrap();
            f.writer().write_all(b"half").unwrap();
            let other = AtomicFile::create(&path).unwrap();
            assert_ne!(f.tmp, other.tmp, "two writers never share a temporary file");
        }
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        std::fs::remove_dir_all(d).unwrap();
    }
}
