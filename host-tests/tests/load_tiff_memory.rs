//! A TIFF file cannot make the loader reserve more memory than its size warrants.
//!
//! The `tiff` crate reserves memory for a directory entry's declared number of values before
//! it reads them, and it reads the first directory before a decoder's limits can be set: a
//! 322-byte file (found by the `load_tiff` fuzz target) whose first directory declares
//! 8 388 608 strip byte counts made it reserve 256 MiB. `read_tiff` now checks every
//! directory's entries against the file's size first. This binary counts the largest single
//! allocation (its own global allocator), so it holds that bound, not only the error.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use volsample_host::scene::load::{read_tiff, DEFAULT_MEMORY_CAP};

/// The global allocator: the system's, recording the largest request.
struct Largest;

static LARGEST: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards every call to `System` unchanged; only records sizes.
unsafe impl GlobalAlloc for Largest {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        // SAFETY: the caller's contract, passed on.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        // SAFETY: the caller's contract, passed on.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract, passed on.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        // SAFETY: the caller's contract, passed on.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Largest = Largest;

/// The tests of this binary measure one at a time (the harness runs them on threads).
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// The most a refused crafted file of a few hundred bytes may make the loader request at once.
const MAX_ALLOCATION_FOR_CRAFTED: usize = 1 << 20;

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

fn tmp(name: &str, bytes: &[u8]) -> PathBuf {
    let d = std::env::temp_dir().join(format!("volsample-tiff-mem-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let p = d.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// Runs `read_tiff` on `path` and returns its error text and the largest allocation it made.
fn refused(path: &Path) -> (String, usize) {
    LARGEST.store(0, Ordering::Relaxed);
    let r = read_tiff(path, DEFAULT_MEMORY_CAP);
    let largest = LARGEST.load(Ordering::Relaxed);
    match r {
        Ok(v) => panic!("{}: loaded {:?}, want an error", path.display(), v.dims),
        Err(e) => (e.to_string(), largest),
    }
}

/// The `tiff_u8.tif` fixture with its StripByteCounts entry (tag 279) rewritten to declare
/// `count` LONG values at byte offset `offset`.
fn u8_fixture_with_strip_counts(count: u32, offset: u32) -> Vec<u8> {
    let mut tif = std::fs::read(data("formats/tiff_u8.tif")).unwrap();
    assert_eq!(&tif[..4], b"II*\0");
    let ifd = u32::from_le_bytes(tif[4..8].try_into().unwrap()) as usize;
    let entries = u16::from_le_bytes(tif[ifd..ifd + 2].try_into().unwrap()) as usize;
    let mut patched = false;
    for k in 0..entries {
        let e = ifd + 2 + 12 * k;
        if u16::from_le_bytes([tif[e], tif[e + 1]]) == 279 {
            tif[e + 2..e + 4].copy_from_slice(&4u16.to_le_bytes());
            tif[e + 4..e + 8].copy_from_slice(&count.to_le_bytes());
            tif[e + 8..e + 12].copy_from_slice(&offset.to_le_bytes());
            patched = true;
        }
    }
    assert!(patched, "tiff_u8.tif has no StripByteCounts entry");
    tif
}

/// The hazard is the `tiff` crate's, and this binary sees it: the crate alone, on the fuzz
/// target's file, requests over 100 MiB at once (if a later version of the crate bounds it,
/// this test fails and says so, and the loader's own check may be revisited).
#[test]
fn the_tiff_crate_alone_reserves_for_the_declared_count() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let file = std::fs::File::open(data("crafted/tiff_first_ifd_count.tif")).unwrap();
    LARGEST.store(0, Ordering::Relaxed);
    let r = tiff::decoder::Decoder::new(std::io::BufReader::new(file));
    let largest = LARGEST.load(Ordering::Relaxed);
    drop(r);
    assert!(
        largest > 100 << 20,
        "the tiff crate requested at most {largest} bytes at once for the crafted file: it no \
         longer reserves for a declared count, so check_directories may be unneeded"
    );
}

/// The fuzz target's file, and the u8 fixture with a declared count or offset past its end:
/// each refused, naming the entry, with no allocation over 1 MiB.
#[test]
fn a_directory_entry_past_the_file_is_refused_before_any_reservation() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let len = std::fs::metadata(data("formats/tiff_u8.tif"))
        .unwrap()
        .len() as u32;
    let cases = [
        (
            data("crafted/tiff_first_ifd_count.tif"),
            "tag 279 declares 8388608 values",
        ),
        (
            tmp("count.tif", &u8_fixture_with_strip_counts(8 << 20, 8)),
            "tag 279 declares 8388608 values",
        ),
        // Two values (8 bytes, out of line) that start 4 bytes before the end.
        (
            tmp("offset.tif", &u8_fixture_with_strip_counts(2, len - 4)),
            "tag 279 declares 2 values",
        ),
    ];
    for (path, want) in cases {
        let (e, largest) = refused(&path);
        assert!(
            e.contains(want) && e.contains(path.file_name().unwrap().to_str().unwrap()),
            "{}: {e}",
            path.display()
        );
        assert!(
            largest <= MAX_ALLOCATION_FOR_CRAFTED,
            "{}: largest allocation {largest} bytes",
            path.display()
        );
    }
}

/// A BigTIFF header (version 43, 8-byte offsets, 20-byte entries) whose one directory
/// declares 2^40 LONG8 strip byte counts: refused by the same check.
#[test]
fn a_bigtiff_directory_entry_past_the_file_is_refused() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let mut f = Vec::new();
    f.extend_from_slice(b"II");
    f.extend_from_slice(&43u16.to_le_bytes());
    f.extend_from_slice(&8u16.to_le_bytes());
    f.extend_from_slice(&0u16.to_le_bytes());
    f.extend_from_slice(&16u64.to_le_bytes());
    f.extend_from_slice(&1u64.to_le_bytes()); // one entry
    f.extend_from_slice(&279u16.to_le_bytes());
    f.extend_from_slice(&16u16.to_le_bytes()); // LONG8
    f.extend_from_slice(&(1u64 << 40).to_le_bytes());
    f.extend_from_slice(&40u64.to_le_bytes());
    f.extend_from_slice(&0u64.to_le_bytes()); // no next directory
    let path = tmp("big.tif", &f);
    let (e, largest) = refused(&path);
    assert!(
        e.contains("tag 279 declares 1099511627776 values of 8 bytes"),
        "{e}"
    );
    assert!(
        largest <= MAX_ALLOCATION_FOR_CRAFTED,
        "largest allocation {largest} bytes"
    );
}

/// The check refuses nothing it should not: every TIFF fixture that loaded before loads.
#[test]
fn well_formed_stacks_still_load() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    for name in [
        "tiff_u8.tif",
        "tiff_f32.tif",
        "tiff_f64.tif",
        "tiff_i16_be.tif",
        "tiff_i32.tif",
        "tiff_u16_deflate.tif",
    ] {
        let v = read_tiff(&data(&format!("formats/{name}")), DEFAULT_MEMORY_CAP);
        assert!(v.is_ok(), "{name}: {:?}", v.err());
    }
}
