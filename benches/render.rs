//! Renderer benchmark: milliseconds per frame (median of N) for drawing,
//! readback, pasting the tile into the base image (and the legend where it
//! meets it) and PNG encoding, at 1280x720 and 1920x1080, for a 2D and a 3D
//! box mesh; and the time per frame of N frames drawn one after the other
//! (each read back before the next is drawn) and pipelined as a run draws
//! them (frame `k` read back while `k + 1` is drawn, through the ring of
//! staging buffers).
//!
//! `cargo bench --bench render` (N = 15 frames, or `ELASTO_BENCH_FRAMES`).

use elasto::encode::write_png;
use elasto::math::{Vector, Vector2, Vector3};
use elasto::mesh::Mesh;
use elasto::render::{
    Colouring, FRAMES_IN_FLIGHT, FrameTimings, RenderFrame, RenderMesh, RenderSettings, Renderer,
    adapter_description,
};
use std::time::{Duration, Instant};

fn main() {
    let samples: usize = std::env::var("ELASTO_BENCH_FRAMES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(15)
        .max(1);
    let adapter = match adapter_description() {
        Ok(adapter) => adapter,
        Err(error) => {
            eprintln!("render benchmark: {error}");
            std::process::exit(1);
        }
    };
    println!("adapter: {adapter}");
    println!("median of {samples} frames, in milliseconds per frame\n");
    println!(
        "| mesh                         | image     |  draw | readback | paste + legend | PNG encode+write | total | one by one | pipelined |"
    );
    println!(
        "|------------------------------|-----------|------:|---------:|---------------:|-----------------:|------:|-----------:|----------:|"
    );

    let box_2d = Mesh::<2>::axis_aligned_box(Vector2::zeros(), Vector2::new(4.0, 1.0), [40, 10])
        .expect("valid box");
    let box_3d = Mesh::<3>::axis_aligned_box(Vector3::zeros(), Vector3::repeat(1.0), [10, 10, 10])
        .expect("valid box");
    let cases = [
        (
            format!("2D box, {} triangles", box_2d.element_count()),
            RenderMesh::from_mesh(&box_2d),
            sway(&box_2d),
        ),
        (
            format!("3D box, {} tetrahedra", box_3d.element_count()),
            RenderMesh::from_mesh(&box_3d),
            sway(&box_3d),
        ),
    ];
    let output = tempfile::tempdir().expect("a temporary folder");
    for (name, mesh, frames) in &cases {
        for (width, height) in [(1280, 720), (1920, 1080)] {
            let settings = RenderSettings {
                width,
                height,
                colouring: Colouring::Scalar {
                    range: None,
                    label: "strain energy density",
                },
                ground_height: Some(-0.05),
                ..RenderSettings::default()
            };
            let mut renderer = match Renderer::new(&settings, mesh, frames) {
                Ok(renderer) => renderer,
                Err(error) => {
                    eprintln!("render benchmark: {error}");
                    std::process::exit(1);
                }
            };
            // Warm-up: shader compilation and first-use allocations.
            for frame in frames.iter().take(2) {
                renderer.render(frame).expect("render");
            }
            let mut timings: Vec<FrameTimings> = Vec::with_capacity(samples);
            let mut encode: Vec<Duration> = Vec::with_capacity(samples);
            for i in 0..samples {
                let (image, timing) = renderer
                    .render_timed(&frames[i % frames.len()])
                    .expect("render");
                timings.push(timing);
                let path = output.path().join(format!("frame_{i:04}.png"));
                let start = Instant::now();
                write_png(&path, &image).expect("write png");
                encode.push(start.elapsed());
            }
            let draw = median(timings.iter().map(|t| t.draw));
            let readback = median(timings.iter().map(|t| t.readback));
            let overlay = median(timings.iter().map(|t| t.overlay));
            let png = median(encode.iter().copied());
            let total = median(
                timings
                    .iter()
                    .zip(&encode)
                    .map(|(t, e)| t.draw + t.readback + t.overlay + *e),
            );
            // The same frames one by one, and pipelined as a run draws them.
            let start = Instant::now();
            for i in 0..samples {
                renderer.render(&frames[i % frames.len()]).expect("render");
            }
            let one_by_one = start.elapsed().as_secs_f64() * 1e3 / samples as f64;
            let start = Instant::now();
            for i in 0..samples {
                renderer.start(&frames[i % frames.len()]).expect("render");
                if renderer.frames_in_flight() == FRAMES_IN_FLIGHT {
                    renderer.finish().expect("render");
                }
            }
            while renderer.finish().expect("render").is_some() {}
            let pipelined = start.elapsed().as_secs_f64() * 1e3 / samples as f64;
            println!(
                "| {name:<28} | {width}x{height:<4} | {draw:5.1} | {readback:8.1} | {overlay:14.1} | {png:16.1} | {total:5.1} | {one_by_one:10.1} | {pipelined:9.1} |"
            );
        }
    }
}

/// Eight frames of the box swaying sideways, with a varying scalar field.
fn sway<const D: usize>(mesh: &Mesh<D>) -> Vec<RenderFrame> {
    (0..8)
        .map(|k| {
            let t = k as f64 / 7.0;
            let positions: Vec<Vector<D>> = mesh
                .rest_positions()
                .iter()
                .map(|p| {
                    let mut q = *p;
                    q[0] += 0.15 * t * p[1] * p[1];
                    q
                })
                .collect();
            let values: Vec<f64> = (0..mesh.element_count())
                .map(|e| t * mesh.rest_positions()[mesh.simplex(e)[0]][1])
                .collect();
            RenderFrame::from_positions(&positions, &values)
        })
        .collect()
}

/// Median in milliseconds.
fn median(durations: impl Iterator<Item = Duration>) -> f64 {
    let mut ms: Vec<f64> = durations.map(|d| d.as_secs_f64() * 1e3).collect();
    ms.sort_by(f64::total_cmp);
    ms[ms.len() / 2]
}
