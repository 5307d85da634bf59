//! Reading a rendered texture back: the copy into a buffer with rows padded
//! to `COPY_BYTES_PER_ROW_ALIGNMENT`, the map, the wait, and the rows
//! without their padding.

use super::RenderError;
use super::gpu::{Gpu, check_scope, wait};

/// Copies the top-left `size` pixels of `texture` into `buffer` (rows
/// `padded_bytes_per_row` apart), maps it, waits, and hands each row's
/// pixels, without the padding, to `row` with its index.
pub(super) fn read_texture(
    gpu: &Gpu,
    texture: &wgpu::Texture,
    buffer: &wgpu::Buffer,
    padded_bytes_per_row: u32,
    size: (u32, u32),
    row: impl FnMut(u32, &[u8]),
) -> Result<(), RenderError> {
    let device = &gpu.device;
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback encoder"),
    });
    encode_texture_copy(&mut encoder, texture, buffer, padded_bytes_per_row, size);
    gpu.queue.submit([encoder.finish()]);
    check_scope(validation, "copying a frame")?;
    read_buffer(gpu, buffer, padded_bytes_per_row, size, row)
}

/// Records the copy of the top-left `size` pixels of `texture` into
/// `buffer`, rows `padded_bytes_per_row` apart.
pub(super) fn encode_texture_copy(
    encoder: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    buffer: &wgpu::Buffer,
    padded_bytes_per_row: u32,
    (width, height): (u32, u32),
) {
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_bytes_per_row),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
}

/// Maps `buffer` once the copies submitted into it are done, and hands
/// each of its `size.1` rows' pixels (`size.0` wide, without the padding
/// to `padded_bytes_per_row`) to `row` with its index.
pub(super) fn read_buffer(
    gpu: &Gpu,
    buffer: &wgpu::Buffer,
    padded_bytes_per_row: u32,
    (width, height): (u32, u32),
    mut row: impl FnMut(u32, &[u8]),
) -> Result<(), RenderError> {
    let device = &gpu.device;
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |result| {
        let _ = sender.send(result);
    });
    wait(device, "reading a frame back")?;
    receiver
        .recv()
        .map_err(|_| RenderError::Gpu {
            during: "reading a frame back",
            message: "the map callback never ran".into(),
        })?
        .map_err(|e| RenderError::Gpu {
            during: "reading a frame back",
            message: e.to_string(),
        })?;
    {
        let mapped = buffer.get_mapped_range(..).map_err(|e| RenderError::Gpu {
            during: "reading a frame back",
            message: e.to_string(),
        })?;
        let row_bytes = (width * 4) as usize;
        for (index, padded) in mapped
            .chunks_exact(padded_bytes_per_row as usize)
            .take(height as usize)
            .enumerate()
        {
            row(index as u32, &padded[..row_bytes]);
        }
    }
    buffer.unmap();
    Ok(())
}
