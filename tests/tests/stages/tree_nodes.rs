//! The splitter tree's nodes (`splitter --node K`): their planes against the old
//! script's awk, to the bit, their --stats labels and the nodes a tree has.

use pipeline_tests::{bin_dir, output_with_stdin};
use std::process::Command;

/// The old tree-planes script of scripts/, which render.sh sourced until the nodes
/// computed their own planes (`splitter --node K`): the oracle for them, kept verbatim.
const OLD_TREE_PLANES_SH: &str = r#"
k_of() {
    awk -v n="$1" -v d="$2" -v s="$3" \
        'BEGIN { k = s * (2 * n / d - 1); if (k == 0) k = 0; printf "%.17g", k }'
}

tree_planes() {
    local width=$1 height=$2 depth=$3
    local leaves=$((1 << depth)) node level n a b m
    local -A x0 x1 y0 y1
    declare -gA plane_of=()
    x0[1]=0 x1[1]=$width y0[1]=0 y1[1]=$height
    for ((node = 1; node < leaves; node++)); do
        level=0
        for ((n = node; n > 1; n /= 2)); do level=$((level + 1)); done
        a=$((2 * node)) b=$((2 * node + 1))
        x0[$a]=${x0[$node]} x1[$a]=${x1[$node]} y0[$a]=${y0[$node]} y1[$a]=${y1[$node]}
        x0[$b]=${x0[$node]} x1[$b]=${x1[$node]} y0[$b]=${y0[$node]} y1[$b]=${y1[$node]}
        if ((level % 2 == 0)); then
            m=$(((x0[$node] + x1[$node]) / 2))
            plane_of[$node]="x=$(k_of "$m" "$width" 1)"
            x1[$a]=$m x0[$b]=$m
        else
            m=$(((y0[$node] + y1[$node]) / 2))
            plane_of[$node]="y=$(k_of "$m" "$height" -1)"
            y0[$a]=$m y1[$b]=$m
        fi
    done
}
"#;

/// `x=K` or `y=K` as (axis, the bits of K).
fn plane_bits(plane: &str) -> (char, u64) {
    let (axis, k) = plane.split_once('=').expect("x=K or y=K");
    let k: f64 = k.parse().expect("a number");
    (axis.chars().next().unwrap(), k.to_bits())
}

/// The sizes the tree's planes are checked at: square, odd, tiny, wide.
const TREE_SIZES: [(u32, u32); 7] = [
    (500, 500),
    (333, 187),
    (21, 21),
    (1920, 1080),
    (64, 48),
    (7, 3),
    (1, 1),
];

#[test]
fn tree_nodes_compute_the_planes_of_the_old_awk_to_the_bit() {
    use splitter::{SplitPlane, Tree};
    for (w, h) in TREE_SIZES {
        let script = format!(
            "{OLD_TREE_PLANES_SH}\nfor d in 0 1 2 3 4 5 6; do tree_planes {w} {h} $d; \
             for ((n = 1; n < 1 << d; n++)); do echo \"$d $n ${{plane_of[$n]}}\"; done; done"
        );
        let out = Command::new("bash").args(["-c", &script]).output().unwrap();
        assert!(out.status.success(), "{out:?}");
        let text = String::from_utf8(out.stdout).unwrap();
        // Depth 0 has no node; depths 1–6 have 2^d − 1 each.
        assert_eq!(text.lines().count(), 1 + 3 + 7 + 15 + 31 + 63, "{w}x{h}");
        for line in text.lines() {
            let mut fields = line.split(' ');
            let (_depth, node, old) = (
                fields.next().unwrap(),
                fields.next().unwrap().parse::<u32>().unwrap(),
                fields.next().unwrap(),
            );
            let new = match (Tree {
                width: w,
                height: h,
            })
            .plane(node)
            {
                SplitPlane::Column(k) => ('x', k.to_bits()),
                SplitPlane::Row(k) => ('y', k.to_bits()),
                other => panic!("{other:?}"),
            };
            assert_eq!(new, plane_bits(old), "{w}x{h} node {node}: awk {old}");
        }
    }
}

/// The splitter binary with --node computes the same planes: its --stats label prints K
/// in the shortest form that reads back as the same double.
#[test]
fn splitter_node_labels_its_stats_with_the_old_plane_and_its_node() {
    for (w, h) in [(333, 187), (21, 21), (500, 500)] {
        let script = format!(
            "{OLD_TREE_PLANES_SH}\ntree_planes {w} {h} 6; \
             for ((n = 1; n < 64; n++)); do echo \"${{plane_of[$n]}}\"; done"
        );
        let out = Command::new("bash").args(["-c", &script]).output().unwrap();
        let old: Vec<String> = String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .map(String::from)
            .collect();
        assert_eq!(old.len(), 63);
        for node in 1..64u32 {
            let out = output_with_stdin(
                {
                    let mut cmd = Command::new(bin_dir().join("splitter"));
                    cmd.args(["--stats", "--node", &node.to_string(), "--depth", "6"])
                        .args(["--size", &format!("{w}x{h}"), "/dev/null", "/dev/null"]);
                    cmd
                },
                b"polypipe 1 eye aspect 1 hither 1 yon 30\nEND\n",
            );
            assert!(out.status.success(), "{out:?}");
            let err = String::from_utf8(out.stderr).unwrap();
            let record = pipeline_tests::stat_record(&err, "plane");
            assert_eq!(record.count("node"), Some(u64::from(node)), "{err}");
            assert_eq!(record.count("polygons_in"), Some(0), "{err}");
            let label = record.get("plane").unwrap_or_default();
            assert_eq!(
                plane_bits(label),
                plane_bits(&old[node as usize - 1]),
                "{w}x{h} node {node}: {label} against awk's {}",
                old[node as usize - 1]
            );
        }
    }
}

/// `--node` outside its tree, or without the screen size, is a usage error (2).
#[test]
fn splitter_node_refuses_a_node_outside_its_tree() {
    let splitter = |args: &[&str]| {
        let mut cmd = Command::new(bin_dir().join("splitter"));
        cmd.args(args).args(["/dev/null", "/dev/null"]);
        output_with_stdin(cmd, b"polypipe 1 eye aspect 1 hither 1 yon 30\nEND\n")
    };
    let out = splitter(&["--node", "4", "--depth", "2", "--size", "500x500"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--node 4 is not a splitter node of a depth-2 tree (nodes 1 to 3)"),
        "{err}"
    );
    let out = splitter(&["--node", "1", "--depth", "1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--size"));
    let out = splitter(&["--node", "1", "--depth", "1", "--size", "9x9", "x=0"]);
    assert_eq!(out.status.code(), Some(2));
}
