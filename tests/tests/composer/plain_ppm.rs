//! `--text` on the stages that write pictures (zbuf, zspec): plain PPM (P3), the same
//! pixels as the binary P6, on stdout and in `-o` files.

use pipeline_tests::{linear_pipeline, parse_ppm_stream, sh};

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// "Add `--text` to any stage", but zbuf and zspec refused it. For the stages that
/// write pictures it means plain PPM (P3): the same pixels as text.
#[test]
fn text_on_the_picture_stages_writes_plain_ppm() {
    let size = "6x4";
    let binary = sh(
        &format!("scene penetrating --frames 2 | {}", linear_pipeline(size)),
        b"",
    );
    let plain = sh(
        &format!(
            "scene penetrating --frames 2 | {} --text",
            linear_pipeline(size)
        ),
        b"",
    );
    assert!(binary.status.success() && plain.status.success());
    assert!(plain.stdout.starts_with(b"P3\n6 4\n255\n"));
    assert!(plain.stdout.is_ascii());
    let frames = parse_ppm_stream(&binary.stdout).unwrap();
    assert_eq!(frames.len(), 2);
    assert_eq!(parse_ppm_stream(&plain.stdout).unwrap(), frames);
    // The reference alike, and to files: -o f%d.ppm --text writes P3 files.
    let exact = sh(
        "scene penetrating --frames 2 | zspec --size 6x4 --text",
        b"",
    );
    assert!(exact.stdout.starts_with(b"P3\n6 4\n255\n"));
    assert_eq!(parse_ppm_stream(&exact.stdout).unwrap(), frames);
    let dir = tempfile::tempdir().unwrap();
    let files = sh(
        &format!(
            "scene penetrating --frames 2 | {} --text -o {}/f%d.ppm",
            linear_pipeline(size),
            dir.path().display()
        ),
        b"",
    );
    assert!(files.status.success(), "{}", stderr(&files));
    let f1 = std::fs::read(dir.path().join("f1.ppm")).unwrap();
    assert!(f1.starts_with(b"P3\n"));
    assert_eq!(parse_ppm_stream(&f1).unwrap()[0], frames[1]);
}
