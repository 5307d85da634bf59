//! [`Mp4Writer`]: H.264 MP4 through an `ffmpeg` child process fed raw
//! YUV 4:2:0 frames on its stdin, which never waits on ffmpeg forever.
//!
//! The frames are converted to yuv420p with BT.709 colours in limited range,
//! dimensions padded to even numbers with the background colour, here
//! (`frame_yuv`: only the rows a frame changes are converted, and the pipe
//! carries 1.5 bytes per pixel instead of 4). ffmpeg encodes them with
//! libx264 as they come ([`ffmpeg_arguments`]), tagged BT.709 and limited
//! range, into the video's hidden temporary file. It runs in a process group of its
//! own, registered with the run's partial files, so an interrupt kills it
//! before removing that file (see `partial_file.rs`).
//!
//! A pipe to a process that stops reading blocks its writer forever, so
//! frames go to ffmpeg's stdin from a feeder thread and the video thread
//! waits for each frame to be taken for at most the **ffmpeg timeout**:
//! `ELASTO_FFMPEG_TIMEOUT_SECS` seconds (default 60; any positive number).
//! After the last frame, ffmpeg may take as long as it needs to finish as
//! long as the video file keeps changing, but no longer than the timeout
//! without a change. The `-encoders` probe before the run is bounded by the
//! same timeout. An ffmpeg that stalls is killed with its process group and
//! the run fails naming the limit; the sequence writer then removes the
//! partial video.

use super::RenderError;
use super::frame_image::FrameImage;
use super::frame_yuv::{Yuv420Frames, padded_size};
use super::partial_file::{PartialFile, SpawnError, kill_and_reap, spawn_process, try_reap};
use super::video::{VideoSpec, VideoWriter};
use crossbeam_channel::{Receiver, RecvTimeoutError, Sender, bounded};
use std::ffi::OsString;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The environment variable that sets the ffmpeg timeout, in seconds.
pub const FFMPEG_TIMEOUT_VARIABLE: &str = "ELASTO_FFMPEG_TIMEOUT_SECS";

/// The ffmpeg timeout without [`FFMPEG_TIMEOUT_VARIABLE`].
const DEFAULT_TIMEOUT: Duration = Duration::from_secs(60);

/// How often a wait for ffmpeg looks at the process and the video file.
const POLL: Duration = Duration::from_millis(20);

/// How long to wait for ffmpeg's output once it has exited (its pipe closes
/// with it unless something it started keeps it open).
const OUTPUT_GRACE: Duration = Duration::from_secs(2);

/// How long ffmpeg may go without progress: [`FFMPEG_TIMEOUT_VARIABLE`] in
/// seconds when it is set and not empty, else 60 s.
pub(crate) fn ffmpeg_timeout() -> Result<Duration, RenderError> {
    parse_timeout(std::env::var_os(FFMPEG_TIMEOUT_VARIABLE).as_deref())
}

/// The ffmpeg timeout for the variable's value.
fn parse_timeout(value: Option<&std::ffi::OsStr>) -> Result<Duration, RenderError> {
    let Some(value) = value else {
        return Ok(DEFAULT_TIMEOUT);
    };
    let text = value.to_string_lossy();
    if text.trim().is_empty() {
        return Ok(DEFAULT_TIMEOUT);
    }
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|&seconds| seconds > 0.0)
        .and_then(|seconds| Duration::try_from_secs_f64(seconds).ok())
        .ok_or_else(|| RenderError::FfmpegTimeoutSetting {
            value: text.into_owned(),
        })
}

/// The `PATH` under which ffmpeg last listed libx264: a run asks up to three
/// times (choosing its videos, validating them, opening the writer), and
/// each `ffmpeg -encoders` costs about 0.1 s before anything is drawn.
static H264_FOUND_ON_PATH: Mutex<Option<Option<OsString>>> = Mutex::new(None);

/// Checks that `ffmpeg` on `PATH` can encode H.264 (lists libx264 among its
/// encoders), waiting for it at most the ffmpeg timeout. A success is
/// remembered for the process as long as `PATH` stays the same.
pub(crate) fn check_h264() -> Result<(), RenderError> {
    let timeout = ffmpeg_timeout()?;
    let path = std::env::var_os("PATH");
    let mut found = H264_FOUND_ON_PATH
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if found.as_ref() == Some(&path) {
        return Ok(());
    }
    list_h264(timeout)?;
    *found = Some(path);
    Ok(())
}

/// Runs `ffmpeg -encoders` and looks for libx264.
fn list_h264(timeout: Duration) -> Result<(), RenderError> {
    let failed = |message: String| RenderError::Ffmpeg {
        path: "video.mp4".into(),
        message,
    };
    let mut command = Command::new("ffmpeg");
    command
        .args(["-hide_banner", "-encoders"])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null());
    let mut child = spawn_process(&mut command).map_err(|error| match error {
        SpawnError::Interrupted => RenderError::Interrupted,
        SpawnError::Io(e) if e.kind() == std::io::ErrorKind::NotFound => RenderError::FfmpegMissing,
        SpawnError::Io(e) => failed(format!("cannot run ffmpeg: {e}")),
    })?;
    let stdout = read_on_thread(child.stdout.take());
    let status = wait_with_timeout(&mut child, timeout, || None)
        .map_err(|e| failed(format!("cannot wait for ffmpeg: {e}")))?;
    if status.is_none() {
        return Err(RenderError::FfmpegStalled {
            path: "video.mp4".into(),
            what: "did not list its encoders",
            timeout,
        });
    }
    let listing = stdout.recv_timeout(OUTPUT_GRACE).unwrap_or_default();
    if listing.contains("libx264") {
        Ok(())
    } else {
        Err(RenderError::FfmpegWithoutH264)
    }
}

/// Writes `video.mp4` through ffmpeg.
pub(crate) struct Mp4Writer {
    /// The final path, for messages.
    path: PathBuf,
    /// The file ffmpeg writes.
    temporary: PathBuf,
    child: Child,
    /// The feeder thread's queue (`None` once the input is closed).
    input: Option<FrameFeeder>,
    /// ffmpeg's error output, once it has closed it.
    stderr: Receiver<String>,
    timeout: Duration,
    /// ffmpeg has exited (or was killed) and is reaped.
    reaped: bool,
}

/// The queue to the thread that writes frames to ffmpeg's stdin, and its
/// answers: one per frame, once the frame is written (or the write failed).
struct FrameFeeder {
    frames: Sender<Arc<FrameImage>>,
    written: Receiver<std::io::Result<()>>,
}

impl FrameFeeder {
    /// Starts the thread. It ends when the queue closes (then ffmpeg sees the
    /// end of its input) or a write fails; it is never joined, so a write
    /// that blocks forever cannot block anything else.
    fn spawn(mut stdin: ChildStdin, mut planes: Yuv420Frames) -> Self {
        let (frames, queue) = bounded::<Arc<FrameImage>>(1);
        let (answer, written) = bounded(1);
        std::thread::spawn(move || {
            for frame in queue {
                let mut result = Ok(());
                planes.for_each_span(&frame, |span| {
                    if result.is_ok() {
                        result = stdin.write_all(span);
                    }
                });
                let failed = result.is_err();
                if answer.send(result).is_err() || failed {
                    break;
                }
            }
        });
        Self { frames, written }
    }
}

/// The ffmpeg arguments for `spec`, reading yuv420p frames of the size
/// padded to even numbers and writing MP4 to `output`.
pub(crate) fn ffmpeg_arguments(spec: &VideoSpec<'_>, output: &Path) -> Vec<String> {
    let mut args: Vec<String> = [
        "-hide_banner",
        "-loglevel",
        "error",
        "-nostdin",
        "-y",
        "-f",
        "rawvideo",
        "-pix_fmt",
        "yuv420p",
        "-s",
    ]
    .map(String::from)
    .into();
    let (width, height) = padded_size((spec.width, spec.height));
    args.push(format!("{width}x{height}"));
    args.push("-r".into());
    args.push(format!("{}", spec.fps));
    args.extend(
        [
            "-i", "-", "-c:v", "libx264", "-preset", "medium", "-crf", "18", "-pix_fmt", "yuv420p",
        ]
        .map(String::from),
    );
    args.extend(
        [
            "-color_range",
            "tv",
            "-colorspace",
            "bt709",
            "-color_primaries",
            "bt709",
            "-color_trc",
            "bt709",
            "-movflags",
            "+faststart",
            "-f",
            "mp4",
        ]
        .map(String::from),
    );
    args.push(output.to_string_lossy().into_owned());
    args
}

impl Mp4Writer {
    /// Starts ffmpeg writing the temporary file of `partial`.
    pub fn new(spec: &VideoSpec<'_>, partial: &PartialFile) -> Result<Self, RenderError> {
        let timeout = ffmpeg_timeout()?;
        let mut command = Command::new("ffmpeg");
        command
            .args(ffmpeg_arguments(spec, partial.temporary()))
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        let mut child = spawn_process(&mut command).map_err(|error| match error {
            SpawnError::Interrupted => RenderError::Interrupted,
            SpawnError::Io(e) if e.kind() == std::io::ErrorKind::NotFound => {
                RenderError::FfmpegMissing
            }
            SpawnError::Io(e) => RenderError::Ffmpeg {
                path: spec.path.to_owned(),
                message: format!("cannot start ffmpeg: {e}"),
            },
        })?;
        let planes = Yuv420Frames::new((spec.width, spec.height), spec.background);
        let input = child
            .stdin
            .take()
            .map(|stdin| FrameFeeder::spawn(stdin, planes));
        // Drain stderr on a thread so that a chatty ffmpeg never blocks on it.
        let stderr = read_on_thread(child.stderr.take());
        Ok(Self {
            path: spec.path.to_owned(),
            temporary: partial.temporary().to_owned(),
            child,
            input,
            stderr,
            timeout,
            reaped: false,
        })
    }

    /// Closes ffmpeg's input and waits for it to finish while the video file
    /// keeps changing; turns a failure into an error with its output.
    fn wait(&mut self) -> Result<(), RenderError> {
        self.input = None;
        let temporary = self.temporary.clone();
        let mut last_size = None;
        let progress = move || {
            let size = std::fs::metadata(&temporary).ok().map(|m| m.len());
            let changed = size != last_size;
            last_size = size;
            changed.then_some(())
        };
        let status = match wait_with_timeout(&mut self.child, self.timeout, progress) {
            Ok(Some(status)) => status,
            Ok(None) => return Err(self.stalled("made no progress finishing the video")),
            Err(e) => {
                self.kill();
                return Err(RenderError::Ffmpeg {
                    path: self.path.clone(),
                    message: format!("cannot wait for ffmpeg: {e}"),
                });
            }
        };
        self.reaped = true;
        let output = self.stderr.recv_timeout(OUTPUT_GRACE).unwrap_or_default();
        if status.success() {
            Ok(())
        } else {
            let output = output.trim();
            Err(RenderError::Ffmpeg {
                path: self.path.clone(),
                message: if output.is_empty() {
                    format!("{status}")
                } else {
                    format!("{status}: {output}")
                },
            })
        }
    }

    /// Kills ffmpeg and its process group.
    fn kill(&mut self) {
        self.input = None;
        if !self.reaped {
            kill_and_reap(&mut self.child);
            self.reaped = true;
        }
    }

    /// Kills a stalled ffmpeg; the error says what it failed to do.
    fn stalled(&mut self, what: &'static str) -> RenderError {
        self.kill();
        RenderError::FfmpegStalled {
            path: self.path.clone(),
            what,
            timeout: self.timeout,
        }
    }

    /// ffmpeg stopped taking frames: its exit status and output say why.
    fn stopped_reading(&mut self, cause: String) -> RenderError {
        match self.wait() {
            Err(error) => error,
            Ok(()) => RenderError::Ffmpeg {
                path: self.path.clone(),
                message: format!("ffmpeg stopped reading frames: {cause}"),
            },
        }
    }
}

impl VideoWriter for Mp4Writer {
    fn push(&mut self, frame: &Arc<FrameImage>) -> Result<(), RenderError> {
        let Some(input) = self.input.as_ref() else {
            return Err(RenderError::Ffmpeg {
                path: self.path.clone(),
                message: "ffmpeg input already closed".into(),
            });
        };
        // The feeder is idle (every earlier frame was answered): this never waits.
        if input.frames.send(frame.clone()).is_err() {
            return Err(self.stopped_reading("its input is closed".into()));
        }
        match input.written.recv_timeout(self.timeout) {
            Ok(Ok(())) => Ok(()),
            // ffmpeg quit early; its own message says why.
            Ok(Err(e)) => Err(self.stopped_reading(e.to_string())),
            Err(RecvTimeoutError::Disconnected) => {
                Err(self.stopped_reading("its input is closed".into()))
            }
            Err(RecvTimeoutError::Timeout) => Err(self.stalled("read no frame")),
        }
    }

    fn finish(mut self: Box<Self>) -> Result<(), RenderError> {
        self.wait()
    }
}

impl Drop for Mp4Writer {
    /// An abandoned encode: stop ffmpeg and reap it.
    fn drop(&mut self) {
        self.kill();
    }
}

/// Reads `pipe` to its end on a thread of its own; the text arrives on the
/// returned channel (never, if something keeps the pipe open).
fn read_on_thread(pipe: Option<impl Read + Send + 'static>) -> Receiver<String> {
    let (sender, receiver) = bounded(1);
    if let Some(mut pipe) = pipe {
        std::thread::spawn(move || {
            let mut text = String::new();
            let _ = pipe.read_to_string(&mut text);
            let _ = sender.send(text);
        });
    }
    receiver
}

/// Waits for `child` to exit while `progress` reports changes (`Some`), and
/// at most `timeout` since the start or the last change. `Ok(None)`: the
/// child stalled and was killed.
fn wait_with_timeout(
    child: &mut Child,
    timeout: Duration,
    mut progress: impl FnMut() -> Option<()>,
) -> std::io::Result<Option<ExitStatus>> {
    let mut last_change = Instant::now();
    loop {
        if let Some(status) = try_reap(child)? {
            return Ok(Some(status));
        }
        if progress().is_some() {
            last_change = Instant::now();
        } else if last_change.elapsed() >= timeout {
            kill_and_reap(child);
            return Ok(None);
        }
        std::thread::sleep(POLL.min(timeout));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ffmpeg_reads_yuv420p_of_the_size_padded_to_even_numbers() {
        let spec = VideoSpec {
            path: Path::new("v.mp4"),
            width: 101,
            height: 61,
            frame_count: 3,
            fps: 25.0,
            background: [245, 245, 250],
        };
        let args = ffmpeg_arguments(&spec, Path::new(".v.mp4.partial"));
        let joined = args.join(" ");
        assert!(
            joined.contains("-f rawvideo -pix_fmt yuv420p -s 102x62 -r 25 -i -"),
            "{joined}"
        );
        assert!(
            joined.contains("-color_range tv -colorspace bt709"),
            "{joined}"
        );
        assert!(
            joined.contains("-c:v libx264") && joined.contains("-pix_fmt yuv420p"),
            "{joined}"
        );
        assert_eq!(args.last().unwrap(), ".v.mp4.partial");
    }

    #[test]
    fn a_child_without_progress_is_killed_after_the_timeout() {
        let mut command = Command::new("sleep");
        command.arg("30");
        let mut child = spawn_process(&mut command).unwrap();
        let start = Instant::now();
        let status = wait_with_timeout(&mut child, Duration::from_millis(200), || None).unwrap();
        assert_eq!(status, None);
        let waited = start.elapsed();
        assert!(waited >= Duration::from_millis(200), "{waited:?}");
        assert!(waited < Duration::from_secs(5), "{waited:?}");
        // Killed and reaped.
        assert!(child.try_wait().unwrap().is_some());
    }

    #[test]
    fn the_timeout_is_a_positive_number_of_seconds() {
        let parse = |text: &str| parse_timeout(Some(std::ffi::OsStr::new(text)));
        assert_eq!(parse_timeout(None).unwrap(), Duration::from_secs(60));
        assert_eq!(parse("").unwrap(), Duration::from_secs(60));
        assert_eq!(parse("2").unwrap(), Duration::from_secs(2));
        assert_eq!(parse(" 0.25 ").unwrap(), Duration::from_millis(250));
        for bad in ["0", "-1", "abc", "NaN", "inf", "1e300"] {
            let error = parse(bad).unwrap_err().to_string();
            assert!(
                error.contains("ELASTO_FFMPEG_TIMEOUT_SECS") && error.contains(bad),
                "{bad}: {error}"
            );
        }
    }

    #[test]
    fn a_child_that_exits_is_reaped_with_its_status() {
        let mut command = Command::new("sh");
        command.args(["-c", "exit 3"]);
        let mut child = spawn_process(&mut command).unwrap();
        let status = wait_with_timeout(&mut child, Duration::from_secs(10), || None)
            .unwrap()
            .unwrap();
        assert_eq!(status.code(), Some(3));
    }
}
