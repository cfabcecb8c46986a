//! A screen or a frame too large for this machine's memory: refused at the header, in one
//! line, with status 3, by the merger and by each leaf stage on its own, rather than an
//! abort of the allocator or a minute's work first. The address space is limited to
//! 8 GB, so that such a frame cannot be had on any machine.

use pipeline_tests::sh;

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `printf 'polypipe 2 fragments 65536 65536\nEND\n' | zbuf` aborted with SIGABRT
/// (`memory allocation of 34359738368 bytes failed`). The address space is limited to
/// 8 GB so that the frame cannot be had on any machine.
#[test]
fn a_frame_too_large_for_memory_is_refused_in_one_line() {
    let out = sh(
        "ulimit -v 8000000; printf 'polypipe 2 fragments 65536 65536\\nEND\\n' | zbuf",
        b"",
    );
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(
        stderr(&out).starts_with(
            "zbuf: stdin: a 65536x65536 screen needs 60 GiB (15 bytes a pixel: depth, polygon \
             and colour), more memory than this machine can give ("
        ),
        "{}",
        stderr(&out)
    );
    assert!(out.stdout.is_empty());
    // The reference's frame the same way.
    let out = sh(
        "ulimit -v 8000000; scene penetrating | zspec --size 65536x65536",
        b"",
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert_eq!(
        stderr(&out),
        "zspec: a 65536x65536 frame needs 44 GiB (11 bytes a pixel: colour and depth), more \
         memory than can be had\n"
    );
}

/// `--size 65536x65536` was refused only after abuf had computed for over 60 s, with
/// status 1. Too large for this machine is status 3, said at the header: by the merger
/// in a render, and by each leaf stage on its own (the address space limited to 8 GB,
/// so that 3 bytes a pixel of 65536x65536 cannot be had on any machine).
#[test]
fn a_screen_too_large_for_this_machine_is_refused_at_the_header() {
    let started = std::time::Instant::now();
    let out = sh(
        "scripts/render.sh --size 65536x65536 --depth 1 --aa abuf examples/penetrating.txt > /dev/null",
        b"",
    );
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(
        stderr(&out).starts_with("zbuf: ") && stderr(&out).lines().count() == 1,
        "{}",
        stderr(&out)
    );
    assert!(
        started.elapsed() < std::time::Duration::from_secs(20),
        "took {:?}",
        started.elapsed()
    );
    for (stage, bytes, what) in [
        ("scanconv --resolve", "48 GiB (12", "depth and colour"),
        ("warnock", "12 GiB (3", "at least a resolved colour"),
        ("scanline", "12 GiB (3", "at least a resolved colour"),
        ("supersample", "12 GiB (3", "at least a resolved colour"),
    ] {
        // The input stays open after the header: a stage that waited for polygons
        // instead of refusing would be stopped after 20 s and fail here.
        let mut words = stage.split(' ');
        let program = pipeline_tests::bin(words.next().unwrap());
        let mut child = std::process::Command::new("bash")
            .arg("-c")
            .arg("ulimit -v 8000000; exec \"$0\" \"$@\"")
            .arg(&program)
            .args(words)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let mut input = child.stdin.take().unwrap();
        std::io::Write::write_all(&mut input, b"polypipe 1 screen 65536 65536\n").unwrap();
        let (status, _) =
            pipeline_tests::wait_within(&mut child, std::time::Duration::from_secs(20), || {
                format!("{stage} waited for polygons instead of refusing the screen")
            });
        drop(input);
        let mut err = String::new();
        std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
        let out = std::process::Output {
            status,
            stdout: Vec::new(),
            stderr: err.into_bytes(),
        };
        let name = stage.split(' ').next().unwrap();
        assert_eq!(out.status.code(), Some(3), "{stage}: {}", stderr(&out));
        assert!(
            stderr(&out).starts_with(&format!(
                "{name}: a 65536x65536 screen needs {bytes} bytes a pixel: {what}), more \
                 memory than this machine can give ("
            )),
            "{stage}: {}",
            stderr(&out)
        );
    }
}
