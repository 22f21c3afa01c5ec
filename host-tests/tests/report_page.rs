//! The report's page, `index.html`: every image it names exists, and in headless Chromium
//! (Debian's `chromium`) the page loads, every image resolves and a screenshot is not blank.
//! Without Chromium the browser half is skipped with a note, unless
//! `VOLSAMPLE_REQUIRE_CHROMIUM` is set (as CI sets it), when its absence fails the test.

use std::path::{Path, PathBuf};
use std::process::Command;

fn out_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("volsample-page-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The `src="…"` attributes of a page.
fn sources(html: &str) -> Vec<String> {
    html.split("src=\"")
        .skip(1)
        .filter_map(|s| s.split('"').next())
        .map(str::to_string)
        .collect()
}

fn chromium() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser"].iter().find_map(|name| {
        std::env::split_paths(&path)
            .map(|d| d.join(name))
            .find(|p| p.is_file())
    })
}

fn headless(chrome: &Path, extra: &[&str], page: &Path) -> std::process::Output {
    Command::new(chrome)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--allow-file-access-from-files",
            "--virtual-time-budget=10000",
        ])
        .args(extra)
        .arg(format!("file://{}", page.display()))
        .output()
        .unwrap()
}

#[test]
fn the_report_page_loads_with_every_image() {
    let out = out_dir().join("report");
    let run = Command::new(env!("CARGO_BIN_EXE_volsample"))
        .args(["report", "--preset", "tiny", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let page = out.join("index.html");
    let html = std::fs::read_to_string(&page).unwrap();
    // The verdict, the plot inline, a sheet per scene.
    assert!(
        html.contains("id=\"verdict\"") && html.contains("pick "),
        "no verdict"
    );
    assert!(html.contains("<svg"), "no inline plot");
    for scene in ["torus-12", "red-12", "tf-shells-12"] {
        assert!(html.contains(&format!("id=\"{scene}\"")), "{scene}");
    }
    // No network: every source is a relative file that exists, a PNG at least 256 wide.
    let srcs = sources(&html);
    assert!(srcs.len() > 50, "{}", srcs.len());
    for s in &srcs {
        assert!(!s.contains("://") && !s.starts_with('/'), "{s}");
        let f = std::fs::File::open(out.join(s)).unwrap_or_else(|e| panic!("{s}: {e}"));
        let info = png::Decoder::new(std::io::BufReader::new(f))
            .read_info()
            .unwrap();
        assert!(info.info().width >= 256, "{s}: {}", info.info().width);
    }

    let Some(chrome) = chromium() else {
        assert!(
            std::env::var_os("VOLSAMPLE_REQUIRE_CHROMIUM").is_none(),
            "VOLSAMPLE_REQUIRE_CHROMIUM is set but no chromium is on PATH"
        );
        eprintln!("note: no chromium on PATH; the browser half of this test did not run");
        return;
    };
    let dom = headless(&chrome, &["--dump-dom"], &page);
    let dom = String::from_utf8_lossy(&dom.stdout);
    let want = format!("data-images=\"ok {}\"", srcs.len());
    assert!(
        dom.contains(&want),
        "want {want}; body: {}",
        dom.split("<body")
            .nth(1)
            .unwrap_or("")
            .chars()
            .take(300)
            .collect::<String>()
    );

    let shot = out.join("screenshot.png");
    let s = headless(
        &chrome,
        &[
            &format!("--screenshot={}", shot.display()),
            "--window-size=1280,1600",
        ],
        &page,
    );
    assert!(shot.is_file(), "{}", String::from_utf8_lossy(&s.stderr));
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&shot).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    let px = info.color_type.samples();
    // Not blank: some pixels are far from white (text, plots, images), and the page is not
    // one color.
    let dark = buf
        .chunks(px)
        .filter(|p| p.iter().take(3).any(|&c| c < 128))
        .count();
    let total = buf.len() / px;
    assert!(dark * 200 > total, "{dark} of {total} pixels dark");
    let distinct: std::collections::HashSet<&[u8]> = buf.chunks(px).collect();
    assert!(distinct.len() > 16, "{} colors", distinct.len());
    eprintln!(
        "chromium: {want}, screenshot {}x{}, {dark} of {total} pixels dark",
        info.width, info.height
    );
}
