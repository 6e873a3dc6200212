//! What files a model may read, and how much of them.
//!
//! A cpfg model is a bundle of files: the grammar (`.l`), its view file (`.v`) and what
//! they name (`#include`, `function:`, `function set:`, `curve:`, `surface:`), and a leaf
//! prefab (`.obj`). A host that opens a user's model decides what that model may read:
//!
//! - [`FileAccess::Bundle`] (the default): the model's own folder and below, after
//!   canonicalising, regular files only; absolute paths, `..` leaving the folder and
//!   symbolic links leading out of it are refused by name.
//! - [`FileAccess::None`]: nothing beyond the one file named (or the text given).
//! - [`FileAccess::Any`]: any regular file the process can read (an explicit opt-in).
//! - [`FileAccess::Host`]: every read goes through the host's function (an engine's asset
//!   system); arbor opens nothing.
//!
//! Every load has one byte budget over all its files ([`FileOptions::max_bytes`]); a read
//! takes at most the budget plus one byte whatever the file says its length is, devices,
//! FIFOs and folders are refused before they are read, and a refusal names the path and
//! why, never the file's content.
//!
//! ```no_run
//! use arbor::files::{FileAccess, FileOptions};
//! use arbor::lsystem::LSystem;
//! use arbor::progress::Run;
//!
//! let confined = FileOptions::default().access(FileAccess::Bundle);
//! let plant = LSystem::from_file_with("models/plant.l", None, &confined, &mut Run::default())?;
//! # Ok::<(), arbor::Error>(())
//! ```

use crate::error::{Error, Result};
use crate::progress::{ProgressFn, Stage};
use std::cell::{Cell, RefCell};
use std::io::Read;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

/// The budget of one load by default: 64 MiB over all its files.
pub const DEFAULT_MAX_FILE_BYTES: u64 = 64 << 20;

/// How many `function:`/`function set:` functions, `curve:` curves and `surface:`
/// surfaces one view file may bring (each kind counted on its own).
pub const MAX_COMPANIONS: usize = 1024;

/// The host's reader: asked for a path (as the model names it, resolved against the
/// model's folder), it writes at most `buffer.len()` bytes of the file into `buffer` and
/// returns the file's full size, or `None` when there is no such file. arbor asks again
/// with a larger buffer when the size is larger than the buffer.
pub type ReadFileFn = dyn Fn(&str, &mut [u8]) -> Option<u64> + Send + Sync;

/// Which files a model may read; see the [module](self) documentation.
#[derive(Clone, Default)]
#[non_exhaustive]
pub enum FileAccess {
    /// The model's own folder and below (canonicalised, regular files, no symbolic link
    /// leaving it). The default.
    #[default]
    Bundle,
    /// Nothing beyond the one file named (or the text given).
    None,
    /// Any regular file the process can read: an explicit opt-in.
    Any,
    /// Every read goes through the host's function; arbor opens nothing.
    Host(Arc<ReadFileFn>),
}

impl std::fmt::Debug for FileAccess {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FileAccess::Bundle => "Bundle",
            FileAccess::None => "None",
            FileAccess::Any => "Any",
            FileAccess::Host(_) => "Host(..)",
        })
    }
}

impl FileAccess {
    /// A host reader serving files from memory (tests, or assets already loaded): the
    /// keys are paths as arbor asks for them.
    pub fn from_map(files: std::collections::HashMap<String, Vec<u8>>) -> Self {
        FileAccess::Host(Arc::new(move |path: &str, buffer: &mut [u8]| {
            let bytes = files.get(path)?;
            let n = bytes.len().min(buffer.len());
            buffer[..n].copy_from_slice(&bytes[..n]);
            Some(bytes.len() as u64)
        }))
    }

    fn name(&self) -> &'static str {
        match self {
            FileAccess::Bundle => "bundle",
            FileAccess::None => "none",
            FileAccess::Any => "any",
            FileAccess::Host(_) => "host",
        }
    }
}

crate::options::options! {
/// What a load may read, and how much.
#[derive(Clone, Debug)]
pub struct FileOptions {
    /// Which files. Default [`FileAccess::Bundle`].
    pub access: FileAccess = FileAccess::Bundle,
    /// Bytes over all files of one load (the model file, its view file, includes,
    /// functions, curves, surfaces, a prefab). Default [`DEFAULT_MAX_FILE_BYTES`].
    pub max_bytes: u64 = DEFAULT_MAX_FILE_BYTES,
}
}

/// One file read.
pub(crate) struct Loaded {
    /// Who the file is, for include cycles: the canonical path, or the host's path.
    pub(crate) key: PathBuf,
    pub(crate) bytes: Vec<u8>,
}

/// Reads of one load under its policy and budget, with progress (`Stage::Load`).
pub(crate) struct Loader<'p> {
    access: FileAccess,
    /// Folders files may come from (Bundle: canonical; Host: lexical).
    roots: RefCell<Vec<PathBuf>>,
    max: u64,
    used: Cell<u64>,
    progress: RefCell<Option<ProgressFn<'p>>>,
}

/// Reads files named by a model (an `#include`, a view file's companions).
pub(crate) trait Source {
    /// Reads `name`, named by a file in `dir`; `what` says what it is for messages.
    /// `None` when there is no such file: an error of the model's text, which its reader
    /// reports at its line.
    fn read(&self, dir: &Path, name: &str, what: &'static str) -> Result<Option<Loaded>>;
    /// Called every so often by long work while loading: reports progress, may cancel.
    fn tick(&self) -> Result<()>;
}

/// A failed canonicalisation: `None` for a file that does not exist, else an error.
fn canonical(path: &Path, shown: impl std::fmt::Display, what: &str) -> Result<Option<PathBuf>> {
    match std::fs::canonicalize(path) {
        Ok(c) => Ok(Some(c)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(refused(shown, format!("cannot open the {what}: {e}"))),
    }
}

fn not_regular(shown: &str, what: &str) -> Error {
    refused(
        shown,
        format!("the {what} is not a regular file (a folder, device or FIFO is never read)"),
    )
}

/// The path a host's reader is asked for: `path` with `.` and `..` applied.
fn host_path(path: &Path) -> String {
    lexical(path)
        .unwrap_or_else(|| path.to_path_buf())
        .to_string_lossy()
        .into_owned()
}

fn refused(path: impl std::fmt::Display, reason: impl Into<String>) -> Error {
    Error::FileAccess {
        path: path.to_string(),
        reason: reason.into(),
    }
}

/// `path` with `.` removed and `..` applied, without touching the disk; `None` when a
/// `..` climbs above the start.
fn lexical(path: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    let mut depth = 0usize;
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if depth == 0 {
                    return None;
                }
                out.pop();
                depth -= 1;
            }
            Component::Normal(n) => {
                out.push(n);
                depth += 1;
            }
            Component::RootDir | Component::Prefix(_) => {
                out.push(c.as_os_str());
            }
        }
    }
    Some(out)
}

fn is_absolute_name(name: &str) -> bool {
    Path::new(name).has_root()
        || name.starts_with('/')
        || name.starts_with('\\')
        || name.as_bytes().get(1) == Some(&b':')
}

impl<'p> Loader<'p> {
    pub(crate) fn new(options: &FileOptions, progress: Option<ProgressFn<'p>>) -> Self {
        Loader {
            access: options.access.clone(),
            roots: RefCell::new(Vec::new()),
            max: options.max_bytes,
            used: Cell::new(0),
            progress: RefCell::new(progress),
        }
    }

    /// Reports the budget spent so far (never going back), or cancels.
    fn report(&self, fraction: f64) -> Result<()> {
        if let Some(f) = self.progress.borrow_mut().as_mut() {
            let fraction = fraction.clamp(0.0, 1.0) as f32;
            if !f(Stage::Load, fraction) {
                return Err(Error::Cancelled {
                    stage: Stage::Load.name(),
                });
            }
        }
        Ok(())
    }

    fn spent(&self) -> f64 {
        if self.max == 0 {
            0.0
        } else {
            self.used.get() as f64 / self.max as f64
        }
    }

    /// The end of the load: progress 1.
    pub(crate) fn finish(&self) -> Result<()> {
        self.report(1.0)
    }

    /// Reads a file the host named (the model file, or a view file it chose): any
    /// policy reads it (Host through the host's function), and under Bundle its folder
    /// becomes a root files it names may come from.
    pub(crate) fn read_named(&self, path: &Path, what: &'static str) -> Result<Loaded> {
        let absent = || refused(path.display(), format!("no such file (the {what})"));
        match &self.access {
            FileAccess::Host(f) => {
                let shown = host_path(path);
                let loaded = self.host_read(f, &shown, what)?.ok_or_else(absent)?;
                let dir = Path::new(&shown).parent().unwrap_or(Path::new(""));
                self.roots.borrow_mut().push(dir.to_path_buf());
                Ok(loaded)
            }
            _ => {
                let canonical = canonical(path, path.display(), what)?.ok_or_else(absent)?;
                let loaded = self.disk_read(&canonical, &path.display().to_string(), what)?;
                if let Some(dir) = canonical.parent() {
                    self.roots.borrow_mut().push(dir.to_path_buf());
                }
                Ok(loaded)
            }
        }
    }

    /// Whether the host-named optional file exists (the `.v` beside a grammar): under
    /// None it is not looked for.
    pub(crate) fn exists(&self, path: &Path) -> bool {
        match &self.access {
            FileAccess::None => false,
            FileAccess::Host(f) => f(&host_path(path), &mut []).is_some(),
            _ => path.is_file(),
        }
    }

    /// Reads at most the budget plus one byte of a regular file.
    fn disk_read(&self, canonical: &Path, shown: &str, what: &'static str) -> Result<Loaded> {
        let meta = std::fs::metadata(canonical)
            .map_err(|e| refused(shown, format!("cannot open the {what}: {e}")))?;
        if !meta.is_file() {
            return Err(not_regular(shown, what));
        }
        let mut open = std::fs::OpenOptions::new();
        open.read(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt;
            // A file swapped for a FIFO after the check must not block the open.
            open.custom_flags(libc::O_NONBLOCK);
        }
        let file = open
            .open(canonical)
            .map_err(|e| refused(shown, format!("cannot open the {what}: {e}")))?;
        let meta = file
            .metadata()
            .map_err(|e| refused(shown, format!("cannot read the {what}: {e}")))?;
        if !meta.is_file() {
            return Err(not_regular(shown, what));
        }
        let left = self.max.saturating_sub(self.used.get());
        let mut bytes = Vec::new();
        let hint = meta.len().min(left.saturating_add(1));
        bytes
            .try_reserve_exact(usize::try_from(hint).unwrap_or(usize::MAX))
            .map_err(|_| Error::OutOfMemory {
                what: format!("the {what} `{shown}` ({hint} bytes)"),
            })?;
        let mut reader = file.take(left.saturating_add(1));
        // A read buffer the size of the file (4 KiB to 1 MiB): a model's files are small,
        // and zeroing a megabyte for each would cost more than reading them.
        let chunk_len = usize::try_from(hint)
            .unwrap_or(usize::MAX)
            .saturating_add(1)
            .clamp(4096, 1 << 20);
        let mut chunk = vec![0u8; chunk_len];
        loop {
            let n = match reader.read(&mut chunk) {
                Ok(0) => break,
                Ok(n) => n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(refused(shown, format!("cannot read the {what}: {e}"))),
            };
            if bytes.len() as u64 + n as u64 > left {
                return Err(self.over_budget(shown, what, bytes.len() as u64 + n as u64));
            }
            bytes.try_reserve(n).map_err(|_| Error::OutOfMemory {
                what: format!("the {what} `{shown}`"),
            })?;
            bytes.extend_from_slice(&chunk[..n]);
            self.used.set(self.used.get() + n as u64);
            self.report(self.spent())?;
        }
        Ok(Loaded {
            key: canonical.to_path_buf(),
            bytes,
        })
    }

    fn over_budget(&self, shown: &str, what: &str, requested: u64) -> Error {
        Error::FileBudget {
            file: format!("the {what} `{shown}`"),
            limit: self.max,
            requested: self.used.get().saturating_add(requested),
        }
    }

    /// Reads through the host's reader; `None` when it has no such file.
    fn host_read(
        &self,
        f: &Arc<ReadFileFn>,
        shown: &str,
        what: &'static str,
    ) -> Result<Option<Loaded>> {
        let left = self.max.saturating_sub(self.used.get());
        self.report(self.spent())?;
        let first = left.min(64 << 10);
        let mut buffer = Vec::new();
        buffer
            .try_reserve_exact(first as usize)
            .map_err(|_| Error::OutOfMemory {
                what: format!("the {what} `{shown}`"),
            })?;
        buffer.resize(first as usize, 0);
        let Some(size) = f(shown, &mut buffer) else {
            return Ok(None);
        };
        if size > left {
            return Err(self.over_budget(shown, what, size));
        }
        if size > first {
            let n = size as usize;
            buffer
                .try_reserve_exact(n - buffer.len())
                .map_err(|_| Error::OutOfMemory {
                    what: format!("the {what} `{shown}` ({size} bytes)"),
                })?;
            buffer.resize(n, 0);
            let again = f(shown, &mut buffer);
            if again != Some(size) {
                let again = again.map_or_else(|| "no such file".into(), |n| format!("{n} bytes"));
                return Err(refused(
                    shown,
                    format!("the host's read_file said {size} bytes, then {again}"),
                ));
            }
        }
        buffer.truncate(size as usize);
        self.used.set(self.used.get() + size);
        self.report(self.spent())?;
        Ok(Some(Loaded {
            key: PathBuf::from(shown),
            bytes: buffer,
        }))
    }
}

impl Source for Loader<'_> {
    fn read(&self, dir: &Path, name: &str, what: &'static str) -> Result<Option<Loaded>> {
        let policy = self.access.name();
        match &self.access {
            FileAccess::None => {
                return Err(refused(
                    name,
                    format!(
                        "file access is `{policy}`: the model may read no file beyond the one \
                         named (the {what} is not read)"
                    ),
                ));
            }
            FileAccess::Any => {
                return match canonical(&dir.join(name), name, what)? {
                    Some(c) => self.disk_read(&c, name, what).map(Some),
                    None => Ok(None),
                };
            }
            FileAccess::Bundle | FileAccess::Host(_) => {}
        }
        if is_absolute_name(name) {
            return Err(refused(
                name,
                format!(
                    "an absolute path; file access is `{policy}`: the model may read only \
                     files in its own folder"
                ),
            ));
        }
        let roots = self.roots.borrow().clone();
        let dir = match &self.access {
            // Roots on disk are canonical: so is the folder names are resolved in.
            FileAccess::Bundle => std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf()),
            _ => dir.to_path_buf(),
        };
        let joined = lexical(&dir.join(name));
        let inside = |p: &Path| roots.iter().any(|r| p.starts_with(r));
        let Some(joined) = joined.filter(|p| inside(p)) else {
            return Err(refused(
                name,
                format!(
                    "`..` leaves the model's folder; file access is `{policy}`: the model may \
                     read only files in its own folder"
                ),
            ));
        };
        match &self.access {
            FileAccess::Host(f) => {
                let shown = joined.to_string_lossy().into_owned();
                self.host_read(f, &shown, what)
            }
            _ => {
                let Some(canonical) = canonical(&joined, name, what)? else {
                    return Ok(None);
                };
                if !inside(&canonical) {
                    return Err(refused(
                        name,
                        format!(
                            "a symbolic link leading out of the model's folder; file access is \
                             `{policy}`"
                        ),
                    ));
                }
                self.disk_read(&canonical, name, what).map(Some)
            }
        }
    }

    fn tick(&self) -> Result<()> {
        self.report(self.spent())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lexical_paths() {
        assert_eq!(lexical(Path::new("a/./b/../c")), Some(PathBuf::from("a/c")));
        assert_eq!(lexical(Path::new("a/../../c")), None);
        assert_eq!(lexical(Path::new("../c")), None);
        assert!(is_absolute_name("/etc/passwd"));
        assert!(is_absolute_name("C:\\x"));
        assert!(!is_absolute_name("sub/x.h"));
    }
}
