//! Atomic file output: write beside the target, then rename, so a failed run leaves no partial file.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file being written. Call [`AtomicFile::commit`] to move it into place; dropping it without
/// committing removes the temporary file.
pub struct AtomicFile {
    target: PathBuf,
    temp: PathBuf,
    writer: BufWriter<fs::File>,
    committed: bool,
}

impl AtomicFile {
    /// Creates `.NAME.tmp-PID-N` in the target's directory.
    pub fn create(target: &Path) -> io::Result<AtomicFile> {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let name = target
            .file_name()
            .ok_or_else(|| {
                io::Error::new(io::ErrorKind::InvalidInput, "output path has no file name")
            })?
            .to_string_lossy()
            .into_owned();
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let temp = dir.join(format!(".{name}.tmp-{}-{n}", std::process::id()));
        let file = fs::File::create(&temp)?;
        Ok(AtomicFile {
            target: target.to_path_buf(),
            temp,
            writer: BufWriter::with_capacity(1 << 20, file),
            committed: false,
        })
    }

    pub fn writer(&mut self) -> &mut BufWriter<fs::File> {
        &mut self.writer
    }

    /// Flushes and renames onto the target.
    pub fn commit(mut self) -> io::Result<()> {
        self.writer.flush()?;
        fs::rename(&self.temp, &self.target)?;
        self.committed = true;
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.writer.write(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.writer.flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_file(&self.temp);
        }
    }
}

/// Writes several files so that either all appear or none do (as far as renames allow): each is
/// produced into a temporary file by `produce`, and all are renamed only when every one succeeded.
pub fn write_all_or_none<E: From<io::Error>>(
    targets: &[PathBuf],
    mut produce: impl FnMut(usize, &mut dyn Write) -> Result<(), E>,
) -> Result<(), E> {
    let mut files = Vec::with_capacity(targets.len());
    for (i, t) in targets.iter().enumerate() {
        let mut f = AtomicFile::create(t)?;
        produce(i, &mut f)?;
        f.flush()?;
        files.push(f);
    }
    for f in files {
        f.commit()?;
    }
    Ok(())
}
