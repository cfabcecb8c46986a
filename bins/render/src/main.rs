//! render: the polypipe stages composed into the thesis's pipeline (the `render` crate's
//! library does the work; this is its command line).

use std::process::ExitCode;

fn main() -> ExitCode {
    // Wide pipes for the scene in and the frames out, as every stage has.
    stagecli::stream::widen_pipe(0);
    stagecli::stream::widen_pipe(1);
    ExitCode::from(render::run(std::env::args_os()))
}
