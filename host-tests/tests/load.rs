//! Loading user volumes and transfer functions: good files load, bad files give an error
//! that names the file and the problem, never a panic.

use std::path::PathBuf;

use volsample_host::scene::load::{load_nrrd, load_raw, load_transfer_function, ScalarType};

fn tmp(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("volsample-load-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

#[test]
fn raw_volumes() {
    let p = tmp("v.raw", &[0, 1, 2, 3, 4, 5, 6, 7]);
    assert_eq!(
        load_raw(&p, [2, 2, 2], ScalarType::U8).unwrap(),
        (0..8).map(|v| v as f32).collect::<Vec<_>>()
    );
    assert_eq!(
        load_raw(&p, [2, 2, 1], ScalarType::U16).unwrap(),
        vec![256.0, 770.0, 1284.0, 1798.0]
    );
    let e = load_raw(&p, [3, 2, 2], ScalarType::U8)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("v.raw") && e.contains("8 data bytes") && e.contains("need 12"),
        "{e}"
    );
    let e = load_raw(&p, [0, 2, 2], ScalarType::U8)
        .unwrap_err()
        .to_string();
    assert!(e.contains("zero"), "{e}");
    let nan = tmp("nan.raw", &f32::NAN.to_le_bytes());
    let e = load_raw(&nan, [1, 1, 1], ScalarType::F32)
        .unwrap_err()
        .to_string();
    assert!(e.contains("NaN"), "{e}");
    let e = load_raw(
        &PathBuf::from("/nonexistent/x.raw"),
        [1, 1, 1],
        ScalarType::U8,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("/nonexistent/x.raw"), "{e}");
}

#[test]
fn nrrd_volumes() {
    let mut f =
        b"NRRD0004\n# comment\ntype: uint8\ndimension: 3\nsizes: 2 1 2\nencoding: raw\n\n".to_vec();
    f.extend([9, 8, 7, 6]);
    let (dims, v) = load_nrrd(&tmp("ok.nrrd", &f)).unwrap();
    assert_eq!((dims, v), ([2, 1, 2], vec![9.0, 8.0, 7.0, 6.0]));

    let mut be =
        b"NRRD0004\ntype: ushort\ndimension: 3\nsizes: 1 1 1\nendian: big\nencoding: raw\n\n"
            .to_vec();
    be.extend([1, 2]);
    assert_eq!(load_nrrd(&tmp("be.nrrd", &be)).unwrap().1, vec![258.0]);

    for (name, text, want) in [
        ("magic.nrrd", &b"P6\n"[..], "not a NRRD"),
        (
            "type.nrrd",
            b"NRRD0004\ntype: double\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\n",
            "unsupported type",
        ),
        (
            "dim.nrrd",
            b"NRRD0004\ntype: uint8\ndimension: 2\nsizes: 1 1\nencoding: raw\n\n",
            "3D",
        ),
        (
            "gz.nrrd",
            b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1 1 1\nencoding: gzip\n\n",
            "unsupported encoding",
        ),
        (
            "short.nrrd",
            b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n\x01",
            "1 data bytes",
        ),
        (
            "nosizes.nrrd",
            b"NRRD0004\ntype: uint8\ndimension: 3\nencoding: raw\n\n",
            "sizes",
        ),
    ] {
        let e = load_nrrd(&tmp(name, text)).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains(want), "{name}: {e}");
    }
}

#[test]
fn transfer_functions() {
    let j = tmp(
        "tf.json",
        br#"{"points": [[0, 0, 0, 0, 0], [255, 1, 0.5, 0.25, 0.8]]}"#,
    );
    let pts = load_transfer_function(&j).unwrap();
    assert_eq!(pts.len(), 2);
    assert_eq!(pts[1].c, [1.0, 0.5, 0.25]);
    let t = tmp("tf.txt", b"# s r g b a\n0 0 0 0 0\n\n100 1 1 1 0.5\n");
    assert_eq!(load_transfer_function(&t).unwrap()[1].a, 0.5);
    for (name, text, want) in [
        ("bad.json", &b"{\"points\": [[0, 1]]}"[..], "need 5"),
        ("syntax.json", b"{\"points\": [", "bad JSON"),
        (
            "unsorted.txt",
            b"5 0 0 0 0\n1 0 0 0 0\n",
            "strictly increasing",
        ),
        ("range.txt", b"0 2 0 0 0\n", "outside [0, 1]"),
        ("words.txt", b"zero one two three four\n", "line 1"),
        ("empty.txt", b"", "no points"),
    ] {
        let e = load_transfer_function(&tmp(name, text))
            .unwrap_err()
            .to_string();
        assert!(e.contains(name) && e.contains(want), "{name}: {e}");
    }
}
