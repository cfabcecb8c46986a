//! The depth a projection writes is `--zmode MODE` on every binary that projects (persp,
//! and zbuf and splitter with `--project`): each one's help names the new spelling and
//! its modes, never the old one (persp's `--depth MODE`, zbuf's and splitter's
//! `--persp MODE`), which each still takes for one release with a note (their own
//! tests: the same outputs, the note, the two spellings together refused).

use pipeline_tests::sh;

#[test]
fn the_help_names_zmode_and_not_the_old_spelling() {
    for (stage, named, not_named) in [
        ("persp", &["--zmode <MODE>", "eye-z"][..], "--depth"),
        ("zbuf", &["--project", "--zmode <MODE>", "eye-z"], "--persp"),
        (
            "splitter",
            &["--project", "--zmode <MODE>", "eye-z"],
            "--persp",
        ),
    ] {
        let out = sh(&format!("{stage} --help"), b"");
        assert!(out.status.success(), "{stage} --help: {:?}", out.status);
        let help = String::from_utf8(out.stdout).unwrap();
        for word in named {
            assert!(help.contains(word), "{stage} --help lacks {word}: {help}");
        }
        assert!(!help.contains(not_named), "{stage} --help: {help}");
    }
}
