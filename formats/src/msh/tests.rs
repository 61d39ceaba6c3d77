//! Unit tests on tiny in-memory files: each version and encoding, and every refusal.

use super::*;
use crate::{cell_type as ct, ArrayData, Place};

const V41: &str = r#"$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 7 "skin"
3 9 "solid part"
$EndPhysicalNames
$Entities
0 0 1 1
3 0 0 0 1 1 1 1 7 0
5 0 0 0 1 1 1 2 9 11 1 3
$EndEntities
$Nodes
2 5 10 50
3 5 0 4
10
20
30
40
0 0 0
1 0 0
0 1 0
0 0 1
2 3 1 1
50
0.5 0.5 0 0.25 0.75
$EndNodes
$Elements
2 2 1 2
3 5 4 1
1 10 20 30 40
2 3 2 1
2 10 30 20
$EndElements
$Custom
anything $Nodes at all
$EndCustom
$NodeData
1
"T"
1
0.5
3
0
1
2
10 1.5
50 2.5
$EndNodeData
$NodeData
1
"T"
1
1.5
3
4
1
1
20 7
$EndNodeData
$ElementData
1
"flux"
1
0
3
0
3
1
2 1 2 3
$EndElementData
$ElementNodeData
1
"per node"
1
0
3
0
1
1
1 4 1 2 3 4
$EndElementNodeData
"#;

fn read(text: &[u8]) -> Result<Grid> {
    read_from(text, Some(Path::new("t.msh")))
}

fn err(text: &[u8]) -> FormatError {
    match read(text) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

fn arr<'g>(g: &'g [crate::DataArray], name: &str) -> &'g ArrayData {
    &g.iter()
        .find(|a| a.name == name)
        .unwrap_or_else(|| panic!("{name}"))
        .data
}

#[test]
fn reads_msh41_ascii() {
    let g = read(V41.as_bytes()).unwrap();
    g.validate().unwrap();
    assert_eq!(g.num_points(), 5);
    assert_eq!(g.cells.types, vec![ct::TETRA, ct::TRIANGLE]);
    assert_eq!(g.cells.cell(0), &[0, 1, 2, 3]);
    assert_eq!(g.cells.cell(1), &[0, 2, 1]);
    let pd = &g.point_data.arrays;
    assert_eq!(
        arr(pd, names::NODE_TAG),
        &ArrayData::Int64(vec![10, 20, 30, 40, 50])
    );
    let ArrayData::Float64(p) = arr(pd, names::PARAMETRIC) else {
        panic!()
    };
    assert!(p[..12].iter().all(|v| v.is_nan()));
    assert_eq!(&p[12..14], &[0.25, 0.75]);
    assert!(p[14].is_nan());
    let cd = &g.cell_data.arrays;
    assert_eq!(arr(cd, names::PHYSICAL), &ArrayData::Int32(vec![9, 7]));
    assert_eq!(arr(cd, names::GEOMETRICAL), &ArrayData::Int32(vec![5, 3]));
    assert_eq!(arr(cd, names::ELEMENT_TAG), &ArrayData::Int64(vec![1, 2]));
    let fd = &g.field_data;
    assert_eq!(
        arr(fd, names::PHYSICAL_NAMES),
        &ArrayData::String(vec!["skin".into(), "solid part".into()])
    );
    assert_eq!(arr(fd, names::PHYSICAL_DIMS), &ArrayData::Int32(vec![2, 3]));
    assert_eq!(arr(fd, names::PHYSICAL_TAGS), &ArrayData::Int32(vec![7, 9]));
    let ArrayData::Float64(t) = arr(pd, "T") else {
        panic!()
    };
    assert_eq!(t[0], 1.5);
    assert!(t[1].is_nan());
    assert_eq!(t[4], 2.5);
    let ArrayData::Float64(t4) = arr(pd, "T@4") else {
        panic!()
    };
    assert_eq!(t4[1], 7.0);
    assert_eq!(arr(fd, "gmsh:time:T"), &ArrayData::Float64(vec![0.5, 1.5]));
    let flux = cd.iter().find(|a| a.name == "flux").unwrap();
    assert_eq!(flux.components, 3);
    let ArrayData::Float64(f) = &flux.data else {
        panic!()
    };
    assert!(f[..3].iter().all(|v| v.is_nan()));
    assert_eq!(&f[3..], &[1.0, 2.0, 3.0]);
    assert!(g.point_data.get("per node").is_none());
}

/// A binary MSH 4.1 file with what [`V41`] holds (no views), written value by value.
struct Bin {
    out: Vec<u8>,
    be: bool,
    size_t: usize,
}

impl Bin {
    fn text(&mut self, s: &str) -> &mut Self {
        self.out.extend_from_slice(s.as_bytes());
        self
    }
    fn i(&mut self, v: i32) -> &mut Self {
        let b = if self.be {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        };
        self.out.extend_from_slice(&b);
        self
    }
    fn z(&mut self, v: u64) -> &mut Self {
        if self.size_t == 4 {
            let v = v as u32;
            let b = if self.be {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            };
            self.out.extend_from_slice(&b);
        } else {
            let b = if self.be {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            };
            self.out.extend_from_slice(&b);
        }
        self
    }
    fn d(&mut self, v: f64) -> &mut Self {
        let b = if self.be {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        };
        self.out.extend_from_slice(&b);
        self
    }
}

fn v41_binary(be: bool, size_t: usize) -> Vec<u8> {
    let mut b = Bin {
        out: Vec::new(),
        be,
        size_t,
    };
    b.text(&format!("$MeshFormat\n4.1 1 {size_t}\n")).i(1);
    b.text("\n$EndMeshFormat\n$PhysicalNames\n2\n2 7 \"skin\"\n3 9 \"solid part\"\n$EndPhysicalNames\n");
    b.text("$Entities\n").z(0).z(0).z(1).z(1);
    b.i(3).d(0.).d(0.).d(0.).d(1.).d(1.).d(1.).z(1).i(7).z(0);
    b.i(5)
        .d(0.)
        .d(0.)
        .d(0.)
        .d(1.)
        .d(1.)
        .d(1.)
        .z(2)
        .i(9)
        .i(11)
        .z(1)
        .i(3);
    b.text("\n$EndEntities\n$Nodes\n").z(2).z(5).z(10).z(50);
    b.i(3).i(5).i(0).z(4).z(10).z(20).z(30).z(40);
    for p in [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]] {
        b.d(p[0]).d(p[1]).d(p[2]);
    }
    b.i(2)
        .i(3)
        .i(1)
        .z(1)
        .z(50)
        .d(0.5)
        .d(0.5)
        .d(0.)
        .d(0.25)
        .d(0.75);
    b.text("\n$EndNodes\n$Elements\n").z(2).z(2).z(1).z(2);
    b.i(3).i(5).i(4).z(1).z(1).z(10).z(20).z(30).z(40);
    b.i(2).i(3).i(2).z(1).z(2).z(10).z(30).z(20);
    b.text("\n$EndElements\n$NodeData\n1\n\"T\"\n1\n0.5\n3\n0\n1\n2\n")
        .i(10)
        .d(1.5)
        .i(50)
        .d(2.5);
    b.text("\n$EndNodeData\n");
    b.out
}

#[test]
fn binary_41_in_both_byte_orders_and_size_t_widths_equals_ascii() {
    let mut a = read(V41.as_bytes()).unwrap();
    a.point_data.arrays.retain(|x| x.name != "T@4");
    a.cell_data.arrays.retain(|x| x.name != "flux");
    a.field_data.retain(|x| x.name != "gmsh:time:flux");
    if let Some(t) = a.field_data.iter_mut().find(|x| x.name == "gmsh:time:T") {
        t.data = ArrayData::Float64(vec![0.5]);
    }
    for (be, st) in [(false, 8), (true, 8), (false, 4)] {
        let g = read(&v41_binary(be, st)).unwrap_or_else(|e| panic!("{be} {st}: {e}"));
        assert_eq!(format!("{g:?}"), format!("{a:?}"), "be {be} size_t {st}");
    }
}

const V22: &str = r#"$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
7
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 1 1 0
6 0 1 1
9 1 1 1
$EndNodes
$Elements
3
1 4 2 9 5 1 2 3 4
2 6 2 9 5 1 2 3 4 5 6
7 15 0 9
$EndElements
"#;

#[test]
fn reads_msh22_ascii_and_flips_prisms() {
    let g = read(V22.as_bytes()).unwrap();
    g.validate().unwrap();
    assert_eq!(g.cells.types, vec![ct::TETRA, ct::WEDGE, ct::VERTEX]);
    assert_eq!(g.cells.cell(1), &[0, 2, 1, 3, 5, 4]);
    let cd = &g.cell_data.arrays;
    assert_eq!(arr(cd, names::PHYSICAL), &ArrayData::Int32(vec![9, 9, 0]));
    assert_eq!(
        arr(cd, names::GEOMETRICAL),
        &ArrayData::Int32(vec![5, 5, 0])
    );
    assert_eq!(
        arr(cd, names::ELEMENT_TAG),
        &ArrayData::Int64(vec![1, 2, 7])
    );
    assert!(g.point_data.get(names::PARAMETRIC).is_none());
    assert!(g.field_data.is_empty());
}

fn v22_binary(be: bool) -> Vec<u8> {
    let mut b = Bin {
        out: Vec::new(),
        be,
        size_t: 8,
    };
    b.text("$MeshFormat\n2.2 1 8\n")
        .i(1)
        .text("\n$EndMeshFormat\n$Nodes\n7\n");
    let pts = [
        (1, [0., 0., 0.]),
        (2, [1., 0., 0.]),
        (3, [0., 1., 0.]),
        (4, [0., 0., 1.]),
        (5, [1., 1., 0.]),
        (6, [0., 1., 1.]),
        (9, [1., 1., 1.]),
    ];
    for (t, p) in pts {
        b.i(t).d(p[0]).d(p[1]).d(p[2]);
    }
    b.text("\n$EndNodes\n$Elements\n3\n");
    b.i(4).i(1).i(2).i(1).i(9).i(5).i(1).i(2).i(3).i(4);
    b.i(6)
        .i(1)
        .i(2)
        .i(2)
        .i(9)
        .i(5)
        .i(1)
        .i(2)
        .i(3)
        .i(4)
        .i(5)
        .i(6);
    b.i(15).i(1).i(0).i(7).i(9);
    b.text("\n$EndElements\n");
    b.out
}

#[test]
fn binary_22_equals_ascii() {
    let a = read(V22.as_bytes()).unwrap();
    for be in [false, true] {
        let g = read(&v22_binary(be)).unwrap();
        assert_eq!(g, a, "big endian {be}");
    }
}

#[test]
fn second_order_node_orders() {
    // A 10-node tet: Gmsh's edge nodes 8 and 9 (edges 3-2 and 3-1) swap places in VTK.
    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 .5 0 0\n6 .5 .5 0\n7 0 .5 0\n8 0 0 .5\n9 0 .5 .5\n10 .5 0 .5\n$EndNodes\n$Elements\n1\n1 11 0 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";
    let g = read(text.as_bytes()).unwrap();
    assert_eq!(g.cells.types, vec![ct::QUADRATIC_TETRA]);
    assert_eq!(g.cells.cell(0), &[0, 1, 2, 3, 4, 5, 6, 7, 9, 8]);
    // Each VTK mid-edge node lies halfway along VTK's edge.
    let edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];
    let ids = g.cells.cell(0);
    for (k, (a, b)) in edges.iter().enumerate() {
        let (pa, pb, pm) = (
            g.point(ids[*a] as usize),
            g.point(ids[*b] as usize),
            g.point(ids[4 + k] as usize),
        );
        for d in 0..3 {
            assert_eq!((pa[d] + pb[d]) / 2.0, pm[d], "edge {k}");
        }
    }
}

fn replace(text: &str, from: &str, to: &str) -> Vec<u8> {
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1).into_bytes()
}

fn assert_err(e: &FormatError, place: Place, needle: &str) {
    assert_eq!(e.place, place, "{e}");
    assert!(e.to_string().contains(needle), "{e}");
    assert!(e.to_string().starts_with("t.msh: "), "{e}");
}

#[test]
fn every_truncation_is_an_error_not_a_panic() {
    for text in [
        V41.as_bytes().to_vec(),
        V22.as_bytes().to_vec(),
        v41_binary(false, 8),
        v22_binary(true),
    ] {
        // Cutting inside the trailing `$End...` line or after the last section still fails or
        // reads; it must never panic.
        for n in 0..text.len() {
            let _ = read(&text[..n]);
        }
        // A cut in the middle of the nodes is an error naming the place.
        let cut = text.len() / 2;
        assert!(read(&text[..cut]).is_err());
    }
    let e = err(&V41.as_bytes()[..V41.find("1 0 0\n").unwrap()]);
    assert!(matches!(e.place, Place::Line(_)), "{e}");
    let bin = v22_binary(false);
    let e = err(&bin[..100]);
    // The error is at the value the file cuts, not at the cut.
    assert_err(
        &e,
        Place::Byte(97),
        "ends in the middle of a node coordinate",
    );
}

#[test]
fn unknown_node_tag_names_the_element() {
    let e = err(&replace(V22, "1 4 2 9 5 1 2 3 4", "1 4 2 9 5 1 2 3 8"));
    assert_err(&e, Place::Line(16), "element 1 refers to node 8");
    let e = err(&replace(V41, "2 10 30 20", "2 10 30 21"));
    assert_err(&e, Place::Line(34), "element 2 refers to node 21");
}

#[test]
fn versions_other_than_41_and_22_are_refused_by_name() {
    for (v, needle) in [
        ("3.0", "MSH 3"),
        ("4", "MSH 4.0"),
        ("4.0", "MSH 4.0"),
        ("5.2", "does not know"),
    ] {
        let e = err(&replace(V22, "2.2 0 8", &format!("{v} 0 8")));
        assert_err(&e, Place::Line(2), needle);
        assert!(e.to_string().contains(&format!("MSH version {v}")), "{e}");
    }
    let e = err(b"$NOD\n1\n1 0 0 0\n$ENDNOD\n");
    assert!(e.to_string().contains("MSH 1"), "{e}");
}

#[test]
fn order_3_elements_are_refused_by_type_and_place() {
    let e = err(&replace(
        V22,
        "7 15 0 9",
        "7 29 0 1 2 3 4 5 6 9 1 2 3 4 5 6 9 1 2 3 4 5 6",
    ));
    assert_err(
        &e,
        Place::Line(18),
        "element type 29 (20-node tetrahedron) is of order 3",
    );
    let e = err(&replace(V41, "3 5 4 1", "3 5 26 1"));
    assert_err(
        &e,
        Place::Line(31),
        "element type 26 (4-node line) is of order 3",
    );
    let e = err(&replace(V41, "3 5 4 1", "3 5 99 1"));
    assert_err(&e, Place::Line(31), "types 1-19");
}

#[test]
fn bad_numbers_counts_and_markers() {
    let e = err(&replace(V22, "2 1 0 0", "2 1 x 0"));
    assert_err(&e, Place::Line(7), "a node coordinate is 'x', not a number");
    let e = err(&replace(V22, "$EndNodes", "$EndNode"));
    assert_err(&e, Place::Line(13), "expected $EndNodes, found '$EndNode'");
    let e = err(&replace(V22, "$EndElements", "$EndNodes"));
    assert_err(&e, Place::Line(19), "expected $EndElements");
    let e = err(&replace(V41, "2 5 10 50", "2 6 10 50"));
    assert_err(&e, Place::Line(15), "counts 6 nodes, its blocks hold 5");
    let e = err(&replace(V22, "2.2 0 8", "2.2 2 8"));
    assert_err(&e, Place::Line(2), "file type 2");
    let e = err(&replace(V22, "2.2 0 8", "2.2 0 4"));
    assert_err(&e, Place::Line(2), "data size 4");
    let e = err(&replace(V22, "4 0 0 1", "1 0 0 1"));
    assert_err(&e, Place::Line(9), "node tag 1 appears twice");
    let e = err(&replace(V22, "5 1 1 0", "5 1 1 inf"));
    assert_err(&e, Place::Line(10), "non-finite");
    let e = err(&replace(V22, "$Nodes\n7", "$Nodes\n-7"));
    assert_err(&e, Place::Line(5), "not a non-negative integer");
    let e = err(&replace(V41, "\"skin\"", "skin"));
    assert_err(&e, Place::Line(6), "not a \"quoted\" string");
    let e = err(&replace(V41, "$EndCustom", "$EndCustard"));
    assert_err(
        &e,
        Place::Line(37),
        "section $Custom has no $EndCustom line",
    );
    let e = err(&replace(V41, "20 7\n", "21 7\n"));
    assert!(
        e.to_string()
            .contains("value for node 21, which the mesh does not have"),
        "{e}"
    );
    let e = err(&replace(V41, "$Elements", "$EndThings"));
    assert!(
        e.to_string()
            .contains("$EndThings without its opening section"),
        "{e}"
    );
    let e = err(b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Elements\n0 0 0 0\n$EndElements\n");
    assert!(
        e.to_string()
            .contains("$Elements before the $Nodes section"),
        "{e}"
    );
    let e = err(b"# vtk DataFile\n");
    assert_err(&e, Place::Line(1), "expected $MeshFormat");
}

#[test]
fn binary_errors_give_byte_offsets() {
    let mut bin = v22_binary(false);
    // The byte order check, 4 bytes after "2.2 1 8\n".
    let at = "$MeshFormat\n2.2 1 8\n".len();
    bin[at] = 7;
    let e = err(&bin);
    assert_err(&e, Place::Byte(at as u64), "byte order check reads 7");
    // An unknown node in a binary element.
    let mut bin = v22_binary(false);
    let tail = bin.len() - "\n$EndElements\n".len();
    bin[tail - 4] = 8;
    let e = err(&bin);
    assert!(matches!(e.place, Place::Byte(_)), "{e}");
    assert!(e.to_string().contains("element 7 refers to node 8"), "{e}");
}

#[test]
fn huge_counts_fail_on_the_data_without_allocating() {
    let e = err(&replace(V22, "$Nodes\n7", "$Nodes\n18446744073709551615"));
    assert!(
        e.to_string().contains("unexpected end of file") || e.to_string().contains("$EndNodes"),
        "{e}"
    );
    let e = err(&replace(V41, "2 5 10 50", "18446744073709551615 5 10 50"));
    assert!(matches!(e.place, Place::Line(_)), "{e}");
    let mut b = Bin {
        out: Vec::new(),
        be: false,
        size_t: 8,
    };
    b.text("$MeshFormat\n4.1 1 8\n")
        .i(1)
        .text("\n$EndMeshFormat\n$Nodes\n");
    b.z(1)
        .z(u64::MAX / 2)
        .z(1)
        .z(u64::MAX / 2)
        .i(3)
        .i(1)
        .i(0)
        .z(u64::MAX / 2);
    let e = err(&b.out);
    assert!(
        e.to_string().contains("ends in the middle of a node tag"),
        "{e}"
    );
    let e = err(&replace(V41, "1\n2\n10 1.5", "1\n4000000000\n10 1.5"));
    assert!(matches!(e.place, Place::Line(_)), "{e}");
}

#[test]
fn physical_group_and_pyramid_conventions() {
    // An entity in two physical groups keeps the first (a warning says so).
    let g = read(V41.as_bytes()).unwrap();
    assert_eq!(
        arr(&g.cell_data.arrays, names::PHYSICAL),
        &ArrayData::Int32(vec![9, 7])
    );
    // A 14-node pyramid keeps 13 nodes: the base centre (Gmsh node 13) goes.
    let mut text = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n14\n");
    for i in 1..=14 {
        text.push_str(&format!("{i} {i} {} 0\n", i * i));
    }
    text.push_str(
        "$EndNodes\n$Elements\n1\n1 14 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14\n$EndElements\n",
    );
    let g = read(text.as_bytes()).unwrap();
    assert_eq!(g.cells.types, vec![ct::QUADRATIC_PYRAMID]);
    assert_eq!(g.cells.cell(0), &[0, 1, 2, 3, 4, 5, 8, 10, 6, 7, 9, 11, 12]);
}

#[test]
fn format_plumbing() {
    assert_eq!(crate::sniff(V41.as_bytes()), Some(crate::Format::Msh));
    assert_eq!(crate::Format::from_name("gmsh"), Some(crate::Format::Msh));
    assert_eq!(
        crate::Format::from_path(Path::new("a.MSH")).unwrap(),
        crate::Format::Msh
    );
    let g = crate::read_bytes(V22.as_bytes(), crate::Format::Msh).unwrap();
    assert_eq!(g.num_cells(), 3);
    let e = crate::write(Path::new("/nonexistent/x.msh"), &g, &Default::default()).unwrap_err();
    assert!(e.to_string().contains("does not write it"), "{e}");
}

#[test]
fn view_headers_are_checked() {
    let e = err(&replace(V41, "0\n3\n1\n2 1 2 3", "0\n10\n1\n2 1 2 3"));
    assert!(
        e.to_string()
            .contains("$ElementData has 10 components; Gmsh writes 1 to 9"),
        "{e}"
    );
    let e = err(&replace(V41, "3\n4\n1\n1\n20 7", "2\n4\n1\n20 7"));
    assert!(
        e.to_string()
            .contains("$NodeData has 2 integer tags; it needs 3"),
        "{e}"
    );
    // A view without a string tag is named `view`.
    let g = read(&replace(V41, "1\n\"flux\"\n", "0\n")).unwrap();
    assert_eq!(g.cell_data.get("view").unwrap().components, 3);
    // A view before the mesh it refers to is refused.
    let e =
        err(b"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$NodeData\n0\n0\n3\n0\n1\n0\n$EndNodeData\n");
    assert!(
        e.to_string()
            .contains("$NodeData before the $Nodes section"),
        "{e}"
    );
}

#[test]
fn corrupt_bytes_give_errors_not_panics() {
    for text in [
        V41.as_bytes().to_vec(),
        V22.as_bytes().to_vec(),
        v41_binary(false, 8),
        v41_binary(true, 4),
        v22_binary(false),
    ] {
        for i in 0..text.len() {
            for b in [b'9', b'-', b' ', b'\n', b'$', 0xff, 0x7f, 0] {
                let mut t = text.clone();
                t[i] = b;
                if let Ok(g) = read(&t) {
                    g.validate().unwrap();
                }
            }
        }
    }
}

/// Every other refusal, each from a one-place change to a valid file: (file, from, to, message).
#[test]
fn every_other_refusal_names_what_was_wrong() {
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            V22,
            "$EndMeshFormat\n",
            "$EndMeshFormat\n$MeshFormat\n",
            "a second $MeshFormat section",
        ),
        (
            V22,
            "$EndNodes\n",
            "$EndNodes\n$Nodes\n0\n$EndNodes\n",
            "a second $Nodes section",
        ),
        (
            V22,
            "$Nodes\n",
            "Nodes\n",
            "expected a section ($Nodes, $Elements, ...), found 'Nodes'",
        ),
        (
            V22,
            "$Nodes\n",
            "$Nodes extra\n",
            "unexpected text at the end of the line",
        ),
        (
            V22,
            "2 1 0 0",
            "2147483648 1 0 0",
            "a node number 2147483648 does not fit 32 bits",
        ),
        (V22, "1 4 2 9 5", "1 4 2000 9 5", "element 1 has 2000 tags"),
        (
            V41,
            "\"skin\"",
            "\"skin",
            "has no closing quote on its line",
        ),
        (
            V41,
            "3 0 0 0 1 1 1 1 7 0",
            "3 0 0 0 1 1 1 99999 7 0",
            "99999 physical tags cannot fit",
        ),
        (
            V41,
            "2 9 11 1 3",
            "2 9 11 99999 3",
            "99999 bounding entities cannot fit",
        ),
        (
            V41,
            "3 5 0 4\n",
            "4 5 0 4\n",
            "node block of dimension 4 with parametric flag 0",
        ),
        (
            V41,
            "2 3 1 1\n",
            "2 3 2 1\n",
            "node block of dimension 2 with parametric flag 2",
        ),
        (
            V41,
            "\n50\n",
            "\n9223372036854775808\n",
            "node tag 9223372036854775808 is too large",
        ),
        (
            V41,
            "2 2 1 2\n",
            "2 3 1 2\n",
            "counts 3 elements, its blocks hold 2",
        ),
        (
            V41,
            "0\n3\n1\n2 1 2 3",
            "0\n3\n1\n2 1 2 3\n$EndElementData\n$ElementData\n1\n\"flux\"\n1\n0\n3\n0\n1\n1\n2 5",
            "view 'flux' step 0 has 1 components here and 3 before",
        ),
        (V41, "1 4 1 2 3 4", "1 -4 1 2 3 4", "-4 nodes per element"),
    ];
    for (text, from, to, needle) in cases {
        let e = err(&replace(text, from, to));
        assert!(e.to_string().contains(needle), "{to:?}: {e}");
        assert!(e.to_string().starts_with("t.msh: line "), "{e}");
    }
    // Binary: a group of elements larger than what is left to read.
    let mut bin = v22_binary(false);
    let at = bin.windows(4).position(|w| w == b"\n3\n\x04").unwrap() + 3;
    bin[at + 4] = 9;
    let e = err(&bin);
    assert_err(
        &e,
        Place::Byte(at as u64),
        "a group of 9 elements, 3 left to read",
    );
}

/// The hand-made V41 file split into partitions: the tet's volume (no physical tag of its own,
/// on the interface of partitions 2 and 1) and the triangle's surface (its own tag 4).
fn v41_partitioned() -> Vec<u8> {
    let text = V41
        .replace(
            "$Nodes\n",
            "$PartitionedEntities\n2\n1\n9 1\n0 0 1 1\n\
             8 2 3 1 2 0 0 0 1 1 1 1 4 0\n\
             7 3 5 2 2 1 0 0 0 1 1 1 0 0\n$EndPartitionedEntities\n$Nodes\n",
        )
        .replace("3 5 4 1\n1 10", "3 7 4 1\n1 10")
        .replace("2 3 2 1\n2 10", "2 8 2 1\n2 10");
    text.into_bytes()
}

fn int32s<'g>(g: &'g [crate::DataArray], name: &str) -> Option<&'g [i32]> {
    match &g.iter().find(|a| a.name == name)?.data {
        ArrayData::Int32(v) => Some(v),
        _ => None,
    }
}

#[test]
fn partitioned_entities_give_physical_groups_and_partitions() -> Result<()> {
    let g = read(&v41_partitioned())?;
    let cd = &g.cell_data.arrays;
    // The volume has no tag of its own: its parent's first (9); the surface its own (4).
    assert_eq!(int32s(cd, names::PHYSICAL), Some(&[9, 4][..]));
    assert_eq!(int32s(cd, names::PARTITION), Some(&[2, 2][..]));
    assert_eq!(int32s(cd, names::GEOMETRICAL), Some(&[7, 8][..]));
    let plain = read(V41.as_bytes())?;
    assert!(int32s(&plain.cell_data.arrays, names::PARTITION).is_none());
    Ok(())
}

#[test]
fn partitioned_entities_errors_name_the_place() {
    let s = String::from_utf8_lossy(&v41_partitioned()).into_owned();
    let two_surfaces =
        s.replacen("0 0 1 1\n8 2", "0 0 2 0\n8 2", 1)
            .replacen("7 3 5 2 2 1", "8 3 5 2 2 1", 1);
    let cut = s.find("7 3 5 2").map_or(0, |i| i + 9);
    for (text, needle) in [
        (
            s.replacen("7 3 5 2 2 1", "7 3 5 0 2 1", 1),
            "is in no partition",
        ),
        (two_surfaces, "appears twice"),
        (
            s.replacen("$EndPartitionedEntities", "", 1),
            "expected $EndPartitionedEntities",
        ),
        (s[..cut].to_string(), "partition"),
    ] {
        let e = read(text.as_bytes()).err();
        assert!(
            e.as_ref().is_some_and(
                |e| e.to_string().contains(needle) && matches!(e.place, Place::Line(_))
            ),
            "{needle}: {e:?}"
        );
    }
}

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/msh")
        .join(name)
}

/// Physical group of each tetrahedron and triangle, by its centroid (to 1e-9).
fn groups_by_centroid(g: &Grid) -> std::collections::BTreeMap<(u8, [i64; 3]), i32> {
    let phys = int32s(&g.cell_data.arrays, names::PHYSICAL).unwrap_or(&[]);
    let mut out = std::collections::BTreeMap::new();
    for (i, &p) in phys.iter().enumerate() {
        let t = g.cells.types[i];
        let ids = g.cells.cell(i);
        let mut c = [0i64; 3];
        for (k, ck) in c.iter_mut().enumerate() {
            let sum: f64 = ids.iter().map(|&v| g.point(v as usize)[k]).sum();
            *ck = (sum / ids.len() as f64 * 1e9).round() as i64;
        }
        out.insert((t, c), p);
    }
    out
}

#[test]
fn gmsh_partitioned_files_keep_the_physical_groups_of_the_unpartitioned_mesh() -> Result<()> {
    let whole = read_path(&fixture("twobodies_41.msh"))?;
    let ascii = read_path(&fixture("twobodies_part_41.msh"))?;
    let binary = read_path(&fixture("twobodies_part_41_bin.msh"))?;
    // ASCII coordinates carry 16 significant digits, binary ones all 17.
    assert!(ascii.cells == binary.cells && ascii.cell_data == binary.cell_data);
    let (a, b) = (ascii.points_f64(), binary.points_f64());
    assert!(
        a.len() == b.len()
            && a.iter()
                .zip(&b)
                .all(|(p, q)| (0..3).all(|k| (p[k] - q[k]).abs() < 1e-12))
    );
    let want = groups_by_centroid(&whole);
    let got = groups_by_centroid(&ascii);
    let count = |m: &std::collections::BTreeMap<(u8, [i64; 3]), i32>, t: u8, p: i32| {
        m.iter().filter(|(k, &v)| k.0 == t && v == p).count()
    };
    for (t, p) in [(ct::TETRA, 1), (ct::TETRA, 2), (ct::TRIANGLE, 3)] {
        assert!(count(&want, t, p) > 0, "type {t} group {p}");
        assert_eq!(count(&got, t, p), count(&want, t, p), "type {t} group {p}");
    }
    // Every tetrahedron and every boxtop triangle is where it was, in the same group; Gmsh
    // adds triangles on the interface between the partitions (in the box's group).
    for (k, p) in &want {
        assert_eq!(got.get(k), Some(p), "{k:?}");
    }
    assert!(got.values().all(|&p| p > 0));
    let parts = int32s(&ascii.cell_data.arrays, names::PARTITION).unwrap_or(&[]);
    assert_eq!(parts.len(), ascii.num_cells());
    for p in [1, 2] {
        assert!(parts.contains(&p), "partition {p}");
    }
    assert!(parts.iter().all(|p| [1, 2].contains(p)));
    // MSH 2.2 keeps the partitions in the element tags: the same groups, the same cells.
    let v22 = read_path(&fixture("twobodies_part_22.msh"))?;
    let got22 = groups_by_centroid(&v22);
    for (k, p) in &want {
        assert_eq!(got22.get(k), Some(p), "2.2: {k:?}");
    }
    let parts22 = int32s(&v22.cell_data.arrays, names::PARTITION).unwrap_or(&[]);
    assert_eq!(parts22.len(), v22.num_cells());
    assert!(parts22.contains(&1) && parts22.contains(&2));
    assert!(parts22.iter().all(|p| [1, 2].contains(p)));
    // An unpartitioned 2.2 file has no partition array.
    let plain = read_path(&fixture("block_hole_22.msh"))?;
    assert!(plain.cell_data.get(names::PARTITION).is_none());
    Ok(())
}

#[test]
fn physical_names_that_are_not_utf8_are_kept_lossily() -> Result<()> {
    let mut text = V41.as_bytes().to_vec();
    let at = text.windows(4).position(|w| w == b"skin").unwrap_or(0);
    text[at + 2] = 0xef;
    let g = read(&text)?;
    let names_ = g
        .field_data
        .iter()
        .find(|a| a.name == names::PHYSICAL_NAMES);
    assert!(names_.is_some_and(
        |a| a.data == ArrayData::String(vec!["sk\u{fffd}n".into(), "solid part".into()])
    ));
    Ok(())
}
