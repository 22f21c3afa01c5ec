//! The generator: SplitMix64, and the draws several kernel families share (see the module docs
//! of [`vectors`](super) for the exact recipes).

use volsample::fixed_point::{premultiply, ONE};

use super::Raw;

/// The SplitMix64 generator (see the module docs).
#[derive(Debug, Clone)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator whose state is `seed`.
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64-bit draw.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

/// The voxel of one draw `w` (no further draws): `r, g, b, a` are bytes 0..3 of `w`, and
/// `k = (w >> 32) & 7` replaces `a` by 0 (`k = 0`), 255 (`k = 1`), 1 (`k = 2`) or all four
/// bytes by 255 (`k = 3`); `associated` then premultiplies each color byte.
pub(super) fn voxel_of_draw(w: u64, associated: bool) -> [u8; 4] {
    let mut b = [w as u8, (w >> 8) as u8, (w >> 16) as u8, (w >> 24) as u8];
    match (w >> 32) & 7 {
        0 => b[3] = 0,
        1 => b[3] = 255,
        2 => b[3] = 1,
        3 => b = [255; 4],
        _ => {}
    }
    if associated {
        for k in 0..3 {
            b[k] = premultiply(b[k], b[3]);
        }
    }
    b
}

/// One random voxel as the sampling kernels draw it: one draw, [`voxel_of_draw`].
pub(super) fn random_voxel(rng: &mut SplitMix64, associated: bool) -> [u8; 4] {
    voxel_of_draw(rng.next_u64(), associated)
}

/// One random U8.8 sample: one draw `w`, `k = w >> 61`; `a = 0` (`k = 0`), `ONE` (`k = 1`),
/// `256·((w >> 8) & 255)` (`k = 2`) or `(w & 0xFFFFFFFF) % 65281`; then `r, g, b`, each one
/// draw `% (a + 1)`.
pub(super) fn random_sample(rng: &mut SplitMix64) -> Raw {
    let w = rng.next_u64();
    let a = match w >> 61 {
        0 => 0,
        1 => u64::from(ONE),
        2 => 256 * ((w >> 8) & 255),
        _ => (w & 0xFFFF_FFFF) % (u64::from(ONE) + 1),
    };
    let mut c = [0u16; 4];
    for x in c.iter_mut().take(3) {
        *x = (rng.next_u64() % (a + 1)) as u16;
    }
    c[3] = a as u16;
    c
}

/// A step ratio `d/d′` of one draw `w` (exact in `f32`): `k = w >> 61`; 1 (`k = 0`),
/// `(1 + w mod 4096)/2^20` (`k = 1`, at most `1/256`), else `(1 + w mod 65536)/4096`
/// (in `(0, 16]`).
pub(super) fn ratio_of_draw(w: u64) -> f32 {
    match w >> 61 {
        0 => 1.0,
        1 => (1 + w % 4096) as f32 / 1_048_576.0,
        _ => (1 + w % 65536) as f32 / 4096.0,
    }
}
