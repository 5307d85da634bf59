//! Asking for MP4 without ffmpeg on PATH is a clear error before any work.
//! (Its own test binary: it empties PATH for the whole process.)

use elasto::render::{
    RenderError, RenderOutputs, RenderSettings, VideoFormat, check_video_support, render_sequence,
};

#[test]
fn mp4_without_ffmpeg_is_refused_up_front() {
    let empty = tempfile::tempdir().unwrap();
    // SAFETY: this test binary has this single test, so no other thread
    // reads the environment while it changes.
    unsafe { std::env::set_var("PATH", empty.path()) };

    let error = check_video_support(&[VideoFormat::Apng, VideoFormat::Mp4]).unwrap_err();
    assert!(matches!(error, RenderError::FfmpegMissing), "{error}");
    let message = error.to_string();
    assert!(
        message.contains("ffmpeg") && message.contains("PATH") && message.contains("mp4"),
        "{message}"
    );
    check_video_support(&[VideoFormat::Apng, VideoFormat::Gif]).unwrap();
    check_video_support(&[]).unwrap();

    // render_sequence checks first: nothing is rendered or written.
    let out = tempfile::tempdir().unwrap();
    let outputs = RenderOutputs {
        frames_dir: out.path().join("frames"),
        video_dir: out.path().join("video"),
        videos: vec![VideoFormat::Mp4],
        fps: 30.0,
    };
    let (mesh, frame) = (
        elasto::render::RenderMesh {
            dimension: 2,
            triangles: vec![[0, 1, 2]],
            triangle_element: vec![0],
            edges: vec![],
            element_count: 1,
        },
        elasto::render::RenderFrame {
            positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            element_values: vec![0.0],
        },
    );
    let error = render_sequence(
        &RenderSettings::default(),
        &mesh,
        &[frame],
        &outputs,
        &mut |_| {},
    )
    .unwrap_err();
    assert!(matches!(error, RenderError::FfmpegMissing), "{error}");
    assert!(!out.path().join("frames").exists());
}
