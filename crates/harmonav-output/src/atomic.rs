//! Output files that appear whole or not at all: written under a temporary name unique to this
//! process and call, then renamed into place (a rename within one directory is atomic), and
//! output *sets* ([`StagedDir`]): written into a fresh folder inside the output folder, then
//! moved into place together. [`check_output_names`] finds every problem of an output folder
//! before anything is computed for it (an empty path, a path below a file, a dangling or
//! looping symbolic link, a folder that cannot be written, a path longer than `PATH_MAX`, an
//! output name taken by a folder); [`OutputError`] says which.

use std::fs::File;
use std::io::{BufWriter, ErrorKind, Write};
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

/// What an interrupt must remove: a staging folder, or an output folder created for a set not
/// yet committed (removed only while empty).
#[derive(Clone, Debug, PartialEq)]
enum Pending {
    Stage(PathBuf),
    Created(PathBuf),
}

/// The staging folders of this process not yet committed or dropped, and the output folders
/// created for them. A commit holds the lock while it moves its files, so [`abandon_staged`]
/// (an interrupt handler) waits for a commit in progress to finish and never sees half of one.
static STAGED: Mutex<Vec<Pending>> = Mutex::new(Vec::new());

fn staged() -> MutexGuard<'static, Vec<Pending>> {
    // A panic while the lock was held leaves the list itself intact.
    STAGED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Removes the staging folders `.<pid>.<n>.staging` in `out` whose process is gone (issue 56,
/// D17: a run killed by SIGKILL left 51 MB that no later run removed). On Linux a process is
/// gone when `/proc/<pid>` is; elsewhere nothing is removed. Best effort: a folder that cannot
/// be read or removed is left as it was.
fn remove_orphans(out: &Path) {
    if !cfg!(target_os = "linux") {
        return;
    }
    let Ok(entries) = std::fs::read_dir(out) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name
            .to_str()
            .and_then(|n| n.strip_prefix('.')?.strip_suffix(".staging"))
            .and_then(|n| n.split_once('.'))
            .filter(|(_, n)| n.parse::<u64>().is_ok())
            .and_then(|(pid, _)| pid.parse::<u32>().ok())
        else {
            continue;
        };
        let gone = pid != std::process::id()
            && !Path::new("/proc").join(pid.to_string()).exists()
            && Path::new("/proc/self").exists();
        if gone && entry.file_type().is_ok_and(|t| t.is_dir()) {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}

/// A set of output files written into a fresh folder `.<pid>.<n>.staging` inside the output
/// folder, then moved into place by [`StagedDir::commit`]; dropped without a commit (an error,
/// a panic), the folder and everything in it is removed.
pub struct StagedDir {
    stage: PathBuf,
    out: PathBuf,
}

impl StagedDir {
    /// A fresh staging folder inside `out` (which must exist). Errors: [`OutputError::Io`]
    /// naming the staging folder.
    pub fn new(out: &Path) -> Result<Self, OutputError> {
        remove_orphans(out);
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let stage = out.join(format!(".{}.{n}.staging", std::process::id()));
        let mut list = staged();
        std::fs::create_dir(&stage).map_err(|e| io_error(&stage, e))?;
        list.push(Pending::Stage(stage.clone()));
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
    ///
    /// Before anything is moved, every name of `names` and `stale` in the output folder is
    /// checked not to be a folder (a rename or removal there would fail half-way through the
    /// set): [`OutputError::OutputIsDirectory`], and the previous set is untouched. Other
    /// errors ([`OutputError::Io`]) come from the file system while moving (a failing rename,
    /// an I/O fault) and can leave a mix.
    pub fn commit(self, names: &[&str], stale: &[&str]) -> Result<(), OutputError> {
        let mut list = staged();
        for name in names.iter().chain(stale) {
            check_not_a_directory(&self.out.join(name))?;
        }
        for name in names {
            let to = self.out.join(name);
            std::fs::rename(self.stage.join(name), &to).map_err(|e| io_error(&to, e))?;
        }
        for name in stale.iter().filter(|s| !names.contains(s)) {
            let path = self.out.join(name);
            match std::fs::remove_file(&path) {
                Err(e) if e.kind() != ErrorKind::NotFound => return Err(io_error(&path, e)),
                _ => {}
            }
        }
        // Only files of the set were there, and they have moved out. The folder goes while the
        // lock is held: an interrupt between its leaving the list and its removal would leave
        // it behind (the handler exits without knowing it).
        let _ = std::fs::remove_dir_all(&self.stage);
        list.retain(|p| p != &Pending::Stage(self.stage.clone()));
        drop(list);
        std::mem::forget(self);
        Ok(())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        // Removed under the lock, as in `commit`: the handler either removes it or waits.
        let mut list = staged();
        let _ = std::fs::remove_dir_all(&self.stage);
        list.retain(|p| p != &Pending::Stage(self.stage.clone()));
    }
}

/// The folders [`CreatedDir::create`] made for an output folder, outermost first: dropped
/// before [`CreatedDir::keep`] (a run that failed or was interrupted), each is removed if it is
/// empty, innermost first, so that a failed run leaves no empty output folder behind.
pub struct CreatedDir {
    made: Vec<PathBuf>,
}

impl CreatedDir {
    /// Creates `dir` and its missing parents, remembering which were missing.
    ///
    /// # Errors
    /// [`OutputError::Io`] naming `dir`.
    pub fn create(dir: &Path) -> Result<Self, OutputError> {
        let mut missing: Vec<PathBuf> = dir
            .ancestors()
            .take_while(|a| !a.as_os_str().is_empty() && std::fs::symlink_metadata(a).is_err())
            .map(Path::to_path_buf)
            .collect();
        missing.reverse();
        let mut list = staged();
        std::fs::create_dir_all(dir).map_err(|e| io_error(dir, e))?;
        list.extend(missing.iter().cloned().map(Pending::Created));
        Ok(Self { made: missing })
    }

    /// The set is in place: the folders stay.
    pub fn keep(self) {
        let mut list = staged();
        list.retain(|p| !matches!(p, Pending::Created(d) if self.made.contains(d)));
        drop(list);
        std::mem::forget(self);
    }
}

impl Drop for CreatedDir {
    fn drop(&mut self) {
        let mut list = staged();
        for d in self.made.iter().rev() {
            // Only an empty folder goes: whatever else was put there stays.
            let _ = std::fs::remove_dir(d);
        }
        list.retain(|p| !matches!(p, Pending::Created(d) if self.made.contains(d)));
    }
}

/// For an interrupt handler: removes every staging folder of this process not yet committed
/// (after waiting for a commit in progress), then the output folders created for them
/// ([`CreatedDir`]) that are empty, and returns the lock, which the caller holds until it exits
/// so that no new set starts. Whatever the moment of the interrupt, each output folder then
/// holds either its previous complete set or the new complete one, and no staging folder; a
/// folder the run created is gone unless a set was moved into it.
pub fn abandon_staged() -> impl Sized + 'static {
    let mut list = staged();
    let pending: Vec<Pending> = list.drain(..).collect();
    for p in &pending {
        if let Pending::Stage(stage) = p {
            // A file the main thread creates meanwhile can make one attempt fail.
            for _ in 0..10 {
                if std::fs::remove_dir_all(stage).is_ok() || !stage.exists() {
                    break;
                }
            }
        }
    }
    // Then the output folders created for the sets, innermost first, if they are empty.
    for p in pending.iter().rev() {
        if let Pending::Created(d) = p {
            let _ = std::fs::remove_dir(d);
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

/// Why an output folder cannot take a set of outputs, or why writing the set failed. Each
/// variant names the path it is about.
#[derive(Debug)]
pub enum OutputError {
    /// The path is empty. It would mean the current folder, where a set replaces files and
    /// removes stale ones (`speed.svg`, `energy.svg`): give `.` to mean that folder.
    EmptyPath,
    /// The path is longer than the system allows once the set's files are written inside it:
    /// `bytes` long, at most `max` (`PATH_MAX` less [`RESERVED_BYTES`]).
    PathTooLong {
        /// The path.
        path: PathBuf,
        /// Its length, bytes.
        bytes: usize,
        /// The longest path that can take the set, bytes.
        max: usize,
    },
    /// A component of the path is longer than `NAME_MAX` ([`NAME_MAX`] bytes).
    NameTooLong {
        /// The path.
        path: PathBuf,
        /// The component's length, bytes.
        bytes: usize,
    },
    /// The path exists and is not a folder.
    NotADirectory {
        /// The path.
        path: PathBuf,
    },
    /// A parent of the path, `file`, is a file: no folder can be created below it.
    BelowFile {
        /// The path.
        path: PathBuf,
        /// The parent that is a file.
        file: PathBuf,
    },
    /// `link` (the path or one of its parents) is a symbolic link to `target`, which does not
    /// exist.
    DanglingSymlink {
        /// The path.
        path: PathBuf,
        /// The link.
        link: PathBuf,
        /// What it points to.
        target: PathBuf,
    },
    /// `link` (the path or one of its parents) is a symbolic link that leads back to itself
    /// (more than [`MAX_SYMLINK_HOPS`] links in a row).
    SymlinkLoop {
        /// The path.
        path: PathBuf,
        /// The link.
        link: PathBuf,
    },
    /// Nothing can be created in `dir`: the folder itself or, where it does not exist yet, its
    /// nearest existing parent (permissions, a read-only file system).
    Unwritable {
        /// The path.
        path: PathBuf,
        /// The folder.
        dir: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// A file of the set would replace `path`, which is a folder.
    OutputIsDirectory {
        /// The path.
        path: PathBuf,
    },
    /// The file `file` of the set could not be produced (a figure, the recording).
    Content {
        /// The file's name.
        file: &'static str,
        /// Why.
        problem: String,
    },
    /// An I/O error at `path`.
    Io {
        /// The path.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
}

impl std::fmt::Display for OutputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::EmptyPath => write!(
                f,
                "the output folder's path is empty; give a folder (`.` for the current one)"
            ),
            Self::PathTooLong { path, bytes, max } => write!(
                f,
                "{}: the path is {bytes} bytes long; the outputs written inside it need it to be \
                 at most {max} (PATH_MAX)",
                shortened(path)
            ),
            Self::NameTooLong { path, bytes } => write!(
                f,
                "{}: a component of the path is {bytes} bytes long, more than NAME_MAX \
                 ({NAME_MAX})",
                shortened(path)
            ),
            Self::NotADirectory { path } => {
                write!(f, "{}: exists and is not a directory", path.display())
            }
            Self::BelowFile { path, file } => write!(
                f,
                "{}: cannot create a folder there: {} is a file, not a directory",
                path.display(),
                file.display()
            ),
            Self::DanglingSymlink { path, link, target } => write!(
                f,
                "{}: {} is a symbolic link to {}, which does not exist",
                path.display(),
                link.display(),
                target.display()
            ),
            Self::SymlinkLoop { path, link } => write!(
                f,
                "{}: {} is a symbolic link that loops (more than {MAX_SYMLINK_HOPS} links in a \
                 row)",
                path.display(),
                link.display()
            ),
            Self::Unwritable { path, dir, source } => write!(
                f,
                "{}: cannot create anything in {}: {source}",
                path.display(),
                dir.display()
            ),
            Self::OutputIsDirectory { path } => write!(
                f,
                "{}: is a directory, where an output file would go; remove or rename it",
                path.display()
            ),
            Self::Content { file, problem } => write!(f, "cannot produce {file}: {problem}"),
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
        }
    }
}

impl std::error::Error for OutputError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Unwritable { source, .. } | Self::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

fn io_error(path: &Path, source: std::io::Error) -> OutputError {
    OutputError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// A path as shown in an error: at most 80 characters of it (a path that is too long is
/// thousands of bytes).
fn shortened(path: &Path) -> String {
    let text = path.display().to_string();
    match text.char_indices().nth(80) {
        Some((cut, _)) => format!("{}…", &text[..cut]),
        None => text,
    }
}

/// The longest path the system takes, bytes (without the terminating NUL).
#[cfg(target_os = "linux")]
pub const PATH_MAX: usize = 4095;
/// The longest path the system takes, bytes (without the terminating NUL).
#[cfg(not(target_os = "linux"))]
pub const PATH_MAX: usize = 1023;

/// The longest component of a path, bytes.
pub const NAME_MAX: usize = 255;

/// What a set adds below its folder, bytes: `/.<pid>.<n>.staging/.<name>.<pid>.<n>.tmp` with
/// the longest pid (10 digits), counters (20 digits) and file name (`trajectory.svg`) is 93.
pub const RESERVED_BYTES: usize = 96;

/// Symbolic links followed in a row before a path counts as a loop (Linux's `MAXSYMLINKS`).
pub const MAX_SYMLINK_HOPS: usize = 40;

/// Checks, before anything is computed for it, that `dir` can take a set of outputs named
/// `names`, and changes nothing: the path is not empty, not too long ([`PATH_MAX`],
/// [`NAME_MAX`]), it is a folder or can be created (no parent is a file, no symbolic link on
/// the way dangles or loops), something can be created in it (or in its nearest existing
/// parent: a probe folder is created and removed), and none of `names` in it is a folder.
/// A `dir` that does not exist yet is not created.
pub fn check_output_names(dir: &Path, names: &[&str]) -> Result<(), OutputError> {
    let bytes = dir.as_os_str().len();
    if bytes == 0 {
        return Err(OutputError::EmptyPath);
    }
    if let Some(long) = dir
        .components()
        .map(|c| c.as_os_str().len())
        .find(|&n| n > NAME_MAX)
    {
        return Err(OutputError::NameTooLong {
            path: dir.to_path_buf(),
            bytes: long,
        });
    }
    let max = PATH_MAX - RESERVED_BYTES;
    if bytes > max {
        return Err(OutputError::PathTooLong {
            path: dir.to_path_buf(),
            bytes,
            max,
        });
    }
    let existing = existing_folder(dir)?;
    probe(dir, &existing)?;
    if existing.as_path() == dir {
        for name in names {
            check_not_a_directory(&dir.join(name))?;
        }
    }
    Ok(())
}

/// The nearest of `dir` and its parents that exists (`dir` itself if it does), which must be
/// a folder (through symbolic links).
fn existing_folder(dir: &Path) -> Result<PathBuf, OutputError> {
    // The first error below the folder found that was not "does not exist" or "not a
    // directory" (e.g. no permission to look): reported if nothing above explains it.
    let mut unexplained: Option<OutputError> = None;
    for a in dir.ancestors() {
        // The relative path's last ancestor is "": the current folder.
        let a = if a.as_os_str().is_empty() {
            Path::new(".")
        } else {
            a
        };
        let meta = match std::fs::symlink_metadata(a) {
            Ok(m) => m,
            Err(e) if matches!(e.kind(), ErrorKind::NotFound | ErrorKind::NotADirectory) => {
                continue;
            }
            Err(e) => {
                unexplained.get_or_insert(io_error(a, e));
                continue;
            }
        };
        let meta = if meta.file_type().is_symlink() {
            follow(dir, a)?
        } else {
            meta
        };
        if !meta.is_dir() {
            return Err(if a == dir {
                OutputError::NotADirectory {
                    path: dir.to_path_buf(),
                }
            } else {
                OutputError::BelowFile {
                    path: dir.to_path_buf(),
                    file: a.to_path_buf(),
                }
            });
        }
        return match unexplained {
            Some(e) => Err(e),
            None => Ok(a.to_path_buf()),
        };
    }
    // Only for a path whose root does not exist.
    Err(unexplained.unwrap_or_else(|| {
        io_error(
            dir,
            std::io::Error::new(ErrorKind::NotFound, "no parent folder exists"),
        )
    }))
}

/// What the symbolic link `link` (on the way to `dir`) leads to: dangling, looping or
/// unreadable links are errors.
fn follow(dir: &Path, link: &Path) -> Result<std::fs::Metadata, OutputError> {
    match std::fs::metadata(link) {
        Ok(m) => Ok(m),
        Err(e) if e.kind() == ErrorKind::NotFound => Err(OutputError::DanglingSymlink {
            path: dir.to_path_buf(),
            link: link.to_path_buf(),
            target: std::fs::read_link(link).unwrap_or_default(),
        }),
        Err(e) => {
            // Follow the chain by hand: a loop is a chain that never ends.
            let mut at = link.to_path_buf();
            for _ in 0..=MAX_SYMLINK_HOPS {
                match std::fs::read_link(&at) {
                    Ok(next) => at = at.parent().unwrap_or(Path::new("")).join(next),
                    Err(_) => return Err(io_error(link, e)),
                }
            }
            Err(OutputError::SymlinkLoop {
                path: dir.to_path_buf(),
                link: link.to_path_buf(),
            })
        }
    }
}

/// Creates and removes a probe folder in `dir` (the output folder `path` or its nearest
/// existing parent): whether anything can be created there.
fn probe(path: &Path, dir: &Path) -> Result<(), OutputError> {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let probe = dir.join(format!(".{}.{n}.probe", std::process::id()));
    // Under the staging lock, so that an interrupt handler ([`abandon_staged`]) waits for the
    // probe to be gone.
    let _no_interrupt = staged();
    match std::fs::create_dir(&probe) {
        Ok(()) => {
            let _ = std::fs::remove_dir(&probe);
            Ok(())
        }
        Err(source) => Err(OutputError::Unwritable {
            path: path.to_path_buf(),
            dir: dir.to_path_buf(),
            source,
        }),
    }
}

/// `path` is not a folder (it may be missing, a file, or a symbolic link, which a rename
/// replaces).
fn check_not_a_directory(path: &Path) -> Result<(), OutputError> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.is_dir() => Err(OutputError::OutputIsDirectory {
            path: path.to_path_buf(),
        }),
        _ => Ok(()),
    }
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
    fn a_staging_folder_of_a_process_that_is_gone_is_removed_by_the_next_set() {
        let _turn = SERIAL.lock().unwrap_or_else(|p| p.into_inner());
        let d = dir("orphans");
        // Beyond Linux's largest pid (2^22): no such process.
        let orphan = d.join(".999999999.3.staging");
        std::fs::create_dir_all(orphan.join("inner")).unwrap();
        std::fs::write(orphan.join("inner/.run.mcap.1.2.tmp"), b"partial").unwrap();
        // This process's own and a name of another kind stay.
        let own = d.join(format!(".{}.999999.staging", std::process::id()));
        std::fs::create_dir_all(&own).unwrap();
        let other = d.join(".12.x.staging");
        std::fs::create_dir_all(&other).unwrap();
        let set = StagedDir::new(&d).unwrap();
        assert!(!orphan.exists());
        assert!(own.exists() && other.exists());
        drop(set);
        std::fs::remove_dir_all(&d).unwrap();
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

    /// The folders a set created for its output folder go when the set is dropped or
    /// abandoned unfinished, while empty and innermost first; kept, or holding anything else,
    /// they stay, and a folder that existed before is never removed.
    #[test]
    fn an_output_folder_created_for_a_set_goes_with_the_set() {
        let _turn = SERIAL.lock().unwrap_or_else(|p| p.into_inner());
        let d = dir("created");
        let nested = d.join("a/b/c");
        drop(CreatedDir::create(&nested).unwrap());
        assert!(!d.join("a").exists(), "every missing level goes");
        // Existing levels stay; a folder something else was put in stays.
        std::fs::create_dir_all(d.join("a")).unwrap();
        {
            let _c = CreatedDir::create(&nested).unwrap();
            std::fs::write(d.join("a/b/mine.txt"), "x").unwrap();
        }
        assert_eq!(names(&d.join("a/b")), ["mine.txt"]);
        std::fs::remove_dir_all(d.join("a")).unwrap();
        // Kept (the set is in place), nothing goes.
        CreatedDir::create(&nested).unwrap().keep();
        assert!(nested.is_dir());
        std::fs::remove_dir_all(d.join("a")).unwrap();
        // An interrupt: the staging folder, then the empty folders made for it.
        let created = CreatedDir::create(&nested).unwrap();
        let stage = StagedDir::new(&nested).unwrap();
        drop(abandon_staged());
        assert!(!d.join("a").exists());
        std::mem::forget((created, stage));
        assert!(!staged().iter().any(|p| matches!(p, Pending::Created(_))));
        std::fs::remove_dir_all(d).unwrap();
    }

    /// A folder where nothing can be created: a read-only one, or for root (who may write
    /// anywhere) `/sys`, which refuses new entries.
    fn unwritable(d: &Path) -> Option<PathBuf> {
        use std::os::unix::fs::PermissionsExt;
        let ro = d.join("read-only");
        std::fs::create_dir_all(&ro).unwrap();
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
        if std::fs::create_dir(ro.join("x")).is_err() {
            return Some(ro);
        }
        let _ = std::fs::remove_dir(ro.join("x"));
        let sys = Path::new("/sys");
        (sys.is_dir() && std::fs::create_dir(sys.join(".harmonav-probe")).is_err())
            .then(|| sys.to_path_buf())
    }

    /// Every problem of an output folder, found before anything is written and without a
    /// change: each case's path, and what the check must say. Before, only "exists and is not
    /// a directory" was found before the run; the others failed after it, or (an empty path)
    /// wrote into the current folder.
    #[test]
    fn every_problem_of_an_output_folder_is_found_up_front_and_named() {
        use std::os::unix::fs::symlink;
        let d = dir("check");
        let file = d.join("a-file");
        std::fs::write(&file, "keep").unwrap();
        symlink(d.join("nowhere"), d.join("dangling")).unwrap();
        symlink(d.join("loop-b"), d.join("loop-a")).unwrap();
        symlink(d.join("loop-a"), d.join("loop-b")).unwrap();
        symlink(d.join("loop-self"), d.join("loop-self")).unwrap();
        std::fs::create_dir_all(d.join("taken/summary.json")).unwrap();
        std::fs::create_dir_all(d.join("linked-target")).unwrap();
        symlink(d.join("linked-target"), d.join("linked")).unwrap();
        let names = ["summary.json", "run.mcap"];
        let unwritable = unwritable(&d);
        let before = names_deep(&d);
        let check = |path: PathBuf, expected: &dyn Fn(&OutputError) -> bool, words: &str| {
            let e = check_output_names(&path, &names).expect_err(&path.display().to_string());
            assert!(expected(&e), "{}: {e:?}", path.display());
            let message = e.to_string();
            assert!(message.contains(words), "{}: {message}", path.display());
        };
        check(
            PathBuf::new(),
            &|e| matches!(e, OutputError::EmptyPath),
            "empty",
        );
        check(
            file.clone(),
            &|e| matches!(e, OutputError::NotADirectory { .. }),
            "not a directory",
        );
        check(
            file.join("sub/deeper"),
            &|e| matches!(e, OutputError::BelowFile { file: f, .. } if *f == file),
            "a-file is a file",
        );
        check(
            d.join("dangling"),
            &|e| matches!(e, OutputError::DanglingSymlink { target, .. } if target.ends_with("nowhere")),
            "does not exist",
        );
        check(
            d.join("dangling/sub"),
            &|e| matches!(e, OutputError::DanglingSymlink { link, .. } if link.ends_with("dangling")),
            "dangling is a symbolic link to",
        );
        for name in ["loop-a", "loop-self"] {
            check(
                d.join(name).join("sub"),
                &|e| matches!(e, OutputError::SymlinkLoop { link, .. } if link.ends_with(name)),
                "loops",
            );
        }
        check(
            d.join("taken"),
            &|e| matches!(e, OutputError::OutputIsDirectory { path } if path.ends_with("taken/summary.json")),
            "summary.json: is a directory",
        );
        let long: PathBuf = std::iter::once(d.clone())
            .chain((0..20).map(|i| PathBuf::from(format!("{i:0>200}"))))
            .collect();
        check(
            long,
            &|e| matches!(e, OutputError::PathTooLong { bytes, max, .. } if *bytes > *max),
            "PATH_MAX",
        );
        check(
            d.join("x".repeat(NAME_MAX + 1)),
            &|e| matches!(e, OutputError::NameTooLong { bytes, .. } if *bytes == NAME_MAX + 1),
            "NAME_MAX",
        );
        match unwritable {
            Some(ro) => check(
                ro.join("new/out"),
                &|e| matches!(e, OutputError::Unwritable { dir, .. } if *dir == ro),
                "cannot create anything in",
            ),
            None => eprintln!("no unwritable folder on this machine: that case is not checked"),
        }
        // What may take a set: an existing folder, one to create, a link to a folder.
        for ok in [d.clone(), d.join("new/deeper"), d.join("linked")] {
            check_output_names(&ok, &names).unwrap_or_else(|e| panic!("{}: {e}", ok.display()));
        }
        assert_eq!(names_deep(&d), before, "a check changes nothing");
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep");
        {
            use std::os::unix::fs::PermissionsExt;
            let ro = d.join("read-only");
            let _ = std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755));
        }
        std::fs::remove_dir_all(d).unwrap();
    }

    /// Every entry below `d`, sorted (links not followed).
    fn names_deep(d: &Path) -> Vec<PathBuf> {
        let mut out = Vec::new();
        let mut todo = vec![d.to_path_buf()];
        while let Some(at) = todo.pop() {
            for e in std::fs::read_dir(&at).unwrap() {
                let e = e.unwrap();
                if e.file_type().unwrap().is_dir() {
                    todo.push(e.path());
                }
                out.push(e.path());
            }
        }
        out.sort();
        out
    }

    /// A folder where a file of the set would go is found before anything is moved: the
    /// previous set stays whole (before, the files ahead of it had already been moved: a
    /// mixed set).
    #[test]
    fn a_commit_onto_a_folder_moves_nothing() {
        let _turn = SERIAL.lock().unwrap_or_else(|p| p.into_inner());
        let d = dir("onto-folder");
        std::fs::write(d.join("a.txt"), "old a").unwrap();
        let stage = StagedDir::new(&d).unwrap();
        std::fs::write(stage.path().join("a.txt"), "new a").unwrap();
        std::fs::write(stage.path().join("z.txt"), "new z").unwrap();
        std::fs::create_dir(d.join("z.txt")).unwrap();
        let e = stage.commit(&["a.txt", "z.txt"], &[]).unwrap_err();
        assert!(
            matches!(&e, OutputError::OutputIsDirectory { path } if path.ends_with("z.txt")),
            "{e:?}"
        );
        assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "old a");
        assert_eq!(names(&d), ["a.txt", "z.txt"], "no staging folder is left");
        std::fs::remove_dir_all(d).unwrap();
    }
}
