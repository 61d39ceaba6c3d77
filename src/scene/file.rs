//! The scene file (TOML): parsing with serde (unknown keys refused), then checks that name the
//! scene file and the line of the offending table or key.

use std::path::{Path, PathBuf};

use formats::FormatError;
use serde::Deserialize;
use toml::Spanned;

use super::{Action, Body, CameraSpec, Primitive, Rule, Scene, Shape, TransferSpec, MAX_BODIES};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    rule: Option<Rule>,
    camera: Option<Spanned<RawCamera>>,
    transfer: Option<Spanned<RawTransfer>>,
    #[serde(default)]
    body: Vec<Spanned<RawBody>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCamera {
    position: Option<[f64; 3]>,
    focal: Option<[f64; 3]>,
    up: Option<[f64; 3]>,
    view_angle: Option<Spanned<f64>>,
    parallel: Option<bool>,
    parallel_scale: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTransfer {
    colormap: Option<Spanned<String>>,
    preset: Option<Spanned<String>>,
    /// Points read at any length, so a point of three numbers is refused rather than cut to
    /// two (serde's fixed arrays drop the rest).
    opacity: Option<Spanned<Vec<Vec<f64>>>>,
    range: Option<Spanned<[f64; 2]>>,
    unit_distance: Option<Spanned<f64>>,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq, Debug)]
#[serde(rename_all = "lowercase")]
enum ShapeKind {
    Box,
    Sphere,
    Cylinder,
    Cone,
    Surface,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq, Debug, Default)]
#[serde(rename_all = "lowercase")]
enum ActionKind {
    #[default]
    Cut,
    Transfer,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBody {
    shape: ShapeKind,
    name: Option<String>,
    #[serde(default)]
    action: ActionKind,
    transfer: Option<Spanned<RawTransfer>>,
    min: Option<Spanned<[f64; 3]>>,
    max: Option<Spanned<[f64; 3]>>,
    center: Option<Spanned<[f64; 3]>>,
    radius: Option<Spanned<f64>>,
    start: Option<Spanned<[f64; 3]>>,
    end: Option<Spanned<[f64; 3]>>,
    start_radius: Option<Spanned<f64>>,
    end_radius: Option<Spanned<f64>>,
    file: Option<Spanned<String>>,
}

/// Reads and checks a scene file. An empty file is a scene with no bodies.
pub fn load(path: &Path) -> Result<Scene, FormatError> {
    let text = std::fs::read_to_string(path).map_err(|e| FormatError::io(path, e))?;
    parse(&text, path)
}

fn line_of(text: &str, byte: usize) -> usize {
    let b = byte.min(text.len());
    text.as_bytes()[..b].iter().filter(|&&c| c == b'\n').count() + 1
}

/// Parses scene text; `path` names the file in errors and anchors relative surface and preset
/// paths.
pub fn parse(text: &str, path: &Path) -> Result<Scene, FormatError> {
    let at =
        |byte: usize, msg: String| FormatError::at_line(line_of(text, byte), msg).with_file(path);
    let raw: RawScene = toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(1, |s| line_of(text, s.start));
        FormatError::at_line(line, e.message().trim().to_string()).with_file(path)
    })?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut scene = Scene::empty(path);
    scene.rule = raw.rule.unwrap_or_default();
    if let Some(c) = raw.camera {
        let pos = c.span().start;
        scene.camera = camera(c.into_inner(), &at, pos)?;
    }
    if let Some(t) = raw.transfer {
        let pos = t.span().start;
        scene.transfer = Some(transfer(t.into_inner(), &dir, &at, pos)?);
    }
    if raw.body.len() > MAX_BODIES {
        let ninth = raw.body[MAX_BODIES].span().start;
        return Err(at(
            ninth,
            format!(
                "{} bodies; a scene holds at most {MAX_BODIES} (one bit each of an 8-bit region code)",
                raw.body.len()
            ),
        ));
    }
    for (i, b) in raw.body.into_iter().enumerate() {
        let pos = b.span().start;
        scene
            .bodies
            .push(body(i, b.into_inner(), &dir, &at, pos, line_of(text, pos))?);
    }
    Ok(scene)
}

type At<'a> = dyn Fn(usize, String) -> FormatError + 'a;

/// Largest magnitude of a body's coordinates and sizes: the shape tests square them (a sphere
/// of radius 1e155 had an infinite r^2 and cut nothing where classify's test cut everything).
const LIMIT: f64 = 1e150;

fn finite3(v: &Spanned<[f64; 3]>, key: &str, at: &At) -> Result<[f64; 3], FormatError> {
    let x = *v.get_ref();
    if !x.iter().all(|c| c.is_finite()) {
        return Err(at(v.span().start, format!("{key} = {x:?} is not finite")));
    }
    if x.iter().any(|c| c.abs() > LIMIT) {
        return Err(at(
            v.span().start,
            format!("{key} = {x:?}: values beyond 1e150 in magnitude are refused (their squares overflow)"),
        ));
    }
    Ok(x)
}

fn camera(c: RawCamera, at: &At, pos: usize) -> Result<CameraSpec, FormatError> {
    for (k, v) in [("position", c.position), ("focal", c.focal), ("up", c.up)] {
        if let Some(v) = v {
            if !v.iter().all(|x| x.is_finite()) {
                return Err(at(pos, format!("camera {k} = {v:?} is not finite")));
            }
        }
    }
    if c.up == Some([0.0; 3]) {
        return Err(at(pos, "camera up = [0, 0, 0]: the zero vector".into()));
    }
    if let (Some(p), Some(f)) = (c.position, c.focal) {
        if p == f {
            return Err(at(
                pos,
                "camera position and focal point are the same point".into(),
            ));
        }
    }
    check_key(
        at,
        &c.view_angle,
        |v| v > 0.0 && v < 180.0,
        |v| format!("view_angle = {v}: must lie in (0, 180) degrees"),
    )?;
    check_key(
        at,
        &c.parallel_scale,
        |v| v > 0.0 && v.is_finite(),
        |v| format!("parallel_scale = {v}: must be positive"),
    )?;
    Ok(CameraSpec {
        position: c.position,
        focal: c.focal,
        up: c.up,
        view_angle: c.view_angle.map(|v| *v.get_ref()),
        parallel: c.parallel,
        parallel_scale: c.parallel_scale.map(|v| *v.get_ref()),
    })
}

/// An error at the key's line when a given value fails `ok`.
fn check_key<T: Copy>(
    at: &At,
    key: &Option<Spanned<T>>,
    ok: impl Fn(T) -> bool,
    msg: impl Fn(T) -> String,
) -> Result<(), FormatError> {
    match key {
        Some(k) if !ok(*k.get_ref()) => Err(at(k.span().start, msg(*k.get_ref()))),
        _ => Ok(()),
    }
}

/// Checks a transfer table. Errors point at the offending key's line (a table's own span is
/// its header's, or for `[body.transfer]` the enclosing `[[body]]`'s); `pos` (the table) only
/// where no key is to blame. Colormap names and preset files are checked here, so that a bad
/// one is reported with its line rather than when a renderer first builds the function.
fn transfer(t: RawTransfer, dir: &Path, at: &At, pos: usize) -> Result<TransferSpec, FormatError> {
    let key = |v: Option<usize>| v.unwrap_or(pos);
    if let (Some(_), Some(p)) = (&t.colormap, &t.preset) {
        return Err(at(
            p.span().start,
            "give a colormap or a preset, not both".into(),
        ));
    }
    let opacity_at = key(t.opacity.as_ref().map(|o| o.span().start));
    let given = t.opacity.is_some();
    let points = t.opacity.map(Spanned::into_inner).unwrap_or_default();
    if given && points.is_empty() {
        return Err(at(
            opacity_at,
            "opacity = []: no points (leave opacity out for the default ramp)".into(),
        ));
    }
    let mut opacity = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        match p.as_slice() {
            &[x, a] => opacity.push([x, a]),
            _ => {
                return Err(at(
                    opacity_at,
                    format!(
                        "opacity point {i} {p:?}: expected two numbers [scalar, opacity], found {}",
                        p.len()
                    ),
                ))
            }
        }
    }
    let mut prev = f64::NEG_INFINITY;
    for p in &opacity {
        if !p[0].is_finite() || !(0.0..=1.0).contains(&p[1]) {
            return Err(at(
                opacity_at,
                format!("opacity point {p:?}: the scalar must be finite and the opacity in [0, 1]"),
            ));
        }
        if p[0] < prev {
            return Err(at(
                opacity_at,
                format!("opacity point {p:?}: scalars must not decrease"),
            ));
        }
        prev = p[0];
    }
    check_key(
        at,
        &t.range,
        |v| v[0].is_finite() && v[1].is_finite() && v[0] < v[1],
        |v| format!("range = {v:?}: need finite min < max"),
    )?;
    check_key(
        at,
        &t.unit_distance,
        |v| v > 0.0 && v.is_finite(),
        |v| format!("unit_distance = {v}: must be positive"),
    )?;
    if let Some(c) = &t.colormap {
        crate::render::transfer::named_colormap(c.get_ref())
            .map_err(|e| at(c.span().start, format!("{e:#}")))?;
    }
    let preset = match t.preset {
        Some(p) => {
            let full = dir.join(p.get_ref());
            if !full.is_file() {
                return Err(at(
                    p.span().start,
                    format!("preset file {} not found", full.display()),
                ));
            }
            crate::render::transfer::read_preset(&full)
                .map_err(|e| at(p.span().start, format!("preset: {e:#}")))?;
            Some(full)
        }
        None => None,
    };
    Ok(TransferSpec {
        colormap: t.colormap.map(Spanned::into_inner),
        preset,
        opacity,
        range: t.range.map(Spanned::into_inner),
        unit_distance: t.unit_distance.map(Spanned::into_inner),
    })
}

fn body(
    i: usize,
    b: RawBody,
    dir: &Path,
    at: &At,
    pos: usize,
    line: usize,
) -> Result<Body, FormatError> {
    let who = format!("body {i} ({:?})", b.shape).to_lowercase();
    let need = |v: Option<Spanned<[f64; 3]>>, key: &str| -> Result<[f64; 3], FormatError> {
        let v = v.ok_or_else(|| at(pos, format!("{who} needs {key} = [x, y, z]")))?;
        finite3(&v, key, at)
    };
    let positive =
        |v: Option<Spanned<f64>>, key: &str, zero_ok: bool| -> Result<f64, FormatError> {
            let v = v.ok_or_else(|| at(pos, format!("{who} needs {key} = r")))?;
            let x = *v.get_ref();
            if !(x.is_finite() && (x > 0.0 || (zero_ok && x == 0.0))) {
                return Err(at(
                    v.span().start,
                    format!(
                        "{who}: {key} = {x} must be {} and finite",
                        if zero_ok { "non-negative" } else { "positive" }
                    ),
                ));
            }
            if x > LIMIT {
                return Err(at(
                    v.span().start,
                    format!(
                    "{who}: {key} = {x}: values beyond 1e150 are refused (their squares overflow)"
                ),
                ));
            }
            Ok(x)
        };
    // Keys that belong to other shapes are mistakes worth naming.
    let allowed: &[&str] = match b.shape {
        ShapeKind::Box => &["min", "max"],
        ShapeKind::Sphere => &["center", "radius"],
        ShapeKind::Cylinder => &["start", "end", "radius"],
        ShapeKind::Cone => &["start", "end", "start_radius", "end_radius"],
        ShapeKind::Surface => &["file"],
    };
    let present: [(&str, Option<usize>); 9] = [
        ("min", b.min.as_ref().map(|v| v.span().start)),
        ("max", b.max.as_ref().map(|v| v.span().start)),
        ("center", b.center.as_ref().map(|v| v.span().start)),
        ("radius", b.radius.as_ref().map(|v| v.span().start)),
        ("start", b.start.as_ref().map(|v| v.span().start)),
        ("end", b.end.as_ref().map(|v| v.span().start)),
        (
            "start_radius",
            b.start_radius.as_ref().map(|v| v.span().start),
        ),
        ("end_radius", b.end_radius.as_ref().map(|v| v.span().start)),
        ("file", b.file.as_ref().map(|v| v.span().start)),
    ];
    for (key, span) in present {
        if let Some(s) = span {
            if !allowed.contains(&key) {
                return Err(at(
                    s,
                    format!(
                        "{who} does not take '{key}' (it takes {})",
                        allowed.join(", ")
                    ),
                ));
            }
        }
    }
    let shape = match b.shape {
        ShapeKind::Box => {
            let (min, max) = (need(b.min, "min")?, need(b.max, "max")?);
            if (0..3).any(|k| min[k] >= max[k]) {
                return Err(at(
                    pos,
                    format!("{who}: max {max:?} must exceed min {min:?} on every axis"),
                ));
            }
            Shape::Primitive(Primitive::Box { min, max })
        }
        ShapeKind::Sphere => Shape::Primitive(Primitive::Sphere {
            center: need(b.center, "center")?,
            radius: positive(b.radius, "radius", false)?,
        }),
        ShapeKind::Cylinder | ShapeKind::Cone => {
            let (start, end) = (need(b.start, "start")?, need(b.end, "end")?);
            if start == end {
                return Err(at(pos, format!("{who}: start and end are the same point")));
            }
            let (r0, r1) = if b.shape == ShapeKind::Cylinder {
                let r = positive(b.radius, "radius", false)?;
                (r, r)
            } else {
                let r0 = positive(b.start_radius, "start_radius", true)?;
                let r1 = positive(b.end_radius, "end_radius", true)?;
                if r0 == 0.0 && r1 == 0.0 {
                    return Err(at(pos, format!("{who}: both radii are zero")));
                }
                (r0, r1)
            };
            Shape::Primitive(Primitive::Frustum { start, end, r0, r1 })
        }
        ShapeKind::Surface => {
            let f = b.file.ok_or_else(|| {
                at(
                    pos,
                    format!("{who} needs file = \"surface.stl|.obj|.vtk|.vtp\""),
                )
            })?;
            let full: PathBuf = dir.join(f.get_ref());
            let surf = super::surface::read(&full)
                .map_err(|e| at(f.span().start, format!("{who}: {e}")))?;
            Shape::Surface(Box::new(surf))
        }
    };
    let action = match (b.action, b.transfer) {
        (ActionKind::Cut, None) => Action::Cut,
        (ActionKind::Cut, Some(t)) => {
            return Err(at(
                t.span().start,
                format!("{who} cuts (draws nothing inside), so it takes no transfer function; set action = \"transfer\""),
            ))
        }
        (ActionKind::Transfer, None) => {
            return Err(at(
                pos,
                format!("{who}: action = \"transfer\" needs a [body.transfer] table"),
            ))
        }
        (ActionKind::Transfer, Some(t)) => {
            let p = t.span().start;
            Action::Transfer(transfer(t.into_inner(), dir, at, p)?)
        }
    };
    Ok(Body {
        name: b.name.unwrap_or_else(|| format!("body{i}")),
        shape,
        action,
        line,
    })
}
