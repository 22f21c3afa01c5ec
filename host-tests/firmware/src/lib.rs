//! Shared pieces of the volsample Cortex-M images: semihosting output and exit.
#![no_std]

use cortex_m_semihosting::{debug, hio};

/// Writes suite lines to the host through semihosting (one `SYS_WRITE` per line).
pub struct Semihosting {
    stream: Option<hio::HostStream>,
    /// `false` once a write failed.
    pub ok: bool,
}

impl Semihosting {
    /// Opens the host's stdout.
    pub fn stdout() -> Self {
        let stream = hio::hstdout().ok();
        let ok = stream.is_some();
        Self { stream, ok }
    }
}

impl volsample_fw_suite::Out for Semihosting {
    fn line(&mut self, s: &str) {
        let mut buf = heapless::Vec::<u8, 520>::new();
        let fits = buf.extend_from_slice(s.as_bytes()).is_ok() && buf.push(b'\n').is_ok();
        if let Some(st) = self.stream.as_mut() {
            self.ok &= fits && st.write_all(&buf).is_ok();
        }
    }
}

/// Ends the QEMU run with the given status (semihosting `SYS_EXIT`).
pub fn exit(success: bool) -> ! {
    debug::exit(if success {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    // Only reached without a debugger/emulator attached.
    #[allow(clippy::empty_loop)]
    loop {}
}

/// Where every panic of the size images ends up: a distinct, never-inlined function, so that
/// the panic check can look for its symbol (`panic_trap`) in the linked image. Nothing in an
/// image without a reachable panic refers to it, and the linker's section GC removes it.
#[inline(never)]
#[cold]
pub fn panic_trap() -> ! {
    exit(false)
}

/// The built-in scene of the size and stack images.
pub mod scene {
    use volsample::StraightU8;

    /// Volume dimensions.
    pub const DIMS: [usize; 3] = [4, 4, 4];
    /// Voxel count.
    pub const N: usize = 64;
    /// Float ray: origin and direction (voxel units).
    pub const RAY: ([f32; 3], [f32; 3]) = ([1.3, 1.6, -1.0], [0.1, 0.05, 1.0]);
    /// Integer ray: start and step (raw, 8 fractional bits), and the sample count.
    pub const INT_RAY: ([u32; 3], [i32; 3], u32) = ([333, 410, 0], [26, 13, 256], 4 * 4);

    /// An opaque white 2×2×2 core with a translucent orange shell in transparent air.
    pub fn voxels() -> [StraightU8; N] {
        core::array::from_fn(|i| {
            let (x, y, z) = (i % 4, (i / 4) % 4, i / 16);
            let core_ = (1..3).contains(&x) && (1..3).contains(&y) && (1..3).contains(&z);
            if core_ {
                StraightU8([255, 255, 255, 255])
            } else if (x + y + z) % 3 == 0 {
                StraightU8([255, 128, 0, 64])
            } else {
                StraightU8([255, 0, 0, 0])
            }
        })
    }

    /// Coordinate `a` of sample `k` of an integer ray: `start[a] + k·step[a]` (wrapping).
    #[inline(always)]
    pub fn int_coord(start: [u32; 3], step: [i32; 3], a: usize, k: u32) -> u32 {
        let s0 = start.get(a).copied().unwrap_or(0);
        let st = step.get(a).copied().unwrap_or(0);
        s0.wrapping_add_signed(st.wrapping_mul(k as i32))
    }
}
