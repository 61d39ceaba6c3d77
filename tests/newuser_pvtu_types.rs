//! Parallel files whose pieces disagree on a type, as real ParaView/VTK writes give them: an
//! empty piece (a rank that owned no cells) has VTK's default Float32 points among Float64
//! pieces, and a piece may store an array in another type than the .pvtu declares. Both were
//! refused ("piece 1 has type Float32 but piece 0 has Float64"). VTK reads the first as tetkit
//! now does; for the second, VTK 9.1 reads the Float32 piece's bytes as doubles (values like
//! 1e248), where tetkit converts each piece's array to the declared type, value by value.

mod common;

use common::{assert_vtk_agrees, require_vtk, tempdir, tetkit, vtk_python};

const MAKE: &str = r#"
import sys, os, vtk
import numpy as np
from vtk.util import numpy_support as ns
d = sys.argv[1]
im = vtk.vtkImageData(); im.SetDimensions(4, 4, 4)
tf = vtk.vtkDataSetTriangleFilter(); tf.SetInputData(im); tf.Update(); g = tf.GetOutput()
pts = vtk.vtkPoints(); pts.SetDataTypeToDouble(); pts.DeepCopy(g.GetPoints()); g.SetPoints(pts)
a = ns.numpy_to_vtk(np.arange(g.GetNumberOfPoints(), dtype=np.float64) + 0.25, deep=1); a.SetName('pid')
g.GetPointData().AddArray(a)
a = ns.numpy_to_vtk(np.arange(g.GetNumberOfCells(), dtype=np.int32), deep=1); a.SetName('cid')
g.GetCellData().AddArray(a)
def piece(lo, hi, name, f32=False):
    ids = vtk.vtkIdList()
    for i in range(lo, hi): ids.InsertNextId(i)
    e = vtk.vtkExtractCells(); e.SetInputData(g); e.SetCellList(ids); e.Update()
    p = vtk.vtkUnstructuredGrid(); p.DeepCopy(e.GetOutput())
    p.GetPointData().RemoveArray('vtkOriginalPointIds'); p.GetCellData().RemoveArray('vtkOriginalCellIds')
    if hi == lo:
        # What a rank with no cells writes: VTK's default (Float32) points, none of them.
        p = vtk.vtkUnstructuredGrid(); p.SetPoints(vtk.vtkPoints())
        for n, t in (('pid', vtk.vtkDoubleArray), ('cid', vtk.vtkIntArray)):
            a = t(); a.SetName(n)
            (p.GetPointData() if n == 'pid' else p.GetCellData()).AddArray(a)
    if f32:
        v = ns.vtk_to_numpy(p.GetPointData().GetArray('pid')).astype(np.float32)
        a = ns.numpy_to_vtk(v, deep=1); a.SetName('pid')
        p.GetPointData().RemoveArray('pid'); p.GetPointData().AddArray(a)
    w = vtk.vtkXMLUnstructuredGridWriter(); w.SetInputData(p); w.SetFileName(os.path.join(d, name)); w.Write()
n = g.GetNumberOfCells()
piece(0, 60, 'a.vtu'); piece(60, 60, 'empty.vtu'); piece(60, n, 'c.vtu'); piece(60, n, 'c32.vtu', f32=True)
def pvtu(name, sources):
    with open(os.path.join(d, name), 'w') as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="PUnstructuredGrid" version="0.1" byte_order="LittleEndian">\n<PUnstructuredGrid GhostLevel="0">\n')
        f.write('<PPointData><PDataArray type="Float64" Name="pid"/></PPointData>\n')
        f.write('<PCellData><PDataArray type="Int32" Name="cid"/></PCellData>\n')
        f.write('<PPoints><PDataArray type="Float64" NumberOfComponents="3"/></PPoints>\n')
        for s in sources: f.write('<Piece Source="%s"/>\n' % s)
        f.write('</PUnstructuredGrid>\n</VTKFile>\n')
pvtu('empty.pvtu', ['a.vtu', 'empty.vtu', 'c.vtu'])
pvtu('f32.pvtu', ['a.vtu', 'c32.vtu'])
for name in ('empty.pvtu', 'f32.pvtu'):
    r = vtk.vtkXMLPUnstructuredGridReader(); r.SetFileName(os.path.join(d, name)); r.Update()
    o = r.GetOutput()
    print(name, o.GetNumberOfPoints(), o.GetNumberOfCells(), o.GetPointData().GetArray('pid').GetDataTypeAsString())
"#;

#[test]
fn pieces_of_other_types_are_converted_to_the_declared_type_as_vtk_does() {
    if !require_vtk("pieces_of_other_types_are_converted_to_the_declared_type_as_vtk_does") {
        return;
    }
    let dir = tempdir();
    let d = dir.path().to_str().unwrap();
    let said = vtk_python(MAKE, &[d]);
    // VTK reads both, the Float32 piece's values converted to the declared Float64.
    assert!(said.contains("empty.pvtu 84 135 double"), "{said}");
    assert!(said.contains("f32.pvtu 84 135 double"), "{said}");
    // Same counts, types and bits as VTK's reading.
    assert_vtk_agrees(&dir.path().join("empty.pvtu"));
    for name in ["empty.pvtu", "f32.pvtu"] {
        let path = dir.path().join(name);
        let g = tetkit::formats::read(&path).unwrap();
        assert_eq!(g.points.data.type_name(), "Float64", "{name}");
        let pid = g.point_data.get("pid").unwrap();
        assert_eq!(pid.data.type_name(), "Float64", "{name}");
        // Each piece's points are its own (pieces are not welded): the values are the pieces'
        // values in piece order, every one a quarter past an integer, as written.
        let v = pid.data.to_f64_vec();
        assert_eq!(v.len(), 84, "{name}");
        assert!(
            v.iter()
                .all(|x| x.fract() == 0.25 && (0.0..64.0).contains(x)),
            "{name}: {v:?}"
        );
        // Quarter values survive Float32 exactly: the conversion is silent.
        let r = tetkit(["info", path.to_str().unwrap()]);
        r.assert_success();
        assert!(!r.stderr.contains("warning"), "{name}: {}", r.stderr);
    }
}
