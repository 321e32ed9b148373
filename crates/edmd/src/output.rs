//! Output files that appear whole or not at all, and the checks that keep outputs off inputs.
//!
//! A regular file (or a new one) is written under a temporary name beside it and renamed into
//! place on [`AtomicFile::commit`]. A symbolic link is followed: its target is written that
//! way and the link stays. A device or a FIFO (`/dev/null`, `/dev/full`, a named pipe) cannot
//! be replaced by a file, so it is written directly. Every temporary file or folder is
//! registered, so that the signal handler can remove them before the program ends, and every
//! error path removes them on drop.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::Result;

use crate::UserError;

/// Temporary files and folders alive now (removed by [`remove_temporaries`] on a signal).
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Registers a temporary file or folder for removal on a signal.
pub fn register_temporary(p: &Path) {
    if let Ok(mut t) = TEMPORARIES.lock() {
        t.push(p.to_path_buf());
    }
}

/// Forgets a temporary file or folder (it was renamed into place or removed).
pub fn unregister_temporary(p: &Path) {
    if let Ok(mut t) = TEMPORARIES.lock() {
        t.retain(|q| q != p);
    }
}

/// Removes every registered temporary file and folder (called before the program ends on a
/// signal, when no destructor runs).
pub fn remove_temporaries() {
    if let Ok(mut t) = TEMPORARIES.try_lock() {
        for p in t.drain(..) {
            if p.is_dir() {
                let _ = std::fs::remove_dir_all(&p);
            } else {
                let _ = std::fs::remove_file(&p);
            }
        }
    }
}

/// Follows a chain of symbolic links to the path they end at (which need not exist).
pub fn resolve_links(path: &Path) -> PathBuf {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::read_link(&p) {
            Ok(target) => {
                p = if target.is_absolute() {
                    target
                } else {
                    p.parent().unwrap_or(Path::new(".")).join(target)
                };
            }
            Err(_) => break,
        }
    }
    p
}

/// True for a path that exists and is neither a regular file nor a folder (a device, a FIFO, a
/// socket): it is written in place.
fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// A write error, as a user error naming the file (exit status 2).
fn write_error(dest: &Path, e: std::io::Error) -> std::io::Error {
    std::io::Error::other(UserError(format!("{}: cannot write: {e}", dest.display())))
}

/// An output file. See the module documentation.
pub struct AtomicFile {
    dest: PathBuf,
    /// The temporary file, for a regular destination; `None` for a device or FIFO.
    tmp: Option<PathBuf>,
    writer: Option<BufWriter<File>>,
}

impl AtomicFile {
    /// Opens the output: creates the temporary file, or opens a device or FIFO.
    pub fn create(dest: &Path) -> Result<Self> {
        let target = resolve_links(dest);
        let fail = |e: std::io::Error| UserError(format!("{}: cannot create: {e}", dest.display()));
        if target.is_dir() {
            return Err(UserError(format!("{}: is a folder, not a file", dest.display())).into());
        }
        if is_special(&target) {
            let file = OpenOptions::new().write(true).open(&target).map_err(fail)?;
            return Ok(AtomicFile {
                dest: dest.to_path_buf(),
                tmp: None,
                writer: Some(BufWriter::new(file)),
            });
        }
        let name = target
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let tmp = target.with_file_name(format!(".{name}.edmd-{}.tmp", std::process::id()));
        register_temporary(&tmp);
        let file = match File::create(&tmp) {
            Ok(f) => f,
            Err(e) => {
                unregister_temporary(&tmp);
                return Err(fail(e).into());
            }
        };
        if let Ok(m) = std::fs::metadata(&target) {
            // Keep the permissions of the file being replaced.
            let _ = std::fs::set_permissions(&tmp, m.permissions());
        }
        Ok(AtomicFile {
            dest: target,
            tmp: Some(tmp),
            writer: Some(BufWriter::with_capacity(1 << 16, file)),
        })
    }

    /// The writer (this file itself; write errors name the file).
    pub fn writer(&mut self) -> &mut Self {
        self
    }

    /// The temporary path, for a program that writes the file itself (`None`: the destination is
    /// a device or FIFO, written in place).
    pub fn temp_path(&self) -> Option<&Path> {
        self.tmp.as_deref()
    }

    /// The path written in the end (symbolic links followed).
    pub fn target(&self) -> &Path {
        &self.dest
    }

    /// Moves a temporary file that another program wrote through [`Self::temp_path`] into place.
    pub fn commit_existing(mut self) -> Result<()> {
        if let Some(w) = self.writer.take() {
            let _ = w.into_parts();
        }
        self.move_into_place()
    }

    /// Renames the temporary file (if there is one) onto the destination.
    fn move_into_place(&mut self) -> Result<()> {
        if let Some(tmp) = &self.tmp {
            std::fs::rename(tmp, &self.dest).map_err(|e| {
                UserError(format!(
                    "{}: cannot move into place: {e}",
                    self.dest.display()
                ))
            })?;
            unregister_temporary(tmp);
            self.tmp = None;
        }
        Ok(())
    }

    /// Flushes and moves the file into place.
    pub fn commit(mut self) -> Result<()> {
        let mut w = self.writer.take().expect("writer present until commit");
        w.flush().map_err(|e| write_error(&self.dest, e))?;
        let file = w
            .into_inner()
            .map_err(|e| write_error(&self.dest, e.into_error()))?;
        if self.tmp.is_some() {
            file.sync_all().map_err(|e| write_error(&self.dest, e))?;
        }
        drop(file);
        self.move_into_place()
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let w = self.writer.as_mut().expect("writer present until commit");
        w.write(buf).map_err(|e| write_error(&self.dest, e))
    }

    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        let w = self.writer.as_mut().expect("writer present until commit");
        w.write_all(buf).map_err(|e| write_error(&self.dest, e))
    }

    fn flush(&mut self) -> std::io::Result<()> {
        // The real flush happens in `commit`; flushing a temporary file early gains nothing.
        Ok(())
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // Not committed (an error, or the rename failed): the temporary file goes, and what a
        // device or FIFO has not yet received is discarded rather than flushed.
        if let Some(w) = self.writer.take() {
            let _ = w.into_parts();
        }
        if let Some(tmp) = self.tmp.take() {
            let _ = std::fs::remove_file(&tmp);
            unregister_temporary(&tmp);
        }
    }
}

/// What identifies a file: device and inode when it exists, else its absolute path with the
/// links followed (a file about to be created).
#[derive(Debug, Clone, PartialEq, Eq)]
enum Identity {
    Inode(u64, u64),
    Path(PathBuf),
}

fn identity(path: &Path) -> Identity {
    use std::os::unix::fs::MetadataExt;
    if let Ok(m) = std::fs::metadata(path) {
        return Identity::Inode(m.dev(), m.ino());
    }
    let target = resolve_links(path);
    let parent = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let parent = std::fs::canonicalize(&parent).unwrap_or_else(|_| lexical_absolute(&parent));
    Identity::Path(parent.join(target.file_name().unwrap_or_default()))
}

/// `path` made absolute without touching the file system (`.` dropped, `..` taken back).
fn lexical_absolute(path: &Path) -> PathBuf {
    use std::path::Component;
    let abs = std::env::current_dir().unwrap_or_default().join(path);
    let mut out = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// Refuses (exit status 2, before any work) an output file that cannot be written where it is
/// named: a name ending in `/` or naming a folder, or one in a folder that does not exist.
/// Each entry is `(what, path)`; `-` and devices are skipped. Checked at the start because
/// some outputs are first written late (a checkpoint when it falls due, a file once the run
/// is over), and a run's work should not be lost to a name that could never be written.
pub fn check_file_destinations(outputs: &[(&str, &Path)]) -> Result<()> {
    for &(what, path) in outputs {
        if path.as_os_str() == "-" || is_special(path) {
            continue;
        }
        let refuse =
            |why: String| Err(UserError(format!("{}: {what} {why}", path.display())).into());
        if path.as_os_str().as_encoded_bytes().ends_with(b"/") || resolve_links(path).is_dir() {
            return refuse("names a folder; give a file name".to_string());
        }
        let parent = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        if !parent.is_dir() {
            return refuse(format!(
                "is in a folder that does not exist ({})",
                parent.display()
            ));
        }
    }
    Ok(())
}

/// Refuses (exit status 2, before any work) a folder for output files that exists as
/// something else (a file), or that cannot be made (inside a file, or where the user may not
/// write): a folder that does not exist is made and removed again here, with any folders above
/// it that this made, so that the run's work is not lost to a folder made only at its end.
pub fn check_folder_destination(what: &str, dir: &Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        return Err(UserError(format!(
            "{}: {what} names a file, not a folder; give a folder (it is made if it does not exist)",
            dir.display()
        ))
        .into());
    }
    if dir.exists() {
        return Ok(());
    }
    let missing = missing_folders(dir);
    let made = std::fs::create_dir_all(dir);
    for p in missing {
        let _ = std::fs::remove_dir(p);
    }
    made.map_err(|e| {
        UserError(format!(
            "{}: {what}: the folder cannot be made: {e}",
            dir.display()
        ))
        .into()
    })
}

/// The folders that making `dir` would make: `dir` and those above it that do not exist,
/// the deepest first.
pub fn missing_folders(dir: &Path) -> Vec<PathBuf> {
    let mut missing = Vec::new();
    let mut at = Some(dir);
    while let Some(p) = at.filter(|p| !p.as_os_str().is_empty() && !p.exists()) {
        missing.push(p.to_path_buf());
        at = p.parent();
    }
    missing
}

/// Refuses (exit status 2, before any work) when an output is one of the inputs or two outputs
/// are the same file. Each entry is `(what, path)`, e.g. `("--trajectory", "t.xyz")`; `-`
/// (standard input or output) is skipped, and so are character devices (`/dev/null`), which
/// several outputs may share.
pub fn check_distinct(inputs: &[(&str, &Path)], outputs: &[(&str, &Path)]) -> Result<()> {
    use std::os::unix::fs::FileTypeExt;
    let skip = |p: &Path| {
        p.as_os_str() == "-" || std::fs::metadata(p).is_ok_and(|m| m.file_type().is_char_device())
    };
    let ins: Vec<(&str, &Path, Identity)> = inputs
        .iter()
        .filter(|(_, p)| !skip(p))
        .map(|&(w, p)| (w, p, identity(p)))
        .collect();
    let outs: Vec<(&str, &Path, Identity)> = outputs
        .iter()
        .filter(|(_, p)| !skip(p))
        .map(|&(w, p)| (w, p, identity(p)))
        .collect();
    for (k, (what, path, id)) in outs.iter().enumerate() {
        if let Some((iw, ip, _)) = ins.iter().find(|(_, _, i)| i == id) {
            return Err(UserError(format!(
                "{}: {what} would overwrite the input {} ({iw}); choose another name",
                path.display(),
                ip.display()
            ))
            .into());
        }
        if let Some((ow, _, _)) = outs[..k].iter().find(|(_, _, i)| i == id) {
            return Err(UserError(format!(
                "{}: {what} and {ow} name the same file; choose another name",
                path.display()
            ))
            .into());
        }
    }
    Ok(())
}

/// Writes a CSV file (header line, then one row per record), whole or not at all. A NaN, a
/// value that does not exist (no reference at that point, an error from one block), is an
/// empty cell, which spreadsheets and pandas read as missing, as the JSON's `null` is.
pub fn write_csv(
    path: &Path,
    header: &[&str],
    rows: impl IntoIterator<Item = Vec<f64>>,
) -> Result<()> {
    let mut f = AtomicFile::create(path)?;
    let w = f.writer();
    writeln!(w, "{}", header.join(","))?;
    for row in rows {
        let cells: Vec<String> = row
            .iter()
            .map(|x| {
                if x.is_nan() {
                    String::new()
                } else {
                    format!("{x:?}")
                }
            })
            .collect();
        writeln!(w, "{}", cells.join(","))?;
    }
    f.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value that does not exist is an empty cell, not `NaN`.
    #[test]
    fn csv_cells_without_a_value_are_empty() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        let rows = vec![vec![1.0, f64::NAN, 0.1], vec![f64::INFINITY, 2.0, f64::NAN]];
        write_csv(&path, &["a", "b", "c"], rows).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, "a,b,c\n1.0,,0.1\ninf,2.0,\n");
    }

    /// Regression: a failed final rename left its temporary file behind.
    #[test]
    fn failed_rename_removes_the_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let dest = dir.path().join("out.txt");
        let mut f = AtomicFile::create(&dest).unwrap();
        f.write_all(b"state\n").unwrap();
        // A folder appears where the file should go: the rename fails.
        std::fs::create_dir(&dest).unwrap();
        std::fs::write(dest.join("keep"), "x").unwrap();
        let e = f.commit().unwrap_err();
        assert!(format!("{e}").contains("cannot move into place"), "{e}");
        let mut left: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, ["out.txt"]);
        assert!(TEMPORARIES.lock().unwrap().is_empty());
    }

    /// Outputs are compared by identity, not spelling.
    #[test]
    fn the_same_file_spelled_two_ways_is_caught() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.txt");
        std::fs::write(&a, "x").unwrap();
        let b = dir.path().join("sub/../a.txt");
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        assert!(check_distinct(&[("in", &a)], &[("out", &b)]).is_err());
        let n1 = dir.path().join("new.txt");
        let n2 = dir.path().join("./new.txt");
        assert!(check_distinct(&[], &[("one", &n1), ("two", &n2)]).is_err());
        assert!(check_distinct(&[("in", &a)], &[("out", &n1)]).is_ok());
    }
}
