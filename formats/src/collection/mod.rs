//! VTK XML collections: `.vtm` multiblocks and `.pvd` time series, merged into one grid.
//!
//! Both name other files (paths relative to themselves); the datasets they reach are read by the
//! readers of their own format and merged in order by [`merge`], as ParaView's Merge Blocks does.

mod merge;
pub mod pvd;
mod tags;
pub mod vtm;

pub use merge::{BLOCK_ID_ARRAY, BLOCK_NAMES_ARRAY};

use crate::{FormatError, Grid, Place, Result};
use merge::Block;
use std::path::{Path, PathBuf};

/// How deep collections may name collections (a .vtm naming a .vtm...): far past what any
/// writer makes, and short of a stack overflow on a hostile chain.
const MAX_DEPTH: usize = 16;

pub(crate) use crate::warn;

/// The collections being read, outermost first, to refuse a file that names itself or an
/// enclosing one.
#[derive(Default)]
pub(crate) struct Chain(Vec<PathBuf>);

impl Chain {
    /// `path` pushed, or an error when it is already open (a cycle) or too deep.
    fn enter(&self, path: &Path) -> Result<Chain> {
        let canon = path.canonicalize().map_err(|e| FormatError::io(path, e))?;
        if let Some(outer) = self.0.iter().find(|p| **p == canon) {
            return Err(FormatError::whole(format!(
                "refers back to '{}', which is being read (a cycle)",
                outer.display()
            ))
            .with_file(path));
        }
        if self.0.len() >= MAX_DEPTH {
            return Err(FormatError::whole(format!(
                "collections nested more than {MAX_DEPTH} deep"
            ))
            .with_file(path));
        }
        let mut next = self.0.clone();
        next.push(canon);
        Ok(Chain(next))
    }
}

/// What kind of data set a file of this extension holds, as far as merging goes.
enum Kind {
    /// An unstructured grid, polydata or structured data set tetkit reads into a [`Grid`].
    Mesh,
    /// A .pvtu, or parallel structured data (.pvti, .pvtr, .pvts).
    Pvtu,
    Legacy,
    Vtm,
    Pvd,
    /// Parallel polydata, AMR or other VTK data tetkit does not read: skipped.
    Other(&'static str),
}

fn kind(path: &Path) -> Option<Kind> {
    let ext = path.extension()?.to_string_lossy().to_ascii_lowercase();
    Some(match ext.as_str() {
        "vtu" | "vtp" | "vti" | "vtr" | "vts" => Kind::Mesh,
        "pvtu" | "pvti" | "pvtr" | "pvts" => Kind::Pvtu,
        "vtk" => Kind::Legacy,
        "vtm" | "vtmb" => Kind::Vtm,
        "pvd" => Kind::Pvd,
        "pvtp" => Kind::Other("parallel polydata"),
        "vthb" | "vth" => Kind::Other("an AMR data set"),
        "vtpc" | "vtpd" => Kind::Other("a partitioned data set"),
        "vtt" => Kind::Other("a table"),
        _ => return None,
    })
}

/// The `DATASET` kind a legacy file's header names (`UNSTRUCTURED_GRID`, `POLYDATA`...).
fn legacy_dataset(path: &Path) -> Result<Option<String>> {
    let head = crate::read_head(path)?;
    let text = String::from_utf8_lossy(&head);
    Ok(text.lines().take(8).find_map(|l| {
        let mut w = l.split_whitespace();
        (w.next()?.eq_ignore_ascii_case("DATASET")).then(|| w.next().unwrap_or("").to_uppercase())
    }))
}

/// A data set named by `referrer` at `place` (`block 'solid'`), read and appended to `out` as
/// blocks: one for a mesh, a .pvtu (merged) or a skipped file, the leaves of a .vtm.
/// `file` is the attribute as written; it is resolved against the referrer's folder.
pub(crate) fn read_into(
    referrer: &Path,
    place: &str,
    name: &str,
    file: &str,
    chain: &Chain,
    out: &mut Vec<Block>,
) -> Result<()> {
    let dir = referrer.parent().unwrap_or(Path::new(""));
    let path = dir.join(file);
    let at =
        |msg: String| FormatError::new(Place::Other(place.to_string()), msg).with_file(referrer);
    if !path.is_file() {
        return Err(at(format!(
            "file '{}' ({file}) does not exist or is not a file",
            path.display()
        )));
    }
    let label = format!("{place} ('{}')", path.display());
    // The block's own error names its file and place; the referrer and block are put in front.
    let wrap = |e: FormatError| at(e.to_string());
    let grid = match kind(&path) {
        None => {
            return Err(at(format!(
                "'{}' is not a VTK data file tetkit knows (.vtu, .vtp, .vti, .vtr, .vts, .pvtu, .vtk, .vtm)",
                path.display()
            )))
        }
        Some(Kind::Vtm) => {
            let inner = chain.enter(&path).map_err(wrap)?;
            let prefix = format!("{name}/");
            let start = out.len();
            vtm::leaves(&path, &inner, out).map_err(wrap)?;
            for b in &mut out[start..] {
                b.name.insert_str(0, &prefix);
            }
            return Ok(());
        }
        Some(Kind::Pvd) => {
            chain.enter(&path).map_err(wrap)?;
            return Err(at(format!(
                "'{}' is a .pvd; a collection may name .vtm files but not time series",
                path.display()
            )));
        }
        Some(Kind::Other(what)) => {
            warn(&format!(
                "{}: {place}: '{}' is {what}, which tetkit does not read; block skipped (no cells)",
                referrer.display(),
                path.display()
            ));
            None
        }
        Some(Kind::Mesh) => Some(crate::vtu::read_path(&path).map_err(wrap)?),
        Some(Kind::Pvtu) => {
            let bytes = std::fs::read(&path).map_err(|e| wrap(FormatError::io(&path, e)))?;
            Some(crate::vtu::pvtu::read(&path, &bytes).map_err(wrap)?)
        }
        Some(Kind::Legacy) => match legacy_dataset(&path).map_err(wrap)?.as_deref() {
            Some(
                "UNSTRUCTURED_GRID" | "POLYDATA" | "STRUCTURED_POINTS" | "STRUCTURED_GRID"
                | "RECTILINEAR_GRID",
            ) => {
                Some(crate::legacy::read_path(&path).map_err(wrap)?)
            }
            other => {
                warn(&format!(
                    "{}: {place}: '{}' is a legacy {} data set, which tetkit does not read; block skipped (no cells)",
                    referrer.display(),
                    path.display(),
                    other.unwrap_or("(unknown)")
                ));
                None
            }
        },
    };
    if let Some(g) = &grid {
        g.validate()
            .map_err(|m| at(format!("'{}': invalid mesh: {m}", path.display())))?;
    }
    out.push(Block {
        name: name.to_string(),
        label,
        grid,
    });
    Ok(())
}

/// Reads a collection file's bytes, refusing one that is not there with its name.
fn read_index(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|e| FormatError::io(path, e))
}

/// Reads a `.vtm` and merges its leaves; see [`vtm`].
pub fn read_vtm(path: &Path) -> Result<Grid> {
    let chain = Chain::default().enter(path)?;
    let mut blocks = Vec::new();
    vtm::leaves(path, &chain, &mut blocks)?;
    merge::merge_blocks(path, blocks)
}
