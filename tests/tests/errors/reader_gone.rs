//! A reader of one output going away (`… | head`): the stage's other outputs still get
//! the whole stream and its END.

use pipeline_tests::sh;

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// when one output's reader went away, the other output was left without END. Now
/// it gets the whole stream: the same as when both readers stay.
#[test]
fn when_one_reader_goes_the_other_branch_is_finished() {
    let dir = tempfile::tempdir().unwrap();
    let (kept, whole) = (dir.path().join("kept"), dir.path().join("whole"));
    let scene = "scene environment --polygons 20000 --seed 3 | viewxf";
    let out = sh(
        &format!(
            "{scene} | splitter --text x=0 - {} | head -c 10",
            kept.display()
        ),
        b"",
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stderr.is_empty());
    let out = sh(
        &format!(
            "{scene} | splitter --text x=0 /dev/null {}",
            whole.display()
        ),
        b"",
    );
    assert!(out.status.success());
    let kept = std::fs::read_to_string(kept).unwrap();
    assert!(kept.ends_with("\nEND\n"));
    assert_eq!(kept, std::fs::read_to_string(whole).unwrap());
}
