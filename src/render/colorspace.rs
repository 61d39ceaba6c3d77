//! Colour interpolation in the spaces a ParaView preset names (`ColorSpace`: RGB, HSV, Lab, Diverging, Step), with VTK's conversions.

use anyhow::{bail, Result};
use std::f64::consts::PI;

/// How colours between two control points are mixed, as `vtkColorTransferFunction` does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorSpace {
    Rgb,
    /// Hue the short way round the circle (VTK's `HSVWrap`, on by default).
    Hsv,
    /// CIELAB under D65, from sRGB.
    Lab,
    /// Moreland's diverging interpolation in Msh (white between distinct saturated hues).
    Diverging,
    /// The next point's colour all the way from just past a point to that next point (VTK's
    /// step).
    Step,
}

impl ColorSpace {
    /// Parses a preset's `ColorSpace` as ParaView writes it (case-insensitive). `Lab/CIEDE2000`
    /// is taken as Lab, which `warn` is told.
    pub fn parse(s: &str, mut warn: impl FnMut(String)) -> Result<ColorSpace> {
        Ok(match s.to_ascii_lowercase().as_str() {
            "rgb" => ColorSpace::Rgb,
            "hsv" => ColorSpace::Hsv,
            "lab" | "cielab" => ColorSpace::Lab,
            "lab/ciede2000" => {
                warn(format!(
                    "ColorSpace '{s}' is interpolated in Lab (the CIEDE2000 path is not modelled)"
                ));
                ColorSpace::Lab
            }
            "diverging" => ColorSpace::Diverging,
            "step" => ColorSpace::Step,
            _ => {
                bail!("ColorSpace '{s}': expected RGB, HSV, Lab, Lab/CIEDE2000, Diverging or Step")
            }
        })
    }

    /// The colour a fraction `t` in [0, 1] of the way from `a` to `b` (sRGB in [0, 1]).
    pub fn mix(self, a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
        let lerp =
            |x: [f64; 3], y: [f64; 3], t: f64| std::array::from_fn(|k| x[k] + t * (y[k] - x[k]));
        match self {
            ColorSpace::Rgb => lerp(a, b, t),
            ColorSpace::Step => {
                if t > 0.0 {
                    b
                } else {
                    a
                }
            }
            ColorSpace::Hsv => {
                let (mut ha, mut hb) = (rgb_to_hsv(a), rgb_to_hsv(b));
                // The short way round: step over the wrap where the hues are more than half a
                // turn apart.
                if hb[0] - ha[0] > 0.5 {
                    ha[0] += 1.0;
                } else if ha[0] - hb[0] > 0.5 {
                    hb[0] += 1.0;
                }
                let mut h = lerp(ha, hb, t);
                if h[0] >= 1.0 {
                    h[0] -= 1.0;
                }
                hsv_to_rgb(h)
            }
            ColorSpace::Lab => lab_to_rgb(lerp(rgb_to_lab(a), rgb_to_lab(b), t)),
            ColorSpace::Diverging => diverging(a, b, t),
        }
    }
}

fn rgb_to_hsv(c: [f64; 3]) -> [f64; 3] {
    let (r, g, b) = (c[0], c[1], c[2]);
    let max = r.max(g).max(b);
    let min = r.min(g).min(b);
    let v = max;
    let s = if max > 0.0 { (max - min) / max } else { 0.0 };
    if s <= 0.0 {
        return [0.0, 0.0, v];
    }
    let d = max - min;
    let h = if r == max {
        (g - b) / d / 6.0
    } else if g == max {
        (2.0 + (b - r) / d) / 6.0
    } else {
        (4.0 + (r - g) / d) / 6.0
    };
    [if h < 0.0 { h + 1.0 } else { h }, s, v]
}

fn hsv_to_rgb(c: [f64; 3]) -> [f64; 3] {
    let (h, s, v) = (c[0].rem_euclid(1.0) * 6.0, c[1], c[2]);
    let i = (h.floor() as i64).clamp(0, 5);
    let f = h - i as f64;
    let (p, q, u) = (v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f)));
    match i {
        0 => [v, u, p],
        1 => [q, v, p],
        2 => [p, v, u],
        3 => [p, q, v],
        4 => [u, p, v],
        _ => [v, p, q],
    }
}

/// D65 white, as VTK's `vtkMath` takes it.
const WHITE: [f64; 3] = [0.9505, 1.000, 1.089];

fn rgb_to_lab(c: [f64; 3]) -> [f64; 3] {
    let lin = c.map(|v| {
        if v > 0.04045 {
            ((v + 0.055) / 1.055).powf(2.4)
        } else {
            v / 12.92
        }
    });
    let xyz = [
        lin[0] * 0.4124 + lin[1] * 0.3576 + lin[2] * 0.1805,
        lin[0] * 0.2126 + lin[1] * 0.7152 + lin[2] * 0.0722,
        lin[0] * 0.0193 + lin[1] * 0.1192 + lin[2] * 0.9505,
    ];
    let f = |t: f64| {
        if t > 0.008856 {
            t.cbrt()
        } else {
            7.787 * t + 16.0 / 116.0
        }
    };
    let [fx, fy, fz] = [0, 1, 2].map(|k| f(xyz[k] / WHITE[k]));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

fn lab_to_rgb(lab: [f64; 3]) -> [f64; 3] {
    let fy = (lab[0] + 16.0) / 116.0;
    let fx = lab[1] / 500.0 + fy;
    let fz = fy - lab[2] / 200.0;
    let inv = |t: f64| {
        let t3 = t * t * t;
        if t3 > 0.008856 {
            t3
        } else {
            (t - 16.0 / 116.0) / 7.787
        }
    };
    let [x, y, z] = [0, 1, 2].map(|k| inv([fx, fy, fz][k]) * WHITE[k]);
    let lin = [
        x * 3.2406 + y * -1.5372 + z * -0.4986,
        x * -0.9689 + y * 1.8758 + z * 0.0415,
        x * 0.0557 + y * -0.2040 + z * 1.0570,
    ];
    let mut c = lin.map(|v| {
        if v > 0.0031308 {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        } else {
            12.92 * v
        }
    });
    // Out of gamut: scaled down into it, then negatives cut, as VTK clips.
    let max = c[0].max(c[1]).max(c[2]);
    if max > 1.0 {
        c = c.map(|v| v / max);
    }
    c.map(|v| v.max(0.0))
}

fn rgb_to_msh(c: [f64; 3]) -> [f64; 3] {
    let lab = rgb_to_lab(c);
    let m = (lab[0] * lab[0] + lab[1] * lab[1] + lab[2] * lab[2]).sqrt();
    let s = if m > 0.001 { (lab[0] / m).acos() } else { 0.0 };
    let h = if s > 0.001 { lab[2].atan2(lab[1]) } else { 0.0 };
    [m, s, h]
}

fn msh_to_rgb(msh: [f64; 3]) -> [f64; 3] {
    let [m, s, h] = msh;
    lab_to_rgb([m * s.cos(), m * s.sin() * h.cos(), m * s.sin() * h.sin()])
}

/// Smallest angle between two hues, in [0, pi].
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).abs().rem_euclid(2.0 * PI);
    if d > PI {
        2.0 * PI - d
    } else {
        d
    }
}

/// Hue for an unsaturated end interpolating towards the saturated `msh`, spun so that the
/// path does not look like it passes through another hue (Moreland, 2009).
fn adjust_hue(msh: [f64; 3], unsat_m: f64) -> f64 {
    if msh[0] >= unsat_m - 0.1 {
        return msh[2];
    }
    let spin = msh[1] * (unsat_m * unsat_m - msh[0] * msh[0]).sqrt() / (msh[0] * msh[1].sin());
    if msh[2] > -0.3 * PI {
        msh[2] + spin
    } else {
        msh[2] - spin
    }
}

fn diverging(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    let (mut m1, mut m2) = (rgb_to_msh(a), rgb_to_msh(b));
    let mut t = t;
    // Distinct saturated ends: through a white (or light grey) middle.
    if m1[1] > 0.05 && m2[1] > 0.05 && angle_diff(m1[2], m2[2]) > PI / 3.0 {
        let mid = m1[0].max(m2[0]).max(88.0);
        if t < 0.5 {
            m2 = [mid, 0.0, 0.0];
            t *= 2.0;
        } else {
            m1 = [mid, 0.0, 0.0];
            t = 2.0 * t - 1.0;
        }
    }
    if m1[1] < 0.05 && m2[1] > 0.05 {
        m1[2] = adjust_hue(m2, m1[0]);
    } else if m2[1] < 0.05 && m1[1] > 0.05 {
        m2[2] = adjust_hue(m1, m2[0]);
    }
    msh_to_rgb(std::array::from_fn(|k| (1.0 - t) * m1[k] + t * m2[k]))
}

/// `points` (x, colour) made dense enough that linear RGB interpolation between them follows
/// `space`: `per` samples between each pair (the points themselves kept exactly).
pub fn densify(points: &[(f64, [f64; 3])], space: ColorSpace, per: usize) -> Vec<(f64, [f64; 3])> {
    if space == ColorSpace::Rgb || points.len() < 2 {
        return points.to_vec();
    }
    let mut out = Vec::with_capacity((points.len() - 1) * per + 1);
    for w in points.windows(2) {
        let ((x0, a), (x1, b)) = (w[0], w[1]);
        out.push((x0, a));
        if x1 <= x0 {
            continue;
        }
        if space == ColorSpace::Step {
            // The jump just past the point (a point exactly at x0 keeps its own colour).
            out.push((x0 + (x1 - x0) * 1e-9, b));
            continue;
        }
        for j in 1..per {
            let t = j as f64 / per as f64;
            out.push((x0 + t * (x1 - x0), space.mix(a, b, t)));
        }
    }
    if let Some(&last) = points.last() {
        out.push(last);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() <= tol)
    }

    #[test]
    fn red_to_blue_midpoints_match_vtk() {
        // vtkColorTransferFunction with points red at 0 and blue at 1, evaluated at 0.5 in
        // each space (VTK 9.1).
        let (red, blue) = ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        let mid = |s: ColorSpace| s.mix(red, blue, 0.5);
        assert!(close(mid(ColorSpace::Rgb), [0.5, 0.0, 0.5], 1e-12));
        assert!(close(mid(ColorSpace::Hsv), [1.0, 0.0, 1.0], 1e-12));
        assert!(
            close(mid(ColorSpace::Lab), [0.79, 0.0, 0.535], 0.01),
            "{:?}",
            mid(ColorSpace::Lab)
        );
        assert!(
            close(mid(ColorSpace::Diverging), [1.0, 1.0, 1.0], 0.01),
            "{:?}",
            mid(ColorSpace::Diverging)
        );
        assert_eq!(mid(ColorSpace::Step), blue);
        assert_eq!(ColorSpace::Step.mix(red, blue, 0.01), blue);
        assert_eq!(ColorSpace::Step.mix(red, blue, 0.0), red);
    }

    #[test]
    fn conversions_round_trip_and_ends_are_kept() {
        for c in [
            [0.2, 0.4, 0.6],
            [1.0, 1.0, 1.0],
            [0.0, 0.0, 0.0],
            [0.9, 0.1, 0.3],
            [0.01, 0.02, 0.0],
        ] {
            assert!(close(lab_to_rgb(rgb_to_lab(c)), c, 1e-3), "{c:?}");
            assert!(close(hsv_to_rgb(rgb_to_hsv(c)), c, 1e-12), "{c:?}");
            assert!(close(msh_to_rgb(rgb_to_msh(c)), c, 1e-3), "{c:?}");
        }
        let pts = vec![(0.0, [0.23, 0.299, 0.754]), (1.0, [0.706, 0.016, 0.15])];
        for s in [ColorSpace::Hsv, ColorSpace::Lab, ColorSpace::Diverging] {
            let d = densify(&pts, s, 16);
            assert_eq!(d.len(), 17);
            assert_eq!((d[0], d[16]), (pts[0], pts[1]));
            assert!(d.windows(2).all(|w| w[0].0 < w[1].0));
        }
        // Moreland's cool-to-warm ends meet in a light grey near (0.865, 0.865, 0.865).
        let m = ColorSpace::Diverging.mix(pts[0].1, pts[1].1, 0.5);
        assert!(close(m, [0.865, 0.865, 0.865], 0.01), "{m:?}");
    }

    #[test]
    fn names_parse_as_paraview_writes_them() {
        let mut warned = Vec::new();
        for (s, want) in [
            ("RGB", ColorSpace::Rgb),
            ("hsv", ColorSpace::Hsv),
            ("Lab", ColorSpace::Lab),
            ("Diverging", ColorSpace::Diverging),
            ("Step", ColorSpace::Step),
            ("Lab/CIEDE2000", ColorSpace::Lab),
        ] {
            assert!(
                matches!(ColorSpace::parse(s, |w| warned.push(w)), Ok(v) if v == want),
                "{s}"
            );
        }
        assert_eq!(warned.len(), 1);
        assert!(ColorSpace::parse("Bogus", |_| {}).is_err());
    }
}
