//! Where an array's bytes come from: decoded inline text in memory, or a span of the appended
//! block read in place (from memory or straight from the file with positioned reads, so a large
//! file is never held twice).

use std::borrow::Cow;
use std::io;

/// Random-access bytes that several threads may read at once.
pub(crate) trait Blob: Sync {
    fn len(&self) -> u64;
    fn read_at(&self, off: u64, buf: &mut [u8]) -> io::Result<()>;
    /// The whole blob, when it is already in memory.
    fn memory(&self) -> Option<&[u8]> {
        None
    }
}

/// A whole file already in memory.
pub(crate) struct MemBlob<'a>(pub &'a [u8]);

impl Blob for MemBlob<'_> {
    fn len(&self) -> u64 {
        self.0.len() as u64
    }
    fn read_at(&self, off: u64, buf: &mut [u8]) -> io::Result<()> {
        let start = usize::try_from(off).map_err(|_| short())?;
        let end = start.checked_add(buf.len()).ok_or_else(short)?;
        let src = self.0.get(start..end).ok_or_else(short)?;
        buf.copy_from_slice(src);
        Ok(())
    }
    fn memory(&self) -> Option<&[u8]> {
        Some(self.0)
    }
}

fn short() -> io::Error {
    io::Error::new(
        io::ErrorKind::UnexpectedEof,
        "read past the end of the file",
    )
}

/// A file read with positioned reads (`pread`), which threads may issue in parallel.
pub(crate) struct FileBlob {
    pub file: std::fs::File,
    pub len: u64,
}

impl Blob for FileBlob {
    fn len(&self) -> u64 {
        self.len
    }
    #[cfg(unix)]
    fn read_at(&self, off: u64, buf: &mut [u8]) -> io::Result<()> {
        use std::os::unix::fs::FileExt;
        match off.checked_add(buf.len() as u64) {
            Some(e) if e <= self.len => {}
            _ => return Err(short()),
        }
        self.file.read_exact_at(buf, off)
    }
    #[cfg(not(unix))]
    fn read_at(&self, off: u64, buf: &mut [u8]) -> io::Result<()> {
        use std::io::{Read, Seek, SeekFrom};
        match off.checked_add(buf.len() as u64) {
            Some(e) if e <= self.len => {}
            _ => return Err(short()),
        }
        let mut f = &self.file;
        f.seek(SeekFrom::Start(off))?;
        f.read_exact(buf)
    }
}

/// The bytes of one binary array (header and data): `[start, end)` of a blob, with `file_pos` the
/// file offset of `start` (for error messages).
#[derive(Clone, Copy)]
pub(crate) enum Src<'a> {
    Mem(&'a [u8]),
    Blob(&'a dyn Blob),
}

#[derive(Clone, Copy)]
pub(crate) struct Region<'a> {
    pub blob: Src<'a>,
    pub start: u64,
    pub end: u64,
    pub file_pos: u64,
}

impl<'a> Region<'a> {
    pub fn in_memory(bytes: &'a [u8], file_pos: u64) -> Region<'a> {
        Region {
            blob: Src::Mem(bytes),
            start: 0,
            end: bytes.len() as u64,
            file_pos,
        }
    }

    pub fn len(&self) -> u64 {
        self.end - self.start
    }

    /// File offset of relative position `rel`.
    pub fn pos(&self, rel: u64) -> u64 {
        self.file_pos.saturating_add(rel)
    }

    /// Reads `buf.len()` bytes at relative position `rel`, which the caller has checked lie inside.
    pub fn read_at(&self, rel: u64, buf: &mut [u8]) -> io::Result<()> {
        let in_range = rel
            .checked_add(buf.len() as u64)
            .is_some_and(|e| e <= self.len());
        if !in_range {
            return Err(short());
        }
        match self.blob {
            Src::Mem(m) => MemBlob(m).read_at(self.start + rel, buf),
            Src::Blob(b) => b.read_at(self.start + rel, buf),
        }
    }

    /// `len` bytes at `rel`, borrowed when the blob is memory.
    pub fn bytes(&self, rel: u64, len: usize) -> io::Result<Cow<'a, [u8]>> {
        let mem = match self.blob {
            Src::Mem(m) => Some(m),
            Src::Blob(b) => b.memory(),
        };
        if let Some(m) = mem {
            let s = self.start.checked_add(rel).ok_or_else(short)?;
            let e = s.checked_add(len as u64).ok_or_else(short)?;
            if e > self.end {
                return Err(short());
            }
            return Ok(Cow::Borrowed(&m[s as usize..e as usize]));
        }
        let mut v = vec![0u8; len];
        self.read_at(rel, &mut v)?;
        Ok(Cow::Owned(v))
    }
}
