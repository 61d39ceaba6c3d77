//! Rendered images: f32 premultiplied RGBA, error measures, and PNG output over a background.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use anyhow::{anyhow, bail, Context, Result};
use std::path::Path;

/// Row-major, top row first, premultiplied RGBA in [0, 1].
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

/// Parses `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32)> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| anyhow!("--size '{s}': expected WIDTHxHEIGHT, e.g. 512x512"))?;
    let p = |t: &str| -> Result<u32> {
        t.trim()
            .parse::<u32>()
            .ok()
            .filter(|v| (1..=16384).contains(v))
            .ok_or_else(|| anyhow!("--size '{s}': '{t}' is not a size between 1 and 16384"))
    };
    Ok((p(w)?, p(h)?))
}

/// Parses a background colour: `black`, `white`, `r,g,b` (0-1) or `#rrggbb`.
pub fn parse_color(s: &str) -> Result<[f32; 3]> {
    match s {
        "black" => return Ok([0.0; 3]),
        "white" => return Ok([1.0; 3]),
        _ => {}
    }
    if let Some(hex) = s.strip_prefix('#') {
        if hex.len() == 6 {
            if let Ok(v) = u32::from_str_radix(hex, 16) {
                return Ok([16, 8, 0].map(|sh| ((v >> sh) & 255) as f32 / 255.0));
            }
        }
        bail!("--background '{s}': expected #rrggbb");
    }
    let parts: Vec<f32> = s
        .split(',')
        .map(|t| t.trim().parse::<f32>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| anyhow!("--background '{s}': expected black, white, #rrggbb or r,g,b"))?;
    if parts.len() != 3 || parts.iter().any(|v| !(0.0..=1.0).contains(v)) {
        bail!("--background '{s}': expected three numbers in [0, 1]");
    }
    Ok([parts[0], parts[1], parts[2]])
}

impl Image {
    pub fn new(width: u32, height: u32) -> Image {
        Image {
            width,
            height,
            pixels: vec![[0.0; 4]; width as usize * height as usize],
        }
    }

    /// 8-bit RGB over `background` (the background shows through the remaining transparency).
    pub fn to_rgb8(&self, background: [f32; 3]) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.pixels.len() * 3);
        for p in &self.pixels {
            for k in 0..3 {
                let v = p[k] + (1.0 - p[3]) * background[k];
                out.push((v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8);
            }
        }
        out
    }

    /// Writes a PNG atomically (temp file + rename): no partial file on failure.
    pub fn write_png(&self, path: &Path, background: [f32; 3]) -> Result<()> {
        let rgb = self.to_rgb8(background);
        let mut bytes = Vec::new();
        {
            use image::ImageEncoder;
            image::codecs::png::PngEncoder::new(&mut bytes)
                .write_image(
                    &rgb,
                    self.width,
                    self.height,
                    image::ExtendedColorType::Rgb8,
                )
                .with_context(|| format!("{}: encoding PNG", path.display()))?;
        }
        write_atomic(path, &bytes)
    }

    /// Error against a reference, colours composited over `background`, per channel in [0, 1]:
    /// (RMSE, max abs, share of pixels with a channel off by more than 1/255).
    pub fn error_against(&self, reference: &Image, background: [f32; 3]) -> ErrorStats {
        let mut sq = 0.0f64;
        let mut max = 0.0f64;
        let mut off = 0usize;
        let n = self.pixels.len().min(reference.pixels.len());
        for (a, b) in self.pixels.iter().zip(&reference.pixels) {
            let mut px_off = false;
            for k in 0..3 {
                let va = a[k] + (1.0 - a[3]) * background[k];
                let vb = b[k] + (1.0 - b[3]) * background[k];
                let d = (va as f64 - vb as f64).abs();
                sq += d * d;
                max = max.max(d);
                px_off |= d > 1.0 / 255.0;
            }
            off += px_off as usize;
        }
        ErrorStats {
            rmse: (sq / (3 * n.max(1)) as f64).sqrt(),
            max,
            share_off: off as f64 / n.max(1) as f64,
        }
    }

    pub fn has_nan(&self) -> bool {
        self.pixels.iter().any(|p| p.iter().any(|v| !v.is_finite()))
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorStats {
    pub rmse: f64,
    pub max: f64,
    pub share_off: f64,
}

/// Writes bytes through a temp file renamed over `path`: no partial file on failure.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write;
    let mut f = formats::atomic::AtomicFile::create(path)
        .with_context(|| format!("{}: creating", path.display()))?;
    f.writer()
        .write_all(bytes)
        .with_context(|| format!("{}: writing", path.display()))?;
    f.commit()
        .with_context(|| format!("{}: writing", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parsing() {
        assert_eq!(parse_size("640x480").unwrap(), (640, 480));
        assert!(parse_size("0x4").is_err());
        assert_eq!(parse_color("#ff0000").unwrap(), [1.0, 0.0, 0.0]);
        assert_eq!(parse_color("0,0.5,1").unwrap(), [0.0, 0.5, 1.0]);
        assert!(parse_color("2,0,0").is_err());
    }
}
