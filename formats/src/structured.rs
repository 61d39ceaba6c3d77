//! Structured data sets (image data, rectilinear and curvilinear grids) as the unstructured cells
//! VTK gives them: points i fastest, one cell per lattice cell in VTK's cell-id order.
//!
//! Image data and rectilinear grids get VTK_VOXEL (VTK_PIXEL in 2-D) cells and curvilinear
//! (structured) grids VTK_HEXAHEDRON (VTK_QUAD), the types `vtkImageData::GetCell` and
//! `vtkStructuredGrid::GetCell` return; a lattice flat in some axis gives cells of lower
//! dimension (lines, a single vertex), as VTK's data description does. Point and cell data need no
//! change: VTK stores them in the same i-fastest order.

use crate::{cell_type, ArrayData, Cells, DataArray, Grid};
use rayon::prelude::*;

/// How a lattice's cells are typed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Lattice {
    /// Image data and rectilinear grids: axis-aligned cells in raster point order (voxel, pixel).
    Axis,
    /// Curvilinear grids: hexahedra and quads in VTK's ring order.
    Curvilinear,
}

/// Points along each axis of an extent `[i0, i1, j0, j1, k0, k1]`; `None` for an empty extent
/// (an upper bound below its lower one, as VTK writes for a piece with no data).
pub(crate) fn dims(extent: [i64; 6]) -> Result<Option<[usize; 3]>, String> {
    let mut d = [0usize; 3];
    for a in 0..3 {
        let (lo, hi) = (extent[2 * a], extent[2 * a + 1]);
        if hi < lo {
            return Ok(None);
        }
        let n = hi
            .checked_sub(lo)
            .and_then(|x| x.checked_add(1))
            .and_then(|x| usize::try_from(x).ok())
            .ok_or_else(|| format!("extent {lo}..{hi} is too large"))?;
        d[a] = n;
    }
    Ok(Some(d))
}

/// Points and cells of a lattice with `dims` points per axis, overflow-checked.
pub(crate) fn counts(dims: Option<[usize; 3]>) -> Result<(usize, usize), String> {
    let Some(d) = dims else {
        return Ok((0, 0));
    };
    let too_big = || format!("a {} x {} x {} lattice is too large", d[0], d[1], d[2]);
    let np = d[0]
        .checked_mul(d[1])
        .and_then(|x| x.checked_mul(d[2]))
        .ok_or_else(too_big)?;
    // VTK: an axis of one point does not count; a single point is one vertex cell.
    let nc = d
        .iter()
        .filter(|&&n| n > 1)
        .try_fold(1usize, |acc, &n| acc.checked_mul(n - 1))
        .ok_or_else(too_big)?;
    Ok((np, nc))
}

/// Physical memory in bytes (Linux `/proc/meminfo`), or `None` where it cannot be read.
fn physical_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// Refuses a lattice whose points and cells would not fit in this machine's memory, before any
/// of it is made: they are made, not read, so a few header bytes can declare 10^9 cells, and
/// filling an allocation the kernel granted on credit would end in the OOM killer, not an error.
fn check_size(dims: [usize; 3]) -> Result<(), String> {
    let np = dims.iter().map(|&n| n as f64).product::<f64>();
    let nc = dims.iter().map(|&n| (n.max(2) - 1) as f64).product::<f64>();
    // Float64 points, eight i64 corners, an offset and a type per cell.
    let need = np * 24.0 + nc * (8.0 * 8.0 + 9.0);
    match physical_memory() {
        Some(have) if need > have as f64 => Err(format!(
            "a {} x {} x {} lattice needs about {:.1} GiB for its points and cells; this machine has {:.1} GiB",
            dims[0],
            dims[1],
            dims[2],
            need / (1u64 << 30) as f64,
            have as f64 / (1u64 << 30) as f64
        )),
        _ => Ok(()),
    }
}

/// `n` zeros, or an error when the allocation fails: a lattice's points and cells are made, not
/// read, so a small file can declare more of them than memory holds.
fn zeroed<T: Clone + Default>(n: usize, what: &str) -> Result<Vec<T>, String> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        format!(
            "the lattice's {what} need {n} values ({:.1} GiB), more than this machine can allocate",
            (n as f64) * std::mem::size_of::<T>() as f64 / (1u64 << 30) as f64
        )
    })?;
    v.resize(n, T::default());
    Ok(v)
}

/// The cell type of a lattice with `active` axes of more than one point, and its corner offsets
/// (in lattice steps along those axes) in VTK's point order.
fn cell_kind(active: usize, lattice: Lattice) -> (u8, &'static [[usize; 3]]) {
    const VERTEX: [[usize; 3]; 1] = [[0, 0, 0]];
    const LINE: [[usize; 3]; 2] = [[0, 0, 0], [1, 0, 0]];
    const PIXEL: [[usize; 3]; 4] = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]];
    const QUAD: [[usize; 3]; 4] = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]];
    const VOXEL: [[usize; 3]; 8] = [
        [0, 0, 0],
        [1, 0, 0],
        [0, 1, 0],
        [1, 1, 0],
        [0, 0, 1],
        [1, 0, 1],
        [0, 1, 1],
        [1, 1, 1],
    ];
    const HEX: [[usize; 3]; 8] = [
        [0, 0, 0],
        [1, 0, 0],
        [1, 1, 0],
        [0, 1, 0],
        [0, 0, 1],
        [1, 0, 1],
        [1, 1, 1],
        [0, 1, 1],
    ];
    match (active, lattice) {
        (0, _) => (cell_type::VERTEX, &VERTEX),
        (1, _) => (cell_type::LINE, &LINE),
        (2, Lattice::Axis) => (cell_type::PIXEL, &PIXEL),
        (2, Lattice::Curvilinear) => (cell_type::QUAD, &QUAD),
        (_, Lattice::Axis) => (cell_type::VOXEL, &VOXEL),
        (_, Lattice::Curvilinear) => (cell_type::HEXAHEDRON, &HEX),
    }
}

/// The cells of a lattice, numbered as VTK numbers them (the first active axis fastest).
/// Callers have checked the counts with [`counts`].
pub(crate) fn cells(dims: Option<[usize; 3]>, lattice: Lattice) -> Result<Cells, String> {
    let Some(d) = dims else {
        return Ok(Cells::new());
    };
    check_size(d)?;
    let stride = [1, d[0], d[0] * d[1]];
    // The axes with more than one point, in order; a cell steps along these only.
    let axes: Vec<usize> = (0..3).filter(|&a| d[a] > 1).collect();
    let (ty, corner) = cell_kind(axes.len(), lattice);
    // Point-id step of each corner, and the cells per active axis.
    let steps: Vec<i64> = corner
        .iter()
        .map(|c| {
            axes.iter()
                .enumerate()
                .map(|(slot, &a)| (c[slot] * stride[a]) as i64)
                .sum()
        })
        .collect();
    let mut per = [1usize; 3];
    let mut along = [0usize; 3];
    for (slot, &a) in axes.iter().enumerate() {
        per[slot] = d[a] - 1;
        along[slot] = stride[a];
    }
    let nc = per[0] * per[1] * per[2];
    let k = steps.len();
    let total = nc
        .checked_mul(k)
        .ok_or_else(|| format!("{nc} cells of {k} points overflow"))?;
    let mut connectivity: Vec<i64> = zeroed(total, "cells")?;
    let mut types: Vec<u8> = zeroed(nc, "cell types")?;
    types.fill(ty);
    let mut offsets: Vec<i64> = zeroed(nc + 1, "cell offsets")?;
    offsets
        .par_iter_mut()
        .enumerate()
        .for_each(|(c, o)| *o = (c * k) as i64);
    connectivity
        .par_chunks_mut(k * per[0])
        .enumerate()
        .for_each(|(row, out)| {
            let (s1, s2) = (row % per[1], row / per[1]);
            let row_base = s1 * along[1] + s2 * along[2];
            for (s0, cell) in out.chunks_mut(k).enumerate() {
                let base = (row_base + s0 * along[0]) as i64;
                for (slot, step) in cell.iter_mut().zip(&steps) {
                    *slot = base + step;
                }
            }
        });
    Ok(Cells {
        types,
        offsets,
        connectivity,
        polyhedron_faces: None,
    })
}

/// Image data geometry: `origin + direction * (spacing * index)`, `direction` row-major.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Image {
    pub origin: [f64; 3],
    pub spacing: [f64; 3],
    pub direction: [f64; 9],
}

impl Default for Image {
    fn default() -> Image {
        Image {
            origin: [0.0; 3],
            spacing: [1.0; 3],
            direction: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        }
    }
}

/// The points of an image's extent (indices are the extent's own, so a piece starting at i = 8
/// lies 8 spacings from the origin), as Float64 like VTK's image-to-point-set conversion.
pub(crate) fn image_points(
    image: &Image,
    extent: [i64; 6],
    dims: Option<[usize; 3]>,
) -> Result<DataArray, String> {
    let Some(d) = dims else {
        return Ok(DataArray::new("Points", 3, ArrayData::Float64(Vec::new())));
    };
    check_size(d)?;
    let m = image.direction;
    let mut v: Vec<f64> = zeroed(d[0] * d[1] * d[2] * 3, "points")?;
    v.par_chunks_mut(3 * d[0])
        .enumerate()
        .for_each(|(row, out)| {
            let j = (extent[2] + (row % d[1].max(1)) as i64) as f64 * image.spacing[1];
            let k = (extent[4] + (row / d[1].max(1)) as i64) as f64 * image.spacing[2];
            for (i, p) in out.chunks_mut(3).enumerate() {
                let x = (extent[0] + i as i64) as f64 * image.spacing[0];
                for r in 0..3 {
                    p[r] = image.origin[r] + m[3 * r] * x + m[3 * r + 1] * j + m[3 * r + 2] * k;
                }
            }
        });
    Ok(DataArray::new("Points", 3, ArrayData::Float64(v)))
}

/// The points of a rectilinear grid from its three coordinate lists (lengths already checked
/// against the extent). Float32 when all three are Float32, else Float64.
pub(crate) fn rectilinear_points(axes: [&ArrayData; 3]) -> Result<DataArray, String> {
    let (nx, ny, nz) = (axes[0].len(), axes[1].len(), axes[2].len());
    check_size([nx, ny, nz])?;
    let all_f32 = axes.iter().all(|a| matches!(a, ArrayData::Float32(_)));
    let c: Vec<Vec<f64>> = axes.iter().map(|a| a.to_f64_vec()).collect();
    let mut v: Vec<f64> = zeroed(nx * ny * nz * 3, "points")?;
    v.par_chunks_mut(3 * nx.max(1))
        .enumerate()
        .for_each(|(row, out)| {
            let (j, k) = (row % ny.max(1), row / ny.max(1));
            for (i, p) in out.chunks_mut(3).enumerate() {
                p[0] = c[0][i];
                p[1] = c[1][j];
                p[2] = c[2][k];
            }
        });
    let data = if all_f32 {
        // Every value came from an f32, so the round trip is exact.
        ArrayData::Float32(v.into_iter().map(|x| x as f32).collect())
    } else {
        ArrayData::Float64(v)
    };
    Ok(DataArray::new("Points", 3, data))
}

/// Points along each axis of a non-empty extent (no overflow: the extent was counted before).
fn span(e: &[i64; 6]) -> [usize; 3] {
    [0, 1, 2].map(|a| (e[2 * a + 1] - e[2 * a] + 1) as usize)
}

/// Puts the pieces of one structured file back together as VTK does: one lattice over the
/// pieces' bounding extent, each point and cell taken from the first piece that holds it (pieces
/// share their boundary points, and a file may repeat a region). `merged` is the pieces'
/// grids concatenated in piece order; `image` recomputes the points of image data.
pub(crate) fn join_pieces(
    extents: &[[i64; 6]],
    merged: Grid,
    lattice: Lattice,
    image: Option<&Image>,
) -> Result<Grid, String> {
    // (extent, first point, first cell) of each non-empty piece.
    let mut pieces = Vec::new();
    let (mut np, mut nc) = (0usize, 0usize);
    for e in extents {
        let d = dims(*e)?;
        let (p, c) = counts(d)?;
        if d.is_some() {
            pieces.push((*e, np, nc));
        }
        np += p;
        nc += c;
    }
    let Some(first) = pieces.first() else {
        return Ok(merged);
    };
    let mut whole = first.0;
    for (e, _, _) in &pieces {
        for a in 0..3 {
            whole[2 * a] = whole[2 * a].min(e[2 * a]);
            whole[2 * a + 1] = whole[2 * a + 1].max(e[2 * a + 1]);
        }
    }
    let wd = span(&whole);
    counts(Some(wd))?;
    let holds = |e: &[i64; 6], ijk: [i64; 3], reach: [i64; 3]| {
        (0..3).all(|a| e[2 * a] <= ijk[a] && ijk[a] + reach[a] <= e[2 * a + 1])
    };
    let uncovered = |what: &str, ijk: [i64; 3]| {
        format!(
            "the pieces' extents leave {what} ({}, {}, {}) of the whole extent {whole:?} uncovered",
            ijk[0], ijk[1], ijk[2]
        )
    };
    let mut pidx: Vec<usize> = zeroed(wd[0] * wd[1] * wd[2], "points")?;
    pidx.clear();
    for k in whole[4]..=whole[5] {
        for j in whole[2]..=whole[3] {
            for i in whole[0]..=whole[1] {
                let ijk = [i, j, k];
                let (e, off, _) = pieces
                    .iter()
                    .find(|(e, _, _)| holds(e, ijk, [0; 3]))
                    .ok_or_else(|| uncovered("point", ijk))?;
                let d = span(e);
                let local =
                    (i - e[0]) as usize + d[0] * ((j - e[2]) as usize + d[1] * (k - e[4]) as usize);
                pidx.push(off + local);
            }
        }
    }
    // Cells step along the whole lattice's active axes; a piece flat along one of them numbers
    // its cells differently and has none of these.
    let active: Vec<usize> = (0..3).filter(|&a| wd[a] > 1).collect();
    let reach = [0, 1, 2].map(|a| i64::from(wd[a] > 1));
    let hi = [0, 1, 2].map(|a| whole[2 * a + 1] - reach[a]);
    let mut cidx = Vec::new();
    for k in whole[4]..=hi[2] {
        for j in whole[2]..=hi[1] {
            for i in whole[0]..=hi[0] {
                let ijk = [i, j, k];
                let (e, _, off) = pieces
                    .iter()
                    .filter(|(e, _, _)| active.iter().all(|&a| e[2 * a + 1] > e[2 * a]))
                    .find(|(e, _, _)| holds(e, ijk, reach))
                    .ok_or_else(|| uncovered("cell", ijk))?;
                let d = span(e);
                let (mut local, mut stride) = (0usize, 1usize);
                for &a in &active {
                    local += (ijk[a] - e[2 * a]) as usize * stride;
                    stride *= d[a] - 1;
                }
                cidx.push(off + local);
            }
        }
    }
    let points = match image {
        Some(img) => image_points(img, whole, Some(wd))?,
        None => DataArray {
            data: merged.points.data.gather(3, &pidx),
            ..merged.points.clone()
        },
    };
    Ok(Grid {
        points,
        cells: cells(Some(wd), lattice)?,
        point_data: merged.point_data.gather(&pidx),
        cell_data: merged.cell_data.gather(&cidx),
        field_data: merged.field_data,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lattice_too_big_for_memory_is_an_error_not_an_abort() {
        // 2^20 x 2^20 x 2^20 points: counts fit in usize, the points do not fit in memory.
        let d = dims([0, (1 << 20) - 1, 0, (1 << 20) - 1, 0, (1 << 20) - 1]).unwrap();
        assert!(counts(d).is_ok());
        let e = image_points(
            &Image::default(),
            [0, (1 << 20) - 1, 0, (1 << 20) - 1, 0, (1 << 20) - 1],
            d,
        )
        .unwrap_err();
        assert!(e.contains("this machine has"), "{e}");
        assert!(cells(d, Lattice::Axis).is_err());
    }

    #[test]
    fn counts_follow_vtk() {
        assert_eq!(counts(dims([0, 2, 0, 3, 0, 4]).unwrap()), Ok((60, 24)));
        assert_eq!(counts(dims([5, 7, 0, 0, 1, 2]).unwrap()), Ok((6, 2)));
        assert_eq!(counts(dims([3, 3, 0, 0, 1, 1]).unwrap()), Ok((1, 1)));
        assert_eq!(counts(dims([0, -1, 0, 4, 0, 4]).unwrap()), Ok((0, 0)));
        assert!(counts(dims([0, i64::MAX / 2, 0, i64::MAX / 2, 0, 3]).unwrap()).is_err());
        assert!(dims([i64::MIN, i64::MAX, 0, 0, 0, 0]).is_err());
    }

    #[test]
    fn voxels_and_hexahedra_number_like_vtk() {
        let d = dims([0, 2, 0, 1, 0, 1]).unwrap();
        let v = cells(d, Lattice::Axis).unwrap();
        assert_eq!(v.types, vec![cell_type::VOXEL; 2]);
        assert_eq!(v.cell(1), &[1, 2, 4, 5, 7, 8, 10, 11]);
        let h = cells(d, Lattice::Curvilinear).unwrap();
        assert_eq!(h.types, vec![cell_type::HEXAHEDRON; 2]);
        assert_eq!(h.cell(0), &[0, 1, 4, 3, 6, 7, 10, 9]);
        assert_eq!(h.offsets, vec![0, 8, 16]);
    }

    #[test]
    fn flat_lattices_give_lower_cells() {
        // An x-z slice: pixels over the x and z axes.
        let d = dims([0, 2, 4, 4, 0, 1]).unwrap();
        let c = cells(d, Lattice::Axis).unwrap();
        assert_eq!(c.types, vec![cell_type::PIXEL; 2]);
        assert_eq!(c.cell(1), &[1, 2, 4, 5]);
        let q = cells(d, Lattice::Curvilinear).unwrap();
        assert_eq!(q.cell(0), &[0, 1, 4, 3]);
        let line = cells(dims([0, 0, 0, 3, 0, 0]).unwrap(), Lattice::Axis).unwrap();
        assert_eq!(line.types, vec![cell_type::LINE; 3]);
        assert_eq!(line.cell(2), &[2, 3]);
        let point = cells(dims([2, 2, 2, 2, 2, 2]).unwrap(), Lattice::Curvilinear).unwrap();
        assert_eq!(point.types, vec![cell_type::VERTEX]);
        assert_eq!(point.cell(0), &[0]);
        assert!(cells(None, Lattice::Axis).unwrap().is_empty());
    }

    #[test]
    fn image_points_use_extent_spacing_and_direction() {
        let image = Image {
            origin: [10.0, 20.0, 30.0],
            spacing: [0.5, 2.0, 1.0],
            // x' = -y, y' = x: a quarter turn about z.
            direction: [0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0],
        };
        let ext = [2, 3, 1, 2, 0, 0];
        let p = image_points(&image, ext, dims(ext).unwrap()).unwrap();
        let ArrayData::Float64(v) = &p.data else {
            panic!("image points are Float64");
        };
        assert_eq!(v.len(), 12);
        // Point (i=3, j=1): index (3*0.5, 1*2) = (1.5, 2) turned to (-2, 1.5).
        assert_eq!(&v[3..6], &[8.0, 21.5, 30.0]);
        // Point (i=2, j=2): (1, 4) turned to (-4, 1).
        assert_eq!(&v[6..9], &[6.0, 21.0, 30.0]);
    }

    #[test]
    fn rectilinear_points_keep_float32() {
        let x = ArrayData::Float32(vec![0.0, 0.25]);
        let y = ArrayData::Float32(vec![1.0]);
        let z = ArrayData::Float32(vec![-1.0, 2.0]);
        let p = rectilinear_points([&x, &y, &z]).unwrap();
        assert_eq!(
            p.data,
            ArrayData::Float32(vec![
                0.0, 1.0, -1.0, 0.25, 1.0, -1.0, 0.0, 1.0, 2.0, 0.25, 1.0, 2.0
            ])
        );
        let z64 = ArrayData::Float64(vec![0.1]);
        let p = rectilinear_points([&x, &y, &z64]).unwrap();
        assert!(matches!(p.data, ArrayData::Float64(_)));
    }
}
