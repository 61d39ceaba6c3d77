//! The float render target and its copy back to host memory as an [`Image`].

use anyhow::{anyhow, Result};

use super::context::{GpuContext, TargetFormat};
use crate::render::image::Image;

/// Render target plus a mappable buffer with rows padded to the copy alignment.
pub struct Target {
    pub width: u32,
    pub height: u32,
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    pub buffer: wgpu::Buffer,
    pub row_bytes: u32,
    pub format: TargetFormat,
}

impl Target {
    pub fn new(ctx: &GpuContext, width: u32, height: u32) -> Result<Target> {
        let max2 = ctx.limits.max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max2 || height > max2 {
            return Err(anyhow!(
                "GPU '{}': image {width}x{height} is outside 1..={max2} per side",
                ctx.info.name
            ));
        }
        let format = ctx.format;
        let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("target"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: format.wgpu(),
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let row_bytes = (width * format.texel_bytes()).div_ceil(align) * align;
        let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: row_bytes as u64 * height as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(Target {
            width,
            height,
            texture,
            view,
            buffer,
            row_bytes,
            format,
        })
    }

    /// Records the copy of the target into the readback buffer.
    pub fn copy(&self, enc: &mut wgpu::CommandEncoder) {
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.row_bytes),
                    rows_per_image: Some(self.height),
                },
            },
            wgpu::Extent3d {
                width: self.width,
                height: self.height,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Maps the readback buffer (after the copy was submitted) and unpacks it.
    pub fn read(&self, ctx: &GpuContext) -> Result<Image> {
        let bytes = map_read(ctx, &self.buffer)?;
        let mut img = Image::new(self.width, self.height);
        let w = self.width as usize;
        for (y, out) in img.pixels.chunks_mut(w).enumerate() {
            let row = &bytes[y * self.row_bytes as usize..];
            match self.format {
                TargetFormat::Rgba32Float => {
                    for (x, px) in out.iter_mut().enumerate() {
                        for (k, c) in px.iter_mut().enumerate() {
                            let o = (x * 4 + k) * 4;
                            *c = f32::from_le_bytes([row[o], row[o + 1], row[o + 2], row[o + 3]]);
                        }
                    }
                }
                TargetFormat::Rgba16Float => {
                    for (x, px) in out.iter_mut().enumerate() {
                        for (k, c) in px.iter_mut().enumerate() {
                            let o = (x * 4 + k) * 2;
                            *c = f16_to_f32(u16::from_le_bytes([row[o], row[o + 1]]));
                        }
                    }
                }
            }
        }
        self.buffer.unmap();
        Ok(img)
    }
}

/// Maps a whole MAP_READ buffer and copies it out.
pub fn map_read(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    ctx.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| anyhow!("GPU '{}': waiting for the readback: {e}", ctx.info.name))?;
    rx.recv()
        .map_err(|_| anyhow!("GPU '{}': readback callback never ran", ctx.info.name))?
        .map_err(|e| anyhow!("GPU '{}': mapping the readback buffer: {e}", ctx.info.name))?;
    let view = buffer
        .get_mapped_range(..)
        .map_err(|e| anyhow!("GPU '{}': reading the readback buffer: {e}", ctx.info.name))?;
    let out = view.to_vec();
    drop(view);
    Ok(out)
}

/// IEEE half to single precision.
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = ((h >> 15) as u32) << 31;
    let exp = ((h >> 10) & 0x1f) as u32;
    let man = (h & 0x3ff) as u32;
    let bits = match (exp, man) {
        (0, 0) => sign,
        (0, m) => {
            // Subnormal: value m * 2^-24.
            let v = m as f32 * (1.0 / 16_777_216.0);
            return if sign != 0 { -v } else { v };
        }
        (31, 0) => sign | 0x7f80_0000,
        (31, m) => sign | 0x7fc0_0000 | (m << 13),
        (e, m) => sign | ((e + 112) << 23) | (m << 13),
    };
    f32::from_bits(bits)
}

#[cfg(test)]
mod tests {
    use super::f16_to_f32;

    #[test]
    fn half_floats_convert() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x3800), 0.5);
        assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(f16_to_f32(0x7bff), 65504.0);
        assert!(f16_to_f32(0x7c00).is_infinite());
        assert!(f16_to_f32(0x7e00).is_nan());
        assert_eq!(f16_to_f32(0x0000), 0.0);
    }
}
