//! The cost of a movie rendered in chunks over hosts: `render --by frames`, whose `farm`
//! cuts the movie into chunks of a few frames, has GNU parallel run each on the next
//! free job slot of a host, and writes the frames back in the movie's order.
//!
//! A movie's frames are independent, so the thesis's pipeline model (chapter 5.2, in
//! [`crate::model`]) prices a chunk as a render of its own: its stages' work for the
//! chunk's frames and their start, render.sh's start, and what a chunk costs on top
//! there (an ssh login, parallel's job, the script that carries the chunk to the host).
//! So a chunk of n frames takes
//!
//! * T_chunk(n) = T_start + n·T_frame
//!
//! on a host, and the hosts share the chunks: parallel hands the next chunk to the slot
//! that frees first (list scheduling), the cutter runs ahead of the writer by at most
//! two chunks a slot (the spool's bound), and the writer takes the chunks in order, each
//! frame checked and written at T_write (the merger's cost of a frame's screen). The
//! movie's wall time is when the last frame is written; its work, what every process of
//! the run costs together: the chunks' and the writer's.

use crate::look::Environment;
use crate::model::{self, Constants, Target};

/// What a chunked render of a movie costs, in seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Farm {
    /// The movie's frames and the frames of a chunk.
    pub frames: u64,
    pub chunk: u64,
    /// Job slots over all hosts (a slot renders one chunk at a time).
    pub slots: usize,
    /// A chunk's wall seconds beyond its frames on a host (T_start), and its CPU seconds.
    pub start_s: f64,
    pub start_cpu_s: f64,
    /// A frame's wall seconds on a host (T_frame), and its CPU seconds.
    pub frame_s: f64,
    pub frame_cpu_s: f64,
    /// The writer's seconds a frame (T_write): read back, checked, written.
    pub write_s: f64,
    /// The run's own start, once: parallel's (a Perl program) and the spool's.
    pub run_s: f64,
}

/// The prediction for a [`Farm`].
#[derive(Clone, Debug, PartialEq)]
pub struct FarmPrediction {
    pub chunks: u64,
    /// Wall seconds from the first chunk's hand-over to the last frame written.
    pub wall_s: f64,
    /// CPU seconds of every process of the run together.
    pub work_s: f64,
    /// Chunks each slot rendered.
    pub per_slot: Vec<u64>,
    /// When each chunk started on its slot.
    pub started: Vec<f64>,
}

impl FarmPrediction {
    pub fn frames_per_s(&self, frames: u64) -> f64 {
        if self.wall_s > 0.0 {
            frames as f64 / self.wall_s
        } else {
            0.0
        }
    }
}

/// The chunks of `frames` frames cut `chunk` at a time: the frames of each.
pub fn chunk_frames(frames: u64, chunk: u64) -> Vec<u64> {
    let chunk = chunk.max(1);
    (0..frames.div_ceil(chunk))
        .map(|i| chunk.min(frames - i * chunk))
        .collect()
}

/// Runs the schedule: chunk i is handed once fewer than two chunks a slot are unwritten
/// (when chunk i − 2·slots has been written), starts on the slot that frees first, and is
/// written after it has finished and chunk i − 1 has been written.
pub fn predict_farm(f: &Farm) -> FarmPrediction {
    let slots = f.slots.max(1);
    let bound = 2 * slots;
    let sizes = chunk_frames(f.frames, f.chunk);
    let mut free_at = vec![0.0f64; slots];
    let mut per_slot = vec![0u64; slots];
    let mut written: Vec<f64> = Vec::with_capacity(sizes.len());
    let mut started = Vec::with_capacity(sizes.len());
    let mut work = 0.0;
    for (i, &n) in sizes.iter().enumerate() {
        let handed = if i >= bound { written[i - bound] } else { 0.0 };
        // The slot that frees first (the lowest numbered of equals).
        let (slot, free) = free_at
            .iter()
            .copied()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, 0.0));
        started.push(handed.max(free));
        let finish = handed.max(free) + f.start_s + n as f64 * f.frame_s;
        free_at[slot] = finish;
        per_slot[slot] += 1;
        let before = written.last().copied().unwrap_or(0.0);
        written.push(finish.max(before) + n as f64 * f.write_s);
        work += f.start_cpu_s + n as f64 * (f.frame_cpu_s + f.write_s);
    }
    FarmPrediction {
        chunks: sizes.len() as u64,
        wall_s: f.run_s + written.last().copied().unwrap_or(0.0),
        work_s: f.run_s + work,
        per_slot,
        started,
    }
}

/// A movie's [`Farm`] from the cost model: `env` the whole movie (its frames), each host
/// slot with `host_cores` cores; `login_s` a chunk's cost beyond render.sh there (an ssh
/// login; 0 for a stand-in that runs the command here) and `job_s` parallel's own for a
/// job (its Perl wrapper and the script carrying the chunk): [`PARALLEL_JOB_S`] and
/// [`PARALLEL_START_S`] unless measured.
pub fn farm_from_model(
    k: &Constants,
    env: &Environment,
    chunk: u64,
    slots: usize,
    host_cores: usize,
    login_s: f64,
    job_s: f64,
) -> Farm {
    let frames = env.frames.max(1);
    let target = Target::cores(host_cores.max(1));
    // A render of one frame and of two: the difference is a frame's cost, the rest the
    // start (render.sh, its stages' processes and their fixed costs).
    let of = |n: u64| {
        let p = model::predict_on(k, &scaled(env, n), 0, &target);
        let cpu: f64 = p.stages.iter().map(|s| s.total_s).sum::<f64>() + p.overhead_s;
        (p.total_s, cpu)
    };
    let (one, one_cpu) = of(1);
    let (two, two_cpu) = of(2);
    let frame_s = (two - one).max(0.0);
    let frame_cpu_s = (two_cpu - one_cpu).max(0.0);
    Farm {
        frames,
        chunk,
        slots,
        start_s: (one - frame_s).max(0.0) + login_s + job_s,
        start_cpu_s: (one_cpu - frame_cpu_s).max(0.0) + login_s + job_s,
        frame_s,
        frame_cpu_s,
        write_s: k.merge.screen * env.screen(),
        run_s: PARALLEL_START_S,
    }
}

/// CPU seconds GNU parallel spends on a job beyond the command: the Perl wrapper it
/// starts with each job on the host, measured on the project's 2-core machine (`seq N |
/// parallel -j1 --ssh STAND-IN --sshlogin 1/a true` under `perf stat -e task-clock`: 0.80
/// s for 25 jobs against 0.125 s for 1, 28 ms a job), and farm's script around it.
pub const PARALLEL_JOB_S: f64 = 0.03;

/// parallel's own start, once a run (the same measure: 0.125 s for one job).
pub const PARALLEL_START_S: f64 = 0.1;

/// The environment of `n` of the movie's frames: its counts in proportion.
pub fn scaled(env: &Environment, n: u64) -> Environment {
    let r = n as f64 / env.frames.max(1) as f64;
    let part = |x: u64| (x as f64 * r).round() as u64;
    Environment {
        frames: n,
        polygons: part(env.polygons),
        vertices: part(env.vertices),
        relevant: part(env.relevant),
        relevant_vertices: part(env.relevant_vertices),
        area: env.area * r,
        ..*env
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn farm(frames: u64, chunk: u64, slots: usize) -> Farm {
        Farm {
            frames,
            chunk,
            slots,
            start_s: 0.1,
            start_cpu_s: 0.05,
            frame_s: 0.01,
            frame_cpu_s: 0.01,
            write_s: 0.0,
            run_s: 0.0,
        }
    }

    #[test]
    fn a_movie_is_cut_into_whole_chunks_and_a_last_short_one() {
        assert_eq!(chunk_frames(20, 8), [8, 8, 4]);
        assert_eq!(chunk_frames(16, 8), [8, 8]);
        assert_eq!(chunk_frames(3, 8), [3]);
        assert!(chunk_frames(0, 8).is_empty());
    }

    #[test]
    fn one_slot_renders_the_chunks_one_after_another() {
        // 12 chunks of 8: 12 × (0.1 + 8 × 0.01) = 2.16 s; work 12 × 0.05 + 96 × 0.01.
        let p = predict_farm(&farm(96, 8, 1));
        assert_eq!(p.chunks, 12);
        assert!((p.wall_s - 2.16).abs() < 1e-9, "{p:?}");
        assert!((p.work_s - 1.56).abs() < 1e-9, "{p:?}");
        assert_eq!(p.per_slot, [12]);
    }

    #[test]
    fn hosts_share_the_chunks_and_the_work_stays() {
        // 12 equal chunks over 4 slots: 3 rounds of 0.18 s; the same work as on one.
        let p = predict_farm(&farm(96, 8, 4));
        assert!((p.wall_s - 0.54).abs() < 1e-9, "{p:?}");
        assert!((p.work_s - 1.56).abs() < 1e-9, "{p:?}");
        assert_eq!(p.per_slot, [3, 3, 3, 3]);
        // 5 chunks over 4 slots: the fifth waits for a slot, 2 rounds.
        let p = predict_farm(&farm(40, 8, 4));
        assert!((p.wall_s - 0.36).abs() < 1e-9, "{p:?}");
    }

    #[test]
    fn the_in_order_writer_adds_its_frames_after_the_last_chunk() {
        // One slot, writes of 0.02 s a frame: chunk 0 is written while chunk 1 renders;
        // the last chunk's 8 writes come after everything.
        let mut f = farm(16, 8, 1);
        f.write_s = 0.02;
        let p = predict_farm(&f);
        // Chunk 0 done at 0.18, written by 0.34; chunk 1 done at 0.36, written by 0.52.
        assert!((p.wall_s - 0.52).abs() < 1e-9, "{p:?}");
        // A writer slower than the rendering bounds the movie: 16 × 0.1 after the first.
        f.write_s = 0.1;
        let p = predict_farm(&f);
        assert!((p.wall_s - (0.18 + 1.6)).abs() < 1e-9, "{p:?}");
    }

    #[test]
    fn the_spool_bound_holds_the_cutter_back() {
        // One slot, a writer of 1 s a frame: chunk 2 is handed only when chunk 0 is
        // written (at 0.11 + 1), so it starts then, not when the slot frees at 0.22.
        let mut f = farm(3, 1, 1);
        f.write_s = 1.0;
        let p = predict_farm(&f);
        assert!((p.started[2] - 1.11).abs() < 1e-9, "{p:?}");
        // Done at 1.22; written after chunk 1 (written at 2.11): 3.11.
        assert!((p.wall_s - 3.11).abs() < 1e-9, "{p:?}");
        // With a fast writer the slot never waits: chunk 2 starts as chunk 1 ends.
        f.write_s = 0.0;
        assert!((predict_farm(&f).started[2] - 0.22).abs() < 1e-9);
    }

    #[test]
    fn a_chunk_from_the_model_is_a_start_and_a_cost_a_frame() {
        let k = Constants::committed();
        let env = Environment {
            frames: 96,
            polygons: 96_000,
            vertices: 384_000,
            relevant: 60_000,
            relevant_vertices: 240_000,
            area: 96.0 * 512.0 * 512.0 * 30.0,
            width: 512,
            height: 512,
            text: false,
        };
        let f = farm_from_model(&k, &env, 8, 2, 1, 0.0, 0.0);
        // The start is render.sh's and its three processes' (script 13 ms, 1.8 ms a
        // process, the stages' own fixed costs), with none of a frame's.
        assert!(f.start_s > k.overheads.script, "{f:?}");
        assert!(f.start_s < 0.05, "{f:?}");
        // Eight frames of a chunk cost what the model says of a render of eight.
        let eight = model::predict_on(&k, &scaled(&env, 8), 0, &Target::cores(1));
        assert!(
            (f.start_s + 8.0 * f.frame_s - eight.total_s).abs() < 1e-6,
            "{f:?} {}",
            eight.total_s
        );
        // A login and parallel's job add to every chunk.
        let g = farm_from_model(&k, &env, 8, 2, 1, 0.1, 0.02);
        assert!((g.start_s - f.start_s - 0.12).abs() < 1e-9);
    }
}
