//! Model of the integer front-to-back compositor, and the exact composites it approximates.

use super::{round_half_up, ONE};

/// A U8.8 sample as `[r, g, b, a]` raw values.
pub type Raw = [u16; 4];

/// The integer front-to-back composite of `samples` (stopping once `A ≥ a_stop`):
/// `T = ONE − A`, each channel `x ← x + ⌊T·x_s/ONE + ½⌋` (**round half up**). Returns the
/// result and the number of samples used.
pub fn front_to_back(samples: &[Raw], a_stop: u16) -> (Raw, usize) {
    let mut acc = [0.0f64; 4];
    let mut used = 0;
    for s in samples {
        if acc[3] >= f64::from(a_stop) {
            break;
        }
        let t = ONE - acc[3];
        for k in 0..4 {
            acc[k] += round_half_up(t * f64::from(s[k]) / ONE);
        }
        used += 1;
    }
    (acc.map(|x| x as u16), used)
}

/// The exact front-to-back composite of the same samples (U8.8 units, unrounded).
pub fn exact_front_to_back(samples: &[Raw]) -> [f64; 4] {
    let mut acc = [0.0f64; 4];
    for s in samples {
        let t = 1.0 - acc[3] / ONE;
        for k in 0..4 {
            acc[k] += t * f64::from(s[k]);
        }
    }
    acc
}

/// The exact back-to-front composite of the same samples (first sample in front).
pub fn exact_back_to_front(samples: &[Raw]) -> [f64; 4] {
    let mut acc = [0.0f64; 4];
    for s in samples.iter().rev() {
        let t = 1.0 - f64::from(s[3]) / ONE;
        for k in 0..4 {
            acc[k] = f64::from(s[k]) + t * acc[k];
        }
    }
    acc
}
