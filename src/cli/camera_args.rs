//! Camera options shared by every command that takes a view (explicit, ParaView-style, .pvcc).

use anyhow::{bail, Context, Result};
use clap::Args;
use std::path::{Path, PathBuf};

use crate::camera::Camera;
use crate::geom::{cross, dot, sub, Aabb};

/// The view, in the order it is built: VTK's default camera (or `--camera-file`), explicit values
/// replacing parts of it, a reset that fits the bounds when no position came from the user, then
/// ParaView-style `--azimuth`, `--elevation`, `--roll`, `--zoom` in that order.
#[derive(Args, Debug, Clone, Default, PartialEq)]
pub struct CameraArgs {
    /// Camera position `x,y,z`. Without it (and without --camera-file) the camera is reset to fit
    /// the mesh bounds, looking along --focal minus --position's default direction (-z).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub position: Option<[f64; 3]>,
    /// Focal point `x,y,z` (default: the centre of the bounds, or the camera file's).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub focal: Option<[f64; 3]>,
    /// View-up vector `x,y,z` (default 0,1,0); made perpendicular to the view direction.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub up: Option<[f64; 3]>,
    /// Full vertical view angle in degrees (perspective; default 30, as VTK).
    #[arg(long, value_name = "DEG", value_parser = parse_finite)]
    pub view_angle: Option<f64>,
    /// Orthographic (parallel) projection.
    #[arg(long, conflicts_with = "perspective")]
    pub parallel: bool,
    /// Perspective projection even where --camera-file or a scene's `[camera]` says parallel.
    #[arg(long)]
    pub perspective: bool,
    /// Half the view height in world units for --parallel (default: fits the bounds).
    #[arg(long, value_name = "S", value_parser = parse_finite)]
    pub parallel_scale: Option<f64>,
    /// Rotate the camera about the view-up vector through the focal point (degrees), after the reset.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_finite)]
    pub azimuth: Option<f64>,
    /// Rotate the camera about its right axis through the focal point (degrees), after azimuth.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_finite)]
    pub elevation: Option<f64>,
    /// Rotate the view-up vector about the view direction (degrees), after elevation.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_finite)]
    pub roll: Option<f64>,
    /// Magnify by this factor (narrower view angle, or smaller parallel scale), applied last.
    #[arg(long, value_name = "FACTOR", value_parser = parse_finite)]
    pub zoom: Option<f64>,
    /// ParaView saved camera (.pvcc XML); explicit options above override its values.
    #[arg(long, value_name = "VIEW.pvcc")]
    pub camera_file: Option<PathBuf>,
}

/// Parses one finite number (`nan` and `inf` are refused here, where they would surface later
/// as a camera "too large for f64").
pub fn parse_finite(s: &str) -> std::result::Result<f64, String> {
    let v = s.trim().parse::<f64>().map_err(|e| format!("'{s}': {e}"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("'{s}' is not a finite number"))
    }
}

/// Parses `x,y,z` (commas or spaces) into three finite numbers.
pub fn parse_vec3(s: &str) -> std::result::Result<[f64; 3], String> {
    let parts: Vec<&str> = s
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|p| !p.is_empty())
        .collect();
    if parts.len() != 3 {
        return Err(format!(
            "'{s}': expected three numbers x,y,z, got {}",
            parts.len()
        ));
    }
    let mut v = [0.0; 3];
    for (k, p) in parts.iter().enumerate() {
        v[k] = p
            .parse::<f64>()
            .map_err(|e| format!("'{s}': component {} '{p}': {e}", k + 1))?;
        if !v[k].is_finite() {
            return Err(format!("'{s}': component {} is not finite", k + 1));
        }
    }
    Ok(v)
}

impl CameraArgs {
    /// The camera these options describe for a scene with the given bounds.
    pub fn camera(&self, bounds: &Aabb) -> Result<Camera> {
        let mut cam = Camera::default();
        let from_file = match &self.camera_file {
            Some(path) => {
                cam = read_pvcc(path)?;
                true
            }
            None => false,
        };
        if let Some(a) = self.view_angle {
            if !(a > 0.0 && a < 180.0) {
                bail!("--view-angle {a}: must be between 0 and 180 degrees");
            }
            cam.view_angle = a;
        }
        if self.parallel {
            cam.parallel = true;
        }
        if self.perspective {
            cam.parallel = false;
        }
        if let Some(up) = self.up {
            cam.up = up;
        }
        let center = if bounds.is_empty() {
            [0.0; 3]
        } else {
            bounds.center()
        };
        match (self.position, self.focal) {
            (Some(p), f) => {
                cam.position = p;
                cam.focal = f.unwrap_or(if from_file { cam.focal } else { center });
            }
            (None, Some(f)) if from_file => cam.focal = f,
            (None, f) if !from_file => {
                // Keep VTK's default direction (-z) but look at the requested point, then fit.
                let dir = cam.direction();
                let target = f.unwrap_or(center);
                cam.focal = target;
                // A unit step would vanish next to coordinates beyond 2^53 (a mesh far from the
                // origin, or a huge one): step by the target's own magnitude, which keeps the
                // direction whatever the coordinates.
                let step = 1.0 + target.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                cam.position = [0, 1, 2].map(|k| target[k] - step * dir[k]);
                let mut fit = if bounds.is_empty() {
                    Aabb {
                        min: target,
                        max: target,
                    }
                } else {
                    *bounds
                };
                if f.is_some() {
                    // Fit the bounds while looking at the given point: centre a box of the
                    // same size there.
                    let e = fit.extent();
                    fit = Aabb {
                        min: [0, 1, 2].map(|k| target[k] - 0.5 * e[k]),
                        max: [0, 1, 2].map(|k| target[k] + 0.5 * e[k]),
                    };
                }
                check_up(&cam)?;
                cam.reset_to(&fit);
            }
            _ => {}
        }
        let d = sub(&cam.focal, &cam.position);
        if dot(&d, &d) == 0.0 && !bounds.is_empty() && bounds.extent() == [0.0; 3] {
            // Every point at one place (a mesh of one point, or coordinates that collapsed when
            // written as f32 far from the origin): there is no size to fit a camera to.
            bail!(
                "the mesh has zero extent (every point at {:?}): no camera fits it; give --position and --focal to look anyway",
                bounds.min
            );
        }
        if dot(&d, &d) == 0.0 {
            bail!(
                "camera position {:?} equals the focal point: no view direction",
                cam.position
            );
        }
        check_up(&cam)?;
        cam.orthogonalize_up();
        if let Some(s) = self.parallel_scale {
            if !(s > 0.0 && s.is_finite()) {
                bail!("--parallel-scale {s}: must be positive");
            }
            cam.parallel_scale = s;
        } else if self.position.is_some() && !from_file && !bounds.is_empty() {
            // An explicit position without a scale: fit the bounds' sphere like a reset would.
            let e = bounds.extent();
            let r = 0.5 * dot(&e, &e).sqrt();
            if r > 0.0 {
                cam.parallel_scale = r;
            }
        }
        if let Some(a) = self.azimuth {
            cam.azimuth(a);
        }
        if let Some(e) = self.elevation {
            cam.elevation(e);
        }
        if let Some(r) = self.roll {
            cam.roll(r);
        }
        if let Some(z) = self.zoom {
            if !(z > 0.0 && z.is_finite()) {
                bail!("--zoom {z}: must be a positive factor");
            }
            cam.zoom(z);
        }
        check_up(&cam)?;
        Ok(cam)
    }
}

fn check_up(cam: &Camera) -> Result<()> {
    let d = sub(&cam.focal, &cam.position);
    // Scaled to the largest component first, so coordinates near f64's range cannot overflow
    // the squares into infinity (and the test into NaN).
    let unit = |v: &[f64; 3]| {
        let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if m > 0.0 && m.is_finite() {
            v.map(|x| x / m)
        } else {
            *v
        }
    };
    if !d.iter().all(|x| x.is_finite()) {
        // A position placed past f64's range from a huge focal point, or two far points whose
        // difference overflows.
        bail!(
            "the camera at {:?} looking at {:?} has no finite view direction (coordinates too large for f64): give smaller --position/--focal",
            cam.position,
            cam.focal
        );
    }
    let (dn, upn) = (unit(&d), unit(&cam.up));
    let c = cross(&dn, &upn);
    let scale = dot(&dn, &dn).sqrt() * dot(&upn, &upn).sqrt();
    if scale.is_nan() || scale <= 0.0 || dot(&c, &c).sqrt() <= 1e-12 * scale {
        bail!(
            "view-up {:?} is parallel to the view direction {:?} (or zero): give another --up",
            cam.up,
            d
        );
    }
    Ok(())
}

/// Reads ParaView's saved camera (`File > Save Camera`, .pvcc): the `CameraPosition`,
/// `CameraFocalPoint`, `CameraViewUp`, `CameraViewAngle`, `CameraParallelScale` and
/// `CameraParallelProjection` properties. Errors name the file and line.
pub fn read_pvcc(path: &Path) -> Result<Camera> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read camera file", path.display()))?;
    parse_pvcc(&text)
        .map_err(|(line, msg)| anyhow::anyhow!("{}: line {line}: {msg}", path.display()))
}

/// Parses .pvcc text; errors carry the 1-based line.
pub fn parse_pvcc(text: &str) -> std::result::Result<Camera, (usize, String)> {
    use quick_xml::events::Event;
    let line_at = |byte: u64| {
        1 + text.as_bytes()[..(byte as usize).min(text.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    };
    let mut reader = quick_xml::Reader::from_str(text);
    let mut cam = Camera::default();
    let mut seen_root = false;
    let mut found = [false; 3];
    // (property name, line where it started, values by index)
    let mut current: Option<(String, usize, Vec<Option<f64>>)> = None;
    loop {
        let start = reader.buffer_position();
        let ev = reader.read_event().map_err(|e| {
            (
                line_at(reader.error_position()),
                format!("malformed XML: {e}"),
            )
        })?;
        let line = line_at(start);
        let attrs = |e: &quick_xml::events::BytesStart| -> std::result::Result<Vec<(String, String)>, (usize, String)> {
            let mut out = Vec::new();
            for a in e.attributes() {
                let a = a.map_err(|err| (line, format!("bad attribute: {err}")))?;
                let v = a
                    .unescape_value()
                    .map_err(|err| (line, format!("bad attribute value: {err}")))?;
                out.push((String::from_utf8_lossy(a.key.as_ref()).into_owned(), v.into_owned()));
            }
            Ok(out)
        };
        match ev {
            Event::Start(e) | Event::Empty(e) => {
                let name = e.name().as_ref().to_vec();
                match name.as_slice() {
                    b"PVCameraConfiguration" => seen_root = true,
                    b"Property" => {
                        let a = attrs(&e)?;
                        let pname = a.iter().find(|(k, _)| k == "name").map(|(_, v)| v.clone());
                        if let Some(p) = pname {
                            current = Some((p, line, Vec::new()));
                        }
                    }
                    b"Element" => {
                        let Some((_, _, vals)) = current.as_mut() else {
                            continue;
                        };
                        let a = attrs(&e)?;
                        let get = |k: &str| a.iter().find(|(n, _)| n == k).map(|(_, v)| v.as_str());
                        let (Some(i), Some(v)) = (get("index"), get("value")) else {
                            return Err((
                                line,
                                "<Element> needs index and value attributes".into(),
                            ));
                        };
                        let i: usize = i
                            .parse()
                            .map_err(|_| (line, format!("element index '{i}' is not a number")))?;
                        let v: f64 = v
                            .parse()
                            .map_err(|_| (line, format!("element value '{v}' is not a number")))?;
                        if !v.is_finite() || i > 16 {
                            return Err((line, format!("element {i} value {v} is out of range")));
                        }
                        if vals.len() <= i {
                            vals.resize(i + 1, None);
                        }
                        vals[i] = Some(v);
                    }
                    _ => {}
                }
            }
            Event::End(e) if e.name().as_ref() == b"Property" => {
                if let Some((name, pline, vals)) = current.take() {
                    let need = |n: usize| -> std::result::Result<Vec<f64>, (usize, String)> {
                        if vals.len() < n || vals[..n].iter().any(|v| v.is_none()) {
                            return Err((pline, format!("property {name} needs {n} elements")));
                        }
                        Ok(vals[..n].iter().map(|v| v.unwrap_or(0.0)).collect())
                    };
                    let v3 = |v: Vec<f64>| [v[0], v[1], v[2]];
                    match name.as_str() {
                        "CameraPosition" => {
                            cam.position = v3(need(3)?);
                            found[0] = true;
                        }
                        "CameraFocalPoint" => {
                            cam.focal = v3(need(3)?);
                            found[1] = true;
                        }
                        "CameraViewUp" => {
                            cam.up = v3(need(3)?);
                            if cam.up == [0.0; 3] {
                                return Err((pline, "CameraViewUp is the zero vector".into()));
                            }
                            found[2] = true;
                        }
                        "CameraViewAngle" => {
                            let a = need(1)?[0];
                            if !(a > 0.0 && a < 180.0) {
                                return Err((
                                    pline,
                                    format!("CameraViewAngle {a} is not in (0, 180)"),
                                ));
                            }
                            cam.view_angle = a;
                        }
                        "CameraParallelScale" => {
                            let s = need(1)?[0];
                            if s > 0.0 {
                                cam.parallel_scale = s;
                            }
                        }
                        "CameraParallelProjection" => cam.parallel = need(1)?[0] != 0.0,
                        _ => {}
                    }
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    let last = line_at(text.len() as u64);
    if !seen_root {
        return Err((
            1,
            "not a ParaView camera file (no <PVCameraConfiguration>)".into(),
        ));
    }
    for (k, n) in ["CameraPosition", "CameraFocalPoint", "CameraViewUp"]
        .iter()
        .enumerate()
    {
        if !found[k] {
            return Err((last, format!("property {n} is missing")));
        }
    }
    if cam.position == cam.focal {
        return Err((
            last,
            format!(
                "CameraPosition {:?} equals CameraFocalPoint: no view direction",
                cam.position
            ),
        ));
    }
    Ok(cam)
}

#[cfg(test)]
mod tests {
    use super::*;

    const PVCC: &str = r#"<?xml version="1.0"?>
<PVCameraConfiguration description="ParaView camera configuration" version="1.0">
  <Proxy group="views" type="RenderView" id="4955" servers="21">
    <Property name="CameraPosition" id="4955.CameraPosition" number_of_elements="3">
      <Element index="0" value="0.5"/>
      <Element index="1" value="-3"/>
      <Element index="2" value="2.25"/>
    </Property>
    <Property name="CameraFocalPoint" id="4955.CameraFocalPoint" number_of_elements="3">
      <Element index="0" value="0.5"/>
      <Element index="1" value="0.5"/>
      <Element index="2" value="0.5"/>
    </Property>
    <Property name="CameraViewUp" id="4955.CameraViewUp" number_of_elements="3">
      <Element index="0" value="0"/>
      <Element index="1" value="0"/>
      <Element index="2" value="1"/>
    </Property>
    <Property name="CenterOfRotation" id="4955.CenterOfRotation" number_of_elements="3">
      <Element index="0" value="0.5"/>
      <Element index="1" value="0.5"/>
      <Element index="2" value="0.5"/>
    </Property>
    <Property name="RotationFactor" id="4955.RotationFactor" number_of_elements="1">
      <Element index="0" value="1"/>
    </Property>
    <Property name="CameraViewAngle" id="4955.CameraViewAngle" number_of_elements="1">
      <Element index="0" value="25"/>
    </Property>
    <Property name="CameraParallelScale" id="4955.CameraParallelScale" number_of_elements="1">
      <Element index="0" value="0.866"/>
    </Property>
    <Property name="CameraParallelProjection" id="4955.CameraParallelProjection" number_of_elements="1">
      <Element index="0" value="1"/>
      <Domain name="bool" id="4955.CameraParallelProjection.bool"/>
    </Property>
  </Proxy>
</PVCameraConfiguration>
"#;

    fn unit() -> Aabb {
        Aabb {
            min: [0.0; 3],
            max: [1.0; 3],
        }
    }

    #[test]
    fn pvcc_parses() {
        let c = parse_pvcc(PVCC).unwrap();
        assert_eq!(c.position, [0.5, -3.0, 2.25]);
        assert_eq!(c.focal, [0.5; 3]);
        assert_eq!(c.up, [0.0, 0.0, 1.0]);
        assert_eq!(c.view_angle, 25.0);
        assert_eq!(c.parallel_scale, 0.866);
        assert!(c.parallel);
    }

    #[test]
    fn pvcc_errors_name_the_line() {
        let bad = PVCC.replace("value=\"-3\"", "value=\"abc\"");
        let (line, msg) = parse_pvcc(&bad).unwrap_err();
        assert_eq!(line, 6, "{msg}");
        let missing = PVCC.replace("CameraViewUp", "SomethingElse");
        let (_, msg) = parse_pvcc(&missing).unwrap_err();
        assert!(msg.contains("CameraViewUp"), "{msg}");
        assert!(parse_pvcc("<a><b></a>").is_err());
    }

    #[test]
    fn default_is_reset_to_bounds() {
        let cam = CameraArgs::default().camera(&unit()).unwrap();
        assert_eq!(cam.focal, [0.5; 3]);
        assert!(cam.position[2] > 1.0);
        assert!((cam.position[0] - 0.5).abs() < 1e-12);
    }

    #[test]
    fn explicit_then_paraview_rotations() {
        let args = CameraArgs {
            position: Some([0.5, 0.5, 5.0]),
            azimuth: Some(90.0),
            ..Default::default()
        };
        let cam = args.camera(&unit()).unwrap();
        assert_eq!(cam.focal, [0.5; 3]);
        assert!((cam.position[0] - 5.0).abs() < 1e-9, "{:?}", cam.position);
        let bad = CameraArgs {
            position: Some([0.5, 5.0, 0.5]),
            ..Default::default()
        };
        assert!(
            bad.camera(&unit()).is_err(),
            "up parallel to the view must fail"
        );
        let same = CameraArgs {
            position: Some([0.5; 3]),
            ..Default::default()
        };
        assert!(same.camera(&unit()).is_err());
    }

    #[test]
    fn parses_vectors() {
        assert_eq!(parse_vec3("1,-2.5,3e1").unwrap(), [1.0, -2.5, 30.0]);
        assert!(parse_vec3("1,2").is_err());
        assert!(parse_vec3("1,2,nan").is_err());
    }
}
