//! Exodus files built byte by byte by a small classic-NetCDF writer: every encoding, the data
//! model's variants, and every refusal.

use super::names;
use crate::pvd::Selector;
use crate::{cell_type as ct, ArrayData, Grid};
use std::path::Path;

/// Values of one variable or attribute, each of a NetCDF type.
#[derive(Clone)]
enum Val {
    I32(Vec<i32>),
    I64(Vec<i64>),
    F32(Vec<f32>),
    F64(Vec<f64>),
    Text(Vec<u8>),
}

impl Val {
    fn code(&self) -> u32 {
        match self {
            Val::Text(_) => 2,
            Val::I32(_) => 4,
            Val::F32(_) => 5,
            Val::F64(_) => 6,
            Val::I64(_) => 10,
        }
    }
    fn size(&self) -> usize {
        match self {
            Val::Text(_) => 1,
            Val::I32(_) | Val::F32(_) => 4,
            Val::F64(_) | Val::I64(_) => 8,
        }
    }
    fn len(&self) -> usize {
        match self {
            Val::Text(v) => v.len(),
            Val::I32(v) => v.len(),
            Val::F32(v) => v.len(),
            Val::F64(v) => v.len(),
            Val::I64(v) => v.len(),
        }
    }
    fn be(&self) -> Vec<u8> {
        match self {
            Val::Text(v) => v.clone(),
            Val::I32(v) => v.iter().flat_map(|x| x.to_be_bytes()).collect(),
            Val::F32(v) => v.iter().flat_map(|x| x.to_be_bytes()).collect(),
            Val::F64(v) => v.iter().flat_map(|x| x.to_be_bytes()).collect(),
            Val::I64(v) => v.iter().flat_map(|x| x.to_be_bytes()).collect(),
        }
    }
}

struct V {
    name: String,
    dims: Vec<usize>,
    attrs: Vec<(String, Val)>,
    /// All values; a record variable's records one after another.
    val: Val,
}

/// A classic NetCDF file to write: version 1, 2 or 5.
struct Cdf {
    version: u8,
    dims: Vec<(String, u64)>,
    numrecs: u64,
    streaming: bool,
    vars: Vec<V>,
}

fn pad4(b: &mut Vec<u8>) {
    while b.len() % 4 != 0 {
        b.push(0);
    }
}

impl Cdf {
    fn new(version: u8) -> Cdf {
        Cdf {
            version,
            dims: Vec::new(),
            numrecs: 0,
            streaming: false,
            vars: Vec::new(),
        }
    }

    fn dim(&mut self, name: &str, len: u64) -> usize {
        if let Some(i) = self.dims.iter().position(|d| d.0 == name) {
            return i;
        }
        self.dims.push((name.to_string(), len));
        self.dims.len() - 1
    }

    fn var(&mut self, name: &str, dims: &[(&str, u64)], val: Val) -> &mut V {
        let dims = dims.iter().map(|&(n, l)| self.dim(n, l)).collect();
        self.vars.retain(|v| v.name != name);
        self.vars.push(V {
            name: name.to_string(),
            dims,
            attrs: Vec::new(),
            val,
        });
        self.vars.last_mut().unwrap()
    }

    fn remove(&mut self, name: &str) {
        self.vars.retain(|v| v.name != name);
    }

    fn count(&self, b: &mut Vec<u8>, n: u64) {
        if self.version == 5 {
            b.extend_from_slice(&n.to_be_bytes());
        } else {
            b.extend_from_slice(&(n as u32).to_be_bytes());
        }
    }

    fn name(&self, b: &mut Vec<u8>, s: &str) {
        self.count(b, s.len() as u64);
        b.extend_from_slice(s.as_bytes());
        pad4(b);
    }

    fn is_record(&self, v: &V) -> bool {
        v.dims.first().is_some_and(|&d| self.dims[d].1 == 0)
    }

    fn attrs(&self, b: &mut Vec<u8>, attrs: &[(String, Val)]) {
        if attrs.is_empty() {
            b.extend_from_slice(&[0; 4]);
            self.count(b, 0);
            return;
        }
        b.extend_from_slice(&0x0Cu32.to_be_bytes());
        self.count(b, attrs.len() as u64);
        for (n, v) in attrs {
            self.name(b, n);
            b.extend_from_slice(&v.code().to_be_bytes());
            self.count(b, v.len() as u64);
            b.extend(v.be());
            pad4(b);
        }
    }

    fn header(&self, begins: &[u64]) -> Vec<u8> {
        let mut b = b"CDF".to_vec();
        b.push(self.version);
        let nr = if self.streaming {
            if self.version == 5 {
                u64::MAX
            } else {
                0xFFFF_FFFF
            }
        } else {
            self.numrecs
        };
        self.count(&mut b, nr);
        b.extend_from_slice(&0x0Au32.to_be_bytes());
        self.count(&mut b, self.dims.len() as u64);
        for (n, l) in &self.dims {
            self.name(&mut b, n);
            self.count(&mut b, *l);
        }
        self.attrs(
            &mut b,
            &[("title".to_string(), Val::Text(b"made by a test".to_vec()))],
        );
        b.extend_from_slice(&0x0Bu32.to_be_bytes());
        self.count(&mut b, self.vars.len() as u64);
        for (v, &begin) in self.vars.iter().zip(begins) {
            self.name(&mut b, &v.name);
            self.count(&mut b, v.dims.len() as u64);
            for &d in &v.dims {
                self.count(&mut b, d as u64);
            }
            self.attrs(&mut b, &v.attrs);
            b.extend_from_slice(&v.val.code().to_be_bytes());
            let size = self.record_bytes(v).div_ceil(4) * 4;
            self.count(&mut b, size as u64);
            if self.version == 1 {
                b.extend_from_slice(&(begin as u32).to_be_bytes());
            } else {
                b.extend_from_slice(&begin.to_be_bytes());
            }
        }
        b
    }

    /// Bytes of one record (record variables) or of the whole (fixed ones).
    fn record_bytes(&self, v: &V) -> usize {
        let n = if self.is_record(v) && self.numrecs > 0 {
            v.val.len() / self.numrecs as usize
        } else {
            v.val.len()
        };
        n * v.val.size()
    }

    fn bytes(&self) -> Vec<u8> {
        let head = self.header(&vec![0; self.vars.len()]).len() as u64;
        let mut begins = vec![0u64; self.vars.len()];
        let mut at = head;
        for (i, v) in self.vars.iter().enumerate() {
            if !self.is_record(v) {
                begins[i] = at;
                at += self.record_bytes(v).div_ceil(4) as u64 * 4;
            }
        }
        let rec: Vec<usize> = (0..self.vars.len())
            .filter(|&i| self.is_record(&self.vars[i]))
            .collect();
        let single = rec.len() == 1;
        for &i in &rec {
            begins[i] = at;
            let n = self.record_bytes(&self.vars[i]);
            at += if single { n } else { n.div_ceil(4) * 4 } as u64;
        }
        let mut b = self.header(&begins);
        for v in self.vars.iter().filter(|v| !self.is_record(v)) {
            b.extend(v.val.be());
            pad4(&mut b);
        }
        for r in 0..self.numrecs as usize {
            for &i in &rec {
                let v = &self.vars[i];
                let n = self.record_bytes(v);
                b.extend_from_slice(&v.val.be()[r * n..(r + 1) * n]);
                if !single {
                    pad4(&mut b);
                }
            }
        }
        b
    }
}

fn text_rows(rows: &[&str], width: usize) -> Val {
    let mut v = Vec::new();
    for r in rows {
        let mut row = r.as_bytes().to_vec();
        row.resize(width, 0);
        v.extend(row);
    }
    Val::Text(v)
}

/// A small Exodus file: 5 nodes; block 7 (one TETRA) and block 9 (one TRI3); two time steps with
/// a nodal, an element (block 7 only) and a global variable; a node set and a side set.
fn exodus(version: u8) -> Cdf {
    let mut c = Cdf::new(version);
    c.numrecs = 2;
    let t = ("time_step", 0);
    let nodes = ("num_nodes", 5);
    c.dim("len_name", 33);
    c.dim("num_dim", 3);
    c.dim("num_elem", 2);
    c.dim("num_el_blk", 2);
    c.var("time_whole", &[t], Val::F64(vec![0.0, 2.5]));
    c.var("coordx", &[nodes], Val::F64(vec![0.0, 1.0, 0.0, 0.0, 1.0]));
    c.var("coordy", &[nodes], Val::F64(vec![0.0, 0.0, 1.0, 0.0, 1.0]));
    c.var("coordz", &[nodes], Val::F64(vec![0.0, 0.0, 0.0, 1.0, 0.0]));
    c.var("eb_prop1", &[("num_el_blk", 2)], Val::I32(vec![7, 9]))
        .attrs
        .push(("name".into(), Val::Text(b"ID".to_vec())));
    c.var(
        "eb_names",
        &[("num_el_blk", 2), ("len_name", 33)],
        text_rows(&["solid", "skin"], 33),
    );
    c.var(
        "connect1",
        &[("num_el_in_blk1", 1), ("num_nod_per_el1", 4)],
        Val::I32(vec![1, 2, 3, 4]),
    )
    .attrs
    .push(("elem_type".into(), Val::Text(b"TETRA4".to_vec())));
    c.var(
        "connect2",
        &[("num_el_in_blk2", 1), ("num_nod_per_el2", 3)],
        Val::I32(vec![2, 5, 3]),
    )
    .attrs
    .push(("elem_type".into(), Val::Text(b"tri3".to_vec())));
    c.var("node_num_map", &[nodes], Val::I32(vec![10, 11, 12, 13, 14]));
    c.var("elem_num_map", &[("num_elem", 2)], Val::I32(vec![100, 200]));
    c.dim("num_nod_var", 1);
    c.var(
        "name_nod_var",
        &[("num_nod_var", 1), ("len_name", 33)],
        text_rows(&["u"], 33),
    );
    c.var(
        "vals_nod_var1",
        &[t, nodes],
        Val::F64(vec![1.0, 2.0, 3.0, 4.0, 5.0, 10.0, 20.0, 30.0, 40.0, 50.0]),
    );
    c.dim("num_elem_var", 1);
    c.var(
        "name_elem_var",
        &[("num_elem_var", 1), ("len_name", 33)],
        text_rows(&["stress"], 33),
    );
    c.var(
        "elem_var_tab",
        &[("num_el_blk", 2), ("num_elem_var", 1)],
        Val::I32(vec![1, 0]),
    );
    c.var(
        "vals_elem_var1eb1",
        &[t, ("num_el_in_blk1", 1)],
        Val::F32(vec![0.5, 1.5]),
    );
    c.dim("num_glo_var", 1);
    c.var(
        "name_glo_var",
        &[("num_glo_var", 1), ("len_name", 33)],
        text_rows(&["energy"], 33),
    );
    c.var(
        "vals_glo_var",
        &[t, ("num_glo_var", 1)],
        Val::F64(vec![7.0, 8.0]),
    );
    c.dim("num_node_sets", 1);
    c.var("ns_prop1", &[("num_node_sets", 1)], Val::I32(vec![3]));
    c.var(
        "ns_names",
        &[("num_node_sets", 1), ("len_name", 33)],
        text_rows(&["top"], 33),
    );
    c.var("node_ns1", &[("num_nod_ns1", 2)], Val::I32(vec![4, 5]));
    c.dim("num_side_sets", 1);
    c.var("ss_prop1", &[("num_side_sets", 1)], Val::I32(vec![4]));
    c
}

fn read_at(bytes: &[u8], sel: Selector) -> crate::Result<Grid> {
    let g = super::read_from(bytes, Path::new("t.exo"), sel)?;
    g.validate().map_err(crate::FormatError::whole)?;
    Ok(g)
}

fn read(bytes: &[u8]) -> Grid {
    read_at(bytes, Selector::Index(0)).unwrap_or_else(|e| panic!("{e}"))
}

fn err(bytes: &[u8]) -> String {
    match read_at(bytes, Selector::Index(0)) {
        Ok(_) => panic!("read a bad file"),
        Err(e) => e.to_string(),
    }
}

fn f64s(g: &Grid, cell: bool, name: &str) -> Vec<f64> {
    let a = if cell { &g.cell_data } else { &g.point_data };
    a.get(name)
        .unwrap_or_else(|| panic!("no array {name}"))
        .data
        .to_f64_vec()
}

#[test]
fn reads_the_data_model() {
    let g = read(&exodus(1).bytes());
    assert_eq!(g.num_points(), 5);
    assert_eq!(
        g.points.data.scalar_type(),
        Some(crate::ScalarType::Float64)
    );
    assert_eq!(g.point(4), [1.0, 1.0, 0.0]);
    assert_eq!(g.cells.types, vec![ct::TETRA, ct::TRIANGLE]);
    assert_eq!(g.cells.cell(1), &[1, 4, 2]);
    assert_eq!(
        g.cell_data.get(names::OBJECT_ID).unwrap().data,
        ArrayData::Int32(vec![7, 9])
    );
    assert_eq!(
        g.cell_data.get(names::ELEMENT_ID).unwrap().data,
        ArrayData::Int64(vec![100, 200])
    );
    assert_eq!(
        g.point_data.get(names::NODE_ID).unwrap().data,
        ArrayData::Int64(vec![10, 11, 12, 13, 14])
    );
    assert_eq!(f64s(&g, false, "u"), vec![1.0, 2.0, 3.0, 4.0, 5.0]);
    let s = &g.cell_data.get("stress").unwrap().data;
    let ArrayData::Float32(s) = s else {
        panic!("stress is {s:?}")
    };
    assert_eq!(s[0], 0.5);
    assert!(s[1].is_nan(), "the truth table leaves block 9 out");
    assert_eq!(
        g.point_data.get("nodeset:top").unwrap().data,
        ArrayData::UInt8(vec![0, 0, 0, 1, 1])
    );
    let field = |n: &str| {
        g.field_data
            .iter()
            .find(|a| a.name == n)
            .unwrap()
            .data
            .clone()
    };
    assert_eq!(field(names::TIME), ArrayData::Float64(vec![0.0, 2.5]));
    assert_eq!(field("energy"), ArrayData::Float64(vec![7.0, 8.0]));
    assert_eq!(
        field(names::BLOCK_NAMES),
        ArrayData::String(vec!["solid".into(), "skin".into()])
    );
}

#[test]
fn every_encoding_reads_alike() {
    // Compared as printed: the NaN in `stress` is not equal to itself.
    let one = read(&exodus(1).bytes());
    assert_eq!(
        format!("{:?}", read(&exodus(2).bytes())),
        format!("{one:?}")
    );
    let mut five = exodus(5);
    // CDF-5's 64-bit integers, as Exodus writes with int64 ids.
    five.var(
        "connect1",
        &[("num_el_in_blk1", 1), ("num_nod_per_el1", 4)],
        Val::I64(vec![1, 2, 3, 4]),
    )
    .attrs
    .push(("elem_type".into(), Val::Text(b"TETRA4".to_vec())));
    let g = read(&five.bytes());
    assert_eq!(g.cells, one.cells);
}

#[test]
fn time_steps_are_selected() {
    let b = exodus(2).bytes();
    for sel in [Selector::Index(1), Selector::Last] {
        let g = read_at(&b, sel).unwrap();
        assert_eq!(f64s(&g, false, "u"), vec![10.0, 20.0, 30.0, 40.0, 50.0]);
        assert_eq!(f64s(&g, true, "stress")[0], 1.5);
    }
    let e = read_at(&b, Selector::Index(2)).unwrap_err().to_string();
    assert!(e.contains("no time step 2: the file has 2 (0 to 1)"), "{e}");
}

#[test]
fn streaming_numrecs_counts_the_records_in_the_file() {
    let mut c = exodus(1);
    c.streaming = true;
    let g = read_at(&c.bytes(), Selector::Last).unwrap();
    assert_eq!(f64s(&g, false, "u")[0], 10.0);
}

#[test]
fn two_dimensional_and_old_style_files() {
    let mut c = exodus(1);
    c.dims[1].1 = 2; // num_dim
    c.remove("coordx");
    c.remove("coordy");
    c.remove("coordz");
    c.var(
        "coord",
        &[("num_dim", 2), ("num_nodes", 5)],
        Val::F32(vec![0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.5, 1.0]),
    );
    c.remove("vals_nod_var1");
    c.var(
        "vals_nod_var",
        &[("time_step", 0), ("num_nod_var", 1), ("num_nodes", 5)],
        Val::F64(vec![1.0, 2.0, 3.0, 4.0, 5.0, 10.0, 20.0, 30.0, 40.0, 50.0]),
    );
    c.remove("eb_prop1");
    let g = read(&c.bytes());
    assert_eq!(
        g.points.data.scalar_type(),
        Some(crate::ScalarType::Float32)
    );
    assert_eq!(g.point(3), [0.0, 0.5, 0.0]);
    assert_eq!(f64s(&g, false, "u")[4], 5.0);
    assert_eq!(f64s(&g, true, names::OBJECT_ID), vec![1.0, 2.0]);
}

#[test]
fn node_orders_follow_vtk() {
    let mut c = exodus(1);
    let n = c.dim("num_nodes", 5);
    c.dims[n].1 = 20;
    for a in ["coordx", "coordy", "coordz"] {
        c.var(
            a,
            &[("num_nodes", 20)],
            Val::F64((0..20).map(f64::from).collect()),
        );
    }
    c.remove("node_num_map");
    c.remove("vals_nod_var1");
    c.dims.iter_mut().find(|d| d.0 == "num_nod_var").unwrap().1 = 0;
    c.remove("name_nod_var");
    c.var(
        "connect1",
        &[("num_el_in_blk1", 1), ("num_nod_per_el1b", 20)],
        Val::I32((1..=20).collect()),
    )
    .attrs
    .push(("elem_type".into(), Val::Text(b"HEX".to_vec())));
    let g = read(&c.bytes());
    assert_eq!(g.cells.types[0], ct::QUADRATIC_HEXAHEDRON);
    let want: Vec<i64> = (0..12).chain(16..20).chain(12..16).collect();
    assert_eq!(g.cells.cell(0), want.as_slice());
    // Without node_num_map the nodes are numbered 1, 2, ... as Exodus and VTK's reader have it.
    assert_eq!(
        g.point_data.get(names::NODE_ID).unwrap().data,
        ArrayData::Int64((1..=20).collect())
    );
}

/// A change that spoils a good file.
type Change = Box<dyn Fn(&mut Cdf)>;

#[test]
fn refusals_name_the_place() {
    let cases: Vec<(&str, Change, &str)> = vec![
        (
            "node out of range",
            Box::new(|c| {
                c.var(
                    "connect2",
                    &[("num_el_in_blk2", 1), ("num_nod_per_el2", 3)],
                    Val::I32(vec![2, 6, 3]),
                )
                .attrs
                .push(("elem_type".into(), Val::Text(b"TRI".to_vec())));
            }),
            "variable 'connect2': element 1 names node 6, out of range (there are 5 nodes, numbered 1 to 5)",
        ),
        (
            "unknown type",
            Box::new(|c| {
                c.vars
                    .iter_mut()
                    .find(|v| v.name == "connect1")
                    .unwrap()
                    .attrs[0]
                    .1 = Val::Text(b"BLOB".to_vec())
            }),
            "variable 'connect1': unknown element type 'BLOB'",
        ),
        (
            "polyhedra",
            Box::new(|c| {
                c.vars
                    .iter_mut()
                    .find(|v| v.name == "connect1")
                    .unwrap()
                    .attrs[0]
                    .1 = Val::Text(b"NFACED".to_vec())
            }),
            "not supported",
        ),
        (
            "no elem_type",
            Box::new(|c| {
                c.vars
                    .iter_mut()
                    .find(|v| v.name == "connect1")
                    .unwrap()
                    .attrs
                    .clear()
            }),
            "variable 'connect1': has no elem_type attribute",
        ),
        (
            "no coordinates",
            Box::new(|c| c.remove("coordy")),
            "5 nodes but no coordinates",
        ),
        (
            "short coordinates",
            Box::new(|c| {
                c.var("coordy", &[("num_nodes4", 4)], Val::F64(vec![0.0; 4]));
            }),
            "variable 'coordy': 4 coordinates for num_nodes 5",
        ),
        ("num_dim", Box::new(|c| c.dims[1].1 = 4), "num_dim is 4"),
        (
            "bad map",
            Box::new(|c| {
                c.var("elem_num_map", &[("three", 3)], Val::I32(vec![1, 2, 3]));
            }),
            "variable 'elem_num_map': 3 entries for 2 objects",
        ),
        (
            "bad truth table",
            Box::new(|c| {
                c.var("elem_var_tab", &[("three", 3)], Val::I32(vec![1, 1, 1]));
            }),
            "variable 'elem_var_tab': 3 entries for 2 blocks x 1 variables",
        ),
        (
            "too many variables",
            Box::new(|c| {
                c.remove("name_nod_var");
                c.dims.iter_mut().find(|d| d.0 == "num_nod_var").unwrap().1 = 1 << 30;
            }),
            "more than the file could hold",
        ),
        (
            "too many blocks",
            Box::new(|c| {
                c.remove("eb_prop1");
                c.dims.iter_mut().find(|d| d.0 == "num_el_blk").unwrap().1 = 1 << 30;
            }),
            "more blocks than the file describes",
        ),
    ];
    for (what, change, needle) in cases {
        let mut c = exodus(2);
        change(&mut c);
        let e = err(&c.bytes());
        assert!(e.starts_with("t.exo: "), "{what}: {e}");
        assert!(e.contains(needle), "{what}: {e}");
    }
}

#[test]
fn netcdf_refusals_name_byte_and_variable() {
    let good = exodus(1).bytes();
    let mut hdf = b"\x89HDF\r\n\x1a\n".to_vec();
    hdf.extend_from_slice(&[0; 64]);
    let e = err(&hdf);
    assert!(e.starts_with("t.exo: NetCDF-4 (HDF5): "), "{e}");
    let e = err(b"CDF\x03rest");
    assert!(
        e.contains("byte 0: not a NetCDF file: neither classic"),
        "{e}"
    );
    // Truncated in the header.
    let e = err(&good[..10]);
    assert!(
        e.contains("byte 8: the header ends inside dimensions"),
        "{e}"
    );
    // A variable whose data lies past the end.
    let e = err(&good[..good.len() - 100]);
    assert!(e.contains("run past the end of the file"), "{e}");
    // An nc_type the classic format lacks (CDF-1 has no 64-bit integers).
    let mut c = exodus(1);
    c.var("node_num_map", &[("num_nodes", 5)], Val::I64(vec![1; 5]));
    let e = err(&c.bytes());
    assert!(
        e.contains("variable 'node_num_map' has an unknown nc_type 10"),
        "{e}"
    );
    // A begin offset past the end.
    let mut b = good.clone();
    let at = find(&b, b"coordx") + 8;
    let begin_at = next_begin(&b, at);
    b[begin_at..begin_at + 4].copy_from_slice(&0x7fff_0000u32.to_be_bytes());
    let e = err(&b);
    assert!(
        e.contains("variable 'coordx': its data (offset 2147418112"),
        "{e}"
    );
    // A negative count.
    let mut b = good.clone();
    b[12..16].copy_from_slice(&(-3i32).to_be_bytes());
    let e = err(&b);
    assert!(
        e.contains("byte 12: the number of dimensions is negative"),
        "{e}"
    );
    // A dimension count the file cannot hold.
    b[12..16].copy_from_slice(&1_000_000u32.to_be_bytes());
    let e = err(&b);
    assert!(e.contains("more than the"), "{e}");
    // A numrecs the records cannot fill.
    let mut b = good.clone();
    b[4..8].copy_from_slice(&1000u32.to_be_bytes());
    let e = err(&b);
    assert!(e.contains("byte 4: numrecs 1000"), "{e}");
}

fn find(hay: &[u8], needle: &[u8]) -> usize {
    hay.windows(needle.len()).position(|w| w == needle).unwrap()
}

/// Where the begin offset of the variable whose name ends at `from` is: past its dims, its
/// (absent) attributes, its nc_type and vsize. Only for CDF-1 variables without attributes.
fn next_begin(b: &[u8], from: usize) -> usize {
    let u = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]) as usize;
    let nd = u(from);
    from + 4 + 4 * nd + 8 + 4 + 4
}

#[test]
fn truncations_and_flipped_bytes_give_errors_not_panics() {
    let files = [
        exodus(1).bytes(),
        exodus(2).bytes(),
        exodus(5).bytes(),
        include_bytes!("../../../fixtures/exodus/tets.exo").to_vec(),
    ];
    for b in &files {
        for n in (0..b.len()).step_by(3) {
            assert!(read_at(&b[..n], Selector::Index(0)).is_err());
        }
        for i in (0..b.len()).step_by(2) {
            for x in [0xFF, 0x80, 0x01] {
                let mut c = b.clone();
                c[i] ^= x;
                let _ = read_at(&c, Selector::Last);
            }
        }
    }
}

/// The NetCDF-4 fixtures (scripts/make_exodus_nc4_fixtures.sh) beside their classic originals.
fn nc4_fixture(name: &str) -> Vec<u8> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/exodus")
        .join(name);
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Everything bit for bit: points, cells, and every array by name, type, components, values.
fn assert_same_grid(what: &str, a: &Grid, b: &Grid) {
    assert!(a.points.bit_eq(&b.points), "{what}: points");
    assert_eq!(a.cells, b.cells, "{what}: cells");
    for (kind, x, y) in [
        ("point", &a.point_data.arrays, &b.point_data.arrays),
        ("cell", &a.cell_data.arrays, &b.cell_data.arrays),
        ("field", &a.field_data, &b.field_data),
    ] {
        let names = |v: &[crate::DataArray]| v.iter().map(|a| a.name.clone()).collect::<Vec<_>>();
        assert_eq!(names(x), names(y), "{what}: {kind} arrays");
        for (ax, ay) in x.iter().zip(y) {
            assert!(ax.bit_eq(ay), "{what}: {kind} array {}", ax.name);
        }
    }
}

const NC4_PAIRS: [(&str, &str); 10] = [
    ("nc4/hand.exo", "hand.exo"),
    ("nc4/hand.exo", "hand5.exo"),
    ("nc4/mixed.exo", "mixed.exo"),
    ("nc4/quadratic.exo", "quadratic.exo"),
    ("nc4/steps.exo", "steps.exo"),
    ("nc4/steps_nc7.exo", "steps.exo"),
    ("nc4/tets.exo", "tets.exo"),
    ("nc4/tets_nc7.exo", "tets.exo"),
    ("nc4/meshio.exo", "nc4/meshio_cdf5.exo"),
    ("nc4/meshio_strings.exo", "nc4/meshio_cdf5.exo"),
];

#[test]
fn netcdf4_reads_as_its_classic_copy() -> crate::Result<()> {
    for (nc4, classic) in NC4_PAIRS {
        let (a, b) = (nc4_fixture(nc4), nc4_fixture(classic));
        assert!(super::nc4::is_hdf5(&a) && !super::nc4::is_hdf5(&b));
        let steps = super::read::times_of(&b, Path::new(classic))?;
        let times = super::read::times_of(&a, Path::new(nc4))?;
        assert_eq!(
            times.iter().map(|t| t.to_bits()).collect::<Vec<_>>(),
            steps.iter().map(|t| t.to_bits()).collect::<Vec<_>>(),
            "{nc4}: times"
        );
        for k in 0..steps.len().max(1) {
            let what = format!("{nc4}@{k}");
            let sel = Selector::Index(k);
            let (ga, gb) = (read_at(&a, sel), read_at(&b, sel));
            let (ga, gb) = (ga?, gb?);
            assert_same_grid(&what, &ga, &gb);
        }
    }
    // int64 connectivity and node sets, NC_STRING names: as meshio writes them.
    let g = read(&nc4_fixture("nc4/meshio_strings.exo"));
    assert_eq!(g.cells.types, vec![ct::TETRA, ct::TETRA, ct::HEXAHEDRON]);
    assert_eq!(f64s(&g, false, "nodeset:bottom").iter().sum::<f64>(), 7.0);
    assert_eq!(f64s(&g, false, "temperature")[6], 30.0);
    assert_eq!(f64s(&g, true, names::OBJECT_ID), vec![0.0, 0.0, 1.0]);
    Ok(())
}

#[test]
fn netcdf4_behind_a_user_block() {
    let b = nc4_fixture("nc4/tets_nc7.exo");
    let want = read(&b);
    for n in [512, 1024, 2048] {
        let mut u = vec![0u8; n];
        u.extend_from_slice(&b);
        assert!(super::nc4::is_hdf5(&u));
        match read_at(&u, Selector::Index(0)) {
            Ok(g) => assert_same_grid(&format!("user block {n}"), &g, &want),
            Err(e) => panic!("user block {n}: {e}"),
        }
    }
}

#[test]
fn netcdf4_truncations_and_flipped_bytes_give_errors_not_panics() {
    for (name, cut, flip) in [("nc4/meshio.exo", 5, 3), ("nc4/tets.exo", 7, 11)] {
        let b = nc4_fixture(name);
        cut_and_flip(&b, cut, flip);
    }
}

/// Reads `b` cut at every `cut`-th byte, and with every `flip`-th byte flipped.
fn cut_and_flip(b: &[u8], cut: usize, flip: usize) {
    let good = read(b);
    for n in (0..b.len()).step_by(cut) {
        let e = read_at(&b[..n], Selector::Index(0))
            .map(|_| ())
            .unwrap_err();
        assert!(e.to_string().starts_with("t.exo: "), "cut at {n}: {e}");
    }
    for i in (0..b.len()).step_by(flip) {
        for x in [0xFF, 0x01] {
            let mut c = b.to_vec();
            c[i] ^= x;
            match read_at(&c, Selector::Last) {
                Err(e) => assert!(e.to_string().starts_with("t.exo: "), "byte {i}: {e}"),
                // A flip in unused space, or in a value: still a grid of the same shape.
                Ok(g) => assert_eq!(g.num_points(), good.num_points(), "byte {i}"),
            }
        }
    }
}

#[test]
fn the_time_array_is_there_exactly_when_the_file_has_steps() {
    let time = |g: &Grid| {
        g.field_data
            .iter()
            .find(|a| a.name == names::TIME)
            .map(|a| a.data.clone())
    };
    // Steps without `time_whole`: one NaN a step, so a listing still counts them.
    let mut c = exodus(1);
    c.remove("time_whole");
    let t = time(&read(&c.bytes()));
    assert!(
        matches!(&t, Some(ArrayData::Float64(v)) if v.len() == 2 && v.iter().all(|x| x.is_nan())),
        "{t:?}"
    );
    // No steps (no record variables, no records): no time array.
    let mut c = exodus(1);
    let rec = c.dims.iter().position(|d| d.0 == "time_step");
    c.vars.retain(|v| v.dims.first().copied() != rec);
    c.numrecs = 0;
    let g = read(&c.bytes());
    assert_eq!(time(&g), None);
    assert_eq!(g.num_cells(), 2);
}
