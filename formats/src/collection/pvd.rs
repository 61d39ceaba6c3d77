//! `.pvd` (ParaView data collection): `<DataSet timestep= part= file=>` entries; the entries of one
//! time step are merged like blocks, and a plain read gives the first step, as ParaView opens.

use super::merge::merge_blocks;
use super::tags::{self, Kind};
use super::{read_index, read_into, Chain};
use crate::{FormatError, Grid, Result};
use std::path::{Path, PathBuf};

/// One `<DataSet>` of a collection, attributes as written.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    pub file: String,
    pub part: Option<String>,
    pub group: Option<String>,
    pub name: Option<String>,
}

/// One time step: its time (`None` when no entry has a `timestep`) and the entries read for it,
/// in file order. Entries without a `timestep` belong to every step.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    pub time: Option<f64>,
    pub entries: Vec<Entry>,
}

/// Which step to read: `FILE.pvd@K` (0-based, as `tetkit info` lists them) or `FILE.pvd@last`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Selector {
    Index(usize),
    Last,
}

impl Selector {
    /// The 0-based step this selects of `n` steps (`Last` of none is 0; an index is not checked).
    pub fn index_of(self, n: usize) -> usize {
        match self {
            Selector::Index(k) => k,
            Selector::Last => n.saturating_sub(1),
        }
    }
}

/// Splits `FILE.pvd@K` / `FILE.pvd@last` into the file and the step; `None` for any other path.
pub fn split_selector(path: &Path) -> Option<(PathBuf, Selector)> {
    split_step(path, |file| {
        file.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("pvd"))
    })
}

/// Splits `FILE@K` / `FILE@last` into the file and the step when `takes(FILE)` (a format with time
/// steps); `None` otherwise, so a path that merely holds an `@` is left as it is.
pub(crate) fn split_step(
    path: &Path,
    takes: impl Fn(&Path) -> bool,
) -> Option<(PathBuf, Selector)> {
    let s = path.to_str()?;
    let (file, sel) = s.rsplit_once('@')?;
    let file = PathBuf::from(file);
    if !takes(&file) {
        return None;
    }
    let sel = match sel {
        "last" => Selector::Last,
        k => Selector::Index(k.parse().ok()?),
    };
    Some((file, sel))
}

/// The time steps of a .pvd, by increasing time (entries with the same time are one step).
pub fn steps(path: &Path) -> Result<Vec<Step>> {
    let bytes = read_index(path)?;
    let tags = tags::tags(&bytes).map_err(|e| e.with_file(path))?;
    tags::check_root(&tags, &["Collection"]).map_err(|e| e.with_file(path))?;
    let mut timed: Vec<(f64, Entry)> = Vec::new();
    let mut always = Vec::new();
    for t in &tags[1..] {
        if t.name != "DataSet" || t.kind == Kind::Close {
            continue;
        }
        let file = t.get("file").filter(|f| !f.is_empty()).ok_or_else(|| {
            FormatError::at_byte(t.pos, "<DataSet> without a file attribute").with_file(path)
        })?;
        let entry = Entry {
            file: file.to_string(),
            part: t.get("part").map(str::to_string),
            group: t.get("group").map(str::to_string),
            name: t.get("name").map(str::to_string),
        };
        match t.get("timestep").map(str::trim).filter(|s| !s.is_empty()) {
            Some(ts) => {
                let time: f64 = ts
                    .parse()
                    .ok()
                    .filter(|v: &f64| !v.is_nan())
                    .ok_or_else(|| {
                        FormatError::at_byte(t.pos, format!("timestep '{ts}' is not a number"))
                            .with_file(path)
                    })?;
                timed.push((time, entry));
            }
            None => always.push(entry),
        }
    }
    if timed.is_empty() && always.is_empty() {
        return Err(FormatError::whole("no <DataSet> in the collection").with_file(path));
    }
    if timed.is_empty() {
        return Ok(vec![Step {
            time: None,
            entries: always,
        }]);
    }
    // Stable, so the entries of one step keep their file order.
    timed.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<Step> = Vec::new();
    for (time, e) in timed {
        match out.last_mut() {
            Some(s) if s.time == Some(time) => s.entries.push(e),
            _ => out.push(Step {
                time: Some(time),
                entries: always.iter().cloned().chain([e]).collect(),
            }),
        }
    }
    Ok(out)
}

/// Reads step `index` of the .pvd at `path`, its entries merged like the blocks of a .vtm.
pub fn read_step(path: &Path, index: usize) -> Result<Grid> {
    let chain = Chain::default().enter(path)?;
    let all = steps(path)?;
    let step = all.get(index).ok_or_else(|| {
        FormatError::whole(format!(
            "there is no time step {index}: the file has {} (0 to {})",
            all.len(),
            all.len() - 1
        ))
        .with_file(path)
    })?;
    let mut blocks = Vec::new();
    for e in &step.entries {
        let name = e.name.clone().unwrap_or_else(|| match &e.part {
            Some(p) => format!("part {p}"),
            None => e.file.clone(),
        });
        let place = match step.time {
            Some(t) => format!("time step {index} (t={t}) dataset '{}'", e.file),
            None => format!("dataset '{}'", e.file),
        };
        read_into(path, &place, &name, &e.file, &chain, &mut blocks)?;
    }
    let mut g = merge_blocks(path, blocks)?;
    // VTK's XML writers record a data set's time as the field array TimeValue; the merged step
    // says which time it is the same way.
    if let Some(t) = step.time {
        g.field_data.retain(|a| a.name != "TimeValue");
        g.field_data.push(crate::DataArray::new(
            "TimeValue",
            1,
            crate::ArrayData::Float64(vec![t]),
        ));
    }
    Ok(g)
}

/// Reads the step `sel` names.
pub fn read_selected(path: &Path, sel: Selector) -> Result<Grid> {
    let index = match sel {
        Selector::Index(k) => k,
        Selector::Last => sel.index_of(steps(path)?.len()),
    };
    read_step(path, index)
}
