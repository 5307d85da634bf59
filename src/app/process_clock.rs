//! [`Stopwatch`]: wall time and the process's CPU time over a stretch of a
//! run, for `--profile`'s "cores busy".
//!
//! The CPU time is the process's (`CLOCK_PROCESS_CPUTIME_ID`): summed over
//! all its threads — the simulation, the drawing thread, the PNG and video
//! encoders (the MP4's H.264 encoder included), and a software rasteriser's
//! own threads (llvmpipe runs in the process). Over a stretch
//! of wall time `w` with CPU time `c`, `c / w` cores were busy on average;
//! on a machine of `n` cores, `n − c / w` stood idle.

use std::time::{Duration, Instant};

/// Wall and CPU time of a stretch of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    pub wall: Duration,
    /// `None` where the process's CPU time cannot be read.
    pub cpu: Option<Duration>,
}

impl Span {
    /// The average number of busy cores: CPU time over wall time.
    pub fn cores_busy(&self) -> Option<f64> {
        let wall = self.wall.as_secs_f64();
        self.cpu
            .filter(|_| wall > 0.0)
            .map(|cpu| cpu.as_secs_f64() / wall)
    }
}

/// Started at an instant; [`Stopwatch::span`] measures from there.
#[derive(Debug, Clone, Copy)]
pub struct Stopwatch {
    wall: Instant,
    cpu: Option<Duration>,
}

impl Stopwatch {
    pub fn start() -> Self {
        Self {
            wall: Instant::now(),
            cpu: process_cpu_time(),
        }
    }

    /// The wall and CPU time since the start.
    pub fn span(&self) -> Span {
        Span {
            wall: self.wall.elapsed(),
            cpu: self
                .cpu
                .zip(process_cpu_time())
                .map(|(start, now)| now.saturating_sub(start)),
        }
    }
}

/// The CPU time of the whole process so far, all threads together.
#[cfg(unix)]
pub fn process_cpu_time() -> Option<Duration> {
    cpu_clock(libc::CLOCK_PROCESS_CPUTIME_ID)
}

#[cfg(not(unix))]
pub fn process_cpu_time() -> Option<Duration> {
    None
}

#[cfg(unix)]
fn cpu_clock(clock: libc::clockid_t) -> Option<Duration> {
    let mut time = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `time` is a valid timespec for the call to fill.
    let status = unsafe { libc::clock_gettime(clock, &mut time) };
    (status == 0).then(|| Duration::new(time.tv_sec as u64, time.tv_nsec as u32))
}

/// The machine's cores, as the run sees them.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    /// Spins until this thread has used `cpu` of CPU time.
    fn spin_for(cpu: Duration) {
        let start = cpu_clock(libc::CLOCK_THREAD_CPUTIME_ID).unwrap();
        let mut x = 0u64;
        while cpu_clock(libc::CLOCK_THREAD_CPUTIME_ID).unwrap() - start < cpu {
            x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
        }
    }

    #[test]
    fn the_process_cpu_time_sums_every_thread() {
        let watch = Stopwatch::start();
        let per_thread = Duration::from_millis(30);
        std::thread::scope(|scope| {
            for _ in 0..3 {
                scope.spawn(|| spin_for(per_thread));
            }
        });
        let span = watch.span();
        let cpu = span.cpu.expect("Unix has a process CPU clock");
        // Three threads used 30 ms each, whenever they were scheduled (other
        // tests running beside this one can only add to it).
        assert!(cpu >= 3 * per_thread, "{cpu:?}");
        assert!(span.cores_busy().unwrap() > 0.0);
    }

    #[test]
    fn cores_busy_is_cpu_over_wall() {
        let span = Span {
            wall: Duration::from_millis(200),
            cpu: Some(Duration::from_millis(370)),
        };
        assert!((span.cores_busy().unwrap() - 1.85).abs() < 1e-12);
        let unknown = Span { cpu: None, ..span };
        assert_eq!(unknown.cores_busy(), None);
        let instant = Span {
            wall: Duration::ZERO,
            ..span
        };
        assert_eq!(instant.cores_busy(), None);
    }
}
