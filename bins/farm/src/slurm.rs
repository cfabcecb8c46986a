//! Slurm: the movie's chunks as a job array.

use stagecli::remote::quote;
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
    /// Where Slurm writes each task's output.
    pub dir: PathBuf,
}

/// The array tasks needed: ⌈frames / chunk⌉.
pub fn array_tasks(frames: u64, chunk: u64) -> u64 {
    frames.div_ceil(chunk.max(1))
}

/// `DIR/render.sbatch`: array task k renders frames k·N to k·N + N − 1 of the whole movie
/// (`frames --from A --to B MOVIE | render … -o PATTERN --first-frame A`); run with
/// `--check` (a job that depends on the array, or by hand) it lists the frames missing
/// and fails when any is.
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
# --slurm-array): task k renders chunk k, frames k*{chunk} to k*{chunk}+{last}, the
# frame numbers of the whole movie.
#
#   jid=$(sbatch --parsable {script})
#   sbatch --dependency=afterok:$jid --wrap 'bash {script} --check'
#
# Locally, as Slurm would: for k in $(seq 0 {max}); do SLURM_ARRAY_TASK_ID=$k bash {script}; done
#SBATCH --job-name=polypipe-frames
#SBATCH --array=0-{max}
#SBATCH --output={dir}/slurm-%A_%a.out
set -euo pipefail
movie={movie}
pattern={pattern}
frames={frames} chunk={chunk} first={first}
if [[ ${{1-}} == --check ]]; then
    missing=0
    for ((i = 0; i < frames; i++)); do
        # shellcheck disable=SC2059 # the pattern is the format: %d, %0Nd, %%
        printf -v file "$pattern" $((first + i))
        [[ -s $file ]] || {{ echo "render.sbatch: frame $i missing: $file" >&2; missing=$((missing + 1)); }}
    done
    ((missing == 0)) || {{ echo "render.sbatch: $missing of $frames frames missing" >&2; exit 1; }}
    echo "render.sbatch: all $frames frames there"
    exit 0
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
        dir = q(&s.dir),
        movie = q(&s.movie),
        pattern = quote(&s.pattern),
        frames = s.frames,
        first = s.first_frame,
        frames_bin = q(&s.frames_bin),
    )
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
