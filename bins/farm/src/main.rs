//! farm: a movie's frames rendered on other hosts, written back in order (the crate's
//! documentation says how).

use clap::Parser;
use farm::{Options, Outcome};
use proto::{Reader, Token};
use stagecli::Error;
use std::process::ExitCode;

/// Renders a movie on other hosts and writes its frames on stdout in order.
///
/// Reads a polygon stream (world, eye or screen; binary or text) from SCENE or stdin,
/// cuts it into chunks of --chunk frames, and runs `$POLYPIPE_SSH HOST COMMAND…` for
/// each chunk on the first host with nothing to do, the chunk on its stdin; COMMAND
/// renders a movie to PPM frames (`render.sh --hosts … --by frames` runs
/// `COMMAND = env POLYPIPE_BIN=DIR …/render.sh OPTIONS -`). The frames come back on
/// stdout in the movie's order as soon as those before them are written, with nothing
/// on disk and a few chunks per host at most in memory.
///
/// Exit status: 0 success (also when the reader of the frames goes away); 1 bad input;
/// 2 bad arguments; 3 a host could not be reached, could not run the command, dropped
/// or sent back fewer frames than it was given (the message names it); a host's own
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
        farm --hosts alpha,beta movie.pp -- /opt/polypipe/scripts/render.sh --size 640x480 -"
)]
struct Cli {
    /// The hosts, as ssh names them (a host named twice renders two chunks at once).
    #[arg(long, value_name = "H1,H2,…")]
    hosts: String,
    /// Frames a chunk: each chunk is one ssh session.
    #[arg(long, value_name = "N", default_value_t = farm::DEFAULT_CHUNK,
          value_parser = clap::value_parser!(u64).range(1..))]
    chunk: u64,
    /// Also: per host, its frames, the bytes each way and the time.
    #[arg(long)]
    stats: bool,
    /// The movie (`-` for stdin, the default).
    #[arg(default_value = "-")]
    scene: String,
    /// What each host runs, the chunk on its stdin and the frames on its stdout.
    #[arg(last = true, required = true, value_name = "COMMAND")]
    command: Vec<String>,
}

fn main() -> ExitCode {
    let mut outcome = Outcome::Done;
    let code = stagecli::main("farm", |cli: Cli| {
        let hosts = farm::parse_hosts(&cli.hosts).map_err(Error::usage)?;
        let name = stagecli::input_name(&cli.scene).to_string();
        let options = Options {
            hosts,
            ssh: stagecli::remote::ssh_command_from_env()?,
            command: farm::remote_command(&cli.command),
            chunk: cli.chunk,
            stats: cli.stats,
            scene: name.clone(),
        };
        let input = stagecli::open_input(&cli.scene)?;
        let reader = Reader::<Token, _>::new(input).map_err(|e| stagecli::input_error(&name, e))?;
        farm::catch_stop_signals();
        let mut out = stagecli::stdout();
        outcome = farm::run(reader, &options, &mut out, &mut std::io::stderr())?;
        Ok(())
    });
    match outcome {
        Outcome::Stopped(sig) => ExitCode::from(128 + sig as u8),
        Outcome::Done => code,
    }
}
