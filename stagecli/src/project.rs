//! The options of a stage that projects eye-space polygons to the screen on request
//! (`zbuf --project`, `splitter --project`), as one clap group each flattens into its own
//! `Args`.

use crate::args::{projection, DepthArg};
use crate::Error;

/// `--project`, `--zmode MODE`, and `--persp MODE`, their old spelling (hidden, taken for
/// one release with a note). The stage that flattens this group must also have a
/// `--size WxH` option: the projection's screen, which `--project` and `--persp`
/// require.
#[derive(Clone, Copy, Debug, clap::Args)]
pub struct ProjectArgs {
    /// Project eye-space polygons to the --size screen here, as `persp --size WxH --zmode
    /// MODE` would: persp's work, without its process.
    #[arg(long, requires = "size")]
    pub project: bool,
    /// The depth --project writes, as persp's --zmode [default: reciprocal].
    #[arg(long, value_enum, value_name = "MODE")]
    pub zmode: Option<DepthArg>,
    /// `--project --zmode MODE`'s old spelling, taken for one release with a note on
    /// stderr.
    #[arg(long, value_enum, value_name = "MODE", hide = true, requires = "size",
          conflicts_with_all = ["project", "zmode"])]
    pub persp: Option<DepthArg>,
}

impl ProjectArgs {
    /// The depth the projection writes, `None` for no projection
    /// ([`projection`]: the old spelling's note goes on stderr; `--zmode` without
    /// `--project` is a usage error).
    pub fn depth(self, stage: &str) -> Result<Option<DepthArg>, Error> {
        projection(stage, self.project, self.zmode, self.persp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser, Debug)]
    #[command(name = "stage")]
    struct Stage {
        #[arg(long)]
        size: Option<String>,
        #[command(flatten)]
        project: ProjectArgs,
    }

    fn parse(args: &[&str]) -> Result<Stage, String> {
        let mut cmd = crate::args::command::<Stage>();
        Stage::try_parse_from(std::iter::once("stage").chain(args.iter().copied()))
            .map_err(|e| crate::args::usage_line(&e.format(&mut cmd), &cmd))
    }

    #[test]
    fn project_and_zmode_give_the_depth_and_need_a_size() {
        let depth = |args: &[&str]| parse(args).unwrap().project.depth("stage").unwrap();
        assert_eq!(depth(&[]), None);
        assert_eq!(
            depth(&["--size", "4x4", "--project"]),
            Some(DepthArg::Reciprocal)
        );
        assert_eq!(
            depth(&["--size", "4x4", "--project", "--zmode", "eye-z"]),
            Some(DepthArg::EyeZ)
        );
        assert_eq!(
            depth(&["--size", "4x4", "--persp", "projective"]),
            Some(DepthArg::Projective)
        );
        assert_eq!(
            parse(&["--project"]).unwrap_err(),
            "the following required arguments were not provided: --size <SIZE>"
        );
        assert_eq!(
            parse(&["--size", "4x4", "--persp", "eye-z", "--project"]).unwrap_err(),
            "the argument '--persp <MODE>' cannot be used with '--project'"
        );
        let zmode_alone = parse(&["--zmode", "eye-z"]).unwrap().project.depth("stage");
        assert_eq!(
            zmode_alone.unwrap_err().to_string(),
            "--zmode eye-z is for --project (the depth its projection writes)"
        );
    }
}
