//! frames as a filter: counts, ranges in both forms, binary bytes kept, refusals and
//! exit codes.

use assert_cmd::Command;
use predicates::prelude::*;

fn frames() -> Command {
    Command::new(pipeline_tests::bin("frames"))
}

/// Three frames of one triangle each, coloured 1, 2 and 3.
const MOVIE: &str = "polypipe 1 world\n\
    colour 1 1 1\n0 0 0\n1 0 0\n0 1 0\nNEXT.FRAME\n\
    colour 2 2 2\n0 0 0\n1 0 0\n0 1 0\nNEXT.FRAME\n\
    colour 3 3 3\n0 0 0\n1 0 0\n0 1 0\nEND\n";

#[test]
fn counts_the_frames() {
    frames()
        .arg("--count")
        .write_stdin(MOVIE)
        .assert()
        .success()
        .stdout("3\n");
}

#[test]
fn counts_a_file_named_on_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("movie.txt");
    std::fs::write(&path, MOVIE).unwrap();
    frames()
        .arg("--count")
        .arg(&path)
        .assert()
        .success()
        .stdout("3\n");
}

#[test]
fn passes_the_middle_frame_as_a_movie() {
    frames()
        .args(["--from", "1", "--to", "2", "--text"])
        .write_stdin(MOVIE)
        .assert()
        .success()
        .stdout("polypipe 1 world\ncolour 2 2 2\n0 0 0\n1 0 0\n0 1 0\nEND\n");
}

#[test]
fn binary_ranges_join_to_the_binary_movie_byte_for_byte() {
    // The whole movie in binary, and its three one-frame cuts: each cut is the header,
    // the frame's records and END, the same bytes as in the whole.
    let whole = frames().write_stdin(MOVIE).output().unwrap().stdout;
    let cut = |a: &str, b: &str| {
        frames()
            .args(["--from", a, "--to", b])
            .write_stdin(whole.clone())
            .output()
            .unwrap()
            .stdout
    };
    let (first, rest) = (cut("0", "1"), cut("1", "3"));
    // header + frame 0 + END, header + frame 1 + NEXT.FRAME + frame 2 + END
    // Magic, version u32, space tag u32 (world has no fields), attributes (one byte: no
    // depth form; one each for vertex colours, vertex normals and opacity; one: no
    // lighting).
    let header_len = 8 + 8 + 5;
    // Stream version 2's fixed-layout records: NEXT.FRAME and END are one 8-byte head each.
    let end_len = 8;
    let next_frame_len = 8;
    let f0 = &first[header_len..first.len() - end_len];
    let rest_body = &rest[header_len..rest.len() - end_len];
    let mut joined = first[..header_len].to_vec();
    joined.extend_from_slice(f0);
    joined.extend_from_slice(&whole[header_len + f0.len()..header_len + f0.len() + next_frame_len]);
    joined.extend_from_slice(rest_body);
    joined.extend_from_slice(&first[first.len() - end_len..]);
    assert_eq!(joined, whole);
}

#[test]
fn a_range_beyond_the_movie_fails_naming_its_length() {
    frames()
        .args(["--from", "3"])
        .write_stdin(MOVIE)
        .assert()
        .code(1)
        .stderr("frames: stdin: the movie has 3 frames (0 to 2): --from 3 selects none\n");
}

#[test]
fn a_range_beyond_the_movie_writes_nothing_not_a_broken_stream() {
    // `frames --from 30 --to 40` on a 30-frame movie wrote a header and no END; now
    // nothing, in either form.
    let movie = (0..30)
        .map(|k| format!("colour {k} 0 0\n0 0 0\n1 0 0\n0 1 0\n"))
        .collect::<Vec<_>>()
        .join("NEXT.FRAME\n");
    let movie = format!("polypipe 1 world\n{movie}END\n");
    for text in [&[][..], &["--text"]] {
        frames()
            .args(["--from", "30", "--to", "40"])
            .args(text)
            .write_stdin(movie.clone())
            .assert()
            .code(1)
            .stdout("")
            .stderr("frames: stdin: the movie has 30 frames (0 to 29): --from 30 selects none\n");
    }
    // The last frame is still a movie of its own.
    frames()
        .args(["--from", "29", "--to", "40", "--text"])
        .write_stdin(movie)
        .assert()
        .success()
        .stdout("polypipe 1 world\ncolour 29 0 0\n0 0 0\n1 0 0\n0 1 0\nEND\n");
}

#[test]
fn an_empty_range_is_a_usage_error() {
    frames()
        .args(["--from", "2", "--to", "2"])
        .write_stdin(MOVIE)
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "--to 2 must be greater than --from 2",
        ));
}

#[test]
fn count_takes_no_range() {
    frames()
        .args(["--count", "--from", "1"])
        .write_stdin(MOVIE)
        .assert()
        .code(2);
}

#[test]
fn a_cut_short_movie_fails_where_it_ends() {
    frames()
        .arg("--count")
        .write_stdin("polypipe 1 world\ncolour 1 1 1\n0 0 0\nNEXT.FRAME\n")
        .assert()
        .code(1)
        .stderr(
            predicate::str::starts_with("frames: line 4")
                .and(predicate::str::contains("without END")),
        );
}

#[test]
fn a_missing_file_is_an_io_error() {
    frames()
        .args(["--count", "/nonexistent/movie"])
        .assert()
        .code(3)
        .stderr(predicate::str::starts_with(
            "frames: cannot open /nonexistent/movie",
        ));
}

#[test]
fn fragment_streams_are_refused() {
    frames()
        .arg("--count")
        .write_stdin("polypipe 2 fragments 4 4\nEND\n")
        .assert()
        .code(1)
        .stderr("frames: stdin: a fragment stream; frames cuts polygon streams (world, eye or screen)\n");
}
