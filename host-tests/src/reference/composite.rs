//! Compositing of associated samples: front to back, back to front, over a background.

use super::volume::RefAssoc;

/// `front` over `back`: `(C_f + (1 − A_f)·C_b, A_f + (1 − A_f)·A_b)`.
///
/// This is one front-to-back step with `front` the accumulator; it is associative.
pub fn over(front: RefAssoc, back: RefAssoc) -> RefAssoc {
    let t = 1.0 - front.alpha;
    RefAssoc {
        color: [
            front.color[0] + t * back.color[0],
            front.color[1] + t * back.color[1],
            front.color[2] + t * back.color[2],
        ],
        alpha: front.alpha + t * back.alpha,
    }
}

/// Front-to-back compositing of `samples` (index 0 nearest the eye), starting from transparent
/// black: `C += (1 − A)·C̃_s`, `A += (1 − A)·α_s`.
///
/// Early stop: before each sample, stop if `A ≥ a_stop`. Pass `a_stop = 1.0` (or anything
/// above it) to composite every sample; with `a_stop ≤ 0` nothing is composited.
pub fn composite_front_to_back(samples: &[RefAssoc], a_stop: f64) -> RefAssoc {
    let mut acc = RefAssoc::TRANSPARENT;
    for &s in samples {
        if acc.alpha >= a_stop {
            break;
        }
        acc = over(acc, s);
    }
    acc
}

/// Number of samples [`composite_front_to_back`] composites before its early stop.
pub fn front_to_back_used(samples: &[RefAssoc], a_stop: f64) -> usize {
    let mut acc = RefAssoc::TRANSPARENT;
    let mut used = 0;
    for &s in samples {
        if acc.alpha >= a_stop {
            break;
        }
        acc = over(acc, s);
        used += 1;
    }
    used
}

/// Back-to-front compositing of `samples` (index 0 nearest the eye, so they are visited from
/// the last to the first), starting from transparent black: `C = C̃_s + (1 − α_s)·C`,
/// `A = α_s + (1 − α_s)·A`. No early stop.
pub fn composite_back_to_front(samples: &[RefAssoc]) -> RefAssoc {
    let mut acc = RefAssoc::TRANSPARENT;
    for &s in samples.iter().rev() {
        let t = 1.0 - s.alpha;
        acc = RefAssoc {
            color: [
                s.color[0] + t * acc.color[0],
                s.color[1] + t * acc.color[1],
                s.color[2] + t * acc.color[2],
            ],
            alpha: s.alpha + t * acc.alpha,
        };
    }
    acc
}

/// Final composite of an accumulated ray `acc` over the associated background `background`:
/// `(C + (1 − A)·B_c, A + (1 − A)·B_a)` (the same as [`over`]).
pub fn over_background(acc: RefAssoc, background: RefAssoc) -> RefAssoc {
    over(acc, background)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples() -> Vec<RefAssoc> {
        vec![
            RefAssoc::new([0.1, 0.0, 0.2], 0.25),
            RefAssoc::new([0.0, 0.0, 0.0], 0.0),
            RefAssoc::new([0.3, 0.5, 0.1], 0.5),
            RefAssoc::new([0.9, 0.2, 0.4], 0.9),
            RefAssoc::new([0.05, 0.05, 0.05], 0.1),
        ]
    }

    fn close(a: RefAssoc, b: RefAssoc) -> bool {
        (a.alpha - b.alpha).abs() < 1e-15 && (0..3).all(|k| (a.color[k] - b.color[k]).abs() < 1e-15)
    }

    #[test]
    fn front_to_back_equals_back_to_front() {
        let s = samples();
        assert!(close(
            composite_front_to_back(&s, 1.0),
            composite_back_to_front(&s)
        ));
    }

    #[test]
    fn over_is_associative() {
        let s = samples();
        for a in &s {
            for b in &s {
                for c in &s {
                    assert!(close(over(over(*a, *b), *c), over(*a, over(*b, *c))));
                }
            }
        }
    }

    #[test]
    fn homogeneous_samples() {
        // n samples of (a·c, a): A = 1 − (1 − a)ⁿ, C = c·A.
        let a = 0.2;
        let s = vec![RefAssoc::new([0.5 * a, a, 0.0], a); 7];
        let acc = composite_front_to_back(&s, 1.0);
        let expect = 1.0 - (1.0 - a).powi(7);
        assert!((acc.alpha - expect).abs() < 1e-15);
        assert!((acc.color[0] - 0.5 * expect).abs() < 1e-15);
        assert!((acc.color[1] - expect).abs() < 1e-15);
    }

    #[test]
    fn early_stop_before_next_sample() {
        let s = samples();
        // After sample 0: A = 0.25; after 1: 0.25; after 2: 0.625; after 3: 0.9625.
        assert_eq!(front_to_back_used(&s, 1.0), 5);
        assert_eq!(front_to_back_used(&s, 0.9), 4);
        assert_eq!(front_to_back_used(&s, 0.625), 3);
        assert_eq!(front_to_back_used(&s, 0.3), 3);
        assert_eq!(front_to_back_used(&s, 0.25), 1);
        assert_eq!(front_to_back_used(&s, 0.0), 0);
        let stopped = composite_front_to_back(&s, 0.625);
        assert!(close(stopped, composite_front_to_back(&s[..3], 1.0)));
        assert_eq!(composite_front_to_back(&s, 0.0), RefAssoc::TRANSPARENT);
    }

    #[test]
    fn background() {
        let acc = RefAssoc::new([0.2, 0.1, 0.0], 0.4);
        let bg = RefAssoc::new([1.0, 0.0, 0.5], 1.0);
        let out = over_background(acc, bg);
        assert!(close(out, RefAssoc::new([0.8, 0.1, 0.3], 1.0)));
        assert_eq!(over_background(RefAssoc::TRANSPARENT, bg), bg);
    }
}
