//! Output files that appear whole or not at all.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

/// A file written to a temporary name beside its destination and renamed on [`Self::commit`];
/// dropped without commit, it is deleted, so a failed run leaves no partial output.
pub struct AtomicFile {
    dest: PathBuf,
    tmp: PathBuf,
    writer: Option<BufWriter<File>>,
}

impl AtomicFile {
    /// Creates the temporary file.
    pub fn create(dest: &Path) -> Result<Self> {
        let name = dest
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let tmp = dest.with_file_name(format!(".{name}.edmd-{}.tmp", std::process::id()));
        let file = File::create(&tmp)
            .map_err(|e| crate::UserError(format!("{}: cannot create: {e}", dest.display())))?;
        Ok(AtomicFile {
            dest: dest.to_path_buf(),
            tmp,
            writer: Some(BufWriter::new(file)),
        })
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        self.writer.as_mut().expect("writer present until commit")
    }

    /// The temporary path (for writers that need a file of their own).
    pub fn temp_path(&self) -> &Path {
        &self.tmp
    }

    /// Moves a temporary file written through [`Self::temp_path`] into place.
    pub fn commit_existing(mut self) -> Result<()> {
        let w = self.writer.take().expect("writer present until commit");
        drop(w);
        std::fs::rename(&self.tmp, &self.dest)
            .with_context(|| format!("{}: cannot move into place", self.dest.display()))
    }

    /// Flushes and moves the file into place.
    pub fn commit(mut self) -> Result<()> {
        let mut w = self.writer.take().expect("writer present until commit");
        w.flush()
            .with_context(|| format!("{}: write failed", self.dest.display()))?;
        drop(w);
        std::fs::rename(&self.tmp, &self.dest)
            .with_context(|| format!("{}: cannot move into place", self.dest.display()))
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}
