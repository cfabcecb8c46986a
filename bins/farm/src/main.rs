//! farm: a movie's frames rendered on other hosts by GNU parallel, written back in order
//! (the crate's documentation says how).

use clap::Parser;
use farm::{Logins, Options, Outcome, Output};
use proto::{Reader, Token};
use stagecli::Error;
use std::path::PathBuf;
use std::process::ExitCode;

/// Renders a movie on other hosts through GNU parallel and writes its frames in order.
///
/// Reads a polygon stream (world, eye or screen; binary or text) from SCENE or stdin,
/// cuts it into chunks of --chunk frames, and hands them to GNU parallel, which runs
/// `$POLYPIPE_SSH HOST COMMAND…` for each on a host with a free job slot, the chunk on
/// its stdin, and retries a chunk that failed on another host; COMMAND renders a movie
/// to PPM frames (`render.sh --by frames` runs `COMMAND = env POLYPIPE_BIN=DIR
/// …/render.sh OPTIONS -`). The frames come out on stdout in the movie's order, or one
/// file each with -o, with two chunks a job slot at most in $TMPDIR.
///
/// With --slurm-array DIR, nothing is rendered: DIR/render.sbatch is written, a Slurm
/// job array whose task k renders chunk k to -o's files, and DIR/check.sbatch, the job
/// that checks the frames once the tasks have ended (`--check`).
///
/// Exit status: 0 success (also when the reader of the frames goes away); 1 bad input;
/// 2 bad arguments; 3 a chunk failed on every try (the message names the host(s) and
/// the chunk; the frames before it are written), or no GNU parallel; a host's own
/// render.sh status 1 or 2 passes through; 130 and 143 after SIGINT and SIGTERM.
#[derive(Parser, Debug)]
#[command(
    name = "farm",
    version,
    after_help = "Environment:\n  \
        POLYPIPE_SSH   the command that runs a command on a host, as `$POLYPIPE_SSH HOST \
        COMMAND`\n                 (default: ssh -o BatchMode=yes -o ConnectTimeout=5 -o \
        ServerAliveInterval=2\n                 -o ServerAliveCountMax=3)\n\n\
        Examples:\n  \
        scene spheres --frames 300 | scripts/render.sh --hosts alpha,beta --by frames - > movie.ppm\n  \
        farm --sshloginfile hosts -o out/f%05d.png movie.pp -- /opt/polypipe/scripts/render.sh -\n  \
        farm --slurm-array out --chunk 10 -o 'out/f%05d.png' movie.pp -- /opt/polypipe/scripts/render.sh -"
)]
struct Cli {
    /// The hosts, as ssh names them (a host named twice renders two chunks at once).
    #[arg(long, value_name = "H1,H2,…", conflicts_with = "sshloginfile")]
    hosts: Option<String>,
    /// The hosts from a file of GNU parallel's: `N/host` a line, N chunks at once there.
    #[arg(long, value_name = "FILE")]
    sshloginfile: Option<PathBuf>,
    /// Frames a chunk: each chunk is one job, one ssh session.
    #[arg(long, value_name = "N", default_value_t = farm::DEFAULT_CHUNK,
          value_parser = stagecli::numbers::whole::<u64>(1, u64::MAX))]
    chunk: u64,
    /// Tries of a chunk, each on a host where it has not failed while there is one.
    #[arg(long, value_name = "N", default_value_t = farm::DEFAULT_RETRIES,
          value_parser = stagecli::numbers::whole::<u32>(1, u32::MAX as u64))]
    retries: u32,
    /// Failed tries in a row after which a host gets no more chunks (while another host
    /// is left); its first failure is named at once.
    #[arg(long, value_name = "K", default_value_t = farm::DEFAULT_HOST_FAILURES,
          value_parser = stagecli::numbers::whole::<u32>(1, u32::MAX as u64))]
    host_failures: u32,
    /// Seconds a host may send nothing (no frame byte, no message) before its try fails
    /// and its chunk is retried elsewhere; 0 waits for ever.
    #[arg(long, value_name = "S", default_value_t = farm::DEFAULT_HOST_TIMEOUT,
          value_parser = stagecli::numbers::whole::<u64>(0, u64::MAX))]
    host_timeout: u64,
    /// GNU parallel's job log (default: farm.joblog beside -o's files; with the frames
    /// on stdout, none kept).
    #[arg(long, value_name = "FILE")]
    joblog: Option<PathBuf>,
    /// Render only the chunks the job log does not call finished, or whose frames are
    /// missing or cut (needs -o; without a job log, every chunk).
    #[arg(long)]
    resume: bool,
    /// Write DIR/render.sbatch, a Slurm job array of the chunks, instead of rendering.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["hosts", "sshloginfile", "resume", "joblog"])]
    slurm_array: Option<PathBuf>,
    /// With --slurm-array DIR: check the frames the array wrote (each there, whole, all of
    /// one size) instead of writing DIR's scripts, printing the line that submits the
    /// tasks of any missing or bad again (status 1 then).
    #[arg(long, requires = "slurm_array")]
    check: bool,
    /// One file a frame instead of PPMs on stdout: `%d` or `%0Nd` the frame's number;
    /// .png or .ppm by the extension (zbuf's -o).
    #[arg(short = 'o', value_name = "PATTERN")]
    output: Option<String>,
    /// The number -o gives the movie's first frame.
    #[arg(long, value_name = "N", default_value_t = 0, requires = "output",
          value_parser = stagecli::numbers::whole::<u64>(0, u64::MAX))]
    first_frame: u64,
    /// Also: per host, its frames, the bytes each way and the time; each failed try.
    #[arg(long)]
    stats: bool,
    /// The movie (`-` for stdin, the default).
    #[arg(default_value = "-")]
    scene: String,
    /// What each host runs, the chunk on its stdin and the frames on its stdout.
    #[arg(last = true, required_unless_present = "check", value_name = "COMMAND")]
    command: Vec<String>,
}

fn main() -> ExitCode {
    let mut outcome = Outcome::Done;
    let code = stagecli::main("farm", |cli: Cli| {
        let output = match &cli.output {
            Some(p) => Output::files(p, cli.first_frame).map_err(Error::usage)?,
            None => Output::Stdout,
        };
        if let Some(dir) = &cli.slurm_array {
            return slurm(&cli, dir);
        }
        let logins = match (&cli.hosts, &cli.sshloginfile) {
            (Some(h), _) => Logins::List(farm::logins_from_hosts(h).map_err(Error::usage)?),
            (None, Some(f)) => Logins::File(f.clone()),
            (None, None) => {
                return Err(Error::usage(
                    "the hosts: --hosts H1,H2,… or --sshloginfile FILE (or --slurm-array DIR)",
                ))
            }
        };
        let ssh = stagecli::remote::ssh_command_from_env()?;
        let parallel = farm::find_parallel(std::env::var_os("PATH").as_deref())?;
        let name = stagecli::input_name(&cli.scene).to_string();
        let options = Options {
            logins,
            ssh,
            command: farm::remote_command(&cli.command),
            chunk: cli.chunk,
            retries: cli.retries,
            joblog: cli.joblog.clone(),
            resume: cli.resume,
            output,
            stats: cli.stats,
            scene: name.clone(),
            parallel,
            host_failures: cli.host_failures,
            host_timeout: cli.host_timeout,
        };
        let input = stagecli::open_input(&cli.scene)?;
        let reader = Reader::<Token, _>::new(input).map_err(|e| stagecli::input_error(&name, e))?;
        farm::catch_stop_signals();
        farm::adopt_orphans();
        let mut out = stagecli::stdout();
        outcome = farm::run(reader, &options, &mut out, &mut std::io::stderr())?;
        Ok(())
    });
    match outcome {
        Outcome::Stopped(sig) => ExitCode::from(128 + sig as u8),
        Outcome::Done => code,
    }
}

/// --slurm-array DIR: counts the movie's frames and writes DIR/render.sbatch and
/// DIR/check.sbatch, or with --check checks the frames.
fn slurm(cli: &Cli, dir: &std::path::Path) -> stagecli::Result<()> {
    let pattern = cli
        .output
        .as_deref()
        .ok_or_else(|| Error::usage("--slurm-array needs -o PATTERN: the tasks write files"))?;
    if cli.scene == "-" {
        return Err(Error::usage(
            "--slurm-array needs the movie as a file: each task reads its frames from it",
        ));
    }
    let absolute = |p: &std::path::Path| -> stagecli::Result<PathBuf> {
        std::path::absolute(p)
            .map_err(|e| Error::io(format!("cannot resolve {}: {e}", p.display())))
    };
    let movie = absolute(std::path::Path::new(&cli.scene))?;
    let pattern = absolute(std::path::Path::new(pattern))?
        .display()
        .to_string();
    let dir = absolute(dir)?;
    let input = stagecli::open_input(&cli.scene)?;
    let reader =
        Reader::<Token, _>::new(input).map_err(|e| stagecli::input_error(&cli.scene, e))?;
    let frames = farm::count_frames(reader).map_err(|e| e.context(&cli.scene))?;
    if cli.check {
        let output = Output::files(&pattern, cli.first_frame).map_err(Error::usage)?;
        let mut out = std::io::stdout();
        let script = dir.join("render.sbatch");
        return farm::check_frames_of(&output, frames, cli.chunk, &script, &mut out);
    }
    if !farm::sbatch_path_ok(&dir) {
        return Err(Error::usage(format!(
            "--slurm-array {}: a folder with a double quote or a newline cannot be named in \
             an #SBATCH line",
            dir.display()
        )));
    }
    let here = std::env::current_exe()
        .map_err(|e| Error::io(format!("cannot find farm's own folder: {e}")))?;
    let script = farm::sbatch_script(&farm::SlurmArray {
        movie,
        frames,
        chunk: cli.chunk,
        pattern: pattern.clone(),
        first_frame: cli.first_frame,
        frames_bin: here.with_file_name("frames"),
        command: cli.command.clone(),
        dir: dir.clone(),
        farm_bin: here,
    });
    farm::make_folder(&dir, "the folder")?;
    let pattern_dir = std::path::Path::new(&pattern).parent();
    farm::make_folder(pattern_dir.unwrap_or(&dir), "-o's folder")?;
    let path = dir.join("render.sbatch");
    let check = dir.join("check.sbatch");
    for (p, text) in [(&path, script), (&check, farm::check_script(&dir))] {
        stagecli::whole::write_whole(p, text.as_bytes())?;
    }
    if cli.stats {
        eprintln!(
            "farm: {}: {} frames in {} array tasks of {}",
            path.display(),
            frames,
            farm::array_tasks(frames, cli.chunk),
            cli.chunk
        );
    }
    Ok(())
}
