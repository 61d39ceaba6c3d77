//! Tetrahedralization speed on structured hexahedron grids (1M cells at the largest size), with
//! points numbered in a shuffled order so the smallest-vertex rule sees every case.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use tetkit::formats::{cell_type, ArrayData, Cells, DataArray, Grid};
use tetkit::mesh::tetrahedralize::tetrahedralize;

/// An `n^3` grid of unit hexahedra with a point scalar and a cell id, point ids scrambled by a
/// multiplicative permutation (odd multiplier mod a power of two, restricted to the range).
fn hex_grid(n: usize) -> Grid {
    let np = (n + 1).pow(3);
    let m = np.next_power_of_two();
    let mut perm = Vec::with_capacity(np);
    let mut x = 0usize;
    while perm.len() < np {
        let v = (x.wrapping_mul(0x9E37_79B1) + 12345) & (m - 1);
        if v < np {
            perm.push(v);
        }
        x += 1;
    }
    let l = |i: usize, j: usize, k: usize| perm[i + (n + 1) * (j + (n + 1) * k)] as i64;
    let mut pts = vec![0.0f64; 3 * np];
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let p = l(i, j, k) as usize;
                pts[3 * p..3 * p + 3].copy_from_slice(&[i as f64, j as f64, k as f64]);
            }
        }
    }
    let mut cells = Cells::new();
    cells.types = vec![cell_type::HEXAHEDRON; n * n * n];
    cells.connectivity.reserve(8 * n * n * n);
    cells.offsets = (0..=n * n * n).map(|c| 8 * c as i64).collect();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                cells.connectivity.extend_from_slice(&[
                    l(i, j, k),
                    l(i + 1, j, k),
                    l(i + 1, j + 1, k),
                    l(i, j + 1, k),
                    l(i, j, k + 1),
                    l(i + 1, j, k + 1),
                    l(i + 1, j + 1, k + 1),
                    l(i, j + 1, k + 1),
                ]);
            }
        }
    }
    let mut g = Grid {
        points: DataArray::new("Points", 3, ArrayData::Float64(pts)),
        cells,
        ..Grid::default()
    };
    let s: Vec<f32> = (0..np).map(|i| i as f32).collect();
    g.point_data
        .insert(DataArray::new("s", 1, ArrayData::Float32(s)));
    let c: Vec<i32> = (0..(n * n * n) as i32).collect();
    g.cell_data
        .insert(DataArray::new("cell", 1, ArrayData::Int32(c)));
    g
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("tetrahedralize_hex");
    group.sample_size(10);
    for n in [20usize, 50, 100] {
        let g = hex_grid(n);
        group.throughput(Throughput::Elements((n * n * n) as u64));
        group.bench_with_input(BenchmarkId::from_parameter(n * n * n), &g, |b, g| {
            b.iter(|| tetrahedralize(g, false).map(|(t, _)| t.num_cells()))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
