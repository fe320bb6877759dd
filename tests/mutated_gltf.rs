//! Mutation testing of the glTF importer: every shared sample model (the animated, skinned and
//! morphed ones included, each mutant posed after loading), mutated many times from a
//! seed (see `common/mutate.rs`: JSON fields, hostile URIs, cycles, NaN, bit flips,
//! truncations), must load or fail with an error naming the file, never panic, answer within
//! [`TIME_BOUND`], and allocate at most [`MEMORY_BOUND`] while loading (a counting allocator
//! measures each load's peak). The mutants are seeded, so a failure names the seed that
//! reproduces it. `CHIARO_MUTANTS=N` runs N per model (default 100, about 1000 in all);
//! `scripts/mutate_long.sh` runs thousands.

mod common;
#[path = "common/mutate.rs"]
mod mutate;

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use chiaro::scene::load_gltf;
use chiaro::shading::rng::Pcg32;

/// Slowest load allowed for one mutant (a debug build of the importer).
const TIME_BOUND: Duration = Duration::from_secs(20);

/// Most memory one load may allocate beyond what was live before it: what the importer's own
/// limits allow a small file to make it allocate (a decoded image is capped at 512 MiB by the
/// image crate's limits, a zero-filled accessor at 2^24 elements), with room for the mesh's
/// copies.
const MEMORY_BOUND: usize = 1 << 30;

/// The system allocator, counting the bytes live and their peak since the last reset.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded to the system allocator unchanged; the counters are only
// arithmetic on the side.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as the caller's contract for GlobalAlloc::alloc.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(live, Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: as the caller's contract for GlobalAlloc::dealloc.
        unsafe { System.dealloc(p, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// How a mutant ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Outcome {
    /// Loaded (perhaps with repairs).
    Loaded,
    /// Refused with an error naming the file.
    Refused,
}

/// Loads the mutant on a thread of its own; fails the test on a panic, a hang, an error that
/// does not name the file, or a load that allocated more than [`MEMORY_BOUND`].
fn check_mutant(path: &Path, bytes: &[u8], what: &str) -> (Outcome, usize) {
    std::fs::write(path, bytes).unwrap();
    let (tx, rx) = mpsc::channel();
    let file = path.to_path_buf();
    PEAK.store(LIVE.load(Ordering::Relaxed), Ordering::Relaxed);
    let before = LIVE.load(Ordering::Relaxed);
    let start = Instant::now();
    std::thread::spawn(move || {
        // Loaded, spawned and posed (animations played, skins and morphs re-posed).
        let result = std::panic::catch_unwind(|| {
            load_gltf(&file).map(|builder| {
                let mut world = bevy_ecs::world::World::new();
                builder.spawn(&mut world);
                chiaro::scene::pose_at(&mut world, 0.5);
            })
        });
        let _ = tx.send(result.map(|r| r.map_err(|e| e.to_string())));
    });
    let result = rx.recv_timeout(TIME_BOUND).unwrap_or_else(|_| {
        panic!(
            "{} gave no answer in {TIME_BOUND:?} ({what})",
            path.display()
        )
    });
    let allocated = PEAK.load(Ordering::Relaxed).saturating_sub(before);
    assert!(
        allocated <= MEMORY_BOUND,
        "{} allocated {allocated} bytes while loading ({what})",
        path.display()
    );
    let outcome = match result {
        Err(_) => panic!("{} panicked ({what})", path.display()),
        Ok(Err(message)) => {
            assert!(
                message.contains(&path.display().to_string()),
                "the error does not name the file ({what}): {message}"
            );
            Outcome::Refused
        }
        Ok(Ok(())) => Outcome::Loaded,
    };
    assert!(start.elapsed() < TIME_BOUND);
    (outcome, allocated)
}

#[test]
fn mutated_sample_models_load_or_fail_cleanly() {
    let dir = common::shared_dir("scenes");
    let per_model: u64 = std::env::var("CHIARO_MUTANTS")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(100);
    let scratch = std::env::temp_dir().join(format!("chiaro-mutants-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).unwrap();
    let (mut loaded, mut refused, mut peak) = (0usize, 0usize, 0usize);
    let start = Instant::now();
    let animated = common::shared_dir("scenes/animated");
    let mut models: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .chain(std::fs::read_dir(&animated).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().and_then(|e| e.to_str()) == Some("glb"))
        .collect();
    models.sort();
    assert!(!models.is_empty(), "no .glb in {}", dir.display());
    for path in &models {
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        let original = std::fs::read(path).unwrap();
        let (json, bin) = mutate::split_glb(&original);
        for seed in 0..per_model {
            let mut rng = Pcg32::new(seed, 0x9e37);
            let (mut json, mut bin) = (json.clone(), bin.clone());
            let mut changes = Vec::new();
            for _ in 0..1 + rng.next_u32() % 3 {
                if rng.next_u32().is_multiple_of(4) {
                    changes.push(mutate::mutate_bin(&mut bin, &mut rng));
                } else {
                    changes.push(mutate::mutate_json(&mut json, &mut rng));
                }
            }
            let (text, nan) = mutate::json_text(&json, &mut rng);
            changes.extend(nan);
            let mut bytes = mutate::join_glb(&text, &bin);
            if rng.next_u32().is_multiple_of(8) {
                changes.push(mutate::mutate_file(&mut bytes, &mut rng));
            }
            let mutant = scratch.join(format!("{stem}-{seed}.glb"));
            let what = format!("{stem} seed {seed}: {}", changes.join("; "));
            let (outcome, allocated) = check_mutant(&mutant, &bytes, &what);
            peak = peak.max(allocated);
            match outcome {
                Outcome::Loaded => loaded += 1,
                Outcome::Refused => refused += 1,
            }
        }
    }
    std::fs::remove_dir_all(&scratch).unwrap();
    eprintln!(
        "{} mutants of {} models in {:.1} s: {refused} refused, {loaded} loaded, no panic, no \
         hang; largest allocation while loading {:.1} MiB",
        refused + loaded,
        models.len(),
        start.elapsed().as_secs_f64(),
        peak as f64 / (1 << 20) as f64
    );
    assert!(
        refused > 0 && loaded > 0,
        "mutations should both break and spare files: {refused} refused, {loaded} loaded"
    );
}
