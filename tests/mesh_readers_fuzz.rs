//! Property test of the mesh readers (issue 33, "Done means"): random and
//! mutated bytes, starting from the real files in `tests/data/meshes/` and
//! `scenes/meshes/`, fed to every reader (gmsh `.msh` ASCII and binary,
//! MEDIT `.mesh`, TetGen `.node` + `.ele`, VTU `.vtu`) in 2D and 3D. Each
//! case must return (a mesh or an error, never a panic), within a time
//! bound, and allocate at most a bounded amount: the peak of live heap
//! bytes during the read, measured by a counting global allocator, below
//! 64 MiB plus 1100 times the input's size (1032 to 1 is the most zlib can
//! inflate a VTU's compressed data).
//!
//! A binary of its own: the allocator is process-wide, and one test
//! function keeps other threads' allocations out of the measurement. The
//! random source is seeded, so every run tries the same cases; the case
//! count keeps it to a few seconds.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

struct PeakAllocator;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(bytes: usize) {
    let live = LIVE.fetch_add(bytes, Ordering::Relaxed) + bytes;
    PEAK.fetch_max(live, Ordering::Relaxed);
}

unsafe impl GlobalAlloc for PeakAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let pointer = unsafe { System.alloc(layout) };
        if !pointer.is_null() {
            grew(layout.size());
        }
        pointer
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let pointer = unsafe { System.alloc_zeroed(layout) };
        if !pointer.is_null() {
            grew(layout.size());
        }
        pointer
    }

    unsafe fn dealloc(&self, pointer: *mut u8, layout: Layout) {
        unsafe { System.dealloc(pointer, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, pointer: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let moved = unsafe { System.realloc(pointer, layout, new_size) };
        if !moved.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
            grew(new_size);
        }
        moved
    }
}

#[global_allocator]
static GLOBAL: PeakAllocator = PeakAllocator;

/// A real mesh file to start from (both of a TetGen pair are kept).
struct Seed {
    /// File name; its extension picks the reader.
    name: String,
    bytes: Vec<u8>,
    /// The other file of a TetGen pair, written beside it unchanged.
    partner: Option<(String, Vec<u8>)>,
}

fn seeds() -> Vec<Seed> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<PathBuf> = Vec::new();
    for folder in ["tests/data/meshes", "scenes/meshes"] {
        for entry in std::fs::read_dir(root.join(folder)).unwrap() {
            files.push(entry.unwrap().path());
        }
    }
    files.sort();
    let mut seeds = Vec::new();
    for file in &files {
        let extension = file.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !["msh", "mesh", "node", "ele", "vtu"].contains(&extension) {
            continue;
        }
        let partner = match extension {
            "node" => Some(file.with_extension("ele")),
            "ele" => Some(file.with_extension("node")),
            _ => None,
        };
        seeds.push(Seed {
            name: file.file_name().unwrap().to_string_lossy().into_owned(),
            bytes: std::fs::read(file).unwrap(),
            partner: partner.map(|p| {
                (
                    p.file_name().unwrap().to_string_lossy().into_owned(),
                    std::fs::read(&p).unwrap(),
                )
            }),
        });
    }
    assert!(seeds.len() >= 12, "{} seeds", seeds.len());
    seeds
}

/// One change to a file's bytes, at a position given as a fraction of its length.
#[derive(Debug, Clone)]
enum Mutation {
    /// Replace the byte there.
    Set(f64, u8),
    /// Insert bytes there.
    Insert(f64, Vec<u8>),
    /// Remove up to this many bytes from there.
    Remove(f64, usize),
    /// Put a number there: huge, negative, or not a number at all.
    Number(f64, &'static str),
    /// Cut the file there.
    Truncate(f64),
    /// Give a compressed VTU array (the one at this fraction of them) other
    /// block sizes `[nu][np]` in its header `[nb][nu][np][nc]` (the bytes
    /// of each block once decompressed, and of the last one), keeping its
    /// compressed sizes, so that vtkio gets as far as allocating them.
    VtuHeader(f64, [u32; 2]),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let at = 0.0..1.0f64;
    prop_oneof![
        (at.clone(), any::<u8>()).prop_map(|(p, b)| Mutation::Set(p, b)),
        (at.clone(), prop::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(p, b)| Mutation::Insert(p, b)),
        (at.clone(), 1..64usize).prop_map(|(p, n)| Mutation::Remove(p, n)),
        (
            at.clone(),
            prop::sample::select(vec![
                "18446744073709551615",
                "4294967295",
                "2147483648",
                "-1",
                "0",
                "1e308",
                "nan",
                "99999999999999999999999",
                "AAAAAAAA//////////8=",
            ])
        )
            .prop_map(|(p, n)| Mutation::Number(p, n)),
        at.clone().prop_map(Mutation::Truncate),
        (at, any::<u32>(), any::<u32>()).prop_map(|(p, nu, np)| Mutation::VtuHeader(p, [nu, np])),
    ]
}

fn mutate(bytes: &mut Vec<u8>, change: &Mutation) {
    let at = |fraction: f64, len: usize| ((fraction * len as f64) as usize).min(len);
    match change {
        Mutation::Set(p, b) => {
            if !bytes.is_empty() {
                let i = at(*p, bytes.len() - 1);
                bytes[i] = *b;
            }
        }
        Mutation::Insert(p, inserted) => {
            let i = at(*p, bytes.len());
            bytes.splice(i..i, inserted.iter().copied());
        }
        Mutation::Remove(p, n) => {
            let i = at(*p, bytes.len());
            let end = (i + n).min(bytes.len());
            bytes.drain(i..end);
        }
        Mutation::Number(p, text) => {
            let i = at(*p, bytes.len());
            bytes.splice(i..i, text.bytes());
        }
        Mutation::Truncate(p) => {
            let i = at(*p, bytes.len());
            bytes.truncate(i);
        }
        Mutation::VtuHeader(p, header) => {
            use base64::Engine;
            let marker = b"format=\"binary\">";
            let arrays: Vec<usize> = bytes
                .windows(marker.len())
                .enumerate()
                .filter(|(_, w)| *w == marker)
                .map(|(i, _)| i + marker.len())
                .collect();
            if arrays.is_empty() {
                return;
            }
            let mut start = arrays[at(*p, arrays.len() - 1)];
            while bytes.get(start).is_some_and(u8::is_ascii_whitespace) {
                start += 1;
            }
            // cube.vtu's headers are one block: 16 bytes, 24 base64 characters.
            let engine = base64::engine::general_purpose::STANDARD;
            let end = (start + 24).min(bytes.len());
            let Ok(mut raw) = engine.decode(&bytes[start..end]) else {
                return;
            };
            if raw.len() < 12 {
                return;
            }
            raw[4..8].copy_from_slice(&header[0].to_le_bytes());
            raw[8..12].copy_from_slice(&header[1].to_le_bytes());
            bytes.splice(start..end, engine.encode(raw).bytes());
        }
    }
}

/// Reads `name` holding `bytes` (and its partner) in 2D and 3D, checking the
/// time and the allocation of each read.
fn read_both_ways(folder: &Path, name: &str, bytes: &[u8], partner: Option<&(String, Vec<u8>)>) {
    let path = folder.join(name);
    std::fs::write(&path, bytes).unwrap();
    if let Some((partner_name, partner_bytes)) = partner {
        std::fs::write(folder.join(partner_name), partner_bytes).unwrap();
    }
    let size = bytes.len() + partner.map_or(0, |(_, b)| b.len());
    let allowed = (64 << 20) + 1100 * size;
    for dimension in [2, 3] {
        let before = LIVE.load(Ordering::SeqCst);
        PEAK.store(before, Ordering::SeqCst);
        let start = Instant::now();
        let read = elasto::mesh_io::read_mesh(&path, dimension);
        let elapsed = start.elapsed();
        let peak = PEAK.load(Ordering::SeqCst) - before;
        drop(read);
        assert!(
            elapsed < Duration::from_secs(5),
            "{name} ({size} bytes, {dimension}D) took {elapsed:?}"
        );
        assert!(
            peak <= allowed,
            "{name} ({size} bytes, {dimension}D) had {peak} bytes live at once, more than {allowed}"
        );
    }
}

#[test]
fn mesh_readers_survive_random_and_mutated_files() {
    let seeds = seeds();
    let folder = tempfile::tempdir().unwrap();
    let config = Config {
        cases: 400,
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner = TestRunner::new_with_rng(
        config.clone(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &[33; 32]),
    );
    let mutated = (
        0..seeds.len(),
        prop::collection::vec(mutation(), 1..6),
        any::<bool>(),
    );
    runner
        .run(&mutated, |(seed, changes, change_partner)| {
            let seed = &seeds[seed];
            let (mut bytes, mut partner) = (seed.bytes.clone(), seed.partner.clone());
            let target = match (&mut partner, change_partner) {
                (Some((_, partner_bytes)), true) => partner_bytes,
                _ => &mut bytes,
            };
            for change in &changes {
                mutate(target, change);
            }
            read_both_ways(folder.path(), &seed.name, &bytes, partner.as_ref());
            Ok(())
        })
        .unwrap();

    // Random bytes after the first line of each format.
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: 200,
            ..config
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]),
    );
    let starts: [(&str, &[u8]); 5] = [
        ("r.msh", b"$MeshFormat\n"),
        ("r.mesh", b"MeshVersionFormatted 2\n"),
        ("r.node", b"8 3 0 0\n"),
        (
            "r.vtu",
            b"<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkZLibDataCompressor\">",
        ),
        ("r.msh", b"$MeshFormat\n4.1 1 8\n"),
    ];
    let random = (0..starts.len(), prop::collection::vec(any::<u8>(), 0..2048));
    runner
        .run(&random, |(start, tail)| {
            let (name, head) = starts[start];
            let mut bytes = head.to_vec();
            bytes.extend(tail);
            let partner = name
                .ends_with(".node")
                .then(|| ("r.ele".to_owned(), b"1 4 0\n1 1 2 3 4\n".to_vec()));
            read_both_ways(folder.path(), name, &bytes, partner.as_ref());
            Ok(())
        })
        .unwrap();
}
