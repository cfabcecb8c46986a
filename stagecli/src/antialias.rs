//! The options the anti-aliasing leaves share (`abuf`, `supersample`; docs/DESIGN.md,
//! "Anti-aliasing"), as one clap group each flattens into its own `Args`.

use crate::args::{parse_colour, TextFlag};
use proto::Colour;

/// `--background R,G,B` and `--text`, for a leaf that anti-aliases.
///
/// Such a leaf box-filters a pixel's samples, so an uncovered sample of a partly covered
/// pixel must count as something: the background the merger will show where no polygon
/// reaches. The leaf and zbuf must therefore be given the same colour.
#[derive(Clone, Copy, Debug, clap::Args)]
pub struct AntialiasArgs {
    /// Background colour R,G,B: what the uncovered samples of a partly covered pixel
    /// show (give zbuf the same).
    #[arg(long, value_parser = parse_colour, default_value = "0,0,0")]
    pub background: Colour,
    #[command(flatten)]
    pub text: TextFlag,
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser, Debug)]
    #[command(name = "leaf")]
    struct Leaf {
        #[command(flatten)]
        aa: AntialiasArgs,
    }

    #[test]
    fn the_background_defaults_to_black_and_is_read_as_r_g_b() {
        let l = Leaf::try_parse_from(["leaf"]).unwrap();
        assert_eq!((l.aa.background, l.aa.text.text), ([0, 0, 0], false));
        let l = Leaf::try_parse_from(["leaf", "--background", "10, 20,30", "--text"]).unwrap();
        assert_eq!((l.aa.background, l.aa.text.text), ([10, 20, 30], true));
        let e = Leaf::try_parse_from(["leaf", "--background", "1,2"]).unwrap_err();
        assert_eq!(
            crate::args::usage_line(&e, &crate::args::command::<Leaf>()),
            "invalid value '1,2' for '--background <BACKGROUND>': expected R,G,B (three \
             numbers 0-255), got `1,2`"
        );
    }
}
