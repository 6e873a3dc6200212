//! Files written whole or not at all: into a temporary file beside the target, flushed to
//! disk, then renamed over it. A failure (disk full, a file too large, a folder that cannot
//! be written) or a cancel removes the temporary file and leaves an existing target as it
//! was; only a killed process can leave the temporary file behind, named
//! `.NAME.arbor-PID-N.tmp` so a user recognises it.

use crate::error::{Error, Result};
use crate::progress::{Run, Stage};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// The temporary file a write of `path` uses (unique in this process).
fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "export".into(), |n| n.to_string_lossy().into_owned());
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let file = format!(".{name}.arbor-{}-{n}.tmp", std::process::id());
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.join(file),
        _ => PathBuf::from(file),
    }
}

/// An I/O error that names `path`.
pub(crate) fn io(path: &Path, doing: &str, e: std::io::Error) -> Error {
    Error::Io(std::io::Error::new(
        e.kind(),
        format!("cannot {doing} {}: {e}", path.display()),
    ))
}

/// Writes `path` through `fill`, atomically: `fill` writes into a temporary file in the
/// same folder (reporting [`Stage::Write`] through the progress it is given, if it likes);
/// on success it is flushed, `progress` is asked once more (`Stage::Write`, 1) and the
/// file is synced and renamed over `path`; on any error or cancel it is removed and
/// `path` is untouched.
pub(crate) fn write_atomic(
    path: &Path,
    progress: &mut Run<'_>,
    fill: impl FnOnce(&mut std::io::BufWriter<&std::fs::File>, &mut Run<'_>) -> Result<()>,
) -> Result<()> {
    // A device, FIFO or folder of that name is never replaced (nor written through).
    if let Ok(meta) = std::fs::symlink_metadata(path) {
        if !meta.is_file() {
            return Err(io(
                path,
                "write",
                std::io::Error::other("it exists and is not a regular file"),
            ));
        }
    }
    let tmp = temporary(path);
    let file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .map_err(|e| io(path, "write", e))?;
    let result = (|| {
        let mut w = std::io::BufWriter::with_capacity(1 << 16, &file);
        fill(&mut w, progress)?;
        w.flush().map_err(|e| io(path, "write", e))?;
        drop(w);
        progress.report(Stage::Write, 1.0)?;
        file.sync_all().map_err(|e| io(path, "write", e))?;
        std::fs::rename(&tmp, path).map_err(|e| io(path, "replace", e))
    })();
    drop(file);
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let dir = std::env::temp_dir().join(format!("arbor-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("tree.obj");
        std::fs::write(&target, "old").unwrap();
        let r = write_atomic(&target, &mut Run::default(), |w, _| {
            w.write_all(b"half of a new fi").unwrap();
            Err(Error::Cancelled { stage: "mesh" })
        });
        assert!(matches!(r, Err(Error::Cancelled { .. })));
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "old");
        // A whole file, cancelled at the last moment before it replaces the target.
        let mut stop = |_: Stage, _: f32| false;
        let r = write_atomic(&target, &mut Run::reporting(&mut stop), |w, _| {
            w.write_all(b"new").map_err(Error::Io)
        });
        assert!(matches!(r, Err(Error::Cancelled { .. })));
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "old");
        write_atomic(&target, &mut Run::default(), |w, _| {
            w.write_all(b"new").map_err(Error::Io)?;
            Ok(())
        })
        .unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left, vec![std::ffi::OsString::from("tree.obj")], "{left:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
