//! A ParaView preset's `ColorSpace` mixes colours as VTK's vtkColorTransferFunction does: RGB,
//! HSV, Lab, Diverging and Step, checked against VTK itself on pairs of colours.

mod common;

use tetkit::render::colorspace::ColorSpace;

const PAIRS: [([f64; 3], [f64; 3]); 5] = [
    ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
    ([0.23, 0.299, 0.754], [0.706, 0.016, 0.15]),
    ([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
    ([0.5, 0.5, 0.5], [0.1, 0.8, 0.2]),
    ([0.9, 0.9, 0.1], [0.1, 0.3, 0.9]),
];

#[test]
fn color_spaces_mix_as_vtk_does() {
    if !common::require_vtk("color_spaces_mix_as_vtk_does") {
        return;
    }
    let code = r#"
import sys, vtk
pairs = eval(sys.argv[1])
for space in ["RGB", "HSV", "Lab", "Diverging", "Step"]:
    for a, b in pairs:
        f = vtk.vtkColorTransferFunction()
        getattr(f, "SetColorSpaceTo" + space)()
        f.AddRGBPoint(0.0, *a)
        f.AddRGBPoint(1.0, *b)
        for i in range(21):
            t = i / 20.0
            print(space, t, *f.GetColor(t))
"#;
    let pairs = format!(
        "[{}]",
        PAIRS
            .iter()
            .map(|(a, b)| format!("({a:?}, {b:?})"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let out = common::vtk_python(code, &[&pairs]);
    let mut rows = out.lines();
    let mut worst = 0.0f64;
    for space in ["RGB", "HSV", "Lab", "Diverging", "Step"] {
        let s = ColorSpace::parse(space, |_| {});
        assert!(s.is_ok(), "{space}");
        let Ok(s) = s else { return };
        for (a, b) in PAIRS {
            for i in 0..21 {
                let t = i as f64 / 20.0;
                let row = rows.next().unwrap_or_default();
                let v: Vec<f64> = row
                    .split_whitespace()
                    .skip(1)
                    .filter_map(|x| x.parse().ok())
                    .collect();
                assert_eq!(v.len(), 4, "{row}");
                let ours = s.mix(a, b, t);
                let err = (0..3)
                    .map(|k| (ours[k] - v[k + 1]).abs())
                    .fold(0.0, f64::max);
                worst = worst.max(err);
                assert!(
                    err < 2e-3,
                    "{space} {a:?} -> {b:?} at {t}: ours {ours:?}, VTK {:?}",
                    &v[1..]
                );
            }
        }
    }
    eprintln!("worst difference from VTK over every space: {worst:.2e}");
}
