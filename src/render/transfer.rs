//! Transfer functions: scalar -> (colour, extinction), from named colormaps or ParaView presets.
//!
//! The function is piecewise linear between `K` evenly spaced nodes over the scalar range and
//! constant beyond it (ParaView clamps). Opacity has ParaView's "unit distance" meaning: a slab of
//! thickness `unit_distance` with constant scalar `s` has opacity `a(s)`, so the extinction is
//! `tau = -ln(1 - a) / unit_distance`. Extinction (not opacity) is what is linear between nodes,
//! which makes the ray integral of a linear scalar segment exactly computable piece by piece.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::colorspace::{densify, ColorSpace};
use anyhow::{anyhow, bail, Context, Result};
use std::path::Path;

/// Opacity never reaches 1 so that extinction stays finite (1e-6 of light passes a unit slab).
const MAX_OPACITY: f64 = 1.0 - 1e-6;

#[derive(Clone, Debug, PartialEq)]
pub struct TransferFunction {
    /// Scalar range the nodes span: node 0 at `range[0]`, node `K-1` at `range[1]`.
    pub range: [f64; 2],
    /// Colour at each node (RGB in [0, 1]).
    pub rgb: Vec<[f64; 3]>,
    /// Extinction per world unit at each node.
    pub tau: Vec<f64>,
}

/// A colour control point list: `(x, [r, g, b])` with x relative in [0, 1] or absolute.
type ColorPoints = Vec<(f64, [f64; 3])>;
/// Opacity control points `(x, a)`.
type OpacityPoints = Vec<(f64, f64)>;

/// Where colours come from.
#[derive(Clone, Debug, PartialEq)]
pub enum ColorSource {
    /// Evenly spaced colours over [0, 1].
    Relative(ColorPoints),
    /// A ParaView preset: points in the preset's own scalar units (rescaled onto the data range
    /// as ParaView does when it applies a preset), with its opacity points when it has them.
    Preset {
        name: String,
        colors: ColorPoints,
        opacity: Option<OpacityPoints>,
    },
}

/// Named colormaps: ParaView's default "Cool to Warm" (Moreland's diverging map, sampled) plus
/// every `colorous` gradient by lower-case name with `-` or `_`.
pub fn named_colormap(name: &str) -> Result<ColorSource> {
    // ParaView's preset names too: "Cool to Warm", "Viridis (matplotlib)", "X Ray".
    let lower = name.trim().to_ascii_lowercase();
    let key = lower
        .strip_suffix("(matplotlib)")
        .unwrap_or(&lower)
        .trim()
        .replace(['_', ' '], "-");
    // ParaView's two grey ramps, linear in RGB.
    match key.as_str() {
        "grayscale" => {
            return Ok(ColorSource::Relative(vec![
                (0.0, [0.0; 3]),
                (1.0, [1.0; 3]),
            ]))
        }
        "x-ray" => {
            return Ok(ColorSource::Relative(vec![
                (0.0, [1.0; 3]),
                (1.0, [0.0; 3]),
            ]))
        }
        _ => {}
    }
    if key == "cool-to-warm" || key == "coolwarm" {
        // Moreland's diverging map sampled at 9 points (sRGB), so RGB interpolation stays close
        // to ParaView's diverging interpolation.
        let pts = [
            [0.230, 0.299, 0.754],
            [0.375, 0.486, 0.904],
            [0.552, 0.690, 0.996],
            [0.720, 0.831, 0.996],
            [0.865, 0.865, 0.865],
            [0.957, 0.769, 0.678],
            [0.969, 0.605, 0.481],
            [0.882, 0.373, 0.298],
            [0.706, 0.016, 0.150],
        ];
        let n = pts.len() - 1;
        return Ok(ColorSource::Relative(
            pts.iter()
                .enumerate()
                .map(|(i, c)| (i as f64 / n as f64, *c))
                .collect(),
        ));
    }
    let g = match key.as_str() {
        "viridis" => colorous::VIRIDIS,
        "inferno" => colorous::INFERNO,
        "magma" => colorous::MAGMA,
        "plasma" => colorous::PLASMA,
        "cividis" => colorous::CIVIDIS,
        "turbo" => colorous::TURBO,
        "warm" => colorous::WARM,
        "cool" => colorous::COOL,
        "cubehelix" => colorous::CUBEHELIX,
        "spectral" => colorous::SPECTRAL,
        "red-blue" | "rdbu" => colorous::RED_BLUE,
        "rainbow" => colorous::RAINBOW,
        "sinebow" => colorous::SINEBOW,
        "greys" | "grays" => colorous::GREYS,
        "blues" => colorous::BLUES,
        "reds" => colorous::REDS,
        "greens" => colorous::GREENS,
        "oranges" => colorous::ORANGES,
        "purples" => colorous::PURPLES,
        "yellow-orange-red" | "ylorrd" => colorous::YELLOW_ORANGE_RED,
        _ => bail!(
            "unknown colormap '{name}' (try viridis, cool-to-warm, inferno, magma, plasma, cividis, turbo, \
             warm, cool, cubehelix, spectral, red-blue, rainbow, sinebow, greys, blues, reds, greens, \
             oranges, purples, yellow-orange-red, ParaView's Cool to Warm, Grayscale, X Ray and \
             the (matplotlib) ones by their names, or a ParaView preset .json: ParaView's Choose \
             Preset dialog exports any other map as one)"
        ),
    };
    let n = 64;
    Ok(ColorSource::Relative(
        (0..=n)
            .map(|i| {
                let c = g.eval_rational(i, n + 1);
                (
                    i as f64 / n as f64,
                    [c.r, c.g, c.b].map(|v| v as f64 / 255.0),
                )
            })
            .collect(),
    ))
}

/// Reads a ParaView colormap preset (the JSON ParaView's "Export preset" writes: a list of
/// objects with `RGBPoints` as x,r,g,b quadruples, optionally `Points` as x,a,mid,sharpness and
/// `ColorSpace`, which says how colours mix between points; see [`ColorSpace`]). Colours and
/// opacities outside [0, 1] are refused. An opacity point's midpoint is modelled as
/// vtkPiecewiseFunction does with sharpness 0 (half-way between the two values at that fraction
/// of the interval); a sharpness above that is drawn as sharpness 0 with a warning, as are
/// `UseLogScale` (colours are mapped linearly) and a file of several presets (the first with
/// `RGBPoints` is used, the warning names it). A categorical preset (`IndexedColors`, no
/// `RGBPoints`) is refused by name.
pub fn read_preset(path: &Path) -> Result<ColorSource> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("{}: reading", path.display()))?;
    // Windows editors save JSON with a byte-order mark, which serde_json refuses.
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let v: serde_json::Value = serde_json::from_str(text).map_err(|e| {
        anyhow!(
            "{}: line {} column {}: not JSON: {e}",
            path.display(),
            e.line(),
            e.column()
        )
    })?;
    let name_of = |o: &serde_json::Value| {
        o.get("Name")
            .and_then(|n| n.as_str())
            .unwrap_or("preset")
            .to_string()
    };
    let obj = match &v {
        serde_json::Value::Array(a) => {
            let Some(obj) = a.iter().find(|o| o.get("RGBPoints").is_some()) else {
                // ParaView's categorical presets ("Interpret Values As Categories") hold
                // IndexedColors and Annotations instead of RGBPoints.
                if let Some(c) = a.iter().find(|o| o.get("IndexedColors").is_some()) {
                    bail!(
                        "{}: preset '{}' is categorical (IndexedColors, ParaView's 'Interpret Values As Categories'), which tetkit does not draw; export a preset with RGBPoints",
                        path.display(),
                        name_of(c)
                    );
                }
                bail!("{}: no preset with RGBPoints in the list", path.display());
            };
            if a.len() > 1 {
                let others: Vec<String> = a
                    .iter()
                    .filter(|o| !std::ptr::eq(*o, obj))
                    .map(name_of)
                    .collect();
                eprintln!(
                    "tetkit: warning: {}: {} presets in the file; using '{}', the first with RGBPoints (not {})",
                    path.display(),
                    a.len(),
                    name_of(obj),
                    others.join(", ")
                );
            }
            obj
        }
        o => o,
    };
    let name = name_of(obj);
    if obj.get("UseLogScale").and_then(|b| b.as_bool()) == Some(true) {
        eprintln!(
            "tetkit: warning: {}: {name}: UseLogScale is not supported: colours and opacity are mapped linearly over the range",
            path.display()
        );
    }
    let nums = |key: &str| -> Result<Option<Vec<f64>>> {
        match obj.get(key) {
            None => Ok(None),
            Some(serde_json::Value::Array(a)) => a
                .iter()
                .enumerate()
                .map(|(i, x)| {
                    x.as_f64().filter(|f| f.is_finite()).ok_or_else(|| {
                        anyhow!(
                            "{}: {name}.{key}[{i}]: not a finite number: {x}",
                            path.display()
                        )
                    })
                })
                .collect::<Result<Vec<f64>>>()
                .map(Some),
            Some(other) => bail!("{}: {name}.{key}: not an array: {other}", path.display()),
        }
    };
    let rgb =
        nums("RGBPoints")?.ok_or_else(|| anyhow!("{}: {name}: no RGBPoints", path.display()))?;
    if rgb.len() < 4 || rgb.len() % 4 != 0 {
        bail!(
            "{}: {name}.RGBPoints: {} numbers, expected a positive multiple of 4 (x, r, g, b)",
            path.display(),
            rgb.len()
        );
    }
    let colors: ColorPoints = rgb
        .chunks(4)
        .enumerate()
        .map(|(i, c)| {
            let rgb = [c[1], c[2], c[3]];
            if rgb.iter().any(|v| !(0.0..=1.0).contains(v)) {
                bail!(
                    "{}: {name}.RGBPoints: point {i} (x = {}) has colour {rgb:?}, outside [0, 1]",
                    path.display(),
                    c[0]
                );
            }
            Ok((c[0], rgb))
        })
        .collect::<Result<_>>()?;
    check_increasing(colors.iter().map(|c| c.0), path, &name, "RGBPoints")?;
    // Colours between the points mix in the preset's space (ParaView's presets are mostly
    // Diverging or Lab); dense RGB points follow that path closely enough for the nodes.
    let space = match obj.get("ColorSpace") {
        None => ColorSpace::Rgb,
        Some(serde_json::Value::String(s)) => ColorSpace::parse(s, |w| {
            eprintln!("tetkit: warning: {}: {name}: {w}", path.display())
        })
        .map_err(|e| anyhow!("{}: {name}: {e}", path.display()))?,
        Some(other) => bail!(
            "{}: {name}.ColorSpace: not a string: {other}",
            path.display()
        ),
    };
    let colors = densify(&colors, space, 32);
    let opacity = match nums("Points")? {
        None => None,
        Some(p) => {
            if p.len() < 4 || p.len() % 4 != 0 {
                bail!(
                    "{}: {name}.Points: {} numbers, expected a positive multiple of 4 (x, a, mid, sharp)",
                    path.display(),
                    p.len()
                );
            }
            let pts: OpacityPoints = p
                .chunks(4)
                .enumerate()
                .map(|(i, c)| {
                    if !(0.0..=1.0).contains(&c[1]) {
                        bail!(
                            "{}: {name}.Points: point {i} (x = {}) has opacity {}, outside [0, 1]",
                            path.display(),
                            c[0],
                            c[1]
                        );
                    }
                    if !((0.0..=1.0).contains(&c[2]) && (0.0..=1.0).contains(&c[3])) {
                        bail!(
                            "{}: {name}.Points: point {i} (x = {}) has midpoint {} and sharpness {}, expected both in [0, 1]",
                            path.display(),
                            c[0],
                            c[2],
                            c[3]
                        );
                    }
                    Ok((c[0], c[1]))
                })
                .collect::<Result<_>>()?;
            check_increasing(pts.iter().map(|c| c.0), path, &name, "Points")?;
            let quads: Vec<&[f64]> = p.chunks(4).collect();
            if let Some(i) = quads[..quads.len() - 1].iter().position(|c| c[3] >= 0.01) {
                eprintln!(
                    "tetkit: warning: {}: {name}.Points: point {i} (x = {}) has sharpness {}: drawn with sharpness 0 (the midpoint kept, linear on either side of it)",
                    path.display(),
                    quads[i][0],
                    quads[i][3]
                );
            }
            Some(with_midpoints(&quads))
        }
    };
    Ok(ColorSource::Preset {
        name,
        colors,
        opacity,
    })
}

/// Opacity points `(x, a)` from ParaView's `x, a, midpoint, sharpness` quadruples: between
/// point i and i + 1, vtkPiecewiseFunction with sharpness 0 reaches the mean of the two values
/// at `x_i + midpoint_i (x_{i+1} - x_i)` and is linear on either side (0.5 adds nothing).
fn with_midpoints(quads: &[&[f64]]) -> OpacityPoints {
    let mut out = Vec::with_capacity(2 * quads.len());
    for (i, c) in quads.iter().enumerate() {
        out.push((c[0], c[1]));
        if let Some(n) = quads.get(i + 1) {
            if c[2] != 0.5 && n[0] > c[0] {
                out.push((c[0] + c[2] * (n[0] - c[0]), 0.5 * (c[1] + n[1])));
            }
        }
    }
    out
}

fn check_increasing(
    xs: impl Iterator<Item = f64>,
    path: &Path,
    name: &str,
    key: &str,
) -> Result<()> {
    let mut prev = f64::NEG_INFINITY;
    for (i, x) in xs.enumerate() {
        if x < prev {
            bail!(
                "{}: {name}.{key}: point {i} at x = {x} is before the previous one ({prev})",
                path.display()
            );
        }
        prev = x;
    }
    Ok(())
}

/// Opacity as the user gives it: constant, or points relative to the scalar range.
#[derive(Clone, Debug, PartialEq)]
pub enum OpacitySpec {
    /// Points `(t, a)` with t in [0, 1] across the scalar range.
    Points(OpacityPoints),
}

impl OpacitySpec {
    /// Parses `0.3` (constant), `ramp` (0 -> 1), `ramp:A:B` (linear A -> B) or
    /// `t:a,t:a,...` (points, t relative to the scalar range).
    pub fn parse(s: &str) -> Result<OpacitySpec> {
        let bad = |why: &str| anyhow!("--opacity '{s}': {why}");
        let num = |t: &str| -> Result<f64> {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(&format!("'{t}' is not a finite number")))
        };
        if let Ok(v) = s.trim().parse::<f64>() {
            if !(0.0..=1.0).contains(&v) {
                return Err(bad("opacity must be in [0, 1]"));
            }
            return Ok(OpacitySpec::Points(vec![(0.0, v), (1.0, v)]));
        }
        if let Some(rest) = s.strip_prefix("ramp") {
            let (a, b) = if rest.is_empty() {
                (0.0, 1.0)
            } else {
                let parts: Vec<&str> = rest.trim_start_matches(':').split(':').collect();
                if parts.len() != 2 {
                    return Err(bad("expected ramp or ramp:A:B"));
                }
                (num(parts[0])?, num(parts[1])?)
            };
            for v in [a, b] {
                if !(0.0..=1.0).contains(&v) {
                    return Err(bad("opacity must be in [0, 1]"));
                }
            }
            return Ok(OpacitySpec::Points(vec![(0.0, a), (1.0, b)]));
        }
        let mut pts = Vec::new();
        for part in s.split(',') {
            let (t, a) = part
                .split_once(':')
                .ok_or_else(|| bad(&format!("'{part}' is not t:a")))?;
            let (t, a) = (num(t)?, num(a)?);
            if !(0.0..=1.0).contains(&a) {
                return Err(bad("opacity must be in [0, 1]"));
            }
            if !(0.0..=1.0).contains(&t) {
                return Err(bad(&format!(
                    "t = {t} is outside [0, 1] (t is relative to the scalar range; --range sets the range)"
                )));
            }
            if let Some(&(pt, _)) = pts.last() {
                if t < pt {
                    return Err(bad("points must be in increasing t"));
                }
            }
            pts.push((t, a));
        }
        if pts.is_empty() {
            return Err(bad("no points"));
        }
        Ok(OpacitySpec::Points(pts))
    }
}

/// Linear interpolation in a sorted point list, clamped at both ends.
fn lerp_points<const N: usize>(pts: &[(f64, [f64; N])], x: f64) -> [f64; N] {
    if pts.is_empty() {
        return [0.0; N];
    }
    if x <= pts[0].0 {
        return pts[0].1;
    }
    let last = pts.len() - 1;
    if x >= pts[last].0 {
        return pts[last].1;
    }
    let i = pts.partition_point(|p| p.0 <= x).max(1) - 1;
    let (x0, a) = pts[i];
    let (x1, b) = pts[(i + 1).min(last)];
    if x1 <= x0 {
        return b;
    }
    let t = (x - x0) / (x1 - x0);
    std::array::from_fn(|k| a[k] + t * (b[k] - a[k]))
}

impl TransferFunction {
    /// Builds the function over `range` with `nodes` nodes. The user's opacity wins over a
    /// preset's; without either, opacity ramps linearly from 0 to 1.
    pub fn build(
        colors: &ColorSource,
        opacity: Option<&OpacitySpec>,
        range: [f64; 2],
        unit_distance: f64,
        nodes: usize,
    ) -> Result<TransferFunction> {
        if !(range[0].is_finite() && range[1].is_finite() && range[0] <= range[1]) {
            bail!("scalar range [{}, {}] is not valid", range[0], range[1]);
        }
        if !(unit_distance > 0.0 && unit_distance.is_finite()) {
            bail!("unit distance {unit_distance} must be positive and finite");
        }
        let k = nodes.max(2);
        // Relative position of node i in [0, 1].
        let rel = |i: usize| i as f64 / (k - 1) as f64;
        let (rgb, preset_opacity): (Vec<[f64; 3]>, Option<Vec<f64>>) = match colors {
            ColorSource::Relative(pts) => {
                ((0..k).map(|i| lerp_points(pts, rel(i))).collect(), None)
            }
            ColorSource::Preset {
                colors, opacity, ..
            } => {
                // Rescale the preset's own x range onto [0, 1] (ParaView's "apply preset, rescale").
                let (x0, x1) = (colors[0].0, colors[colors.len() - 1].0);
                let span = if x1 > x0 { x1 - x0 } else { 1.0 };
                let to_rel = |x: f64| (x - x0) / span;
                let cp: ColorPoints = colors.iter().map(|(x, c)| (to_rel(*x), *c)).collect();
                let op = opacity.as_ref().map(|o| {
                    let p: Vec<(f64, [f64; 1])> =
                        o.iter().map(|(x, a)| (to_rel(*x), [*a])).collect();
                    (0..k).map(|i| lerp_points(&p, rel(i))[0]).collect()
                });
                ((0..k).map(|i| lerp_points(&cp, rel(i))).collect(), op)
            }
        };
        let alpha: Vec<f64> = match (opacity, preset_opacity) {
            (Some(OpacitySpec::Points(p)), _) => {
                let p: Vec<(f64, [f64; 1])> = p.iter().map(|(t, a)| (*t, [*a])).collect();
                (0..k).map(|i| lerp_points(&p, rel(i))[0]).collect()
            }
            (None, Some(a)) => a,
            (None, None) => (0..k).map(rel).collect(),
        };
        let tau = alpha
            .iter()
            .map(|&a| -(1.0 - a.clamp(0.0, MAX_OPACITY)).ln() / unit_distance)
            .collect();
        Ok(TransferFunction { range, rgb, tau })
    }

    pub fn nodes(&self) -> usize {
        self.tau.len()
    }

    /// Position of scalar `s` in node units, clamped to [0, K-1].
    pub fn node_pos(&self, s: f64) -> f64 {
        let k = (self.nodes() - 1) as f64;
        let span = self.range[1] - self.range[0];
        if !(span > 0.0) {
            return if s < self.range[0] { 0.0 } else { k };
        }
        ((s - self.range[0]) / span * k).clamp(0.0, k)
    }

    /// Colour and extinction at node position `x` (linear between nodes).
    #[inline(always)]
    pub fn at_pos(&self, x: f64) -> ([f64; 3], f64) {
        let last = self.nodes() - 1;
        // Truncation is the floor for x >= 0 (and NaN or x < 0 give 0 either way), without a
        // libm call.
        let i = (x.max(0.0) as usize).min(last);
        if i == last {
            return (self.rgb[last], self.tau[last]);
        }
        let t = x - i as f64;
        let (a, b) = (self.rgb[i], self.rgb[i + 1]);
        (
            [
                a[0] + t * (b[0] - a[0]),
                a[1] + t * (b[1] - a[1]),
                a[2] + t * (b[2] - a[2]),
            ],
            self.tau[i] + t * (self.tau[i + 1] - self.tau[i]),
        )
    }

    #[inline]
    pub fn eval(&self, s: f64) -> ([f64; 3], f64) {
        self.at_pos(self.node_pos(s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn opacity_specs() {
        assert_eq!(
            OpacitySpec::parse("0.25").unwrap(),
            OpacitySpec::Points(vec![(0.0, 0.25), (1.0, 0.25)])
        );
        assert_eq!(
            OpacitySpec::parse("ramp:0.1:0.5").unwrap(),
            OpacitySpec::Points(vec![(0.0, 0.1), (1.0, 0.5)])
        );
        assert!(OpacitySpec::parse("0:0,1").is_err());
        assert!(OpacitySpec::parse("1.5").is_err());
        assert!(OpacitySpec::parse("0.5:0.2,0.1:0.3").is_err());
        // t is relative to the range: outside [0, 1] it is refused, not clamped.
        assert!(
            matches!(OpacitySpec::parse("-2:0.5,3:0.5"), Err(e) if e.to_string().contains("t = -2 is outside [0, 1]"))
        );
    }

    #[test]
    fn unit_distance_meaning() {
        let c = named_colormap("viridis").unwrap();
        let tf = TransferFunction::build(
            &c,
            Some(&OpacitySpec::parse("0.5").unwrap()),
            [0.0, 1.0],
            2.0,
            16,
        )
        .unwrap();
        // A slab of thickness 2 transmits 1 - 0.5.
        let (_, tau) = tf.eval(0.3);
        assert!(((-tau * 2.0).exp() - 0.5).abs() < 1e-12);
    }

    #[test]
    fn preset_rescales_and_reads_opacity() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("p.json");
        std::fs::write(
            &p,
            r#"[{"Name":"t","RGBPoints":[10,0,0,0, 20,1,1,1],"Points":[10,0,0.5,0, 20,0.5,0.5,0]}]"#,
        )
        .unwrap();
        let src = read_preset(&p).unwrap();
        let tf = TransferFunction::build(&src, None, [0.0, 1.0], 1.0, 3).unwrap();
        assert_eq!(tf.rgb[1], [0.5, 0.5, 0.5]);
        assert!((tf.tau[2] - (2.0f64).ln()).abs() < 1e-12);
        std::fs::write(&p, r#"{"RGBPoints":[0,1,0]}"#).unwrap();
        let e = read_preset(&p).unwrap_err().to_string();
        assert!(e.contains("multiple of 4"), "{e}");
    }

    #[test]
    fn paraview_preset_names() -> Result<()> {
        for (pv, ours) in [
            ("Cool to Warm", "cool-to-warm"),
            ("Viridis (matplotlib)", "viridis"),
            ("Inferno (matplotlib)", "inferno"),
            ("Turbo", "turbo"),
        ] {
            assert_eq!(named_colormap(pv)?, named_colormap(ours)?, "{pv}");
        }
        let tf = |n: &str| TransferFunction::build(&named_colormap(n)?, None, [0.0, 1.0], 1.0, 3);
        assert_eq!(tf("Grayscale")?.rgb, vec![[0.0; 3], [0.5; 3], [1.0; 3]]);
        assert_eq!(tf("X Ray")?.rgb, vec![[1.0; 3], [0.5; 3], [0.0; 3]]);
        match named_colormap("Jet") {
            Ok(_) => bail!("Jet accepted"),
            Err(e) => assert!(e.to_string().contains("Choose Preset"), "{e}"),
        }
        Ok(())
    }

    #[test]
    fn preset_opacity_midpoint_as_vtk() -> Result<()> {
        let dir = tempfile::tempdir()?;
        let p = dir.path().join("m.json");
        // vtkPiecewiseFunction AddPoint(0, 0, 0.8, 0), AddPoint(1, 1): 0.125 at 0.2, 0.5 at 0.8,
        // 0.75 at 0.9 (VTK 9.1).
        std::fs::write(
            &p,
            r#"[{"Name":"m","RGBPoints":[0,0,0,0, 1,1,1,1],"Points":[0,0,0.8,0, 1,1,0.5,0]}]"#,
        )?;
        let ColorSource::Preset {
            opacity: Some(pts), ..
        } = read_preset(&p)?
        else {
            bail!("no opacity read");
        };
        for (x, want) in [
            (0.2, 0.125),
            (0.4, 0.25),
            (0.8, 0.5),
            (0.9, 0.75),
            (1.0, 1.0),
        ] {
            let p1: Vec<(f64, [f64; 1])> = pts.iter().map(|(x, a)| (*x, [*a])).collect();
            let got = lerp_points(&p1, x)[0];
            assert!((got - want).abs() < 1e-12, "at {x}: {got} != {want}");
        }
        std::fs::write(
            &p,
            r#"[{"Name":"m","RGBPoints":[0,0,0,0, 1,1,1,1],"Points":[0,0,1.5,0, 1,1,0.5,0]}]"#,
        )?;
        let e = read_preset(&p)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(e.contains("midpoint 1.5"), "{e}");
        Ok(())
    }

    #[test]
    fn preset_colour_space_bom_and_ranges() -> Result<()> {
        let dir = tempfile::tempdir()?;
        let p = dir.path().join("p.json");
        let write = |body: &str| std::fs::write(&p, body);
        // Red to blue: RGB meets in purple, Diverging in white (as ParaView draws it).
        for (space, mid) in [("RGB", [0.5, 0.0, 0.5]), ("Diverging", [1.0, 1.0, 1.0])] {
            // With a byte-order mark, as Windows editors save it.
            write(&format!(
                "\u{feff}[{{\"Name\":\"rb\",\"ColorSpace\":\"{space}\",\"RGBPoints\":[0,1,0,0, 1,0,0,1]}}]"
            ))?;
            let tf = TransferFunction::build(&read_preset(&p)?, None, [0.0, 1.0], 1.0, 65)?;
            let got = tf.rgb[32];
            assert!(
                (0..3).all(|k| (got[k] - mid[k]).abs() < 0.01),
                "{space}: {got:?}"
            );
        }
        for (body, needle) in [
            (
                r#"[{"Name":"b","ColorSpace":"Bogus","RGBPoints":[0,1,0,0, 1,0,0,1]}]"#,
                "ColorSpace 'Bogus'",
            ),
            (
                r#"[{"Name":"c","RGBPoints":[0,1,0,0, 1,0,7,1]}]"#,
                "point 1 (x = 1) has colour [0.0, 7.0, 1.0], outside [0, 1]",
            ),
            (
                r#"[{"Name":"o","RGBPoints":[0,1,0,0, 1,0,0,1],"Points":[0,-1,0.5,0, 1,0.5,0.5,0]}]"#,
                "point 0 (x = 0) has opacity -1, outside [0, 1]",
            ),
        ] {
            write(body)?;
            match read_preset(&p) {
                Ok(_) => bail!("{body} accepted"),
                Err(e) => {
                    let e = e.to_string();
                    assert!(e.contains(needle) && e.contains("p.json"), "{e}");
                }
            }
        }
        Ok(())
    }
}
