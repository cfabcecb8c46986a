//! Slurm: the movie's chunks as a job array.

use crate::checks::{verify_frame, Output};
use stagecli::remote::quote;
use stagecli::{Error, Result};
use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Path, PathBuf};

/// What the sbatch script needs.
#[derive(Clone, Debug)]
pub struct SlurmArray {
    /// The movie, a file (absolute).
    pub movie: PathBuf,
    /// Its frames, and the frames of a chunk (an array task).
    pub frames: u64,
    pub chunk: u64,
    /// `-o`'s pattern (absolute) and `--first-frame`.
    pub pattern: String,
    pub first_frame: u64,
    /// The `frames` binary (absolute).
    pub frames_bin: PathBuf,
    /// The command that renders a movie on stdin (`env POLYPIPE_BIN=… …/render.sh OPTIONS
    /// -`), to which each task adds `-o PATTERN --first-frame A`.
    pub command: Vec<String>,
    /// Where the scripts are, and where Slurm writes each task's output.
    pub dir: PathBuf,
    /// farm itself (absolute), which checks the frames.
    pub farm_bin: PathBuf,
}

/// The array tasks needed: ⌈frames / chunk⌉.
pub fn array_tasks(frames: u64, chunk: u64) -> u64 {
    frames.div_ceil(chunk.max(1))
}

/// `DIR/render.sbatch`: array task k renders frames k·N to k·N + N − 1 of the whole movie
/// (`frames --from A --to B MOVIE | render … -o PATTERN --first-frame A`); run with
/// `--check` (DIR/check.sbatch, a job that runs after the array whatever its tasks did,
/// or by hand) it checks every frame (`farm --slurm-array DIR --check`), and prints the
/// line that submits again the tasks of the frames missing or bad.
pub fn sbatch_script(s: &SlurmArray) -> String {
    let tasks = array_tasks(s.frames, s.chunk);
    let q = |p: &Path| quote(&p.display().to_string());
    let mut render = String::new();
    for w in &s.command {
        render.push_str(&quote(w));
        render.push(' ');
    }
    format!(
        r#"#!/bin/bash
# A movie's frames as a Slurm job array, written by farm (render.sh --by frames
# --slurm-array): task k renders chunk k, frames k*{chunk} to k*{chunk}+{last} of the
# movie, named by the movie's numbers (from {first}). Submit it and its check, which
# runs when the tasks have ended, however they ended, and names the tasks to submit
# again:
#
#   jid=$(sbatch --parsable {script})
#   sbatch --dependency=afterany:$jid {check}
#
# Locally, as Slurm would: for k in $(seq 0 {max}); do SLURM_ARRAY_TASK_ID=$k bash {script}; done
#SBATCH --job-name=polypipe-frames
#SBATCH --array=0-{max}
#SBATCH --output={output}
set -euo pipefail
movie={movie}
pattern={pattern}
frames={frames} chunk={chunk} first={first}
if [[ ${{1-}} == --check ]]; then
    exec {farm_bin} --slurm-array {dir} --check --chunk "$chunk" -o "$pattern" --first-frame "$first" "$movie"
fi
k=${{SLURM_ARRAY_TASK_ID:?render.sbatch: run by sbatch --array, or with SLURM_ARRAY_TASK_ID=k, or --check}}
a=$((k * chunk))
b=$((a + chunk < frames ? a + chunk : frames))
((a < frames)) || {{ echo "render.sbatch: task $k is past the movie's $frames frames" >&2; exit 2; }}
{frames_bin} --from "$a" --to "$b" "$movie" | {render}-o "$pattern" --first-frame $((first + a))
"#,
        chunk = s.chunk,
        last = s.chunk - 1,
        max = tasks.saturating_sub(1),
        script = q(&s.dir.join("render.sbatch")),
        check = q(&s.dir.join("check.sbatch")),
        output = sbatch_quote(&s.dir.join("slurm-%A_%a.out")),
        dir = q(&s.dir),
        movie = q(&s.movie),
        pattern = quote(&s.pattern),
        frames = s.frames,
        first = s.first_frame,
        frames_bin = q(&s.frames_bin),
        farm_bin = q(&s.farm_bin),
    )
}

/// `DIR/check.sbatch`: the check of the frames as a job of its own, its log in DIR.
pub fn check_script(dir: &Path) -> String {
    format!(
        "#!/bin/bash\n# The check of DIR/render.sbatch's frames, written by farm: submit it \
         to run after the\n# array, however its tasks ended (see render.sbatch).\n\
         #SBATCH --job-name=polypipe-check\n#SBATCH --output={}\nexec bash {} --check\n",
        sbatch_quote(&dir.join("check-%j.out")),
        quote(&dir.join("render.sbatch").display().to_string())
    )
}

/// A path in an `#SBATCH` line: in double quotes, which sbatch takes off (a path with a
/// double quote or a newline is refused before the script is written).
fn sbatch_quote(path: &Path) -> String {
    format!("\"{}\"", path.display())
}

/// Whether a folder can be named in an `#SBATCH` line.
pub fn sbatch_path_ok(path: &Path) -> bool {
    let p = path.display().to_string();
    !p.contains('"') && !p.contains('\n')
}

/// `render.sbatch --check`: checks each of the movie's `frames` frames as `--resume` does
/// (a whole PNG or PPM, all of one size), prints a line on `out` for each missing or
/// bad, and then, when any is, the line that submits their array tasks again; the error
/// then says how many.
pub fn check_frames_of(
    output: &Output,
    frames: u64,
    chunk: u64,
    script: &Path,
    out: &mut dyn Write,
) -> Result<()> {
    let png = matches!(output, Output::Files { png: true, .. });
    let mut size = None;
    let mut bad = 0u64;
    let mut tasks = BTreeSet::new();
    for k in 0..frames {
        let Some(file) = output.path(k) else { break };
        let why = match (verify_frame(&file, png), size) {
            (Err(why), _) => why,
            (Ok(wh), None) => {
                size = Some(wh);
                continue;
            }
            (Ok(wh), Some(s)) if wh == s => continue,
            (Ok((w, h)), Some((sw, sh))) => format!("{w}x{h}, the others {sw}x{sh}"),
        };
        bad += 1;
        tasks.insert(k / chunk.max(1));
        let _ = writeln!(
            out,
            "frame {} ({}): {why}",
            output.number(k),
            file.display()
        );
    }
    if bad == 0 {
        let _ = writeln!(out, "all {frames} frames there, whole");
        return Ok(());
    }
    let list: Vec<String> = tasks.iter().map(u64::to_string).collect();
    let list = list.join(",");
    let _ = writeln!(
        out,
        "sbatch --array={list} {}",
        quote(&script.display().to_string())
    );
    let _ = out.flush();
    Err(Error::data(format!(
        "{bad} of {frames} frames missing or bad, of array task{} {list}: the line above \
         submits {} again",
        if tasks.len() == 1 { "" } else { "s" },
        if tasks.len() == 1 { "it" } else { "them" }
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sbatch_script_renders_chunk_k_with_the_movies_numbers() {
        let s = sbatch_script(&SlurmArray {
            movie: "/m/movie.pp".into(),
            frames: 60,
            chunk: 16,
            pattern: "/out/f%05d.png".into(),
            first_frame: 0,
            frames_bin: "/bin/frames".into(),
            command: vec![
                "/r/render.sh".into(),
                "--size".into(),
                "32x32".into(),
                "-".into(),
            ],
            dir: "/out".into(),
            farm_bin: "/bin/farm".into(),
        });
        assert!(s.contains("#SBATCH --array=0-3\n"), "{s}");
        assert!(s.contains("frames=60 chunk=16 first=0\n"), "{s}");
        assert!(
            s.contains(
                "'/bin/frames' --from \"$a\" --to \"$b\" \"$movie\" | '/r/render.sh' '--size' \
             '32x32' '-' -o \"$pattern\" --first-frame $((first + a))\n"
            ),
            "{s}"
        );
        assert_eq!(array_tasks(60, 16), 4);
        assert_eq!(array_tasks(64, 16), 4);
    }
}
