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
        let temp = hidden_sibling(target, "tmp")?;
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

/// `.NAME.TAG-PID-N` beside `target`: a name no other run or file uses.
fn hidden_sibling(target: &Path, tag: &str) -> io::Result<PathBuf> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = target
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "output path has no file name"))?
        .to_string_lossy()
        .into_owned();
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    Ok(dir.join(format!(".{name}.{tag}-{}-{n}", std::process::id())))
}

/// `target` with its folder resolved (symbolic links, `.` and `..`), so that two spellings of
/// one file compare equal; as given when its folder cannot be resolved.
fn resolve(target: &Path) -> PathBuf {
    if let Ok(p) = target.canonicalize() {
        return p;
    }
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match (dir.canonicalize(), target.file_name()) {
        (Ok(d), Some(name)) => d.join(name),
        _ => target.to_path_buf(),
    }
}

/// An I/O failure on one of the files [`write_all_or_none`] places, naming that file (the
/// caller only knows the group: `x.ele` for `x.node` + `x.ele` + `x.face`).
#[derive(Debug)]
pub struct TargetError {
    pub path: PathBuf,
    pub source: io::Error,
}

impl std::fmt::Display for TargetError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.source)
    }
}

/// No `source`: the message already ends with the I/O error, and a report that walks the
/// chain (anyhow's) would print it twice.
impl std::error::Error for TargetError {}

/// Writes several files so that either all appear or none do: each is produced into a temporary
/// file by `produce`, and only when every one succeeded are they moved into place. A file they
/// replace is first moved aside, so a target that cannot be placed (a folder in the way) puts
/// back every file already placed, and what was there before, instead of leaving a mix.
pub fn write_all_or_none<E: From<TargetError>>(
    targets: &[PathBuf],
    mut produce: impl FnMut(usize, &mut dyn Write) -> Result<(), E>,
) -> Result<(), E> {
    let at = |path: &Path| {
        let path = path.to_path_buf();
        move |source| TargetError { path, source }
    };
    // Found before any work: a folder cannot be replaced by a file.
    if let Some(t) = targets.iter().find(|t| t.is_dir()) {
        return Err(at(t)(io::Error::other("a folder of that name is in the way")).into());
    }
    // Two outputs named as one file (`-o x.vtu --tree x.vtu`, or `./x.vtu` and `x.vtu`): the
    // second placed would silently replace the first.
    let resolved: Vec<PathBuf> = targets.iter().map(|t| resolve(t)).collect();
    for (j, r) in resolved.iter().enumerate() {
        if let Some(i) = resolved[..j].iter().position(|q| q == r) {
            return Err(at(&targets[j])(io::Error::other(format!(
                "this is also the output {}: two outputs cannot share one file",
                targets[i].display()
            )))
            .into());
        }
    }
    let mut files = Vec::with_capacity(targets.len());
    for (i, t) in targets.iter().enumerate() {
        let mut f = AtomicFile::create(t).map_err(at(t))?;
        produce(i, &mut f)?;
        f.flush().map_err(at(t))?;
        files.push(f);
    }
    // (target, where its previous file waits) for every file placed so far.
    let mut placed: Vec<(PathBuf, Option<PathBuf>)> = Vec::with_capacity(files.len());
    for f in files {
        let target = f.target.clone();
        let step = (|| -> io::Result<Option<PathBuf>> {
            let old = if fs::symlink_metadata(&target).is_ok() {
                let aside = hidden_sibling(&target, "old")?;
                fs::rename(&target, &aside)?;
                Some(aside)
            } else {
                None
            };
            if let Err(e) = f.commit() {
                if let Some(aside) = &old {
                    let _ = fs::rename(aside, &target);
                }
                return Err(e);
            }
            Ok(old)
        })();
        match step {
            Ok(old) => placed.push((target, old)),
            Err(e) => {
                for (t, old) in placed.into_iter().rev() {
                    let _ = fs::remove_file(&t);
                    if let Some(aside) = old {
                        let _ = fs::rename(aside, &t);
                    }
                }
                return Err(at(&target)(e).into());
            }
        }
    }
    for (_, old) in placed {
        if let Some(aside) = old {
            let _ = fs::remove_file(aside);
        }
    }
    Ok(())
}
