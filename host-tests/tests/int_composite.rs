//! The integer front-to-back compositor: invariants, model agreement and bounds on random and
//! extreme sample sequences (through `checks::composite`), and its worst observed error.

use volsample::fixed_point::{composite_front_to_back, front_to_back, IntSample, IntStop, ONE};
use volsample_host::checks::{self, CompositeInput};
use volsample_host::int_model::composite as cm;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

#[test]
fn random_sequences() {
    let mut rng = Rng(0xc0ffee);
    let mut worst = [0.0f64; 2];
    for i in 0..2000 {
        let n = (rng.next() % 300) as usize;
        let faint = i % 3 == 0;
        let samples = (0..n)
            .map(|_| {
                let a = if faint {
                    (rng.next() % 600) as u16
                } else {
                    rng.next() as u16
                };
                [rng.next() as u16, rng.next() as u16, rng.next() as u16, a]
            })
            .collect();
        let inp = CompositeInput {
            samples,
            a_stop: rng.next() as u16,
        };
        checks::composite(&inp).unwrap_or_else(|e| panic!("{e}"));
        let raws: Vec<[u16; 4]> = inp
            .valid_samples()
            .iter()
            .map(|s| [s.c()[0], s.c()[1], s.c()[2], s.a()])
            .collect();
        if raws.is_empty() {
            continue;
        }
        let (got, used) = cm::front_to_back(&raws, ONE);
        let exact = cm::exact_front_to_back(&raws[..used]);
        for k in 0..4 {
            let e = (f64::from(got[k]) - exact[k]).abs() / used.max(1) as f64;
            worst[usize::from(k == 3)] = worst[usize::from(k == 3)].max(e);
        }
    }
    println!(
        "compositor worst error per sample: C {:.4} LSB, A {:.4} LSB",
        worst[0], worst[1]
    );
}

#[test]
fn extremes() {
    let cases: Vec<Vec<[u16; 4]>> = vec![
        vec![],
        vec![[0; 4]; 1000],
        vec![[ONE; 4]; 3],
        vec![[1, 1, 0, 1]; 4000],
        vec![[256, 0, 256, 256]; 4000],
        vec![[65535; 4]; 100],
    ];
    for samples in cases {
        for a_stop in [0u16, 1, ONE - 1, ONE, 65535] {
            let inp = CompositeInput {
                samples: samples.clone(),
                a_stop,
            };
            checks::composite(&inp).unwrap_or_else(|e| panic!("{e}"));
        }
    }
    // An opaque sample ends the ray: nothing behind it shows.
    let opaque = IntSample::new([ONE, 0, 0], ONE).unwrap();
    let behind = IntSample::new([0, ONE, 0], ONE).unwrap();
    let (s, used) = composite_front_to_back([opaque, behind], IntStop::NEVER);
    assert_eq!((s.c(), s.a(), used), ([ONE, 0, 0], ONE, 1));
    // α = 1/255 repeated: A creeps up monotonically and never passes ONE.
    let faint = IntSample::new([256; 3], 256).unwrap();
    let mut acc = IntSample::TRANSPARENT;
    for _ in 0..20_000 {
        let next = front_to_back(acc, faint);
        assert!(next.a() >= acc.a() && next.a() <= ONE);
        acc = next;
    }
    assert!(IntStop::new(0).is_err());
    assert!(IntStop::new(ONE + 1).is_err());
}
