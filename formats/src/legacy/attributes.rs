//! POINT_DATA / CELL_DATA sections (SCALARS, COLOR_SCALARS, LOOKUP_TABLE, VECTORS, NORMALS,
//! TEXTURE_COORDINATES, TENSORS, TENSORS6, GLOBAL_IDS, PEDIGREE_IDS, EDGE_FLAGS, FIELD), FIELD
//! blocks, and the METADATA block that may follow any array.

use super::cursor::{is_kw, show, Cursor};
use super::values::{read_ascii, read_numeric, read_values, LegacyType};
use crate::{ArrayData, Attribute, Attributes, DataArray, FormatError};

/// Field-data name under which an inline `LOOKUP_TABLE name size` block is kept: 4 Float32
/// components (r, g, b, a in 0..1), one tuple per table entry.
pub const LOOKUP_TABLE_PREFIX: &str = "lookup_table:";

/// Reads a data type keyword.
pub(crate) fn read_type(cur: &mut Cursor<'_>, what: &str) -> Result<LegacyType, FormatError> {
    let (p, t) = cur.require(&format!("the data type of {what}"))?;
    LegacyType::parse(&t)
        .ok_or_else(|| cur.err(p, format!("{what}: unknown data type '{}'", show(&t))))
}

/// Reads a (%-encoded) array name.
pub(crate) fn read_name(cur: &mut Cursor<'_>, what: &str) -> Result<String, FormatError> {
    let (p, t) = cur.require(what)?;
    Ok(cur.name(p, &t, true, what))
}

/// Reads `tuples * components` values of `ty`, then any METADATA block, into a named array.
pub(crate) fn read_array(
    cur: &mut Cursor<'_>,
    name: String,
    ty: LegacyType,
    components: usize,
    tuples: usize,
) -> Result<DataArray, FormatError> {
    let at = cur.pos;
    let n = tuples.checked_mul(components).ok_or_else(|| {
        cur.err(
            at,
            format!("array '{name}': {tuples} tuples x {components} components overflows"),
        )
    })?;
    let data = read_numeric(cur, ty, n, &format!("array '{name}'"))?;
    let mut array = DataArray::new(name, components, data);
    array.id_type = matches!(ty, LegacyType::IdType);
    if let Some(names) = read_metadata(cur, components)? {
        array.component_names = names;
    }
    Ok(array)
}

/// A METADATA block after an array: COMPONENT_NAMES (kept, one %-encoded line per component,
/// empty for unnamed ones) and INFORMATION keys (skipped: the data model has no place for
/// them). The block ends at an empty line.
pub(crate) fn read_metadata(
    cur: &mut Cursor<'_>,
    components: usize,
) -> Result<Option<Vec<String>>, FormatError> {
    match cur.peek_keyword("METADATA or the next keyword")? {
        Some((_, t)) if is_kw(&t, "METADATA") => {}
        _ => return Ok(None),
    }
    let here = cur.pos;
    let begin = cur.token().map_or(here, |(p, _)| p);
    cur.line();
    let mut names = Vec::new();
    let mut any = false;
    loop {
        if cur.remaining() == 0 {
            if !any {
                // VTK ends every block with an empty line: a METADATA keyword and then nothing
                // is a file cut after it.
                return Err(cur.err(
                    cur.pos,
                    format!("unexpected end of file after the METADATA keyword at byte {begin} (truncated file)"),
                ));
            }
            break;
        }
        any = true;
        let at = cur.pos;
        let line = cur.line().to_vec();
        let word = line
            .split(|b| b.is_ascii_whitespace())
            .find(|w| !w.is_empty());
        let Some(word) = word else { break };
        if is_kw(word, "COMPONENT_NAMES") {
            names.clear();
            for k in 0..components {
                if cur.remaining() == 0 {
                    return Err(cur.err(
                        cur.pos,
                        format!("METADATA: end of file after {k} of {components} component names"),
                    ));
                }
                let at = cur.pos;
                let line = cur.line().to_vec();
                names.push(cur.name(at, &line, true, &format!("component name {k}")));
            }
        } else if is_kw(word, "INFORMATION") {
            skip_information(cur, at, &line)?;
            break;
        } else if cur.remaining() == 0 && !cur.after_newline() {
            return Err(cur.err(
                at,
                format!(
                    "unexpected end of file in '{}' in a METADATA block (truncated file)",
                    show(&line)
                ),
            ));
        } else {
            return Err(cur.err(
                at,
                format!(
                    "METADATA: expected COMPONENT_NAMES, INFORMATION or an empty line, found '{}'",
                    show(&line)
                ),
            ));
        }
    }
    Ok((names.iter().any(|n| !n.is_empty())).then_some(names))
}

/// Keywords that start a section or an array: met inside an INFORMATION block, they mean the
/// block lacked its closing empty line (a miscounted or hand-written one), and reading on there
/// keeps the array VTK would skip.
const SECTION_KEYWORDS: [&str; 15] = [
    "SCALARS",
    "COLOR_SCALARS",
    "LOOKUP_TABLE",
    "VECTORS",
    "NORMALS",
    "TEXTURE_COORDINATES",
    "TENSORS",
    "TENSORS6",
    "FIELD",
    "GLOBAL_IDS",
    "PEDIGREE_IDS",
    "EDGE_FLAGS",
    "POINT_DATA",
    "CELL_DATA",
    "METADATA",
];

/// Skips the keys of `INFORMATION n` (the line `header`, at byte `at`): each a `NAME ...
/// LOCATION ...` line and its `DATA` (a string vector's strings on lines of their own), to the
/// empty line that ends the METADATA block. The file ending before `n` keys and their data is a
/// cut file, an error; a section keyword before the empty line ends the block there, with a
/// warning.
fn skip_information(cur: &mut Cursor<'_>, at: usize, header: &[u8]) -> Result<(), FormatError> {
    let declared = header
        .split(|b| b.is_ascii_whitespace())
        .filter(|w| !w.is_empty())
        .nth(1)
        .and_then(|w| std::str::from_utf8(w).ok()?.parse::<usize>().ok());
    let (mut names, mut data) = (0usize, 0usize);
    // Whether the last line read ended in a newline (VTK ends every line, and the block with an
    // empty one): one that did not is a file cut inside it.
    let mut whole = true;
    loop {
        if cur.remaining() == 0 {
            let want = declared.unwrap_or(names).max(names);
            if names < want || data < names || !whole {
                return Err(cur.err(
                    cur.pos,
                    format!(
                        "unexpected end of file in the METADATA INFORMATION block begun at byte {at}: {names} of {want} keys named, {data} with their DATA{} (truncated file)",
                        if whole { "" } else { ", the last line cut" }
                    ),
                ));
            }
            return Ok(());
        }
        let start = cur.pos;
        let line = cur.line().to_vec();
        whole = cur.after_newline();
        let Some(word) = line
            .split(|b| b.is_ascii_whitespace())
            .find(|w| !w.is_empty())
        else {
            return Ok(());
        };
        if is_kw(word, "NAME") {
            names += 1;
        } else if is_kw(word, "DATA") {
            data += 1;
        } else if SECTION_KEYWORDS.iter().any(|k| is_kw(word, k)) {
            cur.pos = start;
            crate::warn(&format!(
                "{}: byte {start}: the METADATA INFORMATION block begun at byte {at} ({} keys declared, {names} found) has no empty line before '{}'; read on from there",
                cur.label,
                declared.map_or("no count of".to_string(), |n| n.to_string()),
                show(&line)
            ));
            return Ok(());
        }
    }
}

/// A FIELD block: `FIELD name count`, then per array `name components tuples type` and its
/// values (or `NULL_ARRAY`).
pub(crate) fn read_field(cur: &mut Cursor<'_>) -> Result<Vec<DataArray>, FormatError> {
    let _block = read_name(cur, "the FIELD name")?;
    let count = cur.expect_count("the number of FIELD arrays")?;
    let mut out = Vec::new();
    for _ in 0..count {
        let (p, t) = cur.require("a FIELD array name")?;
        if is_kw(&t, "NULL_ARRAY") {
            continue;
        }
        let name = cur.name(p, &t, true, "a FIELD array name");
        let comps = cur.expect_count(&format!("the component count of FIELD array '{name}'"))?;
        if comps == 0 {
            return Err(cur.err(p, format!("FIELD array '{name}' has 0 components")));
        }
        let tuples = cur.expect_count(&format!("the tuple count of FIELD array '{name}'"))?;
        let ty = read_type(cur, &format!("FIELD array '{name}'"))?;
        out.push(read_array(cur, name, ty, comps, tuples)?);
    }
    Ok(out)
}

/// Reads one attribute section's entries until the next section keyword or the end of the file.
/// `n` is the tuple count the section declared. Lookup tables go to `field` (see
/// [`LOOKUP_TABLE_PREFIX`]).
pub(crate) fn read_section(
    cur: &mut Cursor<'_>,
    n: usize,
    attrs: &mut Attributes,
    field: &mut Vec<DataArray>,
) -> Result<(), FormatError> {
    // The array read last: a number where a keyword should be means it (or its header) is wrong.
    let mut last: Option<String> = None;
    while let Some((p, t)) = cur.peek_keyword("an attribute keyword")? {
        if is_kw(&t, "POINT_DATA") || is_kw(&t, "CELL_DATA") {
            return Ok(());
        }
        cur.token();
        let kw = String::from_utf8_lossy(&t).to_ascii_uppercase();
        let (role, comps) = match kw.as_str() {
            "SCALARS" => {
                let name = read_name(cur, "the SCALARS name")?;
                let ty = read_type(cur, &format!("SCALARS '{name}'"))?;
                let (q, t2) = cur.require("LOOKUP_TABLE or a component count")?;
                let mut comps = 1;
                let mut t2 = t2;
                if !is_kw(&t2, "LOOKUP_TABLE") {
                    comps = super::cursor::parse_count(&t2)
                        .filter(|c| (1..=4).contains(c))
                        .ok_or_else(|| {
                            cur.err(
                                q,
                                format!(
                                    "SCALARS '{name}': component count must be 1..4, found '{}'",
                                    show(&t2)
                                ),
                            )
                        })?;
                    let (q2, t3) = cur.require("LOOKUP_TABLE")?;
                    if !is_kw(&t3, "LOOKUP_TABLE") {
                        return Err(cur.err(
                            q2,
                            format!(
                                "SCALARS '{name}': expected LOOKUP_TABLE, found '{}'",
                                show(&t3)
                            ),
                        ));
                    }
                    t2 = t3;
                }
                let _ = t2;
                let lut = read_name(cur, "the lookup table name")?;
                let array = read_array(cur, name.clone(), ty, comps, n)?;
                if lut != "default" {
                    attrs.lookup_tables.push((name.clone(), lut));
                }
                add(attrs, &mut last, array, Some(Attribute::Scalars));
                continue;
            }
            "COLOR_SCALARS" => {
                let name = read_name(cur, "the COLOR_SCALARS name")?;
                let comps = cur.expect_count("the COLOR_SCALARS component count")?;
                if comps == 0 {
                    return Err(cur.err(p, format!("COLOR_SCALARS '{name}' has 0 components")));
                }
                let total = n
                    .checked_mul(comps)
                    .ok_or_else(|| cur.err(p, "COLOR_SCALARS size overflows"))?;
                let what = format!("COLOR_SCALARS '{name}'");
                // Bytes in binary files, floats in 0..1 in ASCII ones; VTK keeps bytes.
                let data: Vec<u8> = if cur.binary {
                    read_values(cur, total, &what)?
                } else {
                    let f: Vec<f32> = read_values(cur, total, &what)?;
                    f.into_iter()
                        .map(|x| (255.0 * x + 0.5).clamp(0.0, 255.0) as u8)
                        .collect()
                };
                let mut array = DataArray::new(name, comps, ArrayData::UInt8(data));
                if let Some(names) = read_metadata(cur, comps)? {
                    array.component_names = names;
                }
                add(attrs, &mut last, array, Some(Attribute::Scalars));
                continue;
            }
            "LOOKUP_TABLE" => {
                let name = read_name(cur, "the lookup table name")?;
                let size = cur.expect_count("the lookup table size")?;
                let total = size
                    .checked_mul(4)
                    .ok_or_else(|| cur.err(p, "lookup table size overflows"))?;
                let what = format!("LOOKUP_TABLE '{name}'");
                let data: Vec<f32> = if cur.binary {
                    let b: Vec<u8> = read_values(cur, total, &what)?;
                    b.into_iter().map(|x| x as f32 / 255.0).collect()
                } else {
                    read_ascii(
                        cur,
                        total,
                        &what,
                        <f32 as super::values::Value>::parse_ascii,
                    )?
                };
                let array = DataArray::new(
                    format!("{LOOKUP_TABLE_PREFIX}{name}"),
                    4,
                    ArrayData::Float32(data),
                );
                match field.iter_mut().find(|a| a.name == array.name) {
                    Some(slot) => *slot = array,
                    None => field.push(array),
                }
                continue;
            }
            "VECTORS" => (Some(Attribute::Vectors), 3),
            "NORMALS" => (Some(Attribute::Normals), 3),
            "TENSORS" => (Some(Attribute::Tensors), 9),
            "TENSORS6" => (Some(Attribute::Tensors), 6),
            "GLOBAL_IDS" => (Some(Attribute::GlobalIds), 1),
            "PEDIGREE_IDS" => (Some(Attribute::PedigreeIds), 1),
            "EDGE_FLAGS" => (None, 1),
            "TEXTURE_COORDINATES" => {
                let name = read_name(cur, "the TEXTURE_COORDINATES name")?;
                let (q, t2) = cur.require("the texture coordinate dimension")?;
                let dim = super::cursor::parse_count(&t2)
                    .filter(|d| (1..=3).contains(d))
                    .ok_or_else(|| {
                        cur.err(
                            q,
                            format!(
                                "TEXTURE_COORDINATES '{name}': dimension must be 1..3, found '{}'",
                                show(&t2)
                            ),
                        )
                    })?;
                let ty = read_type(cur, &format!("TEXTURE_COORDINATES '{name}'"))?;
                let array = read_array(cur, name, ty, dim, n)?;
                add(attrs, &mut last, array, Some(Attribute::TCoords));
                continue;
            }
            "FIELD" => {
                for array in read_field(cur)? {
                    add(attrs, &mut last, array, None);
                }
                continue;
            }
            _ => {
                // A number, or in a binary file anything unknown: values past the array's end.
                let data =
                    cur.binary || std::str::from_utf8(&t).is_ok_and(|s| s.parse::<f64>().is_ok());
                let hint = match (&last, data) {
                    (Some(a), true) => format!(
                        ": data where a keyword belongs, so array {a} holds more values than its header declares"
                    ),
                    _ => String::new(),
                };
                return Err(cur.err(
                    p,
                    format!(
                        "unknown keyword '{}' in a POINT_DATA/CELL_DATA section{hint}",
                        show(&t)
                    ),
                ));
            }
        };
        let name = read_name(cur, &format!("the {kw} name"))?;
        let ty = read_type(cur, &format!("{kw} '{name}'"))?;
        let array = read_array(cur, name, ty, comps, n)?;
        add(attrs, &mut last, array, role);
    }
    Ok(())
}

/// Adds an array; the first array of each role becomes the active one, as in VTK. An array
/// whose name an earlier one has is kept too (VTK would replace the earlier one): the common
/// read path renames it.
fn add(
    attrs: &mut Attributes,
    last: &mut Option<String>,
    array: DataArray,
    role: Option<Attribute>,
) {
    *last = Some(format!(
        "'{}' ({} tuples of {})",
        array.name,
        array.tuples(),
        array.components
    ));
    if let Some(role) = role {
        if !attrs.active.iter().any(|(r, _)| *r == role) {
            attrs.active.push((role, array.name.clone()));
        }
    }
    attrs.arrays.push(array);
}
